//! The derivatives the fold-of-cycles system needs beyond the collocation
//! Jacobian: the column of a second parameter, and the gradient of
//! `psi^T A v` from exact second derivatives of the vector field.

use crate::periodic::collocation::Collocation;
use crate::system::{
    jacobian, param_derivative, second_derivative_into, JointDirection, VectorField,
};

/// The gradient of `phi = psi^T A v` over `(u, T, p1[, p2])` and, with a
/// second parameter `k2`, the column `dF/dp2`. On the collocation row of
/// point `x` (interval length `h`), `(A v) = v' - h T Df(x) v_x - h v_T f(x)`.
pub(super) fn adjoint_gradient<S: VectorField>(
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
