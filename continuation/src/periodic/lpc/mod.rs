//! Folds of cycles (limit points of cycles, LPC) by the minimally augmented
//! system of Doedel, Govaerts & Kuznetsov (2003, "Computation of periodic
//! solution bifurcations in ODEs using bordered systems", SIAM J. Numer.
//! Anal. 41, 401–435), on the collocation discretization.
//!
//! With `F(u, T, p) = 0` the collocation and phase equations and
//! `A = dF/d(u, T)`, a fold of cycles is where `A` is singular. With
//! bordering vectors `b`, `c` (approximate left and right null vectors of
//! `A`), the scalar `g` defined by
//!
//! ```text
//! [ A    b ] [ v ]   [ 0 ]
//! [ c^T  0 ] [ g ] = [ 1 ]
//! ```
//!
//! vanishes exactly there, and its gradient is `dg = -psi^T (dA) v` with
//! `(psi, gamma)` from the transposed system. The LPC is the solution of
//! `F = 0, g = 0`: in `(u, T, p1)` at a fixed second parameter (a route
//! independent of the sign change of `dp/ds` on a branch), and in
//! `(u, T, p1, p2)` with pseudo-arclength for a curve of folds.

mod curve;
mod gradient;

pub use curve::{fold_beside_bautin, FoldsOfCycles, LpcCurve, LpcCurveSettings};

use super::bordered::{shaped, Bordered, BorderedStore, CyclicReduction};
use super::collocation::{Collocation, Linearization};
use super::cycle::Cycle;
use crate::error::{ContinuationError, NewtonFailure};
use crate::newton::{
    self, max_norm, Failure, Linearized, NewtonProblem, NewtonReport, NewtonSettings, Stall,
};
use crate::system::VectorField;
use gradient::adjoint_gradient;
use nalgebra::DMatrix;
use std::cell::Cell;

/// The minimally augmented system on one mesh, with its bordering vectors.
struct Augmented<'a, S: VectorField> {
    coll: Collocation<'a, S>,
    /// Second free parameter (curves of folds), read from the unknowns.
    k2: Option<usize>,
    b: Vec<f64>,
    c: Vec<f64>,
    /// The system of the test function, `[A b; c^T 0]`, in storage kept
    /// between evaluations.
    test: TestSystem,
    /// An evaluation no longer used, whose storage (linearization,
    /// reduction, border columns and rows) the next one reuses.
    spare: Option<Evaluation>,
}

/// Storage of the test function's system: its border columns transformed
/// by the reduction (`dF/dT`, `b`), its dense rows, and the bordered
/// system's.
#[derive(Default)]
struct TestSystem {
    columns: DMatrix<f64>,
    rows: DMatrix<f64>,
    store: BorderedStore,
}

/// `F` and `g` at a point, their Jacobian (the collocation rows reduced,
/// border columns and dense rows) and the null vectors.
struct Evaluation {
    /// The collocation system linearized at the point.
    lin: Linearization,
    residual: Vec<f64>,
    reduction: CyclicReduction,
    /// The Jacobian's border columns on the collocation rows, transformed
    /// by the reduction: `dF/dT`, `dF/dp1` (the reduction's own) and, for
    /// curves, `dF/dp2`.
    columns: DMatrix<f64>,
    /// Its dense rows: the phase condition, `dg`, and for curves a last row
    /// left to the linear equation that closes the system.
    rows: DMatrix<f64>,
    v: Vec<f64>,
    psi: Vec<f64>,
    /// Storage of [`Evaluation::solve`]: the dense rows being reduced and
    /// the bordered system's.
    solves: Cell<Option<(DMatrix<f64>, BorderedStore)>>,
}

impl Evaluation {
    /// Solves `J x = rhs` with the Jacobian of `(F, g)` and the last dense
    /// row, on the reduction of the collocation rows, in storage kept
    /// between solves.
    fn solve(&self, rhs: &[f64]) -> Result<Vec<f64>, ContinuationError> {
        let (mut rows, store) = self.solves.take().unwrap_or_default();
        shaped(&mut rows, self.rows.shape());
        rows.copy_from(&self.rows);
        let mut system = Bordered::transformed(&self.reduction, &self.columns, &mut rows, store)?;
        let mut x = Vec::new();
        let solved = system.solve_into(rhs, &mut x);
        self.solves.set(Some((rows, system.into_store())));
        solved.map(|()| x)
    }
}

impl<'a, S: VectorField> Augmented<'a, S> {
    /// On `orbit`'s mesh, with `b`, `c` from inverse iteration started at
    /// `dF/dp1` and the constant vector.
    fn new(
        sys: &'a S,
        orbit: &Cycle,
        k1: usize,
        k2: Option<usize>,
    ) -> Result<Self, ContinuationError> {
        // Explicit: the second derivatives below differentiate `f`.
        let coll = Collocation::new(sys, orbit, k1).explicit();
        let nn = coll.mesh.n_nodes() * sys.dim();
        let mut y = coll.unknowns(orbit);
        if let Some(k) = k2 {
            y.push(orbit.p[k]);
        }
        // dF/dp1 (the phase row has none).
        let mut b: Vec<f64> = coll
            .linearize(&y[..nn + 2])
            .border_columns()
            .column(1)
            .iter()
            .copied()
            .collect();
        b.push(0.0);
        let mut aug = Augmented {
            coll,
            k2,
            b,
            c: vec![1.0; nn + 1],
            test: TestSystem::default(),
            spare: None,
        };
        for _ in 0..2 {
            let e = aug.evaluate(&y)?;
            aug.update_borders(&e);
            aug.recycle(e);
        }
        Ok(aug)
    }

    /// Keeps the storage of an evaluation done with.
    fn recycle(&mut self, e: Evaluation) {
        self.spare = Some(e);
    }

    fn nn(&self) -> usize {
        self.coll.mesh.n_nodes() * self.coll.sys.dim()
    }

    /// The next bordering vectors: the current null vectors, normalized.
    fn update_borders(&mut self, e: &Evaluation) {
        let unit = |a: &[f64]| {
            let norm = a.iter().map(|v| v * v).sum::<f64>().sqrt();
            a.iter().map(|v| v / norm).collect::<Vec<_>>()
        };
        self.c = unit(&e.v);
        self.b = unit(&e.psi);
    }

    /// `(F, g)` at `y = (u, T, p1[, p2])`, the Jacobian of both, and `v`, `psi`.
    ///
    /// `(v, g)` and `(psi, gamma)` solve the bordered system and its transpose
    /// on one structured factorization (`b` a border column, `c^T` a dense
    /// row, next to `dF/dT` and the phase condition); the Newton matrix
    /// shares its reduction of the collocation rows.
    fn evaluate(&mut self, y: &[f64]) -> Result<Evaluation, ContinuationError> {
        let n = self.coll.sys.dim();
        let nn = self.nn();
        if let Some(k) = self.k2 {
            self.coll.p[k] = y[nn + 2];
        }
        let z = &y[..nn + 2];
        let mut e = match self.spare.take() {
            Some(mut e) => {
                self.coll.linearize_into(z, &mut e.lin);
                e.reduction.factor(&e.lin);
                e
            }
            None => {
                let lin = self.coll.linearize(z);
                let reduction = CyclicReduction::new(&lin, n);
                Evaluation {
                    lin,
                    residual: Vec::new(),
                    reduction,
                    columns: DMatrix::zeros(0, 0),
                    rows: DMatrix::zeros(0, 0),
                    v: Vec::new(),
                    psi: Vec::new(),
                    solves: Cell::new(None),
                }
            }
        };
        let reduction = &e.reduction;
        // The test function's system `[A b; c^T 0]`: border columns `dF/dT`
        // (the reduction's own) and `b`'s collocation rows; dense rows the
        // phase condition (`b`'s last entry, the phase row's, in `g`'s
        // column) and `c^T`.
        let TestSystem {
            columns,
            rows,
            store,
        } = &mut self.test;
        shaped(columns, (nn, 2));
        columns
            .column_mut(0)
            .copy_from(&reduction.border().column(0));
        let b_column = &mut columns.as_mut_slice()[nn..2 * nn];
        b_column.copy_from_slice(&self.b[..nn]);
        reduction.apply_r(b_column);
        shaped(rows, (2, nn + 2));
        rows.fill(0.0);
        rows.view_mut((0, 0), (1, nn)).copy_from_slice(&e.lin.phase);
        rows[(0, nn + 1)] = self.b[nn];
        rows.view_mut((1, 0), (1, nn + 1)).copy_from_slice(&self.c);
        let mut bordered = Bordered::transformed(reduction, columns, rows, std::mem::take(store))?;
        let mut unit = vec![0.0; nn + 2];
        unit[nn + 1] = 1.0;
        let solved = bordered
            .solve(&unit)
            .and_then(|vg| Ok((vg, bordered.solve_transpose(&unit)?)));
        *store = bordered.into_store();
        let (vg, psi) = solved?;
        e.v.clear();
        e.v.extend_from_slice(&vg[..nn + 1]);
        e.psi.clear();
        e.psi.extend_from_slice(&psi[..nn + 1]);
        let (grad, fp2) = adjoint_gradient(&self.coll, z, &e.v, &e.psi, self.k2);
        let k = grad.len() - nn;
        shaped(&mut e.columns, (nn, k));
        e.columns.columns_mut(0, 2).copy_from(reduction.border());
        if self.k2.is_some() {
            let column = &mut e.columns.as_mut_slice()[2 * nn..3 * nn];
            column.copy_from_slice(&fp2[..nn]);
            reduction.apply_r(column);
        }
        // g's row: dg = -grad(phi), scaled to unit size (the scale of g is
        // arbitrary, set by the bordering vectors).
        let scale = grad
            .iter()
            .fold(0.0f64, |a, v| a.max(v.abs()))
            .max(f64::MIN_POSITIVE);
        shaped(&mut e.rows, (k, nn + k));
        e.rows.fill(0.0);
        e.rows
            .view_mut((0, 0), (1, nn))
            .copy_from_slice(&e.lin.phase);
        e.rows
            .row_mut(1)
            .iter_mut()
            .zip(&grad)
            .for_each(|(r, g)| *r = -g / scale);
        e.residual.clear();
        e.residual.extend_from_slice(&e.lin.residual);
        e.residual.push(vg[nn + 1] / scale);
        Ok(e)
    }

    /// The orbit of unknowns `y`.
    fn cycle(&self, y: &[f64]) -> Cycle {
        let nn = self.nn();
        let mut c = self.coll.cycle(&y[..nn + 2]);
        if let Some(k) = self.k2 {
            c.p[k] = y[nn + 2];
        }
        c
    }

    /// Newton's method ([`newton::iterate`]) on `(F, g)` plus, for curves,
    /// the linear equation `<row, y - anchor> = 0`. With `stop_at_floor`, a
    /// step that stops shrinking within 1e3 of the tolerance (the residual
    /// within its own) ends it with [`NewtonFailure::Stalled`]: the rounding
    /// floor of the system, which more iterations do not lower (near a
    /// Bautin point, where the fold system degenerates); otherwise it
    /// iterates on.
    fn newton(
        &mut self,
        y: &mut [f64],
        extra: Option<(&[f64], &[f64])>,
        settings: &NewtonSettings,
        stop_at_floor: bool,
    ) -> Result<(NewtonReport, Evaluation), ContinuationError> {
        let stall = if stop_at_floor {
            Stall::Fail
        } else {
            Stall::Iterate
        };
        let mut system = FoldSystem {
            aug: self,
            extra,
            stall,
        };
        newton::iterate(&mut system, y, settings)
    }
}

impl Linearized for Evaluation {
    fn residual(&self) -> &[f64] {
        &self.residual
    }

    /// The residual of `F` (and of the closing equation): the test function
    /// `g` (after the `nn + 1` rows of `F`) is judged by the step it causes,
    /// its own scale being arbitrary (set by the bordering vectors).
    fn residual_norm(&self) -> f64 {
        let g = self.v.len();
        max_norm(&self.residual[..g]).max(max_norm(&self.residual[g + 1..]))
    }
}

/// The system `(F, g)` of an [`Augmented`], closed for curves by the linear
/// equation `<row, y - anchor> = 0`, for [`newton::iterate`].
struct FoldSystem<'s, 'a, S: VectorField> {
    aug: &'s mut Augmented<'a, S>,
    extra: Option<(&'s [f64], &'s [f64])>,
    stall: Stall,
}

impl<S: VectorField> NewtonProblem for FoldSystem<'_, '_, S> {
    type Point = Evaluation;

    fn evaluate(&mut self, y: &[f64]) -> Result<Evaluation, ContinuationError> {
        let mut e = self.aug.evaluate(y)?;
        if let Some((row, anchor)) = self.extra {
            let r: f64 = (0..y.len()).map(|i| row[i] * (y[i] - anchor[i])).sum();
            e.residual.push(r);
            let last = e.rows.nrows() - 1;
            e.rows.row_mut(last).copy_from_slice(row);
        }
        Ok(e)
    }

    fn newton_step(&mut self, e: &Evaluation) -> Result<Vec<f64>, ContinuationError> {
        e.solve(&e.residual)
    }

    fn recycle(&mut self, e: Evaluation) {
        self.aug.recycle(e);
    }

    fn stall(&self) -> Stall {
        self.stall
    }

    /// A failed evaluation or solve is returned as it is at the start; once
    /// Newton has moved off the start it diverged, and the failure says so.
    fn error(&self, failure: Failure, cause: Option<ContinuationError>) -> ContinuationError {
        let cause = match cause {
            Some(e) if failure.iterations == 0 => return e,
            Some(e) => format!(" ({e})"),
            None => String::new(),
        };
        let hint = match failure.reason {
            NewtonFailure::Stalled => {
                "the fold is ill-conditioned here (the fold system degenerates at a Bautin point)"
            }
            _ => "start closer to the fold (a cycle of the branch next to it)",
        };
        failure.error(format!(" solving the fold-of-cycles system{cause}"), hint)
    }
}

/// A fold of cycles.
#[derive(Clone, Debug)]
pub struct LpcPoint {
    /// The orbit at the fold (parameters included).
    pub cycle: Cycle,
    /// Newton's work on it; on a curve of folds, a correction started on
    /// the quadratic predictor counts one iteration more, the one the
    /// tangent's prediction would have taken (what the step control reads).
    pub newton: NewtonReport,
}

/// Locates the fold of cycles near `orbit` in parameter `k1` (the others
/// fixed) by Newton's method on the minimally augmented system `F = 0, g = 0`.
pub fn locate_lpc<S: VectorField>(
    sys: &S,
    orbit: &Cycle,
    k1: usize,
    settings: &NewtonSettings,
) -> Result<LpcPoint, ContinuationError> {
    let mut aug = Augmented::new(sys, orbit, k1, None)?;
    let mut y = aug.coll.unknowns(orbit);
    let (newton, _) = aug.newton(&mut y, None, settings, false)?;
    Ok(LpcPoint {
        cycle: aug.cycle(&y),
        newton,
    })
}
