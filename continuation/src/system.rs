//! The vector-field trait and the exact derivatives derived from it.
//!
//! A system implements [`VectorField::rhs`] once, generic over the scalar
//! type. Evaluated with `f64` it gives `f(x, p)`; with dual numbers it gives
//! the Jacobian `J = D_x f`, the parameter derivatives `D_p f` and the
//! multilinear forms `B(u, w) = D^2 f [u, w]` to machine precision, with no
//! finite differences.

use nalgebra::{Const, DMatrix, DVector, SMatrix, U1};
use num_dual::{Derivative, Dual64, DualNum, DualSVec64, HyperDual64, HyperDualSVec64};
use smallvec::SmallVec;

/// A buffer of scalars (dual-number copies of a state or parameter vector)
/// that lives on the stack up to 16 entries, so that the derivatives below do
/// not allocate for small systems (the driven block has 11 parameters).
pub(crate) type Buf<D> = SmallVec<[D; 16]>;

/// The scalar types a vector field is evaluated with: `f64` and the dual numbers.
pub trait Scalar: DualNum<Primitive = f64> + Copy {}
impl<T: DualNum<Primitive = f64> + Copy> Scalar for T {}

/// A parameter-dependent vector field `x' = f(x, p)`. `Sync`: a field is
/// evaluated from several threads at once (collocation intervals in parallel).
pub trait VectorField: Sync {
    /// Dimension `n` of the state `x`.
    fn dim(&self) -> usize;

    /// Number of entries of the parameter vector `p`.
    fn n_params(&self) -> usize;

    /// Name of parameter `k` in messages; `p[k]` unless the field names it.
    fn param_name(&self, k: usize) -> String {
        format!("p[{k}]")
    }

    /// Writes `f(x, p)` into `out` (length [`dim`](Self::dim)).
    fn rhs<D: Scalar>(&self, x: &[D], p: &[D], out: &mut [D]);

    /// Number of observables: the scalar functions of the state whose
    /// extremes along a periodic orbit are reported, and whose accuracy the
    /// cycle branches control (with the period). Default: the components
    /// of the state.
    fn n_observables(&self) -> usize {
        self.dim()
    }

    /// Observable `k` (below [`n_observables`](Self::n_observables)) at
    /// `(x, p)`. Default: the component `x_k`.
    fn observable(&self, k: usize, x: &[f64], _p: &[f64]) -> f64 {
        x[k]
    }

    /// Whether [`implicit_rhs`](Self::implicit_rhs) gives this field in an
    /// implicit form of its own; collocation then solves that form.
    fn has_implicit_form(&self) -> bool {
        false
    }

    /// The field in the implicit form `rho_r(x, p) x'_r = g_r(x, p)` (one
    /// nonnegative scale `rho_r` per equation, `f_r = g_r / rho_r`), written
    /// into `rho` and `g`. A field whose component is a ratio with a
    /// denominator that can be tiny (a relaxation rate beyond any scale of
    /// the solution) gives `g_r` directly: collocation then solves
    /// `rho_r x'_r - g_r = 0`, whose rounding is that of `g_r` (not divided
    /// by `rho_r`), and which stays defined where `rho_r` underflows to 0
    /// (the equation is then the algebraic `g_r = 0`). Default: `rho = 1`,
    /// `g = f`.
    fn implicit_rhs<D: Scalar>(&self, x: &[D], p: &[D], rho: &mut [D], g: &mut [D]) {
        rho.fill(D::from(1.0));
        self.rhs(x, p, g);
    }

    /// A Newton iterate's state at one mesh node, `x`, moved by the Newton
    /// step `-dx` (the linear system's solution, `dx` subtracted). Default:
    /// `x <- x - dx`. A field whose component is the logarithm of a quantity
    /// the equations hold nearly linearly may take the step in that quantity.
    fn newton_update(&self, x: &mut [f64], dx: &[f64]) {
        x.iter_mut().zip(dx).for_each(|(xi, d)| *xi -= d);
    }

    /// Writes `f(x, p)` into `f`, the Jacobian into `jac` and `d f / d p_k`
    /// into `fp`: what a collocation point needs. The default evaluates
    /// them together ([`first_order_by_duals`]); a system with a
    /// hand-written [`jacobian`](Self::jacobian) overrides this too.
    fn first_order(
        &self,
        x: &[f64],
        p: &[f64],
        k: usize,
        out: (&mut [f64], &mut DMatrix<f64>, &mut [f64]),
    ) {
        first_order_by_duals(self, x, p, k, out)
    }

    /// `D f[u]`, and for every `w_j` of `ws` `D f[w_j]` and `D^2 f[u, w_j]`
    /// (see [`derivatives_along_into`], which the default is).
    fn derivatives_along(
        &self,
        x: &[f64],
        p: &[f64],
        u: JointDirection,
        ws: &[JointDirection],
        out: (&mut [f64], &mut [f64], &mut [f64]),
    ) {
        derivatives_along_into(self, x, p, u, ws, out)
    }

    /// Writes the Jacobian `J_ij = d f_i / d x_j` into `jac`. The default
    /// differentiates [`rhs`](Self::rhs) with dual numbers, one column per
    /// evaluation; a system may override it with a hand-written one.
    fn jacobian(&self, x: &[f64], p: &[f64], jac: &mut DMatrix<f64>) {
        let n = self.dim();
        let pd: Buf<Dual64> = p.iter().map(|&v| Dual64::from(v)).collect();
        let mut xd: Buf<Dual64> = x.iter().map(|&v| Dual64::from(v)).collect();
        let mut out: Buf<Dual64> = SmallVec::from_elem(Dual64::from(0.0), n);
        for j in 0..n {
            xd[j].eps = 1.0;
            self.rhs(&xd, &pd, &mut out);
            xd[j].eps = 0.0;
            for i in 0..n {
                jac[(i, j)] = out[i].eps;
            }
        }
    }
}

/// `f(x, p)`, the Jacobian `D_x f` and `d f / d p_k` at `(x, p)` (into `f`,
/// `jac`, `fp`) in one evaluation of [`VectorField::rhs`] with dual numbers
/// of `n + 1` directions (`x_1 .. x_n`, `p_k`): every transcendental function
/// of the field is evaluated once, not once per column. Systems of more than
/// 7 states use [`VectorField::jacobian`] and [`param_derivative_into`].
/// Used through [`VectorField::first_order`].
pub fn first_order_by_duals<S: VectorField + ?Sized>(
    sys: &S,
    x: &[f64],
    p: &[f64],
    k: usize,
    (f, jac, fp): (&mut [f64], &mut DMatrix<f64>, &mut [f64]),
) {
    match sys.dim() {
        0..=3 => first_order_in::<S, 4>(sys, x, p, k, (f, jac, fp)),
        4..=7 => first_order_in::<S, 8>(sys, x, p, k, (f, jac, fp)),
        _ => {
            sys.rhs(x, p, f);
            sys.jacobian(x, p, jac);
            param_derivative_into(sys, x, p, k, fp);
        }
    }
}

/// `body(x, p)` on the state `x` (`n` entries) and the parameters `p` in
/// dual numbers of `N >= n + 1` directions: `x_j` along direction `j`,
/// `p_k` along direction `n`. Both are arrays filled in place on this
/// frame (the parameters on the heap beyond [`PARAMS_ON_STACK`]), lent to
/// `body` rather than returned: a buffer returned by value is copied, and
/// this runs at every collocation point.
#[inline(always)]
fn with_seeded<const N: usize, R>(
    n: usize,
    (x, p, k): (&[f64], &[f64], usize),
    body: impl FnOnce(&[DualSVec64<N>], &[DualSVec64<N>]) -> R,
) -> R {
    let zero = DualSVec64::<N>::from_re(0.0);
    let mut xd = [zero; N];
    for (j, (d, &v)) in xd.iter_mut().zip(x).enumerate() {
        *d = DualSVec64::from_re(v).derivative(j);
    }
    let fill = |pd: &mut [DualSVec64<N>]| {
        for (j, (d, &v)) in pd.iter_mut().zip(p).enumerate() {
            *d = DualSVec64::from_re(v);
            if j == k {
                *d = d.derivative(n);
            }
        }
    };
    if p.len() <= PARAMS_ON_STACK {
        let mut pd = [zero; PARAMS_ON_STACK];
        fill(&mut pd[..p.len()]);
        body(&xd[..n], &pd[..p.len()])
    } else {
        let mut pd = vec![zero; p.len()];
        fill(&mut pd);
        body(&xd[..n], &pd)
    }
}

/// Parameters [`with_seeded`] keeps on the stack.
const PARAMS_ON_STACK: usize = 16;

/// [`first_order_by_duals`] with `N >= n + 1` directions.
fn first_order_in<S: VectorField + ?Sized, const N: usize>(
    sys: &S,
    x: &[f64],
    p: &[f64],
    k: usize,
    (f, jac, fp): (&mut [f64], &mut DMatrix<f64>, &mut [f64]),
) {
    let n = sys.dim();
    let mut out = [DualSVec64::<N>::from_re(0.0); N];
    with_seeded::<N, _>(n, (x, p, k), |xd, pd| sys.rhs(xd, pd, &mut out[..n]));
    for (i, y) in out[..n].iter().enumerate() {
        f[i] = y.re;
        let eps = y.eps.unwrap_generic(Const::<N>, U1);
        for j in 0..n {
            jac[(i, j)] = eps[j];
        }
        fp[i] = eps[n];
    }
}

/// The implicit form [`VectorField::implicit_rhs`] at `(x, p)` with its first
/// derivatives over `(x_1 .. x_n, p_k)`: `rho`, `g` (length `n`) and their
/// Jacobians `drho`, `dg` (`n x (n + 1)`, the last column along `p_k`), from
/// one evaluation in dual numbers of `n + 1` directions (one evaluation per
/// direction for systems of more than 7 states).
pub fn implicit_first_order<S: VectorField + ?Sized>(
    sys: &S,
    x: &[f64],
    p: &[f64],
    k: usize,
    out: ImplicitFirstOrder,
) {
    match sys.dim() {
        0..=3 => implicit_first_order_in::<S, 4>(sys, x, p, k, out),
        4..=7 => implicit_first_order_in::<S, 8>(sys, x, p, k, out),
        _ => implicit_first_order_by_columns(sys, x, p, k, out),
    }
}

/// Where [`implicit_first_order`] writes: `rho`, `g`, `drho`, `dg`.
pub type ImplicitFirstOrder<'o> = (
    &'o mut [f64],
    &'o mut [f64],
    &'o mut DMatrix<f64>,
    &'o mut DMatrix<f64>,
);

/// [`implicit_first_order`] with `N >= n + 1` directions.
fn implicit_first_order_in<S: VectorField + ?Sized, const N: usize>(
    sys: &S,
    x: &[f64],
    p: &[f64],
    k: usize,
    (rho, g, drho, dg): ImplicitFirstOrder,
) {
    let n = sys.dim();
    let zero = DualSVec64::<N>::from_re(0.0);
    let (mut rd, mut gd) = ([zero; N], [zero; N]);
    with_seeded::<N, _>(n, (x, p, k), |xd, pd| {
        sys.implicit_rhs(xd, pd, &mut rd[..n], &mut gd[..n])
    });
    for i in 0..n {
        rho[i] = rd[i].re;
        g[i] = gd[i].re;
        let (er, eg) = (
            rd[i].eps.unwrap_generic(Const::<N>, U1),
            gd[i].eps.unwrap_generic(Const::<N>, U1),
        );
        for j in 0..=n {
            drho[(i, j)] = er[j];
            dg[(i, j)] = eg[j];
        }
    }
}

/// [`implicit_first_order`] one direction at a time.
fn implicit_first_order_by_columns<S: VectorField + ?Sized>(
    sys: &S,
    x: &[f64],
    p: &[f64],
    k: usize,
    (rho, g, drho, dg): ImplicitFirstOrder,
) {
    let n = sys.dim();
    let mut xd: Buf<Dual64> = x.iter().map(|&v| Dual64::from(v)).collect();
    let mut pd: Buf<Dual64> = p.iter().map(|&v| Dual64::from(v)).collect();
    let (mut rd, mut gd): (Buf<Dual64>, Buf<Dual64>) = (
        SmallVec::from_elem(Dual64::from(0.0), n),
        SmallVec::from_elem(Dual64::from(0.0), n),
    );
    for j in 0..=n {
        let seed = if j < n { &mut xd[j] } else { &mut pd[k] };
        seed.eps = 1.0;
        sys.implicit_rhs(&xd, &pd, &mut rd, &mut gd);
        let seed = if j < n { &mut xd[j] } else { &mut pd[k] };
        seed.eps = 0.0;
        for i in 0..n {
            rho[i] = rd[i].re;
            g[i] = gd[i].re;
            drho[(i, j)] = rd[i].eps;
            dg[(i, j)] = gd[i].eps;
        }
    }
}

/// `f(x, p)` as a vector.
pub fn eval<S: VectorField>(sys: &S, x: &[f64], p: &[f64]) -> DVector<f64> {
    let mut out = DVector::zeros(sys.dim());
    sys.rhs(x, p, out.as_mut_slice());
    out
}

/// The Jacobian `D_x f(x, p)` as a new matrix.
pub fn jacobian<S: VectorField>(sys: &S, x: &[f64], p: &[f64]) -> DMatrix<f64> {
    let n = sys.dim();
    let mut jac = DMatrix::zeros(n, n);
    sys.jacobian(x, p, &mut jac);
    jac
}

/// The derivative `d f / d p_k` at `(x, p)`.
pub fn param_derivative<S: VectorField>(sys: &S, x: &[f64], p: &[f64], k: usize) -> DVector<f64> {
    let mut out = DVector::zeros(sys.dim());
    param_derivative_into(sys, x, p, k, out.as_mut_slice());
    out
}

/// [`param_derivative`] written into `out` (length `dim`), without allocating
/// for systems of up to 8 states and parameters.
pub fn param_derivative_into<S: VectorField + ?Sized>(
    sys: &S,
    x: &[f64],
    p: &[f64],
    k: usize,
    out: &mut [f64],
) {
    let xd: Buf<Dual64> = x.iter().map(|&v| Dual64::from(v)).collect();
    let mut pd: Buf<Dual64> = p.iter().map(|&v| Dual64::from(v)).collect();
    pd[k].eps = 1.0;
    let mut res: Buf<Dual64> = SmallVec::from_elem(Dual64::from(0.0), sys.dim());
    sys.rhs(&xd, &pd, &mut res);
    for (o, d) in out.iter_mut().zip(&res) {
        *o = d.eps;
    }
}

/// A direction in the joint space `(x, p)`: a state part and a parameter part.
#[derive(Clone, Copy, Debug)]
pub struct JointDirection<'a> {
    /// Component along the state, length `n`.
    pub x: &'a [f64],
    /// Component along the parameters, length `n_params` (empty: none).
    pub p: &'a [f64],
}

impl<'a> JointDirection<'a> {
    /// A pure state direction.
    pub fn state(x: &'a [f64]) -> Self {
        JointDirection { x, p: &[] }
    }
}

/// The mixed second derivative `d^2/(dt ds) f(x + t u + s w)` at `t = s = 0`,
/// i.e. the bilinear form `D^2 f(x, p)[u, w]` over the joint space `(x, p)`.
///
/// With pure state directions this is Kuznetsov's `B(u, w)` (Kuznetsov 1998,
/// eq. 3.18); with `w = (0, e_k)` it is `(D_{p_k} J) u`.
pub fn second_derivative<S: VectorField>(
    sys: &S,
    x: &[f64],
    p: &[f64],
    u: JointDirection,
    w: JointDirection,
) -> DVector<f64> {
    let mut out = DVector::zeros(sys.dim());
    second_derivative_into(sys, x, p, u, w, out.as_mut_slice());
    out
}

/// [`second_derivative`] written into `out` (length `dim`), without
/// allocating for systems of up to 8 states and parameters.
pub fn second_derivative_into<S: VectorField>(
    sys: &S,
    x: &[f64],
    p: &[f64],
    u: JointDirection,
    w: JointDirection,
    out: &mut [f64],
) {
    hyper_dual(sys, x, p, u, w, |res| {
        for (o, d) in out.iter_mut().zip(res) {
            *o = d.eps1eps2;
        }
    });
}

/// The first derivatives `D f(x, p)[u]`, `D f(x, p)[w]` and the second
/// `D^2 f(x, p)[u, w]` over the joint space, from one evaluation in
/// hyper-dual numbers (its three derivative parts), written into `du`, `dw`
/// and `duw` (length `dim`).
pub fn derivatives_into<S: VectorField + ?Sized>(
    sys: &S,
    x: &[f64],
    p: &[f64],
    u: JointDirection,
    w: JointDirection,
    (du, dw, duw): (&mut [f64], &mut [f64], &mut [f64]),
) {
    hyper_dual(sys, x, p, u, w, |res| {
        for (i, d) in res.iter().enumerate() {
            (du[i], dw[i], duw[i]) = (d.eps1, d.eps2, d.eps1eps2);
        }
    });
}

/// [`derivatives_into`] for one direction `u` and several `ws` at once: `D
/// f[u]` into `du`, and for every `w_j` of `ws` `D f[w_j]` and `D^2 f[u,
/// w_j]` into `dw` and `duw` (`n` entries per direction, direction-major),
/// from one evaluation in vector hyper-dual numbers (`eps1` along `u`,
/// `eps2` along the `w_j`) when there are at most 8 directions: every
/// transcendental function of the field is evaluated once, not once per
/// direction. Used through [`VectorField::derivatives_along`].
pub fn derivatives_along_into<S: VectorField + ?Sized>(
    sys: &S,
    x: &[f64],
    p: &[f64],
    u: JointDirection,
    ws: &[JointDirection],
    (du, dw, duw): (&mut [f64], &mut [f64], &mut [f64]),
) {
    let n = sys.dim();
    match ws.len() {
        0..=4 => along_in::<S, 4>(sys, x, p, u, ws, (du, dw, duw)),
        // n + 2 for n = 3: the fold of cycles of the inertial block in two parameters.
        5 => along_in::<S, 5>(sys, x, p, u, ws, (du, dw, duw)),
        6..=8 => along_in::<S, 8>(sys, x, p, u, ws, (du, dw, duw)),
        _ => {
            for (j, w) in ws.iter().enumerate() {
                let block = j * n..(j + 1) * n;
                derivatives_into(
                    sys,
                    x,
                    p,
                    u,
                    *w,
                    (du, &mut dw[block.clone()], &mut duw[block]),
                );
            }
        }
    }
}

/// [`derivatives_along_into`] with `N >= ws.len()` directions.
fn along_in<S: VectorField + ?Sized, const N: usize>(
    sys: &S,
    x: &[f64],
    p: &[f64],
    u: JointDirection,
    ws: &[JointDirection],
    (du, dw, duw): (&mut [f64], &mut [f64], &mut [f64]),
) {
    type H<const N: usize> = HyperDualSVec64<1, N>;
    let comp = |d: &[f64], i: usize| d.get(i).copied().unwrap_or(0.0);
    // Entry i of the state part (or of the parameter part) of a direction.
    let entry = |d: &JointDirection, state: bool, i: usize| comp(if state { d.x } else { d.p }, i);
    let lift = |v: f64, i: usize, state: bool| {
        let along_ws =
            SMatrix::<f64, 1, N>::from_fn(|_, j| ws.get(j).map_or(0.0, |w| entry(w, state, i)));
        H::<N>::new(
            v,
            Derivative::some(SMatrix::<f64, 1, 1>::new(entry(&u, state, i))),
            Derivative::some(along_ws),
            Derivative::none(),
        )
    };
    let xd: Buf<H<N>> = (0..x.len()).map(|i| lift(x[i], i, true)).collect();
    let pd: Buf<H<N>> = (0..p.len()).map(|i| lift(p[i], i, false)).collect();
    let mut res: Buf<H<N>> = SmallVec::from_elem(H::<N>::from_re(0.0), sys.dim());
    sys.rhs(&xd, &pd, &mut res);
    let n = sys.dim();
    for (i, y) in res.iter().enumerate() {
        du[i] = y.eps1.unwrap_generic(U1, U1)[0];
        let (first, second) = (
            y.eps2.unwrap_generic(U1, Const::<N>),
            y.eps1eps2.unwrap_generic(U1, Const::<N>),
        );
        for j in 0..ws.len() {
            dw[j * n + i] = first[j];
            duw[j * n + i] = second[j];
        }
    }
}

/// `f(x + t u + s w)` in hyper-dual numbers (`eps1` along `u`, `eps2` along
/// `w`), handed to `read`.
fn hyper_dual<S: VectorField + ?Sized>(
    sys: &S,
    x: &[f64],
    p: &[f64],
    u: JointDirection,
    w: JointDirection,
    read: impl FnOnce(&[HyperDual64]),
) {
    let comp = |d: &[f64], i: usize| d.get(i).copied().unwrap_or(0.0);
    let xd: Buf<HyperDual64> = (0..x.len())
        .map(|i| HyperDual64::new(x[i], comp(u.x, i), comp(w.x, i), 0.0))
        .collect();
    let pd: Buf<HyperDual64> = (0..p.len())
        .map(|i| HyperDual64::new(p[i], comp(u.p, i), comp(w.p, i), 0.0))
        .collect();
    let mut res: Buf<HyperDual64> = SmallVec::from_elem(HyperDual64::from(0.0), sys.dim());
    sys.rhs(&xd, &pd, &mut res);
    read(&res);
}

/// A system whose parameters `indices` are given by their logarithms:
/// `rhs(x, p)` evaluates the inner system at `exp(p_k)` for those `k`.
/// Continuation in `ln p` takes steps that are uniform on a logarithmic axis.
pub struct LogParameters<'a, S: VectorField> {
    /// The system in its own parameters.
    pub inner: &'a S,
    /// Which parameters are logarithmic.
    pub indices: Vec<usize>,
}

impl<S: VectorField> LogParameters<'_, S> {
    /// Converts a parameter vector to the logarithmic one (`ln p_k` at `indices`).
    pub fn to_log(&self, p: &[f64]) -> Vec<f64> {
        let mut q = p.to_vec();
        for &k in &self.indices {
            q[k] = q[k].ln();
        }
        q
    }

    /// Converts a logarithmic parameter vector back.
    pub fn from_log(&self, q: &[f64]) -> Vec<f64> {
        let mut p = q.to_vec();
        for &k in &self.indices {
            p[k] = p[k].exp();
        }
        p
    }
}

impl<S: VectorField> VectorField for LogParameters<'_, S> {
    fn dim(&self) -> usize {
        self.inner.dim()
    }
    fn n_params(&self) -> usize {
        self.inner.n_params()
    }
    fn param_name(&self, k: usize) -> String {
        let name = self.inner.param_name(k);
        if self.indices.contains(&k) {
            format!("ln {name}")
        } else {
            name
        }
    }
    fn rhs<D: Scalar>(&self, x: &[D], p: &[D], out: &mut [D]) {
        let mut q: Buf<D> = SmallVec::from_slice(p);
        for &k in &self.indices {
            q[k] = q[k].exp();
        }
        self.inner.rhs(x, &q, out);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `f = (x0^2 x1 + p0 sin x1, exp(x0) p0 p1)`, derivatives known by hand.
    struct Toy;
    impl VectorField for Toy {
        fn dim(&self) -> usize {
            2
        }
        fn n_params(&self) -> usize {
            2
        }
        fn rhs<D: Scalar>(&self, x: &[D], p: &[D], out: &mut [D]) {
            out[0] = x[0] * x[0] * x[1] + p[0] * x[1].sin();
            out[1] = x[0].exp() * p[0] * p[1];
        }
    }

    /// `f_i = exp(p0 x_i) sin(x_{i+1}) + p1 x_i^2` (indices mod `n`): any
    /// dimension, so that every width of the one-pass derivatives is used.
    struct Ring(usize);
    impl VectorField for Ring {
        fn dim(&self) -> usize {
            self.0
        }
        fn n_params(&self) -> usize {
            2
        }
        fn rhs<D: Scalar>(&self, x: &[D], p: &[D], out: &mut [D]) {
            let n = self.0;
            for i in 0..n {
                out[i] = (p[0] * x[i]).exp() * x[(i + 1) % n].sin() + p[1] * x[i] * x[i];
            }
        }
    }

    fn ring_point(n: usize) -> (Vec<f64>, Vec<f64>) {
        (
            (0..n).map(|i| 0.3 + 0.17 * i as f64).collect(),
            vec![0.8, -1.4],
        )
    }

    fn close(a: f64, b: f64, what: &str) {
        assert!(
            (a - b).abs() <= 1e-14 * (1.0 + b.abs()),
            "{what}: {a} vs {b}"
        );
    }

    /// The one-pass value, Jacobian and parameter column equal the value, the
    /// column-by-column dual Jacobian and the dual parameter derivative, in
    /// the 4- and 8-wide passes and the fallback beyond.
    #[test]
    fn first_order_in_one_pass_matches_column_by_column() {
        for n in [1, 2, 3, 4, 7, 8, 9] {
            let (x, p) = ring_point(n);
            let sys = Ring(n);
            let (mut f, mut fp, mut jac) = (vec![0.0; n], vec![0.0; n], DMatrix::zeros(n, n));
            sys.first_order(&x, &p, 1, (&mut f, &mut jac, &mut fp));
            let (f0, j0, fp0) = (
                eval(&sys, &x, &p),
                jacobian(&sys, &x, &p),
                param_derivative(&sys, &x, &p, 1),
            );
            for i in 0..n {
                close(f[i], f0[i], "f");
                close(fp[i], fp0[i], "df/dp");
                for c in 0..n {
                    close(jac[(i, c)], j0[(i, c)], "J");
                }
            }
        }
    }

    /// The second derivatives along several directions at once equal those
    /// of one hyper-dual evaluation per direction.
    #[test]
    fn derivatives_along_several_directions_match_one_at_a_time() {
        for n in [2, 3, 4, 6, 9] {
            let (x, p) = ring_point(n);
            let sys = Ring(n);
            let u: Vec<f64> = (0..n).map(|i| 0.5 - 0.1 * i as f64).collect();
            let states: Vec<Vec<f64>> = (0..n)
                .map(|j| (0..n).map(|i| if i == j { 1.0 } else { 0.2 }).collect())
                .collect();
            let pdir = [0.0, 1.0];
            let ws: Vec<JointDirection> = states
                .iter()
                .map(|e| JointDirection::state(e))
                .chain([JointDirection { x: &[], p: &pdir }])
                .collect();
            let (mut du, mut dw, mut duw) = (
                vec![0.0; n],
                vec![0.0; ws.len() * n],
                vec![0.0; ws.len() * n],
            );
            derivatives_along_into(
                &sys,
                &x,
                &p,
                JointDirection::state(&u),
                &ws,
                (&mut du, &mut dw, &mut duw),
            );
            for (d, w) in ws.iter().enumerate() {
                let (mut a, mut b, mut c) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
                derivatives_into(
                    &sys,
                    &x,
                    &p,
                    JointDirection::state(&u),
                    *w,
                    (&mut a, &mut b, &mut c),
                );
                for i in 0..n {
                    close(du[i], a[i], "D f[u]");
                    close(dw[d * n + i], b[i], "D f[w]");
                    close(duw[d * n + i], c[i], "D2 f[u, w]");
                }
            }
        }
    }

    #[test]
    fn dual_derivatives_match_hand_derivatives() {
        let (x, p) = ([0.7, -1.3], [0.4, 2.5]);
        let j = jacobian(&Toy, &x, &p);
        let e = x[0].exp();
        let expect = [
            [2.0 * x[0] * x[1], x[0] * x[0] + p[0] * x[1].cos()],
            [e * p[0] * p[1], 0.0],
        ];
        for i in 0..2 {
            for k in 0..2 {
                assert!((j[(i, k)] - expect[i][k]).abs() < 1e-15, "J[{i},{k}]");
            }
        }
        let fp = param_derivative(&Toy, &x, &p, 1);
        assert!((fp[0]).abs() < 1e-15 && (fp[1] - e * p[0]).abs() < 1e-15);
        // B(u, w) for the first component: 2 x1 u0 w0 + 2 x0 (u0 w1 + u1 w0) - p0 sin(x1) u1 w1.
        let (u, w) = ([0.3, 0.8], [-1.1, 0.5]);
        let b = second_derivative(
            &Toy,
            &x,
            &p,
            JointDirection::state(&u),
            JointDirection::state(&w),
        );
        let b0 = 2.0 * x[1] * u[0] * w[0] + 2.0 * x[0] * (u[0] * w[1] + u[1] * w[0])
            - p[0] * x[1].sin() * u[1] * w[1];
        assert!((b[0] - b0).abs() < 1e-14);
        // (D_p0 J) u for the second component: exp(x0) p1 u0.
        let dp = second_derivative(
            &Toy,
            &x,
            &p,
            JointDirection::state(&u),
            JointDirection {
                x: &[],
                p: &[1.0, 0.0],
            },
        );
        assert!((dp[1] - e * p[1] * u[0]).abs() < 1e-14);
    }
}
