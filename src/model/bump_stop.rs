//! Lateral bump stops (docs/model.md §13): free play $±δ_b$, then a stiff spring. On the
//! lateral deflection $Δ$ of the two bodies it joins,
//! $$F(Δ) = −g(|Δ| − δ_b)\,\operatorname{sign} Δ \quad (|Δ| > δ_b),\qquad F = 0 \text{ inside},$$
//! with $g(p) = k_b\,p$ (a linear stop) or a progressive piecewise-linear table $g$ of the
//! penetration $p$, monotone and through zero. $F$ is odd in $Δ$, so $f(−x) = −f(x)$ holds.
//!
//! The edges $±δ_b$ and the table's knees are switching surfaces, like the flange's edges: the
//! functions $Δ − δ_b − p_i$ and $−Δ − δ_b − p_i$ ($p_0 = 0$, then each knee) change sign
//! exactly where the law changes its piece, as [`BumpStop::force`] compares the same numbers.

use super::table::{knots, Knots, Wording, MAX_TABLE_POINTS};

/// The most points a progressive table holds (the struct stays `Copy`).
pub const MAX_STOP_POINTS: usize = MAX_TABLE_POINTS;

/// The rules of [`StopTable::from_points`] in a stop's words.
const WORDING: Wording = Wording {
    finite: "every penetration and force must be finite",
    through_zero: "the table must pass through zero: at penetration 0 the force is 0",
    odd: "give penetrations beyond the clearance only (>= 0): the stop is odd",
    positive: "a penetration > 0",
    at: "a penetration of ",
    unit: "m",
};

/// The force of a stop against its penetration $p ≥ 0$ beyond the clearance.
// (the table inline, not boxed: the suspensions' parameter structs stay `Copy`, as with
// `ForceVelocity`)
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum StopLaw {
    /// $g(p) = k_b\,p$ (N/m)
    Linear(f64),
    /// a progressive table
    Table(StopTable),
}

/// A piecewise-linear $g(p)$ through $(0, 0)$ and the given points, beyond the last with the
/// last segment's slope.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StopTable {
    /// penetrations $0 = p_0 < p_1 < … < p_k$ (m)
    penetration: [f64; MAX_STOP_POINTS + 1],
    /// forces $0 = g_0 < g_1 < … < g_k$ (N)
    force: [f64; MAX_STOP_POINTS + 1],
    /// k + 1, the origin included
    len: usize,
}

impl StopTable {
    /// From points $(p_i, g_i)$ (m, N) with $p_i > 0$ in any order; $(0, 0)$ is implied (a given
    /// $p = 0$ must have $g = 0$). Errors name the rule: finite values, at least one point with
    /// $p > 0$, no negative penetration, distinct penetrations, the force strictly increasing
    /// with the penetration (monotone) and through zero.
    pub fn from_points(points: &[(f64, f64)]) -> Result<Self, String> {
        let Knots { x, force, len } = knots(points, &WORDING)?;
        Ok(Self {
            penetration: x,
            force,
            len,
        })
    }

    /// The same table with every force multiplied by `factor` > 0.
    pub fn scaled(&self, factor: f64) -> Self {
        let mut t = *self;
        for g in &mut t.force {
            *g *= factor;
        }
        t
    }

    /// The points $(p_i, g_i)$, the origin included.
    pub fn points(&self) -> Vec<(f64, f64)> {
        let p = self.penetration[..self.len].iter().copied();
        p.zip(self.force[..self.len].iter().copied()).collect()
    }

    /// The slope at the start, $g'(0^+)$ (N/m).
    pub fn initial_stiffness(&self) -> f64 {
        self.slope(0)
    }

    /// The penetrations where the slope changes: $p_1 … p_{k−1}$ (the last point is not a
    /// kink, the last segment continues beyond it).
    pub fn knees(&self) -> &[f64] {
        &self.penetration[1..self.len.saturating_sub(1).max(1)]
    }

    fn slope(&self, i: usize) -> f64 {
        let i = i.min(self.len - 2);
        (self.force[i + 1] - self.force[i]) / (self.penetration[i + 1] - self.penetration[i])
    }

    /// $g(p)$ and $g'(p)$ for $p > 0$: the segment is the last knee $p_i$ with $p > p_i$ (the
    /// comparison of the switching function $p − p_i$).
    fn at(&self, p: f64) -> (f64, f64) {
        let i = self
            .knees()
            .iter()
            .rposition(|&k| p > k)
            .map_or(0, |j| j + 1);
        let s = self.slope(i);
        (self.force[i] + s * (p - self.penetration[i]), s)
    }
}

impl StopLaw {
    /// $g(p)$ (N) and $g'(p)$ (N/m) at penetration $p > 0$.
    #[inline]
    pub fn at(&self, p: f64) -> (f64, f64) {
        match self {
            StopLaw::Linear(k) => (k * p, *k),
            StopLaw::Table(t) => t.at(p),
        }
    }

    /// The knees $p_i$ beyond the first contact (m): none for a linear stop.
    pub fn knees(&self) -> &[f64] {
        match self {
            StopLaw::Linear(_) => &[],
            StopLaw::Table(t) => t.knees(),
        }
    }

    /// The stiffness at first contact (N/m).
    pub fn initial_stiffness(&self) -> f64 {
        match self {
            StopLaw::Linear(k) => *k,
            StopLaw::Table(t) => t.initial_stiffness(),
        }
    }
}

/// A stop as the study gives it: clearance and law.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StopSpec {
    /// free play each way, $δ_b$ (m)
    pub clearance: f64,
    /// the force beyond it
    pub law: StopLaw,
}

/// An assembled stop: the lateral deflection $Δ = b\,q$ it acts on (the same row as the
/// lateral spring between the two bodies, lever arms included), its clearance and its law.
#[derive(Clone, Debug, PartialEq)]
pub struct BumpStop {
    /// e.g. `"secondary bump stop, frame 1"`
    pub name: String,
    /// the deflection $Δ = b\,q$: `(coordinate, coefficient)` pairs
    pub row: Vec<(usize, f64)>,
    /// clearance $δ_b$ (m)
    pub clearance: f64,
    /// the force beyond the clearance
    pub law: StopLaw,
}

impl BumpStop {
    /// $Δ = b\,q$ (m).
    #[inline]
    pub fn deflection(&self, q: &[f64]) -> f64 {
        self.row.iter().fold(0.0, |s, &(j, b)| s + b * q[j])
    }

    /// The force on the first body $F(Δ)$ (N) and its slope $dF/dΔ$ (N/m). The comparisons
    /// are those of [`Self::switch`]: right contact where $Δ − δ_b > 0$, left contact where
    /// $−Δ − δ_b > 0$.
    #[inline]
    pub fn force(&self, delta: f64) -> (f64, f64) {
        let right = delta - self.clearance;
        if right > 0.0 {
            let (g, s) = self.law.at(right);
            return (-g, -s);
        }
        let left = -delta - self.clearance;
        if left > 0.0 {
            let (g, s) = self.law.at(left);
            return (g, -s);
        }
        (0.0, 0.0)
    }

    /// Number of switching functions: 2 for the edges, 2 per knee of a table.
    pub fn switches(&self) -> usize {
        2 * (1 + self.law.knees().len())
    }

    /// Switching function `k` at deflection `delta`: for $j = k/2$ and the offset $p_j$ ($p_0 =
    /// 0$, then each knee), $(Δ − δ_b) − p_j$ for even `k`, $(−Δ − δ_b) − p_j$ for odd `k`.
    pub fn switch(&self, k: usize, delta: f64) -> f64 {
        let side = if k.is_multiple_of(2) {
            delta - self.clearance
        } else {
            -delta - self.clearance
        };
        match k / 2 {
            0 => side,
            j => self.law.knees().get(j - 1).map_or(f64::NAN, |&p| side - p),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linear_stop_is_a_dead_band_spring() {
        let s = BumpStop {
            name: "s".into(),
            row: vec![(0, 1.0)],
            clearance: 0.01,
            law: StopLaw::Linear(1e6),
        };
        assert_eq!(s.force(0.005), (0.0, 0.0));
        assert_eq!(s.force(-0.01), (0.0, 0.0));
        let (f, d) = s.force(0.012);
        assert!((f + 2000.0).abs() < 1e-6 && d == -1e6);
        assert_eq!(s.force(-0.012).0, -f);
        assert_eq!(s.switches(), 2);
    }

    #[test]
    fn tables_are_monotone_through_zero_and_progressive() {
        assert!(StopTable::from_points(&[(0.01, 5.0), (0.02, 4.0)]).is_err());
        assert!(StopTable::from_points(&[(0.0, 1.0), (0.02, 4.0)]).is_err());
        assert!(StopTable::from_points(&[(-0.01, 1.0)]).is_err());
        assert!(StopTable::from_points(&[]).is_err());
        let t = StopTable::from_points(&[(0.02, 3e4), (0.01, 1e4)]).expect("table");
        assert_eq!(t.knees(), &[0.01]);
        let law = StopLaw::Table(t);
        let (g, s) = law.at(0.015);
        assert!((g - 2e4).abs() < 1e-6 && (s - 2e6).abs() < 1e-6);
        let (g, s) = law.at(0.03);
        assert!((g - 5e4).abs() < 1e-6 && (s - 2e6).abs() < 1e-6);
        let (g, s) = law.at(0.005);
        assert!((g - 5e3).abs() < 1e-6 && (s - 1e6).abs() < 1e-6);
    }
}
