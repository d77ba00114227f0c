//! Where methods fail: each hard case either gets the right answer to a
//! stated tolerance or a typed error that names the cause (docs/hard-cases.md).

mod common;

use stickslip::analysis::cycles::{trace_cycles, CycleRequest};
use stickslip::analysis::hopf::{find_hopf, Criticality, HopfOutcome, HopfPoint};
use stickslip::appendix_c;
use stickslip::model::ModelKind;
use stickslip::params::Params;

fn pmma(mu2: f64) -> Params {
    common::pmma(0.0, mu2)
}

fn hopf(kind: ModelKind, p: &Params) -> HopfPoint {
    match find_hopf(kind, p).unwrap() {
        HopfOutcome::Found(h) => h,
        other => panic!("{p:?}: {other:?}"),
    }
}

fn assert_appendix_c(h: &HopfPoint, p: &Params) {
    let (k, w) = (
        appendix_c::critical_stiffness(p),
        appendix_c::critical_frequency(p).unwrap(),
    );
    assert!(
        (h.kappa_c / k - 1.0).abs() < 1e-10,
        "{p:?}: kappa_c {} vs {k}",
        h.kappa_c
    );
    assert!(
        (h.omega_c / w - 1.0).abs() < 1e-10,
        "{p:?}: omega_c {} vs {w}",
        h.omega_c
    );
}

#[test]
fn degenerate_hopf_is_named_and_cycles_refuse_with_a_reason() {
    let p = pmma(0.0);
    let h = hopf(ModelKind::QuasiStatic, &p);
    assert_eq!(h.onset.criticality, Criticality::Degenerate);
    let req = CycleRequest {
        kappa_min: 0.0,
        kappa_max: 1.0,
        max_steps: 5,
        ntst: 20,
        at_kappa: Vec::new(),
        ntst_max: 400,
        collocation: None,
    };
    let err = trace_cycles(ModelKind::QuasiStatic, &p, &req, |_| Ok(()))
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("degenerate Hopf point") && err.contains("--from-simulation"),
        "{err}"
    );
}

#[test]
fn vanishing_inertia_converges_to_the_quasi_static_onset_linearly_in_m() {
    // The coordinate-free onset coefficient C of the inertial model tends to the
    // quasi-static closed form 4 sqrt(mu_phi (mu_phi - A) / mu2) like O(m), until
    // the 1/m entries of the Jacobian cost digits (eps/m: below m ~ 1e-8 the
    // quasi-static model is the right tool, and the model choice takes it).
    let c_qs = 4.0 * (0.023f64 * 0.011 / 2.4e-4).sqrt();
    let errs: Vec<f64> = [1e-5, 1e-6, 1e-7]
        .iter()
        .map(|&m| {
            let p = Params { m, ..pmma(2.4e-4) };
            let h = hopf(ModelKind::Inertial, &p);
            assert_appendix_c(&h, &p);
            h.onset.amplitude_coefficient.unwrap() / c_qs - 1.0
        })
        .collect();
    for w in errs.windows(2) {
        let rate = w[0] / w[1];
        assert!(
            (8.0..12.5).contains(&rate),
            "error must fall tenfold per decade of m: {errs:?}"
        );
    }
}

#[test]
fn extreme_parameters_still_match_appendix_c() {
    let cases = [
        (
            ModelKind::Inertial,
            Params {
                m: 1e4,
                nu: 3.0,
                ..pmma(2.4e-4)
            },
        ),
        (
            ModelKind::Inertial,
            Params {
                m: 10.0,
                nu: 100.0,
                ..pmma(2.4e-4)
            },
        ),
        (
            ModelKind::Inertial,
            Params {
                a: 1e-4,
                b: 0.02,
                m: 2.5e-7,
                ..pmma(2.4e-4)
            },
        ),
        (
            ModelKind::QuasiStatic,
            Params {
                a: 1e-4,
                b: 0.02,
                ..pmma(2.4e-4)
            },
        ),
        (
            ModelKind::QuasiStatic,
            Params {
                nu: 1e-4,
                ..pmma(2.4e-4)
            },
        ),
        (
            ModelKind::QuasiStatic,
            Params {
                nu: 1e4,
                ..pmma(1e-6)
            },
        ),
        (
            ModelKind::Inertial,
            Params {
                nu: 1e4,
                m: 2.5e-7,
                ..pmma(2.4e-4)
            },
        ),
        (
            ModelKind::Inertial,
            Params {
                nu: 1e-4,
                m: 1.0,
                ..pmma(2.4e-4)
            },
        ),
    ];
    for (kind, p) in cases {
        assert_appendix_c(&hopf(kind, &p), &p);
    }
}

#[test]
fn velocity_strengthening_is_stable_for_every_stiffness() {
    for (kind, p) in [
        (
            ModelKind::QuasiStatic,
            Params {
                b: 0.005,
                ..pmma(0.0)
            },
        ),
        (
            ModelKind::Inertial,
            Params {
                b: 0.011,
                m: 0.1,
                ..pmma(0.0)
            },
        ),
        (
            ModelKind::QuasiStatic,
            Params {
                nu: 1e12,
                ..pmma(2.4e-4)
            },
        ),
    ] {
        assert!(appendix_c::critical_stiffness(&p) <= 0.0);
        assert!(
            matches!(
                find_hopf(kind, &p).unwrap(),
                HopfOutcome::StableForAllStiffness { .. }
            ),
            "{p:?}"
        );
    }
}

#[test]
fn negative_ln2_term_makes_the_onset_subcritical() {
    // Quasi-static closed form: l1 = -mu2 nu^2 / (2 sqrt(A (mu_phi - A)) D) > 0 for mu2 < 0.
    let p = pmma(-1e-3);
    let h = hopf(ModelKind::QuasiStatic, &p);
    let mu_phi = 0.023;
    let d = 1.0 + mu_phi * (mu_phi - 0.012);
    let l1 = 1e-3 / (2.0 * (0.012f64 * (mu_phi - 0.012)).sqrt() * d);
    assert!((h.onset.l1 / l1 - 1.0).abs() < 1e-10);
    assert_eq!(h.onset.criticality, Criticality::Subcritical);
    assert_eq!(
        h.onset.side,
        Some(1.0),
        "the unstable cycle lies on the stable side, kappa > kappa_c"
    );
}

#[test]
fn cutoff_law_at_and_near_the_friction_minimum() {
    let theta_c = 0.01;
    let v_min = (0.023 - 0.012) / (0.012 * theta_c);
    let at = Params {
        nu: v_min,
        m: 1e-6,
        theta_c: Some(theta_c),
        ..pmma(0.0)
    };
    assert!(matches!(
        find_hopf(ModelKind::Inertial, &at).unwrap(),
        HopfOutcome::StableForAllStiffness { .. }
    ));
    let near = Params {
        nu: v_min * (1.0 - 1e-6),
        ..at
    };
    let h = hopf(ModelKind::Inertial, &near);
    // kappa_c ~ 1e-8 here: the closed form itself carries the cancellation mu_phi - mu_v.
    let k = appendix_c::critical_stiffness(&near);
    assert!((h.kappa_c / k - 1.0).abs() < 1e-7, "{} vs {k}", h.kappa_c);
}

#[test]
fn stiff_stick_slip_cycles_are_resolved_and_match_integration() {
    // Inertial ln² PMMA (m = 0.01) from its Hopf point down to kappa = 1e-4
    // (issue #4's target; a widely used Fortran code stops near 7e-4): the
    // slip velocity spans more than fourteen decades within a period. Every
    // cycle carries a finite error estimate within the accepted bound and is
    // stable; the last one is reproduced by Radau integration (period and
    // Delta_s to 1e-6).
    let p = Params {
        m: 0.01,
        ..pmma(2.4e-4)
    };
    let req = CycleRequest {
        kappa_min: 1e-4,
        kappa_max: 1.0,
        max_steps: 1000,
        ntst: 40,
        at_kappa: Vec::new(),
        ntst_max: 12800,
        collocation: None,
    };
    let mut cycles = Vec::new();
    trace_cycles(ModelKind::Inertial, &p, &req, |c| {
        cycles.push(c.clone());
        Ok(())
    })
    .unwrap();
    let last = cycles.last().unwrap();
    assert!(last.kappa <= 1e-4, "reached kappa = {}", last.kappa);
    assert!(
        last.v_max / last.v_min > 1e14,
        "{} .. {}",
        last.v_min,
        last.v_max
    );
    for c in &cycles {
        assert!(c.error_estimate.is_some_and(|e| e <= 1e-4));
        assert!(c.stability.is_stable() && c.trivial_error.is_some_and(|e| e < 1e-3));
    }
    common::assert_reproduced_by_integration(ModelKind::Inertial, &p, last, "stiff cycle");
}

/// A huge ln² coefficient at `nu = 1`, where it does not enter the linear
/// problem (`mu_phi = B - 2 mu2 ln nu = B`): the onset is the plain law's,
/// `kappa_c = B - A`. The search's starting stiffness comes from the slopes,
/// not from `mu2` itself (with `mu2 = 1e10` it started at 4e10 and its
/// floor, 1e-12 of that, lay above `kappa_c`: "no Hopf point").
#[test]
fn a_huge_ln2_coefficient_that_does_not_act_leaves_the_onset_alone() {
    for mu2 in [1e-3, 1e4, 1e10] {
        let p = common::pmma(0.0, mu2);
        let HopfOutcome::Found(h) = find_hopf(ModelKind::QuasiStatic, &p).unwrap() else {
            panic!("mu2 = {mu2}: no Hopf point")
        };
        let exact = appendix_c::critical_stiffness_quasi_static(&p);
        assert!(
            (h.kappa_c / exact - 1.0).abs() < 1e-10,
            "mu2 = {mu2}: {} vs {exact}",
            h.kappa_c
        );
    }
}
