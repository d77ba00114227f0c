//! A periodic orbit on a collocation mesh: node values, period, parameters.

use super::mesh::{lagrange_values, Mesh};

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
        (0..self.n).map(|j| self.value_at(tau, j)).collect()
    }

    /// Component `j` of the state at normalized time `tau`.
    pub fn value_at(&self, tau: f64, j: usize) -> f64 {
        let (i, z) = self.mesh.locate(tau);
        lagrange_values(self.mesh.degree, z)
            .iter()
            .enumerate()
            .map(|(l, b)| b * self.node(self.mesh.node(i, l))[j])
            .sum()
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

    /// Minimum and maximum of component `j` over the orbit: the extreme
    /// samples (8 per interval) refined by golden-section search on the
    /// piecewise polynomial between their neighbours.
    pub fn range(&self, j: usize) -> (f64, f64) {
        let per = 8;
        let taus: Vec<f64> = (0..self.mesh.ntst())
            .flat_map(|i| {
                let (a, b) = (self.mesh.t[i], self.mesh.t[i + 1]);
                (0..per).map(move |s| a + (b - a) * s as f64 / per as f64)
            })
            .collect();
        let values: Vec<f64> = taus.iter().map(|&t| self.value_at(t, j)).collect();
        let k = taus.len();
        let pick = |sign: f64| {
            let i = (0..k)
                .max_by(|&a, &b| (sign * values[a]).total_cmp(&(sign * values[b])))
                .unwrap_or(0);
            let lo = if i == 0 {
                taus[k - 1] - 1.0
            } else {
                taus[i - 1]
            };
            let hi = if i + 1 == k { 1.0 } else { taus[i + 1] };
            sign * golden_max(|tau| sign * self.value_at(tau.rem_euclid(1.0), j), lo, hi)
        };
        (pick(-1.0), pick(1.0))
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

/// Maximum of a unimodal `f` on `[a, b]` by golden-section search.
fn golden_max(f: impl Fn(f64) -> f64, mut a: f64, mut b: f64) -> f64 {
    let g = 0.5 * (5f64.sqrt() - 1.0);
    let (mut c, mut d) = (b - g * (b - a), a + g * (b - a));
    let (mut fc, mut fd) = (f(c), f(d));
    for _ in 0..80 {
        if fc > fd {
            (b, d, fd) = (d, c, fc);
            c = b - g * (b - a);
            fc = f(c);
        } else {
            (a, c, fc) = (c, d, fd);
            d = a + g * (b - a);
            fd = f(d);
        }
        if (b - a).abs() < 1e-14 {
            break;
        }
    }
    fc.max(fd)
}
