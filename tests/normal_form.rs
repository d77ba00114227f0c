//! First Lyapunov coefficient and onset law of the driven block against
//! independent values: 40-digit references (sympy/mpmath, exact derivatives;
//! `docs/reference/t3_lyap.py`, cross-checked there by direct simulation),
//! and closed forms for the quasi-static ln² law (`docs/reference/t4_qs_symbolic.py`).
//! (The finite-difference evaluation of the same formula is tested with it,
//! in `bench/tests/l1_finite_differences.rs`.)

#![allow(clippy::excessive_precision)] // references are quoted with every digit of their source

use stickslip::analysis::hopf::{find_hopf, Criticality, HopfOutcome, HopfPoint};
use stickslip::model::ModelKind;
use stickslip::params::Params;

fn hopf(kind: ModelKind, p: Params) -> HopfPoint {
    match find_hopf(kind, &p).unwrap() {
        HopfOutcome::Found(h) => h,
        other => panic!("{p:?}: {other:?}"),
    }
}

fn rr(m: f64, nu: f64, mu2: f64) -> Params {
    Params {
        kappa: 0.0,
        nu,
        m,
        a: 0.012,
        b: 0.023,
        mu0: 0.6,
        mu2,
        theta_c: None,
        state_law: Default::default(),
        mu_vv: 0.0,
        mu_vphi: 0.0,
        eta_d: 0.0,
    }
}

#[test]
fn l1_matches_forty_digit_references() {
    let cases: [(ModelKind, Params, f64); 8] = [
        (
            ModelKind::QuasiStatic,
            rr(0.0, 1.0, 2.4e-4),
            -0.0104420175269075626772801235,
        ),
        (
            ModelKind::QuasiStatic,
            rr(0.0, 10.0, 2.4e-4),
            -1.07790323522073909214007765,
        ),
        (
            ModelKind::Inertial,
            Params {
                kappa: 0.0,
                nu: 3.0,
                m: 0.1,
                a: 0.01,
                b: 0.02,
                mu0: 0.6,
                mu2: 5e-4,
                theta_c: None,
                state_law: Default::default(),
                mu_vv: 0.0,
                mu_vphi: 0.0,
                eta_d: 0.0,
            },
            -6.33249221023467425246e-4,
        ),
        (
            ModelKind::Inertial,
            rr(0.001, 1.0, 0.0),
            0.00789086539631080917,
        ),
        (
            ModelKind::Inertial,
            rr(0.01, 1.0, 0.0),
            -0.126592829429862545170,
        ),
        (
            ModelKind::Inertial,
            rr(0.1, 1.0, 0.0),
            -0.0398806363899330281489,
        ),
        (
            ModelKind::Inertial,
            rr(1.0, 1.0, 0.0),
            -0.00275385071027963309390,
        ),
        (
            ModelKind::Inertial,
            Params {
                kappa: 0.0,
                nu: 50.0,
                m: 1e-3,
                a: 0.012,
                b: 0.023,
                mu0: 0.6,
                mu2: 0.0,
                theta_c: Some(0.01),
                state_law: Default::default(),
                mu_vv: 0.0,
                mu_vphi: 0.0,
                eta_d: 0.0,
            },
            -1.06322912431647633328e-6,
        ),
    ];
    for (kind, p, l1_ref) in cases {
        let h = hopf(kind, p);
        let err = (h.onset.l1 / l1_ref - 1.0).abs();
        assert!(
            err < 1e-10,
            "{kind:?} {p:?}: l1 = {:.16e} vs {l1_ref:.16e} ({err:.1e})",
            h.onset.l1
        );
        let want = if l1_ref < 0.0 {
            Criticality::Supercritical
        } else {
            Criticality::Subcritical
        };
        assert_eq!(h.onset.criticality, want);
    }
}

#[test]
fn quasi_static_rr_hopf_is_degenerate() {
    // l1 is proportional to mu2 for the quasi-static law (Ranjith & Rice 1999; the
    // symbolic check in docs/reference): it must vanish against the size of its terms.
    for nu in [0.01, 1.0, 300.0] {
        let h = hopf(ModelKind::QuasiStatic, rr(0.0, nu, 0.0));
        assert_eq!(
            h.onset.criticality,
            Criticality::Degenerate,
            "nu = {nu}: l1 = {}",
            h.onset.l1
        );
        assert!(h.onset.amplitude_coefficient.is_none());
    }
    // ...while a small ln² term is already decided.
    let h = hopf(ModelKind::QuasiStatic, rr(0.0, 1.0, 1e-6));
    assert_eq!(h.onset.criticality, Criticality::Supercritical);
}

#[test]
fn quasi_static_ln2_l1_and_amplitude_match_closed_forms() {
    // l1 = -mu2 nu^2 / (2 sqrt(A (mu_phi - A)) D), D = 1 + nu^2 mu_phi (mu_phi - A),
    // Delta_s = 4 sqrt(mu_phi (mu_phi - A) (kappa_c - kappa) / mu2), cycles for kappa < kappa_c.
    for (a, b, mu2, nu) in [
        (0.012, 0.023, 2.4e-4, 1.0),
        (0.012, 0.023, 2.4e-4, 10.0),
        (0.005, 0.03, 3e-3, 0.02),
        (0.04, 0.05, 1e-5, 70.0),
    ] {
        let p = Params {
            kappa: 0.0,
            nu,
            m: 0.0,
            a,
            b,
            mu0: 0.4,
            mu2,
            theta_c: None,
            state_law: Default::default(),
            mu_vv: 0.0,
            mu_vphi: 0.0,
            eta_d: 0.0,
        };
        let h = hopf(ModelKind::QuasiStatic, p);
        let mu_phi = b - 2.0 * mu2 * nu.ln();
        let d = 1.0 + nu * nu * mu_phi * (mu_phi - a);
        let l1 = -mu2 * nu * nu / (2.0 * (a * (mu_phi - a)).sqrt() * d);
        let c = 4.0 * (mu_phi * (mu_phi - a) / mu2).sqrt();
        assert!(
            (h.onset.l1 / l1 - 1.0).abs() < 1e-10,
            "{p:?}: l1 {} vs {l1}",
            h.onset.l1
        );
        let got = h.onset.amplitude_coefficient.unwrap();
        assert!((got / c - 1.0).abs() < 1e-10, "{p:?}: C {got} vs {c}");
        assert_eq!(h.onset.side, Some(-1.0));
        // Transversality, closed form -nu / (2 mu_v) (docs/reference/REPORT.md §1).
        assert!((h.onset.dlambda_dkappa.re / (-nu / (2.0 * a)) - 1.0).abs() < 1e-10);
    }
}

#[test]
fn inertial_transversality_matches_closed_form() {
    // d Re(lambda)/d kappa = -mu_v nu / (2 ((mu_v + m nu^2)^2 + m^2 nu^2 w^2)).
    for (m, nu) in [(0.01, 1.0), (0.3, 4.0), (5.0, 0.05)] {
        let p = rr(m, nu, 2e-4);
        let h = hopf(ModelKind::Inertial, p);
        let (mu_v, w) = (p.a, h.omega_c);
        let want = -mu_v * nu / (2.0 * ((mu_v + m * nu * nu).powi(2) + m * m * nu * nu * w * w));
        assert!(
            (h.onset.dlambda_dkappa.re / want - 1.0).abs() < 1e-10,
            "{p:?}"
        );
    }
}
