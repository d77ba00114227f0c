//! Newton's method and tangents for the collocation system bordered by one
//! linear scalar equation `<row, z - anchor> = 0` (fixed parameter, or the
//! pseudo-arclength condition), solved by condensation and cyclic reduction
//! ([`super::bordered`]).

use super::bordered::{shape, Bordered, BorderedStore, CyclicReduction};
use super::collocation::{Collocation, Linearization};
use crate::error::{ContinuationError, NewtonFailure};
use crate::newton::{
    self, max_norm, Failure, Linearized, NewtonProblem, NewtonReport, NewtonSettings, Stall,
};
use crate::system::VectorField;
use nalgebra::DMatrix;
use std::cell::{Cell, OnceCell};

/// Weights of the pseudo-arclength inner product on `z = (u, T, p)`:
/// `1 / N` on each of the `N` orbit values (a quadrature of
/// `int_0^1 |u|^2 dtau`), `1 / T^2` on the period and `1 / max(|p|, floor)^2`
/// on the parameter, `T` and `p` taken at the orbit the step starts from.
/// A step of length `ds` then changes the period and the parameter by at most
/// the fraction `ds`, so branches whose period and parameter span decades
/// (stick-slip down to small stiffness) advance in equal relative steps.
#[derive(Clone, Copy, Debug)]
pub struct ArcWeights {
    n_orbit: usize,
    period: f64,
    param: f64,
}

impl ArcWeights {
    /// The weights at the orbit `z`; `floor` bounds the parameter's scale below.
    pub fn at(z: &[f64], floor: f64) -> Self {
        let nz = z.len();
        let scale = |v: f64, f: f64| 1.0 / v.abs().max(f).powi(2);
        ArcWeights {
            n_orbit: nz - 2,
            period: scale(z[nz - 2], f64::MIN_POSITIVE.sqrt()),
            param: scale(z[nz - 1], floor),
        }
    }

    /// Weight of unknown `i`.
    pub fn get(&self, i: usize) -> f64 {
        if i < self.n_orbit {
            1.0 / self.n_orbit as f64
        } else if i == self.n_orbit {
            self.period
        } else {
            self.param
        }
    }

    /// Weighted inner product.
    pub fn dot(&self, a: &[f64], b: &[f64]) -> f64 {
        a.iter()
            .zip(b)
            .enumerate()
            .map(|(i, (x, y))| self.get(i) * x * y)
            .sum()
    }

    /// `a` scaled by the weights: the row of the constraint `<a, dz>_w = 0`.
    pub fn row(&self, a: &[f64]) -> Vec<f64> {
        a.iter().enumerate().map(|(i, v)| self.get(i) * v).collect()
    }
}

/// The row `e_k`: the constraint `z_k = anchor_k` (parameter fixed when `k` is last).
pub fn unit_row(nz: usize, k: usize) -> Vec<f64> {
    let mut row = vec![0.0; nz];
    row[k] = 1.0;
    row
}

/// The collocation system linearized at an orbit (state dimension `n`),
/// with the reduction of its collocation rows ([`CyclicReduction`]) built
/// at its first use and then shared: by a Newton step from the orbit, the
/// branch's tangent there and the Floquet multipliers (which do not depend
/// on the phase condition, so also after the phase reference moves on).
pub struct OrbitJacobian {
    pub lin: Linearization,
    n: usize,
    reduction: OnceCell<CyclicReduction>,
    /// A reduction of an earlier linearization, whose storage the next
    /// reduction reuses.
    spare: Cell<Option<CyclicReduction>>,
    /// The storage of the bordered solves, kept between solves.
    solves: Cell<Option<Solves>>,
}

impl OrbitJacobian {
    /// `lin` (state dimension `n`), not yet reduced.
    pub fn new(lin: Linearization, n: usize) -> Self {
        OrbitJacobian {
            lin,
            n,
            reduction: OnceCell::new(),
            spare: Cell::new(None),
            solves: Cell::new(None),
        }
    }

    /// The system of `coll` linearized at `z` in place of this one, in its
    /// storage.
    fn relinearize<S: VectorField>(&mut self, coll: &Collocation<S>, z: &[f64]) {
        coll.linearize_into(z, &mut self.lin);
        if let Some(reduction) = self.reduction.take() {
            self.spare.set(Some(reduction));
        }
        if let Some(mut solves) = self.solves.take() {
            solves.extra.clear();
            self.solves.set(Some(solves));
        }
    }

    /// Whether [`OrbitJacobian::reduction`] has been built.
    fn is_reduced(&self) -> bool {
        self.reduction.get().is_some()
    }

    /// The reduction of the collocation rows, built at the first call.
    pub fn reduction(&self) -> &CyclicReduction {
        self.reduction.get_or_init(|| match self.spare.take() {
            Some(mut reduction) => {
                reduction.factor(&self.lin);
                reduction
            }
            None => CyclicReduction::new(&self.lin, self.n),
        })
    }

    /// Solves `J x = rhs`, `J` the collocation Jacobian (border columns `T`,
    /// `p`) bordered by the phase condition and the row `extra`.
    pub fn solve(&self, extra: &[f64], rhs: &[f64]) -> Result<Vec<f64>, ContinuationError> {
        let mut x = Vec::new();
        self.solve_into(extra, rhs, &mut x)?;
        Ok(x)
    }

    /// [`OrbitJacobian::solve`] into `x`, in storage kept between solves:
    /// no allocation once it has the mesh's size.
    pub fn solve_into(
        &self,
        extra: &[f64],
        rhs: &[f64],
        x: &mut Vec<f64>,
    ) -> Result<(), ContinuationError> {
        let nn = self.lin.phase.len();
        shape("the bordering row", nn + 2, extra)?;
        shape("the right-hand side", nn + 2, rhs)?;
        let Solves {
            mut rows,
            store,
            extra: mut reduced_for,
        } = self.solves.take().unwrap_or_default();
        // Chord steps solve with one reduction and one bordering row again
        // and again: the bordered system reduced for them is kept.
        let system = if reduced_for == extra {
            Ok(Bordered::reused(self.reduction(), store))
        } else {
            if rows.shape() != (2, nn + 2) {
                rows = DMatrix::zeros(2, nn + 2);
            }
            // Row 0: the phase condition on the nodes, zero on `T` and `p`.
            for (c, v) in self.lin.phase.iter().enumerate() {
                rows[(0, c)] = *v;
            }
            rows[(0, nn)] = 0.0;
            rows[(0, nn + 1)] = 0.0;
            rows.row_mut(1).copy_from_slice(extra);
            Bordered::on_border(self.reduction(), &mut rows, store)
        };
        reduced_for.clear();
        let (result, store) = match system {
            Ok(mut system) => {
                reduced_for.extend_from_slice(extra);
                (system.solve_into(rhs, x), system.into_store())
            }
            Err(e) => (Err(e), BorderedStore::default()),
        };
        self.solves.set(Some(Solves {
            rows,
            store,
            extra: reduced_for,
        }));
        result
    }
}

/// The storage of [`OrbitJacobian::solve_into`]: the dense rows and the
/// [`Bordered`] system's, with the bordering row that system was reduced
/// for (empty: none, or the reduction changed since).
#[derive(Default)]
struct Solves {
    rows: DMatrix<f64>,
    store: BorderedStore,
    extra: Vec<f64>,
}

/// The collocation system bordered by `<row, z - anchor> = 0`, for
/// [`newton::iterate`].
struct BorderedCollocation<'c, 'a, S: VectorField> {
    coll: &'c Collocation<'a, S>,
    row: &'c [f64],
    anchor: &'c [f64],
    /// The last point Newton's method is done with: the next one is
    /// linearized and reduced in its storage.
    spare: Option<BorderedPoint>,
    /// How the iterates are linearized.
    mode: Linearize<'c>,
}

/// How [`BorderedCollocation`] linearizes its iterates.
enum Linearize<'c> {
    /// At every iterate: Newton's method.
    Every,
    /// At the first iterate only: chord iterations, every step with that
    /// Jacobian (its reduction kept), the later iterates evaluated for
    /// their residual alone ([`chord_bordered`]).
    First,
    /// Newton's method until its steps fall fast, then chord iterations
    /// while they keep falling ([`correct_along`]).
    UntilFast(&'c Cell<Hybrid>),
}

/// The state of [`Linearize::UntilFast`].
#[derive(Clone, Copy, Debug, Default)]
struct Hybrid {
    /// Max norms of the last two steps taken, the latest first.
    steps: [f64; 2],
    /// Whether the last step was a chord step.
    chord: bool,
    /// Newton iterations (linearizations) taken, and whether any chord
    /// step was.
    newton: usize,
    chorded: bool,
    /// A chord step that did not fall fast enough: it was not taken, and
    /// the iterate is linearized again.
    refused: bool,
}

/// A Newton step at most this fraction of the one before it starts chord
/// iterations (Newton's method has reached its quadratic phase: the
/// Jacobian changes little over the remaining corrections).
const CHORD_START: f64 = 0.1;

/// A chord step larger than this fraction of the step before it is refused,
/// and Newton's method takes over again from the iterate it started from.
const CHORD_KEEP: f64 = 0.5;

/// The bordered collocation system linearized at an orbit: the
/// collocation Jacobian and the residual with the bordering equation's last.
pub struct BorderedPoint {
    /// The collocation system linearized there (its residual also in `rhs`).
    pub jacobian: OrbitJacobian,
    rhs: Vec<f64>,
}

impl Linearized for BorderedPoint {
    fn residual(&self) -> &[f64] {
        &self.rhs
    }

    /// `max(residual_tol (1 + |z|), 1e3 eps term_scale)`: the residual cannot
    /// fall below the rounding of its terms (`term_scale`), which on stiff
    /// stretches of stick-slip orbits exceeds any fixed tolerance.
    fn residual_bound(&self, residual_tol: f64, z_max: f64) -> f64 {
        (residual_tol * (1.0 + z_max)).max(1e3 * f64::EPSILON * self.jacobian.lin.term_scale)
    }
}

impl<'c, 'a, S: VectorField> BorderedCollocation<'c, 'a, S> {
    fn new(
        coll: &'c Collocation<'a, S>,
        row: &'c [f64],
        anchor: &'c [f64],
        mode: Linearize<'c>,
    ) -> Self {
        BorderedCollocation {
            coll,
            row,
            anchor,
            spare: None,
            mode,
        }
    }
}

impl<S: VectorField> NewtonProblem for BorderedCollocation<'_, '_, S> {
    type Point = BorderedPoint;

    fn evaluate(&mut self, z: &[f64]) -> Result<BorderedPoint, ContinuationError> {
        let mut point = self.spare.take().unwrap_or_else(|| BorderedPoint {
            jacobian: OrbitJacobian::new(Linearization::default(), self.coll.sys.dim()),
            rhs: Vec::new(),
        });
        let residual_only = match &self.mode {
            Linearize::Every => false,
            Linearize::First => point.jacobian.is_reduced(),
            Linearize::UntilFast(state) => {
                let mut h = state.get();
                let fast = (h.steps[1].is_finite() && h.steps[0] <= CHORD_START * h.steps[1])
                    || (h.chord && !h.refused);
                h.chord = fast && !h.refused && point.jacobian.is_reduced();
                h.refused = false;
                if h.chord {
                    h.chorded = true;
                } else {
                    h.newton += 1;
                }
                state.set(h);
                h.chord
            }
        };
        if residual_only {
            self.coll.residual_into(z, &mut point.rhs);
        } else {
            point.jacobian.relinearize(self.coll, z);
            point.rhs.clear();
            point.rhs.extend_from_slice(&point.jacobian.lin.residual);
        }
        let extra: f64 = self
            .row
            .iter()
            .zip(z.iter().zip(self.anchor))
            .map(|(r, (a, b))| r * (a - b))
            .sum();
        point.rhs.push(extra);
        Ok(point)
    }

    fn recycle(&mut self, point: BorderedPoint) {
        self.spare = Some(point);
    }

    /// Each node's state by the field's [`VectorField::newton_update`], the
    /// period and the parameter by `z <- z - dz`.
    fn update(&self, z: &mut [f64], dz: &[f64]) {
        if let Linearize::UntilFast(state) = &self.mode {
            let mut h = state.get();
            let step = max_norm(dz);
            // A step that is not finite (NaN) is refused too.
            let falls = step <= CHORD_KEEP * h.steps[0];
            if h.chord && !falls {
                // Not taken: the iterate is linearized again.
                h.refused = true;
                state.set(h);
                return;
            }
            h.steps = [step, h.steps[0]];
            state.set(h);
        }
        let n = self.coll.sys.dim();
        let nn = z.len() - 2;
        for (x, dx) in z[..nn].chunks_exact_mut(n).zip(dz[..nn].chunks_exact(n)) {
            self.coll.sys.newton_update(x, dx);
        }
        z[nn] -= dz[nn];
        z[nn + 1] -= dz[nn + 1];
    }

    fn newton_step(&mut self, point: &BorderedPoint) -> Result<Vec<f64>, ContinuationError> {
        point.jacobian.solve(self.row, &point.rhs)
    }

    fn newton_step_into(
        &mut self,
        point: &BorderedPoint,
        dz: &mut Vec<f64>,
    ) -> Result<(), ContinuationError> {
        point.jacobian.solve_into(self.row, &point.rhs, dz)
    }

    /// A step that no longer shrinks while within 1e3 of the tolerance is
    /// the rounding floor of the solve: converged as far as it can be.
    fn stall(&self) -> Stall {
        Stall::Converged
    }

    fn error(&self, failure: Failure, _cause: Option<ContinuationError>) -> ContinuationError {
        let hint = match failure.reason {
            NewtonFailure::MaxIterations | NewtonFailure::Stalled => {
                "reduce the step size or refine the mesh (more NTST)"
            }
            NewtonFailure::SingularJacobian => {
                "the orbit may be at a fold or period doubling; perturb the parameter"
            }
            NewtonFailure::NonFinite => {
                "the orbit left the model's domain (a non-finite value); a smaller step may stay inside it"
            }
        };
        failure.error(" correcting a periodic orbit".into(), hint)
    }
}

/// Newton's method on the collocation system plus the linear equation
/// `<row, z - anchor> = 0` ([`newton::iterate`]; the residual bound has the
/// rounding floor of [`BorderedPoint`] and a stalled step converges);
/// returns the report and the system linearized at the solution.
pub fn correct_bordered<S: VectorField>(
    coll: &Collocation<S>,
    z: &mut [f64],
    settings: &NewtonSettings,
    row: &[f64],
    anchor: &[f64],
) -> Result<(NewtonReport, BorderedPoint), ContinuationError> {
    newton::iterate(
        &mut BorderedCollocation::new(coll, row, anchor, Linearize::Every),
        z,
        settings,
    )
}

/// [`newton_bordered`] by chord iterations (the simplified Newton method;
/// Deuflhard, *Newton Methods for Nonlinear Problems*, 2004, §2.1.4):
/// every step solved with the Jacobian of the first iterate, reduced once,
/// the later iterates evaluated for their residual alone
/// ([`Collocation::residual_into`]; the rounding floor of the residual
/// stays the first iterate's). The iterates contract by about the
/// Jacobian's relative change across the correction, so from a guess whose
/// correction is small (an orbit moved onto another mesh of the same
/// branch, `1e-8` relative) the steps fall as fast as Newton's, at a
/// fraction of an iteration's cost (a residual and a solve, no
/// linearization or reduction); for solutions only (the Jacobian at the
/// solution is not formed). Where they do not converge within the
/// settings' iterations, `z` is left where they stopped (and `Err`).
pub fn chord_bordered<S: VectorField>(
    coll: &Collocation<S>,
    z: &mut [f64],
    settings: &NewtonSettings,
    row: &[f64],
    anchor: &[f64],
) -> Result<NewtonReport, ContinuationError> {
    let mut problem = BorderedCollocation::new(coll, row, anchor, Linearize::First);
    newton::iterate(&mut problem, z, settings).map(|(report, _)| report)
}

/// Whether `z` already solves the collocation system bordered by `<row, z -
/// anchor> = 0` to `settings`: its residual finite and within the bound of
/// [`BorderedPoint`] and its Newton step within `settings.step_tol`
/// (relative to the iterate, as [`newton::iterate`] measures steps), the
/// test [`newton::iterate`] applies after a step, here applied before one.
/// A system that cannot be linearized or solved there is not solved: Newton's
/// method, run next, says why in its own words.
pub fn solves_bordered<S: VectorField>(
    coll: &Collocation<S>,
    z: &[f64],
    settings: &NewtonSettings,
    row: &[f64],
    anchor: &[f64],
) -> bool {
    let mut problem = BorderedCollocation::new(coll, row, anchor, Linearize::Every);
    let Ok(point) = problem.evaluate(z) else {
        return false;
    };
    let bound = point.residual_bound(settings.residual_tol, max_norm(z));
    if !point.residual().iter().all(|v| v.is_finite()) || point.residual_norm() > bound {
        return false;
    }
    let mut dz = Vec::new();
    problem.newton_step_into(&point, &mut dz).is_ok()
        && problem.relative_step(&dz, z) <= settings.step_tol
}

/// [`correct_bordered`] without the linearization.
pub fn newton_bordered<S: VectorField>(
    coll: &Collocation<S>,
    z: &mut [f64],
    settings: &NewtonSettings,
    row: &[f64],
    anchor: &[f64],
) -> Result<NewtonReport, ContinuationError> {
    correct_bordered(coll, z, settings, row, anchor).map(|(report, _)| report)
}

/// Unit tangent (norm of `w`) of the cycle branch at `z`: the null vector of
/// the collocation Jacobian, normalized by `<reference, t>_w = 1` and then
/// scaled to unit length (so it points along `reference`).
pub fn tangent<S: VectorField>(
    coll: &Collocation<S>,
    z: &[f64],
    reference: &[f64],
    w: &ArcWeights,
) -> Result<Vec<f64>, ContinuationError> {
    let jacobian = OrbitJacobian::new(coll.linearize(z), coll.sys.dim());
    tangent_from(&jacobian, reference, w)
}

/// The [`tangent`] from the collocation Jacobian at the orbit.
pub fn tangent_from(
    jacobian: &OrbitJacobian,
    reference: &[f64],
    w: &ArcWeights,
) -> Result<Vec<f64>, ContinuationError> {
    let nz = jacobian.lin.phase.len() + 2;
    let mut rhs = vec![0.0; nz];
    rhs[nz - 1] = 1.0;
    let t = jacobian.solve(&w.row(reference), &rhs)?;
    let norm = w.dot(&t, &t).sqrt();
    let sign = if w.dot(&t, reference) < 0.0 {
        -1.0
    } else {
        1.0
    };
    Ok(t.iter().map(|v| sign * v / norm).collect())
}

/// Predicts `z0 + sigma t` and corrects it on the collocation system plus the
/// pseudo-arclength condition `<t, z - prediction>_w = 0`; returns the orbit,
/// the report and the system linearized there.
///
/// Newton's method until a step falls to a tenth of the one before
/// ([`CHORD_START`]: its quadratic phase), then chord iterations with the
/// last Jacobian while each step falls to half the one before
/// ([`CHORD_KEEP`]; a chord step that does not is refused and the iterate
/// linearized again); the orbit is linearized once more at the solution
/// for its tangent and multipliers. The solution is the same to the
/// tolerance; the work is about 3 linearizations and reductions a step in
/// place of 6 (Deuflhard 2004, §2.1.4, on the simplified Newton method).
///
/// `storage`: a Jacobian no longer needed (the previous step's), whose
/// storage the correction linearizes into.
pub fn correct_along<S: VectorField>(
    coll: &Collocation<S>,
    (z0, t, sigma): (&[f64], &[f64], f64),
    w: &ArcWeights,
    settings: &NewtonSettings,
    storage: Option<OrbitJacobian>,
) -> Result<(Vec<f64>, NewtonReport, BorderedPoint), ContinuationError> {
    let pred: Vec<f64> = z0.iter().zip(t).map(|(z, t)| z + sigma * t).collect();
    let mut z = pred.clone();
    let row = w.row(t);
    let state = Cell::new(Hybrid {
        steps: [f64::INFINITY; 2],
        ..Hybrid::default()
    });
    let mut problem = BorderedCollocation::new(coll, &row, &pred, Linearize::UntilFast(&state));
    problem.spare = storage.map(|jacobian| BorderedPoint {
        jacobian,
        rhs: Vec::new(),
    });
    let (mut rep, mut point) = newton::iterate(&mut problem, &mut z, settings)?;
    let h = state.get();
    if h.chord {
        // The tangent and the multipliers need the Jacobian at the solution.
        point.jacobian.relinearize(coll, &z);
    }
    // The step control counts Newton's iterations: the chord steps, taken
    // where Newton's method was in its quadratic phase, count as the one
    // more iteration it would have needed there (the steps then grow and
    // shrink as with Newton's method alone; counted one by one, they held
    // the steps small, and stiff branches ended earlier).
    rep.iterations = h.newton - 1 + usize::from(h.chorded);
    Ok((z, rep, point))
}
