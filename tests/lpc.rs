//! Folds of cycles (LPC): two independent routes, a reference from another
//! code, and the curve of folds that bounds the hysteretic region.

mod common;

use common::brockley;
use continuation::periodic::locate_lpc;
use continuation::periodic::CollocationPoints;
use continuation::periodic::{CycleBranch, CycleEvent, CyclePoint, CycleSettings, Discretization};
use continuation::NewtonSettings;
use stickslip::analysis::cycles::{hopf_start, start_amplitude};
use stickslip::analysis::diagram::{stability_diagram, SpecialKind};
use stickslip::analysis::hopf::{find_hopf, HopfOutcome};
use stickslip::analysis::lpc_curve::{lpc_curve_through, LpcCurvePoint};
use stickslip::log_model::LogBlock;
use stickslip::model::ModelKind;
use stickslip::params::{Param, Params};

/// The inertial block of `p` in the variables of the cycle branches
/// (measured from steady sliding), those `lpc_curve_through` takes its fold in.
fn log(p: &Params) -> LogBlock {
    LogBlock::centered(ModelKind::Inertial, p)
}

/// The fold on the branch of cycles born at the Hopf point of `p` (route 1:
/// sign change of dp/ds, located by regula falsi) and the branch's orbit
/// nearest to it in the stiffness (the one before it or the first past it).
fn fold_on_branch(p: &Params) -> (CyclePoint, CyclePoint) {
    fold_on_branch_with(p, CollocationPoints::Gauss)
}

/// [`fold_on_branch`] with the given collocation points.
fn fold_on_branch_with(p: &Params, points: CollocationPoints) -> (CyclePoint, CyclePoint) {
    let HopfOutcome::Found(h) = find_hopf(ModelKind::Inertial, p).unwrap() else {
        panic!("no Hopf point at nu = {}", p.nu)
    };
    let log = log(p);
    let (x0, pv) = hopf_start(&log, p, &h);
    let settings = CycleSettings {
        mesh: Discretization {
            ntst: 40,
            points,
            ..Default::default()
        },
        p_max: 50.0 * h.kappa_c,
        max_steps: 300,
        param_floor: 1e-3 * h.kappa_c,
        start_amplitude: start_amplitude(&log),
        ..Default::default()
    };
    let branch =
        CycleBranch::from_hopf(&log, &x0, h.omega_c, &pv, Param::Kappa as usize, settings).unwrap();
    let mut previous = None;
    for pt in branch {
        let pt = pt.unwrap();
        if let Some(lpc) = pt.event(CycleEvent::Fold) {
            let before: CyclePoint = previous.expect("a cycle before the fold");
            let kappa = |c: &CyclePoint| c.cycle.p[Param::Kappa as usize];
            let distance = |c: &CyclePoint| (kappa(c) - kappa(lpc)).abs();
            let nearest = if distance(&pt) < distance(&before) {
                pt.clone()
            } else {
                before
            };
            return (lpc.clone(), nearest);
        }
        previous = Some(pt);
    }
    panic!("no fold of cycles at nu = {}", p.nu)
}

#[test]
fn fold_of_cycles_by_two_routes_and_against_auto() {
    let (fold, nearest) = fold_on_branch(&brockley(90.0));
    let route1 = fold.cycle.p[Param::Kappa as usize];
    // Route 2: Newton on the minimally augmented system from the branch's
    // orbit nearest to the fold (chord steps make the branch's steps longer:
    // the orbit before it may lie 1.3 % away, outside Newton's basin).
    let newton = NewtonSettings {
        step_tol: 1e-12,
        residual_tol: 1e-10,
        max_iter: 20,
    };
    let route2 = locate_lpc(
        &log(&brockley(90.0)),
        &nearest.cycle,
        Param::Kappa as usize,
        &newton,
    )
    .unwrap()
    .cycle
    .p[Param::Kappa as usize];
    assert!(
        ((route1 - route2) / route1).abs() < 1e-8,
        "route 1: {route1}, route 2: {route2}"
    );
    // AUTO-07p (NCOL 4, log variables; docs/performance.md) printed 4.8441890476E-01.
    assert!(((route1 - 0.48441890476) / route1).abs() < 1e-9, "{route1}");
}

#[test]
fn the_curve_of_folds_starts_at_the_bautin_point_and_holds_folds_of_the_branches() {
    let d = stability_diagram(ModelKind::Inertial, &brockley(50.0), (50.0, 300.0)).unwrap();
    let bautin = d
        .special
        .iter()
        .find(|s| s.kind == SpecialKind::Bautin)
        .expect("a Bautin point below V_min");
    assert_eq!(d.lpc.points.len(), 1, "{:?}", d.lpc.stops);
    let curve = &d.lpc.points[0];
    // It ends where the folded cycles vanish: at the Bautin point (the fold
    // system degenerates there; the curve stops once the cycles are small).
    let end = curve.iter().min_by(|a, b| a.nu.total_cmp(&b.nu)).unwrap();
    assert!(
        ((end.nu - bautin.nu) / bautin.nu).abs() < 5e-3
            && ((end.kappa - bautin.kappa) / bautin.kappa).abs() < 5e-3,
        "curve end ({}, {}) vs Bautin ({}, {})",
        end.nu,
        end.kappa,
        bautin.nu,
        bautin.kappa
    );
    let at_90 = curve
        .iter()
        .min_by(|a, b| (a.nu - 90.0).abs().total_cmp(&(b.nu - 90.0).abs()))
        .unwrap();
    assert!(
        end.delta_s < 0.2 * at_90.delta_s,
        "the cycles shrink towards the Bautin point"
    );
    // It crosses the friction minimum (nu = 100) into velocity strengthening.
    assert!(
        curve.iter().any(|p| p.nu > 150.0),
        "the curve stays below V_min"
    );
    assert_holds_branch_folds(curve);
}

/// Points of a curve of folds below V_min are the folds of the one-parameter
/// branches there (to 1e-7).
fn assert_holds_branch_folds(curve: &[LpcCurvePoint]) {
    for target in [85.0, 95.0] {
        let pt = curve
            .iter()
            .min_by(|a, b| (a.nu - target).abs().total_cmp(&(b.nu - target).abs()))
            .unwrap();
        let (fold, _) = fold_on_branch(&brockley(pt.nu));
        let k = fold.cycle.p[Param::Kappa as usize];
        assert!(
            ((pt.kappa - k) / k).abs() < 1e-7,
            "nu = {}: curve kappa {} vs branch fold {k}",
            pt.nu,
            pt.kappa
        );
    }
}

#[test]
fn the_curve_through_a_fold_found_on_a_branch_holds_the_other_folds() {
    // Started from the fold of the branch at nu = 90 (not from a Bautin
    // point), on that orbit's own mesh, with the Radau points `cycles` uses
    // for the inertial block; checked against folds of Gauss branches.
    let (fold, _) = fold_on_branch_with(&brockley(90.0), CollocationPoints::Radau);
    let curves = lpc_curve_through(
        ModelKind::Inertial,
        &brockley(90.0),
        &fold.cycle,
        (80.0, 300.0),
    );
    let curve = &curves.points[0];
    assert!(
        curve.first().unwrap().nu < 85.0 && curve.last().unwrap().nu > 150.0,
        "{} .. {}: {:?}",
        curve.first().unwrap().nu,
        curve.last().unwrap().nu,
        curves.stops
    );
    assert_holds_branch_folds(curve);
}

/// Between two Bautin points (a PMMA-like rig, `M = 2 kg`, `W = 200 N`:
/// at 145.7 and 253.6 µm/s) the curve traced from the first Bautin point
/// stops short of the second (the fold system ill-conditioned 1.6 % from
/// it), and the curve traced from the second covers that span: the
/// diagram is complete, without a gap or a stop (it reported the first
/// curve's end as a gap and exited 4). Each fold stiffness lies above
/// `kappa_c` (C11; the hysteretic band of a subcritical onset).
#[test]
fn a_span_covered_by_the_curve_from_the_next_bautin_point_is_no_gap() {
    let dir = common::temp_dir("lpc-two-bautin");
    let scene = dir.join("rig27.toml");
    std::fs::write(
        &scene,
        "A = 0.011\nB = 0.02\nmu0 = 0.55\nmu2 = 3e-4\nD0 = 0.5\nV0 = 1.0\nM = 2.0\nW = 200.0\n\
         K = 1e5\nV = 10.0\nV_range = [0.1, 1000.0]\n",
    )
    .unwrap();
    let out = dir.join("out");
    let (code, v) = common::run_json(&[
        "diagram",
        "--scene",
        scene.to_str().unwrap(),
        "--json",
        "--out",
        out.to_str().unwrap(),
        "--force",
    ]);
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(code, 0, "{}", v["lpc_stops"]);
    assert_eq!(v["lpc_complete"], true);
    assert!(v["lpc_gaps"].as_array().unwrap().is_empty());
    assert!(v["lpc_stops"].as_array().unwrap().is_empty());
    let bautin: Vec<f64> = v["special_points"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|p| p["kind"] == "bautin")
        .map(|p| p["nu"].as_f64().unwrap())
        .collect();
    assert_eq!(bautin.len(), 2, "{bautin:?}");
    let folds = v["lpc_curve"].as_array().unwrap();
    let nu = |p: &serde_json::Value| p["nu"].as_f64().unwrap();
    let (lo, hi) = folds
        .iter()
        .map(nu)
        .fold((f64::INFINITY, 0.0f64), |(a, b), x| (a.min(x), b.max(x)));
    assert!((lo / bautin[0]).ln().abs() < 0.01, "{lo} vs {}", bautin[0]);
    assert!((hi / bautin[1]).ln().abs() < 0.01, "{hi} vs {}", bautin[1]);
    // kappa_c at each fold's velocity by C11 (mu_v = A, mu_phi = B - 2
    // mu2 ln nu).
    let q = |k: &str| v["params"][k].as_f64().unwrap();
    let (a, b, mu2, m) = (q("A"), q("B"), q("mu2"), q("m"));
    for f in folds {
        let nu = nu(f);
        let kc = (b - 2.0 * mu2 * nu.ln() - a) * (1.0 + m * nu * nu / a);
        assert!(
            f["kappa"].as_f64().unwrap() > kc,
            "{f} against kappa_c {kc}"
        );
    }
}

/// A fold-of-cycles curve that stopped short of the request (pmma-rr: its
/// cycles too stiff for the curve's mesh near 0.39 um/s) ends its CSV with
/// a `# incomplete` line naming why, as the JSON's `lpc_stops` do.
#[test]
fn a_short_fold_curve_csv_says_it_is_incomplete() {
    let dir = common::temp_dir("diagram-lpc-incomplete");
    let (code, v) = common::run_json(&[
        "diagram",
        "--scene",
        "pmma-rr",
        "--json",
        "--out",
        dir.to_str().unwrap(),
        "--force",
    ]);
    let csv = std::fs::read_to_string(dir.join("pmma-rr-lpc-curve.csv")).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(code, 4);
    assert_eq!(v["lpc_complete"], false);
    let last = csv.lines().last().unwrap();
    let stop = v["lpc_stops"][0]["message"].as_str().unwrap();
    assert!(last.starts_with("# incomplete: "), "{last}");
    assert!(last.contains(stop), "{last}");
}
