//! Curves of folds of cycles in two parameters by pseudo-arclength on the
//! minimally augmented system: the [`Curve`] [`FoldsOfCycles`], traced by
//! the [`Driver`] ([`LpcCurve`]).

use super::{Augmented, Evaluation, LpcPoint};
use crate::codim2::HopfCurvePoint;
use crate::driver::{Advance, Curve, Driver, Event, Stop};
use crate::error::ContinuationError;
use crate::newton::{NewtonReport, NewtonSettings};
use crate::normal_form::{hopf_normal_form, HopfNormalForm};
use crate::periodic::adapt::equidistribute;
use crate::periodic::branch::{CycleBranch, CycleEvent, CyclePoint, CycleSettings};
use crate::periodic::cycle::unknowns_on;
use crate::periodic::newton::unit_row;
use crate::periodic::CollocationPoints;
use crate::periodic::Cycle;
use crate::predictor_corrector::{self, Corrected, CurveProblem, StepControl};
use crate::system::VectorField;

/// Settings of a curve of folds of cycles. The engine defaults take absolute
/// steps in parameters below 1 (`param_floor`); for parameters spanning
/// decades set the floors to the smallest scale of interest.
#[derive(Clone, Debug)]
pub struct LpcCurveSettings {
    /// Step-size control (steps relative in `T`, `p1`, `p2`). Default:
    /// `ds = 1e-2`, `ds_min = 1e-8`, `ds_max = 0.1`, growth 1.3 after at most
    /// 4 Newton iterations, turns of the tangent up to `acos 0.8`.
    pub step: StepControl,
    /// Largest number of folds after the start.
    pub max_steps: usize,
    /// Bounds of the second parameter; the curve lands and stops on them.
    pub p2_min: f64,
    pub p2_max: f64,
    /// Smallest scales of the parameters in the arclength weights.
    pub param_floor: [f64; 2],
    /// The curve stops where the orbit's amplitude (largest range of a
    /// component over the mesh nodes) falls below this: it ends on a Bautin
    /// point there.
    pub min_amplitude: f64,
    /// Newton's method on the augmented system (the test function `g` is
    /// judged by the step it causes, `F` by its residual).
    pub corrector: NewtonSettings,
    /// Largest acceptable estimate of a fold's discretization error: the
    /// relative difference of `p1` (scale at least `param_floor[0]`) and of
    /// the period between the fold on the mesh and on half of it, at the
    /// same `p2`, over `2^q - 1`, `q` the order of the mesh-point values
    /// (`2m` with Gauss points, `2m - 1` with Radau points). It is checked
    /// whenever the mesh is re-equidistributed (every fifth fold): above it
    /// the mesh doubles, up to `ntst_max` (beyond, the curve stops); below
    /// `mesh_tol / (8 * 2^q)` it halves (halving raises the error by about
    /// `2^q`, which leaves a margin of 8), down to `ntst_min`. Default
    /// `None`: the start's mesh size throughout, no estimate.
    pub mesh_tol: Option<f64>,
    pub ntst_min: usize,
    pub ntst_max: usize,
}

impl Default for LpcCurveSettings {
    fn default() -> Self {
        LpcCurveSettings {
            step: StepControl {
                ds: 1e-2,
                ds_min: 1e-8,
                ds_max: 0.1,
                growth: 1.3,
                easy_iterations: 4,
                min_tangent_cos: 0.8,
            },
            max_steps: 200,
            p2_min: f64::NEG_INFINITY,
            p2_max: f64::INFINITY,
            param_floor: [1.0, 1.0],
            min_amplitude: 1e-4,
            corrector: NewtonSettings {
                step_tol: 1e-10,
                residual_tol: 1e-9,
                max_iter: 8,
            },
            mesh_tol: None,
            ntst_min: 4,
            ntst_max: 400,
        }
    }
}

/// A curve of folds of cycles in `(p1, p2)`, traced by pseudo-arclength
/// from a fold; each item is the next fold (the first is the start). It ends
/// at a [`Stop`] ([`Driver::stop`]): [`Stop::Bound`] (the last fold on the
/// bound of `p2`), [`Stop::SmallAmplitude`], [`Stop::BautinPoint`] or
/// [`Stop::MaxSteps`], or after the first error.
pub type LpcCurve<'a, S> = Driver<FoldsOfCycles<'a, S>>;

/// The `Curve` of an [`LpcCurve`].
pub struct FoldsOfCycles<'a, S: VectorField> {
    sys: &'a S,
    k1: usize,
    k2: usize,
    aug: Augmented<'a, S>,
    y: Vec<f64>,
    tangent: Vec<f64>,
    /// The fold before `y` (on `y`'s mesh): with `y` and the tangent there,
    /// the third point of the predictor (see [`FoldStep`]).
    previous: Option<Vec<f64>>,
    ds: f64,
    settings: LpcCurveSettings,
    /// Folds handed out (or failed).
    steps: usize,
}

impl<'a, S: VectorField> Driver<FoldsOfCycles<'a, S>> {
    /// Starts at the fold near `lpc` (in `k1`, at the value of `k2` it
    /// carries, corrected first), going towards increasing `p2` when
    /// `direction > 0`.
    pub fn new(
        sys: &'a S,
        lpc: &Cycle,
        (k1, k2): (usize, usize),
        direction: f64,
        settings: LpcCurveSettings,
    ) -> Result<Self, ContinuationError> {
        let mut aug = Augmented::new(sys, lpc, k1, Some(k2))?;
        let mut y = aug.coll.unknowns(lpc);
        y.push(lpc.p[k2]);
        // The start is corrected onto the fold at its own p2 (it may come from
        // another mesh or a looser location).
        let mut fix_p2 = vec![0.0; y.len()];
        *fix_p2.last_mut().unwrap_or(&mut 0.0) = 1.0;
        let anchor = y.clone();
        let (_, mut e) =
            aug.newton(&mut y, Some((&fix_p2, &anchor)), &settings.corrector, false)?;
        aug.update_borders(&e);
        let mut seed = vec![0.0; y.len()];
        *seed.last_mut().unwrap_or(&mut 0.0) = direction.signum();
        let tangent = tangent_at(&mut e, &weights(&y, &settings), &seed)?;
        let max_steps = settings.max_steps;
        let curve = FoldsOfCycles {
            sys,
            k1,
            k2,
            aug,
            y,
            tangent,
            previous: None,
            ds: settings.step.ds,
            settings,
            steps: 0,
        };
        Ok(Driver::trace(curve, max_steps))
    }
}

impl<'a, S: VectorField> Driver<FoldsOfCycles<'a, S>> {
    /// Branch switching: the curve of folds of cycles through a fold of
    /// cycles located on a cycle branch (`event`, continued in `k1`), with
    /// `k2` the second free parameter; `None` for another kind of event.
    pub fn from_event(
        sys: &'a S,
        event: &Event<CycleEvent, CyclePoint>,
        (k1, k2): (usize, usize),
        direction: f64,
        settings: LpcCurveSettings,
    ) -> Option<Result<Self, ContinuationError>> {
        (event.kind == CycleEvent::Fold)
            .then(|| Self::new(sys, &event.point.cycle, (k1, k2), direction, settings))
    }
}

impl<'a, S: VectorField> Driver<FoldsOfCycles<'a, S>> {
    /// Branch switching from a Bautin point: the curve of folds of cycles
    /// born at `bautin` (a point of a Hopf curve in `(k1, k2)` where `l1`
    /// vanishes), traced toward increasing `p2` when `direction > 0`. Its
    /// first fold is the one of the cycles born at `beside`, a subcritical
    /// point of the same Hopf curve near the Bautin point
    /// ([`fold_beside_bautin`]; at the Bautin point itself the folded cycles
    /// are vanishingly small). For a Bautin point with `l2 < 0`, whose
    /// folds lie on the side where `l1 > 0` (with `l2 > 0` they lie on the
    /// supercritical side, which this constructor does not take). The
    /// normal form at `beside` is computed in `f64`;
    /// [`fold_beside_bautin`] takes one computed otherwise.
    pub fn from_bautin(
        sys: &'a S,
        bautin: &HopfCurvePoint,
        beside: &HopfCurvePoint,
        (k1, k2): (usize, usize),
        direction: f64,
        cycles: CycleSettings,
        settings: LpcCurveSettings,
    ) -> Result<Self, ContinuationError> {
        let nf = hopf_normal_form(sys, &beside.x, &beside.p, beside.omega)?;
        let fold = fold_beside_bautin(
            sys,
            (k2, bautin.p[k2]),
            (&beside.x, &beside.p),
            &nf,
            k1,
            cycles,
        )?;
        Self::new(sys, &fold, (k1, k2), direction, settings)
    }
}

/// The fold of cycles next to a Bautin point (where the second parameter
/// `k2` has the value `bautin`): the cycles born at the subcritical Hopf point `(x, p)`
/// beside it (normal form `nf`, with `l1 > 0` beyond its rounding bound) are
/// continued in `k1` with `cycles`' settings until they turn back (Kuznetsov
/// 1998, §8.3: near a Bautin point with `l2 < 0` the subcritical cycles
/// fold once, at an amplitude that vanishes at the Bautin point). The
/// orbit at the located fold is returned, the start of the curve of folds
/// ([`LpcCurve::new`]). Errors: [`ContinuationError::NotSubcritical`],
/// [`ContinuationError::NoFoldOfCycles`] with how the branch ended, or the
/// branch's own failure.
pub fn fold_beside_bautin<S: VectorField>(
    sys: &S,
    (k2, bautin): (usize, f64),
    (x, p): (&[f64], &[f64]),
    nf: &HopfNormalForm,
    k1: usize,
    cycles: CycleSettings,
) -> Result<Cycle, ContinuationError> {
    let subcritical = nf.l1 > nf.l1_error_bound;
    // Also a NaN is refused.
    if !subcritical {
        return Err(ContinuationError::NotSubcritical {
            param_name: sys.param_name(k2),
            at: p[k2],
            bautin,
            l1: nf.l1,
            bound: nf.l1_error_bound,
        });
    }
    let mut branch = CycleBranch::from_hopf_normal_form(sys, x, p, k1, nf, cycles)?;
    for point in branch.by_ref() {
        if let Some(fold) = point?.event(CycleEvent::Fold) {
            return Ok(fold.cycle.clone());
        }
    }
    Err(ContinuationError::NoFoldOfCycles {
        param_name: sys.param_name(k2),
        at: p[k2],
        bautin,
        stop: branch.stop(),
    })
}

impl<'a, S: VectorField> FoldsOfCycles<'a, S> {
    /// Re-equidistributes the mesh and, under a finite `mesh_tol`, sizes it
    /// by the fold's error estimate (see [`LpcCurveSettings::mesh_tol`]),
    /// the fold corrected on the new mesh at the same `p2`; the bordering
    /// vectors are rebuilt there.
    fn adapt(&mut self) -> Result<(), ContinuationError> {
        let orbit = self.aug.cycle(&self.y);
        let ntst = orbit.mesh.ntst();
        if let Some(tol) = self.settings.mesh_tol {
            // p1 and the period are read at the mesh points, where the
            // collocation solution converges at order 2m (Gauss points) or
            // 2m - 1 (Radau points), like the period.
            let m = orbit.mesh.degree as i32;
            let order = match orbit.mesh.points {
                CollocationPoints::Gauss => 2 * m,
                CollocationPoints::Radau => 2 * m - 1,
            };
            let coarse = self.fold_on(&orbit, ntst / 2);
            let mut estimate = coarse
                .as_ref()
                .map_or(f64::INFINITY, |(_, y)| self.difference(&self.y, y, order));
            if estimate <= tol / (8.0 * 2f64.powi(order)) && ntst / 2 >= self.settings.ntst_min {
                if let Ok((aug, y)) = coarse {
                    self.move_to(aug, y);
                    return Ok(());
                }
            }
            let (mut at, mut previous) = (orbit.clone(), self.y.clone());
            while estimate > tol {
                let fine = 2 * at.mesh.ntst();
                if fine > self.settings.ntst_max {
                    return Err(ContinuationError::Unresolved {
                        param_name: self.sys.param_name(self.k2),
                        ntst: at.mesh.ntst(),
                        error: estimate,
                        tol,
                        param: self.y[self.y.len() - 1],
                    });
                }
                let (aug, y) = self.fold_on(&at, fine)?;
                estimate = self.difference(&y, &previous, order);
                if estimate <= tol {
                    self.move_to(aug, y);
                    return Ok(());
                }
                at = aug.cycle(&y);
                previous = y;
            }
        }
        let new = equidistribute(&orbit, ntst);
        let aug = Augmented::new(self.sys, &new, self.k1, Some(self.k2))?;
        let mut y = aug.coll.unknowns(&new);
        y.push(new.p[self.k2]);
        self.move_to(aug, y);
        Ok(())
    }

    /// The fold at the current `p2` on an equidistributing mesh of `ntst`
    /// intervals for `orbit`.
    fn fold_on(
        &self,
        orbit: &Cycle,
        ntst: usize,
    ) -> Result<(Augmented<'a, S>, Vec<f64>), ContinuationError> {
        if ntst < 2 {
            return Err(ContinuationError::Singular);
        }
        let new = equidistribute(orbit, ntst);
        let mut aug = Augmented::new(self.sys, &new, self.k1, Some(self.k2))?;
        let mut y = aug.coll.unknowns(&new);
        y.push(new.p[self.k2]);
        let anchor = y.clone();
        let fix_p2 = unit_row(y.len(), y.len() - 1);
        let (_, e) = aug.newton(
            &mut y,
            Some((&fix_p2, &anchor)),
            &self.settings.corrector,
            false,
        )?;
        aug.update_borders(&e);
        Ok((aug, y))
    }

    /// The error estimate of the fold `fine` from the same fold `coarse` on
    /// half the mesh (see [`LpcCurveSettings::mesh_tol`]).
    fn difference(&self, fine: &[f64], coarse: &[f64], order: i32) -> f64 {
        let (d, e) = (fine.len(), coarse.len());
        let p1 = fine[d - 2].abs().max(self.settings.param_floor[0]);
        let dp1 = ((fine[d - 2] - coarse[e - 2]) / p1).abs();
        let dt = ((fine[d - 3] - coarse[e - 3]) / fine[d - 3]).abs();
        dp1.max(dt) / (2f64.powi(order) - 1.0)
    }

    /// Continues from the fold `y` of the system `aug` (on another mesh),
    /// the tangent moved onto that mesh, and the fold before as `y` plus
    /// its difference from the fold left moved there (`y` may be corrected
    /// on the new mesh, which moves it by the discretization error: the
    /// difference keeps the predictor's quadratic from taking that up).
    fn move_to(&mut self, aug: Augmented<'a, S>, y: Vec<f64>) {
        let (from, to, n) = (&self.aug.coll.mesh, &aug.coll.mesh, self.sys.dim());
        self.tangent = unknowns_on(&self.tangent, from, n, to);
        self.previous = self.previous.as_deref().map(|before| {
            let difference: Vec<f64> = before.iter().zip(&self.y).map(|(b, y)| b - y).collect();
            let moved = unknowns_on(&difference, from, n, to);
            y.iter().zip(moved).map(|(y, d)| y + d).collect()
        });
        self.aug = aug;
        self.y = y;
    }

    /// The next fold ([`predictor_corrector::step`] on the augmented system
    /// closed by the pseudo-arclength condition), or `None` where the curve
    /// has passed through a Bautin point (see [`passed_bautin`]). At the
    /// rounding floor of the fold system smaller steps do not help: a stalled
    /// corrector ends the curve (near a Bautin point).
    fn step(&mut self) -> Result<Option<LpcPoint>, ContinuationError> {
        if self.steps.is_multiple_of(5) {
            self.adapt()?;
        }
        let before = (self.y.clone(), self.tangent.clone());
        let mut curve = FoldStep {
            w: weights(&self.y, &self.settings),
            aug: &mut self.aug,
            y: &mut self.y,
            tangent: &mut self.tangent,
            previous: &mut self.previous,
            corrector: &self.settings.corrector,
            k2: self.k2,
            passed_bautin: false,
        };
        let stepped = predictor_corrector::step(&mut curve, &self.settings.step, &mut self.ds)?;
        if curve.passed_bautin {
            return Ok(None);
        }
        let newton = self.land(&before).unwrap_or(stepped.report);
        Ok(Some(LpcPoint {
            cycle: self.aug.cycle(&self.y),
            newton,
        }))
    }

    /// Where the step from `before` (fold, tangent) went past `p2_min` or
    /// `p2_max`: the fold exactly at that bound (predicted along the
    /// tangent, corrected with `p2` fixed there) replaces it, so that the
    /// curve ends on its range, not a step beyond. `None` when the step
    /// stayed inside, or the fold at the bound did not converge (the step's
    /// fold is kept).
    fn land(&mut self, (y0, t0): &(Vec<f64>, Vec<f64>)) -> Option<NewtonReport> {
        let d = self.y.len();
        let p2 = self.y[d - 1];
        let bound = if p2 > self.settings.p2_max {
            self.settings.p2_max
        } else if p2 < self.settings.p2_min {
            self.settings.p2_min
        } else {
            return None;
        };
        if y0.len() != d || t0[d - 1] == 0.0 {
            return None;
        }
        let s = (bound - y0[d - 1]) / t0[d - 1];
        let mut y: Vec<f64> = y0.iter().zip(t0).map(|(y, t)| y + s * t).collect();
        y[d - 1] = bound;
        let anchor = y.clone();
        let fix_p2 = unit_row(d, d - 1);
        let (report, e) = self
            .aug
            .newton(
                &mut y,
                Some((&fix_p2, &anchor)),
                &self.settings.corrector,
                true,
            )
            .ok()?;
        self.aug.update_borders(&e);
        self.aug.recycle(e);
        self.y = y;
        self.previous = None;
        Some(report)
    }
}

/// The point `y0 + ds t + a ds^2` of the quadratic through `before`, `y0`
/// and the tangent `t` at `y0`: `a = (before - y0 + h t) / h^2`, `before`
/// taken at `s = -h`, `h = <row, y0 - before> / <row, t>` its distance
/// along the tangent (`row` the tangent in this step's arclength weights,
/// in which `t` need not be of unit length: the weights follow the
/// point). The point lies on the tangent's pseudo-arclength hyperplane
/// `<row, y - (y0 + ds t)> = 0`. `None` where `before` does not lie behind
/// `y0`, or lies so close behind it that the step would extrapolate the
/// quadratic over more than 4 times that distance.
fn quadratic_start(
    y0: &[f64],
    t: &[f64],
    before: &[f64],
    row: &[f64],
    ds: f64,
) -> Option<Vec<f64>> {
    let along: f64 = (0..y0.len()).map(|i| row[i] * t[i]).sum();
    let h = (0..y0.len())
        .map(|i| row[i] * (y0[i] - before[i]))
        .sum::<f64>()
        / along;
    (h > 0.0 && ds.abs() <= 4.0 * h).then(|| {
        let c = (ds / h).powi(2);
        (0..y0.len())
            .map(|i| y0[i] + ds * t[i] + c * (before[i] - y0[i] + h * t[i]))
            .collect()
    })
}

/// One step of an [`LpcCurve`] as a [`CurveProblem`]: the augmented system
/// closed by the pseudo-arclength condition in the weights `w`.
struct FoldStep<'c, 'a, S: VectorField> {
    aug: &'c mut Augmented<'a, S>,
    y: &'c mut Vec<f64>,
    tangent: &'c mut Vec<f64>,
    previous: &'c mut Option<Vec<f64>>,
    w: Vec<f64>,
    corrector: &'c NewtonSettings,
    k2: usize,
    /// Whether the accepted fold lies past a Bautin point.
    passed_bautin: bool,
}

impl<S: VectorField> CurveProblem for FoldStep<'_, '_, S> {
    type Point = (Vec<f64>, Evaluation);
    type Tangent = Vec<f64>;

    /// Newton's method from the quadratic through the fold before, this
    /// one and its tangent (`y + s t + a s^2`, `a` from the fold before at
    /// `s = -h`, `h` its distance along the tangent), where there is a fold
    /// before: its error is of the third order in the step where the
    /// tangent's is of the second. The pseudo-arclength condition is the
    /// tangent's (`<t, y - (y0 + ds t)>_w = 0`): the fold it fixes near the
    /// prediction does not depend on where Newton's method starts.
    fn correct(&mut self, ds: f64) -> Result<Corrected<Self::Point>, ContinuationError> {
        let d = self.y.len();
        let pred: Vec<f64> = (0..d).map(|i| self.y[i] + ds * self.tangent[i]).collect();
        let row: Vec<f64> = (0..d).map(|i| self.w[i] * self.tangent[i]).collect();
        let quadratic = self
            .previous
            .as_deref()
            .filter(|before| before.len() == d)
            .and_then(|before| quadratic_start(self.y, self.tangent, before, &row, ds));
        let from_quadratic = quadratic.is_some();
        let mut y = quadratic.unwrap_or_else(|| pred.clone());
        let (mut report, e) = self
            .aug
            .newton(&mut y, Some((&row, &pred)), self.corrector, true)?;
        // The step control counts the iteration the tangent's prediction
        // would have taken more: the steps grow and shrink as they did
        // from it, and the curve keeps its folds (counted as they come, the
        // steps grew longer and the last fold before a Bautin point lay
        // farther from it).
        report.iterations += usize::from(from_quadratic);
        Ok(Corrected {
            point: (y, e),
            report,
            ds,
            constrained: false,
        })
    }

    fn tangent(&mut self, (_, e): &mut Self::Point) -> Result<Vec<f64>, ContinuationError> {
        tangent_at(e, &self.w, self.tangent)
    }

    fn turn(&self, t: &Vec<f64>) -> f64 {
        (0..t.len())
            .map(|i| self.w[i] * t[i] * self.tangent[i])
            .sum()
    }

    /// Also notes whether the fold has come through a Bautin point.
    fn accept(&mut self, (y, e): Self::Point, t: Vec<f64>) -> Result<(), ContinuationError> {
        let (d, n) = (y.len(), self.aug.coll.sys.dim());
        self.passed_bautin = passed_bautin(&self.y[..d - 3], &y[..d - 3], n);
        self.aug.update_borders(&e);
        self.aug.recycle(e);
        *self.previous = Some(std::mem::replace(self.y, y));
        *self.tangent = t;
        Ok(())
    }

    fn location(&self) -> (String, f64) {
        (
            format!(
                "{} along the fold of cycles",
                self.aug.coll.sys.param_name(self.k2)
            ),
            self.y[self.y.len() - 1],
        )
    }
}

/// Arclength weights at `y`: `1/N` on the orbit, relative on `T`, `p1`, `p2`.
fn weights(y: &[f64], settings: &LpcCurveSettings) -> Vec<f64> {
    let d = y.len();
    let nn = d - 3;
    let rel = |v: f64, floor: f64| 1.0 / v.abs().max(floor).powi(2);
    (0..d)
        .map(|i| match i.checked_sub(nn) {
            None => 1.0 / nn as f64,
            Some(0) => rel(y[i], f64::MIN_POSITIVE.sqrt()),
            Some(1) => rel(y[i], settings.param_floor[0]),
            Some(_) => rel(y[i], settings.param_floor[1]),
        })
        .collect()
}

/// The unit tangent (weights `w`) at the point of the evaluation `e`,
/// oriented along `reference`: `J t = e_last` with the Jacobian of
/// `(F, g)` closed by the row `w reference`.
fn tangent_at(
    e: &mut Evaluation,
    w: &[f64],
    reference: &[f64],
) -> Result<Vec<f64>, ContinuationError> {
    let d = reference.len();
    let last = e.rows.nrows() - 1;
    e.rows
        .row_mut(last)
        .iter_mut()
        .enumerate()
        .for_each(|(i, r)| *r = w[i] * reference[i]);
    let mut rhs = vec![0.0; d];
    rhs[d - 1] = 1.0;
    let t = e.solve(&rhs)?;
    let norm = (0..d).map(|i| w[i] * t[i] * t[i]).sum::<f64>().sqrt();
    Ok(t.iter().map(|v| v / norm).collect())
}

/// Whether the orbit `u` has come through zero amplitude from `previous`
/// (node values on the same mesh, state dimension `n`): their deviations from
/// their means point opposite ways. Where the folded cycles shrink to nothing
/// the curve of folds ends on the Hopf curve (a Bautin point); continued
/// through it, the amplitude changes sign and the curve comes back along the
/// same folds, the orbits shifted by half a period.
fn passed_bautin(previous: &[f64], u: &[f64], n: usize) -> bool {
    let mean = |u: &[f64]| {
        let count = (u.len() / n) as f64;
        (0..n)
            .map(|j| u.iter().skip(j).step_by(n).sum::<f64>() / count)
            .collect::<Vec<_>>()
    };
    let (a, b) = (mean(previous), mean(u));
    let overlap: f64 = previous
        .iter()
        .zip(u)
        .enumerate()
        .map(|(i, (p, v))| (p - a[i % n]) * (v - b[i % n]))
        .sum();
    overlap < 0.0
}

impl<S: VectorField> FoldsOfCycles<'_, S> {
    /// The fold `pt` handed out, with the reason the curve ends on it: `p2`
    /// on a bound, or the folded cycles smaller than `min_amplitude`.
    fn handed_out(&mut self, pt: LpcPoint) -> (LpcPoint, Option<Stop>) {
        self.steps += 1;
        let p2 = pt.cycle.p[self.k2];
        let c = &pt.cycle;
        let amplitude = (0..c.n)
            .map(|j| {
                let (lo, hi) =
                    c.u.chunks(c.n)
                        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
                            (lo.min(x[j]), hi.max(x[j]))
                        });
                hi - lo
            })
            .fold(0.0, f64::max);
        let (p2_min, p2_max) = (self.settings.p2_min, self.settings.p2_max);
        let stop = if p2 <= p2_min || p2 >= p2_max {
            Some(Stop::Bound {
                index: self.k2,
                value: p2,
                bound: if p2 <= p2_min { p2_min } else { p2_max },
            })
        } else if amplitude < self.settings.min_amplitude {
            Some(Stop::SmallAmplitude {
                amplitude,
                min_amplitude: self.settings.min_amplitude,
            })
        } else {
            None
        };
        (pt, stop)
    }
}

impl<S: VectorField> Curve for FoldsOfCycles<'_, S> {
    type Point = LpcPoint;

    fn start(&mut self) -> Result<(LpcPoint, Option<Stop>), ContinuationError> {
        let pt = LpcPoint {
            cycle: self.aug.cycle(&self.y),
            newton: NewtonReport::NONE,
        };
        Ok(self.handed_out(pt))
    }

    fn advance(&mut self) -> Result<Advance<LpcPoint>, ContinuationError> {
        let param = self.y[self.y.len() - 1];
        match self.step() {
            Ok(Some(pt)) => {
                let (pt, stop) = self.handed_out(pt);
                Ok(Advance::Point(pt, stop))
            }
            Ok(None) => Ok(Advance::End(Stop::BautinPoint { param })),
            Err(e) => Err(e),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::quadratic_start;

    /// On the parabola `(s, s^2)`, from its vertex (tangent `(1, 0)`) with
    /// the point at `s = -h` behind it, the start is the parabola's point at
    /// `s = ds`, where the tangent's prediction is `ds^2` off; a point
    /// ahead of the vertex gives none.
    #[test]
    fn the_quadratic_start_lies_on_a_parabola() {
        let (h, ds) = (0.3, 0.45);
        let (y0, t) = ([0.0, 0.0], [1.0, 0.0]);
        let start = quadratic_start(&y0, &t, &[-h, h * h], &t, ds).unwrap();
        assert!((start[0] - ds).abs() < 1e-15, "{start:?}");
        assert!((start[1] - ds * ds).abs() < 1e-15, "{start:?}");
        assert!(quadratic_start(&y0, &t, &[h, h * h], &t, ds).is_none());
    }

    /// In uneven weights, with a tangent off the axes and not of unit
    /// length in them, the start lies on the pseudo-arclength hyperplane,
    /// and its distance from the curve's point there (the parabola
    /// `y0 + s t + s^2 a` where it crosses the hyperplane) falls with the
    /// cube of the step where the tangent's prediction falls with its
    /// square.
    #[test]
    fn the_quadratic_start_is_of_the_third_order_in_any_weights() {
        let (y0, t, a) = ([1.0, 2.0, -0.5], [0.6, -0.3, 0.9], [0.2, 0.7, -0.4]);
        let w = [3.0, 0.25, 10.0];
        let at = |s: f64| -> Vec<f64> { (0..3).map(|i| y0[i] + s * t[i] + s * s * a[i]).collect() };
        let row: Vec<f64> = (0..3).map(|i| w[i] * t[i]).collect();
        let dot = |u: &[f64], v: &[f64]| -> f64 { u.iter().zip(v).map(|(u, v)| u * v).sum() };
        // Along the row the parabola is at `s + alpha s^2`.
        let alpha = dot(&row, &a) / dot(&row, &t);
        let mut errors = Vec::new();
        for k in 0..3 {
            let (h0, ds) = (0.2 / 2f64.powi(k), 0.3 / 2f64.powi(k));
            let start = quadratic_start(&y0, &t, &at(-h0), &row, ds).unwrap();
            let pred: Vec<f64> = (0..3).map(|i| y0[i] + ds * t[i]).collect();
            let off = dot(&row, &start) - dot(&row, &pred);
            assert!(off.abs() < 1e-14, "{off}");
            let crossing = at(2.0 * ds / (1.0 + (1.0 + 4.0 * alpha * ds).sqrt()));
            let distance = |y: &[f64]| -> f64 {
                y.iter()
                    .zip(&crossing)
                    .map(|(y, c)| (y - c).abs())
                    .fold(0.0, f64::max)
            };
            errors.push((distance(&start), distance(&pred)));
        }
        for pair in errors.windows(2) {
            let (quadratic, tangent) = (pair[1].0 / pair[0].0, pair[1].1 / pair[0].1);
            assert!(quadratic < 0.16 && tangent > 0.2, "{errors:?}");
        }
        // A point too close behind for this step: none.
        assert!(quadratic_start(&y0, &t, &at(-0.05), &row, 0.3).is_none());
    }
}
