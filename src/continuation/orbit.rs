//! Periodic orbits by single shooting, with the period and the parameter as unknowns.
//!
//! For a vector field $\dot x = f(x; p)$ with flow $φ_t(x; p)$ a periodic orbit through $x_0$
//! with period $T$ satisfies $φ_T(x_0) − x_0 = 0$. When the field is odd, $f(−x) = −f(x)$ (the
//! wheelset on tangent track, docs/model.md §9), the primary cycles are *symmetric*,
//! $x(t + T/2) = −x(t)$, and the half-period condition $φ_{T/2}(x_0) + x_0 = 0$ is used instead:
//! half the integration, and the symmetry is exact. Its multipliers $ν$ (eigenvalues of
//! $−Φ_{T/2}$) give the full Floquet multipliers $μ = ν^2$, and tell symmetry breaking
//! ($ν = −1$, $μ = 1$) from a fold ($ν = +1$).
//!
//! The phase is fixed by the Poincaré condition $⟨f(x_r), x_0 − x_r⟩ = 0$ through a reference
//! point $x_r$ (the previous orbit's start).

use nalgebra::{Complex, DMatrix, DVector, SMatrix, SVector};

use crate::system::ode::{integrate, integrate_with_extremes, OdeError, OdeOptions, VectorField};

/// The shooting problem: a vector field, whether to use the symmetric half-period form, the
/// number of segments, and the integrator options.
///
/// **Segments.** With `segments = m > 1` the shooting interval is cut into `m` equal pieces
/// (multiple shooting): each piece starts from its own state $x_i$ and is integrated
/// independently (with its monodromy $Φ_i$ and parameter difference), so the pieces run on
/// rayon threads. The interior unknowns are condensed out — $δx_{i+1} = Φ_iδx_i + g_iδT +
/// q_iδp + (e_i − x_{i+1})$ — so the caller still sees the $N × (N + 2)$ residual and Jacobian
/// of single shooting in $(x_0, T, p)$, with the monodromy $Φ_{m−1}\cdotsΦ_0$. The interior
/// starts of the next linearisation are the Newton-updated ones, from the previous
/// linearisation's [`SegmentSeed`] (at a fresh start they are integrated from $x_0$).
pub struct Shooting<'a, const N: usize, F: VectorField<N>> {
    /// the vector field
    pub field: &'a F,
    /// use $φ_{T/2}(x_0) + x_0 = 0$ (requires an odd field)
    pub symmetric: bool,
    /// integrator options (tolerances); the monodromy flag is set internally
    pub ode: OdeOptions,
    /// run the independent integrations of each Newton step (per segment: the flow with its
    /// monodromy, and the parameter perturbation) on rayon threads; the results are bitwise
    /// identical to the serial run because the integrations are pure and independent
    pub parallel: bool,
    /// while this flag is up (another computation has the pool's workers), integrate the
    /// segments one after the other on the calling thread instead (the same numbers); `None`:
    /// `parallel` alone decides
    pub busy: Option<PoolBusy>,
    /// relative step of the one-sided difference for ∂φ/∂p; about √rtol balances truncation
    /// against integration noise. Its error only affects the Newton rate and the predictor,
    /// never the converged orbits, nor the folds (where the (x0, T) block is singular).
    pub dp_rel: f64,
    /// shooting segments m >= 1 (1: single shooting); each is one independent piece of work
    pub segments: usize,
}

/// One flow evaluation: end state, monodromy (when asked for), integrator steps, the largest
/// and smallest x_k over the interval, and the first accepted step size.
struct Flowed<const N: usize> {
    end: SVector<f64, N>,
    phi: Option<SMatrix<f64, N, N>>,
    steps: usize,
    rejected: usize,
    high: SVector<f64, N>,
    low: SVector<f64, N>,
    h_first: f64,
}

/// One point of an orbit computation: the start, period and parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OrbitPoint<const N: usize> {
    /// start of the orbit on the phase section
    pub x0: SVector<f64, N>,
    /// period T
    pub period: f64,
    /// parameter p
    pub param: f64,
}

/// One segment of a linearisation: its start, end, monodromy and the end's derivatives in
/// T and p.
#[derive(Clone, Debug, PartialEq)]
struct Segment<const N: usize> {
    start: SVector<f64, N>,
    end: SVector<f64, N>,
    phi: SMatrix<f64, N, N>,
    d_t: SVector<f64, N>,
    d_p: SVector<f64, N>,
    /// first accepted steps of the flow and of the shifted flow (the next trial steps)
    h_first: (f64, f64),
}

/// What a multiple-shooting linearisation at `z` knows of its segments: the interior starts
/// of a linearisation at a nearby `z'` follow from it by the Newton update of the condensed
/// unknowns, $x_{i+1}' = e_i + Φ_i(x_i' − x_i) + g_i(T' − T) + q_i(p' − p)$.
#[derive(Clone, Debug, PartialEq)]
pub struct SegmentSeed<const N: usize> {
    z: OrbitPoint<N>,
    segments: Vec<Segment<N>>,
}

impl<const N: usize> SegmentSeed<N> {
    /// Number of segments.
    pub fn len(&self) -> usize {
        self.segments.len()
    }

    /// Whether there are no segments (never, for a linearisation's seed).
    pub fn is_empty(&self) -> bool {
        self.segments.is_empty()
    }

    /// The start of segment `i` (segment 0 starts at the orbit's $x_0$).
    pub fn start(&self, i: usize) -> Option<SVector<f64, N>> {
        self.segments.get(i).map(|s| s.start)
    }

    /// The end of the shooting interval with the interior mismatches carried through by the
    /// segments' Φ (the second value of [`condensed`](Self::condensed), which takes it from
    /// here; a chord iteration needs it alone).
    fn condensed_end(&self) -> SVector<f64, N> {
        let mut c = SVector::<f64, N>::zeros();
        for (s, next) in self.segments.iter().zip(self.segments.iter().skip(1)) {
            c = s.phi * c + (s.end - next.start);
        }
        self.segments
            .last()
            .map_or(self.z.x0, |last| last.end + last.phi * c)
    }

    /// The condensed linearisation of these segments: the monodromy $Φ_{m−1}\cdotsΦ_0$, the
    /// end of the shooting interval with the interior mismatches carried through, and the
    /// $N × (N + 2)$ Jacobian $[∂G/∂x_0 \;|\; ∂G/∂T \;|\; ∂G/∂p]$ of the residual ($G = $ end
    /// $+ x_0$ for the symmetric half-period form, end $− x_0$ else).
    fn condensed(&self, symmetric: bool) -> (SMatrix<f64, N, N>, SVector<f64, N>, DMatrix<f64>) {
        let m = self.segments.len();
        // δx_i = A δx0 + G δT + Q δp + C, condensed segment by segment (C in `condensed_end`)
        let mut a = SMatrix::<f64, N, N>::identity();
        let (mut g, mut q) = (SVector::zeros(), SVector::zeros());
        for s in self.segments.iter().take(m.saturating_sub(1)) {
            a = s.phi * a;
            g = s.phi * g + s.d_t;
            q = s.phi * q + s.d_p;
        }
        let end = self.condensed_end();
        let mut jacobian = DMatrix::zeros(N, N + 2);
        let Some(last) = self.segments.last() else {
            return (a, end, jacobian);
        };
        let monodromy = last.phi * a;
        let sign = if symmetric { 1.0 } else { -1.0 };
        let d_x0 = monodromy + SMatrix::<f64, N, N>::identity() * sign;
        jacobian.view_mut((0, 0), (N, N)).copy_from(&d_x0);
        jacobian
            .view_mut((0, N), (N, 1))
            .copy_from(&(last.phi * g + last.d_t));
        jacobian
            .view_mut((0, N + 1), (N, 1))
            .copy_from(&(last.phi * q + last.d_p));
        (monodromy, end, jacobian)
    }

    fn starts(&self, z: &OrbitPoint<N>) -> Vec<SVector<f64, N>> {
        let (dt, dp) = (z.period - self.z.period, z.param - self.z.param);
        let mut out = vec![z.x0];
        for (i, prev) in self
            .segments
            .iter()
            .enumerate()
            .take(self.segments.len() - 1)
        {
            let dx = out[i] - prev.start;
            out.push(prev.end + prev.phi * dx + prev.d_t * dt + prev.d_p * dp);
        }
        out
    }
}

/// A flag a computation raises while it keeps the rayon pool's workers busy (the curves of
/// cycles followed beside a diagram): a [`Shooting`] holding it integrates serially while it
/// is up, and in parallel again when it is down. Linearisations are the same either way; the
/// flag only decides who computes them. Clones share the flag.
#[derive(Clone, Debug, Default)]
pub struct PoolBusy(std::sync::Arc<std::sync::atomic::AtomicBool>);

impl PoolBusy {
    /// A lowered flag.
    pub fn new() -> Self {
        Self::default()
    }

    /// Raises (`true`) or lowers the flag.
    pub fn set(&self, up: bool) {
        self.0.store(up, std::sync::atomic::Ordering::Relaxed);
    }

    /// Whether the flag is up.
    pub fn is_up(&self) -> bool {
        self.0.load(std::sync::atomic::Ordering::Relaxed)
    }
}

/// Two options are equal when they share the flag.
impl PartialEq for PoolBusy {
    fn eq(&self, other: &Self) -> bool {
        std::sync::Arc::ptr_eq(&self.0, &other.0)
    }
}

/// The residual and its Jacobian with respect to (x0, T, p), as an N × (N + 2) matrix.
pub struct Linearised<const N: usize> {
    /// $G(x_0, T, p)$ (condensed over the segments)
    pub residual: SVector<f64, N>,
    /// $[∂G/∂x_0 \;|\; ∂G/∂T \;|\; ∂G/∂p]$
    pub jacobian: DMatrix<f64>,
    /// the (half-period when symmetric) monodromy $Φ$, the product over the segments
    pub monodromy: SMatrix<f64, N, N>,
    /// state at the end of the shooting interval
    pub end: SVector<f64, N>,
    /// integrator steps used (all segments, the flows with their monodromy)
    pub steps: usize,
    /// integrator steps rejected by the error test (the same flows)
    pub rejected: usize,
    /// the largest $|x_k|$ over the whole orbit, per component (located on the integrator's
    /// continuous extension); for a symmetric orbit the half period holds the maximum over the
    /// whole period
    pub peaks: SVector<f64, N>,
    /// the largest $x_k$ over the whole orbit (for a symmetric orbit, $x(t + T/2) = −x(t)$
    /// makes it the largest $|x_k|$ of the half period)
    pub high: SVector<f64, N>,
    /// the smallest $x_k$ over the whole orbit (−`high` for a symmetric orbit)
    pub low: SVector<f64, N>,
    /// the segments, for the interior starts of the next linearisation
    pub seed: SegmentSeed<N>,
}

impl<'a, const N: usize, F: VectorField<N>> Shooting<'a, N, F> {
    fn horizon(&self, period: f64) -> f64 {
        if self.symmetric {
            0.5 * period
        } else {
            period
        }
    }

    fn count(&self) -> usize {
        self.segments.max(1)
    }

    #[allow(clippy::too_many_arguments)]
    fn flow(
        &self,
        x0: &SVector<f64, N>,
        span: f64,
        p: f64,
        monodromy: bool,
        h_initial: f64,
        rtol: f64,
    ) -> Result<Flowed<N>, OdeError> {
        let opts = OdeOptions {
            monodromy,
            tol: crate::system::ode::Tolerances {
                rtol,
                ..self.ode.tol
            },
            h_initial: (h_initial.is_finite() && h_initial > 0.0)
                .then_some(h_initial)
                .or(self.ode.h_initial),
            ..self.ode
        };
        let (s, high, low) = if monodromy {
            integrate_with_extremes(self.field, p, x0, span, &opts)?
        } else {
            let s = integrate(self.field, p, x0, span, &opts)?;
            (s, SVector::zeros(), SVector::zeros())
        };
        Ok(Flowed {
            end: s.x,
            phi: s.monodromy,
            steps: s.stats.steps,
            rejected: s.stats.rejected,
            high,
            low,
            h_first: s.h_first,
        })
    }

    fn residual_of(&self, x0: &SVector<f64, N>, end: &SVector<f64, N>) -> SVector<f64, N> {
        if self.symmetric {
            end + x0
        } else {
            end - x0
        }
    }

    /// The shooting residual and its Jacobian at `z`; interior segment starts (if
    /// `segments > 1`) are integrated from $x_0$.
    pub fn linearise(&self, z: &OrbitPoint<N>) -> Result<Linearised<N>, OdeError> {
        self.linearise_from(z, None)
    }

    /// As [`linearise`](Self::linearise), with the interior segment starts from `seed` (a
    /// previous linearisation nearby) when it has this problem's segment count.
    pub fn linearise_from(
        &self,
        z: &OrbitPoint<N>,
        seed: Option<&SegmentSeed<N>>,
    ) -> Result<Linearised<N>, OdeError> {
        self.linearise_at(z, seed, self.ode.tol.rtol)
    }

    /// As [`linearise_from`](Self::linearise_from), with the flows integrated at the relative
    /// tolerance `rtol` instead of the problem's (and the parameter difference scaled to
    /// match, $\sqrt{\mathrm{rtol}}$): an inexact Newton iteration far from the orbit, where
    /// the update need not be accurate to the final tolerance.
    pub fn linearise_at(
        &self,
        z: &OrbitPoint<N>,
        seed: Option<&SegmentSeed<N>>,
        rtol: f64,
    ) -> Result<Linearised<N>, OdeError> {
        let m = self.count();
        let span = self.horizon(z.period) / m as f64;
        let seed = seed.filter(|s| s.segments.len() == m);
        let starts = match seed {
            Some(s) => s.starts(z),
            None => {
                let mut v = vec![z.x0];
                for i in 1..m {
                    v.push(
                        self.flow(&v[i - 1], span, z.param, false, f64::NAN, rtol)?
                            .end,
                    );
                }
                v
            }
        };
        // the previous linearisation's first steps: no step-size search at each restart
        let h0: Vec<(f64, f64)> = (0..m)
            .map(|i| seed.map_or((f64::NAN, f64::NAN), |s| s.segments[i].h_first))
            .collect();
        // ∂φ/∂p by a one-sided difference: the integrator has no parameter sensitivities, and
        // one extra integration instead of two is worth the O(h) error in a Newton column
        // (it changes the convergence rate slightly, not the converged orbit).
        let h = self.dp_rel * (rtol / self.ode.tol.rtol).sqrt() * z.param.abs().max(1.0);
        // one rayon thread: no join (from outside the pool each join is a hand-over to the
        // worker and back, a tenth of the one-thread cone branch in futex calls)
        let parallel = self.parallel
            && rayon::current_num_threads() > 1
            && !self.busy.as_ref().is_some_and(PoolBusy::is_up);
        let piece = |(x, h0): (&SVector<f64, N>, &(f64, f64))| {
            let main = || self.flow(x, span, z.param, true, h0.0, rtol);
            let shifted = || self.flow(x, span, z.param + h, false, h0.1, rtol);
            if parallel {
                rayon::join(main, shifted)
            } else {
                (main(), shifted())
            }
        };
        let flows: Vec<_> = if parallel && m > 1 {
            use rayon::prelude::*;
            starts.par_iter().zip(h0.par_iter()).map(piece).collect()
        } else {
            starts.iter().zip(h0.iter()).map(piece).collect()
        };
        let dtau = self.horizon(1.0) / m as f64;
        let mut segments = Vec::with_capacity(m);
        let (mut steps, mut rejected) = (0, 0);
        let mut high = SVector::<f64, N>::repeat(f64::NEG_INFINITY);
        let mut low = SVector::<f64, N>::repeat(f64::INFINITY);
        for (start, (a, b)) in starts.iter().zip(flows) {
            let (a, b) = (a?, b?);
            let phi = a.phi.ok_or(OdeError::NonFinite { t: 0.0 })?;
            steps += a.steps;
            rejected += a.rejected;
            high = high.sup(&a.high);
            low = low.inf(&a.low);
            segments.push(Segment {
                start: *start,
                end: a.end,
                phi,
                d_t: self.field.rhs(&a.end, z.param) * dtau,
                d_p: (b.end - a.end) / h,
                h_first: (a.h_first, b.h_first),
            });
        }
        let seed = SegmentSeed { z: *z, segments };
        let (monodromy, end, jacobian) = seed.condensed(self.symmetric);
        let residual = self.residual_of(&z.x0, &end);
        if self.symmetric {
            // the second half period is the first one negated
            high = high.sup(&(-low));
            low = -high;
        }
        let peaks = high.abs().sup(&low.abs());
        Ok(Linearised {
            residual,
            jacobian,
            monodromy,
            end,
            steps,
            rejected,
            peaks,
            high,
            low,
            seed,
        })
    }
}

impl<'a, const N: usize, F: VectorField<N>> Shooting<'a, N, F> {
    /// The shooting residual at `z` by the plain flows alone, with the Jacobian of an earlier
    /// linearisation (`frozen`, which has this problem's segment count): one chord iteration
    /// of Newton's method. The interior starts follow from `frozen` as in
    /// [`linearise_from`](Self::linearise_from), and the segments' mismatches are condensed
    /// with its monodromies $Φ_i$, so that the update from the frozen bordered matrix is the
    /// chord update of the whole multiple-shooting system. The returned seed carries the new
    /// starts and ends with the frozen derivatives (the next chord iteration's).
    ///
    /// A plain flow costs a fraction of a flow with its monodromy (the variational equations
    /// are N + 1 times the state; on the DTU car's call-graph profile the plain flows were a
    /// fifteenth of the variational ones over the same spans), so a chord iteration is much
    /// cheaper than a Newton iteration; it converges linearly, at a rate set by how far the
    /// frozen Jacobian is from the current one. Only the condensed end is formed here, not the
    /// frozen Jacobian, which the caller keeps factorised.
    pub fn residual_chord(
        &self,
        z: &OrbitPoint<N>,
        frozen: &SegmentSeed<N>,
        rtol: f64,
    ) -> Result<Chord<N>, OdeError> {
        let m = self.count();
        if frozen.segments.len() != m {
            return Err(OdeError::BadArgument {
                name: "the kept linearisation's segment count",
                value: frozen.segments.len() as f64,
                rule: "must equal the shooting's segment count",
            });
        }
        let span = self.horizon(z.period) / m as f64;
        let starts = frozen.starts(z);
        let parallel = self.parallel
            && rayon::current_num_threads() > 1
            && m > 1
            && !self.busy.as_ref().is_some_and(PoolBusy::is_up);
        let piece = |(x, s): (&SVector<f64, N>, &Segment<N>)| {
            self.flow(x, span, z.param, false, s.h_first.0, rtol)
        };
        let flows: Vec<_> = if parallel {
            use rayon::prelude::*;
            starts
                .par_iter()
                .zip(frozen.segments.par_iter())
                .map(piece)
                .collect()
        } else {
            starts
                .iter()
                .zip(frozen.segments.iter())
                .map(piece)
                .collect()
        };
        let mut segments = Vec::with_capacity(m);
        let (mut steps, mut rejected) = (0, 0);
        for ((start, old), f) in starts.iter().zip(&frozen.segments).zip(flows) {
            let f = f?;
            if !f.end.iter().all(|v| v.is_finite()) {
                return Err(OdeError::NonFinite { t: span });
            }
            steps += f.steps;
            rejected += f.rejected;
            segments.push(Segment {
                start: *start,
                end: f.end,
                h_first: (f.h_first, old.h_first.1),
                ..old.clone()
            });
        }
        let seed = SegmentSeed { z: *z, segments };
        let end = seed.condensed_end();
        Ok(Chord {
            residual: self.residual_of(&z.x0, &end),
            steps,
            rejected,
            seed,
        })
    }
}

/// One chord iteration's residual (see [`Shooting::residual_chord`]).
pub struct Chord<const N: usize> {
    /// $G(x_0, T, p)$, condensed over the segments with the frozen monodromies
    pub residual: SVector<f64, N>,
    /// integrator steps of the plain flows
    pub steps: usize,
    /// integrator steps rejected by the error test
    pub rejected: usize,
    /// the new starts and ends with the frozen derivatives
    pub seed: SegmentSeed<N>,
}

/// Floquet multipliers of an orbit from its shooting monodromy.
#[derive(Clone, Debug, PartialEq)]
pub struct Floquet {
    /// the full-period multipliers μ, sorted by decreasing modulus
    pub multipliers: Vec<Complex<f64>>,
    /// for symmetric orbits the half-period multipliers ν (μ = ν²), same order
    pub half: Option<Vec<Complex<f64>>>,
    /// distance of the multiplier nearest to 1 from 1: the accuracy figure
    pub trivial_error: f64,
    /// largest modulus of the others (the orbit is stable when < 1)
    pub max_nontrivial: f64,
    /// index of the trivial multiplier in `multipliers` (and `half`)
    pub trivial: usize,
}

impl Floquet {
    /// Multipliers from the shooting monodromy (`symmetric`: $Φ_{T/2}$, else $Φ_T$).
    pub fn from_monodromy<const N: usize>(phi: &SMatrix<f64, N, N>, symmetric: bool) -> Self {
        let m = DMatrix::from_fn(
            N,
            N,
            |i, j| if symmetric { -phi[(i, j)] } else { phi[(i, j)] },
        );
        let Some(mut eig) = crate::stability::eigenvalues_dense(&m) else {
            // a monodromy with a non-finite entry, or whose eigenvalues did not converge: no
            // multipliers, and not stable
            let nan = vec![Complex::new(f64::NAN, f64::NAN); N];
            return Floquet {
                multipliers: nan.clone(),
                half: symmetric.then_some(nan),
                trivial_error: f64::INFINITY,
                max_nontrivial: f64::INFINITY,
                trivial: 0,
            };
        };
        eig.sort_by(|a, b| b.norm().total_cmp(&a.norm()));
        let (mu, half) = if symmetric {
            // |ν²| keeps the order of |ν|, so μ stays sorted and paired with ν
            let mu: Vec<Complex<f64>> = eig.iter().map(|v| v * v).collect();
            (mu, Some(eig.clone()))
        } else {
            (eig.clone(), None)
        };
        // The trivial multiplier: ν (or μ) closest to +1.
        let trivial = eig
            .iter()
            .enumerate()
            .min_by(|a, b| (a.1 - 1.0).norm().total_cmp(&(b.1 - 1.0).norm()))
            .map(|(k, _)| k)
            .unwrap_or(0);
        let trivial_error = eig.get(trivial).map_or(f64::NAN, |v| (v - 1.0).norm());
        let max_nontrivial = mu
            .iter()
            .enumerate()
            .filter(|(k, _)| *k != trivial)
            .map(|(_, v)| v.norm())
            .fold(0.0, f64::max);
        Floquet {
            multipliers: mu,
            half,
            trivial_error,
            max_nontrivial,
            trivial,
        }
    }

    /// The multipliers of the shooting map: ν (half period) for a symmetric orbit, μ else.
    pub fn shooting_multipliers(&self) -> &[Complex<f64>] {
        self.half.as_deref().unwrap_or(&self.multipliers)
    }

    /// All nontrivial multipliers inside the unit circle.
    pub fn stable(&self) -> bool {
        self.max_nontrivial < 1.0
    }
}

/// Why a Newton correction stopped.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum NewtonStop {
    /// the scaled update fell below the tolerance
    Converged,
    /// the iteration limit was reached
    MaxIterations,
    /// from the third iteration on, an update shrank by less than a quarter while still well
    /// above the tolerance: the iteration is not converging
    NotContracting,
    /// the bordered Jacobian was singular
    Singular,
    /// the residual or update became NaN/inf, or the integrator failed
    Diverged,
}

/// Solves the dense (N+2)×(N+2) bordered system; `None` when singular.
pub fn solve_dense(a: DMatrix<f64>, b: DVector<f64>) -> Option<DVector<f64>> {
    let lu = a.lu();
    let x = lu.solve(&b)?;
    x.iter().all(|v| v.is_finite()).then_some(x)
}
