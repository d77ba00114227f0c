//! Newton's method with a typed outcome: one loop for every system of the
//! crate.
//!
//! A [`NewtonProblem`] evaluates the residual `G(z)` together with what it
//! needs to solve with the Jacobian `DG(z)` (a [`Linearized`] point: a dense
//! LU, the structured bordered reduction of collocation, ...) and returns the
//! Newton step `DG(z)^{-1} G(z)`. [`iterate`] runs `z <- z - DG^{-1} G` and
//! judges convergence in max norms: the last step below
//! `step_tol` relative to the iterate and the residual below the bound the linearized point
//! gives ([`Linearized::residual_bound`]: `residual_tol (1 + |z|)`, or a
//! backward-error bound, or a rounding floor), with a [`Stall`] rule for a
//! step that stops shrinking at the rounding floor of the system.
//!
//! [`solve`] is the dense corrector: the caller supplies one closure that
//! writes `G(z)` and `DG(z)`, and the residual is judged by the backward
//! error `residual_tol (1 + |DG| |z|)`, so that a badly scaled system is
//! judged against its own rounding level.

use crate::error::{ContinuationError, NewtonFailure};
use nalgebra::{DMatrix, DVector};

/// Tolerances and limits of the corrector.
#[derive(Clone, Copy, Debug)]
pub struct NewtonSettings {
    /// Relative step tolerance (max norm). Default `1e-11`.
    pub step_tol: f64,
    /// Residual tolerance relative to the scale of the residual (max norms;
    /// see `residual_bound`). Default `1e-10`.
    pub residual_tol: f64,
    /// Iteration limit. Default `12`.
    pub max_iter: usize,
}

impl Default for NewtonSettings {
    fn default() -> Self {
        NewtonSettings {
            step_tol: 1e-11,
            residual_tol: 1e-10,
            max_iter: 12,
        }
    }
}

/// What a converged Newton run did.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NewtonReport {
    /// Iterations taken.
    pub iterations: usize,
    /// Max norm of the final residual.
    pub residual: f64,
    /// Max norm of the last step.
    pub step: f64,
}

impl NewtonReport {
    /// No Newton run: the report of a curve's first point, taken as given.
    pub const NONE: NewtonReport = NewtonReport {
        iterations: 0,
        residual: 0.0,
        step: 0.0,
    };
}

/// Max norm `max_i |a_i|`; NaN entries are passed over, as `f64::max`
/// passes them. In four running maxima (vector lanes): a maximum is exact
/// in any order, so the result is that of one running maximum.
pub(crate) fn max_norm(a: &[f64]) -> f64 {
    let larger = |m: f64, v: f64| if v > m { v } else { m };
    let mut lanes = [0.0f64; 4];
    let mut quads = a.chunks_exact(4);
    for q in &mut quads {
        for (lane, v) in lanes.iter_mut().zip(q) {
            *lane = larger(*lane, v.abs());
        }
    }
    let m = lanes.into_iter().fold(0.0, larger);
    quads.remainder().iter().fold(m, |m, v| larger(m, v.abs()))
}

/// A system linearized at an iterate: its residual and whatever solves with
/// its Jacobian there.
pub trait Linearized {
    /// The residual `G(z)`, the right-hand side of the Newton step.
    fn residual(&self) -> &[f64];

    /// The residual convergence is judged by: `|G(z)|` (max norm) unless a
    /// component has a scale of its own (a test function is then judged by
    /// the step it causes).
    fn residual_norm(&self) -> f64 {
        max_norm(self.residual())
    }

    /// The largest residual accepted at an iterate of max norm `z_max`:
    /// `residual_tol (1 + |z|)` unless the system knows its rounding level
    /// better.
    fn residual_bound(&self, residual_tol: f64, z_max: f64) -> f64 {
        residual_tol * (1.0 + z_max)
    }
}

/// What a step that stops shrinking at the rounding floor means: the last
/// step within `1e3` of the step tolerance, more than half the one before,
/// which itself did not fall by more than a factor `1e3` (the fast fall of
/// Newton's quadratic phase has ended: a step back right after it, seen in
/// the fold-of-cycles system on stiff orbits, relative steps 8e-4, 2.5e-8,
/// 7.7e-8, is followed by convergence, not a floor), the residual already
/// within its bound.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Stall {
    /// Nothing: Newton iterates on (the step tolerance is reachable).
    Iterate,
    /// Converged as far as rounding allows (collocation on stiff orbits,
    /// whose residual floor exceeds any fixed tolerance).
    Converged,
    /// Failure [`NewtonFailure::Stalled`]: an ill-conditioned system whose
    /// floor smaller continuation steps do not lower.
    Fail,
}

/// The numbers of a Newton run that stopped without converging.
#[derive(Clone, Debug, PartialEq)]
pub struct Failure {
    /// Iterations taken.
    pub iterations: usize,
    /// Max norm of the last residual evaluated.
    pub residual: f64,
    /// Max norm of the last step.
    pub step: f64,
    /// Why it stopped.
    pub reason: NewtonFailure,
}

impl Failure {
    /// The error [`ContinuationError::Newton`] with what was being solved
    /// (`context`) and what to try (`hint`).
    pub fn error(self, context: String, hint: &'static str) -> ContinuationError {
        ContinuationError::Newton {
            context,
            iterations: self.iterations,
            residual: self.residual,
            step: self.step,
            reason: self.reason,
            hint,
        }
    }
}

/// A system `G(z) = 0` Newton's method solves.
pub trait NewtonProblem {
    /// The system linearized at an iterate.
    type Point: Linearized;

    /// `G(z)` and its linearization.
    fn evaluate(&mut self, z: &[f64]) -> Result<Self::Point, ContinuationError>;

    /// The Newton step `DG(z)^{-1} G(z)` at the linearized point.
    fn newton_step(&mut self, point: &Self::Point) -> Result<Vec<f64>, ContinuationError>;

    /// [`NewtonProblem::newton_step`] into `dz` (its storage reused).
    /// Default: the step, moved into `dz`.
    fn newton_step_into(
        &mut self,
        point: &Self::Point,
        dz: &mut Vec<f64>,
    ) -> Result<(), ContinuationError> {
        *dz = self.newton_step(point)?;
        Ok(())
    }

    /// The next iterate from `z` and the Newton step `dz`. Default:
    /// `z <- z - dz`.
    fn update(&self, z: &mut [f64], dz: &[f64]) {
        z.iter_mut().zip(dz).for_each(|(zi, d)| *zi -= d);
    }

    /// Takes back a linearized point no longer needed (to reuse its storage).
    fn recycle(&mut self, _point: Self::Point) {}

    /// What a step stalled at the rounding floor means. Default: nothing.
    fn stall(&self) -> Stall {
        Stall::Iterate
    }

    /// The size of the step `dz` that led to `z`, relative to the scale the
    /// step tolerance applies to: Newton's method has converged (as far as
    /// the step goes) when it is at most `step_tol`. Default: the max norm
    /// relative to the iterate's, `max|dz| / (1 + max|z|)`.
    fn relative_step(&self, dz: &[f64], z: &[f64]) -> f64 {
        max_norm(dz) / (1.0 + max_norm(z))
    }

    /// The error for `failure`; `cause` is the error of a failed evaluation
    /// or linear solve (then `failure.reason` is
    /// [`NewtonFailure::SingularJacobian`]).
    fn error(&self, failure: Failure, cause: Option<ContinuationError>) -> ContinuationError;
}

/// Runs Newton's method on `problem` from `z`, which is overwritten with the
/// solution; returns the report and the system linearized at the solution.
///
/// Iterates `z <- z - DG(z)^{-1} G(z)` until the last step is at most
/// `step_tol` relative to the iterate ([`NewtonProblem::relative_step`]) and
/// the residual ([`Linearized::residual_norm`]) at most
/// [`Linearized::residual_bound`], or the step stalls
/// ([`NewtonProblem::stall`]). A residual or step that is not finite, a
/// failed solve and the iteration limit are failures.
pub fn iterate<P: NewtonProblem>(
    problem: &mut P,
    z: &mut [f64],
    settings: &NewtonSettings,
) -> Result<(NewtonReport, P::Point), ContinuationError> {
    let mut last_step = f64::INFINITY;
    // The last three steps relative to their iterates, the latest first.
    let mut relative = [f64::INFINITY; 3];
    let mut residual = f64::INFINITY;
    // The step, in storage kept between iterations.
    let mut dz = Vec::new();
    let failure = |iterations, residual, step, reason| Failure {
        iterations,
        residual,
        step,
        reason,
    };
    for it in 0..=settings.max_iter {
        let point = match problem.evaluate(z) {
            Ok(point) => point,
            Err(cause) => {
                let f = failure(it, residual, last_step, NewtonFailure::SingularJacobian);
                return Err(problem.error(f, Some(cause)));
            }
        };
        residual = point.residual_norm();
        if !(residual.is_finite() && point.residual().iter().all(|v| v.is_finite())) {
            let f = failure(it, residual, last_step, NewtonFailure::NonFinite);
            return Err(problem.error(f, None));
        }
        let z_max = max_norm(z);
        let tol = settings.step_tol;
        let small_residual = residual <= point.residual_bound(settings.residual_tol, z_max);
        let report = NewtonReport {
            iterations: it,
            residual,
            step: last_step,
        };
        let [last, previous, earlier] = relative;
        if small_residual && last <= tol {
            return Ok((report, point));
        }
        // At the iteration limit a floor is read as one: no iteration is left
        // to tell a step back from it.
        let fell_fast = it < settings.max_iter && earlier.is_finite() && previous < 1e-3 * earlier;
        if small_residual && last <= 1e3 * tol && last > 0.5 * previous && !fell_fast {
            match problem.stall() {
                Stall::Iterate => {}
                Stall::Converged => return Ok((report, point)),
                Stall::Fail => {
                    let f = failure(it, residual, last_step, NewtonFailure::Stalled);
                    return Err(problem.error(f, None));
                }
            }
        }
        if it == settings.max_iter {
            break;
        }
        match problem.newton_step_into(&point, &mut dz) {
            Ok(()) => {}
            Err(cause) => {
                let f = failure(it, residual, last_step, NewtonFailure::SingularJacobian);
                return Err(problem.error(f, Some(cause)));
            }
        };
        let step = max_norm(&dz);
        if !step.is_finite() {
            let f = failure(it, residual, step, NewtonFailure::SingularJacobian);
            return Err(problem.error(f, None));
        }
        last_step = step;
        problem.recycle(point);
        problem.update(z, &dz);
        relative = [problem.relative_step(&dz, z), relative[0], relative[1]];
    }
    let f = failure(
        settings.max_iter,
        residual,
        last_step,
        NewtonFailure::MaxIterations,
    );
    Err(problem.error(f, None))
}

/// A dense system linearized at a point: `G(z)`, `DG(z)` and the backward
/// error scale `|DG|` (max row sum).
pub struct DensePoint {
    /// The residual `G(z)`.
    pub g: DVector<f64>,
    /// The Jacobian `DG(z)`.
    pub dg: DMatrix<f64>,
    dg_norm: f64,
}

impl Linearized for DensePoint {
    fn residual(&self) -> &[f64] {
        self.g.as_slice()
    }

    /// The backward-error bound `residual_tol (1 + |DG| |z|)`: rounding in
    /// `G` is about `eps |DG| |z|`.
    fn residual_bound(&self, residual_tol: f64, z_max: f64) -> f64 {
        residual_tol * (1.0 + self.dg_norm * z_max)
    }
}

/// A square dense system given by a closure that writes `G(z)` and `DG(z)`.
struct Dense<'c, F> {
    system: F,
    z: DVector<f64>,
    context: &'c str,
    /// With [`solve_scaled`], per unknown, the absolute part of its step
    /// tolerance: `min(1, |z_i|)` at the starting point (1 where that is
    /// zero); `None`: the max norm.
    floor: Option<Vec<f64>>,
}

impl<F> NewtonProblem for Dense<'_, F>
where
    F: FnMut(&DVector<f64>, &mut DVector<f64>, &mut DMatrix<f64>),
{
    type Point = DensePoint;

    fn evaluate(&mut self, z: &[f64]) -> Result<DensePoint, ContinuationError> {
        let n = z.len();
        self.z.copy_from_slice(z);
        let (mut g, mut dg) = (DVector::zeros(n), DMatrix::zeros(n, n));
        (self.system)(&self.z, &mut g, &mut dg);
        let dg_norm = dg
            .row_iter()
            .map(|r| r.iter().fold(0.0, |acc, v| acc + v.abs()))
            .fold(0.0, f64::max);
        Ok(DensePoint { g, dg, dg_norm })
    }

    /// With [`solve_scaled`] component by component,
    /// `max_i |dz_i| / (|z_i| + floor_i)`, relative to each unknown's own
    /// size (down to its size at the start, or 1); else the max norm.
    fn relative_step(&self, dz: &[f64], z: &[f64]) -> f64 {
        match &self.floor {
            Some(floor) => dz
                .iter()
                .zip(z)
                .zip(floor)
                .map(|((d, v), f)| d.abs() / (v.abs() + f))
                .fold(0.0, f64::max),
            None => max_norm(dz) / (1.0 + max_norm(z)),
        }
    }

    /// With [`solve_scaled`], a step that no longer shrinks within 1e3 of
    /// the tolerance is the rounding floor of an unknown judged relative to
    /// its own size.
    fn stall(&self) -> Stall {
        match self.floor {
            Some(_) => Stall::Converged,
            None => Stall::Iterate,
        }
    }

    /// With [`solve_scaled`], solved in the unknowns' own scales, `DG C y =
    /// G`, `dz = C y` with `C = diag(|z_i| + floor_i)` (the scales of
    /// [`Self::relative_step`]), the rows of `DG C` equilibrated: the small
    /// unknowns' steps then come out accurate relative to their size, as the
    /// step test asks, also where others are many orders larger.
    fn newton_step(&mut self, point: &DensePoint) -> Result<Vec<f64>, ContinuationError> {
        let Some(floor) = &self.floor else {
            let dz = point.dg.clone().lu().solve(&point.g);
            return dz
                .map(|dz| dz.as_slice().to_vec())
                .ok_or(ContinuationError::Singular);
        };
        let scale: Vec<f64> = self.z.iter().zip(floor).map(|(v, f)| v.abs() + f).collect();
        let mut a = point.dg.clone();
        for (j, c) in scale.iter().enumerate() {
            a.column_mut(j).iter_mut().for_each(|v| *v *= c);
        }
        let rows = crate::linalg::row_equilibration(&a);
        let mut g = point.g.clone();
        for (i, r) in rows.iter().enumerate() {
            a.row_mut(i).iter_mut().for_each(|v| *v *= r);
            g[i] *= r;
        }
        let y = a.lu().solve(&g).ok_or(ContinuationError::Singular)?;
        Ok(y.iter().zip(&scale).map(|(y, c)| y * c).collect())
    }

    fn error(&self, failure: Failure, _cause: Option<ContinuationError>) -> ContinuationError {
        let hint = match failure.reason {
            NewtonFailure::MaxIterations | NewtonFailure::Stalled => {
                "reduce the step size or improve the initial guess"
            }
            NewtonFailure::SingularJacobian => {
                "the point may be a bifurcation of higher codimension; perturb a parameter"
            }
            NewtonFailure::NonFinite => "the iterate left the model's domain; reduce the step size",
        };
        failure.error(self.context.to_string(), hint)
    }
}

/// Newton's method on a square dense system from `z`, which is overwritten
/// with the solution; also returns the system linearized there.
///
/// `system(z, g, dg)` writes the residual into `g` and the Jacobian into `dg`.
pub fn solve_dense<F>(
    z: &mut DVector<f64>,
    settings: &NewtonSettings,
    context: &str,
    system: F,
) -> Result<(NewtonReport, DensePoint), ContinuationError>
where
    F: FnMut(&DVector<f64>, &mut DVector<f64>, &mut DMatrix<f64>),
{
    run_dense(z, settings, context, system, None)
}

/// Newton's method on the [`Dense`] problem of `system` from `z`, with the
/// per-unknown step floors `floor` of [`solve_scaled`] or the max norm.
fn run_dense<F>(
    z: &mut DVector<f64>,
    settings: &NewtonSettings,
    context: &str,
    system: F,
    floor: Option<Vec<f64>>,
) -> Result<(NewtonReport, DensePoint), ContinuationError>
where
    F: FnMut(&DVector<f64>, &mut DVector<f64>, &mut DMatrix<f64>),
{
    let mut dense = Dense {
        system,
        z: z.clone(),
        context,
        floor,
    };
    iterate(&mut dense, z.as_mut_slice(), settings)
}

/// [`solve`] with each unknown judged against its own size: converged when
/// `max_i |dz_i| / (|z_i| + min(1, |z0_i|)) <= step_tol` (`z0` the start), the
/// steps solved in those scales, a step stalled within 1e3 of the tolerance
/// taken as converged. For locating a point to rounding in every unknown
/// where they differ by many orders of magnitude (at nu = 1e-7 the age
/// `phi = 1/nu` is 1e7 and the frequency 1e-7: judged against the age, the
/// frequency was left 4e-3 off). Continuation correctors keep the max norm:
/// an unknown below its own rounding there (a step of `phi = 1e12` under
/// its last place) converges only linearly in the others.
pub fn solve_scaled<F>(
    z: &mut DVector<f64>,
    settings: &NewtonSettings,
    context: &str,
    system: F,
) -> Result<NewtonReport, ContinuationError>
where
    F: FnMut(&DVector<f64>, &mut DVector<f64>, &mut DMatrix<f64>),
{
    let floor = z
        .iter()
        .map(|v| if *v == 0.0 { 1.0 } else { v.abs().min(1.0) })
        .collect();
    run_dense(z, settings, context, system, Some(floor)).map(|(report, _)| report)
}

/// Runs Newton's method from `z`, which is overwritten with the solution
/// ([`solve_dense`] without the linearization).
///
/// `system(z, g, dg)` writes the residual into `g` and the Jacobian into `dg`.
pub fn solve<F>(
    z: &mut DVector<f64>,
    settings: &NewtonSettings,
    context: &str,
    system: F,
) -> Result<NewtonReport, ContinuationError>
where
    F: FnMut(&DVector<f64>, &mut DVector<f64>, &mut DMatrix<f64>),
{
    solve_dense(z, settings, context, system).map(|(report, _)| report)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn max_norm_in_lanes_is_the_running_maximum() {
        // Lengths across the lanes and the remainder; NaN (passed over),
        // infinities, signed zeros and subnormals, the largest at every place.
        let pool = [
            0.5,
            -3.0,
            f64::NAN,
            -0.0,
            1e-310,
            f64::INFINITY,
            -7.25,
            2.0,
            f64::NEG_INFINITY,
            1e300,
        ];
        for len in 0..=21 {
            for shift in 0..pool.len() {
                let a: Vec<f64> = (0..len)
                    .map(|i| pool[(i * 7 + shift) % pool.len()] * (1.0 + i as f64))
                    .collect();
                let running = a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                assert_eq!(max_norm(&a).to_bits(), running.to_bits(), "{a:?}");
                let finite: Vec<f64> = a.iter().copied().filter(|v| v.is_finite()).collect();
                let running = finite.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                assert_eq!(max_norm(&finite).to_bits(), running.to_bits(), "{finite:?}");
            }
        }
    }

    #[test]
    fn converges_quadratically_on_a_scalar_root() {
        let mut z = DVector::from_element(1, 1.0);
        let rep = solve(&mut z, &NewtonSettings::default(), "", |z, g, dg| {
            g[0] = z[0] * z[0] - 2.0;
            dg[(0, 0)] = 2.0 * z[0];
        })
        .unwrap();
        assert!((z[0] - 2f64.sqrt()).abs() < 1e-15);
        assert!(rep.iterations <= 7);
    }

    /// A residual at its floor (reported as 0) and a step that no longer
    /// shrinks (`1e-9`, above the step tolerance but within `1e3` of it).
    struct Floor(Stall);

    struct Zero;

    impl Linearized for Zero {
        fn residual(&self) -> &[f64] {
            &[0.0]
        }
    }

    impl NewtonProblem for Floor {
        type Point = Zero;
        fn evaluate(&mut self, _z: &[f64]) -> Result<Zero, ContinuationError> {
            Ok(Zero)
        }
        fn newton_step(&mut self, _point: &Zero) -> Result<Vec<f64>, ContinuationError> {
            Ok(vec![1e-9])
        }
        fn stall(&self) -> Stall {
            self.0
        }
        fn error(&self, failure: Failure, _cause: Option<ContinuationError>) -> ContinuationError {
            failure.error(String::new(), "")
        }
    }

    #[test]
    fn a_stalled_step_converges_fails_or_iterates_by_the_stall_rule() {
        let settings = NewtonSettings::default();
        let run = |stall| iterate(&mut Floor(stall), &mut [1.0], &settings);
        let (report, _) = run(Stall::Converged).unwrap();
        assert_eq!((report.iterations, report.step), (2, 1e-9));
        let reason = |stall| match run(stall) {
            Err(ContinuationError::Newton {
                reason, iterations, ..
            }) => (reason, iterations),
            other => panic!("{:?}", other.map(|(r, _)| r)),
        };
        assert_eq!(reason(Stall::Fail), (NewtonFailure::Stalled, 2));
        assert_eq!(
            reason(Stall::Iterate),
            (NewtonFailure::MaxIterations, settings.max_iter)
        );
    }

    /// Newton steps given in turn (a residual at its floor throughout).
    struct Scripted(Vec<f64>);

    impl NewtonProblem for Scripted {
        type Point = Zero;
        fn evaluate(&mut self, _z: &[f64]) -> Result<Zero, ContinuationError> {
            Ok(Zero)
        }
        fn newton_step(&mut self, _point: &Zero) -> Result<Vec<f64>, ContinuationError> {
            Ok(vec![self.0.remove(0)])
        }
        fn relative_step(&self, dz: &[f64], _z: &[f64]) -> f64 {
            dz[0]
        }
        fn stall(&self) -> Stall {
            Stall::Fail
        }
        fn error(&self, failure: Failure, _cause: Option<ContinuationError>) -> ContinuationError {
            failure.error(String::new(), "")
        }
    }

    /// A step back right after a fast fall is not a floor (the fold-of-cycles
    /// system's steps on a stiff orbit); after a slow one it is.
    #[test]
    fn a_step_back_after_a_fast_fall_is_not_a_stall() {
        // The fold-of-cycles corrector's tolerance: a floor within 1e-7.
        let settings = NewtonSettings {
            step_tol: 1e-10,
            residual_tol: 1e-9,
            max_iter: 8,
        };
        let steps = vec![8e-4, 2.5e-8, 7.7e-8, 3e-12];
        let (report, _) = iterate(&mut Scripted(steps), &mut [1.0], &settings).unwrap();
        assert_eq!((report.iterations, report.step), (4, 3e-12));
        let stalled = |steps: Vec<f64>, settings: &NewtonSettings| match iterate(
            &mut Scripted(steps),
            &mut [1.0],
            settings,
        ) {
            Err(ContinuationError::Newton {
                reason, iterations, ..
            }) => (reason, iterations),
            other => panic!("{:?}", other.map(|(r, _)| r)),
        };
        let slow_fall = vec![1e-6, 2.5e-8, 7.7e-8, 3e-12];
        assert_eq!(stalled(slow_fall, &settings), (NewtonFailure::Stalled, 3));
        // A floor after a fast fall: seen one iteration later.
        let floor = vec![8e-4, 2.5e-8, 7.7e-8, 6e-8, 3e-12];
        assert_eq!(stalled(floor, &settings), (NewtonFailure::Stalled, 4));
        // The step back at the iteration limit: a floor, not the limit.
        let at_limit = NewtonSettings {
            max_iter: 3,
            ..settings
        };
        let fast_fall = vec![8e-4, 2.5e-8, 7.7e-8, 3e-12];
        assert_eq!(stalled(fast_fall, &at_limit), (NewtonFailure::Stalled, 3));
    }

    #[test]
    fn reports_a_singular_jacobian() {
        let mut z = DVector::from_element(1, 0.0);
        let err = solve(
            &mut z,
            &NewtonSettings::default(),
            " at test",
            |z, g, dg| {
                g[0] = z[0] * z[0] + 1.0;
                dg[(0, 0)] = 2.0 * z[0];
            },
        )
        .unwrap_err();
        assert!(matches!(
            err,
            ContinuationError::Newton {
                reason: NewtonFailure::SingularJacobian,
                ..
            }
        ));
    }
}
