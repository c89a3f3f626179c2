//! The two-parameter family the Hopf-curve continuation works on: the Jacobian of the centred
//! motion $J(V, P)$ with its derivatives, and $l_1$ at a Hopf point. [`StudyFamily`] is a
//! study with its design key; the tests use closed-form families.
//!
//! $P$ is the continuation's parameter: the key's value $p$ on a linear axis, $\ln p$ on a
//! log axis (so that a curve over decades of stiffness is resolved evenly on a log plot).

use std::cell::RefCell;
use std::rc::Rc;

use nalgebra::SMatrix;

use super::keyed::KeyedStudy;
use super::CurveError;
use crate::contact::creep::CreepLaw;
use crate::model::Vehicle;
use crate::stability::{first_lyapunov, LinearSystem, Lyapunov, LyapunovOptions};

/// $J(V, P)$ at the equilibrium and what the continuation needs of it.
pub trait HopfFamily<const N: usize> {
    /// $J(V, P)$.
    fn jacobian(&self, v: f64, p: f64) -> Result<SMatrix<f64, N, N>, CurveError>;
    /// $∂J/∂V$ at $(V, P)$.
    fn jacobian_v(&self, v: f64, p: f64) -> Result<SMatrix<f64, N, N>, CurveError>;
    /// $∂J/∂P$ at $(V, P)$ (a documented difference is enough: it only enters Newton's
    /// matrix and the tangent, never the residual).
    fn jacobian_p(&self, v: f64, p: f64) -> Result<SMatrix<f64, N, N>, CurveError>;
    /// $l_1$ at the Hopf point $(V, P)$ with frequency `omega` (rad/s), when it can be had.
    fn lyapunov(&self, v: f64, p: f64, omega: f64) -> Option<Lyapunov>;
    /// The key's value at $P$ (for output).
    fn value(&self, p: f64) -> f64 {
        p
    }
}

/// The model and $J = J_0 + J_1/V$ at one value of the key.
struct Entry<const N: usize> {
    p: f64,
    sys: LinearSystem<N>,
    model: Vehicle,
}

/// A study's centred-motion Jacobian over its design key, for one creep law. Models are
/// rebuilt by [`KeyedStudy::model_at`] and the last few kept.
pub struct StudyFamily<'s, const N: usize> {
    keyed: &'s KeyedStudy,
    /// Kalker's law (`true`) or the study's own at each key value (whose friction may be the
    /// key)
    kalker: bool,
    log: bool,
    /// the difference step of $∂J/∂P$ (in $P$)
    dp: f64,
    cache: RefCell<Vec<Rc<Entry<N>>>>,
    /// models built (the continuation's main cost)
    pub builds: RefCell<usize>,
    /// $(P, p)$ pairs whose value is exact (the range's ends: $e^{\ln p}$ is not always $p$)
    exact: Vec<(f64, f64)>,
}

/// Entries kept: the corrector and the difference for $∂J/∂P$ visit about five values a step.
const CACHED: usize = 8;

impl<'s, const N: usize> StudyFamily<'s, N> {
    /// The family of `keyed` under Kalker's law (`kalker`) or the study's own; `log`:
    /// $P = \ln p$. `span` is the width of the $P$
    /// range: the difference step of $∂J/∂P$ is $10^{-6}$ of it (a relative step where $J$ is
    /// smooth in $P$: the truncation error $O(10^{-12})$, rounding $O(10^{-10})$ relative).
    pub fn new(keyed: &'s KeyedStudy, kalker: bool, log: bool, span: f64) -> Self {
        Self {
            keyed,
            kalker,
            log,
            dp: 1e-6 * span.abs(),
            cache: RefCell::new(Vec::new()),
            builds: RefCell::new(0),
            exact: Vec::new(),
        }
    }

    /// Makes $P$ = `p` stand for exactly the key value `value` (the range's ends).
    pub fn exact_at(mut self, p: f64, value: f64) -> Self {
        self.exact.push((p, value));
        self
    }

    fn entry(&self, p: f64) -> Result<Rc<Entry<N>>, CurveError> {
        if let Some(e) = self
            .cache
            .borrow()
            .iter()
            .find(|e| e.p.to_bits() == p.to_bits())
        {
            return Ok(e.clone());
        }
        let mut model = self.keyed.model_at(self.value(p))?;
        *self.builds.borrow_mut() += 1;
        if model.states() != N {
            return Err(CurveError::Model {
                parameter: self.value(p),
                message: format!("the model has {} states, not {N}", model.states()),
            });
        }
        if self.kalker {
            model.contact.creep_law = CreepLaw::Kalker;
        }
        let e = Rc::new(Entry {
            p,
            sys: LinearSystem::<N>::at_centre(&model),
            model,
        });
        let mut cache = self.cache.borrow_mut();
        cache.insert(0, e.clone());
        cache.truncate(CACHED);
        Ok(e)
    }
}

impl<const N: usize> HopfFamily<N> for StudyFamily<'_, N> {
    fn jacobian(&self, v: f64, p: f64) -> Result<SMatrix<f64, N, N>, CurveError> {
        Ok(self.entry(p)?.sys.jacobian(v))
    }

    fn jacobian_v(&self, v: f64, p: f64) -> Result<SMatrix<f64, N, N>, CurveError> {
        Ok(self.entry(p)?.sys.j1 * (-1.0 / (v * v)))
    }

    /// Central difference over $P ± δ$; one-sided where a side is not a valid study (a
    /// damping of 0 cannot be differenced below 0).
    fn jacobian_p(&self, v: f64, p: f64) -> Result<SMatrix<f64, N, N>, CurveError> {
        let d = self.dp;
        let (lo, hi) = match (self.entry(p - d), self.entry(p + d)) {
            (Ok(a), Ok(b)) => ((a, p - d), (b, p + d)),
            (Err(_), Ok(b)) => ((self.entry(p)?, p), (b, p + d)),
            (Ok(a), Err(_)) => ((a, p - d), (self.entry(p)?, p)),
            (Err(e), Err(_)) => return Err(e),
        };
        Ok((lo.0.sys.jacobian(v) - hi.0.sys.jacobian(v)) / (lo.1 - hi.1))
    }

    fn lyapunov(&self, v: f64, p: f64, omega: f64) -> Option<Lyapunov> {
        let e = self.entry(p).ok()?;
        first_lyapunov::<N, _>(&e.model, v, omega, &LyapunovOptions::default()).ok()
    }

    fn value(&self, p: f64) -> f64 {
        if let Some((_, v)) = self.exact.iter().find(|e| e.0.to_bits() == p.to_bits()) {
            return *v;
        }
        if self.log {
            p.exp()
        } else {
            p
        }
    }
}
