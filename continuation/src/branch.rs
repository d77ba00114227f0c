//! Pseudo-arclength continuation of equilibria in one parameter (Keller 1977;
//! Kuznetsov 1998, §10.2.1), as an iterator over branch points.
//!
//! With `z = (x, p_k)` and unit tangent `t`, a step predicts `z + ds t` and
//! corrects by Newton on `f(x, p) = 0, t . (z - z_pred) = 0`. The step grows
//! after easy corrections, halves after failures, and a step that would cross
//! a parameter bound is shortened to land on it. Between consecutive points
//! the fold and Hopf test functions are watched; sign changes are located
//! (see [`crate::events`]) and attached to the later point. The branch is the
//! [`Curve`] [`Equilibria`], traced by the [`Driver`] ([`Branch`]).

use crate::arclength::{Bound, CurveControl, Stepper};
use crate::defining::{EquilibriumSystem, FreeParams};
use crate::driver::{Advance, Curve, Driver, Stop};
use crate::error::ContinuationError;
use crate::events::{
    critical_pair, hopf_test, is_complex_pair, locate_fold, locate_hopf, Event, EventKind,
};
use crate::linalg::{count_unstable, eigenvalues};
use crate::newton::{self, NewtonReport, NewtonSettings};
use crate::predictor_corrector::StepControl;
use crate::system::{eval, jacobian, VectorField};
use nalgebra::DVector;
use num_complex::Complex64;

/// Which way the continuation parameter moves at the start.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    /// The parameter increases initially.
    Increasing,
    /// The parameter decreases initially.
    Decreasing,
}

/// Settings of the continuation; see the field docs for defaults.
#[derive(Clone, Debug)]
pub struct ContinuationSettings {
    /// Step-size control. Default: `ds = 1e-2`, `ds_min = 1e-10`,
    /// `ds_max = 0.5`, growth 1.5 after at most 3 Newton iterations, turns of
    /// the tangent up to `acos 0.9` (sharper turns are rejected and retried
    /// with a smaller step).
    pub step: StepControl,
    /// Largest number of points, the start included (`max_steps - 1` steps
    /// after it). Default `500`.
    pub max_steps: usize,
    /// Lower bound of the parameter. Default `-inf`.
    pub p_min: f64,
    /// Upper bound of the parameter. Default `+inf`.
    pub p_max: f64,
    /// Initial direction of the parameter. Default increasing.
    pub direction: Direction,
    /// Corrector settings. Default: [`NewtonSettings::default`] with 8 iterations.
    pub corrector: NewtonSettings,
    /// Settings of the Newton runs that locate events to relative `~1e-14`.
    pub locator: NewtonSettings,
    /// Watch and locate folds and Hopf points. Default `true`.
    pub detect_events: bool,
}

impl Default for ContinuationSettings {
    fn default() -> Self {
        ContinuationSettings {
            step: StepControl {
                ds: 1e-2,
                ds_min: 1e-10,
                ds_max: 0.5,
                growth: 1.5,
                easy_iterations: 3,
                min_tangent_cos: 0.9,
            },
            max_steps: 500,
            p_min: f64::NEG_INFINITY,
            p_max: f64::INFINITY,
            direction: Direction::Increasing,
            corrector: NewtonSettings {
                max_iter: 8,
                ..NewtonSettings::default()
            },
            locator: NewtonSettings {
                step_tol: 1e-14,
                residual_tol: 1e-12,
                max_iter: 20,
            },
            detect_events: true,
        }
    }
}

/// One point of a branch of equilibria.
#[derive(Clone, Debug)]
pub struct BranchPoint {
    /// The equilibrium.
    pub x: Vec<f64>,
    /// The full parameter vector.
    pub p: Vec<f64>,
    /// Index of the continuation parameter.
    pub param_index: usize,
    /// Unit tangent `(dx/ds, dp/ds)`.
    pub tangent: Vec<f64>,
    /// Eigenvalues of the Jacobian, by decreasing real part.
    pub eigenvalues: Vec<Complex64>,
    /// Number of eigenvalues with positive real part.
    pub n_unstable: usize,
    /// Bifurcations located between the previous point and this one.
    pub events: Vec<Event>,
    /// The corrector's work at this point.
    pub newton: NewtonReport,
}

impl BranchPoint {
    /// Value of the continuation parameter.
    pub fn param(&self) -> f64 {
        self.p[self.param_index]
    }
}

/// A branch of equilibria being traced; iterate it to get the points.
///
/// The first item is the corrected starting point. Iteration ends at a
/// [`Stop`] ([`Driver::stop`]: [`Stop::Bound`], the last point on the
/// bound, or [`Stop::MaxSteps`]) or after the first error.
pub type Branch<'a, S> = Driver<Equilibria<'a, S>>;

/// The [`Curve`] of a [`Branch`]: equilibria in one parameter.
pub struct Equilibria<'a, S: VectorField> {
    sys: &'a S,
    k: usize,
    settings: ContinuationSettings,
    stepper: Stepper<EquilibriumSystem<'a, S>>,
    last: Option<BranchPoint>,
}

impl<'a, S: VectorField> Driver<Equilibria<'a, S>> {
    /// Starts a branch at `(x0, p0)` in parameter `k`. The starting point is
    /// corrected at fixed parameter first.
    pub fn new(
        sys: &'a S,
        x0: &[f64],
        p0: &[f64],
        k: usize,
        settings: ContinuationSettings,
    ) -> Result<Self, ContinuationError> {
        let n = sys.dim();
        let mut x = DVector::from_column_slice(x0);
        newton::solve(
            &mut x,
            &settings.corrector,
            " at the starting point",
            |x, g, dg| {
                g.copy_from(&eval(sys, x.as_slice(), p0));
                sys.jacobian(x.as_slice(), p0, dg);
            },
        )
        .map_err(|e| ContinuationError::BadStart(Box::new(e)))?;
        let z = DVector::from_iterator(n + 1, x.iter().copied().chain([p0[k]]));
        let sign = if settings.direction == Direction::Increasing {
            1.0
        } else {
            -1.0
        };
        let seed = DVector::from_fn(n + 1, |i, _| if i == n { sign } else { 0.0 });
        let system = EquilibriumSystem {
            sys,
            params: FreeParams {
                base: p0.to_vec(),
                free: vec![k],
            },
        };
        let control = CurveControl {
            step: settings.step,
            corrector: settings.corrector,
            weights: Vec::new(),
            relative: Vec::new(),
        };
        let bounds = vec![Bound {
            index: n,
            min: settings.p_min,
            max: settings.p_max,
        }];
        let stepper = Stepper::new(system, z, &seed, control, bounds)?;
        // `max_steps` counts the points, the start included.
        let max_steps = settings.max_steps.saturating_sub(1);
        Ok(Driver::trace(
            Equilibria {
                sys,
                k,
                settings,
                stepper,
                last: None,
            },
            max_steps,
        ))
    }
}

impl<'a, S: VectorField> Driver<Equilibria<'a, S>> {
    /// Branch switching: the branch through a computed equilibrium `point`
    /// (of any branch) in the parameter `k`, which may differ from the
    /// parameter it was computed in.
    pub fn from_point(
        sys: &'a S,
        point: &BranchPoint,
        k: usize,
        settings: ContinuationSettings,
    ) -> Result<Self, ContinuationError> {
        Self::new(sys, &point.x, &point.p, k, settings)
    }
}

impl<S: VectorField> Equilibria<'_, S> {
    fn make_point(&self, newton: NewtonReport) -> Result<BranchPoint, ContinuationError> {
        let n = self.sys.dim();
        let z = self.stepper.z();
        let p = self.stepper.system.params.with(&z.as_slice()[n..]);
        let x = z.as_slice()[..n].to_vec();
        let ev = eigenvalues(&jacobian(self.sys, &x, &p))?;
        Ok(BranchPoint {
            n_unstable: count_unstable(&ev),
            x,
            p,
            param_index: self.k,
            tangent: self.stepper.tangent().as_slice().to_vec(),
            eigenvalues: ev,
            events: Vec::new(),
            newton,
        })
    }

    /// Watches the test functions between `prev` and `cur` and locates what changed sign.
    fn detect(
        &self,
        prev: &BranchPoint,
        cur: &BranchPoint,
    ) -> Result<Vec<Event>, ContinuationError> {
        let n = self.sys.dim();
        let k = self.k;
        let mut events = Vec::new();
        let interpolate = |a: f64, b: f64| {
            let s = a / (a - b);
            let x: Vec<f64> = (0..n)
                .map(|i| prev.x[i] + s * (cur.x[i] - prev.x[i]))
                .collect();
            let mut p = prev.p.clone();
            p[k] = prev.param() + s * (cur.param() - prev.param());
            (x, p, s)
        };
        let wrap = |kind: &'static str, e: ContinuationError| ContinuationError::Location {
            kind,
            param_name: self.sys.param_name(k),
            from: prev.param(),
            to: cur.param(),
            cause: Box::new(e),
        };
        let (fa, fb) = (prev.tangent[n], cur.tangent[n]);
        if fa * fb < 0.0 {
            let (x, p, _) = interpolate(fa, fb);
            events.push(
                locate_fold(self.sys, k, &x, &p, &self.settings.locator)
                    .map_err(|e| wrap("fold", e))?,
            );
        }
        let (ha, hb) = (hopf_test(&prev.eigenvalues), hopf_test(&cur.eigenvalues));
        if ha * hb < 0.0 {
            let pairs = (
                critical_pair(&prev.eigenvalues),
                critical_pair(&cur.eigenvalues),
            );
            if let (Some(pa), Some(pb)) = pairs {
                // A real pair at either end is a neutral saddle, not a Hopf point.
                if is_complex_pair(pa) && is_complex_pair(pb) {
                    let (x, p, s) = interpolate(ha, hb);
                    let omega = pa.0.im.abs() + s * (pb.0.im.abs() - pa.0.im.abs());
                    let ev = locate_hopf(self.sys, k, &x, &p, omega, &self.settings.locator)
                        .and_then(|e| plausible(e, prev.param(), cur.param(), omega))
                        .map_err(|e| wrap("Hopf", e))?;
                    events.push(ev);
                }
            }
        }
        events.sort_by(|a, b| {
            let da = (a.point.param() - prev.param()).abs();
            da.total_cmp(&(b.point.param() - prev.param()).abs())
        });
        Ok(events)
    }

    /// Steps from `prev`. A step across which the number of unstable
    /// eigenvalues changes without a located bifurcation to explain it (two
    /// crossings inside one step, say), or whose bifurcation could not be
    /// located from the bracket, is retaken with half the step size, down to
    /// `ds_min`.
    fn next_point_after(
        &mut self,
        prev: &BranchPoint,
    ) -> Result<(BranchPoint, Option<Stop>), ContinuationError> {
        let (z0, t0) = (self.stepper.z().clone(), self.stepper.tangent().clone());
        loop {
            let step = self.stepper.step().map_err(|e| match e {
                ContinuationError::StepTooSmall {
                    ds, ds_min, cause, ..
                } => ContinuationError::StepTooSmall {
                    param_name: self.sys.param_name(self.k),
                    param: prev.param(),
                    ds,
                    ds_min,
                    cause,
                },
                other => other,
            })?;
            let mut point = self.make_point(step.report)?;
            let values = point
                .x
                .iter()
                .chain(point.eigenvalues.iter().map(|l| &l.re));
            if let Some(x) = values.clone().find(|v| !v.is_finite()) {
                return Err(ContinuationError::NonFinite {
                    what: format!("{x}"),
                    param_name: self.sys.param_name(self.k),
                    param: point.param(),
                });
            }
            if self.settings.detect_events {
                let can_retry = 0.5 * step.ds.abs() >= self.settings.step.ds_min;
                let retry = match self.detect(prev, &point) {
                    Ok(events) => {
                        point.events = events;
                        point.n_unstable != prev.n_unstable && point.events.is_empty()
                    }
                    // A long step gives a poor initial guess for the location.
                    Err(_) if can_retry => true,
                    Err(e) => return Err(e),
                };
                if retry && can_retry {
                    self.stepper
                        .restore(z0.clone(), t0.clone(), 0.5 * step.ds.abs())?;
                    continue;
                }
            }
            let stop = step.bound.map(|b| Stop::Bound {
                index: self.k,
                value: point.param(),
                bound: if point.param() <= b.min { b.min } else { b.max },
            });
            return Ok((point, stop));
        }
    }
}

impl<S: VectorField> Curve for Equilibria<'_, S> {
    type Point = BranchPoint;

    fn start(&mut self) -> Result<(BranchPoint, Option<Stop>), ContinuationError> {
        let point = self.make_point(NewtonReport::NONE)?;
        self.last = Some(point.clone());
        Ok((point, None))
    }

    fn advance(&mut self) -> Result<Advance<BranchPoint>, ContinuationError> {
        let prev = self.last.take().ok_or(ContinuationError::Singular)?;
        let result = self.next_point_after(&prev);
        self.last = Some(match &result {
            Ok((point, _)) => point.clone(),
            Err(_) => prev,
        });
        result.map(|(point, stop)| Advance::Point(point, stop))
    }
}

/// Accepts a located Hopf point only inside its bracket (with half a
/// bracket of slack) and with a frequency of the order of the one
/// interpolated from the bracket: Newton may otherwise converge to another
/// solution of the augmented system, e.g. a degenerate one (`omega -> 0`) at
/// the end of the branch. A rejected location makes the step retry shorter.
fn plausible(e: Event, a: f64, b: f64, omega_guess: f64) -> Result<Event, ContinuationError> {
    let (lo, hi) = (a.min(b), a.max(b));
    let slack = 0.5 * (hi - lo);
    let omega = match e.kind {
        EventKind::Hopf { omega } => omega,
        EventKind::Fold { .. } => omega_guess,
    };
    let found = e.point.param();
    if found >= lo - slack && found <= hi + slack && omega > 0.1 * omega_guess {
        Ok(e)
    } else {
        Err(ContinuationError::OutsideBracket {
            found,
            from: a,
            to: b,
        })
    }
}
