//! Two-parameter continuation of Hopf points and folds (Govaerts 2000, §4;
//! Kuznetsov 1998, §10.2.2), with Bautin (generalized Hopf) points located on
//! Hopf curves where the first Lyapunov coefficient `l1` changes sign.
//!
//! A Hopf curve is the solution curve of `HopfSystem` with two free
//! parameters, `z = (x, omega, p_a, p_b)`; a fold curve that of `FoldSystem`,
//! `z = (x, p_a, p_b)`. Both are traced by the shared `Stepper`, as
//! `Curve`s of the [`Driver`].

use crate::arclength::{Bound, CurveControl, Stepper};
use crate::defining::{DefiningSystem, FoldSystem, FreeParams, HopfSystem};
use crate::driver::{Advance, Curve, Driver, Event, Stop};
use crate::error::ContinuationError;
use crate::hopf_extended::hopf_normal_form_extended;
use crate::newton::NewtonSettings;
use crate::normal_form::hopf_normal_form;
use crate::predictor_corrector::StepControl;
use crate::system::VectorField;
use nalgebra::DVector;

/// Settings of a two-parameter curve.
#[derive(Clone, Debug)]
pub struct CurveSettings {
    /// Step-size control (`ds` etc. in the joint space `(x, omega, p_a, p_b)`).
    pub control: CurveControl,
    /// Largest number of points of a Hopf curve, the start included; a fold
    /// curve takes this many steps after its start.
    pub max_steps: usize,
    /// Bounds `(min, max)` of the two free parameters; the curve stops on them.
    pub bounds: [(f64, f64); 2],
    /// Initial direction: the sign of `d p_b / ds`.
    pub increase_second: bool,
    /// Hopf curves: stop when `omega` falls below this (approach to a
    /// Bogdanov–Takens point, where the Hopf system degenerates). Default `1e-6`.
    pub omega_min: f64,
    /// Newton settings for locating codimension-2 points.
    pub locator: NewtonSettings,
}

impl Default for CurveSettings {
    fn default() -> Self {
        CurveSettings {
            control: CurveControl {
                step: StepControl {
                    ds: 1e-2,
                    ds_min: 1e-12,
                    ds_max: 0.2,
                    growth: 1.5,
                    easy_iterations: 3,
                    min_tangent_cos: 0.95,
                },
                weights: Vec::new(),
                relative: Vec::new(),
                corrector: NewtonSettings {
                    max_iter: 8,
                    ..NewtonSettings::default()
                },
            },
            max_steps: 1000,
            bounds: [(f64::NEG_INFINITY, f64::INFINITY); 2],
            increase_second: true,
            omega_min: 1e-6,
            locator: NewtonSettings {
                step_tol: 1e-14,
                residual_tol: 1e-12,
                max_iter: 20,
            },
        }
    }
}

/// The tangent seed (sign of `d p_b / ds`) and the bounds of a curve whose
/// two free parameters sit at `first` and `first + 1` of its `len` unknowns.
fn seed_and_bounds(
    len: usize,
    first: usize,
    settings: &CurveSettings,
) -> (DVector<f64>, Vec<Bound>) {
    let sign = if settings.increase_second { 1.0 } else { -1.0 };
    let seed = DVector::from_fn(len, |i, _| if i == first + 1 { sign } else { 0.0 });
    let bounds = (0..2)
        .map(|i| Bound {
            index: first + i,
            min: settings.bounds[i].0,
            max: settings.bounds[i].1,
        })
        .collect();
    (seed, bounds)
}

/// A point of a Hopf curve.
#[derive(Clone, Debug)]
pub struct HopfCurvePoint {
    /// Equilibrium.
    pub x: Vec<f64>,
    /// Angular frequency.
    pub omega: f64,
    /// Full parameter vector.
    pub p: Vec<f64>,
    /// First Lyapunov coefficient (Kuznetsov's normalization), its term
    /// scale and the bound on its rounding error.
    pub l1: f64,
    pub l1_scale: f64,
    pub l1_error_bound: f64,
    /// The Bautin point located between the previous point and this one,
    /// if any (its error: the bound on the rounding error of its `l1`).
    pub events: Vec<Event<HopfCurveEvent, HopfCurvePoint>>,
}

/// What a special point of a Hopf curve is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum HopfCurveEvent {
    /// A Bautin (generalized Hopf) point: `l1` changes sign.
    Bautin,
}

/// A Hopf curve being traced in parameters `(p_a, p_b)`; it ends at a
/// [`Stop`] ([`Driver::stop`]): [`Stop::Bound`] (the last point on it),
/// [`Stop::FrequencyVanishing`] or [`Stop::MaxSteps`].
pub type HopfCurve<'a, S> = Driver<Hopf<'a, S>>;

/// The `Curve` of a [`HopfCurve`].
pub struct Hopf<'a, S: VectorField> {
    sys: &'a S,
    stepper: Stepper<HopfSystem<'a, S>>,
    settings: CurveSettings,
    last: Option<HopfCurvePoint>,
}

/// The [`Stop::Bound`] of a step of `stepper` that landed on `bound`.
fn bound_stop<G: DefiningSystem>(
    stepper: &Stepper<G>,
    free: &[usize],
    first: usize,
    bound: Bound,
) -> Stop {
    let value = stepper.z()[bound.index];
    Stop::Bound {
        index: free[bound.index - first],
        value,
        bound: if value <= bound.min {
            bound.min
        } else {
            bound.max
        },
    }
}

impl<'a, S: VectorField> Driver<Hopf<'a, S>> {
    /// Starts at a Hopf point `(x0, omega0, p0)` and frees parameters `a`, `b`.
    pub fn new(
        sys: &'a S,
        x0: &[f64],
        omega0: f64,
        p0: &[f64],
        [a, b]: [usize; 2],
        settings: CurveSettings,
    ) -> Result<Self, ContinuationError> {
        let n = sys.dim();
        let z0 = DVector::from_iterator(n + 3, x0.iter().copied().chain([omega0, p0[a], p0[b]]));
        let system = HopfSystem::new(
            sys,
            FreeParams {
                base: p0.to_vec(),
                free: vec![a, b],
            },
            &z0,
        )?;
        let (seed, bounds) = seed_and_bounds(n + 3, n + 1, &settings);
        let stepper = Stepper::new(system, z0, &seed, settings.control.clone(), bounds)?;
        // `max_steps` counts the points, the start included.
        let max_steps = settings.max_steps.saturating_sub(1);
        Ok(Driver::trace(
            Hopf {
                sys,
                stepper,
                settings,
                last: None,
            },
            max_steps,
        ))
    }
}

impl<'a, S: VectorField> Driver<Hopf<'a, S>> {
    /// Branch switching: the Hopf curve through a Hopf point located on a
    /// branch of equilibria (`event`, in the parameter it was located in),
    /// with `b` the second free parameter. `None` for a fold.
    pub fn from_event(
        sys: &'a S,
        event: &crate::events::Event,
        b: usize,
        settings: CurveSettings,
    ) -> Option<Result<Self, ContinuationError>> {
        let (e, omega) = event.hopf()?;
        Some(Self::new(
            sys,
            &e.x,
            omega,
            &e.p,
            [e.param_index, b],
            settings,
        ))
    }
}

impl<S: VectorField> Hopf<'_, S> {
    fn point_at(&self, z: &DVector<f64>) -> Result<HopfCurvePoint, ContinuationError> {
        let n = self.sys.dim();
        let x = z.as_slice()[..n].to_vec();
        let p = self.stepper.system.params.with(&z.as_slice()[n + 1..]);
        let mut nf = hopf_normal_form(self.sys, &x, &p, z[n])?;
        // Where f64 leaves fewer than eight digits (terms cancelling far
        // below their size, e.g. small inertia), double-double, refined on
        // the curve in its first parameter; kept where it agrees.
        if nf.l1_error_bound > 1e-8 * nf.l1.abs() {
            let a = self.stepper.system.params.free[0];
            if let Ok(ext) = hopf_normal_form_extended(self.sys, &x, &p, a, &nf) {
                let ext = ext.normal_form;
                if (ext.l1 - nf.l1).abs() <= nf.l1_error_bound + ext.l1_error_bound {
                    nf = ext;
                }
            }
        }
        Ok(HopfCurvePoint {
            x,
            omega: z[n].abs(),
            p,
            l1: nf.l1,
            l1_scale: nf.term_scale,
            l1_error_bound: nf.l1_error_bound,
            events: Vec::new(),
        })
    }

    /// Locates `l1 = 0` between `z0` (tangent `t0`) and the current point,
    /// `ds` apart along `t0`, by the Illinois variant of regula falsi on the
    /// arclength `sigma` ([`crate::root::illinois`]); each trial point is
    /// corrected onto the curve.
    fn locate_bautin(
        &self,
        z0: &DVector<f64>,
        t0: &DVector<f64>,
        l1_0: f64,
        ds: f64,
        l1_1: f64,
    ) -> Result<HopfCurvePoint, ContinuationError> {
        let mut best = None;
        crate::root::illinois(
            |sigma| {
                let mut z = z0 + t0 * sigma;
                self.stepper
                    .correct(&mut z, t0, None, &self.settings.locator)?;
                let pt = self.point_at(&z)?;
                // Within its rounding bound l1 is zero as far as it is known.
                let l1 = if pt.l1.abs() <= pt.l1_error_bound {
                    0.0
                } else {
                    pt.l1
                };
                best = Some(pt);
                Ok(l1)
            },
            (0.0, l1_0),
            (ds, l1_1),
            1e-13 * ds.abs(),
            100,
        )?;
        best.ok_or(ContinuationError::Singular)
    }

    fn next_point(&mut self) -> Result<(HopfCurvePoint, Option<Stop>), ContinuationError> {
        let prev = self.last.clone().ok_or(ContinuationError::Singular)?;
        let (z0, t0) = (self.stepper.z().clone(), self.stepper.tangent().clone());
        let step = self.stepper.step()?;
        let mut point = self.point_at(self.stepper.z())?;
        // A sign change counts only where l1 exceeds its rounding-error bound
        // at both ends (not rounding noise near a degenerate point).
        let resolved = |p: &HopfCurvePoint| p.l1.abs() > p.l1_error_bound;
        if prev.l1 * point.l1 < 0.0 && resolved(&prev) && resolved(&point) {
            let b = self.locate_bautin(&z0, &t0, prev.l1, step.ds, point.l1)?;
            point.events.push(Event {
                kind: HopfCurveEvent::Bautin,
                error: b.l1_error_bound,
                point: b,
            });
        }
        let n = self.sys.dim();
        let stop = if let Some(b) = step.bound {
            Some(bound_stop(
                &self.stepper,
                &self.stepper.system.params.free,
                n + 1,
                b,
            ))
        } else if point.omega < self.settings.omega_min {
            Some(Stop::FrequencyVanishing {
                omega: point.omega,
                omega_min: self.settings.omega_min,
            })
        } else {
            None
        };
        Ok((point, stop))
    }
}

impl<S: VectorField> Curve for Hopf<'_, S> {
    type Point = HopfCurvePoint;

    fn start(&mut self) -> Result<(HopfCurvePoint, Option<Stop>), ContinuationError> {
        let point = self.point_at(self.stepper.z())?;
        self.last = Some(point.clone());
        Ok((point, None))
    }

    fn advance(&mut self) -> Result<Advance<HopfCurvePoint>, ContinuationError> {
        let (point, stop) = self.next_point()?;
        self.last = Some(point.clone());
        Ok(Advance::Point(point, stop))
    }
}

/// A point of a fold curve.
#[derive(Clone, Debug)]
pub struct FoldCurvePoint {
    /// Equilibrium.
    pub x: Vec<f64>,
    /// Full parameter vector.
    pub p: Vec<f64>,
}

/// The [`Curve`] of [`fold_curve`].
struct Fold<'a, S: VectorField> {
    stepper: Stepper<FoldSystem<'a, S>>,
    n: usize,
}

impl<S: VectorField> Fold<'_, S> {
    fn point(&self) -> FoldCurvePoint {
        let (z, n) = (self.stepper.z(), self.n);
        FoldCurvePoint {
            x: z.as_slice()[..n].to_vec(),
            p: self.stepper.system.params.with(&z.as_slice()[n..]),
        }
    }
}

impl<S: VectorField> Curve for Fold<'_, S> {
    type Point = FoldCurvePoint;

    fn start(&mut self) -> Result<(FoldCurvePoint, Option<Stop>), ContinuationError> {
        Ok((self.point(), None))
    }

    fn advance(&mut self) -> Result<Advance<FoldCurvePoint>, ContinuationError> {
        let step = self.stepper.step()?;
        let stop = step
            .bound
            .map(|b| bound_stop(&self.stepper, &self.stepper.system.params.free, self.n, b));
        Ok(Advance::Point(self.point(), stop))
    }
}

/// Traces a fold curve from the fold `(x0, p0)` in parameters `(p_a, p_b)`,
/// at most `settings.max_steps` steps after the start; it ends on a bound or
/// at the step limit.
pub fn fold_curve<S: VectorField>(
    sys: &S,
    x0: &[f64],
    p0: &[f64],
    [a, b]: [usize; 2],
    settings: &CurveSettings,
) -> Result<Vec<FoldCurvePoint>, ContinuationError> {
    let n = sys.dim();
    let z0 = DVector::from_iterator(n + 2, x0.iter().copied().chain([p0[a], p0[b]]));
    let system = FoldSystem::new(
        sys,
        FreeParams {
            base: p0.to_vec(),
            free: vec![a, b],
        },
        &z0,
    )?;
    let (seed, bounds) = seed_and_bounds(n + 2, n, settings);
    let stepper = Stepper::new(system, z0, &seed, settings.control.clone(), bounds)?;
    Driver::trace(Fold { stepper, n }, settings.max_steps).collect()
}
