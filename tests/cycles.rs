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

/// A branch continued back to the Hopf point ends there: Brockley-type
/// subcritical onset (cutoff law, `nu = 90`, `m = 1e-3`), cycles through a
/// simulated stable orbit at `kappa = 0.45`. Toward larger stiffness the
/// stable cycles fold at the LPC and return, unstable, down to `kappa_c`,
/// where their amplitude passes through zero and the parameter turns: that
/// turn is neither a fold (none reported there) nor a reason to go on (past
/// it the same cycles come back shifted by half a period, and were drawn
/// twice). Independent values: `kappa_c` of steady sliding by `find_hopf`.
#[test]
fn a_branch_that_returns_to_the_hopf_point_ends_there() {
    use continuation::Stop;
    use stickslip::analysis::cycles::{trace_cycles_from_orbit, Leg};
    use stickslip::analysis::hopf::{find_hopf, HopfOutcome};
    use stickslip::analysis::model_choice::DEFAULT_INERTIA_THRESHOLD;
    use stickslip::analysis::orbit_inertia::InertiaWatch;
    use stickslip::analysis::settle::{settle, stuck_start, SettleSettings};
    let params = |kappa: f64| Params {
        kappa,
        ..common::brockley(90.0)
    };
    let kind = ModelKind::Inertial;
    let HopfOutcome::Found(hopf) = find_hopf(kind, &params(0.5)).unwrap() else {
        panic!("a Hopf point")
    };
    let p = params(0.45);
    let orbit = settle(kind, &p, stuck_start(&p), &SettleSettings::for_params(&p)).unwrap();
    let req = CycleRequest {
        kappa_min: 0.34,
        kappa_max: 0.50,
        max_steps: 60,
        ntst: 40,
        at_kappa: Vec::new(),
        ntst_max: 1600,
        collocation: None,
    };
    let watch = InertiaWatch::new(&p, DEFAULT_INERTIA_THRESHOLD, false);
    let mut cycles: Vec<CycleRecord> = Vec::new();
    let legs = trace_cycles_from_orbit(kind, &p, &orbit, &req, &watch, |c: &CycleRecord| {
        cycles.push(c.clone());
        Ok(())
    })
    .unwrap();
    assert!(
        matches!(legs[0], (Leg::Up, Ok(Stop::HopfPoint { .. }))),
        "the leg toward larger stiffness ends at the Hopf point: {:?}",
        legs[0].1.as_ref().map_err(|e| e.to_string())
    );
    // One fold, the real one, well above kappa_c.
    let folds: Vec<f64> = cycles
        .iter()
        .filter_map(|c| c.lpc.as_ref().map(|l| l.kappa))
        .collect();
    assert_eq!(folds.len(), 1, "{folds:?}");
    assert!(
        folds[0] > hopf.kappa_c * 1.1,
        "{folds:?} vs kappa_c {}",
        hopf.kappa_c
    );
    // The unstable cycles, in the order handed out, come down toward kappa_c
    // and end near it, without coming back.
    let unstable: Vec<&CycleRecord> = cycles.iter().filter(|c| !c.stability.is_stable()).collect();
    assert!(
        unstable.windows(2).all(|w| w[1].kappa < w[0].kappa),
        "unstable cycles go one way"
    );
    let last = unstable.last().unwrap();
    assert!(
        (last.kappa - hopf.kappa_c) / hopf.kappa_c < 0.01 && last.delta_s < 0.3,
        "last unstable cycle at kappa {} (kappa_c {}), Delta_s {}",
        last.kappa,
        hopf.kappa_c,
        last.delta_s
    );
}

/// The stiff inertial branch down to 0.023 kappa_c (slip velocities over
/// ten decades): every cycle is delivered with its trivial Floquet
/// multiplier within 1e-6 of its exact value 1. (A refinement that fell back
/// to a coarser mesh for the orbit's sake used to skip judging the
/// multipliers there: one cycle came out on 160 intervals with |mu_1 - 1| =
/// 1.3e-4.)
#[test]
fn every_cycle_of_a_stiff_branch_has_its_multipliers_resolved() {
    let dir = common::temp_dir("stiff-multipliers");
    let (code, out, err) = common::stickslip(&[
        "cycles",
        "--json",
        "--set",
        "m=0.01",
        "--model",
        "inertial",
        "--kappa-fraction",
        "0.023223",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let cycles = v["cycles"].as_array().unwrap();
    assert!(cycles.len() > 100, "{} cycles", cycles.len());
    for c in cycles {
        let error = c["trivial_multiplier_error"].as_f64().unwrap();
        assert!(
            error < 1e-6,
            "kappa = {}: |mu_1 - 1| = {error:.1e} on {} intervals",
            c["kappa"],
            c["ntst"]
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
