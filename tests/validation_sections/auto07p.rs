//! critspeed against AUTO-07p on the same equations: the stored AUTO results of
//! `scripts/auto07p-compare` (tests/data/auto07p/<case>/) read back here, and critspeed's
//! cycles solved at AUTO's user-point speeds from AUTO's own start states. Used by
//! tests/auto07p.rs (the tolerances) and tests/validation.rs (the report section).

use std::fmt::Write as _;
use std::path::PathBuf;

use critspeed::bifurcation::{analyse, cycle_at_with};
use critspeed::continuation::SpecialKind;
use critspeed::study;
use critspeed::system::ode::{integrate_with_peaks, Method, OdeOptions, Tolerances};
use nalgebra::SVector;

/// The two cases: (AUTO case folder, critspeed study).
pub const CASES: [(&str, &str); 2] = [
    ("cone", "seed-hunting-cone.toml"),
    ("cubic", "cubic-fold.toml"),
];

/// AUTO's scaling of the state (scripts/auto07p/wheelset.f90): mm, mrad, and rates over 30 rad/s.
const OMS: f64 = 30.0;

fn data(case: &str, file: &str) -> String {
    let p = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/auto07p")
        .join(case)
        .join(file);
    std::fs::read_to_string(&p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// AUTO writes exponents of three digits without the E when they do not fit ("1.2+308").
fn number(s: &str) -> f64 {
    s.parse().unwrap_or_else(|_| {
        let t = s.replace('D', "E");
        t.parse().unwrap_or_else(|_| {
            let k = t.rfind(['+', '-']).filter(|&k| k > 0).expect("AUTO number");
            format!("{}E{}", &t[..k], &t[k..])
                .parse()
                .expect("AUTO number")
        })
    })
}

/// One labelled solution of an AUTO s-file.
pub struct Solution {
    pub pt: i64,
    pub kind: i64,
    pub t: Vec<f64>,
    pub u: Vec<[f64; 4]>,
    pub ncol: usize,
    /// PAR(1..), 1-based: par[1] = V, par[11] = period
    pub par: Vec<f64>,
}

/// The s-file format: per solution a header of 12 integers (IBR NTOT ITP LAB NFPR ISW NTPL NAR
/// NROWPR NTST NCOL NPAR), then NROWPR lines: NTPL rows of (t, U), ICP, RLDOT, UDOT, PAR.
pub fn solutions(text: &str) -> Vec<Solution> {
    let lines: Vec<&str> = text.lines().collect();
    let (mut i, mut out) = (0, Vec::new());
    while i < lines.len() {
        let h: Vec<i64> = lines[i]
            .split_whitespace()
            .map(|v| v.parse().expect("header"))
            .collect();
        let (pt, kind, nfpr) = (h[1], h[2], h[4] as usize);
        let (ntpl, nar, nrowpr) = (h[6] as usize, h[7] as usize, h[8] as usize);
        let (ncol, npar) = (h[10] as usize, h[11] as usize);
        let body: Vec<f64> = lines[i + 1..i + 1 + nrowpr]
            .iter()
            .flat_map(|l| l.split_whitespace())
            .map(number)
            .collect();
        let rows = &body[..ntpl * nar];
        let t = rows.chunks(nar).map(|r| r[0]).collect();
        let u = rows.chunks(nar).map(|r| [r[1], r[2], r[3], r[4]]).collect();
        let k = ntpl * nar + 2 * nfpr + ntpl * (nar - 1);
        let mut par = vec![f64::NAN];
        par.extend_from_slice(&body[k..k + npar]);
        out.push(Solution {
            pt,
            kind,
            t,
            u,
            ncol,
            par,
        });
        i += 1 + nrowpr;
    }
    out
}

/// Largest |U(1)| of AUTO's continuous solution: on each mesh interval the NCOL + 1 stored
/// points (mesh ends and equally spaced interior points) define AUTO's collocation polynomial
/// of degree NCOL exactly; it is maximised by golden section on the intervals around the
/// largest stored value.
pub fn collocation_max(s: &Solution) -> f64 {
    let m = s.ncol;
    let intervals = (s.t.len() - 1) / m;
    let poly = |j: usize, x: f64| -> f64 {
        let (ts, ys): (Vec<f64>, Vec<f64>) =
            (0..=m).map(|q| (s.t[j * m + q], s.u[j * m + q][0])).unzip();
        (0..=m)
            .map(|a| {
                let l: f64 = (0..=m)
                    .filter(|&b| b != a)
                    .map(|b| (x - ts[b]) / (ts[a] - ts[b]))
                    .product();
                ys[a] * l
            })
            .sum()
    };
    let mut best = s.u.iter().map(|u| u[0].abs()).fold(0.0, f64::max);
    for j in 0..intervals {
        let (a0, b0) = (s.t[j * m], s.t[(j + 1) * m]);
        let sign = if poly(j, 0.5 * (a0 + b0)) < 0.0 {
            -1.0
        } else {
            1.0
        };
        let f = |x: f64| sign * poly(j, x);
        let g = 0.5 * (5f64.sqrt() - 1.0);
        let (mut a, mut b) = (a0, b0);
        for _ in 0..80 {
            let (c, d) = (b - g * (b - a), a + g * (b - a));
            if f(c) > f(d) {
                b = d;
            } else {
                a = c;
            }
        }
        best = best.max(f(0.5 * (a + b)).abs());
    }
    best
}

/// AUTO's Floquet multipliers of point `pt` from the d-file lines (5 significant digits).
pub fn multipliers(text: &str, pt: i64) -> Vec<(f64, f64)> {
    text.lines()
        .filter_map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            (f.len() >= 6 && f[2] == "Multiplier" && f[1].parse::<i64>().ok()?.abs() == pt.abs())
                .then(|| (number(f[4]), number(f[5])))
        })
        .collect()
}

/// One cycle compared: AUTO's user point and critspeed's cycle at the same speed.
pub struct Row {
    pub speed: f64,
    pub auto_period: f64,
    pub period: f64,
    pub auto_amplitude_mm: f64,
    pub amplitude_mm: f64,
    /// the largest nontrivial multiplier of each (by distance from 1 of the trivial one)
    pub auto_critical: f64,
    pub critical: f64,
    pub trivial_error: f64,
    /// the same cycle by critspeed at rtol 1e-12: the reference both are measured against
    pub tight_period: f64,
    pub tight_amplitude_mm: f64,
}

/// One case compared.
pub struct Case {
    pub name: &'static str,
    /// the study's `[bifurcation]` rtol and integrator, at which critspeed's cycles are solved
    pub rtol: f64,
    pub integrator: &'static str,
    pub auto_hopf: f64,
    pub hopf: f64,
    /// AUTO's fold: the vertex of the parabola V(A) through its three branch points of lowest
    /// speed (AUTO 0.9.2 detects the sign change of its fold function but does not locate it
    /// here); critspeed's located fold
    pub fold: Option<(f64, f64)>,
    pub rows: Vec<Row>,
}

fn critical_of(m: &[(f64, f64)]) -> f64 {
    // drop the multiplier nearest 1 (trivial), take the largest modulus of the rest
    let k = (0..m.len())
        .min_by(|&a, &b| {
            let d = |i: usize| (m[i].0 - 1.0).hypot(m[i].1);
            d(a).total_cmp(&d(b))
        })
        .unwrap_or(0);
    (0..m.len())
        .filter(|&i| i != k)
        .map(|i| m[i].0.hypot(m[i].1))
        .fold(0.0, f64::max)
}

/// AUTO's fold estimate from the b-file: the vertex of V(A) through the lowest three points.
fn auto_fold(b: &str) -> Option<f64> {
    let pts: Vec<(f64, f64)> = b
        .lines()
        .filter_map(|l| {
            let f: Vec<&str> = l.split_whitespace().collect();
            (f.len() > 8 && f[0] != "0").then(|| (number(f[4]), number(f[f.len() - 1])))
        })
        .collect();
    let k = (1..pts.len().saturating_sub(1)).min_by(|&a, &b| pts[a].0.total_cmp(&pts[b].0))?;
    let ((v0, a0), (v1, a1), (v2, a2)) = (pts[k - 1], pts[k], pts[k + 1]);
    // V = c0 + c1 A + c2 A^2 through three points (divided differences)
    let d01 = (v1 - v0) / (a1 - a0);
    let d12 = (v2 - v1) / (a2 - a1);
    let c2 = (d12 - d01) / (a2 - a0);
    let c1 = d01 - c2 * (a0 + a1);
    let c0 = v0 - c1 * a0 - c2 * a0 * a0;
    let a = -c1 / (2.0 * c2);
    (c2 > 0.0 && a > a0.min(a2) && a < a0.max(a2)).then_some(c0 + c1 * a + c2 * a * a)
}

pub fn compare(case: &'static str, study_file: &str) -> Case {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("studies")
        .join(study_file);
    let plan = study::load(&path).expect("study");
    let model = plan.model().expect("model");
    let opts = plan.bifurcation_options();
    let report = analyse(&plan.name, &model, &opts).expect("analysis");
    let hb = solutions(&data(case, "s.hb"));
    let auto_hopf = hb
        .iter()
        .find(|s| s.kind.abs() == 3)
        .map_or(f64::NAN, |s| s.par[1]);
    let fold = report
        .special
        .iter()
        .find(|s| s.kind == SpecialKind::Fold && s.located)
        .and_then(|s| auto_fold(&data(case, "b.po")).map(|a| (a, s.speed_m_s)));
    let mult = data(case, "multipliers.txt");
    let rows = solutions(&data(case, "s.po"))
        .iter()
        .filter(|s| s.kind.abs() == 4)
        .map(|s| {
            let (speed, auto_period) = (s.par[1], s.par[11]);
            let u = s.u[0];
            let x0 = [
                u[0] * 1e-3,
                u[1] * 1e-3,
                u[2] * 1e-3 * OMS,
                u[3] * 1e-3 * OMS,
            ];
            let solve = |rtol: f64, method: Method| {
                let (orbit, floquet, _) =
                    cycle_at_with(&model, speed, x0, auto_period, rtol, method)
                        .expect("critspeed cycle");
                let ode = OdeOptions {
                    tol: Tolerances::new(rtol, rtol * 1e-3).expect("tolerances"),
                    method,
                    ..OdeOptions::default()
                };
                let (_, peaks) =
                    integrate_with_peaks(&model, speed, &orbit.x0, 0.5 * orbit.period, &ode)
                        .expect("integration");
                let peaks: SVector<f64, 4> = peaks;
                (orbit, floquet, peaks[0] * 1e3)
            };
            let (orbit, floquet, amplitude_mm) = solve(opts.rtol, opts.integrator);
            // the reference: the 5th-order pair at 1e-12, whichever pair the study uses
            let (tight, _, tight_amplitude_mm) = solve(1e-12, Method::DormandPrince5);
            Row {
                speed,
                auto_period,
                period: orbit.period,
                auto_amplitude_mm: collocation_max(s),
                amplitude_mm,
                auto_critical: critical_of(&multipliers(&mult, s.pt)),
                critical: floquet.max_nontrivial,
                trivial_error: floquet.trivial_error,
                tight_period: tight.period,
                tight_amplitude_mm,
            }
        })
        .collect();
    Case {
        name: case,
        rtol: opts.rtol,
        integrator: match opts.integrator {
            Method::DormandPrince5 => "dopri5",
            Method::DormandPrince8 => "dop853",
        },
        auto_hopf,
        hopf: report.hopf.map_or(f64::NAN, |h| h.speed_m_s),
        fold,
        rows,
    }
}

pub fn section(s: &mut String) {
    let _ = writeln!(s, "## 8. AUTO-07p on the same equations\n");
    let _ = writeln!(s, "AUTO-07p 0.9.2 (orthogonal collocation, NTST 40, NCOL 4, EPSL = EPSU = 1e-10) runs the right-hand side `scripts/auto07p/wheelset.f90`, which evaluates the same functions as critspeed for `studies/seed-hunting-cone.toml` (cone, supercritical) and `studies/cubic-fold.toml` (r_R − r0 = 0.15 y + 2000 y³, subcritical with a fold). AUTO's results are stored in `tests/data/auto07p/` (regenerate with `scripts/auto07p-compare`); critspeed solves each AUTO user point's cycle at the same speed from AUTO's start state (`cycle_at_with`, at the study's `[bifurcation]` rtol and integrator, named with each case); the last two columns are both tools' relative errors against critspeed's cycle at rtol 1e-12 with the 5th-order pair (`dopri5`), whatever pair the study uses. Amplitudes: AUTO's is the maximum of its collocation polynomials, critspeed's the peak on its dense output. Multipliers: the largest nontrivial modulus; AUTO prints 5 significant digits.\n");
    for (case, file) in CASES {
        let c = compare(case, file);
        let _ = writeln!(
            s,
            "**{}** (`studies/{file}`, critspeed at rtol {:e} with `{}`): V_H AUTO {:.6} m/s, critspeed {:.6} m/s.",
            c.name, c.rtol, c.integrator, c.auto_hopf, c.hopf
        );
        if let Some((a, b)) = c.fold {
            let _ = writeln!(s, " Fold: AUTO {a:.4} m/s (vertex of the parabola through its three slowest branch points: AUTO detects the sign change of its fold function but its location does not converge here), critspeed {b:.6} m/s (located).");
        }
        let _ = writeln!(s, "\n| V (m/s) | period AUTO (s) | critspeed | rel. diff. | max y AUTO (mm) | critspeed | rel. diff. | largest nontrivial &#124;μ&#124; AUTO | critspeed | period error AUTO, critspeed | max y error AUTO, critspeed |\n|---|---|---|---|---|---|---|---|---|---|---|");
        for r in &c.rows {
            let _ = writeln!(
                s,
                "| {:.4} | {:.10} | {:.10} | {:.1e} | {:.7} | {:.7} | {:.1e} | {:.5} | {:.5} | {:.0e}, {:.0e} | {:.0e}, {:.0e} |",
                r.speed,
                r.auto_period,
                r.period,
                (r.period - r.auto_period) / r.auto_period,
                r.auto_amplitude_mm,
                r.amplitude_mm,
                (r.amplitude_mm - r.auto_amplitude_mm) / r.auto_amplitude_mm,
                r.auto_critical,
                r.critical,
                (r.auto_period - r.tight_period) / r.tight_period,
                (r.period - r.tight_period) / r.tight_period,
                (r.auto_amplitude_mm - r.tight_amplitude_mm) / r.tight_amplitude_mm,
                (r.amplitude_mm - r.tight_amplitude_mm) / r.tight_amplitude_mm,
            );
        }
        let worst = c.rows.iter().map(|r| r.trivial_error).fold(0.0, f64::max);
        let _ = writeln!(
            s,
            "\ncritspeed's trivial multipliers are within {worst:.0e} of 1.\n"
        );
    }
}
