//! Continuation results against the closed forms of the seed's Appendix C
//! and against the roots of the exact characteristic cubic (eq. C9).

use continuation::system::jacobian;
use continuation::Complex64;
use continuation::{count_unstable, eigenvalues};
use stickslip::analysis::hopf::{find_hopf, HopfOutcome};
use stickslip::appendix_c;
use stickslip::model::{steady_state, DrivenBlock, ModelKind};
use stickslip::params::Params;

/// SplitMix64: a seeded generator, so the sweep is random but reproducible.
struct SplitMix(u64);
impl SplitMix {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
    fn log_uniform(&mut self, lo: f64, hi: f64) -> f64 {
        (lo.ln() + (hi.ln() - lo.ln()) * self.next()).exp()
    }
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// The sweep of issue 2: A in [1e-3, 0.05], B - A in [1e-3, 0.05],
/// mu2 in [0, 3e-3], nu over four decades, m = 0 or in [1e-4, 10].
fn sweep(n: usize, seed: u64) -> Vec<Params> {
    let mut rng = SplitMix(seed);
    (0..n)
        .map(|i| {
            let a = rng.uniform(1e-3, 0.05);
            let b = a + rng.uniform(1e-3, 0.05);
            let mu2 = if i % 4 == 0 {
                0.0
            } else {
                rng.uniform(0.0, 3e-3)
            };
            let nu = rng.log_uniform(0.01, 100.0);
            let m = if i % 3 == 0 {
                0.0
            } else {
                rng.log_uniform(1e-4, 10.0)
            };
            Params {
                kappa: 0.0,
                nu,
                m,
                a,
                b,
                mu0: rng.uniform(0.1, 0.9),
                mu2,
                theta_c: None,
                state_law: Default::default(),
                mu_vv: 0.0,
                mu_vphi: 0.0,
                eta_d: 0.0,
            }
        })
        .collect()
}

fn model_for(p: &Params) -> ModelKind {
    if p.m == 0.0 {
        ModelKind::QuasiStatic
    } else {
        ModelKind::Inertial
    }
}

#[test]
fn hopf_point_matches_c11_and_c13_over_a_random_sweep() {
    let (mut found, mut stable) = (0, 0);
    for p in sweep(400, 2026) {
        let kappa_ref = appendix_c::critical_stiffness(&p);
        match find_hopf(model_for(&p), &p).unwrap_or_else(|e| panic!("{p:?}: {e}")) {
            HopfOutcome::Found(h) => {
                found += 1;
                let omega_ref = appendix_c::critical_frequency(&p).unwrap();
                assert!(
                    rel(h.kappa_c, kappa_ref) < 1e-10,
                    "{p:?}: kappa_c {} vs {kappa_ref}",
                    h.kappa_c
                );
                assert!(
                    rel(h.omega_c, omega_ref) < 1e-10,
                    "{p:?}: omega_c {} vs {omega_ref}",
                    h.omega_c
                );
            }
            HopfOutcome::StableForAllStiffness { .. } => {
                // Only legitimate when the law is not velocity weakening here.
                stable += 1;
                assert!(
                    kappa_ref <= 0.0,
                    "{p:?}: no Hopf point found, but C11 gives {kappa_ref}"
                );
            }
        }
    }
    assert!(
        found > 300 && stable > 0,
        "sweep coverage: {found} Hopf points, {stable} stable cases"
    );
}

#[test]
fn hopf_point_of_the_cutoff_law_matches_c11_and_c13() {
    let mut rng = SplitMix(7);
    for _ in 0..60 {
        let a = rng.uniform(1e-3, 0.05);
        let b = a + rng.uniform(1e-3, 0.05);
        let theta_c = rng.log_uniform(1e-3, 1.0);
        // Stay below V_min = (B - A)/(A theta_c), where friction weakens.
        let nu = rng.uniform(0.05, 0.9) * (b - a) / (a * theta_c);
        let m = rng.log_uniform(1e-4, 10.0) / (nu * nu);
        let p = Params {
            kappa: 0.0,
            nu,
            m,
            a,
            b,
            mu0: 0.5,
            mu2: 0.0,
            theta_c: Some(theta_c),
            state_law: Default::default(),
            mu_vv: 0.0,
            mu_vphi: 0.0,
            eta_d: 0.0,
        };
        let HopfOutcome::Found(h) = find_hopf(ModelKind::Inertial, &p).unwrap() else {
            panic!("{p:?}: no Hopf")
        };
        assert!(
            rel(h.kappa_c, appendix_c::critical_stiffness(&p)) < 1e-10,
            "{p:?}"
        );
        assert!(
            rel(h.omega_c, appendix_c::critical_frequency(&p).unwrap()) < 1e-10,
            "{p:?}"
        );
    }
}

/// Roots of a real cubic by the Durand–Kerner iteration, polished by Newton:
/// an eigenvalue-free route to the spectrum.
fn cubic_roots(c: [f64; 4]) -> [Complex64; 3] {
    let [a3, a2, a1, a0] = c;
    let poly = |z: Complex64| ((z * a3 + a2) * z + a1) * z + a0;
    let dpoly = |z: Complex64| (z * (3.0 * a3) + 2.0 * a2) * z + a1;
    let scale = 1.0
        + [a2 / a3, a1 / a3, a0 / a3]
            .iter()
            .map(|v| v.abs())
            .fold(0.0, f64::max);
    let mut r = [0, 1, 2].map(|k| Complex64::from_polar(scale, 0.4 + 2.1 * k as f64));
    for _ in 0..500 {
        for i in 0..3 {
            let mut den = Complex64::from(a3);
            for j in 0..3 {
                if j != i {
                    den *= r[i] - r[j];
                }
            }
            r[i] -= poly(r[i]) / den;
        }
    }
    r.map(|mut z| {
        for _ in 0..3 {
            z -= poly(z) / dpoly(z);
        }
        z
    })
}

#[test]
fn inertial_frequency_matches_the_roots_of_the_cubic_c9() {
    for p in sweep(120, 99).into_iter().filter(|p| p.m > 0.0) {
        let HopfOutcome::Found(h) = find_hopf(ModelKind::Inertial, &p).unwrap() else {
            continue;
        };
        let mut at = p;
        at.kappa = h.kappa_c;
        let roots = cubic_roots(appendix_c::characteristic_polynomial(&at));
        let upper = roots
            .iter()
            .copied()
            .max_by(|a, b| a.im.total_cmp(&b.im))
            .unwrap();
        let scale = roots.iter().map(|z| z.norm()).fold(0.0, f64::max);
        assert!(
            upper.re.abs() < 1e-9 * scale,
            "{p:?}: Re of the critical root {}",
            upper.re
        );
        assert!(
            rel(upper.im, h.omega_c) < 1e-10,
            "{p:?}: cubic {} vs {}",
            upper.im,
            h.omega_c
        );
    }
}

#[test]
fn eigenvalues_equal_the_roots_of_the_cubic() {
    for p in sweep(60, 5).into_iter().filter(|p| p.m > 0.0) {
        let mut at = p;
        at.kappa = 0.37 * appendix_c::critical_stiffness(&p).abs() + 1e-3;
        let x = steady_state(ModelKind::Inertial, &at);
        let ev = eigenvalues(&jacobian(
            &DrivenBlock::new(ModelKind::Inertial, &at),
            &x,
            &at.to_vec(),
        ))
        .unwrap();
        let roots = cubic_roots(appendix_c::characteristic_polynomial(&at));
        for r in roots {
            let d = ev
                .iter()
                .map(|l| (l - r).norm())
                .fold(f64::INFINITY, f64::min);
            assert!(
                d < 1e-8 * r.norm().max(1.0),
                "{at:?}: root {r} has no eigenvalue nearby ({ev:?})"
            );
        }
    }
}

#[test]
fn large_stiffness_eigenvalues_approach_the_asymptotics() {
    // Leading terms: l1 -> -nu, l+- -> -mu_v/(2 m nu) +- i sqrt(kappa/m). From the
    // sum of the roots and l1 = -nu - mu_phi nu/kappa + O(1/kappa^2), the real parts
    // carry an O(1/kappa) error: error * kappa must settle to a constant.
    let base = Params {
        kappa: 0.0,
        nu: 1.0,
        m: 0.01,
        a: 0.012,
        b: 0.023,
        mu0: 0.6,
        mu2: 0.0,
        theta_c: None,
        state_law: Default::default(),
        mu_vv: 0.0,
        mu_vphi: 0.0,
        eta_d: 0.0,
    };
    let block = DrivenBlock::new(ModelKind::Inertial, &base);
    let mut scaled = Vec::new();
    for kappa in [1e2, 1e3, 1e4, 1e5] {
        let mut p = base;
        p.kappa = kappa;
        let ev = eigenvalues(&jacobian(
            &block,
            &steady_state(ModelKind::Inertial, &p),
            &p.to_vec(),
        ))
        .unwrap();
        let (real, pair) = appendix_c::large_stiffness_roots(&p);
        let l1 = ev.iter().find(|l| l.im == 0.0).unwrap();
        let lp = ev.iter().find(|l| l.im > 0.0).unwrap();
        assert!(rel(lp.im, pair.im) < 1e-3, "Im at kappa = {kappa}");
        let mu_phi = p.mu_phi();
        // Next-order terms for the real root and the real part of the pair.
        assert!(
            rel(l1.re, real - mu_phi * p.nu / kappa) < 50.0 / (kappa * kappa),
            "kappa = {kappa}"
        );
        assert!(
            rel(lp.re, pair.re + mu_phi * p.nu / (2.0 * kappa)) < 50.0 / (kappa * kappa),
            "kappa = {kappa}"
        );
        scaled.push((rel(lp.re, pair.re) * kappa, rel(l1.re, real) * kappa));
    }
    for w in scaled.windows(2) {
        assert!(
            rel(w[1].0, w[0].0) < 0.05 && rel(w[1].1, w[0].1) < 0.05,
            "O(1/kappa) rate: {scaled:?}"
        );
    }
}

#[test]
fn eigenvalue_signs_on_both_sides_of_kappa_c() {
    for p in sweep(80, 11) {
        let kind = model_for(&p);
        let HopfOutcome::Found(h) = find_hopf(kind, &p).unwrap() else {
            continue;
        };
        let block = DrivenBlock::new(kind, &p);
        for (factor, unstable) in [(1.0 + 1e-6, 0), (1.0 - 1e-6, 2)] {
            let mut at = p;
            at.kappa = h.kappa_c * factor;
            let ev =
                eigenvalues(&jacobian(&block, &steady_state(kind, &at), &at.to_vec())).unwrap();
            assert_eq!(count_unstable(&ev), unstable, "{at:?}: {ev:?}");
        }
    }
}
