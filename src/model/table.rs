//! The knots of a piecewise-linear odd table $g$ through zero, as a damper's force–velocity
//! curve ([`super::ForceVelocity`]) and a progressive bump stop ([`super::StopTable`]) are
//! given: points $(x_i, g_i)$ for $x > 0$, $(0, 0)$ implied, $g$ strictly rising. One
//! validation for both, each naming its abscissa in its own words.

/// The most points a table holds beside the origin: the suspensions' parameter structs stay
/// `Copy` with the tables inside.
pub const MAX_TABLE_POINTS: usize = 16;

/// How a table's messages name it and its abscissa.
pub(super) struct Wording {
    /// "every velocity and force must be finite"
    pub finite: &'static str,
    /// the rule for a point at $x = 0$ with a force
    pub through_zero: &'static str,
    /// the rule for a point at $x < 0$
    pub odd: &'static str,
    /// the abscissa beyond zero, e.g. "v > 0"
    pub positive: &'static str,
    /// before a value of the abscissa, e.g. "v = "
    pub at: &'static str,
    /// its unit, e.g. "m/s"
    pub unit: &'static str,
}

/// The validated knots $0 = x_0 < x_1 < … < x_k$, $0 = g_0 < g_1 < … < g_k$, `len` = k + 1.
pub(super) struct Knots {
    pub x: [f64; MAX_TABLE_POINTS + 1],
    pub force: [f64; MAX_TABLE_POINTS + 1],
    pub len: usize,
}

/// The knots of `points` $(x_i, g_i)$ in any order. Errors name the rule, in `w`'s words:
/// every value finite, a given $x = 0$ with $g = 0$, no $x < 0$, at least one and at most
/// [`MAX_TABLE_POINTS`] points with $x > 0$, distinct abscissae, $g$ strictly rising.
pub(super) fn knots(points: &[(f64, f64)], w: &Wording) -> Result<Knots, String> {
    if points
        .iter()
        .any(|(x, g)| !(x.is_finite() && g.is_finite()))
    {
        return Err(w.finite.into());
    }
    if points.iter().any(|&(x, g)| x == 0.0 && g != 0.0) {
        return Err(w.through_zero.into());
    }
    if points.iter().any(|&(x, _)| x < 0.0) {
        return Err(w.odd.into());
    }
    let mut pts: Vec<(f64, f64)> = points.iter().copied().filter(|p| p.0 > 0.0).collect();
    if pts.is_empty() {
        return Err(format!("needs at least one point with {}", w.positive));
    }
    if pts.len() > MAX_TABLE_POINTS {
        return Err(format!(
            "at most {MAX_TABLE_POINTS} points with {} ({} given)",
            w.positive,
            pts.len()
        ));
    }
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (at, unit) = (w.at, w.unit);
    let mut x = [0.0; MAX_TABLE_POINTS + 1];
    let mut force = [0.0; MAX_TABLE_POINTS + 1];
    for (k, &(xk, g)) in pts.iter().enumerate() {
        let (x0, g0) = (x[k], force[k]);
        if xk == x0 {
            return Err(format!("two points at {at}{xk} {unit}"));
        }
        if g <= g0 {
            return Err(format!(
                "must be monotone: the force {g} N at {xk} {unit} is not above {g0} N at {x0} {unit}"
            ));
        }
        x[k + 1] = xk;
        force[k + 1] = g;
    }
    Ok(Knots {
        x,
        force,
        len: pts.len() + 1,
    })
}
