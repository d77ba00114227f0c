//! A periodic orbit on a collocation mesh: node values, period, parameters.

use super::mesh::{lagrange, Mesh};

/// A periodic orbit `x(t)`, `t` in `[0, T]`, as piecewise polynomials on a
/// [`Mesh`] of normalized time `tau = t / T`.
#[derive(Clone, Debug)]
pub struct Cycle {
    /// The mesh.
    pub mesh: Mesh,
    /// Node values, node-major: node `g` occupies `u[g n .. (g + 1) n]`.
    pub u: Vec<f64>,
    /// Period `T`.
    pub period: f64,
    /// Full parameter vector.
    pub p: Vec<f64>,
    /// State dimension.
    pub n: usize,
}

impl Cycle {
    /// Node value `g` (periodic index).
    pub fn node(&self, g: usize) -> &[f64] {
        let g = g % self.mesh.n_nodes();
        &self.u[g * self.n..(g + 1) * self.n]
    }

    /// The state at normalized time `tau` in `[0, 1]`.
    pub fn state_at(&self, tau: f64) -> Vec<f64> {
        let (i, z) = self.mesh.locate(tau);
        let (basis, _) = lagrange(self.mesh.degree, z);
        let mut x = vec![0.0; self.n];
        for (l, b) in basis.iter().enumerate() {
            let v = self.node(self.mesh.node(i, l));
            for j in 0..self.n {
                x[j] += b * v[j];
            }
        }
        x
    }

    /// Samples `(tau, x)` at `per_interval` evenly spaced points of every
    /// interval (closing with `tau = 1`).
    pub fn samples(&self, per_interval: usize) -> Vec<(f64, Vec<f64>)> {
        let mut out = Vec::new();
        for i in 0..self.mesh.ntst() {
            for s in 0..per_interval {
                let tau = self.mesh.t[i]
                    + (self.mesh.t[i + 1] - self.mesh.t[i]) * s as f64 / per_interval as f64;
                out.push((tau, self.state_at(tau)));
            }
        }
        out.push((1.0, self.state_at(0.0)));
        out
    }

    /// Minimum and maximum of component `j` over the orbit (sampled densely:
    /// 8 points per interval besides the nodes).
    pub fn range(&self, j: usize) -> (f64, f64) {
        self.samples(8)
            .iter()
            .map(|(_, x)| x[j])
            .chain((0..self.mesh.n_nodes()).map(|g| self.node(g)[j]))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                (lo.min(v), hi.max(v))
            })
    }

    /// Moves the orbit onto another mesh (same degree) by evaluating its polynomials.
    pub fn remesh(&self, mesh: Mesh) -> Cycle {
        let mut u = Vec::with_capacity(mesh.n_nodes() * self.n);
        for i in 0..mesh.ntst() {
            for l in 0..mesh.degree {
                u.extend(self.state_at(mesh.node_time(i, l)));
            }
        }
        Cycle {
            mesh,
            u,
            period: self.period,
            p: self.p.clone(),
            n: self.n,
        }
    }
}
