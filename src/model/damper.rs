//! A damper's force–velocity characteristic (docs/model.md §13): $F = g(v)$, odd, strictly
//! increasing, through zero; piecewise linear between the given points and beyond the last
//! with the last segment's slope. A relief valve's blow-off is the two-segment case: slope
//! $c_1$ up to the knee velocity $v_b$, then $c_2 < c_1$.
//!
//! Piecewise linear rather than a smooth interpolation: the table is the data a damper maker
//! publishes, reproduced exactly, and its kinks are switching surfaces for the integrator, as
//! the flange's edges are (each knee $F_i$ is crossed where $±F − F_i$ changes sign), so the
//! segments are integrated smoothly and the kinks are located, not stepped over.
//!
//! On a damper in series with a stiffness the bushes' force $F = k_s(Δ − z)$ is known from
//! the state and the damper's stroke rate is $\dot z = g^{-1}(F)$: the characteristic is
//! stored as knees in force with the inverse slopes, so that the field needs no solve.

use super::table::{knots, Knots, Wording, MAX_TABLE_POINTS};

/// The most points a characteristic holds (beside the origin): the suspensions' parameter
/// structs stay `Copy` with the curve inside.
pub const MAX_POINTS: usize = MAX_TABLE_POINTS;

/// The rules of [`ForceVelocity::from_points`] in a damper's words.
const WORDING: Wording = Wording {
    finite: "every velocity and force must be finite",
    through_zero: "the curve must pass through zero: at v = 0 the force is 0",
    odd: "give the points for v > 0 only: the curve is odd, F(-v) = -F(v)",
    positive: "v > 0",
    at: "v = ",
    unit: "m/s",
};

/// $F = g(v)$ for $v ≥ 0$ as knees, odd-extended: $g(−v) = −g(v)$.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ForceVelocity {
    /// knee velocities $0 = v_0 < v_1 < … < v_k$ (m/s), `len` of them
    velocity: [f64; MAX_POINTS + 1],
    /// knee forces $0 = F_0 < F_1 < … < F_k$ (N)
    force: [f64; MAX_POINTS + 1],
    /// k + 1: the knees in use, the origin included
    len: usize,
    /// slope beyond the last knee (N s/m)
    tail: f64,
    /// given in the blow-off form (two slopes and the knee), not as a table
    blow_off: bool,
}

impl ForceVelocity {
    /// From points $(v_i, F_i)$ (m/s, N) with $v_i > 0$, in any order; $(0, 0)$ is implied
    /// (a given $v = 0$ must have $F = 0$). Beyond the last point the last segment's slope
    /// continues. Errors name the rule: at least one point with $v > 0$, every value finite,
    /// velocities distinct, the force strictly increasing with the velocity (a damper
    /// dissipates: the curve is monotone), through zero.
    pub fn from_points(points: &[(f64, f64)]) -> Result<Self, String> {
        let Knots {
            x: velocity,
            force,
            len,
        } = knots(points, &WORDING)?;
        let k = len - 1;
        let tail = (force[k] - force[k - 1]) / (velocity[k] - velocity[k - 1]);
        Ok(Self {
            velocity,
            force,
            len,
            tail,
            blow_off: false,
        })
    }

    /// The blow-off form: slope `slope` (N s/m) up to `knee` (m/s), then `slope_after`.
    /// Errors unless all three are positive and finite (a `slope_after` above `slope`, a
    /// stiffening valve, is accepted).
    pub fn blow_off(slope: f64, knee: f64, slope_after: f64) -> Result<Self, String> {
        for (what, v) in [
            ("slope", slope),
            ("knee", knee),
            ("slope_after", slope_after),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(format!("{what} must be positive and finite"));
            }
        }
        let (mut velocity, mut force) = ([0.0; MAX_POINTS + 1], [0.0; MAX_POINTS + 1]);
        velocity[1] = knee;
        force[1] = slope * knee;
        Ok(Self {
            velocity,
            force,
            len: 2,
            tail: slope_after,
            blow_off: true,
        })
    }

    /// The blow-off force (N) and the slope after it (N s/m) of a curve given in the blow-off
    /// form ([`Self::blow_off`]); `None` for a table.
    pub fn blow_off_form(&self) -> Option<(f64, f64)> {
        self.blow_off.then(|| (self.force[1], self.tail))
    }

    /// The slope at zero $g'(0)$ (N s/m): the damping the linear analysis uses.
    pub fn slope_at_zero(&self) -> f64 {
        self.slope(0)
    }

    /// The knee forces $F_1 … F_k$ (N): where the slope changes, on either side.
    pub fn knee_forces(&self) -> &[f64] {
        &self.force[1..self.len]
    }

    /// The points $(v_i, F_i)$ for $v ≥ 0$ and the slope beyond the last.
    pub fn points(&self) -> (Vec<(f64, f64)>, f64) {
        let pts = self.velocity[..self.len].iter().copied();
        (
            pts.zip(self.force[..self.len].iter().copied()).collect(),
            self.tail,
        )
    }

    /// The same curve with every force multiplied by `factor` > 0.
    pub fn scaled(&self, factor: f64) -> Self {
        let mut g = *self;
        for f in &mut g.force {
            *f *= factor;
        }
        g.tail *= factor;
        g
    }

    /// Slope of segment `i` (from knee i to knee i + 1; the tail beyond the last).
    fn slope(&self, i: usize) -> f64 {
        if i + 1 < self.len {
            (self.force[i + 1] - self.force[i]) / (self.velocity[i + 1] - self.velocity[i])
        } else {
            self.tail
        }
    }

    /// The segment of force magnitude `a` ≥ 0: the last knee strictly below it (a knee's own
    /// force belongs to the segment below, as the switching function $a − F_i$ is not yet
    /// positive there).
    fn segment(&self, a: f64) -> usize {
        self.force[..self.len]
            .iter()
            .rposition(|&f| a > f)
            .unwrap_or(0)
    }

    /// $g(v)$ (N).
    pub fn force_at(&self, v: f64) -> f64 {
        let a = v.abs();
        let i = self.velocity[..self.len]
            .iter()
            .rposition(|&k| a > k)
            .unwrap_or(0);
        let f = self.force[i] + self.slope(i) * (a - self.velocity[i]);
        f.copysign(v)
    }

    /// $g^{-1}(F)$ (m/s) and its derivative $1/g'$ (m/(N s)) at force `f` (N).
    #[inline]
    pub fn velocity_at(&self, f: f64) -> (f64, f64) {
        let a = f.abs();
        let i = self.segment(a);
        let inv = 1.0 / self.slope(i);
        let v = self.velocity[i] + (a - self.force[i]) * inv;
        (v.copysign(f), inv)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blow_off_is_two_slopes_and_its_inverse_is_exact() {
        let g = ForceVelocity::blow_off(3e5, 0.01, 2e4).expect("curve");
        assert_eq!(g.slope_at_zero(), 3e5);
        assert_eq!(g.knee_forces(), &[3000.0]);
        for v in [-0.2, -0.01, -0.004, 0.0, 0.003, 0.01, 0.05, 0.3] {
            let f = g.force_at(v);
            let expected = if v.abs() <= 0.01 {
                3e5 * v
            } else {
                (3000.0 + 2e4 * (v.abs() - 0.01)).copysign(v)
            };
            assert!(
                (f - expected).abs() <= 1e-9 * expected.abs().max(1.0),
                "{v}: {f}"
            );
            let (back, inv) = g.velocity_at(f);
            assert!((back - v).abs() <= 1e-12, "{v}: {back}");
            let slope = if v.abs() <= 0.01 { 3e5 } else { 2e4 };
            assert!((inv * slope - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn tables_must_be_monotone_and_through_zero() {
        assert!(ForceVelocity::from_points(&[(0.1, 5.0), (0.2, 4.0)]).is_err());
        assert!(ForceVelocity::from_points(&[(0.0, 1.0), (0.2, 4.0)]).is_err());
        assert!(ForceVelocity::from_points(&[(-0.1, -1.0)]).is_err());
        assert!(ForceVelocity::from_points(&[]).is_err());
        let g = ForceVelocity::from_points(&[(0.3, 9.0), (0.1, 5.0), (0.0, 0.0)]).expect("ok");
        assert_eq!(g.knee_forces(), &[5.0, 9.0]);
        assert_eq!(g.slope_at_zero(), 50.0);
        assert_eq!(g.force_at(-0.2), -7.0);
        assert_eq!(g.force_at(0.5), 13.0);
    }
}
