//! Edges a stranger found in session 12 (issue 22: one model decision for
//! all commands, no panic), each kept fixed as a class:
//!
//! - `simulate`'s regime reached did not depend on the model decision along
//!   the whole orbit: a protocol too short for the run itself to switch to
//!   the inertial model reported the quasi-static cycle (36.2 s, 1.81 N for
//!   the steel-on-granite rig below) where the inertial one (43.75 s,
//!   2.31 N) is the answer, as `cycles` and a long run give. Now the regime
//!   of every protocol length is the same, and equal to the cycle
//!   continued in the stiffness by collocation (an independent method).
//! - a branch from a simulated orbit whose first collocation failed
//!   panicked ("the driver keeps the stop of a branch that ended without an
//!   error": the skipped start swallowed the error); now a typed failure.

mod common;

use common::{stickslip, temp_dir};
use serde_json::Value;

/// A stranger's subcritical rig: a light steel slider with saturating
/// ageing, K above the fold of cycles.
const STEEL: &str = "A = 0.010\nB = 0.020\nmu0 = 0.55\ntau = 1.0e-3\nD0 = 1.0\nV0 = 1.0\n\
                     M = 2.0\nW = 20.0\nV = 800.0\nV_range = [10.0, 10000.0]\nK = 1.7e5\n";

/// `cycles --json` on [`STEEL`] with `extra` options, in a folder of its
/// own named `name`: exit 0, the JSON parsed and as written.
fn steel_cycles(name: &str, extra: &[&str]) -> (Value, String) {
    let dir = temp_dir(name);
    let scene = dir.join("steel.toml");
    std::fs::write(&scene, STEEL).unwrap();
    let out = dir.join("out");
    let mut args = vec![
        "cycles",
        "--scene",
        scene.to_str().unwrap(),
        "--json",
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend(extra);
    let (code, json, err) = stickslip(&args);
    assert_eq!(code, 0, "{err}");
    (serde_json::from_str(&json).unwrap(), json)
}

/// A press-loaded steel-on-granite rig, written as a user would.
const GRANITE: &str = r#"
name = "granite"
description = "steel slider on polished granite, press-loaded"
A = 0.008
B = 0.012
mu0 = 0.65
mu2 = 3e-4
D0 = 5.0
V0 = 1.0
M = 5.0
W = 50.0
K = 2e4
V = 3.0
V_range = [0.3, 300.0]
"#;

/// The period [s] and force drop [N] of the regime `simulate` reports.
fn regime(scene: &str, protocol: &str, out: &str) -> (f64, f64) {
    let (code, text, err) = stickslip(&[
        "simulate",
        "--scene",
        scene,
        "--protocol",
        protocol,
        "--out",
        out,
        "--force",
    ]);
    assert_eq!(code, 0, "{err}");
    let line = text
        .lines()
        .find(|l| l.starts_with("regime reached"))
        .unwrap_or_else(|| panic!("no regime line: {text}"));
    let number_after = |key: &str| -> f64 {
        let rest = &line[line.find(key).unwrap_or_else(|| panic!("{key}: {line}")) + key.len()..];
        rest.split_whitespace().next().unwrap().parse().unwrap()
    };
    (number_after("period "), number_after("force drop "))
}

#[test]
fn the_regime_reached_is_the_same_for_every_protocol_length() {
    let dir = temp_dir("stranger-regime");
    let scene = dir.join("granite.toml");
    std::fs::write(&scene, GRANITE).unwrap();
    let scene = scene.to_str().unwrap();
    let out = dir.join("out");
    let out = out.to_str().unwrap();
    // The cycle at the rig's K, continued from the Hopf point by collocation.
    let (code, json, err) = stickslip(&[
        "cycles", "--scene", scene, "--at", "K=2e4", "--json", "--out", out, "--force",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: Value = serde_json::from_str(&json).unwrap();
    let at_k = v["cycles"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["user_point"] == true)
        .expect("the cycle at K = 2e4 N/m");
    let (period, drop) = (
        at_k["period_s"].as_f64().unwrap(),
        at_k["delta_s_N"].as_f64().unwrap(),
    );
    // Shorter than the first slip, before the run's own switch, and long.
    for protocol in ["3:1e-12", "3:50", "3:300"] {
        let (p, d) = regime(scene, protocol, out);
        let (ep, ed) = ((p / period - 1.0).abs(), (d / drop - 1.0).abs());
        assert!(
            ep < 1e-6 && ed < 1e-5,
            "--protocol {protocol}: period {p} s against {period} s ({ep:.1e}), force drop {d} N \
             against {drop} N ({ed:.1e})"
        );
    }
}

#[test]
fn the_rigs_simulated_orbit_at_one_micron_per_second_starts_its_branch() {
    let dir = temp_dir("stranger-start");
    let scene = dir.join("rig.toml");
    // Issue 24's rig at 1 µm/s: the orbit simulated at K = 2e5 N/m with the
    // onset's quasi-static model needs inertia (its slip reaches 1e5 µm/s).
    // It was corrected quasi-statically and the first collocation failed
    // (status 3); now it is settled in the model the whole orbit needs, as
    // `simulate` judges it, and corrected on enough intervals.
    std::fs::write(
        &scene,
        "name = \"rig\"\nA = 0.012\nB = 0.023\nmu0 = 0.6\nmu2 = 1e-3\nD0 = 0.4\nV0 = 1.0\n\
         M = 1.0\nW = 300.0\nK = 2e5\nV = 1.0\nV_range = [0.1, 100.0]\n",
    )
    .unwrap();
    let out = dir.join("out");
    let (code, stdout, err) = stickslip(&[
        "cycles",
        "--scene",
        scene.to_str().unwrap(),
        "--from-simulation",
        "--out",
        out.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let j: Value = serde_json::from_str(&stdout).unwrap();
    let first = &j["cycles"][0];
    assert_eq!(first["model"], "inertial");
    assert_eq!(first["K_N_per_m"].as_f64().unwrap(), 2e5);
    let op = &j["operating_point"];
    assert_eq!(op["method"], "branch_start");
    assert_eq!(op["cycle"], *first);
    // `simulate --set V=1 --protocol 1:2000`: period 439.5281 s, force drop
    // 87.73421 N (events on a long integration).
    let period = first["period_s"].as_f64().unwrap();
    let drop = first["delta_s_N"].as_f64().unwrap();
    assert!((period / 439.5281 - 1.0).abs() < 1e-6, "{period}");
    assert!((drop / 87.73421 - 1.0).abs() < 1e-6, "{drop}");
}

/// The granite rig in a fresh folder: (scene path, output folder).
fn granite(name: &str) -> (String, String) {
    let dir = temp_dir(name);
    let scene = dir.join("granite.toml");
    std::fs::write(&scene, GRANITE).unwrap();
    (
        scene.to_str().unwrap().to_string(),
        dir.join("out").to_str().unwrap().to_string(),
    )
}

/// `cycles --param V --to` on the side where no cycle is born (above a
/// supercritical onset at 28.2 µm/s) said "end of the requested range",
/// status 0, though the branch went the other way: now partial, and why.
#[test]
fn a_branch_born_away_from_to_says_so() {
    let (scene, out) = granite("stranger-side");
    let (code, _, err) = stickslip(&[
        "cycles",
        "--scene",
        &scene,
        "--param",
        "V",
        "--to",
        "1000",
        "--max-steps",
        "5",
        "--out",
        &out,
    ]);
    assert_eq!(code, 4, "{err}");
    assert!(err.contains("born on the other side"), "{err}");
    // Toward --to from the same onset the branch is whole, and drawn: the
    // force drop and the period against V.
    let (code, _, err) = stickslip(&[
        "cycles", "--scene", &scene, "--param", "V", "--to", "20", "--out", &out, "--force",
    ]);
    assert_eq!(code, 0, "{err}");
    for figure in ["amplitude", "period"] {
        let png = std::path::Path::new(&out).join(format!("granite-cycles-in-V-{figure}.png"));
        assert!(png.is_file(), "{} missing", png.display());
    }
}

/// A pair diagram that finds no onset on its grid is not an empty answer:
/// partial (status 4), with the remedy of the pair's own option.
#[test]
fn a_pair_diagram_without_a_start_is_partial() {
    let (scene, out) = granite("stranger-pair");
    let (code, text, err) = stickslip(&[
        "diagram",
        "--scene",
        &scene,
        "--x",
        "V",
        "--y",
        "M",
        "--y-range",
        "1:2",
        "--out",
        &out,
    ]);
    assert_eq!(code, 4, "{err}");
    assert!(
        text.contains("--y-range") && !text.contains("--from"),
        "{text}"
    );
}

/// From a simulated orbit at the rig's K, `--at K=` that very stiffness was
/// "not delivered" though the branch starts there, and the leg that ran
/// into the Hopf point, where its cycles are born, ended as `failed`: now
/// the start's cycle answers the request and that leg ends at `hopf_point`.
#[test]
fn a_branch_from_a_simulated_orbit_delivers_its_own_stiffness() {
    let (scene, out) = granite("stranger-from-simulation");
    let (code, json, err) = stickslip(&[
        "cycles",
        "--scene",
        &scene,
        "--from-simulation",
        "--at",
        "K=2e4",
        "--json",
        "--out",
        &out,
    ]);
    assert_eq!(code, 0, "{err}");
    let v: Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["requested_points"][0]["delivered"], true, "{json}");
    assert_eq!(
        common::leg_reasons(&v),
        ["hopf_point", "end_of_range"],
        "{json}"
    );
}

/// A search range written downward is refused with the range to give,
/// not silently turned around (issue 22's leftover: `hopf --param V --from
/// 100 --to 10` searched 10 to 100 without a word).
#[test]
fn a_downward_search_range_is_refused_naming_the_options() {
    use stickslip::analysis::control::Control;
    use stickslip::jobs::cycles_in::{CyclesInControlRequest, Plan};
    use stickslip::jobs::hopf::{run, HopfRequest};
    use stickslip::jobs::SceneSpec;
    let rig = SceneSpec::named("examples/scenes/rig.toml");
    let v = Control::from_param(Some("V")).unwrap();
    let ask = |from, to| {
        run(&rig, &HopfRequest { param: v, from, to })
            .err()
            .map(|e| e.to_string())
    };
    let e = ask(Some(100.0), Some(10.0)).unwrap();
    assert!(
        e.contains("--from/--to") && e.contains("give 1e1 to 1e2"),
        "{e}"
    );
    let e = ask(Some(2000.0), None).unwrap();
    assert!(e.contains("--from (with the default --to)"), "{e}");
    assert!(ask(Some(10.0), Some(1000.0)).is_none());
    let request = CyclesInControlRequest {
        control: v.unwrap(),
        to: 150.0,
        search: Some((1000.0, 1.0)),
        at: Vec::new(),
        from_simulation: false,
        max_steps: 10,
        ntst: 40,
        ntst_max: 1280,
        collocation: None,
        from: None,
    };
    let e = Plan::new(&rig, &request).err().unwrap().to_string();
    assert!(
        e.contains("--search") && e.contains("give 1e0 to 1e3"),
        "{e}"
    );
}

/// A quasi-static onset whose simulated orbit needs inertia (m = 3e-6 on
/// the PMMA scene: chi below 1e-3 at the onset, above it on the orbit):
/// the branch starts inertial, on Radau points, and the text and JSON say
/// so. The numerics line used to name the onset's model (Gauss-Legendre
/// points, Liouville's formula) for an inertial branch.
#[test]
fn the_numerics_named_are_those_of_the_first_cycles() {
    use stickslip::jobs::cycles::{CyclesRequest, Plan};
    use stickslip::jobs::{SceneSpec, TextUnits};
    use stickslip::model::ModelKind;
    let spec = SceneSpec {
        set: vec!["m=3e-6".into()],
        ..SceneSpec::named("pmma")
    };
    let request = CyclesRequest {
        from_simulation: true,
        ..CyclesRequest::default()
    };
    let plan = Plan::new(&spec, request).expect("a simulated start");
    assert_eq!(plan.setup.choice.kind, ModelKind::QuasiStatic);
    assert_eq!(
        plan.start.first_model(plan.setup.choice.kind),
        ModelKind::Inertial
    );
    let text = plan.describe(TextUnits::Physical).join("\n");
    assert!(text.contains("collocation: Radau IIA points"), "{text}");
    assert!(text.contains("stability from the Floquet pencil"), "{text}");
    assert!(!text.contains("Liouville"), "{text}");
    assert_eq!(plan.points_name(), "radau");
}

/// A branch from a simulated orbit ends at the Hopf point its cycles
/// shrink onto, also where the last step toward it fails short of SHRUNK
/// (PMMA with m = 1e-2 and 1e-5: the leg toward larger stiffness failed at
/// Delta_s 20 % and 7 % of its largest, exit 4). The last three cycles of
/// that leg follow the normal form's square-root law onto the inertial
/// Hopf point that `hopf` locates independently (eq. C11).
#[test]
fn a_leg_shrinking_onto_its_hopf_point_ends_there() {
    for m in ["1e-2", "1e-5"] {
        let out = temp_dir(&format!("stranger-shrinking-{m}"));
        let set = format!("m={m}");
        let (code, json, err) = stickslip(&[
            "cycles",
            "--set",
            &set,
            "--from-simulation",
            "--json",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "m = {m}: {err}");
        let v: Value = serde_json::from_str(&json).unwrap();
        assert_eq!(v["leg_stops"][0]["reason"], "hopf_point", "m = {m}: {json}");
        // The leg toward larger stiffness: the cycles from the start while
        // kappa grows.
        let cycles = v["cycles"].as_array().unwrap();
        let pts: Vec<(f64, f64)> = cycles
            .iter()
            .map(|c| (c["kappa"].as_f64().unwrap(), c["delta_s"].as_f64().unwrap()))
            .collect();
        let up = pts.windows(2).take_while(|w| w[1].0 > w[0].0).count() + 1;
        let [(p0, d0), (p1, d1), (p2, d2)] = pts[up.saturating_sub(3)..up] else {
            panic!("m = {m}: fewer than three cycles toward larger stiffness: {json}")
        };
        let s1 = (d1 * d1 - d0 * d0) / (p1 - p0);
        let s2 = (d2 * d2 - d1 * d1) / (p2 - p1);
        let zero = p2 - d2 * d2 / s2;
        let (_, hopf, _) = stickslip(&["hopf", "--set", &set, "--model", "inertial", "--json"]);
        let h: Value = serde_json::from_str(&hopf).unwrap();
        let kappa_c = h["kappa_c"].as_f64().unwrap();
        assert!((s1 / s2 - 1.0).abs() < 0.1, "m = {m}: slopes {s1} {s2}");
        assert!(
            (zero - kappa_c).abs() < 0.05 * (kappa_c - p2),
            "m = {m}: zero at {zero}, kappa_c {kappa_c}, last {p2}"
        );
    }
}

/// A protocol that ends by stopping the drive (docs/cycles.md's stop-and-go
/// example) is complete: the block creeps toward rest, a regime of its own
/// (`held`), not an undetermined one. It was exit 4 with "the time span
/// [0, inf] is not finite" from the settling run at V = 0.
#[test]
fn a_protocol_ending_with_the_drive_stopped_is_complete() {
    let out = temp_dir("stranger-held");
    let (code, json, err) = stickslip(&[
        "simulate",
        "--set",
        "kappa=10",
        "--protocol",
        "1:20,10:2,0:100",
        "--json",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let v: Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["complete"], true, "{json}");
    assert_eq!(v["regime"]["kind"], "held", "{json}");
    assert!(!err.contains("not finite"), "{err}");
}

/// A stranger's subcritical rig (saturating ageing, a light steel slider):
/// the branch from its simulated stable cycle goes up to the fold of cycles,
/// one step lands on the small unstable cycles near the Hopf point (8 % of
/// the largest amplitude), and the next went through the Hopf point and back
/// along the stable cycles it had traced (exit 0, "end_of_range", the stable
/// branch twice). Now the pass through the equilibrium is seen (the orbit
/// turned around, half a period) and the leg ends at the Hopf point.
#[test]
fn a_leg_through_its_hopf_point_after_a_fold_ends_there() {
    let (v, json) = steel_cycles("stranger-steel", &["--from-simulation"]);
    assert_eq!(v["leg_stops"][0]["leg"], "up", "{json}");
    assert_eq!(v["leg_stops"][0]["reason"], "hopf_point", "{json}");
    let folds = v["special_points"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|p| p["kind"] == "lpc")
        .count();
    assert_eq!(folds, 1, "{json}");
    // The cycles run from the start up to the fold and the Hopf point,
    // then the down leg from the start: the first cycle below the start's
    // stiffness is the down leg's first step, close to it. (Retracing, the
    // up leg went on below the start, 10 % away at its first cycle there.)
    let start = v["start"]["kappa"].as_f64().unwrap();
    let first_below = v["cycles"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["kappa"].as_f64().unwrap())
        .find(|&k| k < start)
        .unwrap();
    assert!(
        (first_below / start - 1.0).abs() < 0.01,
        "the up leg retraced the stable cycles below its start: {first_below} vs {start}"
    );
}

/// On the subcritical steel rig, `cycles` locates the fold of cycles below
/// the rig's K (K_fold = 1.6456e5 N/m < 1.7e5): the operating point is
/// steady sliding, not "undecided ... `stickslip cycles` locates it" (which
/// this run had just done), and no cycle is wanted there.
#[test]
fn the_operating_point_is_decided_by_the_fold_the_branch_locates() {
    let (v, _) = steel_cycles("stranger-steel-op", &[]);
    let op = &v["operating_point"];
    assert_eq!(op["regime"], "steady", "{op}");
    assert_eq!(op["wanted"], false, "{op}");
    assert!(
        op["reason"].as_str().unwrap().contains("above the fold"),
        "{op}"
    );
    let fold = v["special_points"][0]["kappa"].as_f64().unwrap();
    assert!(fold < op["kappa"].as_f64().unwrap() && fold > v["kappa_c"].as_f64().unwrap());
    assert_eq!(v["complete"], true);
}

/// The figures of a branch in V draw its cycles in their order along the
/// branch: the leg toward smaller V reversed, then the other, so a branch
/// without a fold is monotone in V. They were drawn in the order computed,
/// and the line from the end of one leg to the start of the other drew a
/// closed loop (a stranger took it for hysteresis).
#[test]
fn a_branch_in_v_is_drawn_along_the_branch() {
    use stickslip::analysis::control::Control;
    use stickslip::jobs::cycles::Quiet;
    use stickslip::jobs::cycles_in::{CyclesInControlRequest, Plan};
    use stickslip::jobs::SceneSpec;
    let rig = SceneSpec::named("examples/scenes/rig.toml");
    let request = CyclesInControlRequest {
        control: Control::from_param(Some("V")).unwrap().unwrap(),
        to: 150.0,
        search: None,
        at: Vec::new(),
        from_simulation: true,
        max_steps: 500,
        ntst: 40,
        ntst_max: 1280,
        collocation: None,
        from: None,
    };
    let plan = Plan::new(&rig, &request).unwrap();
    let axis = plan.axis();
    let result = plan.run(&mut Quiet).unwrap();
    let legs = result.leg_stops.len();
    assert_eq!(legs, 2, "both legs from the simulated orbit");
    let along: Vec<f64> = result
        .along_branch
        .iter()
        .map(|&i| axis.value_of(&result.cycles[i]))
        .collect();
    assert_eq!(along.len(), result.cycles.len());
    assert!(
        along.windows(2).all(|w| w[1] >= w[0]) || along.windows(2).all(|w| w[1] <= w[0]),
        "not monotone along the branch: {along:?}"
    );
}

/// A stranger's steel-on-PMMA rig (session 25), `K` below `K_c`: steady
/// sliding repels at the pulling velocity.
const STEEL_PMMA: &str = "A = 0.010\nB = 0.018\nmu0 = 0.45\nmu2 = 3e-4\nD0 = 0.5\nV0 = 1.0\n\
                          M = 0.3\nW = 50.0\nK = 6e5\nV = 5.0\nV_range = [0.5, 200.0]\n";

/// `simulate --perturb P` started closer to a repelling steady sliding than
/// the integrator's tolerance reported steady sliding with exit 0 (two
/// steps over 60 s: Radau IIA's long steps damped the growing oscillation
/// they did not resolve, and the regime's search called a start 1e-6 off
/// steady sliding decayed at once). Every perturbation, down to none (the
/// rounding grows), reaches the stick-slip cycle the default perturbation
/// and `cycles` reach.
#[test]
fn a_small_perturbation_of_repelling_steady_sliding_grows_to_the_cycle() {
    let dir = temp_dir("steel-pmma-perturb");
    let scene = dir.join("steelpmma.toml");
    std::fs::write(&scene, STEEL_PMMA).unwrap();
    let out = dir.join("out");
    let run = |perturb: &str| {
        let (status, stdout, err) = stickslip(&[
            "simulate",
            "--scene",
            scene.to_str().unwrap(),
            "--perturb",
            perturb,
            "--protocol",
            "5:60",
            "--json",
            "--out",
            out.to_str().unwrap(),
            "--force",
        ]);
        assert_eq!(status, 0, "--perturb {perturb}: {err}");
        let v: Value = serde_json::from_str(&stdout).unwrap();
        let regime = v["regime"].clone();
        assert_eq!(regime["kind"], "periodic", "--perturb {perturb}: {regime}");
        (
            regime["period_s"].as_f64().unwrap(),
            regime["force_drop_N"].as_f64().unwrap(),
        )
    };
    let (period, drop) = run("0.01");
    for perturb in ["0", "1e-12", "1e-9", "1e-6", "7e-5"] {
        let (p, d) = run(perturb);
        assert!(
            (p / period - 1.0).abs() < 1e-6,
            "--perturb {perturb}: {p} s against {period} s"
        );
        assert!(
            (d / drop - 1.0).abs() < 1e-6,
            "--perturb {perturb}: {d} N against {drop} N"
        );
    }
    // The cycle continued by collocation to the same stiffness agrees.
    let (status, stdout, err) = stickslip(&[
        "cycles",
        "--scene",
        scene.to_str().unwrap(),
        "--at",
        "K=6e5",
        "--json",
        "--out",
        out.to_str().unwrap(),
        "--force",
    ]);
    assert_eq!(status, 0, "{err}");
    let v: Value = serde_json::from_str(&stdout).unwrap();
    let at = v["cycles"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["user_point"] == true)
        .unwrap_or_else(|| panic!("no cycle at K = 6e5 N/m: {err}"));
    let (p, d) = (
        at["period_s"].as_f64().unwrap(),
        at["delta_s_N"].as_f64().unwrap(),
    );
    assert!(
        (p / period - 1.0).abs() < 1e-6,
        "cycles {p} s, simulate {period} s"
    );
    assert!(
        (d / drop - 1.0).abs() < 1e-6,
        "cycles {d} N, simulate {drop} N"
    );
}

/// Input messages a stranger met (session 25): a negative `--nu-range` was
/// clap's "unexpected argument '-1'" (not naming the option); an empty
/// `--from/--to` range was advised "give 1e1 to 1e1", the range refused; a
/// misspelt scene was offered every built-in but `gel`.
#[test]
fn input_messages_name_the_field_and_never_repeat_the_refused_input() {
    let dir = temp_dir("input-messages");
    let out = dir.to_str().unwrap();
    let (status, _, err) = stickslip(&["diagram", "--nu-range", "-1:10", "--out", out]);
    assert_eq!(status, 2, "{err}");
    assert!(err.contains("--nu-range") && err.contains("-1:10"), "{err}");
    let (status, _, err) = stickslip(&["hopf", "--param", "V", "--from", "10", "--to", "10"]);
    assert_eq!(status, 2, "{err}");
    assert!(
        err.contains("empty") && !err.contains("give 1e1 to 1e1"),
        "{err}"
    );
    let (status, _, err) = stickslip(&["hopf", "--scene", "gle"]);
    assert_eq!(status, 2, "{err}");
    assert!(err.contains("did you mean 'gel'"), "{err}");
}
