//! Mesh adaptation by equidistribution (Russell & Christiansen 1978; the
//! AUTO-07p strategy): the new mesh puts equal shares of
//! `int |u^(m)|^(1/(m+1)) dtau` in every interval, which balances the local
//! collocation error `h^(m+1) |u^(m+1)|`.

use super::cycle::Cycle;

/// The `m`-th derivative (in `tau`) of the local polynomial of every
/// interval: the `m`-th divided difference of its `m + 1` node values.
fn mth_derivatives(c: &Cycle) -> Vec<Vec<f64>> {
    let m = c.mesh.degree;
    let binom = |k: usize| (0..k).fold(1.0, |acc, j| acc * (m - j) as f64 / (j + 1) as f64);
    (0..c.mesh.ntst())
        .map(|i| {
            let h = c.mesh.t[i + 1] - c.mesh.t[i];
            (0..c.n)
                .map(|j| {
                    let mut d = 0.0;
                    for l in 0..=m {
                        let sign = if (m - l).is_multiple_of(2) { 1.0 } else { -1.0 };
                        d += sign * binom(l) * c.node(c.mesh.node(i, l))[j];
                    }
                    // Step between nodes is h/m: the m-th derivative is d (m/h)^m.
                    d * (m as f64 / h).powi(m as i32)
                })
                .collect()
        })
        .collect()
}

/// The monitor `|u^(m)|^(1/(m+1))` of every interval.
fn monitor(c: &Cycle) -> Vec<f64> {
    let m = c.mesh.degree;
    mth_derivatives(c)
        .iter()
        .map(|d| {
            let norm = d.iter().map(|v| v * v).sum::<f64>().sqrt();
            norm.powf(1.0 / (m as f64 + 1.0))
        })
        .collect()
}

/// A mesh of `ntst` intervals equidistributing the monitor of `c` (with a
/// floor so that no region is left without points), the orbit moved onto it.
pub fn equidistribute(c: &Cycle, ntst: usize) -> Cycle {
    let w = monitor(c);
    let mean = w
        .iter()
        .zip(c.mesh.t.windows(2))
        .map(|(w, t)| w * (t[1] - t[0]))
        .sum::<f64>();
    let floor = 0.05 * mean.max(f64::MIN_POSITIVE);
    let dens: Vec<f64> = w.iter().map(|v| v.max(floor)).collect();
    let mut cum = vec![0.0];
    for (i, d) in dens.iter().enumerate() {
        let last = cum[cum.len() - 1];
        cum.push(last + d * (c.mesh.t[i + 1] - c.mesh.t[i]));
    }
    let total = cum[cum.len() - 1];
    let mut t = vec![0.0];
    let mut i = 0;
    for s in 1..ntst {
        let target = total * s as f64 / ntst as f64;
        while cum[i + 1] < target {
            i += 1;
        }
        let frac = (target - cum[i]) / (cum[i + 1] - cum[i]);
        t.push(c.mesh.t[i] + frac * (c.mesh.t[i + 1] - c.mesh.t[i]));
    }
    t.push(1.0);
    c.remesh(c.mesh.on(t))
}
