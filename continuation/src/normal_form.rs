//! Normal-form coefficients of a Hopf point (Kuznetsov 1998, §3.5 and §10.2).
//!
//! With `A = D_x f`, `A q = i w q`, `A^T p = -i w p`, `<q, q> = 1`,
//! `<p, q> = 1` (`<a, b> = conj(a) . b`):
//!
//! ```text
//! c1 = 1/2 <p, C(q,q,qbar)> - <p, B(q, A^-1 B(q,qbar))> + 1/2 <p, B(qbar, (2iw - A)^-1 B(q,q))>
//! l1 = Re(c1) / w                                              (Kuznetsov 1998, eq. 3.20)
//! ```
//!
//! so that `l1 < 0` is a supercritical Hopf bifurcation. The restriction to
//! the centre manifold reads `z' = (alpha + i w) z + c1 z |z|^2` with
//! `x = x0 + 2 Re(z q) + ...`; hence, with `lambda'` the derivative of the
//! critical eigenvalue along a parameter, the emerging cycle has
//! `|z|^2 = -Re(lambda') (p - p_c) / Re(c1)` and component `j` oscillates with
//! peak-to-peak amplitude `4 |q_j| |z|`.

use crate::error::ContinuationError;
use crate::linalg::{eigenpair_near, solve_complex};
use crate::multilinear::At;
use crate::system::{jacobian, param_derivative, second_derivative, JointDirection, VectorField};
use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

/// The first normal-form coefficient at a Hopf point and what it is made of.
#[derive(Clone, Debug)]
pub struct HopfNormalForm {
    /// Angular frequency `w > 0`.
    pub omega: f64,
    /// Right critical eigenvector, `<q, q> = 1`.
    pub q: DVector<Complex64>,
    /// Adjoint critical eigenvector, `<p, q> = 1`.
    pub p: DVector<Complex64>,
    /// Cubic normal-form coefficient `c1`.
    pub c1: Complex64,
    /// First Lyapunov coefficient `l1 = Re(c1) / w`.
    pub l1: f64,
    /// Sum of the moduli of the three terms of `c1`, divided by `w`: the scale
    /// against which a vanishing `l1` is judged.
    pub term_scale: f64,
}

impl HopfNormalForm {
    /// Whether `|l1|` is at rounding level compared with its terms
    /// (`|l1| <= rel_tol * term_scale`): a degenerate Hopf point.
    pub fn is_degenerate(&self, rel_tol: f64) -> bool {
        self.l1.abs() <= rel_tol * self.term_scale
    }
}

fn dotc(a: &DVector<Complex64>, b: &DVector<Complex64>) -> Complex64 {
    a.dotc(b)
}

/// Computes `c1` and `l1` at the Hopf point `(x, p)` with frequency `omega`.
pub fn hopf_normal_form<S: VectorField>(
    sys: &S,
    x: &[f64],
    p: &[f64],
    omega: f64,
) -> Result<HopfNormalForm, ContinuationError> {
    let omega = omega.abs();
    let a = jacobian(sys, x, p);
    let iw = Complex64::new(0.0, omega);
    let (_, q) = eigenpair_near(&a, iw)?;
    let (_, pt) = eigenpair_near(&a.transpose(), -iw)?;
    let q = &q / Complex64::from(q.norm());
    let s = dotc(&pt, &q);
    let padj = pt / s.conj();
    let at = At { sys, x, p };
    let qb = q.map(|z| z.conj());
    let ac = a.map(Complex64::from);
    let n = x.len();
    let eye = DMatrix::<Complex64>::identity(n, n);
    let h11 = solve_complex(ac.clone(), &at.b(&q, &qb))?;
    let h20 = solve_complex(eye * Complex64::new(0.0, 2.0 * omega) - &ac, &at.b(&q, &q))?;
    let t1 = dotc(&padj, &at.c(&q, &q, &qb)) * 0.5;
    let t2 = -dotc(&padj, &at.b(&q, &h11));
    let t3 = dotc(&padj, &at.b(&qb, &h20)) * 0.5;
    let c1 = t1 + t2 + t3;
    Ok(HopfNormalForm {
        omega,
        q,
        p: padj,
        c1,
        l1: c1.re / omega,
        term_scale: (t1.norm() + t2.norm() + t3.norm()) / omega,
    })
}

/// Coefficient `a` of the fold normal form `y' = beta + a y^2` on the centre
/// manifold of a limit point: `a = 1/2 <p, B(q, q)>` with `A q = 0`,
/// `A^T p = 0`, `<q, q> = 1`, `<p, q> = 1` (Kuznetsov 1998, §3.2 and §5.4,
/// projection method); `a != 0` makes the fold nondegenerate.
pub fn fold_coefficient<S: VectorField>(
    sys: &S,
    x: &[f64],
    p: &[f64],
) -> Result<f64, ContinuationError> {
    let a = jacobian(sys, x, p);
    let zero = Complex64::new(0.0, 0.0);
    let q = eigenpair_near(&a, zero)?.1.map(|z| z.re);
    let q = &q / q.norm();
    let pt = eigenpair_near(&a.transpose(), zero)?.1.map(|z| z.re);
    let padj = &pt / pt.dot(&q);
    let b = second_derivative(
        sys,
        x,
        p,
        JointDirection::state(q.as_slice()),
        JointDirection::state(q.as_slice()),
    );
    Ok(0.5 * padj.dot(&b))
}

/// Derivative of the critical eigenvalue along parameter `k`,
/// `lambda' = <p, (D_pk A + B(., x_pk)) q>` with `x_pk = -A^-1 D_pk f` the
/// motion of the equilibrium (Kuznetsov 1998, §3.5, transversality).
pub fn eigenvalue_derivative<S: VectorField>(
    sys: &S,
    x: &[f64],
    par: &[f64],
    k: usize,
    nf: &HopfNormalForm,
) -> Result<Complex64, ContinuationError> {
    let a = jacobian(sys, x, par);
    let fp = param_derivative(sys, x, par, k);
    let xp = crate::linalg::solve(a, &(-fp))?;
    let mut ek = vec![0.0; par.len()];
    ek[k] = 1.0;
    let mut dq = DVector::from_element(x.len(), Complex64::new(0.0, 0.0));
    let qr: Vec<f64> = nf.q.iter().map(|z| z.re).collect();
    let qi: Vec<f64> = nf.q.iter().map(|z| z.im).collect();
    let dir = JointDirection {
        x: xp.as_slice(),
        p: &ek,
    };
    for (v, c) in [
        (qr, Complex64::new(1.0, 0.0)),
        (qi, Complex64::new(0.0, 1.0)),
    ] {
        dq += second_derivative(sys, x, par, JointDirection::state(&v), dir).map(|t| c * t);
    }
    Ok(dotc(&nf.p, &dq))
}

/// The cycle born at a Hopf point, to leading order in `p - p_c`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OnsetLaw {
    /// Peak-to-peak amplitude of component `j`: `Delta_j ~ coefficient sqrt|p - p_c|`,
    /// `coefficient = 4 |q_j| sqrt|Re(lambda') / Re(c1)|`.
    pub coefficient: f64,
    /// `+1` if the cycle exists for `p > p_c`, `-1` for `p < p_c`.
    pub side: f64,
    /// Frequency shift on the cycle, `d w / d p = Im(lambda') - Im(c1) Re(lambda') / Re(c1)`.
    pub frequency_slope: f64,
}

/// Leading-order amplitude and frequency of the emerging cycle in component `j`.
pub fn onset_law(nf: &HopfNormalForm, dlambda: Complex64, j: usize) -> OnsetLaw {
    let ratio = dlambda.re / nf.c1.re;
    OnsetLaw {
        coefficient: 4.0 * nf.q[j].norm() * ratio.abs().sqrt(),
        side: if ratio < 0.0 { 1.0 } else { -1.0 },
        frequency_slope: dlambda.im - nf.c1.im * ratio,
    }
}
