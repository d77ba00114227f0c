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

    /// Minimum and maximum of component `j` over the orbit: the extreme
    /// samples (8 per interval) refined by golden-section search on the
    /// piecewise polynomial between their neighbours.
    pub fn range(&self, j: usize) -> (f64, f64) {
        let samples = self.samples(8);
        let k = samples.len() - 1;
        let pick = |sign: f64| {
            let (i, _) = samples[..k]
                .iter()
                .enumerate()
                .max_by(|a, b| (sign * a.1 .1[j]).total_cmp(&(sign * b.1 .1[j])))
                .unwrap_or((0, &samples[0]));
            let (lo, hi) = (
                if i == 0 {
                    samples[k - 1].0 - 1.0
                } else {
                    samples[i - 1].0
                },
                samples[i + 1].0,
            );
            sign * golden_max(|tau| sign * self.state_at(tau.rem_euclid(1.0))[j], lo, hi)
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
