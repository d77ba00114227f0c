//! The derivatives the fold-of-cycles system needs beyond the collocation
//! Jacobian: the column of a second parameter, and the gradient of
//! `psi^T A v` from exact second derivatives of the vector field (hyper-dual
//! evaluations, which give the first derivatives it needs as well).

use crate::periodic::collocation::Collocation;
use crate::system::{JointDirection, VectorField};

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
    // The directions of the derivatives: the state's unit vectors, then
    // p_k and p_k2.
    let params: Vec<(usize, usize)> = std::iter::once((coll.k, nn + 1))
        .chain(k2.map(|k| (k, nn + 2)))
        .collect();
    let unit = |len: usize, at: usize| {
        let mut e = vec![0.0; len];
        e[at] = 1.0;
        e
    };
    let states: Vec<Vec<f64>> = (0..n).map(|j| unit(n, j)).collect();
    let param_units: Vec<Vec<f64>> = params.iter().map(|&(k, _)| unit(p.len(), k)).collect();
    let ws: Vec<JointDirection> = states
        .iter()
        .map(|e| JointDirection::state(e))
        .chain(param_units.iter().map(|e| JointDirection { x: &[], p: e }))
        .collect();
    let (mut x, mut vx, mut jv) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let (mut first, mut second) = (vec![0.0; ws.len() * n], vec![0.0; ws.len() * n]);
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
            let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(a, b)| a * b).sum::<f64>();
            // One evaluation gives J v_x and, along each direction w, the
            // column J w (or dF/dp) and the second derivative along v_x and w.
            sys.derivatives_along(
                &x,
                &p,
                JointDirection::state(&vx),
                &ws,
                (&mut jv, &mut first, &mut second),
            );
            // The part of d phi along direction `d`.
            let along = |d: usize| {
                let block = d * n..(d + 1) * n;
                -h * period * dot(psi_k, &second[block.clone()])
                    - h * v_t * dot(psi_k, &first[block])
            };
            // d phi / d x_j, spread to the interval's nodes by the basis.
            for j in 0..n {
                let dphi = along(j);
                for l in 0..=m {
                    grad[coll.mesh.node(i, l) * n + j] += coll.mesh.basis[kk][l] * dphi;
                }
            }
            grad[nn] -= h * dot(psi_k, &jv);
            for (d, &(k, col)) in params.iter().enumerate() {
                grad[col] += along(n + d);
                if Some(k) == k2 {
                    for j in 0..n {
                        fp2[row + j] = -h * period * first[(n + d) * n + j];
                    }
                }
            }
        }
    }
    (grad, fp2)
}
