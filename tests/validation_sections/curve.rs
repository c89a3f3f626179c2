//! critspeed's generalised Hopf (Bautin) points against AUTO-07p's GH points on the same
//! equations: `studies/cubic-fold.toml` over the friction coefficient (its `[curve]`), AUTO's
//! stored results of `scripts/auto07p-curve` (tests/data/auto07p/curve/sc-<SC>/) read back.
//! AUTO takes its first Lyapunov coefficient from finite differences whose steps are set in the
//! state's unit SC, so its GH points move like SC² (truncation); the runs at SC = 0.5, 1, 2, 4 m
//! are extrapolated by Richardson's rule from the two smallest units that found a point. Used
//! by tests/curve.rs (the tolerances) and tests/validation.rs (the report section).

use std::fmt::Write as _;
use std::path::PathBuf;

use critspeed::api::{self, Source};
use critspeed::curve::SpecialKind;

use super::auto07p_section::solutions;

/// The state units of AUTO's runs (m), doubling.
pub const UNITS: [&str; 4] = ["0.5", "1", "2", "4"];

/// AUTO's s-file label types on a Hopf curve (its codes plus −30 there): generalised Hopf
/// and user point.
const GH: i64 = -32;
const UZ: i64 = -34;

/// (V m/s, friction) of every point of type `kind` in the stored runs at unit `sc`.
fn points(sc: &str, kind: i64) -> Vec<(f64, f64)> {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/auto07p/curve")
        .join(format!("sc-{sc}"));
    ["s.gh-up", "s.gh-down"]
        .iter()
        .flat_map(|f| {
            let p = dir.join(f);
            let text =
                std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()));
            solutions(&text)
        })
        .filter(|s| s.kind == kind)
        .map(|s| (s.par[1], s.par[3]))
        .collect()
}

/// One generalised Hopf point: critspeed's, AUTO's at each unit (`None` where that run did
/// not label it) and AUTO's extrapolated to a zero step.
pub struct Bautin {
    /// critspeed (friction, V m/s)
    pub critspeed: (f64, f64),
    /// AUTO per unit of [`UNITS`]: (friction, V)
    pub auto: Vec<Option<(f64, f64)>>,
    /// Richardson from the two smallest units with the point: f(h) + (f(h) − f(2h))/3
    pub extrapolated: Option<(f64, f64)>,
}

/// critspeed's Bautin points of the study's `[curve]`, each with AUTO's nearest GH point
/// (within 0.01 in friction) at every unit.
pub fn bautin_points() -> Vec<Bautin> {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("studies/cubic-fold.toml");
    let study = api::curve::curve_study(&Source::file(&path).expect("study")).expect("curve");
    let report = api::curve::curve(&study, None).expect("curves");
    let mut out: Vec<Bautin> = report
        .special_points
        .iter()
        .filter(|s| s.kind == SpecialKind::Bautin)
        .map(|s| {
            let auto: Vec<Option<(f64, f64)>> = UNITS
                .iter()
                .map(|sc| {
                    points(sc, GH)
                        .into_iter()
                        .map(|(v, mu)| (mu, v))
                        .filter(|(mu, _)| (mu - s.parameter).abs() < 0.01)
                        .min_by(|a, b| {
                            (a.0 - s.parameter)
                                .abs()
                                .total_cmp(&(b.0 - s.parameter).abs())
                        })
                })
                .collect();
            let extrapolated = auto.windows(2).find_map(|w| match (w[0], w[1]) {
                (Some(h), Some(h2)) => Some((h.0 + (h.0 - h2.0) / 3.0, h.1 + (h.1 - h2.1) / 3.0)),
                _ => None,
            });
            Bautin {
                critspeed: (s.parameter, s.speed_m_s),
                auto,
                extrapolated,
            }
        })
        .collect();
    out.sort_by(|a, b| b.critspeed.0.total_cmp(&a.critspeed.0));
    out
}

/// AUTO's user points at the ends of the Hopf curve (V = 150 m/s and friction 0.6) at unit 1 m,
/// with critspeed's curve there: ((AUTO friction at 150 m/s, critspeed's), (AUTO V at 0.6,
/// critspeed's)).
pub fn curve_ends() -> ((f64, f64), (f64, f64)) {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("studies/cubic-fold.toml");
    let study = api::curve::curve_study(&Source::file(&path).expect("study")).expect("curve");
    let report = api::curve::curve(&study, None).expect("curves");
    let vh = report
        .curves
        .iter()
        .find(|c| c.label == "V_H")
        .expect("V_H curve");
    let at_150 = vh
        .points
        .iter()
        .find(|p| (p.speed_m_s - 150.0).abs() < 1e-9)
        .expect("the curve's end at 150 m/s");
    let at_06 = vh
        .points
        .iter()
        .find(|p| (p.parameter - 0.6).abs() < 1e-12)
        .expect("the curve's end at 0.6");
    let uz = points("1", UZ);
    let auto_150 = uz
        .iter()
        .find(|(v, _)| (v - 150.0).abs() < 1e-9)
        .expect("AUTO at 150 m/s");
    let auto_06 = uz
        .iter()
        .find(|(_, mu)| (mu - 0.6).abs() < 1e-9)
        .expect("AUTO at 0.6");
    ((auto_150.1, at_150.parameter), (auto_06.0, at_06.speed_m_s))
}

fn rel(a: f64, b: f64) -> String {
    format!("{:.1e}", (a - b) / b)
}

/// The report section.
pub fn section(s: &mut String) {
    let _ = writeln!(s, "## 9. Generalised Hopf points against AUTO-07p\n");
    let _ = writeln!(
        s,
        "`studies/cubic-fold.toml` over the friction coefficient (its `[curve]`, `critspeed curve studies/cubic-fold.toml`): the Hopf point of the Shen model is subcritical at high friction and turns supercritical between two generalised Hopf (Bautin) points, where critspeed's first Lyapunov coefficient l1 changes sign. AUTO-07p 0.9.2 continues the same Hopf point in (V, friction) (`ISW = 2`, right-hand side `scripts/auto07p/wheelset-friction.f90`, constants `scripts/auto07p/c.gh`) and labels GH where its own first Lyapunov coefficient changes sign. AUTO computes that coefficient by finite differences whose steps are set in the units of its state variables: with the state in mm (the unit of section 8's runs) its GH test function is rounding noise (its sign changes at almost every step), with the state in units of SC = 0.5 to 4 m it is smooth and its GH points move with SC like SC², so the table gives AUTO's points at four units and their Richardson extrapolation from the two smallest units that found each point. AUTO's results are stored in `tests/data/auto07p/curve/` (regenerate with `scripts/auto07p-curve`).\n"
    );
    let _ = writeln!(
        s,
        "| | critspeed | AUTO SC = 0.5 m | SC = 1 m | SC = 2 m | SC = 4 m | AUTO extrapolated | rel. diff. |"
    );
    let _ = writeln!(s, "|---|---|---|---|---|---|---|---|");
    let cell = |p: &Option<(f64, f64)>, k: usize| match p {
        Some(p) => format!("{:.7}", if k == 0 { p.0 } else { p.1 }),
        None => "not labelled".into(),
    };
    for (n, b) in bautin_points().iter().enumerate() {
        for (k, what) in ["friction", "V (m/s)"].iter().enumerate() {
            let c = if k == 0 { b.critspeed.0 } else { b.critspeed.1 };
            let e = b.extrapolated.map(|e| if k == 0 { e.0 } else { e.1 });
            let _ = writeln!(
                s,
                "| GH {} {what} | {c:.7} | {} | {} | {} | {} | {} | {} |",
                n + 1,
                cell(&b.auto[0], k),
                cell(&b.auto[1], k),
                cell(&b.auto[2], k),
                cell(&b.auto[3], k),
                e.map_or("–".into(), |e| format!("{e:.7}")),
                e.map_or("–".into(), |e| rel(e, c)),
            );
        }
    }
    let ((a150, c150), (a06, c06)) = curve_ends();
    let _ = writeln!(
        s,
        "\nThe Hopf curves themselves agree to AUTO's tolerance: where V_H reaches 150 m/s the friction is {a150:.9} (AUTO) and {c150:.9} (critspeed), rel. diff. {}; at friction 0.6, V_H = {a06:.7} m/s (AUTO) and {c06:.7} m/s (critspeed), rel. diff. {}.\n",
        rel(a150, c150),
        rel(a06, c06)
    );
}
