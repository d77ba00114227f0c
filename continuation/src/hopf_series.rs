//! Hopf normal form to fifth order: the second Lyapunov coefficient `l2`,
//! needed at Bautin (generalized Hopf) points where `l1 = 0`.
//!
//! The centre manifold `x = x0 + H(z, zbar)`, `H = sum a_jk z^j zbar^k`
//! (`a_10 = q`, `a_01 = qbar`) and the normal form
//! `z' = i w z + c1 z |z|^2 + c2 z |z|^4` are found order by order from the
//! invariance equation `H_z z' + H_zbar zbar' = A H + F(H)` (Kuznetsov 1998,
//! §8.7; Kuznetsov 1999, "Numerical normalization techniques"):
//!
//! ```text
//! (i w (j - k) - A) a_jk = [F(H)]_jk - [H_z N + H_zbar Nbar]'_jk
//! ```
//!
//! where `'` drops the terms already on the left. For the resonant
//! `(j, k) = (k + 1, k)` the solvability condition gives the normal-form
//! coefficient, `n_jk = <p, rhs>`, and `a_jk` is fixed by `<p, a_jk> = 0`.
//! `F` is expanded with the exact multilinear forms of orders 2 to 5, taken by
//! nested dual numbers (one dual level per direction). Then `c1 = n_21`,
//! `c2 = n_32`, `l1 = Re(c1)/w`, `l2 = Re(c2)/w` (Kuznetsov's
//! `l2 = Re G32 / (12 w)` with `G32 = 12 c2`).

use crate::error::ContinuationError;
use crate::hopf_pencil::HopfPencil;
use crate::normal_form::rounding_factor;
use crate::system::{jacobian, Scalar, VectorField};
use nalgebra::DVector;
use num_complex::Complex64;
use num_dual::{Dual, Dual64};
use std::collections::BTreeMap;

/// Normal-form coefficients up to fifth order.
#[derive(Clone, Copy, Debug)]
pub struct HopfSeries {
    /// Angular frequency.
    pub omega: f64,
    /// Cubic coefficient `c1`.
    pub c1: Complex64,
    /// Quintic coefficient `c2`.
    pub c2: Complex64,
    /// First Lyapunov coefficient `Re(c1)/w`.
    pub l1: f64,
    /// Second Lyapunov coefficient `Re(c2)/w`.
    pub l2: f64,
    /// Bound on the rounding error of `l2`, built like
    /// [`HopfNormalForm::l1_error_bound`](crate::normal_form::HopfNormalForm):
    /// the size of the terms of the resonant fifth-order equation, times the
    /// rounding factor and the worst condition number of the solves its
    /// lower-order coefficients went through.
    pub l2_error_bound: f64,
}

/// Scalars that carry one dual direction per nesting level: evaluating `f`
/// at `x + sum_k d_k eps_k` gives `D^r f [d_1, ..., d_r]` as the coefficient
/// of `eps_1 ... eps_r`.
trait Nested: Scalar {
    fn lift(x: f64, dirs: &[f64]) -> Self;
    fn top(&self) -> f64;
}

impl Nested for f64 {
    fn lift(x: f64, _: &[f64]) -> Self {
        x
    }
    fn top(&self) -> f64 {
        *self
    }
}

impl<T: Nested> Nested for Dual<T>
where
    Dual<T>: Scalar,
{
    fn lift(x: f64, dirs: &[f64]) -> Self {
        let (last, rest) = dirs
            .split_last()
            .map(|(l, r)| (*l, r))
            .unwrap_or((0.0, &[]));
        Dual::new(T::lift(x, rest), T::from(last))
    }
    fn top(&self) -> f64 {
        self.eps.top()
    }
}

type N2 = Dual<Dual64>;
type N3 = Dual<N2>;
type N4 = Dual<N3>;
type N5 = Dual<N4>;

fn mixed_nested<T: Nested, S: VectorField>(
    sys: &S,
    x: &[f64],
    p: &[f64],
    dirs: &[Vec<f64>],
) -> DVector<f64> {
    let xd: Vec<T> = (0..x.len())
        .map(|i| {
            let d: Vec<f64> = dirs.iter().map(|v| v[i]).collect();
            T::lift(x[i], &d)
        })
        .collect();
    let pd: Vec<T> = p.iter().map(|&v| T::from(v)).collect();
    let mut out = vec![T::from(0.0); sys.dim()];
    sys.rhs(&xd, &pd, &mut out);
    DVector::from_iterator(out.len(), out.iter().map(|v| v.top()))
}

/// Real mixed derivative `D^r f(x) [d_1, ..., d_r]`, `2 <= r <= 5`.
fn mixed<S: VectorField>(sys: &S, x: &[f64], p: &[f64], dirs: &[Vec<f64>]) -> DVector<f64> {
    match dirs.len() {
        2 => mixed_nested::<N2, S>(sys, x, p, dirs),
        3 => mixed_nested::<N3, S>(sys, x, p, dirs),
        4 => mixed_nested::<N4, S>(sys, x, p, dirs),
        _ => mixed_nested::<N5, S>(sys, x, p, dirs),
    }
}

/// Complex multilinear form `D^r f [u_1, ..., u_r]`, expanded over the real
/// and imaginary parts of its arguments.
fn form<S: VectorField>(
    sys: &S,
    x: &[f64],
    p: &[f64],
    args: &[&DVector<Complex64>],
) -> DVector<Complex64> {
    let n = x.len();
    let r = args.len();
    let mut out = DVector::from_element(n, Complex64::new(0.0, 0.0));
    'choice: for mask in 0..(1usize << r) {
        let mut coef = Complex64::new(1.0, 0.0);
        let mut dirs = Vec::with_capacity(r);
        for (i, a) in args.iter().enumerate() {
            let imag = mask >> i & 1 == 1;
            let d: Vec<f64> = a.iter().map(|z| if imag { z.im } else { z.re }).collect();
            if d.iter().all(|&v| v == 0.0) {
                continue 'choice;
            }
            if imag {
                coef *= Complex64::i();
            }
            dirs.push(d);
        }
        out += mixed(sys, x, p, &dirs).map(|t| coef * t);
    }
    out
}

type Key = (usize, usize);

/// All ordered `r`-tuples of keys of `a` whose exponents add up to `target`.
fn tuples(keys: &[Key], r: usize, target: Key) -> Vec<Vec<Key>> {
    if r == 0 {
        return if target == (0, 0) {
            vec![vec![]]
        } else {
            vec![]
        };
    }
    let mut out = Vec::new();
    for &k in keys {
        if k.0 <= target.0 && k.1 <= target.1 {
            for mut rest in tuples(keys, r - 1, (target.0 - k.0, target.1 - k.1)) {
                rest.insert(0, k);
                out.push(rest);
            }
        }
    }
    out
}

/// Computes `c1`, `c2`, `l1`, `l2` at the Hopf point `(x, p)` with frequency `omega`.
pub fn hopf_series<S: VectorField>(
    sys: &S,
    x: &[f64],
    p: &[f64],
    omega: f64,
) -> Result<HopfSeries, ContinuationError> {
    let n = x.len();
    let pencil = HopfPencil::new(&jacobian(sys, x, p), omega)?;
    let omega = pencil.omega;
    let q = pencil.q.clone();
    // Worst componentwise condition of the solves so far, and the size of
    // the terms of the last resonant right-hand side.
    let mut cond = 1.0f64;
    let mut size = 0.0;
    let mut a: BTreeMap<Key, DVector<Complex64>> = BTreeMap::new();
    a.insert((1, 0), q.clone());
    a.insert((0, 1), q.map(|z| z.conj()));
    let mut nf: BTreeMap<Key, Complex64> = BTreeMap::new();
    let factorial = |r: usize| (1..=r).product::<usize>() as f64;
    for d in 2..=5usize {
        for k in 0..=d / 2 {
            let j = d - k;
            if d == 5 && (j, k) != (3, 2) {
                continue;
            }
            let keys: Vec<Key> = a.keys().copied().collect();
            let mut rhs = DVector::from_element(n, Complex64::new(0.0, 0.0));
            let mut rhs_size = DVector::<f64>::zeros(n);
            for r in 2..=d {
                for t in tuples(&keys, r, (j, k)) {
                    let args: Vec<&DVector<Complex64>> = t.iter().map(|key| &a[key]).collect();
                    let term = form(sys, x, p, &args) / Complex64::from(factorial(r));
                    rhs_size += term.map(|z| z.norm());
                    rhs += term;
                }
            }
            // Known normal-form terms of order >= 3 acting on lower-order H.
            for (&(l, m), &c) in nf.iter().filter(|(key, _)| **key != (1, 0)) {
                // H_z N: j' a_{j'k'} with j' - 1 + l = j, k' + m = k.
                if j + 1 >= l && k >= m {
                    if let Some(ak) = a.get(&(j + 1 - l, k - m)) {
                        let term = ak * (c * (j + 1 - l) as f64);
                        rhs_size += term.map(|z| z.norm());
                        rhs -= term;
                    }
                }
                // H_zbar Nbar: Nbar has conj(c) at monomial (m, l); k' a_{j'k'} with j' + m = j, k' - 1 + l = k.
                if j >= m && k + 1 >= l {
                    if let Some(ak) = a.get(&(j - m, k + 1 - l)) {
                        let term = ak * (c.conj() * (k + 1 - l) as f64);
                        rhs_size += term.map(|z| z.norm());
                        rhs -= term;
                    }
                }
            }
            let ajk = if j == k + 1 {
                let (c, _) = pencil.project(&rhs);
                size = pencil
                    .p
                    .iter()
                    .zip(rhs_size.iter())
                    .map(|(a, b)| a.norm() * b)
                    .sum();
                nf.insert((j, k), c);
                if d == 5 {
                    break;
                }
                let (ajk, kappa) = pencil.resolve_resonant(&rhs)?;
                cond = cond.max(kappa);
                ajk
            } else {
                let sigma = Complex64::new(0.0, omega * (j as f64 - k as f64));
                let (ajk, kappa) = pencil.resolve(sigma, &rhs)?;
                cond = cond.max(kappa);
                ajk
            };
            if j != k {
                a.insert((k, j), ajk.map(|z| z.conj()));
            }
            a.insert((j, k), ajk);
        }
    }
    let c1 = nf.get(&(2, 1)).copied().unwrap_or_default();
    let c2 = nf.get(&(3, 2)).copied().unwrap_or_default();
    Ok(HopfSeries {
        omega,
        c1,
        c2,
        l1: c1.re / omega,
        l2: c2.re / omega,
        l2_error_bound: (rounding_factor(n) * cond + pencil.eigen_error()) * size / omega,
    })
}
