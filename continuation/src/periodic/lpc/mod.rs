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

pub use curve::{FoldsOfCycles, LpcCurve, LpcCurveSettings};

use super::bordered::{Bordered, CyclicReduction};
use super::collocation::Collocation;
use super::cycle::Cycle;
use crate::error::{ContinuationError, NewtonFailure};
use crate::newton::{
    self, max_norm, Failure, Linearized, NewtonProblem, NewtonReport, NewtonSettings, Stall,
};
use crate::system::VectorField;
use gradient::adjoint_gradient;
use nalgebra::DMatrix;

/// The minimally augmented system on one mesh, with its bordering vectors.
struct Augmented<'a, S: VectorField> {
    coll: Collocation<'a, S>,
    /// Second free parameter (curves of folds), read from the unknowns.
    k2: Option<usize>,
    b: Vec<f64>,
    c: Vec<f64>,
    /// The storage of a reduction no longer used, for the next evaluation.
    spare: Option<CyclicReduction>,
}

/// `F` and `g` at a point, their Jacobian (the collocation rows reduced,
/// border columns and dense rows) and the null vectors.
struct Evaluation {
    residual: Vec<f64>,
    reduction: CyclicReduction,
    /// The Jacobian's border columns on the collocation rows: `dF/dT`,
    /// `dF/dp1` and, for curves, `dF/dp2`.
    columns: DMatrix<f64>,
    /// Its dense rows: the phase condition, `dg`, and for curves a last row
    /// left to the linear equation that closes the system.
    rows: DMatrix<f64>,
    v: Vec<f64>,
    psi: Vec<f64>,
}

impl Evaluation {
    /// Solves `J x = rhs` with the Jacobian of `(F, g)` and the last dense row.
    fn solve(&self, rhs: &[f64]) -> Result<Vec<f64>, ContinuationError> {
        Bordered::new(&self.reduction, self.columns.clone(), self.rows.clone())?.solve(rhs)
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
        self.spare = Some(e.reduction);
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
        let lin = self.coll.linearize(z);
        let reduction = match self.spare.take() {
            Some(mut reduction) => {
                reduction.factor(&lin);
                reduction
            }
            None => CyclicReduction::new(&lin, n),
        };
        let border = lin.border_columns();
        let mut columns = DMatrix::zeros(nn, 2);
        columns.column_mut(0).copy_from(&border.column(0));
        columns.column_mut(1).copy_from_slice(&self.b[..nn]);
        let mut rows = DMatrix::zeros(2, nn + 2);
        rows.view_mut((0, 0), (1, nn)).copy_from_slice(&lin.phase);
        rows[(0, nn + 1)] = self.b[nn];
        rows.view_mut((1, 0), (1, nn + 1)).copy_from_slice(&self.c);
        let mut bordered = Bordered::new(&reduction, columns, rows)?;
        let mut e = vec![0.0; nn + 2];
        e[nn + 1] = 1.0;
        let vg = bordered.solve(&e)?;
        let psi = bordered.solve_transpose(&e)?;
        let (v, psi) = (vg[..nn + 1].to_vec(), psi[..nn + 1].to_vec());
        let (grad, fp2) = adjoint_gradient(&self.coll, z, &v, &psi, self.k2);
        let k = grad.len() - nn;
        let mut columns = DMatrix::zeros(nn, k);
        columns.columns_mut(0, 2).copy_from(&border);
        if self.k2.is_some() {
            columns.column_mut(2).copy_from_slice(&fp2[..nn]);
        }
        // g's row: dg = -grad(phi), scaled to unit size (the scale of g is
        // arbitrary, set by the bordering vectors).
        let scale = grad
            .iter()
            .fold(0.0f64, |a, v| a.max(v.abs()))
            .max(f64::MIN_POSITIVE);
        let mut rows = DMatrix::zeros(k, nn + k);
        rows.view_mut((0, 0), (1, nn)).copy_from_slice(&lin.phase);
        rows.row_mut(1)
            .iter_mut()
            .zip(&grad)
            .for_each(|(r, g)| *r = -g / scale);
        let mut residual = lin.residual;
        residual.push(vg[nn + 1] / scale);
        Ok(Evaluation {
            residual,
            reduction,
            columns,
            rows,
            v,
            psi,
        })
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
