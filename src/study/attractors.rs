//! The `[attractors]` section: checked once here, resolved against the Hopf speed when the
//! search runs ([`AttractorSettings::options`]).

use super::schema::AttractorsSection;
use super::units::Dimension;
use super::{positive, rule, StudyError};
use crate::attractors::AttractorOptions;

/// The study's `[attractors]` settings in SI; `None` fields take the defaults of
/// [`AttractorOptions::new`], which depend on the Hopf speed.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct AttractorSettings {
    /// the grid's lowest and highest speed (m/s)
    pub speed_range: Option<(f64, f64)>,
    /// grid speeds
    pub speeds: Option<usize>,
    /// kick amplitudes (m)
    pub amplitudes: Option<Vec<f64>>,
    /// longest simulation of one motion (s)
    pub settle: Option<f64>,
    /// bracket of the death speeds (m/s)
    pub bracket: Option<f64>,
    /// largest descent step relative to the speed
    pub descent_step: Option<f64>,
    /// the lowest speed of a descent (m/s)
    pub lowest: Option<f64>,
    /// equilibrium threshold (m)
    pub threshold: Option<f64>,
    /// integrator relative tolerance
    pub rtol: Option<f64>,
    /// largest period in returns
    pub max_period: Option<usize>,
}

impl AttractorSettings {
    /// The options of a search over the bifurcation speed range `range`, around the Hopf speed
    /// `v_h`, with the contact geometry's half-width `geometry_limit`.
    pub fn options(
        &self,
        range: (f64, f64),
        v_h: Option<f64>,
        geometry_limit: Option<f64>,
    ) -> AttractorOptions {
        let mut o = AttractorOptions::new(range, v_h, geometry_limit);
        if let Some(r) = self.speed_range {
            o.speed_range = r;
        }
        if let Some(n) = self.speeds {
            o.speeds = n;
        }
        if let Some(a) = &self.amplitudes {
            o.amplitudes = a.clone();
        }
        if let Some(v) = self.settle {
            o.settle = v;
        }
        if let Some(v) = self.bracket {
            o.bracket = v;
        }
        if let Some(v) = self.descent_step {
            o.descent_step = v;
        }
        if let Some(v) = self.lowest {
            o.lowest = v;
        }
        o.lowest = o.lowest.min(o.speed_range.0);
        if let Some(v) = self.threshold {
            o.threshold = v;
        }
        if let Some(v) = self.rtol {
            o.rtol = v;
        }
        if let Some(v) = self.max_period {
            o.max_period = v;
        }
        o
    }
}

/// Checks the section against the bifurcation speed range `range` (m/s) and the contact
/// geometry's half-width `geometry_limit` (m).
pub(super) fn plan(
    a: &AttractorsSection,
    range: (f64, f64),
    geometry_limit: Option<f64>,
) -> Result<AttractorSettings, StudyError> {
    let mut s = AttractorSettings::default();
    let inside = |key: &str, v: f64| {
        if v < range.0 || v > range.1 {
            Err(rule(
                key,
                format!("{v} m/s"),
                &format!(
                    "must lie inside the bifurcation speed range [{}, {}] m/s",
                    range.0, range.1
                ),
            ))
        } else {
            Ok(v)
        }
    };
    if let Some([lo, hi]) = &a.speed_range {
        let lo = inside(
            "attractors.speed_range[0]",
            positive("attractors.speed_range[0]", lo, Dimension::Speed)?,
        )?;
        let hi = inside(
            "attractors.speed_range[1]",
            positive("attractors.speed_range[1]", hi, Dimension::Speed)?,
        )?;
        if hi <= lo {
            return Err(rule(
                "attractors.speed_range",
                format!("[{lo}, {hi}] m/s"),
                "the maximum must exceed the minimum",
            ));
        }
        s.speed_range = Some((lo, hi));
    }
    if let Some(n) = a.speeds {
        if !(1..=200).contains(&n) {
            return Err(rule("attractors.speeds", n, "must lie in [1, 200]"));
        }
        s.speeds = Some(n);
    }
    if let Some(list) = &a.amplitudes {
        if list.is_empty() || list.len() > 20 {
            return Err(rule(
                "attractors.amplitudes",
                format!("{} values", list.len()),
                "must hold 1 to 20 amplitudes",
            ));
        }
        let mut v = Vec::with_capacity(list.len());
        for (i, q) in list.iter().enumerate() {
            let key = format!("attractors.amplitudes[{i}]");
            let x = positive(&key, q, Dimension::Length)?;
            if let Some(g) = geometry_limit {
                if x > g {
                    return Err(rule(
                        &key,
                        format!("{x} m"),
                        &format!(
                            "must not exceed the contact geometry's range {g} m (contact.lateral_range)"
                        ),
                    ));
                }
            }
            v.push(x);
        }
        s.amplitudes = Some(v);
    }
    if let Some(q) = &a.settle {
        let v = positive("attractors.settle", q, Dimension::Time)?;
        if v > 3600.0 {
            return Err(rule(
                "attractors.settle",
                format!("{v} s"),
                "must not exceed 3600 s",
            ));
        }
        s.settle = Some(v);
    }
    if let Some(q) = &a.bracket {
        let v = positive("attractors.bracket", q, Dimension::Speed)?;
        if v >= range.1 - range.0 {
            return Err(rule(
                "attractors.bracket",
                format!("{v} m/s"),
                "must be narrower than the bifurcation speed range",
            ));
        }
        s.bracket = Some(v);
    }
    if let Some(v) = a.descent_step {
        if !(v > 0.0 && v <= 0.5) {
            return Err(rule(
                "attractors.descent_step",
                v,
                "must lie in (0, 0.5] (a fraction of the speed)",
            ));
        }
        s.descent_step = Some(v);
    }
    if let Some(q) = &a.lowest {
        let v = positive("attractors.lowest", q, Dimension::Speed)?;
        s.lowest = Some(inside("attractors.lowest", v)?);
        if let Some((lo, _)) = s.speed_range {
            if v > lo {
                return Err(rule(
                    "attractors.lowest",
                    format!("{v} m/s"),
                    &format!("must not exceed the grid's lowest speed {lo} m/s (attractors.speed_range[0])"),
                ));
            }
        }
    }
    if let Some(q) = &a.threshold {
        let v = positive("attractors.threshold", q, Dimension::Length)?;
        let smallest = s.amplitudes.as_ref().map_or(f64::INFINITY, |a| {
            a.iter().copied().fold(f64::INFINITY, f64::min)
        });
        if v >= smallest.min(geometry_limit.unwrap_or(f64::INFINITY)) {
            return Err(rule(
                "attractors.threshold",
                format!("{v} m"),
                "must be below the smallest kick amplitude and the geometry's range",
            ));
        }
        s.threshold = Some(v);
    }
    if let Some(r) = a.rtol {
        if !(1e-12..=1e-4).contains(&r) {
            return Err(rule("attractors.rtol", r, "must lie in [1e-12, 1e-4]"));
        }
        s.rtol = Some(r);
    }
    if let Some(n) = a.max_period {
        if !(1..=64).contains(&n) {
            return Err(rule("attractors.max_period", n, "must lie in [1, 64]"));
        }
        s.max_period = Some(n);
    }
    Ok(s)
}
