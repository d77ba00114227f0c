//! Stick-slip cycles against the normal form and the closed-form onset law.

mod common;

use common::pmma;

use stickslip::analysis::cycles::{trace_cycles, CycleRecord, CycleRequest};
use stickslip::analysis::hopf::HopfPoint;
use stickslip::model::ModelKind;
use stickslip::params::Params;

fn cycles(kind: ModelKind, p: &Params, steps: usize) -> (HopfPoint, Vec<CycleRecord>) {
    let mut out = Vec::new();
    // Down to 0.9 kappa_c: stick-slip well developed (v over 4 to 5 decades).
    let req = CycleRequest {
        kappa_min: 0.9 * stickslip::appendix_c::critical_stiffness(p),
        kappa_max: 1.0,
        max_steps: steps,
        ntst: 40,
        at_kappa: Vec::new(),
        ntst_max: 1600,
        collocation: None,
    };
    let h = trace_cycles(kind, p, &req, |c| {
        out.push(c.clone());
        Ok(())
    })
    .unwrap();
    (h, out)
}

#[test]
fn onset_amplitude_and_period_follow_the_normal_form() {
    // Quasi-static ln² law: Delta_s = 4 sqrt(mu_phi (mu_phi - A) (kappa_c - kappa) / mu2),
    // an independent closed form (docs/diagram.md); the error is O(kappa_c - kappa).
    let p = pmma(0.0, 2.4e-4);
    let (h, recs) = cycles(ModelKind::QuasiStatic, &p, 14);
    let (kappa_c, omega) = (h.kappa_c, h.omega_c);
    let slope = h.onset.frequency_slope.unwrap();
    let c = 4.0 * (0.023f64 * 0.011 / 2.4e-4).sqrt();
    let mut checked = 0;
    for r in &recs {
        let eps = (kappa_c - r.kappa) / kappa_c;
        assert!(eps > 0.0, "supercritical: cycles below kappa_c");
        assert!(r.stability.is_stable(), "supercritical cycles are stable");
        assert!(r.trivial_error.is_some_and(|e| e < 1e-8));
        // Below eps ~ 1e-6 the corrector's tolerance on kappa (1e-10) dominates kappa_c - kappa.
        if (1e-6..1e-3).contains(&eps) {
            let ratio = r.delta_s / (c * (kappa_c - r.kappa).sqrt());
            assert!(
                (ratio - 1.0).abs() < 0.5 * eps + 1e-7,
                "eps = {eps:.2e}: amplitude ratio {ratio}"
            );
            // Period from the normal form's frequency shift: Omega = omega + slope (kappa - kappa_c).
            let t = 2.0 * std::f64::consts::PI / (omega + slope * (r.kappa - kappa_c));
            assert!(
                (r.period / t - 1.0).abs() < 1e3 * eps * eps + 1e-8,
                "eps = {eps:.2e}: period {} vs {t}",
                r.period
            );
            checked += 1;
        }
    }
    assert!(checked >= 3, "{checked} cycles close to onset");
}

#[test]
fn collocation_cycles_agree_with_long_time_integration() {
    // Stable stick-slip cycles, quasi-static ln² law and inertial (m = 0.01):
    // integrate from a point of the collocation orbit with Radau IIA at rtol 1e-12,
    // measure period and Delta_s from the events v = nu (extremes of s).
    for (kind, p) in [
        (ModelKind::QuasiStatic, pmma(0.0, 2.4e-4)),
        (ModelKind::Inertial, pmma(0.01, 2.4e-4)),
    ] {
        let (h, recs) = cycles(kind, &p, 60);
        let r = recs
            .iter()
            .rev()
            .find(|r| (h.kappa_c - r.kappa) / h.kappa_c > 0.005)
            .expect("a developed cycle");
        // The trivial multiplier's error here is the rounding floor of the
        // Floquet reduction (3e-8 for the quasi-static cycle, whose slip
        // velocity spans 5 decades; it stays put when the mesh doubles).
        assert!(r.stability.is_stable() && r.trivial_error.is_some_and(|e| e < 1e-7));
        common::assert_reproduced_by_integration(kind, &p, r, &format!("{kind:?}"));
    }
}
