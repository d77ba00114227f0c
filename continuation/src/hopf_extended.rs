//! The first Lyapunov coefficient in double-double precision, where `f64`
//! cannot resolve it.
//!
//! `l1` is a sum of terms (see [`crate::normal_form`]) that may cancel far
//! below their own size: with a small coefficient in front of a derivative
//! (a mass `m`) whose limit system has a degenerate Hopf point, the terms are
//! of order one and `l1` of order `m`. In `f64` the result then carries an
//! absolute error of order `eps` whatever the method, so that at `m = 1e-12`
//! only a few digits are left. Here the Hopf point itself and every quantity
//! of the normal form are recomputed with [`DoubleDouble`](crate::double_double::DoubleDouble) (unit roundoff
//! `u = 2^-104`), starting from the `f64` ones:
//!
//! 1. Newton's method on the standard Hopf system in the unknowns
//!    `(x, p_k, w, q)` (Kuznetsov 1998, §10.2.2):
//!    ```text
//!    f(x, p) = 0,   (A(x, p) - i w I) q = 0,   <c, q> = 1     (c: the f64 vector q)
//!    ```
//!    with exact second derivatives from hyper-dual numbers over
//!    double-double; one or two steps take the point from 16 to 32 digits.
//! 2. The adjoint vector from the bordered system
//!    `[[A^T + i w I, p0], [p0^H, 0]] (p, s) = (0, 1)`, then `<p, q> = 1`.
//! 3. `c1` by the formula of [`crate::normal_form`], with the resolvents
//!    solved by Gaussian elimination with partial pivoting on the
//!    row-equilibrated matrices (rows scaled by powers of two, exactly).
//!
//! The error bound is that of [`crate::normal_form::hopf_normal_form`] with
//! `u` in place of `eps`: the same first-order analysis of the same sum, at a
//! point located to double-double precision.

use crate::double_double::{ComplexDD, DoubleDouble as DD};
use crate::error::ContinuationError;
use crate::normal_form::HopfNormalForm;
use crate::system::VectorField;
use nalgebra::DVector;
use num_complex::{Complex, Complex64};
use num_dual::{Dual, DualNum, HyperDual, HyperHyperDual};
use num_traits::{One, Signed, Zero};
use std::ops::{Add, Div, Mul, Sub, SubAssign};

/// A Hopf point and its normal form in double-double precision.
#[derive(Clone, Debug)]
pub struct ExtendedHopf {
    /// The normal form, every field rounded to `f64`; `l1_error_bound` is the
    /// double-double rounding bound plus the rounding of `l1` to `f64`.
    pub normal_form: HopfNormalForm,
    /// The refined equilibrium.
    pub x: Vec<DD>,
    /// The refined value of the free parameter `p_k`.
    pub param: DD,
    /// Size of the last Newton step in `p_k` (the a-posteriori error of the
    /// location, relative to nothing: an absolute value).
    pub param_step: f64,
    /// Newton iterations taken.
    pub newton_iterations: usize,
}

/// An entry of a matrix that Gaussian elimination works on.
trait Entry:
    Copy
    + Zero
    + Add<Output = Self>
    + Sub<Output = Self>
    + SubAssign
    + Mul<Output = Self>
    + Div<Output = Self>
{
    /// A size for pivoting and equilibration, `|re| + |im|` of the leading parts.
    fn size(&self) -> f64;
    /// Multiplication by a power of two (exact).
    fn scaled(self, s: f64) -> Self;
}

impl Entry for DD {
    fn size(&self) -> f64 {
        self.hi().abs()
    }
    fn scaled(self, s: f64) -> Self {
        self * s
    }
}

impl Entry for ComplexDD {
    fn size(&self) -> f64 {
        self.re.hi().abs() + self.im.hi().abs()
    }
    fn scaled(self, s: f64) -> Self {
        Complex::new(self.re * s, self.im * s)
    }
}

/// Solves `a x = b` (dense, `a` row-major) by Gaussian elimination with
/// partial pivoting after scaling each row by a power of two near the
/// inverse of its largest entry.
fn solve<T: Entry>(mut a: Vec<Vec<T>>, mut b: Vec<T>) -> Result<Vec<T>, ContinuationError> {
    let n = b.len();
    for (row, bi) in a.iter_mut().zip(b.iter_mut()) {
        let size = row.iter().map(Entry::size).fold(0.0, f64::max);
        if !(size > 0.0 && size.is_finite()) {
            return Err(ContinuationError::Singular);
        }
        let s = (-size.log2().floor()).exp2();
        row.iter_mut().for_each(|e| *e = e.scaled(s));
        *bi = bi.scaled(s);
    }
    for col in 0..n {
        let piv = (col..n)
            .max_by(|&i, &j| a[i][col].size().total_cmp(&a[j][col].size()))
            .ok_or(ContinuationError::Singular)?;
        if a[piv][col].size() == 0.0 {
            return Err(ContinuationError::Singular);
        }
        a.swap(col, piv);
        b.swap(col, piv);
        let (upper, lower) = a.split_at_mut(col + 1);
        let pivot_row = &upper[col];
        for (offset, row) in lower.iter_mut().enumerate() {
            let factor = row[col] / pivot_row[col];
            for (e, &t) in row[col..].iter_mut().zip(&pivot_row[col..]) {
                *e -= factor * t;
            }
            let t = b[col];
            b[col + 1 + offset] -= factor * t;
        }
    }
    let mut x = vec![T::zero(); n];
    for i in (0..n).rev() {
        let mut s = b[i];
        for j in i + 1..n {
            s -= a[i][j] * x[j];
        }
        x[i] = s / a[i][i];
    }
    if x.iter().any(|e| !e.size().is_finite()) {
        return Err(ContinuationError::Singular);
    }
    Ok(x)
}

/// A point `(x, p)` of a system, in double-double.
struct At<'a, S: VectorField> {
    sys: &'a S,
    x: Vec<DD>,
    p: Vec<DD>,
}

/// A direction in the joint space `(x, p)`.
type Joint<'a> = (&'a [DD], &'a [DD]);

fn comp(d: &[DD], i: usize) -> DD {
    d.get(i).copied().unwrap_or_else(DD::zero)
}

impl<S: VectorField> At<'_, S> {
    fn n(&self) -> usize {
        self.x.len()
    }

    fn f(&self) -> Vec<DD> {
        let mut out = vec![DD::zero(); self.n()];
        self.sys.rhs(&self.x, &self.p, &mut out);
        out
    }

    /// `d/dt f((x, p) + t u)`: a column of the Jacobian or `D_p f`.
    fn first(&self, u: Joint) -> Vec<DD> {
        let xd: Vec<Dual<DD>> = (0..self.n())
            .map(|i| Dual::new(self.x[i], comp(u.0, i)))
            .collect();
        let pd: Vec<Dual<DD>> = (0..self.p.len())
            .map(|i| Dual::new(self.p[i], comp(u.1, i)))
            .collect();
        let mut out = vec![Dual::from_re(DD::zero()); self.n()];
        self.sys.rhs(&xd, &pd, &mut out);
        out.iter().map(|d| d.eps).collect()
    }

    /// `D^2 f [u, w]` over the joint space.
    fn second(&self, u: Joint, w: Joint) -> Vec<DD> {
        let z = DD::zero();
        let xd: Vec<HyperDual<DD>> = (0..self.n())
            .map(|i| HyperDual::new(self.x[i], comp(u.0, i), comp(w.0, i), z))
            .collect();
        let pd: Vec<HyperDual<DD>> = (0..self.p.len())
            .map(|i| HyperDual::new(self.p[i], comp(u.1, i), comp(w.1, i), z))
            .collect();
        let mut out = vec![HyperDual::from_re(z); self.n()];
        self.sys.rhs(&xd, &pd, &mut out);
        out.iter().map(|d| d.eps1eps2).collect()
    }

    /// `D^3 f [u, v, w]` along state directions.
    fn third(&self, u: &[DD], v: &[DD], w: &[DD]) -> Vec<DD> {
        let z = DD::zero();
        let xd: Vec<HyperHyperDual<DD>> = (0..self.n())
            .map(|i| HyperHyperDual::new(self.x[i], u[i], v[i], w[i], z, z, z, z))
            .collect();
        let pd: Vec<HyperHyperDual<DD>> =
            self.p.iter().map(|&v| HyperHyperDual::from_re(v)).collect();
        let mut out = vec![HyperHyperDual::from_re(z); self.n()];
        self.sys.rhs(&xd, &pd, &mut out);
        out.iter().map(|d| d.eps1eps2eps3).collect()
    }

    /// The Jacobian `A = D_x f`, row-major.
    fn jacobian(&self) -> Vec<Vec<DD>> {
        let n = self.n();
        let mut a = vec![vec![DD::zero(); n]; n];
        let mut e = vec![DD::zero(); n];
        for j in 0..n {
            e[j] = DD::one();
            let col = self.first((&e, &[]));
            e[j] = DD::zero();
            for i in 0..n {
                a[i][j] = col[i];
            }
        }
        a
    }

    /// Complex `B(u, v)` by bilinearity over real and imaginary parts.
    fn b(&self, u: &[ComplexDD], v: &[ComplexDD]) -> Vec<ComplexDD> {
        let mut out = vec![ComplexDD::zero(); self.n()];
        for (ur, cu) in parts(u) {
            for (vr, cv) in parts(v) {
                let d = self.second((&ur, &[]), (&vr, &[]));
                add_scaled(&mut out, &d, cu * cv);
            }
        }
        out
    }

    /// Complex `C(u, v, w)` by trilinearity.
    fn c(&self, u: &[ComplexDD], v: &[ComplexDD], w: &[ComplexDD]) -> Vec<ComplexDD> {
        let mut out = vec![ComplexDD::zero(); self.n()];
        for (ur, cu) in parts(u) {
            for (vr, cv) in parts(v) {
                for (wr, cw) in parts(w) {
                    add_scaled(&mut out, &self.third(&ur, &vr, &wr), cu * cv * cw);
                }
            }
        }
        out
    }
}

/// Real and imaginary parts of a complex vector with their unit factors
/// (`1` and `i`); an all-zero part is left out.
fn parts(u: &[ComplexDD]) -> Vec<(Vec<DD>, ComplexDD)> {
    let re: Vec<DD> = u.iter().map(|z| z.re).collect();
    let im: Vec<DD> = u.iter().map(|z| z.im).collect();
    [(re, ComplexDD::one()), (im, ComplexDD::i())]
        .into_iter()
        .filter(|(v, _)| v.iter().any(|t| !t.is_zero()))
        .collect()
}

fn add_scaled(out: &mut [ComplexDD], d: &[DD], c: ComplexDD) {
    for (o, t) in out.iter_mut().zip(d) {
        *o += c * *t;
    }
}

/// `<a, b> = conj(a) . b`.
fn dotc(a: &[ComplexDD], b: &[ComplexDD]) -> ComplexDD {
    a.iter()
        .zip(b)
        .fold(ComplexDD::zero(), |s, (x, y)| s + x.conj() * *y)
}

fn to_dd(z: &Complex64) -> ComplexDD {
    Complex::new(DD::from(z.re), DD::from(z.im))
}

fn to_f64(z: &ComplexDD) -> Complex64 {
    Complex64::new(z.re.hi(), z.im.hi())
}

/// Newton's method on the Hopf system (module documentation, step 1), from
/// the `f64` point `(x, p)` and the `f64` normal form `start` there. Returns
/// the refined point, `w`, `q`, the last step in `p_k` and the iterations.
#[allow(clippy::type_complexity)]
fn refine<'a, S: VectorField>(
    sys: &'a S,
    x: &[f64],
    p: &[f64],
    k: usize,
    start: &HopfNormalForm,
) -> Result<(At<'a, S>, DD, Vec<ComplexDD>, f64, usize), ContinuationError> {
    let n = x.len();
    let mut at = At {
        sys,
        x: x.iter().map(|&v| DD::from(v)).collect(),
        p: p.iter().map(|&v| DD::from(v)).collect(),
    };
    let c: Vec<ComplexDD> = start.q.iter().map(to_dd).collect();
    let mut omega = DD::from(start.omega);
    let mut q = c.clone();
    let mut ek = vec![DD::zero(); p.len()];
    ek[k] = DD::one();
    let mut last_step = f64::INFINITY;
    let mut previous_step = f64::INFINITY;
    for iteration in 1..=8 {
        let a = at.jacobian();
        let f = at.f();
        let qr: Vec<DD> = q.iter().map(|z| z.re).collect();
        let qi: Vec<DD> = q.iter().map(|z| z.im).collect();
        let m = 3 * n + 2;
        let mut jac = vec![vec![DD::zero(); m]; m];
        let mut res = vec![DD::zero(); m];
        let fp = at.first((&[], &ek));
        let mut e = vec![DD::zero(); n];
        let b_col = |u: &[DD], e: &[DD], ep: &[DD]| at.second((u, &[]), (e, ep));
        for j in 0..=n {
            // Column j of the state block (j < n) or the parameter column (j = n).
            let (br, bi) = if j < n {
                e[j] = DD::one();
                let r = (b_col(&qr, &e, &[]), b_col(&qi, &e, &[]));
                e[j] = DD::zero();
                r
            } else {
                (b_col(&qr, &[], &ek), b_col(&qi, &[], &ek))
            };
            for i in 0..n {
                jac[i][j] = if j < n { a[i][j] } else { fp[i] };
                jac[n + i][j] = br[i];
                jac[2 * n + i][j] = bi[i];
            }
        }
        for i in 0..n {
            let (mut aqr, mut aqi) = (DD::zero(), DD::zero());
            for j in 0..n {
                aqr += a[i][j] * qr[j];
                aqi += a[i][j] * qi[j];
                jac[n + i][n + 2 + j] = a[i][j];
                jac[2 * n + i][2 * n + 2 + j] = a[i][j];
            }
            jac[n + i][n + 1] = qi[i];
            jac[2 * n + i][n + 1] = -qr[i];
            jac[n + i][2 * n + 2 + i] = omega;
            jac[2 * n + i][n + 2 + i] = -omega;
            res[i] = f[i];
            res[n + i] = aqr + omega * qi[i];
            res[2 * n + i] = aqi - omega * qr[i];
        }
        let norm = dotc(&c, &q);
        res[3 * n] = norm.re - 1.0;
        res[3 * n + 1] = norm.im;
        for j in 0..n {
            jac[3 * n][n + 2 + j] = c[j].re;
            jac[3 * n][2 * n + 2 + j] = c[j].im;
            jac[3 * n + 1][n + 2 + j] = -c[j].im;
            jac[3 * n + 1][2 * n + 2 + j] = c[j].re;
        }
        let dz = solve(jac, res)?;
        for i in 0..n {
            at.x[i] -= dz[i];
            q[i] -= Complex::new(dz[n + 2 + i], dz[2 * n + 2 + i]);
        }
        at.p[k] -= dz[n];
        omega -= dz[n + 1];
        // Steps relative to each unknown's size, floored at 1e-8 of the
        // largest one (an equilibrium or parameter at zero has no size of its own).
        let x_size = at.x.iter().map(|v| v.hi().abs()).fold(0.0, f64::max);
        let (p_size, w_size) = (at.p[k].hi().abs(), omega.hi().abs());
        let floor = 1e-8 * x_size.max(p_size).max(w_size).max(1.0);
        let rel = |d: DD, size: f64| d.hi().abs() / size.max(floor);
        let step = (0..n)
            .map(|i| {
                rel(dz[i], x_size)
                    .max(rel(dz[n + 2 + i], 1.0))
                    .max(rel(dz[2 * n + 2 + i], 1.0))
            })
            .fold(rel(dz[n], p_size), f64::max)
            .max(rel(dz[n + 1], w_size));
        last_step = dz[n].hi().abs();
        if !step.is_finite() {
            break;
        }
        // Converged at rounding level, or stagnant at a floor far below f64
        // (a component whose own size is zero measures its step against nothing).
        if step <= 64.0 * DD::EPSILON || (previous_step < 1e-20 && step >= 0.5 * previous_step) {
            return Ok((at, omega, q, last_step, iteration));
        }
        previous_step = step;
    }
    Err(ContinuationError::Eigen(format!(
        "the Hopf point did not converge in double-double precision (last step in the \
         parameter {last_step:.1e})"
    )))
}

/// The normal form of the Hopf point near `(x, p)` in double-double
/// precision, with the point refined in parameter `k` (module documentation).
/// `start` is the `f64` normal form at `(x, p)`, whose critical vectors start
/// the refinement and whose error bound, scaled from `eps` to `u`, bounds
/// the result's rounding.
pub fn hopf_normal_form_extended<S: VectorField>(
    sys: &S,
    x: &[f64],
    p: &[f64],
    k: usize,
    start: &HopfNormalForm,
) -> Result<ExtendedHopf, ContinuationError> {
    let n = x.len();
    let (at, omega, q, param_step, iterations) = refine(sys, x, p, k, start)?;
    let qnorm = q.iter().fold(DD::zero(), |s, z| s + z.norm_sqr()).sqrt();
    let q: Vec<ComplexDD> = q.iter().map(|z| *z / qnorm).collect();
    let qb: Vec<ComplexDD> = q.iter().map(|z| z.conj()).collect();
    let a = at.jacobian();
    let iw = Complex::new(DD::zero(), omega);
    // Adjoint: (A^T + i w I) p = 0 bordered by the f64 adjoint.
    let p0: Vec<ComplexDD> = start.p.iter().map(to_dd).collect();
    let mut m = vec![vec![ComplexDD::zero(); n + 1]; n + 1];
    for i in 0..n {
        for j in 0..n {
            m[i][j] = Complex::from(a[j][i]);
        }
        m[i][i] += iw;
        m[i][n] = p0[i];
        m[n][i] = p0[i].conj();
    }
    let mut rhs = vec![ComplexDD::zero(); n + 1];
    rhs[n] = ComplexDD::one();
    let padj = solve(m, rhs)?;
    let scale = dotc(&padj[..n], &q).conj();
    let padj: Vec<ComplexDD> = padj[..n].iter().map(|z| *z / scale).collect();
    // Resolvents: A h11 = B(q, qbar), (2 i w I - A) h20 = B(q, q).
    let shifted = |sigma: ComplexDD, sign: f64| -> Vec<Vec<ComplexDD>> {
        (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| {
                        let d = if i == j { sigma } else { ComplexDD::zero() };
                        d + Complex::from(a[i][j] * sign)
                    })
                    .collect()
            })
            .collect()
    };
    let h11 = solve(shifted(ComplexDD::zero(), 1.0), at.b(&q, &qb))?;
    let h20 = solve(shifted(iw * DD::from(2.0), -1.0), at.b(&q, &q))?;
    let half = DD::from(0.5);
    let t1 = dotc(&padj, &at.c(&q, &q, &qb)) * half;
    let t2 = -dotc(&padj, &at.b(&q, &h11));
    let t3 = dotc(&padj, &at.b(&qb, &h20)) * half;
    let c1 = t1 + t2 + t3;
    let l1 = c1.re / omega;
    let size = |t: &ComplexDD| t.norm_sqr().sqrt().hi();
    let w = omega.hi();
    let normal_form = HopfNormalForm {
        omega: w,
        q: DVector::from_iterator(n, q.iter().map(to_f64)),
        p: DVector::from_iterator(n, padj.iter().map(to_f64)),
        c1: to_f64(&c1),
        l1: l1.hi(),
        term_scale: (size(&t1) + size(&t2) + size(&t3)) / w,
        // The f64 bound with u for eps, plus the rounding of l1 to f64.
        l1_error_bound: start.l1_error_bound * (DD::EPSILON / f64::EPSILON)
            + (l1 - DD::from(l1.hi())).abs().hi(),
    };
    Ok(ExtendedHopf {
        normal_form,
        param: at.p[k],
        x: at.x,
        param_step,
        newton_iterations: iterations,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::normal_form::hopf_normal_form;
    use crate::Scalar;

    /// In the complex coordinate `z = u + i v`:
    /// `z' = (mu + i) z + i z^2 + z zbar + (1 + delta) z^2 zbar`, i.e.
    /// `g20 = 2i`, `g11 = 1`, `g21 = 2 (1 + delta)`. Kuznetsov's (3.20),
    /// `c1 = i/(2w) (g20 g11 - 2|g11|^2 - |g02|^2/3) + g21/2 = delta - i`
    /// at `mu = 0`, `w = 1`: the quadratic part cancels the unit cubic one
    /// and `Re c1 = delta` is left. With `q = (1, -i)/sqrt 2` (`<q, q> = 1`)
    /// the engine's coordinate is `z/sqrt 2`, so its `l1` is `2 delta`.
    struct CancellingHopf {
        delta: f64,
    }

    impl VectorField for CancellingHopf {
        fn dim(&self) -> usize {
            2
        }
        fn n_params(&self) -> usize {
            1
        }
        fn rhs<D: Scalar>(&self, x: &[D], p: &[D], out: &mut [D]) {
            let (u, v, mu) = (x[0], x[1], p[0]);
            let r2 = u * u + v * v;
            out[0] = mu * u - v - u * v * 2.0 + r2 + u * r2 + u * r2 * self.delta;
            out[1] = mu * v + u + u * u - v * v + v * r2 + v * r2 * self.delta;
        }
    }

    fn forms(delta: f64, mu: f64) -> (HopfNormalForm, ExtendedHopf) {
        let sys = CancellingHopf { delta };
        let (x, p) = ([0.0, 0.0], [mu]);
        let nf = hopf_normal_form(&sys, &x, &p, 1.0).unwrap();
        let ext = hopf_normal_form_extended(&sys, &x, &p, 0, &nf).unwrap();
        (nf, ext)
    }

    #[test]
    fn double_double_agrees_with_f64_where_f64_resolves_l1() {
        let (nf, ext) = forms(0.25, 0.0);
        assert!((nf.l1 - 0.5).abs() < 1e-15, "f64 l1 = {}", nf.l1);
        assert!((ext.normal_form.l1 - 0.5).abs() < 1e-30);
        assert!((ext.normal_form.c1 - Complex64::new(0.5, -2.0)).norm() < 1e-15);
    }

    /// `l1 = 2e-20` under terms of size one: below `f64`'s bound (degenerate
    /// there), resolved to ten digits in double-double from a start off the
    /// Hopf point (`mu = 1e-9`), with the bound bracketing the error.
    #[test]
    fn double_double_resolves_l1_below_the_f64_rounding_of_its_terms() {
        let (nf, ext) = forms(1e-20, 1e-9);
        assert!(nf.is_degenerate() || (nf.l1 - 2e-20).abs() > 1e-10 * 2e-20);
        let got = &ext.normal_form;
        let err = (got.l1 - 2e-20).abs();
        assert!(err <= 1e-10 * 2e-20, "l1 = {:e}, error {err:e}", got.l1);
        assert!(err <= got.l1_error_bound && got.l1_error_bound < 1e-3 * 2e-20);
        assert!(ext.param.hi().abs() < 1e-30, "mu_c = {}", ext.param);
        assert!(ext.newton_iterations <= 3);
    }
}
