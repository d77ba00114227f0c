//! Test functions along a branch of equilibria, and the location of the
//! bifurcations they detect by Newton's method on minimally augmented systems
//! (Govaerts 2000, ch. 4; Kuznetsov 1998, §10.2).
//!
//! * Fold (limit point): `psi_F = dp/ds`, the parameter component of the
//!   tangent. Located on `f(x, p) = 0, g(x, p) = 0`, where `g` is the last
//!   component of the solution of `[[J, b], [c^T, 0]] (v, g) = (0, 1)`.
//! * Hopf: `psi_H = prod_{i<j} (lambda_i + lambda_j)`, the bialternate-product
//!   determinant. It also vanishes at neutral saddles (a real pair `+-lambda`);
//!   those are recognised from the eigenvalues and never reported. Located on
//!   `f(x, p) = 0, Re g = Im g = 0` with unknowns `(x, p, omega)`, where `g`
//!   comes from `[[J - i omega I, b], [c^H, 0]] (v, g) = (0, 1)`.
//!
//! The derivatives of `g` are exact: `dg/dz = -w^H (dJ/dz) v` with `w` from
//! the adjoint bordered system, and `(dJ/dz) v` a second derivative of `f`
//! computed with hyper-dual numbers.

use crate::error::ContinuationError;
use crate::linalg::{eigenpair_near, eigenvalues, solve, solve_complex};
use crate::newton::{self, NewtonReport, NewtonSettings};
use crate::system::{
    eval, jacobian, param_derivative, second_derivative, JointDirection, VectorField,
};
use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

/// What kind of bifurcation an event is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EventKind {
    /// A limit point of the equilibrium branch (one real eigenvalue crosses 0).
    Fold,
    /// A pair `+-i omega` crosses the imaginary axis.
    Hopf {
        /// Angular frequency at the bifurcation (positive).
        omega: f64,
    },
}

impl EventKind {
    /// Short name: `fold` or `hopf`.
    pub fn name(&self) -> &'static str {
        match self {
            EventKind::Fold => "fold",
            EventKind::Hopf { .. } => "hopf",
        }
    }
}

/// A located bifurcation point.
#[derive(Clone, Debug)]
pub struct Event {
    /// Fold or Hopf.
    pub kind: EventKind,
    /// The equilibrium at the bifurcation.
    pub x: Vec<f64>,
    /// The full parameter vector at the bifurcation.
    pub p: Vec<f64>,
    /// Index of the continuation parameter in `p`.
    pub param_index: usize,
    /// Eigenvalues at the bifurcation, by decreasing real part.
    pub eigenvalues: Vec<Complex64>,
    /// How the locating Newton run went.
    pub newton: NewtonReport,
}

impl Event {
    /// Value of the continuation parameter at the bifurcation.
    pub fn param(&self) -> f64 {
        self.p[self.param_index]
    }
}

/// Hopf test function `Re prod_{i<j} (lambda_i + lambda_j)`.
pub fn hopf_test(ev: &[Complex64]) -> f64 {
    let mut prod = Complex64::new(1.0, 0.0);
    for i in 0..ev.len() {
        for j in i + 1..ev.len() {
            prod *= ev[i] + ev[j];
        }
    }
    prod.re
}

/// The eigenvalue pair with the smallest `|lambda_i + lambda_j|`: the pair that
/// makes the Hopf test function vanish. Returns `(lambda_i, lambda_j)`.
pub fn critical_pair(ev: &[Complex64]) -> Option<(Complex64, Complex64)> {
    let mut best: Option<(f64, Complex64, Complex64)> = None;
    for i in 0..ev.len() {
        for j in i + 1..ev.len() {
            let d = (ev[i] + ev[j]).norm();
            if best.is_none_or(|b| d < b.0) {
                best = Some((d, ev[i], ev[j]));
            }
        }
    }
    best.map(|(_, a, b)| (a, b))
}

/// Whether the critical pair is a complex-conjugate pair (a Hopf candidate)
/// rather than a real pair `+-lambda` (a neutral saddle).
pub fn is_complex_pair(pair: (Complex64, Complex64)) -> bool {
    let (a, b) = pair;
    let scale = a.norm().max(b.norm()).max(f64::MIN_POSITIVE);
    a.im.abs() > 1e-8 * scale && (a.im + b.im).abs() <= 1e-6 * scale
}

fn with_param(p: &[f64], k: usize, value: f64) -> Vec<f64> {
    let mut q = p.to_vec();
    q[k] = value;
    q
}

fn context(kind: &str, k: usize, value: f64) -> String {
    format!(" locating the {kind} point (p[{k}] = {value:.10e})")
}

/// Locates a Hopf point from the guess `(x0, p0[k], omega0)` by Newton's
/// method on the minimally augmented system; `p0` holds the other parameters.
pub fn locate_hopf<S: VectorField>(
    sys: &S,
    k: usize,
    x0: &[f64],
    p0: &[f64],
    omega0: f64,
    settings: &NewtonSettings,
) -> Result<Event, ContinuationError> {
    let n = sys.dim();
    let j0 = jacobian(sys, x0, p0);
    let target = Complex64::new(0.0, omega0.abs());
    let (_, q) = eigenpair_near(&j0, target)?;
    let (_, lt) = eigenpair_near(&j0.transpose(), target)?;
    let border_b = lt.map(|z| z.conj());
    let border_c = q;
    let mut z = DVector::zeros(n + 2);
    z.rows_mut(0, n).copy_from_slice(x0);
    z[n] = p0[k];
    z[n + 1] = omega0.abs();
    let report = newton::solve(&mut z, settings, &context("Hopf", k, p0[k]), |z, g, dg| {
        let x = &z.as_slice()[..n];
        let p = with_param(p0, k, z[n]);
        let omega = z[n + 1];
        let jac = jacobian(sys, x, &p);
        g.rows_mut(0, n).copy_from(&eval(sys, x, &p));
        dg.fill(0.0);
        dg.view_mut((0, 0), (n, n)).copy_from(&jac);
        dg.view_mut((0, n), (n, 1))
            .copy_from(&param_derivative(sys, x, &p, k));
        let Ok((v, w, gval)) = complex_bordered(&jac, omega, &border_b, &border_c) else {
            g[n] = f64::NAN;
            return;
        };
        g[n] = gval.re;
        g[n + 1] = gval.im;
        for col in 0..=n {
            let d = jacobian_action_derivative(sys, x, &p, k, col, &v);
            let dgz = -w.dotc(&d);
            dg[(n, col)] = dgz.re;
            dg[(n + 1, col)] = dgz.im;
        }
        let dgw = Complex64::i() * w.dotc(&v);
        dg[(n, n + 1)] = dgw.re;
        dg[(n + 1, n + 1)] = dgw.im;
    })?;
    let x = z.as_slice()[..n].to_vec();
    let p = with_param(p0, k, z[n]);
    let ev = eigenvalues(&jacobian(sys, &x, &p))?;
    Ok(Event {
        kind: EventKind::Hopf {
            omega: z[n + 1].abs(),
        },
        x,
        p,
        param_index: k,
        eigenvalues: ev,
        newton: report,
    })
}

/// Locates a fold (limit point) from the guess `(x0, p0[k])` by Newton's
/// method on the minimally augmented system.
pub fn locate_fold<S: VectorField>(
    sys: &S,
    k: usize,
    x0: &[f64],
    p0: &[f64],
    settings: &NewtonSettings,
) -> Result<Event, ContinuationError> {
    let n = sys.dim();
    let j0 = jacobian(sys, x0, p0);
    let zero = Complex64::new(0.0, 0.0);
    let border_c = eigenpair_near(&j0, zero)?.1.map(|z| z.re);
    let border_b = eigenpair_near(&j0.transpose(), zero)?.1.map(|z| z.re);
    let mut z = DVector::zeros(n + 1);
    z.rows_mut(0, n).copy_from_slice(x0);
    z[n] = p0[k];
    let report = newton::solve(&mut z, settings, &context("fold", k, p0[k]), |z, g, dg| {
        let x = &z.as_slice()[..n];
        let p = with_param(p0, k, z[n]);
        let jac = jacobian(sys, x, &p);
        g.rows_mut(0, n).copy_from(&eval(sys, x, &p));
        dg.view_mut((0, 0), (n, n)).copy_from(&jac);
        dg.view_mut((0, n), (n, 1))
            .copy_from(&param_derivative(sys, x, &p, k));
        let mut m = DMatrix::zeros(n + 1, n + 1);
        m.view_mut((0, 0), (n, n)).copy_from(&jac);
        m.view_mut((0, n), (n, 1)).copy_from(&border_b);
        m.view_mut((n, 0), (1, n)).copy_from(&border_c.transpose());
        let e = DVector::from_fn(n + 1, |i, _| if i == n { 1.0 } else { 0.0 });
        let (Ok(vg), Ok(wh)) = (solve(m.clone(), &e), solve(m.transpose(), &e)) else {
            g[n] = f64::NAN;
            return;
        };
        g[n] = vg[n];
        let v = vg.rows(0, n).map(Complex64::from);
        let w = wh.rows(0, n).into_owned();
        for col in 0..=n {
            let d = jacobian_action_derivative(sys, x, &p, k, col, &v);
            dg[(n, col)] = -w.dot(&d.map(|c| c.re));
        }
    })?;
    let x = z.as_slice()[..n].to_vec();
    let p = with_param(p0, k, z[n]);
    let ev = eigenvalues(&jacobian(sys, &x, &p))?;
    Ok(Event {
        kind: EventKind::Fold,
        x,
        p,
        param_index: k,
        eigenvalues: ev,
        newton: report,
    })
}

/// Solves the complex bordered system `[[J - i omega I, b], [c^H, 0]] (v, g) = (0, 1)`
/// and its adjoint; returns `(v, w, g)`.
fn complex_bordered(
    jac: &DMatrix<f64>,
    omega: f64,
    b: &DVector<Complex64>,
    c: &DVector<Complex64>,
) -> Result<(DVector<Complex64>, DVector<Complex64>, Complex64), ContinuationError> {
    let n = jac.nrows();
    let mut m = DMatrix::<Complex64>::zeros(n + 1, n + 1);
    for i in 0..n {
        for j in 0..n {
            m[(i, j)] = Complex64::from(jac[(i, j)]);
        }
        m[(i, i)] -= Complex64::new(0.0, omega);
        m[(i, n)] = b[i];
        m[(n, i)] = c[i].conj();
    }
    let e = DVector::from_fn(n + 1, |i, _| {
        Complex64::from(if i == n { 1.0 } else { 0.0 })
    });
    let vg = solve_complex(m.clone(), &e)?;
    let wh = solve_complex(m.adjoint(), &e)?;
    Ok((
        vg.rows(0, n).into_owned(),
        wh.rows(0, n).into_owned(),
        vg[n],
    ))
}

/// `(dJ/dz_col) v` for the joint unknown `z = (x, p_k)`: column `col < n` is a
/// state direction, `col = n` the parameter `p_k`. Complex `v` is split into
/// real and imaginary parts (the form is linear in `v`).
fn jacobian_action_derivative<S: VectorField>(
    sys: &S,
    x: &[f64],
    p: &[f64],
    k: usize,
    col: usize,
    v: &DVector<Complex64>,
) -> DVector<Complex64> {
    let n = x.len();
    let mut ex = vec![0.0; n];
    let mut ep = vec![0.0; p.len()];
    if col < n {
        ex[col] = 1.0;
    } else {
        ep[k] = 1.0;
    }
    let dir = JointDirection { x: &ex, p: &ep };
    let vr: Vec<f64> = v.iter().map(|c| c.re).collect();
    let vi: Vec<f64> = v.iter().map(|c| c.im).collect();
    let re = second_derivative(sys, x, p, JointDirection::state(&vr), dir);
    if vi.iter().all(|&t| t == 0.0) {
        return re.map(Complex64::from);
    }
    let im = second_derivative(sys, x, p, JointDirection::state(&vi), dir);
    DVector::from_fn(n, |i, _| Complex64::new(re[i], im[i]))
}
