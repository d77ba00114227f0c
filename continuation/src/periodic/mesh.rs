//! Collocation meshes: `NTST` intervals of `[0, 1]`, a degree-`m` polynomial
//! on each, represented by its values at `m + 1` equally spaced nodes, and
//! collocation at `m` points of every interval: the Gauss–Legendre points
//! (de Boor & Swartz 1973; Doedel, AUTO-07p manual, §"orthogonal
//! collocation") or the Radau IIA points (Hairer & Wanner, *Solving ODEs II*,
//! §IV.5), which make the scheme L-stable for stiff orbits.

use smallvec::SmallVec;
use std::ops::Deref;
use std::sync::{Arc, Mutex, PoisonError};

/// Gauss–Legendre points on `(0, 1)` and their weights, by Newton's method
/// on the Legendre polynomial `P_m` (three-term recurrence).
pub fn gauss_legendre(m: usize) -> (Vec<f64>, Vec<f64>) {
    let mut nodes = Vec::with_capacity(m);
    let mut weights = Vec::with_capacity(m);
    for i in 0..m {
        // Chebyshev-like initial guess on (-1, 1), descending.
        let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (m as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, x);
            for k in 2..=m {
                let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = p2;
            }
            let pm = if m == 0 { 1.0 } else { p1 };
            let pm1 = if m == 0 { 0.0 } else { p0 };
            dp = m as f64 * (x * pm - pm1) / (x * x - 1.0);
            let dx = pm / dp;
            x -= dx;
            if dx.abs() < 1e-16 {
                break;
            }
        }
        nodes.push(0.5 * (1.0 - x));
        weights.push(1.0 / ((1.0 - x * x) * dp * dp));
    }
    (nodes, weights)
}

/// The Radau IIA points on `(0, 1]` (right end included) and their
/// quadrature weights: the zeros of `P_m(2z - 1) - P_{m-1}(2z - 1)`, found by
/// bisection between sign changes on a fine grid; the weights make the
/// quadrature exact for polynomials of degree `m - 1` (it then is for `2m - 2`).
pub fn radau_right(m: usize) -> (Vec<f64>, Vec<f64>) {
    let q = |x: f64| {
        let xi = 2.0 * x - 1.0;
        let (mut p0, mut p1) = (1.0, xi);
        for k in 2..=m {
            let p2 = ((2 * k - 1) as f64 * xi * p1 - (k - 1) as f64 * p0) / k as f64;
            p0 = p1;
            p1 = p2;
        }
        p1 - p0
    };
    let grid = 64 * m;
    let mut nodes = Vec::with_capacity(m);
    for g in 0..grid - 1 {
        let (mut a, mut b) = (g as f64 / grid as f64, (g + 1) as f64 / grid as f64);
        let mut qa = q(a);
        if qa * q(b) > 0.0 {
            continue;
        }
        for _ in 0..80 {
            let c = 0.5 * (a + b);
            let qc = q(c);
            if qa * qc <= 0.0 {
                b = c;
            } else {
                (a, qa) = (c, qc);
            }
        }
        nodes.push(0.5 * (a + b));
    }
    nodes.push(1.0);
    let moments = nalgebra::DMatrix::from_fn(m, m, |k, i| nodes[i].powi(k as i32));
    let rhs = nalgebra::DVector::from_fn(m, |k, _| 1.0 / (k as f64 + 1.0));
    let weights = moments
        .lu()
        .solve(&rhs)
        .map_or_else(Vec::new, |w| w.iter().copied().collect());
    (nodes, weights)
}

/// Values `L_l(z)` and derivatives `L_l'(z)` of the Lagrange basis on the
/// equally spaced nodes `l / m`, `l = 0..=m`, at the point `z` in `[0, 1]`.
pub fn lagrange(m: usize, z: f64) -> (Vec<f64>, Vec<f64>) {
    let nodes: Vec<f64> = (0..=m).map(|l| l as f64 / m as f64).collect();
    let mut val = vec![0.0; m + 1];
    let mut der = vec![0.0; m + 1];
    for l in 0..=m {
        let mut v = 1.0;
        for (j, &xj) in nodes.iter().enumerate() {
            if j != l {
                v *= (z - xj) / (nodes[l] - xj);
            }
        }
        val[l] = v;
        let mut d = 0.0;
        for (k, &xk) in nodes.iter().enumerate() {
            if k == l {
                continue;
            }
            let mut term = 1.0 / (nodes[l] - xk);
            for (j, &xj) in nodes.iter().enumerate() {
                if j != l && j != k {
                    term *= (z - xj) / (nodes[l] - xj);
                }
            }
            d += term;
        }
        der[l] = d;
    }
    (val, der)
}

/// Values `L_l(z)` of the Lagrange basis on the equally spaced nodes `l / m`
/// (no derivatives, no heap allocation for `m < 8`): for evaluating orbits.
pub fn lagrange_values(m: usize, z: f64) -> SmallVec<[f64; 8]> {
    let mut values = SmallVec::from_elem(0.0, m + 1);
    lagrange_into(m, z, &mut values);
    values
}

/// [`lagrange_values`] written into `out[..=m]`: `L_l(z) = prod_{j != l}
/// (z - x_j) / (x_l - x_j)`, `x_j = j / m`, the factors in increasing `j`.
/// Compiled once more for `m = 4` (the default degree) with the nodes as
/// constants and the loops unrolled: the same operations in the same order,
/// so the same values to the bit.
#[inline]
pub fn lagrange_into(m: usize, z: f64, out: &mut [f64]) {
    match m {
        4 => lagrange_fixed::<5>(z, out),
        _ => {
            let nodes: SmallVec<[f64; 8]> = (0..=m).map(|j| j as f64 / m as f64).collect();
            lagrange_on(&nodes, z, out);
        }
    }
}

/// [`lagrange_into`] with the number of nodes `P = m + 1` constant.
#[inline(always)]
fn lagrange_fixed<const P: usize>(z: f64, out: &mut [f64]) {
    let mut nodes = [0.0; P];
    for (j, x) in nodes.iter_mut().enumerate() {
        *x = j as f64 / (P - 1) as f64;
    }
    lagrange_on(&nodes, z, out);
}

/// The Lagrange basis on `nodes` at `z`, into `out[..nodes.len()]`.
#[inline(always)]
fn lagrange_on(nodes: &[f64], z: f64, out: &mut [f64]) {
    for (l, (value, &xl)) in out[..nodes.len()].iter_mut().zip(nodes).enumerate() {
        let mut v = 1.0;
        for (j, &xj) in nodes.iter().enumerate() {
            if j != l {
                v *= (z - xj) / (xl - xj);
            }
        }
        *value = v;
    }
}

/// Where the collocation equations are imposed in every interval.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CollocationPoints {
    /// Gauss–Legendre: order `2m` at the mesh points; A-stable but not
    /// L-stable — a stiff component is pinned to its slow manifold at the
    /// Gauss points only, and between them its polynomial may oscillate.
    #[default]
    Gauss,
    /// Radau IIA (right end of the interval included): order `2m - 1` at the
    /// mesh points and L-stable: on stiff stretches (the stuck phase of
    /// stick-slip, where the velocity relaxes at rates of `1e10`) every
    /// mesh point lies on the slow manifold and the polynomials stay smooth.
    Radau,
}

/// The collocation tableau of one degree and kind of collocation points:
/// the points on `(0, 1]`, their quadrature weights and the Lagrange basis
/// on the interval's `m + 1` equidistant nodes, with its derivative, at
/// each point. Built once per degree and kind ([`Tableau::shared`]) and
/// shared by every mesh that uses it.
#[derive(Debug, PartialEq)]
pub struct Tableau {
    /// Polynomial degree `m`.
    pub degree: usize,
    /// Which collocation points.
    pub points: CollocationPoints,
    /// Collocation points on `(0, 1]` and their quadrature weights.
    pub nodes: Vec<f64>,
    pub weights: Vec<f64>,
    /// `basis[k][l] = L_l(z_k)`, `dbasis[k][l] = L_l'(z_k)` at collocation
    /// point `z_k` (derivative in the local variable).
    pub basis: Vec<Vec<f64>>,
    pub dbasis: Vec<Vec<f64>>,
}

impl Tableau {
    fn new(degree: usize, points: CollocationPoints) -> Self {
        let (nodes, weights) = match points {
            CollocationPoints::Gauss => gauss_legendre(degree),
            CollocationPoints::Radau => radau_right(degree),
        };
        let (basis, dbasis) = nodes.iter().map(|&z| lagrange(degree, z)).unzip();
        Tableau {
            degree,
            points,
            nodes,
            weights,
            basis,
            dbasis,
        }
    }

    /// The tableau of `degree` and `points`: built at the first request
    /// (the Radau points by bisection), the same one afterwards.
    pub fn shared(degree: usize, points: CollocationPoints) -> Arc<Tableau> {
        static BUILT: Mutex<Vec<Arc<Tableau>>> = Mutex::new(Vec::new());
        // A panic elsewhere while the list was held leaves it intact
        // (entries are pushed whole): poisoning is no reason to fail.
        let mut built = BUILT.lock().unwrap_or_else(PoisonError::into_inner);
        if let Some(t) = built
            .iter()
            .find(|t| t.degree == degree && t.points == points)
        {
            return Arc::clone(t);
        }
        let tableau = Arc::new(Tableau::new(degree, points));
        built.push(Arc::clone(&tableau));
        tableau
    }
}

/// A collocation mesh: its points and the shared [`Tableau`] of its degree
/// and collocation points (read through the mesh: `mesh.degree`,
/// `mesh.basis`, ...). A clone copies the mesh points only.
#[derive(Clone, Debug)]
pub struct Mesh {
    /// Mesh points `0 = t_0 < ... < t_NTST = 1`.
    pub t: Vec<f64>,
    tableau: Arc<Tableau>,
}

impl Deref for Mesh {
    type Target = Tableau;

    fn deref(&self) -> &Tableau {
        &self.tableau
    }
}

impl Mesh {
    /// A Gauss mesh on the given points (strictly increasing, from 0 to 1).
    pub fn new(t: Vec<f64>, degree: usize) -> Self {
        Mesh::with_points(t, degree, CollocationPoints::Gauss)
    }

    /// A mesh on the given points with the given collocation points.
    pub fn with_points(t: Vec<f64>, degree: usize, points: CollocationPoints) -> Self {
        Mesh {
            t,
            tableau: Tableau::shared(degree, points),
        }
    }

    /// A mesh of the same degree and collocation points on other mesh points.
    pub fn on(&self, t: Vec<f64>) -> Self {
        Mesh {
            t,
            tableau: Arc::clone(&self.tableau),
        }
    }

    /// A uniform mesh of `ntst` intervals.
    pub fn uniform(ntst: usize, degree: usize, points: CollocationPoints) -> Self {
        Mesh::with_points(
            (0..=ntst).map(|i| i as f64 / ntst as f64).collect(),
            degree,
            points,
        )
    }

    /// Number of intervals.
    pub fn ntst(&self) -> usize {
        self.t.len() - 1
    }

    /// Number of distinct nodes (the last node is the first: periodicity).
    pub fn n_nodes(&self) -> usize {
        self.ntst() * self.degree
    }

    /// Global node index of local node `l` of interval `i` (periodic).
    pub fn node(&self, i: usize, l: usize) -> usize {
        (i * self.degree + l) % self.n_nodes()
    }

    /// Normalized time of node `(i, l)`.
    pub fn node_time(&self, i: usize, l: usize) -> f64 {
        self.t[i] + (self.t[i + 1] - self.t[i]) * l as f64 / self.degree as f64
    }

    /// Interval containing normalized time `tau` in `[0, 1]` and the local coordinate.
    pub fn locate(&self, tau: f64) -> (usize, f64) {
        let tau = tau.rem_euclid(1.0);
        let i = match self.t.binary_search_by(|x| x.total_cmp(&tau)) {
            Ok(i) => i.min(self.ntst() - 1),
            Err(i) => i.saturating_sub(1).min(self.ntst() - 1),
        };
        (i, (tau - self.t[i]) / (self.t[i + 1] - self.t[i]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lagrange_basis_compiled_for_degree_4_is_the_general_one_to_the_bit() {
        // The product written out with the degree hidden from the compiler.
        let reference = |m: usize, z: f64| -> Vec<f64> {
            let m = std::hint::black_box(m);
            let x = |j: usize| j as f64 / m as f64;
            (0..=m)
                .map(|l| {
                    (0..=m)
                        .filter(|&j| j != l)
                        .fold(1.0, |v, j| v * ((z - x(j)) / (x(l) - x(j))))
                })
                .collect()
        };
        for m in 1..=9 {
            for k in -40..=440 {
                let z = k as f64 / 400.0 + 1e-3 * (k as f64).sin();
                let mut out = vec![f64::NAN; m + 1];
                lagrange_into(m, z, &mut out);
                let expected = reference(m, z);
                assert!(
                    out.iter()
                        .zip(&expected)
                        .all(|(a, b)| a.to_bits() == b.to_bits()),
                    "m = {m}, z = {z}: {out:?} against {expected:?}"
                );
                assert_eq!(lagrange_values(m, z).as_slice(), &out[..]);
            }
        }
    }

    #[test]
    fn gauss_legendre_integrates_degree_2m_minus_1_exactly() {
        for m in 1..=7 {
            let (z, w) = gauss_legendre(m);
            for d in 0..2 * m {
                let q: f64 = z.iter().zip(&w).map(|(z, w)| w * z.powi(d as i32)).sum();
                assert!(
                    (q - 1.0 / (d as f64 + 1.0)).abs() < 1e-14,
                    "m = {m}, degree {d}"
                );
            }
        }
    }

    #[test]
    fn radau_points_are_the_tableau_and_integrate_degree_2m_minus_2_exactly() {
        for m in 1..=7 {
            let (z, w) = radau_right(m);
            assert_eq!(z.len(), m);
            assert_eq!(z[m - 1], 1.0);
            for d in 0..2 * m - 1 {
                let q: f64 = z.iter().zip(&w).map(|(z, w)| w * z.powi(d as i32)).sum();
                assert!(
                    (q - 1.0 / (d as f64 + 1.0)).abs() < 1e-13,
                    "m = {m}, degree {d}"
                );
            }
        }
        // Radau IIA, three stages (Hairer & Wanner, Table IV.5.6): (4 -+ sqrt 6)/10, 1.
        let (z, _) = radau_right(3);
        let s6 = 6f64.sqrt();
        assert!((z[0] - (4.0 - s6) / 10.0).abs() < 1e-15);
        assert!((z[1] - (4.0 + s6) / 10.0).abs() < 1e-15);
    }

    #[test]
    fn lagrange_basis_reproduces_polynomials_and_derivatives() {
        let m = 4;
        let p = |x: f64| 1.0 - 2.0 * x + 3.0 * x.powi(3) - x.powi(4);
        let dp = |x: f64| -2.0 + 9.0 * x * x - 4.0 * x.powi(3);
        let values: Vec<f64> = (0..=m).map(|l| p(l as f64 / m as f64)).collect();
        for z in [0.0, 0.13, 0.5, 0.91] {
            let (v, d) = lagrange(m, z);
            let pv: f64 = v.iter().zip(&values).map(|(a, b)| a * b).sum();
            let pd: f64 = d.iter().zip(&values).map(|(a, b)| a * b).sum();
            assert!((pv - p(z)).abs() < 1e-13 && (pd - dp(z)).abs() < 1e-12);
        }
    }
}
