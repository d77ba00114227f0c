//! Hysteretic (Brockley-type) stick-slip: cycles that coexist with stable
//! steady sliding, found by simulation and continued by collocation.
//!
//! Parameters: the `brockley` friction law (A = 0.012, B = 0.023, cutoff
//! `theta_c = (B - A)/(100 A)`, i.e. V_min = 100 V0), with
//! * `nu = 90, m = 1e-3`: a subcritical Hopf point at
//!   `kappa_c = (mu_phi - mu_v)(1 + m nu^2/mu_v)` (Appendix C) and a fold of
//!   cycles above it;
//! * `nu = 150, m = 2.548e-7` (the scene's inertia, above V_min): no Hopf
//!   point at all, stick-slip cycles at small stiffness.

mod common;

use stickslip::analysis::cycles::{trace_cycles_from_orbit, CycleRecord, CycleRequest, Leg};
use stickslip::analysis::model_choice::DEFAULT_INERTIA_THRESHOLD;
use stickslip::analysis::orbit_inertia::InertiaWatch;
use stickslip::analysis::settle::{settle, stuck_start, SettleError, SettleSettings};
use stickslip::appendix_c::critical_stiffness;
use stickslip::model::ModelKind;
use stickslip::params::Params;

fn brockley(nu: f64, m: f64, kappa: f64) -> Params {
    Params {
        kappa,
        nu,
        m,
        a: 0.012,
        b: 0.023,
        mu0: 0.5,
        mu2: 0.0,
        theta_c: Some((0.023 - 0.012) / (0.012 * 100.0)),
        state_law: Default::default(),
        mu_vv: 0.0,
        mu_vphi: 0.0,
        eta_d: 0.0,
    }
}

/// The fold of cycles of the subcritical onset at `nu = 90`, `m = 1e-3`,
/// computed with AUTO-07p (an independent code): `kappa`, period.
const AUTO_LPC: (f64, f64) = (0.48441890476, 0.2857396);

/// Cycles through the orbit settled from a stuck start at `p`.
fn branch(p: &Params, req: &CycleRequest) -> Vec<CycleRecord> {
    let kind = ModelKind::Inertial;
    let orbit = settle(kind, p, stuck_start(p), &SettleSettings::for_params(p)).unwrap();
    let mut out = Vec::new();
    let watch = InertiaWatch::new(p, DEFAULT_INERTIA_THRESHOLD, false);
    let legs = trace_cycles_from_orbit(kind, p, &orbit, req, &watch, |c: &CycleRecord| {
        out.push(c.clone());
        Ok(())
    })
    .unwrap();
    for leg in legs {
        leg.1.unwrap();
    }
    out
}

#[test]
fn steady_sliding_and_stick_slip_coexist_at_one_stiffness() {
    // nu = 90: between kappa_c and the fold of cycles, where steady sliding
    // is only weakly attracting (Re lambda = -4.9e-4: an e-folding time of
    // 2000 time units); nu = 150: above V_min, below the fold (3.36e-5).
    for (nu, m, kappa) in [(90.0, 1e-3, 0.47), (150.0, 2.548e-7, 2.3e-5)] {
        let p = brockley(nu, m, kappa);
        assert!(
            kappa > critical_stiffness(&p),
            "nu = {nu}: steady sliding linearly stable"
        );
        // A start near steady sliding (age 0.1 % off) decays back to it.
        let near = [p.friction().steady(nu), nu, 1.001 / nu];
        let settings = SettleSettings {
            max_time: 3e4,
            ..SettleSettings::for_params(&p)
        };
        assert!(
            matches!(
                settle(ModelKind::Inertial, &p, near, &settings),
                Err(SettleError::Decayed { .. })
            ),
            "nu = {nu}: the start near steady sliding should decay"
        );
        // The collocation cycle at the same parameters (the branch's first
        // cycle, corrected at kappa), integrated from one of its points.
        let req = CycleRequest {
            kappa_min: 0.99 * kappa,
            kappa_max: 1.01 * kappa,
            max_steps: 0,
            ntst: 40,
            at_kappa: Vec::new(),
            ntst_max: 1600,
            collocation: None,
        };
        let cycle = &branch(&p, &req)[0];
        assert_eq!(cycle.kappa, kappa);
        assert!(
            cycle.stability.is_stable(),
            "nu = {nu}: the coexisting cycle is stable"
        );
        common::assert_reproduced_by_integration(
            ModelKind::Inertial,
            &p,
            cycle,
            &format!("nu = {nu}"),
        );
    }
}

#[test]
fn fold_of_cycles_of_the_subcritical_onset_matches_auto() {
    let p = brockley(90.0, 1e-3, 0.45);
    let req = CycleRequest {
        kappa_min: 0.44,
        kappa_max: 0.6,
        max_steps: 25,
        ntst: 40,
        at_kappa: Vec::new(),
        ntst_max: 1600,
        collocation: None,
    };
    let cycles = branch(&p, &req);
    let lpc: Vec<&CycleRecord> = cycles.iter().filter_map(|c| c.lpc.as_deref()).collect();
    assert_eq!(lpc.len(), 1, "one fold of cycles");
    let (kappa, period) = AUTO_LPC;
    assert!(
        (lpc[0].kappa / kappa - 1.0).abs() < 1e-6,
        "LPC at kappa = {} vs AUTO {kappa}",
        lpc[0].kappa
    );
    assert!(
        (lpc[0].period / period - 1.0).abs() < 1e-6,
        "LPC period {} vs AUTO {period}",
        lpc[0].period
    );
    // Toward larger stiffness: stable cycles up to the fold, unstable past it.
    let up: Vec<&CycleRecord> = cycles.iter().filter(|c| c.leg == Leg::Up).collect();
    let fold = up.iter().position(|c| c.lpc.is_some()).unwrap();
    assert!(fold > 1 && up[..fold].iter().all(|c| c.stability.is_stable()));
    assert!(up.len() > fold + 1 && up[fold..].iter().all(|c| c.stability.is_unstable()));
}
