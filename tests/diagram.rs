//! Hopf curves and their special points against closed forms (Appendix C,
//! the friction minimum) and independent references.

#![allow(clippy::excessive_precision)] // references are quoted with every digit of their source

use stickslip::analysis::diagram::{hopf_curve, stability_diagram, CurveEnd, SpecialKind};
use stickslip::analysis::hopf::Criticality;
use stickslip::appendix_c;
use stickslip::model::ModelKind;
use stickslip::params::{Param, Params};
use stickslip::scene;

fn c11(p: &Params, nu: f64) -> f64 {
    let mut q = *p;
    q.nu = nu;
    appendix_c::critical_stiffness(&q)
}

#[test]
fn hopf_curves_match_appendix_c_along_nu() {
    let cases = [
        (
            ModelKind::Inertial,
            scene::builtin("pmma").unwrap().params,
            (0.1, 100.0),
        ),
        (
            ModelKind::QuasiStatic,
            Params {
                m: 0.0,
                ..scene::builtin("pmma").unwrap().params
            },
            (1e-2, 1e2),
        ),
        (
            ModelKind::Inertial,
            Params {
                kappa: 0.0,
                nu: 1.0,
                m: 0.05,
                a: 0.01,
                b: 0.03,
                mu0: 0.5,
                mu2: 1e-3,
                theta_c: None,
                state_law: Default::default(),
                mu_vv: 0.0,
                mu_vphi: 0.0,
                eta_d: 0.0,
            },
            (0.01, 10.0),
        ),
        (
            ModelKind::Inertial,
            Params {
                kappa: 0.0,
                nu: 1.0,
                m: 1e-4,
                a: 0.012,
                b: 0.023,
                mu0: 0.5,
                mu2: 0.0,
                theta_c: Some(0.05),
                state_law: Default::default(),
                mu_vv: 0.0,
                mu_vphi: 0.0,
                eta_d: 0.0,
            },
            (0.1, 10.0),
        ),
    ];
    for (kind, p, range) in cases {
        let d = stability_diagram(kind, &p, range).unwrap();
        assert!(d.points.len() > 20, "{p:?}: {} points", d.points.len());
        for pt in &d.points {
            let want = c11(&p, pt.nu);
            // Near kappa_c -> 0 the closed form itself loses digits to the cancellation mu_phi - mu_v.
            let tol = 1e-10f64.max(1e-16 * p.b / want);
            assert!(
                (pt.kappa / want - 1.0).abs() < tol,
                "{kind:?} {p:?} nu = {}: {} vs {want}",
                pt.nu,
                pt.kappa
            );
            let mut q = p;
            q.nu = pt.nu;
            let w = appendix_c::critical_frequency(&q).unwrap();
            assert!((pt.omega / w - 1.0).abs() < tol, "omega at nu = {}", pt.nu);
        }
    }
}

#[test]
fn ln2_term_gives_the_observed_ten_percent_per_decade() {
    // Quasi-static ln² law with mu2 = 2.4e-4 (the pmma scene): kappa_c(nu) = B - A - 2 mu2 ln nu,
    // so kappa_c falls by 2 ln(10) mu2 per decade: 10.05 % of kappa_c at 1 um/s.
    let p = Params {
        m: 0.0,
        ..scene::builtin("pmma").unwrap().params
    };
    let d = stability_diagram(ModelKind::QuasiStatic, &p, (1.0, 10.0)).unwrap();
    let (first, last) = (d.points.first().unwrap(), d.points.last().unwrap());
    assert!((first.nu - 1.0).abs() < 1e-12 && (last.nu - 10.0).abs() < 1e-11);
    let drop = first.kappa - last.kappa;
    assert!(
        (drop / (2.0 * 10f64.ln() * 2.4e-4) - 1.0).abs() < 1e-9,
        "drop per decade {drop}"
    );
    let percent = 100.0 * drop / first.kappa;
    assert!((9.5..10.5).contains(&percent), "{percent} % per decade");
    // The quasi-static ln² onset is supercritical everywhere.
    assert!(d
        .points
        .iter()
        .all(|p| p.criticality == Criticality::Supercritical));
}

#[test]
fn inertia_bends_the_curve_up_at_high_velocity() {
    // C11: kappa_c = (mu_phi - A)(1 + m nu^2/A) grows like nu^2 once m nu^2/A ~ 1.
    let p = scene::builtin("pmma").unwrap().params;
    let d = stability_diagram(ModelKind::Inertial, &p, (0.1, 1000.0)).unwrap();
    let k: Vec<f64> = d.points.iter().map(|p| p.kappa).collect();
    let i_min = (0..k.len()).min_by(|&a, &b| k[a].total_cmp(&k[b])).unwrap();
    assert!(
        i_min > 0 && i_min < k.len() - 1,
        "kappa_c must have an interior minimum"
    );
    assert!(
        k[k.len() - 1] > 5.0 * k[i_min],
        "strong upturn at 1 mm/s: {} vs {}",
        k[k.len() - 1],
        k[i_min]
    );
    // The minimum of C11 in ln nu: d/d ln nu [(B - A - 2 mu2 ln nu)(1 + m nu^2/A)] = 0.
    let (a, b, mu2, m) = (p.a, p.b, p.mu2, p.m);
    let slope = |nu: f64| {
        -2.0 * mu2 * (1.0 + m * nu * nu / a) + (b - a - 2.0 * mu2 * nu.ln()) * 2.0 * m * nu * nu / a
    };
    let (mut lo, mut hi) = (d.points[i_min - 1].nu, d.points[i_min + 1].nu);
    for _ in 0..100 {
        let mid = (lo * hi).sqrt();
        if slope(mid) < 0.0 {
            lo = mid
        } else {
            hi = mid
        }
    }
    assert!(d.points[i_min - 1].nu <= lo && lo <= d.points[i_min + 1].nu);
}

#[test]
fn cutoff_curve_ends_at_the_friction_minimum() {
    let s = scene::builtin("brockley").unwrap();
    let d = stability_diagram(ModelKind::Inertial, &s.params, s.nu_range).unwrap();
    let end = d
        .special
        .iter()
        .find(|p| p.kind == SpecialKind::Endpoint)
        .expect("endpoint");
    let tc = s.params.theta_c.unwrap();
    let v_min = (s.params.b - s.params.a) / (s.params.a * tc);
    assert!(
        (end.nu / v_min - 1.0).abs() < 1e-13,
        "{} vs {v_min}",
        end.nu
    );
    assert_eq!(d.stop, CurveEnd::KappaCVanishes);
    assert!(d.points.last().unwrap().kappa < 1e-5 * d.points[0].kappa);
}

/// Bautin point of the inertial plain RR law (A = 0.012, B = 0.023, nu = 1):
/// m* from a 40-digit computation (docs/reference/REPORT.md, case d).
const M_STAR: f64 = 0.0016140505108687765219;

#[test]
fn inertial_rr_onset_changes_type_at_eta_star() {
    for nu in [1.0, 3.0, 0.2] {
        let p = Params {
            kappa: 0.0,
            nu,
            m: 0.0,
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
        let d = hopf_curve(
            ModelKind::Inertial,
            &p,
            Param::M,
            (1e-5 / (nu * nu), 1.0 / (nu * nu)),
        )
        .unwrap();
        let bautins: Vec<_> = d
            .special
            .iter()
            .filter(|s| s.kind == SpecialKind::Bautin)
            .collect();
        assert_eq!(bautins.len(), 1, "nu = {nu}: {:?}", d.special);
        let b = bautins[0];
        // The onset type depends on eta = m nu^2 / A only: eta* = m*(nu = 1) / A.
        let eta = b.m * nu * nu / p.a;
        assert!(
            (eta / (M_STAR / p.a) - 1.0).abs() < 1e-10,
            "nu = {nu}: eta* = {eta}"
        );
        assert!((b.kappa / ((p.b - p.a) * (1.0 + eta)) - 1.0).abs() < 1e-12);
        if nu == 1.0 {
            // l2 at the Bautin point: two independent 40-digit computations
            // (docs/reference/l2: generic homological solver and Kuznetsov's formulas).
            let l2 = b.l2.unwrap();
            assert!(
                (l2 / -0.0186423503821319602273952015914 - 1.0).abs() < 1e-8,
                "l2 = {l2}"
            );
        }
        if nu == 3.0 {
            let l2 = b.l2.unwrap();
            assert!(
                (l2 / -0.000526259450281443271422534277299 - 1.0).abs() < 1e-8,
                "l2 = {l2}"
            );
        }
        // Subcritical below eta*, supercritical above.
        let first = d.points.first().unwrap();
        let last = d.points.last().unwrap();
        assert_eq!(
            (first.criticality, last.criticality),
            (Criticality::Subcritical, Criticality::Supercritical)
        );
    }
}

#[test]
fn a_hopf_region_starting_inside_the_range_is_traced_from_its_start() {
    // mu2 < 0 and B < A: mu_phi = B - 2 mu2 ln nu exceeds A only for nu > exp((A - B) / (-2 mu2)),
    // so the Hopf curve starts at the friction minimum nu* = e^0.5 inside [0.1, 100].
    let p = Params {
        kappa: 0.0,
        nu: 1.0,
        m: 0.0,
        a: 0.012,
        b: 0.011,
        mu0: 0.5,
        mu2: -1e-3,
        theta_c: None,
        state_law: Default::default(),
        mu_vv: 0.0,
        mu_vphi: 0.0,
        eta_d: 0.0,
    };
    let d = stability_diagram(ModelKind::QuasiStatic, &p, (0.1, 100.0)).unwrap();
    let nu_star = 0.5f64.exp();
    let end = d
        .special
        .iter()
        .find(|s| s.kind == SpecialKind::Endpoint)
        .expect("the start of the region is found");
    assert!(
        (end.nu / nu_star - 1.0).abs() < 1e-12,
        "{} vs {nu_star}",
        end.nu
    );
    let first = &d.points[0];
    assert!(
        first.nu < nu_star * 1.01 && first.kappa < 1e-4 * d.points.last().unwrap().kappa,
        "{first:?}"
    );
    assert!(
        d.points.windows(2).all(|w| w[1].nu > w[0].nu),
        "points in increasing velocity"
    );
    for pt in &d.points {
        assert!(
            (pt.kappa - c11(&p, pt.nu)).abs() < 1e-10 * c11(&p, 100.0),
            "nu = {}",
            pt.nu
        );
    }
}

/// Along the Hopf curve the first Lyapunov coefficient is as exact as at a
/// single Hopf point: plain RR law with `m = 1e-12` (terms of order one,
/// `l1 = 2.6e-11`), where `f64` leaves a few digits and the curve point is
/// recomputed in double-double. Reference: `docs/reference/m_sweep.csv`
/// (90 digits), row `RR A=0.012 nu=1 m=1e-12`.
#[test]
fn curve_points_resolve_l1_at_small_inertia() {
    let p = Params {
        kappa: 0.0,
        nu: 1.0,
        m: 1e-12,
        a: 0.012,
        b: 0.023,
        mu0: 0.5,
        mu2: 0.0,
        theta_c: None,
        state_law: Default::default(),
        mu_vv: 0.0,
        mu_vphi: 0.0,
        eta_d: 0.0,
    };
    let d = stability_diagram(ModelKind::Inertial, &p, (1.0, 1.5)).unwrap();
    let first = d.points.first().unwrap();
    assert!(
        (first.nu - 1.0).abs() < 1e-12,
        "starts at nu = {}",
        first.nu
    );
    let reference = 2.6212992234022181164e-11;
    let err = (first.l1 - reference).abs();
    // The curve's bound is for the parameters as stored in f64; the
    // reference is at the decimal ones (A = 0.012), whose rounding moves l1
    // by about an ulp (the `hopf` onset adds that term, the curve does not).
    let ulp = f64::EPSILON * reference;
    assert!(
        err <= first.l1_error_bound + 2.0 * ulp,
        "l1 = {:e}, error {err:e}, bound {:e}",
        first.l1,
        first.l1_error_bound
    );
    assert!(
        first.l1_error_bound < 1e-12 * reference,
        "bound {:e}",
        first.l1_error_bound
    );
    assert!(d
        .points
        .iter()
        .all(|q| q.criticality == Criticality::Subcritical));
}

/// Fourteen decades of driving velocity, where the steady state's age
/// `phi = 1/nu` spans as many: the curve covers the range in a few hundred
/// points (with the state's arclength weight fixed, the one decade above
/// nu = 1e-12 took the whole 50 000-step budget), and every point is on
/// Appendix C's curve.
#[test]
fn hopf_curve_spans_fourteen_decades_of_velocity() {
    let pmma = scene::builtin("pmma").unwrap().params;
    for (kind, p) in [
        (ModelKind::QuasiStatic, Params { m: 0.0, ..pmma }),
        (ModelKind::Inertial, Params { m: 1e-3, ..pmma }),
    ] {
        let d = stability_diagram(kind, &p, (1e-12, 1e2)).unwrap();
        assert!(d.complete, "{kind:?}: {:?}", d.stop);
        assert_eq!(d.stop, CurveEnd::EndOfRange, "{kind:?}");
        let (first, last) = (d.points.first().unwrap(), d.points.last().unwrap());
        assert!(
            (first.nu / 1e-12 - 1.0).abs() < 1e-10,
            "{kind:?}: {}",
            first.nu
        );
        assert!((last.nu / 1e2 - 1.0).abs() < 1e-10, "{kind:?}: {}", last.nu);
        assert!(d.points.len() < 1000, "{kind:?}: {} points", d.points.len());
        for pt in &d.points {
            let want = c11(&p, pt.nu);
            assert!(
                (pt.kappa / want - 1.0).abs() < 1e-10,
                "{kind:?} nu = {}: {} vs {want}",
                pt.nu,
                pt.kappa
            );
        }
    }
}

/// The curve of folds of cycles between the two Bautin points of the
/// inertial PMMA scene (`m = 0.01`, job 2 of docs/performance.md): near a
/// Bautin point the fold system cannot see itself pass it, and the half
/// that ran past it failed one fold later and was reported cut short. A half
/// failing at or past a Bautin point on its way has ended there: the curve
/// is complete, with no stop, and no fold lies beyond either Bautin point.
#[test]
fn a_fold_curve_ends_at_the_bautin_points_it_runs_into() {
    let p = Params {
        m: 0.01,
        ..scene::builtin("pmma").unwrap().params
    };
    let d = stability_diagram(ModelKind::Inertial, &p, (0.01, 100.0)).unwrap();
    let bautin: Vec<f64> = d
        .special
        .iter()
        .filter(|s| s.kind == SpecialKind::Bautin)
        .map(|s| s.nu)
        .collect();
    assert_eq!(bautin.len(), 2, "{bautin:?}");
    assert!(!d.lpc.incomplete, "{:?}", d.lpc.stops);
    assert!(d.lpc.stops.is_empty(), "{:?}", d.lpc.stops);
    let folds: Vec<f64> = d.lpc.points.iter().flatten().map(|f| f.nu).collect();
    assert!(folds.len() > 10, "{} folds", folds.len());
    let (lo, hi) = (bautin[0].min(bautin[1]), bautin[0].max(bautin[1]));
    assert!(
        folds
            .iter()
            .all(|&nu| nu >= lo * (1.0 - 1e-9) && nu <= hi * (1.0 + 1e-9)),
        "folds {:?} outside the Bautin points {lo} .. {hi}",
        (folds.first(), folds.last())
    );
}
