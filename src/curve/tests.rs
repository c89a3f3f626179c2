//! The Hopf-curve continuation on families whose curves and special points are known in
//! closed form: a Bautin point where $l_1$ of a normal form changes sign, a double Hopf and a
//! zero-Hopf point where a second pair or a real eigenvalue crosses, a Bogdanov–Takens end,
//! and a circle, which has two folds in $P$ and closes on itself.

use nalgebra::SMatrix;

use super::family::HopfFamily;
use super::hopf::{HopfParams, State};
use super::trace::walk;
use super::{CurveError, CurveStop, SpecialKind};
use crate::reference::HopfNormalForm;
use crate::stability::{eigenvalues, first_lyapunov, Lyapunov, LyapunovOptions};

/// A family given by a closed-form $J(V, P)$ and, optionally, the cubic coefficient of a
/// normal form at the Hopf points (for $l_1 = a/ω$).
struct Closed<const N: usize> {
    j: fn(f64, f64) -> SMatrix<f64, N, N>,
    cubic: Option<fn(f64) -> f64>,
}

impl<const N: usize> HopfFamily<N> for Closed<N> {
    fn jacobian(&self, v: f64, p: f64) -> Result<SMatrix<f64, N, N>, CurveError> {
        Ok((self.j)(v, p))
    }
    fn jacobian_v(&self, v: f64, p: f64) -> Result<SMatrix<f64, N, N>, CurveError> {
        let h = 1e-6;
        Ok(((self.j)(v + h, p) - (self.j)(v - h, p)) / (2.0 * h))
    }
    fn jacobian_p(&self, v: f64, p: f64) -> Result<SMatrix<f64, N, N>, CurveError> {
        let h = 1e-6;
        Ok(((self.j)(v, p + h) - (self.j)(v, p - h)) / (2.0 * h))
    }
    fn lyapunov(&self, _v: f64, p: f64, omega: f64) -> Option<Lyapunov> {
        let a = (self.cubic?)(p);
        let nf = HopfNormalForm { omega, a, b: -1.0 };
        first_lyapunov::<2, _>(&nf, 0.0, omega, &LyapunovOptions::default()).ok()
    }
}

/// A rotation block with real part `re` and frequency `w` at rows/columns `k`, `k + 1`.
fn block<const N: usize>(m: &mut SMatrix<f64, N, N>, k: usize, re: f64, w: f64) {
    m[(k, k)] = re;
    m[(k + 1, k + 1)] = re;
    m[(k, k + 1)] = -w;
    m[(k + 1, k)] = w;
}

fn params(speed: (f64, f64), p: (f64, f64)) -> HopfParams {
    HopfParams {
        speed_range: speed,
        param_range: p,
        ds_initial: 0.005,
        ds_max: 0.02,
        ds_min: 1e-9,
        max_points: 400,
        newton_tol: 1e-12,
    }
}

fn start<const N: usize>(v: f64, p: f64, omega: f64, k: usize) -> State<N> {
    let mut s = State {
        a: nalgebra::SVector::zeros(),
        b: nalgebra::SVector::zeros(),
        omega,
        v,
        p,
    };
    // the rotation block's eigenvector for +iω: (1, −i)
    s.a[k] = 1.0;
    s.b[k + 1] = -1.0;
    s
}

/// Every point is a Hopf point: $J$ has an eigenvalue within 1e-10 of $iω$.
fn on_the_axis<const N: usize>(f: &Closed<N>, points: &[super::trace::TracedPoint<N>]) {
    for p in points {
        let s = &p.state;
        let ev = eigenvalues(&(f.j)(s.v, s.p)).expect("eigenvalues");
        let d = ev
            .iter()
            .map(|z| z.0.hypot(z.1 - s.omega))
            .fold(f64::INFINITY, f64::min);
        assert!(d < 1e-10, "({}, {}): {d:e}", s.v, s.p);
    }
}

/// $σ = V − P^2$, ω = 2, $l_1 = (P − 0.3)/2$: the Hopf curve $V = P^2$ with a Bautin point
/// at $P = 0.3$, $V = 0.09$; subcritical beyond it, supercritical before.
#[test]
fn bautin_point_is_located_where_l1_changes_sign() {
    let f = Closed::<2> {
        j: |v, p| {
            let mut m = SMatrix::zeros();
            block(&mut m, 0, v - p * p, 2.0);
            m
        },
        cubic: Some(|p| p - 0.3),
    };
    let pr = params((-1.0, 2.0), (-1.0, 1.0));
    let half = walk(&f, &start::<2>(0.0, 0.0, 2.0, 0), 1.0, &pr, None).expect("walk");
    on_the_axis(&f, &half.points);
    assert_eq!(half.stop, CurveStop::ParameterBound { parameter: 1.0 });
    let last = half.points.last().expect("points");
    assert!((last.state.p - 1.0).abs() < 1e-12 && (last.state.v - 1.0).abs() < 1e-10);
    let gh: Vec<_> = half
        .special
        .iter()
        .filter(|s| s.kind == SpecialKind::Bautin)
        .collect();
    assert_eq!(gh.len(), 1, "{:?}", half.special);
    assert!(gh[0].located);
    assert!((gh[0].state.p - 0.3).abs() < 1e-9, "{:?}", gh[0].state);
    assert!((gh[0].state.v - 0.09).abs() < 1e-9);
    assert!(half.special.iter().all(|s| s.kind == SpecialKind::Bautin));
}

/// A second pair with real part $P − 0.4$ (ω = 3) beside the continued one ($σ = V − P^2$,
/// ω = 1): a double Hopf point at $P = 0.4$; a real eigenvalue $P − 0.4$ instead: zero-Hopf.
#[test]
fn double_hopf_and_zero_hopf_points_are_located() {
    let hh = Closed::<4> {
        j: |v, p| {
            let mut m = SMatrix::zeros();
            block(&mut m, 0, v - p * p, 1.0);
            block(&mut m, 2, p - 0.4, 3.0);
            m
        },
        cubic: None,
    };
    let pr = params((-1.0, 2.0), (-1.0, 1.0));
    let half = walk(&hh, &start::<4>(0.0, 0.0, 1.0, 0), 1.0, &pr, None).expect("walk");
    on_the_axis(&hh, &half.points);
    let s: Vec<_> = half.special.iter().collect();
    assert_eq!(s.len(), 1, "{s:?}");
    assert_eq!(s[0].kind, SpecialKind::DoubleHopf);
    assert!(
        s[0].located && (s[0].state.p - 0.4).abs() < 1e-9 && (s[0].state.v - 0.16).abs() < 1e-9
    );
    let second = s[0]
        .eval
        .as_ref()
        .and_then(|e| e.second)
        .expect("second pair");
    assert!((second.1 - 3.0).abs() < 1e-9 && second.0.abs() < 1e-9);

    let zh = Closed::<3> {
        j: |v, p| {
            let mut m = SMatrix::zeros();
            block(&mut m, 0, v - p * p, 1.0);
            m[(2, 2)] = p - 0.4;
            m
        },
        cubic: None,
    };
    let half = walk(&zh, &start::<3>(0.0, 0.0, 1.0, 0), 1.0, &pr, None).expect("walk");
    let s: Vec<_> = half.special.iter().collect();
    assert_eq!(s.len(), 1, "{s:?}");
    assert_eq!(s[0].kind, SpecialKind::ZeroHopf);
    assert!(s[0].located && (s[0].state.p - 0.4).abs() < 1e-9);
}

/// $J = [[0, 1], [P, V]]$: Hopf points $V = 0$ for $P < 0$ with $ω = \sqrt{−P}$; the pair
/// meets at zero at $P = 0$, a Bogdanov–Takens point, where the curve ends.
#[test]
fn the_curve_ends_at_a_bogdanov_takens_point() {
    let bt = Closed::<2> {
        j: |v, p| SMatrix::<f64, 2, 2>::new(0.0, 1.0, p, v),
        cubic: None,
    };
    let pr = params((-1.0, 1.0), (-1.0, 0.5));
    // at P = −1: ω = 1, eigenvector of [[0, 1], [−1, 0]] for i: (1, i)
    let mut s = start::<2>(0.0, -1.0, 1.0, 0);
    s.b[1] = 1.0;
    let half = walk(&bt, &s, 1.0, &pr, None).expect("walk");
    on_the_axis(&bt, &half.points);
    let CurveStop::BogdanovTakens {
        parameter,
        speed_m_s,
    } = half.stop
    else {
        panic!("{:?}", half.stop);
    };
    assert!(
        parameter.abs() < 1e-8 && speed_m_s.abs() < 1e-8,
        "{parameter} {speed_m_s}"
    );
    assert_eq!(half.special.len(), 1);
    assert_eq!(half.special[0].kind, SpecialKind::BogdanovTakens);
    // ω = √(−P) along the way
    for p in &half.points {
        assert!((p.state.omega - (-p.state.p).sqrt()).abs() < 1e-9);
    }
}

/// $σ = 1 − V^2 − P^2$: the Hopf curve is the unit circle, with folds in $P$ at $(±1, 0)$.
/// From $(0, 1)$ the continuation goes round both folds and stops where it started.
#[test]
fn the_curve_passes_folds_in_the_key_and_closes() {
    let circle = Closed::<2> {
        j: |v, p| {
            let mut m = SMatrix::zeros();
            block(&mut m, 0, 1.0 - v * v - p * p, 1.5);
            m
        },
        cubic: None,
    };
    let pr = params((-2.0, 2.0), (-2.0, 2.0));
    let half = walk(&circle, &start::<2>(1.0, 0.0, 1.5, 0), 1.0, &pr, None).expect("walk");
    assert_eq!(half.stop, CurveStop::Closed);
    on_the_axis(&circle, &half.points);
    for p in &half.points {
        assert!((p.state.v.hypot(p.state.p) - 1.0).abs() < 1e-10);
    }
    let (pmin, pmax) = half.points.iter().fold((0.0f64, 0.0f64), |(a, b), p| {
        (a.min(p.state.p), b.max(p.state.p))
    });
    assert!(pmin < -0.99 && pmax > 0.99, "{pmin} {pmax}");
}
