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

use super::adapt::equidistribute;
use super::collocation::{Collocation, Linearization};
use super::cycle::Cycle;
use crate::error::ContinuationError;
use crate::linalg::SparseLu;
use crate::newton::{NewtonReport, NewtonSettings};
use crate::system::{
    jacobian, param_derivative, second_derivative_into, JointDirection, VectorField,
};
use faer::sparse::Triplet;

/// Triplets of the collocation and phase rows on `(u, T, p_k)` (columns
/// `0..nn`, `nn`, `nn + 1`).
fn jacobian_triplets(
    lin: &Linearization,
    n: usize,
    nodes: &dyn Fn(usize, usize) -> usize,
) -> Vec<Triplet<usize, usize, f64>> {
    let mn = lin.local[0].nrows();
    let m = mn / n;
    let nn = lin.phase.len();
    let mut t = Vec::with_capacity(lin.local.len() * mn * ((m + 1) * n + 2) + nn);
    for (i, block) in lin.local.iter().enumerate() {
        for r in 0..mn {
            let row = i * mn + r;
            for l in 0..=m {
                let col0 = nodes(i, l) * n;
                for c in 0..n {
                    t.push(Triplet::new(row, col0 + c, block[(r, l * n + c)]));
                }
            }
            t.push(Triplet::new(row, nn, block[(r, (m + 1) * n)]));
            t.push(Triplet::new(row, nn + 1, block[(r, (m + 1) * n + 1)]));
        }
    }
    t.extend(
        lin.phase
            .iter()
            .enumerate()
            .filter(|(_, v)| **v != 0.0)
            .map(|(c, v)| Triplet::new(nn, c, *v)),
    );
    t
}

/// The gradient of `phi = psi^T A v` over `(u, T, p1[, p2])` and, with a
/// second parameter `k2`, the column `dF/dp2`. On the collocation row of
/// point `x` (interval length `h`), `(A v) = v' - h T Df(x) v_x - h v_T f(x)`.
fn adjoint_gradient<S: VectorField>(
    coll: &Collocation<S>,
    z: &[f64],
    v: &[f64],
    psi: &[f64],
    k2: Option<usize>,
) -> (Vec<f64>, Vec<f64>) {
    let sys = coll.sys;
    let n = sys.dim();
    let m = coll.mesh.degree;
    let nn = coll.mesh.n_nodes() * n;
    let (period, v_t) = (z[nn], v[nn]);
    let mut p = coll.p.clone();
    p[coll.k] = z[nn + 1];
    let mut grad = vec![0.0; nn + 2 + usize::from(k2.is_some())];
    let mut fp2 = vec![0.0; nn + 1];
    let (mut x, mut vx, mut unit, mut pdir) =
        (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; p.len()]);
    let mut d2 = vec![0.0; n];
    for i in 0..coll.mesh.ntst() {
        let h = coll.mesh.t[i + 1] - coll.mesh.t[i];
        for kk in 0..m {
            x.fill(0.0);
            vx.fill(0.0);
            for l in 0..=m {
                let g = coll.mesh.node(i, l);
                for j in 0..n {
                    x[j] += coll.mesh.basis[kk][l] * z[g * n + j];
                    vx[j] += coll.mesh.basis[kk][l] * v[g * n + j];
                }
            }
            let row = (i * m + kk) * n;
            let psi_k = &psi[row..row + n];
            let jac = jacobian(sys, &x, &p);
            let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(a, b)| a * b).sum::<f64>();
            // d phi / d x_j, spread to the interval's nodes by the basis.
            for j in 0..n {
                unit.fill(0.0);
                unit[j] = 1.0;
                second_derivative_into(
                    sys,
                    &x,
                    &p,
                    JointDirection::state(&vx),
                    JointDirection::state(&unit),
                    &mut d2,
                );
                let jt_psi: f64 = (0..n).map(|r| jac[(r, j)] * psi_k[r]).sum();
                let dphi = -h * period * dot(psi_k, &d2) - h * v_t * jt_psi;
                for l in 0..=m {
                    grad[coll.mesh.node(i, l) * n + j] += coll.mesh.basis[kk][l] * dphi;
                }
            }
            let jv: Vec<f64> = (0..n)
                .map(|r| (0..n).map(|c| jac[(r, c)] * vx[c]).sum())
                .collect();
            grad[nn] -= h * dot(psi_k, &jv);
            let params = std::iter::once((coll.k, nn + 1)).chain(k2.map(|k| (k, nn + 2)));
            for (k, col) in params {
                pdir.fill(0.0);
                pdir[k] = 1.0;
                second_derivative_into(
                    sys,
                    &x,
                    &p,
                    JointDirection::state(&vx),
                    JointDirection { x: &[], p: &pdir },
                    &mut d2,
                );
                let fp = param_derivative(sys, &x, &p, k);
                grad[col] -= h * period * dot(psi_k, &d2) + h * v_t * dot(psi_k, fp.as_slice());
                if Some(k) == k2 {
                    for j in 0..n {
                        fp2[row + j] = -h * period * fp[j];
                    }
                }
            }
        }
    }
    (grad, fp2)
}

/// The minimally augmented system on one mesh, with its bordering vectors.
struct Augmented<'a, S: VectorField> {
    coll: Collocation<'a, S>,
    /// Second free parameter (curves of folds), read from the unknowns.
    k2: Option<usize>,
    b: Vec<f64>,
    c: Vec<f64>,
}

/// `F` and `g` at a point, the Newton matrix rows (triplets) and the null vectors.
struct Evaluation {
    residual: Vec<f64>,
    triplets: Vec<Triplet<usize, usize, f64>>,
    v: Vec<f64>,
    psi: Vec<f64>,
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
        let coll = Collocation::new(sys, orbit, k1);
        let nn = coll.mesh.n_nodes() * sys.dim();
        let mut y = coll.unknowns(orbit);
        if let Some(k) = k2 {
            y.push(orbit.p[k]);
        }
        let lin = coll.linearize(&y[..nn + 2]);
        let b: Vec<f64> = jacobian_triplets(&lin, sys.dim(), &|i, l| coll.mesh.node(i, l))
            .iter()
            .filter(|t| t.col == nn + 1)
            .fold(vec![0.0; nn + 1], |mut b, t| {
                b[t.row] += t.val;
                b
            });
        let mut aug = Augmented {
            coll,
            k2,
            b,
            c: vec![1.0; nn + 1],
        };
        for _ in 0..2 {
            let e = aug.evaluate(&y)?;
            aug.update_borders(&e);
        }
        Ok(aug)
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

    /// `(F, g)` at `y = (u, T, p1[, p2])`, the Jacobian rows of both, and `v`, `psi`.
    fn evaluate(&mut self, y: &[f64]) -> Result<Evaluation, ContinuationError> {
        let n = self.coll.sys.dim();
        let nn = self.nn();
        if let Some(k) = self.k2 {
            self.coll.p[k] = y[nn + 2];
        }
        let z = &y[..nn + 2];
        let lin = self.coll.linearize(z);
        let mesh = &self.coll.mesh;
        let mut triplets = jacobian_triplets(&lin, n, &|i, l| mesh.node(i, l));
        let mut bordered: Vec<_> = triplets.iter().filter(|t| t.col <= nn).copied().collect();
        bordered.extend(
            self.b
                .iter()
                .enumerate()
                .map(|(r, v)| Triplet::new(r, nn + 1, *v)),
        );
        bordered.extend(
            self.c
                .iter()
                .enumerate()
                .map(|(c, v)| Triplet::new(nn + 1, c, *v)),
        );
        let lu = SparseLu::new(nn + 2, &bordered)?;
        let mut e = vec![0.0; nn + 2];
        e[nn + 1] = 1.0;
        let vg = lu.solve(&e)?;
        let psi = lu.solve_transpose(&e)?;
        let (v, psi) = (vg[..nn + 1].to_vec(), psi[..nn + 1].to_vec());
        let (grad, fp2) = adjoint_gradient(&self.coll, z, &v, &psi, self.k2);
        if self.k2.is_some() {
            triplets.extend(
                fp2.iter()
                    .enumerate()
                    .filter(|(_, v)| **v != 0.0)
                    .map(|(r, v)| Triplet::new(r, nn + 2, *v)),
            );
        }
        // g's row: dg = -grad(phi).
        triplets.extend(
            grad.iter()
                .enumerate()
                .map(|(c, v)| Triplet::new(nn + 1, c, -v)),
        );
        let mut residual = lin.residual;
        residual.push(vg[nn + 1]);
        Ok(Evaluation {
            residual,
            triplets,
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

    /// Newton's method on `(F, g)` plus, for curves, the linear equation
    /// `<row, y - anchor> = 0`.
    fn newton(
        &mut self,
        y: &mut [f64],
        extra: Option<(&[f64], &[f64])>,
        settings: &NewtonSettings,
    ) -> Result<(NewtonReport, Evaluation), ContinuationError> {
        let dim = y.len();
        let (mut last_step, mut residual) = (f64::INFINITY, f64::INFINITY);
        for it in 0..=settings.max_iter {
            let mut e = self.evaluate(y)?;
            if let Some((row, anchor)) = extra {
                let r: f64 = (0..dim).map(|i| row[i] * (y[i] - anchor[i])).sum();
                e.residual.push(r);
                e.triplets.extend(
                    row.iter()
                        .enumerate()
                        .filter(|(_, v)| **v != 0.0)
                        .map(|(c, v)| Triplet::new(dim - 1, c, *v)),
                );
            }
            // The test function g is judged by the step it causes (its own
            // scale is arbitrary: set by the bordering vectors); F by its residual.
            let nn = self.nn();
            residual = e.residual[..=nn]
                .iter()
                .chain(&e.residual[nn + 2..])
                .fold(0.0f64, |a, v| a.max(v.abs()));
            let ymax = y.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            if !(residual.is_finite() && e.residual.iter().all(|v| v.is_finite())) {
                break;
            }
            if last_step <= settings.step_tol * (1.0 + ymax)
                && residual <= settings.residual_tol * (1.0 + ymax)
            {
                return Ok((
                    NewtonReport {
                        iterations: it,
                        residual,
                        step: last_step,
                    },
                    e,
                ));
            }
            if it == settings.max_iter {
                break;
            }
            let dy = SparseLu::new(dim, &e.triplets)?.solve(&e.residual)?;
            last_step = dy.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            y.iter_mut().zip(&dy).for_each(|(a, d)| *a -= d);
        }
        Err(ContinuationError::Newton {
            context: " solving the fold-of-cycles system".into(),
            iterations: settings.max_iter,
            residual,
            step: last_step,
            hint: "start closer to the fold (a cycle of the branch next to it)",
            reason: crate::error::NewtonFailure::MaxIterations,
        })
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
    let (newton, _) = aug.newton(&mut y, None, settings)?;
    Ok(LpcPoint {
        cycle: aug.cycle(&y),
        newton,
    })
}

/// Settings of a curve of folds of cycles.
#[derive(Clone, Debug)]
pub struct LpcCurveSettings {
    /// Initial, smallest and largest step (relative in `T`, `p1`, `p2`).
    pub ds: f64,
    pub ds_min: f64,
    pub ds_max: f64,
    pub max_steps: usize,
    /// Bounds of the second parameter; the curve stops on them.
    pub p2_min: f64,
    pub p2_max: f64,
    /// Smallest scales of the parameters in the arclength weights.
    pub param_floor: [f64; 2],
    /// The curve stops where the orbit's amplitude (largest range of a
    /// component) falls below this: it ends on a Bautin point there.
    pub min_amplitude: f64,
    pub corrector: NewtonSettings,
}

impl Default for LpcCurveSettings {
    fn default() -> Self {
        LpcCurveSettings {
            ds: 1e-2,
            ds_min: 1e-8,
            ds_max: 0.1,
            max_steps: 200,
            p2_min: f64::NEG_INFINITY,
            p2_max: f64::INFINITY,
            param_floor: [1e-6, 1e-6],
            min_amplitude: 1e-4,
            corrector: NewtonSettings {
                step_tol: 1e-10,
                residual_tol: 1e-9,
                max_iter: 8,
            },
        }
    }
}

/// A curve of folds of cycles in `(p1, p2)`, traced by pseudo-arclength
/// from a fold; each item is the next fold (the first is the start).
pub struct LpcCurve<'a, S: VectorField> {
    sys: &'a S,
    k1: usize,
    k2: usize,
    aug: Augmented<'a, S>,
    y: Vec<f64>,
    tangent: Vec<f64>,
    ds: f64,
    settings: LpcCurveSettings,
    steps: usize,
    done: bool,
}

impl<'a, S: VectorField> LpcCurve<'a, S> {
    /// Starts at the fold `lpc` (in `k1`, at the value of `k2` it carries),
    /// going towards increasing `p2` when `direction > 0`.
    pub fn new(
        sys: &'a S,
        lpc: &Cycle,
        (k1, k2): (usize, usize),
        direction: f64,
        settings: LpcCurveSettings,
    ) -> Result<Self, ContinuationError> {
        let aug = Augmented::new(sys, lpc, k1, Some(k2))?;
        let mut y = aug.coll.unknowns(lpc);
        y.push(lpc.p[k2]);
        let mut seed = vec![0.0; y.len()];
        *seed.last_mut().unwrap_or(&mut 0.0) = direction.signum();
        let mut curve = LpcCurve {
            sys,
            k1,
            k2,
            aug,
            y,
            tangent: seed,
            ds: settings.ds,
            settings,
            steps: 0,
            done: false,
        };
        curve.tangent = curve.tangent_at(&curve.y.clone(), &curve.tangent.clone())?;
        Ok(curve)
    }

    /// Arclength weights: `1/N` on the orbit, relative on `T`, `p1`, `p2`.
    fn weights(&self) -> Vec<f64> {
        let d = self.y.len();
        let nn = d - 3;
        let rel = |v: f64, floor: f64| 1.0 / v.abs().max(floor).powi(2);
        (0..d)
            .map(|i| match i.checked_sub(nn) {
                None => 1.0 / nn as f64,
                Some(0) => rel(self.y[i], f64::MIN_POSITIVE.sqrt()),
                Some(1) => rel(self.y[i], self.settings.param_floor[0]),
                Some(_) => rel(self.y[i], self.settings.param_floor[1]),
            })
            .collect()
    }

    /// The unit tangent at `y`, oriented along `reference`.
    fn tangent_at(&mut self, y: &[f64], reference: &[f64]) -> Result<Vec<f64>, ContinuationError> {
        let w = self.weights();
        let d = y.len();
        let mut e = self.aug.evaluate(y)?;
        e.triplets.extend(
            (0..d)
                .filter(|&i| reference[i] != 0.0)
                .map(|i| Triplet::new(d - 1, i, w[i] * reference[i])),
        );
        let mut rhs = vec![0.0; d];
        rhs[d - 1] = 1.0;
        let t = SparseLu::new(d, &e.triplets)?.solve(&rhs)?;
        let norm = (0..d).map(|i| w[i] * t[i] * t[i]).sum::<f64>().sqrt();
        Ok(t.iter().map(|v| v / norm).collect())
    }

    /// Re-equidistributes the mesh (same size) and rebuilds the bordering vectors.
    fn adapt(&mut self) -> Result<(), ContinuationError> {
        let orbit = self.aug.cycle(&self.y);
        let new = equidistribute(&orbit, orbit.mesh.ntst());
        let nn = orbit.u.len();
        let dir = Cycle {
            u: self.tangent[..nn].to_vec(),
            ..orbit.clone()
        }
        .remesh(new.mesh.clone());
        self.aug = Augmented::new(self.sys, &new, self.k1, Some(self.k2))?;
        self.y = self.aug.coll.unknowns(&new);
        self.y.push(new.p[self.k2]);
        let mut t = dir.u;
        t.extend_from_slice(&self.tangent[nn..]);
        self.tangent = t;
        Ok(())
    }

    fn step(&mut self) -> Result<LpcPoint, ContinuationError> {
        if self.steps.is_multiple_of(5) {
            self.adapt()?;
        }
        let w = self.weights();
        let d = self.y.len();
        loop {
            let pred: Vec<f64> = (0..d)
                .map(|i| self.y[i] + self.ds * self.tangent[i])
                .collect();
            let row: Vec<f64> = (0..d).map(|i| w[i] * self.tangent[i]).collect();
            let mut y = pred.clone();
            let attempt = self
                .aug
                .newton(&mut y, Some((&row, &pred)), &self.settings.corrector);
            if let Ok((rep, e)) = attempt {
                let reference = self.tangent.clone();
                let t = self.tangent_at(&y, &reference);
                if let Some(t) = t
                    .ok()
                    .filter(|t| (0..d).map(|i| w[i] * t[i] * reference[i]).sum::<f64>() > 0.8)
                {
                    self.aug.update_borders(&e);
                    self.y = y;
                    self.tangent = t;
                    if rep.iterations <= 3 {
                        self.ds = (self.ds * 1.3).min(self.settings.ds_max);
                    }
                    return Ok(LpcPoint {
                        cycle: self.aug.cycle(&self.y),
                        newton: rep,
                    });
                }
            }
            self.ds *= 0.5;
            if self.ds < self.settings.ds_min {
                return Err(ContinuationError::StepTooSmall {
                    param_name: format!("p[{}] along the fold of cycles", self.k2),
                    param: self.y[d - 1],
                    ds: self.ds,
                    ds_min: self.settings.ds_min,
                    cause: "the fold-of-cycles system did not converge".into(),
                });
            }
        }
    }
}

impl<S: VectorField> Iterator for LpcCurve<'_, S> {
    type Item = Result<LpcPoint, ContinuationError>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.done {
            return None;
        }
        let result = if self.steps == 0 {
            Ok(LpcPoint {
                cycle: self.aug.cycle(&self.y),
                newton: NewtonReport {
                    iterations: 0,
                    residual: 0.0,
                    step: 0.0,
                },
            })
        } else {
            self.step()
        };
        self.steps += 1;
        match &result {
            Ok(pt) => {
                let p2 = pt.cycle.p[self.k2];
                let amplitude = (0..pt.cycle.n)
                    .map(|j| {
                        let (lo, hi) = pt.cycle.range(j);
                        hi - lo
                    })
                    .fold(0.0, f64::max);
                if self.steps > self.settings.max_steps
                    || p2 <= self.settings.p2_min
                    || p2 >= self.settings.p2_max
                    || amplitude < self.settings.min_amplitude
                {
                    self.done = true;
                }
            }
            Err(_) => self.done = true,
        }
        Some(result)
    }
}
