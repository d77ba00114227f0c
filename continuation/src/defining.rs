//! Defining systems `G(z) = 0` of equilibria, folds and Hopf points, with
//! exact Jacobians. Each frees `r` parameters: with as many unknowns as
//! equations (`r` = codimension) Newton locates a point; with one unknown
//! more, pseudo-arclength continuation ([`crate::arclength`]) traces a curve.
//!
//! | system | unknowns `z` | equations |
//! |---|---|---|
//! | [`EquilibriumSystem`] | `(x, p_free)` | `f(x, p) = 0` |
//! | [`FoldSystem`] | `(x, p_free)` | `f = 0`, `g = 0` from `[[J, b], [c^T, 0]] (v, g) = (0, 1)` |
//! | [`HopfSystem`] | `(x, omega, p_free)` | `f = 0`, `Re g = Im g = 0` from `[[J - i omega I, b], [c^H, 0]] (v, g) = (0, 1)` |
//!
//! Minimally augmented systems after Govaerts (2000, §4.3) and Kuznetsov
//! (1998, §10.2); `dg/dz = -w^H (dJ/dz) v` with `w` from the adjoint bordered
//! system and `(dJ/dz) v` a second derivative from hyper-dual numbers.

use crate::error::ContinuationError;
use crate::linalg::{eigenpair_near, solve, solve_complex};
use crate::system::{
    jacobian, param_derivative_into, second_derivative_into, Buf, JointDirection, VectorField,
};
use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;
use smallvec::SmallVec;

/// A system of equations `G(z) = 0` with an exact Jacobian.
pub trait DefiningSystem {
    /// Number of equations.
    fn n_equations(&self) -> usize;
    /// Writes `G(z)` into `g` and `DG(z)` into the first `n_equations` rows of `dg`.
    fn eval(&self, z: &DVector<f64>, g: &mut DVector<f64>, dg: &mut DMatrix<f64>);
    /// Called at every accepted point: refresh auxiliary data (bordering vectors).
    fn accept(&mut self, _z: &DVector<f64>) -> Result<(), ContinuationError> {
        Ok(())
    }
}

/// The parameters of a system with some of them free.
#[derive(Clone, Debug)]
pub struct FreeParams {
    /// The full parameter vector; entries `free` are overwritten from `z`.
    pub base: Vec<f64>,
    /// Indices of the free parameters, in the order they appear in `z`.
    pub free: Vec<usize>,
}

impl FreeParams {
    /// The full parameter vector with the free ones read from `values`.
    pub fn with(&self, values: &[f64]) -> Vec<f64> {
        let mut p = self.base.clone();
        for (&k, &v) in self.free.iter().zip(values) {
            p[k] = v;
        }
        p
    }
}

/// Writes the `f` rows of a defining system: `f(x, p)`, `[J, f_p_free]`
/// (parameter columns starting at `pcol`). Returns `J`.
fn equilibrium_rows<S: VectorField>(
    sys: &S,
    x: &[f64],
    p: &[f64],
    free: &[usize],
    pcol: usize,
    g: &mut DVector<f64>,
    dg: &mut DMatrix<f64>,
) -> DMatrix<f64> {
    let n = x.len();
    let mut jac = DMatrix::zeros(n, n);
    sys.jacobian(x, p, &mut jac);
    sys.rhs(x, p, &mut g.as_mut_slice()[..n]);
    dg.view_mut((0, 0), (n, n)).copy_from(&jac);
    let rows = dg.nrows();
    let data = dg.as_mut_slice();
    for (i, &k) in free.iter().enumerate() {
        let start = (pcol + i) * rows;
        param_derivative_into(sys, x, p, k, &mut data[start..start + n]);
    }
    jac
}

/// `(dJ/dz) v` for one unknown of the joint space: a state coordinate
/// (`state = Some(j)`) or the parameter `param`, written into `re` and `im`
/// (length `n`). Complex `v = vr + i vi` is split into real and imaginary
/// parts (the form is linear in `v`); `vi = None` means a real `v` (then
/// `im` is zero).
#[allow(clippy::too_many_arguments)]
fn jacobian_action_derivative<S: VectorField>(
    sys: &S,
    x: &[f64],
    p: &[f64],
    unknown: Unknown,
    vr: &[f64],
    vi: Option<&[f64]>,
    re: &mut [f64],
    im: &mut [f64],
) {
    let mut ex: Buf<f64> = SmallVec::from_elem(0.0, x.len());
    let mut ep: Buf<f64> = SmallVec::from_elem(0.0, p.len());
    match unknown {
        Unknown::State(j) => ex[j] = 1.0,
        Unknown::Param(k) => ep[k] = 1.0,
    }
    let dir = JointDirection { x: &ex, p: &ep };
    second_derivative_into(sys, x, p, JointDirection::state(vr), dir, re);
    match vi {
        Some(vi) => second_derivative_into(sys, x, p, JointDirection::state(vi), dir, im),
        None => im.fill(0.0),
    }
}

/// Real and imaginary parts of `v` on the stack; the imaginary part is
/// `None` when it vanishes.
fn split_parts(v: &DVector<Complex64>) -> (Buf<f64>, Option<Buf<f64>>) {
    let vr: Buf<f64> = v.iter().map(|c| c.re).collect();
    let vi: Buf<f64> = v.iter().map(|c| c.im).collect();
    let real = vi.iter().all(|&t| t == 0.0);
    (vr, (!real).then_some(vi))
}

/// `a . b`, summed in order (as nalgebra's `dot` does for fewer than 8 entries).
pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).fold(0.0, |acc, (x, y)| acc + x * y)
}

#[derive(Clone, Copy)]
enum Unknown {
    State(usize),
    Param(usize),
}

/// Equilibria `f(x, p) = 0`, `z = (x, p_free)`.
pub struct EquilibriumSystem<'a, S: VectorField> {
    pub sys: &'a S,
    pub params: FreeParams,
}

impl<S: VectorField> DefiningSystem for EquilibriumSystem<'_, S> {
    fn n_equations(&self) -> usize {
        self.sys.dim()
    }
    fn eval(&self, z: &DVector<f64>, g: &mut DVector<f64>, dg: &mut DMatrix<f64>) {
        let n = self.sys.dim();
        let p = self.params.with(&z.as_slice()[n..]);
        equilibrium_rows(
            self.sys,
            &z.as_slice()[..n],
            &p,
            &self.params.free,
            n,
            g,
            dg,
        );
    }
}

/// Folds, `z = (x, p_free)`, by the minimally augmented system.
pub struct FoldSystem<'a, S: VectorField> {
    pub sys: &'a S,
    pub params: FreeParams,
    b: DVector<f64>,
    c: DVector<f64>,
}

impl<'a, S: VectorField> FoldSystem<'a, S> {
    /// Bordering vectors from the null vectors of `J` at the guess `z0`.
    pub fn new(
        sys: &'a S,
        params: FreeParams,
        z0: &DVector<f64>,
    ) -> Result<Self, ContinuationError> {
        let mut fs = FoldSystem {
            sys,
            params,
            b: DVector::zeros(0),
            c: DVector::zeros(0),
        };
        fs.accept(z0)?;
        Ok(fs)
    }
}

impl<S: VectorField> DefiningSystem for FoldSystem<'_, S> {
    fn n_equations(&self) -> usize {
        self.sys.dim() + 1
    }
    fn eval(&self, z: &DVector<f64>, g: &mut DVector<f64>, dg: &mut DMatrix<f64>) {
        let n = self.sys.dim();
        let x = &z.as_slice()[..n];
        let p = self.params.with(&z.as_slice()[n..]);
        let jac = equilibrium_rows(self.sys, x, &p, &self.params.free, n, g, dg);
        let mut m = DMatrix::zeros(n + 1, n + 1);
        m.view_mut((0, 0), (n, n)).copy_from(&jac);
        m.view_mut((0, n), (n, 1)).copy_from(&self.b);
        m.view_mut((n, 0), (1, n)).copy_from(&self.c.transpose());
        let e = DVector::from_fn(n + 1, |i, _| if i == n { 1.0 } else { 0.0 });
        let mt = m.transpose();
        let (Ok(vg), Ok(wh)) = (solve(m, &e), solve(mt, &e)) else {
            g[n] = f64::NAN;
            return;
        };
        g[n] = vg[n];
        let v = &vg.as_slice()[..n];
        let w = &wh.as_slice()[..n];
        let unknowns = (0..n)
            .map(Unknown::State)
            .chain(self.params.free.iter().map(|&k| Unknown::Param(k)));
        let mut re: Buf<f64> = SmallVec::from_elem(0.0, n);
        let mut im: Buf<f64> = SmallVec::from_elem(0.0, n);
        for (col, u) in unknowns.enumerate() {
            jacobian_action_derivative(self.sys, x, &p, u, v, None, &mut re, &mut im);
            dg[(n, col)] = -dot(w, &re);
        }
    }
    fn accept(&mut self, z: &DVector<f64>) -> Result<(), ContinuationError> {
        let n = self.sys.dim();
        let p = self.params.with(&z.as_slice()[n..]);
        let j = jacobian(self.sys, &z.as_slice()[..n], &p);
        let zero = Complex64::new(0.0, 0.0);
        self.c = eigenpair_near(&j, zero)?.1.map(|z| z.re);
        self.b = eigenpair_near(&j.transpose(), zero)?.1.map(|z| z.re);
        Ok(())
    }
}

/// Hopf points, `z = (x, omega, p_free)`, by the minimally augmented system.
pub struct HopfSystem<'a, S: VectorField> {
    pub sys: &'a S,
    pub params: FreeParams,
    b: DVector<Complex64>,
    c: DVector<Complex64>,
}

impl<'a, S: VectorField> HopfSystem<'a, S> {
    /// Bordering vectors from the eigenvectors of `+-i omega` at the guess `z0`.
    pub fn new(
        sys: &'a S,
        params: FreeParams,
        z0: &DVector<f64>,
    ) -> Result<Self, ContinuationError> {
        let mut hs = HopfSystem {
            sys,
            params,
            b: DVector::zeros(0),
            c: DVector::zeros(0),
        };
        hs.accept(z0)?;
        Ok(hs)
    }

    /// Solves `[[J - i omega I, b], [c^H, 0]] (v, g) = (0, 1)` and its adjoint;
    /// returns `(v, w, g)`.
    fn bordered(
        &self,
        jac: &DMatrix<f64>,
        omega: f64,
    ) -> Result<(DVector<Complex64>, DVector<Complex64>, Complex64), ContinuationError> {
        let n = jac.nrows();
        let mut m = DMatrix::<Complex64>::zeros(n + 1, n + 1);
        for i in 0..n {
            for j in 0..n {
                m[(i, j)] = Complex64::from(jac[(i, j)]);
            }
            m[(i, i)] -= Complex64::new(0.0, omega);
            m[(i, n)] = self.b[i];
            m[(n, i)] = self.c[i].conj();
        }
        let e = DVector::from_fn(n + 1, |i, _| {
            Complex64::from(if i == n { 1.0 } else { 0.0 })
        });
        let madj = m.adjoint();
        let vg = solve_complex(m, &e)?;
        let wh = solve_complex(madj, &e)?;
        Ok((
            vg.rows(0, n).into_owned(),
            wh.rows(0, n).into_owned(),
            vg[n],
        ))
    }
}

impl<S: VectorField> DefiningSystem for HopfSystem<'_, S> {
    fn n_equations(&self) -> usize {
        self.sys.dim() + 2
    }
    fn eval(&self, z: &DVector<f64>, g: &mut DVector<f64>, dg: &mut DMatrix<f64>) {
        let n = self.sys.dim();
        let x = &z.as_slice()[..n];
        let omega = z[n];
        let p = self.params.with(&z.as_slice()[n + 1..]);
        let jac = equilibrium_rows(self.sys, x, &p, &self.params.free, n + 1, g, dg);
        dg.view_mut((0, n), (n, 1)).fill(0.0);
        let Ok((v, w, gval)) = self.bordered(&jac, omega) else {
            g[n] = f64::NAN;
            return;
        };
        g[n] = gval.re;
        g[n + 1] = gval.im;
        let state = (0..n).map(|j| (j, Unknown::State(j)));
        let params = self
            .params
            .free
            .iter()
            .enumerate()
            .map(|(i, &k)| (n + 1 + i, Unknown::Param(k)));
        let (vr, vi) = split_parts(&v);
        let mut re: Buf<f64> = SmallVec::from_elem(0.0, n);
        let mut im: Buf<f64> = SmallVec::from_elem(0.0, n);
        for (col, u) in state.chain(params) {
            jacobian_action_derivative(self.sys, x, &p, u, &vr, vi.as_deref(), &mut re, &mut im);
            // -w^H d, summed in order (as nalgebra's `dotc` does for n < 8).
            let mut acc = Complex64::new(0.0, 0.0);
            for i in 0..n {
                acc += w[i].conj() * Complex64::new(re[i], im[i]);
            }
            let dgz = -acc;
            dg[(n, col)] = dgz.re;
            dg[(n + 1, col)] = dgz.im;
        }
        let dgw = Complex64::i() * w.dotc(&v);
        dg[(n, n)] = dgw.re;
        dg[(n + 1, n)] = dgw.im;
    }
    fn accept(&mut self, z: &DVector<f64>) -> Result<(), ContinuationError> {
        let n = self.sys.dim();
        let p = self.params.with(&z.as_slice()[n + 1..]);
        let j = jacobian(self.sys, &z.as_slice()[..n], &p);
        let target = Complex64::new(0.0, z[n].abs());
        let (_, q) = eigenpair_near(&j, target)?;
        let (_, lt) = eigenpair_near(&j.transpose(), target)?;
        self.b = lt.map(|z| z.conj());
        self.c = q;
        Ok(())
    }
}
