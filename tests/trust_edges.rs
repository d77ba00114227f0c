//! The edges a stranger found (issue 22), each as the command line that
//! showed it: one model decision and one onset type for every command, no
//! spurious period doublings, negative friction named, branches from a
//! simulated orbit that end at the Hopf point they reach, exit statuses
//! that tell the truth, requested points answered once, fold-of-cycles
//! curves that end on their range, advice that is not already the case.

mod common;

use common::{stickslip, temp_dir};
use serde_json::Value;

/// A press-loaded rock rig driven at 0.01 µm/s with the plain ageing law:
/// `m = M V0^2 / (W D0) = 2e-12`. The quasi-static onset is degenerate
/// (`l1 = 0` exactly); the inertial one is subcritical, `l1 ~ 1e-18`, which
/// only double-double resolves.
const ROCK: &str = r#"
name = "rock"
description = "press-loaded granite rig, slow drive"
A = 0.008
B = 0.012
mu2 = 0
mu0 = 0.7
D0 = 5.0
V0 = 1.0
M = 1.0
W = 1.0e5
V = 0.01
V_range = [0.01, 10.0]
"#;

/// The rock scene written into `dir`, its path.
fn rock(dir: &std::path::Path) -> String {
    let path = dir.join("rock.toml");
    std::fs::write(&path, ROCK).unwrap();
    path.to_str().unwrap().to_string()
}

fn json(text: &str) -> Value {
    serde_json::from_str(text).unwrap_or_else(|e| panic!("{e}: {text}"))
}

#[test]
fn hopf_diagram_and_cycles_decide_the_same_model_and_onset_type() {
    let dir = temp_dir("trust-rock");
    let scene = rock(&dir);
    let out = dir.to_str().unwrap();
    let (code, text, err) = stickslip(&["hopf", "--scene", &scene, "--json"]);
    assert_eq!(code, 0, "{err}");
    let h = json(&text);
    assert_eq!(h["model"], "inertial");
    assert_eq!(h["criticality"], "subcritical");
    let l1 = h["l1"].as_f64().unwrap();
    assert!(l1 > 0.0 && l1 > h["l1_error_bound"].as_f64().unwrap());

    // The diagram: the quasi-static curve is degenerate everywhere, so the
    // whole curve is traced with the inertia (before: quasi-static, every
    // point "degenerate", judged at the top of the range).
    let (code, text, err) = stickslip(&["diagram", "--scene", &scene, "--json", "--out", out]);
    assert_eq!(code, 0, "{err}");
    let d = json(&text);
    assert_eq!(d["model"], "inertial");
    assert!(d["model_reason"].as_str().unwrap().contains("degenerate"));
    let curve = d["hopf_curve"].as_array().unwrap();
    assert!(curve.len() > 10);
    for p in curve {
        assert_eq!(p["criticality"], "subcritical", "{p}");
    }
    // Its first point is the scene's velocity: the same l1 as `hopf`.
    let first = curve[0]["l1"].as_f64().unwrap();
    assert!((first / l1 - 1.0).abs() < 1e-9, "{first} vs {l1}");

    // Cycles start from the Hopf point `hopf` resolved (before: exit 3,
    // "degenerate Hopf point: l1 = 3.6e-15 vanishes").
    let (code, text, err) = stickslip(&[
        "cycles",
        "--scene",
        &scene,
        "--max-steps",
        "5",
        "--json",
        "--out",
        out,
    ]);
    assert_eq!(code, 4, "step limit: {err}");
    let c = json(&text);
    assert_eq!(c["model"], "inertial");
    assert_eq!(c["start"]["kind"], "hopf");
    assert_eq!(c["cycles"].as_array().unwrap().len(), 6);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_branch_from_a_simulated_orbit_ends_at_the_hopf_point_it_reaches() {
    let dir = temp_dir("trust-rock-sim");
    let scene = rock(&dir);
    let (code, text, err) = stickslip(&[
        "cycles",
        "--scene",
        &scene,
        "--from-simulation",
        "--json",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let v = json(&text);
    let up = &v["leg_stops"][0];
    assert_eq!(up["leg"], "up");
    assert_eq!(up["reason"], "hopf_point", "{up}");
    // The cycles of the up leg shrink toward the onset and are not traced
    // back (before: Delta_s down to 0.0017, then 27 cycles retraced).
    let cycles = v["cycles"].as_array().unwrap();
    let ds: Vec<f64> = cycles
        .iter()
        .map(|c| c["delta_s"].as_f64().unwrap())
        .collect();
    let smallest = ds.iter().copied().fold(f64::INFINITY, f64::min);
    let at = ds.iter().position(|d| *d == smallest).unwrap();
    assert!(smallest < 0.05 * ds[0], "{ds:?}");
    // After the smallest cycle only the down leg, which starts again at
    // the simulated orbit.
    assert!((ds[at + 1] / ds[0] - 1.0).abs() < 0.01, "{ds:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn no_period_doubling_from_a_multiplier_through_infinity_and_negative_friction_is_named() {
    let dir = temp_dir("trust-mu2");
    let (code, text, err) = stickslip(&[
        "cycles",
        "--set",
        "mu2=-0.01",
        "--max-steps",
        "115",
        "--json",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 4, "step limit: {err}");
    let v = json(&text);
    // Before: 58 period doublings, the one huge nontrivial multiplier
    // (1e10 .. 1e12) changing sign by rounding.
    let kinds: Vec<&Value> = v["special_points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| &p["kind"])
        .collect();
    assert!(!kinds.iter().any(|k| *k == "pd" || *k == "ns"), "{kinds:?}");
    let n = &v["negative_friction"];
    assert!(n["cycles"].as_u64().unwrap() > 0, "{n}");
    assert!(n["friction_min"].as_f64().unwrap() < 0.0);
    assert!(err.contains("negative friction"), "{err}");
    // After the switch to the inertial model, the parameters used carry its m.
    assert!(!v["model_switch"].is_null());
    assert!(v["params"]["m"].as_f64().unwrap() > 0.0);
    let cycles = v["cycles"].as_array().unwrap();
    let last = cycles.last().unwrap();
    assert_eq!(last["model"], "inertial");
    assert_eq!(last["m"], v["params"]["m"]);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_run_that_kept_a_cycle_is_partial_and_requested_points_are_answered_once() {
    let dir = temp_dir("trust-exit");
    let out = dir.to_str().unwrap();
    // Cycles, then a failure: kept, so partial (before: exit 3 after one
    // cycle; since the turns a step cannot locate are taken again shorter,
    // 9 cycles).
    let (code, text, err) = stickslip(&["cycles", "--set", "nu=1e6", "--json", "--out", out]);
    assert_eq!(code, 4, "{err}");
    let kept = json(&text)["cycles"].as_array().unwrap().len();
    assert!(kept >= 1, "{err}");
    assert!(
        err.contains(&format!("partial results: {kept} cycles written")),
        "{err}"
    );
    assert!(!err.contains("reduce the step size"), "{err}");
    // A repeated stiffness once; one that cannot be delivered (above
    // kappa_c) makes the request incomplete (before: exit 0).
    let (code, text, err) = stickslip(&[
        "cycles",
        "--kappa-fraction",
        "0.9",
        "--at-kappa",
        "0.0105,0.02,0.0105",
        "--json",
        "--out",
        out,
        "--force",
    ]);
    assert_eq!(code, 4, "{err}");
    let v = json(&text);
    let requested = v["requested_points"].as_array().unwrap();
    assert_eq!(requested.len(), 2, "{requested:?}");
    let users = v["cycles"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|c| c["user_point"] == true)
        .count();
    assert_eq!(users, 1);
    assert_eq!(v["complete"], false);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_fold_curve_ends_on_its_range_with_a_stop_entry() {
    let dir = temp_dir("trust-lpc-range");
    let (code, text, err) = stickslip(&[
        "diagram",
        "--scene",
        "brockley",
        "--nu-range",
        "1000:20000",
        "--json",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let v = json(&text);
    let nus: Vec<f64> = v["lpc_curve"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["nu"].as_f64().unwrap())
        .collect();
    assert!(nus.len() > 10);
    let hi = nus.iter().copied().fold(0.0, f64::max);
    let lo = nus.iter().copied().fold(f64::INFINITY, f64::min);
    // Before: the last fold a step beyond the range (e.g. 100 566 µm/s for
    // a range ending at 1e5), with no stop entry.
    assert!((hi / 20000.0 - 1.0).abs() < 1e-12, "ends at {hi}");
    assert!(lo >= 1000.0, "starts at {lo}");
    let stops = v["lpc_stops"].as_array().unwrap();
    assert!(
        stops
            .iter()
            .any(|s| s["reason"] == "end_of_range" && s["nu"] == 20000.0),
        "{stops:?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_degenerate_onset_is_not_told_to_add_what_the_scene_has() {
    // pmma-rr has a mass: forced quasi-static, the advice is to drop the
    // forcing, not to add inertia (before: "add the ln² term (mu2) or
    // inertia" whatever the scene).
    let (code, text, err) = stickslip(&["hopf", "--scene", "pmma-rr", "--model", "quasi-static"]);
    assert_eq!(code, 0, "{err}");
    assert!(text.contains("degenerate within rounding"), "{text}");
    assert!(text.contains("without --model quasi-static"), "{text}");
    assert!(!text.contains("inertia (a mass M)"), "{text}");
}

#[test]
fn a_simulated_start_records_the_stiffnesses_it_rejected() {
    // The scene's stiffness is above kappa_c: the simulation there decays,
    // and the branch starts at 0.9 kappa_c; the JSON says so (before: the
    // failed try was in the text only).
    let dir = temp_dir("trust-rejected");
    let (code, text, err) = stickslip(&[
        "cycles",
        "--from-simulation",
        "--set",
        "kappa=0.02",
        "--max-steps",
        "3",
        "--json",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 4, "step limit: {err}");
    let start = &json(&text)["start"];
    assert_eq!(start["kind"], "simulation");
    let rejected = start["rejected"].as_array().unwrap();
    assert_eq!(rejected.len(), 1, "{start}");
    assert_eq!(rejected[0]["kappa"], 0.02);
    assert!(rejected[0]["outcome"].as_str().unwrap().contains("decayed"));
    let kappa_c = json(&text)["kappa_c"].as_f64().unwrap();
    assert!((start["kappa"].as_f64().unwrap() / (0.9 * kappa_c) - 1.0).abs() < 1e-12);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn dropped_inertia_that_reverses_the_onset_type_decides_it_in_every_command() {
    // m = 0.05 at nu = 0.01: the inertia ratio 6.25e-4 is below the 1e-3 that
    // lets the quasi-static model shift kappa_c by that little, yet it turns
    // the quasi-static supercritical onset (l1 = -8.8e-9) subcritical
    // (l1 = +2.4e-8). Before: hopf and cycles quasi-static supercritical,
    // diagram (judged at the top of its range) inertial subcritical.
    let dir = temp_dir("trust-heavy");
    let scene = dir.join("heavy.toml");
    std::fs::write(
        &scene,
        ROCK.replace("mu2 = 0", "mu2 = 1e-6")
            .replace("M = 1.0", "M = 2.5e10"),
    )
    .unwrap();
    let scene = scene.to_str().unwrap();
    let out = dir.to_str().unwrap();
    let (code, text, err) = stickslip(&["hopf", "--scene", scene, "--json"]);
    assert_eq!(code, 0, "{err}");
    let h = json(&text);
    assert_eq!(h["model"], "inertial", "{}", h["model_reason"]);
    assert_eq!(h["criticality"], "subcritical");
    assert!((h["params"]["m"].as_f64().unwrap() / 0.05 - 1.0).abs() < 1e-12);
    let kappa_c = h["kappa_c"].as_f64().unwrap();
    let (code, text, err) = stickslip(&["diagram", "--scene", scene, "--json", "--out", out]);
    assert!(code == 0 || code == 4, "{err}");
    let d = json(&text);
    assert_eq!(d["model"], "inertial");
    let first = &d["hopf_curve"][0];
    assert_eq!(first["criticality"], "subcritical");
    assert!((first["kappa"].as_f64().unwrap() / kappa_c - 1.0).abs() < 1e-12);
    let (code, text, err) = stickslip(&[
        "cycles",
        "--scene",
        scene,
        "--max-steps",
        "2",
        "--json",
        "--out",
        out,
    ]);
    assert_eq!(code, 4, "step limit: {err}");
    let c = json(&text);
    assert_eq!(c["model"], "inertial");
    assert!((c["kappa_c"].as_f64().unwrap() / kappa_c - 1.0).abs() < 1e-12);
    // Subcritical: the cycles born there lie above kappa_c.
    let cycles = c["cycles"].as_array().unwrap();
    assert!(cycles
        .iter()
        .all(|x| x["kappa"].as_f64().unwrap() > kappa_c));
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_stiffness_between_the_onset_and_the_first_cycle_is_explained_as_such() {
    let dir = temp_dir("trust-near-onset");
    let (code, text, err) = stickslip(&[
        "cycles",
        "--at-kappa",
        "0.0109999999",
        "--max-steps",
        "3",
        "--json",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 4, "{err}");
    let r = &json(&text)["requested_points"][0];
    assert_eq!(r["delivered"], false);
    // Before: "the branch stopped at kappa = 1.0999999460e-2 before reaching
    // it", of a branch that started above it and ran downward.
    let why = r["reason"].as_str().unwrap();
    assert!(
        why.contains("between kappa_c") && why.contains("first cycle"),
        "{why}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_empty_branch_advises_only_what_was_not_tried() {
    // mu2 < 0: steady friction has a maximum, not a minimum, and the
    // simulations went down to kappa ~ 1e-7 (before: "try --set kappa=...
    // smaller, or --set nu=... closer to the friction minimum").
    let dir = temp_dir("trust-advice");
    let scene = rock(&dir);
    let (code, text, err) = stickslip(&[
        "cycles",
        "--scene",
        &scene,
        "--set",
        "mu2=-0.01",
        "--json",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let v = json(&text);
    assert_eq!(v["start"]["kind"], "none");
    let why = v["reason"].as_str().unwrap();
    assert!(!why.contains("friction minimum"), "{why}");
    assert!(!why.contains("kappa=... smaller"), "{why}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Huge inertia (`m` up to 1e60, far past any rig): the onset is Appendix
/// C's (eq. C11, exact for the linear stability of steady sliding) to 1e-9,
/// or a numerical failure that says the Jacobian spans too many decades —
/// never "no Hopf point" (which `hopf --set m=1e30` said, exit 0, before
/// the search fell back on Newton's method from the closed form), and
/// never a wrong point (m = 1e19 gave kappa_c ten times too small).
#[test]
fn huge_inertia_locates_the_onset_of_appendix_c_or_says_why_not() {
    use stickslip::analysis::hopf::{find_hopf, HopfOutcome};
    use stickslip::appendix_c::critical_stiffness;
    use stickslip::model::ModelKind;
    let mut located = 0;
    for k in 0..=46 {
        let m = 10f64.powf(14.0 + k as f64);
        let p = common::pmma(m, 2.4e-4);
        let exact = critical_stiffness(&p);
        match find_hopf(ModelKind::Inertial, &p) {
            Ok(HopfOutcome::Found(h)) => {
                assert!(
                    ((h.kappa_c - exact) / exact).abs() < 1e-9,
                    "m = {m:e}: kappa_c {} vs C11 {exact}",
                    h.kappa_c
                );
                located += 1;
            }
            Ok(HopfOutcome::StableForAllStiffness { .. }) => {
                panic!("m = {m:e}: no Hopf point, C11 puts one at {exact:e}")
            }
            Err(e) => assert!(e.to_string().contains("too many decades"), "m = {m:e}: {e}"),
        }
    }
    // 37 of the 47 decades are located today (the others fail as above): a floor.
    assert!(located >= 37, "{located} of 47 located");
}

/// `hopf` where the onset cannot be located in double precision (a direct
/// effect of 1e-12 with `mu_vv`, damping and the slip law): the failure in
/// numbers and why, without the engine's advice to reduce a step or
/// improve a guess, which `hopf` has no option for.
#[test]
fn hopf_gives_no_advice_it_has_no_option_for() {
    let dir = common::temp_dir("trust-hopf-advice");
    let scene = dir.join("granite.toml");
    std::fs::write(
        &scene,
        "A = 0.010\nB = 0.015\nD0 = 10\nmu0 = 0.6\nmu_vv = 2e-4\nM = 5\nW = 1e5\nK = 5e7\n\
         V = 1\nstate_law = \"slip\"\neta = 0.01\n",
    )
    .unwrap();
    let (status, _, err) = common::stickslip(&[
        "hopf",
        "--scene",
        scene.to_str().unwrap(),
        "--set",
        "A=1e-12",
    ]);
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(status, 3, "{err}");
    assert!(err.contains("double precision"), "{err}");
    assert!(!err.contains("reduce the step size"), "{err}");
    assert!(!err.contains("initial guess"), "{err}");
}

/// A bad value in a scene file names the file once before the key (the
/// state law's error named it twice).
#[test]
fn a_bad_scene_value_names_its_file_once() {
    let dir = common::temp_dir("trust-file-once");
    let scene = dir.join("badstate.toml");
    std::fs::write(&scene, "A = 0.01\nstate_law = \"slipp\"\n").unwrap();
    let path = scene.to_str().unwrap();
    let (status, _, err) = common::stickslip(&["hopf", "--scene", path]);
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(status, 2, "{err}");
    assert_eq!(err.matches(path).count(), 1, "{err}");
    assert!(err.contains("state_law"), "{err}");
}

/// A spring compressed by the block's overshoot is not negative friction:
/// with `m = 0.5` (inertial) the spring force swings far below zero while
/// the friction coefficient stays above 0.68; before, the warning called
/// that "negative friction" and quoted the positive coefficient.
#[test]
fn a_compressed_spring_is_not_called_negative_friction() {
    let dir = temp_dir("trust-compressed-spring");
    let scene = dir.join("shear-granite.toml");
    std::fs::write(&scene, common::SHEAR_GRANITE).unwrap();
    let (code, text, err) = stickslip(&[
        "cycles",
        "--scene",
        scene.to_str().unwrap(),
        "--model",
        "inertial",
        "--set",
        "m=0.5",
        "--json",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let v = json(&text);
    let cycles = v["cycles"].as_array().unwrap();
    let least = |key: &str| {
        cycles
            .iter()
            .map(|c| c[key].as_f64().unwrap())
            .fold(f64::INFINITY, f64::min)
    };
    assert!(least("s_min") < -1.0, "the spring is compressed");
    assert!(least("friction_min") > 0.5, "friction stays positive");
    assert!(
        v["negative_friction"].is_null(),
        "{}",
        v["negative_friction"]
    );
    assert!(!err.contains("negative friction"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}
