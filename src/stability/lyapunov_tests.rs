//! $l_1$ against closed forms: the Hopf normal form, the same form in curved coordinates
//! (quadratic terms, the same $l_1$), a centre-manifold system whose $l_1$ comes from both
//! $B$ terms, and a non-polynomial field on which the step extrapolation must converge.

use nalgebra::{SMatrix, SVector};

use super::*;
use crate::reference::HopfNormalForm;
use crate::system::scalar::{Dual, Scalar};

/// A field written once over [`Scalar`], with its Jacobian from dual numbers.
trait Generic<const N: usize>: Sync {
    fn f<T: Scalar>(&self, x: &[T; N], mu: f64) -> [T; N];
}

struct Field<G>(G);

impl<const N: usize, G: Generic<N>> VectorField<N> for Field<G> {
    fn rhs(&self, x: &SVector<f64, N>, mu: f64) -> SVector<f64, N> {
        let xs: [f64; N] = std::array::from_fn(|k| x[k]);
        SVector::from(self.0.f(&xs, mu))
    }
    fn jacobian(&self, x: &SVector<f64, N>, mu: f64) -> SMatrix<f64, N, N> {
        let xd: [Dual<N>; N] = std::array::from_fn(|k| Dual::var(x[k], k));
        let r = self.0.f(&xd, mu);
        SMatrix::from_fn(|i, j| r[i].eps[j])
    }
}

/// The normal form $\dot w = F(w)$ seen in $x = (w_1, w_2 + k w_1^2)$: quadratic terms
/// appear, $B \ne 0$, but $l_1$ (a normal-form invariant, and $x_1 = w_1$ keeps the
/// reference amplitude) stays $a/ω$.
struct Curved {
    omega: f64,
    a: f64,
    k: f64,
}

impl Generic<2> for Curved {
    fn f<T: Scalar>(&self, x: &[T; 2], mu: f64) -> [T; 2] {
        let w1 = x[0];
        let w2 = x[1] - w1 * w1 * self.k;
        let g = (w1 * w1 + w2 * w2) * self.a + mu;
        let f1 = g * w1 - w2 * self.omega;
        let f2 = w1 * self.omega + g * w2;
        [f1, f2 + w1 * f1 * (2.0 * self.k)]
    }
}

/// $\dot x = μx − ωy + s x z$, $\dot y = ωx + μy$, $\dot z = −λz + κx^2$: on the centre
/// manifold $z$ is slaved with a mean and a second harmonic, and
/// $ω l_1 = sκ[1/(4λ) + λ/(8(λ^2 + 4ω^2))]$ (the $J^{-1}B(q,\bar q)$ and
/// $(2iωI − J)^{-1}B(q,q)$ terms of the formula, one each).
struct Slaved {
    omega: f64,
    lambda: f64,
    kappa: f64,
    s: f64,
}

impl Generic<3> for Slaved {
    fn f<T: Scalar>(&self, x: &[T; 3], mu: f64) -> [T; 3] {
        let [u, v, z] = *x;
        [
            u * mu - v * self.omega + u * z * self.s,
            u * self.omega + v * mu,
            -(z * self.lambda) + u * u * self.kappa,
        ]
    }
}

impl Slaved {
    fn l1(&self) -> f64 {
        let (w, l) = (self.omega, self.lambda);
        self.s * self.kappa * (1.0 / (4.0 * l) + l / (8.0 * (l * l + 4.0 * w * w))) / w
    }
}

/// $\dot r = r(μ + a(e^{r^2} − 1))$ in Cartesian coordinates: $l_1 = a/ω$, but every
/// difference step sees the $r^4, r^6, …$ terms, so only the extrapolation gives it to rounding.
struct Exponential {
    omega: f64,
    a: f64,
}

impl Generic<2> for Exponential {
    fn f<T: Scalar>(&self, x: &[T; 2], mu: f64) -> [T; 2] {
        let r2 = x[0] * x[0] + x[1] * x[1];
        let e = r2.re().exp();
        let g = (r2.lift(e, e) - 1.0) * self.a + mu;
        [g * x[0] - x[1] * self.omega, x[0] * self.omega + g * x[1]]
    }
}

fn opts(step: f64) -> LyapunovOptions {
    LyapunovOptions {
        initial_step: step,
        ..LyapunovOptions::default()
    }
}

/// $l_1 = a/ω$ for $\dot r = r(μ + a r^2 + b r^4)$, both signs, and the type follows.
#[test]
fn normal_form_gives_a_over_omega() {
    for (a, kind) in [
        (-0.7, HopfKind::Supercritical),
        (1.3, HopfKind::Subcritical),
    ] {
        let nf = HopfNormalForm {
            omega: 2.0,
            a,
            b: 0.3,
        };
        let l = first_lyapunov(&nf, 0.0, 2.0, &opts(0.1)).expect("l1");
        assert!((l.l1 - a / 2.0).abs() < 1e-12, "{a}: {l:?}");
        assert_eq!(l.kind(), kind);
        assert!((l.omega - 2.0).abs() < 1e-14 && l.sigma.abs() < 1e-14);
        // ⟨p, q⟩ = 1 and q_ref = 1/2
        assert!((dot(&l.p, &l.q) - C64::new(1.0, 0.0)).norm() < 1e-14);
        assert!((l.q[0] - C64::new(0.5, 0.0)).norm() < 1e-15);
    }
    // a = 0: the generalised Hopf (Bautin) point of this family; the sign is undecided
    let nf = HopfNormalForm {
        omega: 2.0,
        a: 0.0,
        b: -1.0,
    };
    let l = first_lyapunov(&nf, 0.0, 2.0, &opts(0.1)).expect("l1");
    assert!(l.l1.abs() < 1e-12, "{l:?}");
    assert_eq!(l.kind(), HopfKind::Undecided);
}

/// Quadratic terms from a curved coordinate do not change $l_1$, whatever their size.
#[test]
fn curved_coordinates_keep_l1() {
    for k in [0.0, 0.8, -2.5] {
        let f = Field(Curved {
            omega: 1.5,
            a: -0.4,
            k,
        });
        let l = first_lyapunov(&f, 0.0, 1.5, &opts(1e-2)).expect("l1");
        assert!(
            (l.l1 - (-0.4 / 1.5)).abs() < 1e-9,
            "k = {k}: {} (error {:e})",
            l.l1,
            l.error
        );
    }
}

/// Both $B$ terms of the formula against the centre-manifold closed form.
#[test]
fn slaved_mode_matches_the_centre_manifold_closed_form() {
    for (lambda, kappa, s) in [(0.5, 1.0, 1.0), (3.0, -2.0, 0.7), (0.2, 1.5, -1.1)] {
        let sys = Slaved {
            omega: 1.7,
            lambda,
            kappa,
            s,
        };
        let want = sys.l1();
        let l = first_lyapunov(&Field(sys), 0.0, 1.7, &opts(1e-2)).expect("l1");
        assert!(
            (l.l1 - want).abs() < 1e-9 * want.abs(),
            "λ {lambda}: {} against {want}",
            l.l1
        );
    }
}

/// On a non-polynomial field the single-step values converge like $h^2$, the extrapolation
/// reaches the closed form far below the error of any single step, its error estimate covers
/// its actual error, and the result does not depend on the first step.
#[test]
fn extrapolation_converges_and_its_error_estimate_holds() {
    let f = Field(Exponential {
        omega: 1.0,
        a: -1.0,
    });
    let want = -1.0;
    // single steps: the error falls by a factor of 4 per halving
    let at = Point::new(&f, 0.0, 1.0, &LyapunovOptions::default()).expect("point");
    let single = |h: f64| at.value(h).expect("value");
    let (e1, e2) = ((single(0.2) - want).abs(), (single(0.1) - want).abs());
    assert!(e1 > 1e-4 && (e1 / e2 - 4.0).abs() < 0.2, "{e1:e} {e2:e}");
    for h0 in [0.05, 0.2, 0.5] {
        let l = first_lyapunov(&f, 0.0, 1.0, &opts(h0)).expect("l1");
        assert!((l.l1 - want).abs() < 1e-9, "h0 {h0}: {l:?}");
        assert!(
            (l.l1 - want).abs() <= 10.0 * l.error + 1e-14,
            "h0 {h0}: {l:?}"
        );
        assert!(l.error < 1e-8, "h0 {h0}: {}", l.error);
    }
}

/// The options' rules, and a reference state that does not move.
#[test]
fn bad_options_and_reference_are_refused() {
    let nf = HopfNormalForm {
        omega: 1.0,
        a: -1.0,
        b: 0.0,
    };
    for o in [
        LyapunovOptions {
            initial_step: 0.0,
            ..LyapunovOptions::default()
        },
        LyapunovOptions {
            halvings: 0,
            ..LyapunovOptions::default()
        },
        LyapunovOptions {
            reference: 2,
            ..LyapunovOptions::default()
        },
    ] {
        assert!(matches!(
            first_lyapunov(&nf, 0.0, 1.0, &o),
            Err(LyapunovError::Options(_))
        ));
    }
    // the slaved z does not move in the critical mode
    let f = Field(Slaved {
        omega: 1.0,
        lambda: 1.0,
        kappa: 1.0,
        s: 1.0,
    });
    let o = LyapunovOptions {
        reference: 2,
        ..LyapunovOptions::default()
    };
    assert!(matches!(
        first_lyapunov(&f, 0.0, 1.0, &o),
        Err(LyapunovError::Reference { .. })
    ));
}
