//! The adhesive family's verdicts, each against an independent value:
//!
//! - `cycles` above `V_c` (steady friction rising with the velocity, the
//!   closed form D2 differentiated by finite differences) is a physical
//!   answer, exit 0, with its reason, confirmed by a simulation from a
//!   stick;
//! - `hopf`, `diagram` and `cycles` give one onset verdict over a range of
//!   `tau_on` (the presence of an onset against the sign of `dF_ss/dV`);
//! - the inertial branch of the PVA gel with a 10 kg block ends where its
//!   cycle grazes `v = 0` (no repeated rows), which `simulate` confirms
//!   (its integration fails just below that stiffness, and above it the
//!   settled cycle is collocation's);
//! - a subcritical onset's fold of cycles is reported, and a simulation
//!   from a stick finds large stick-slip just below it and none above.

mod common;

use common::{json_of, stickslip, temp_dir};
use stickslip::adhesive::block::steady_friction;
use stickslip::adhesive::params::AdhesiveParams;

fn field(v: &serde_json::Value, key: &str) -> f64 {
    v[key]
        .as_f64()
        .unwrap_or_else(|| panic!("{key} missing in {v}"))
}

fn rel(a: f64, b: f64) -> f64 {
    ((a - b) / b).abs()
}

/// The PVA hydrogel of a stranger's scene file, with `M = 10 kg`.
const PVA_HEAVY: &str = "law = \"adhesive\"
name = \"pva\"
F_a = 0.02
V_s = 0.05
tau_out = 2.0
tau_on = 0.2
F_v = 2e-4
alpha = 0.5
M = 10.0
K = 100.0
V = 10.0
V_range = [0.1, 1000.0]
";

/// `dF_ss/dnu` of the closed form (D2) by central differences in `ln nu`,
/// at the gel's numbers with `r = tau_on / tau_out`.
fn gel_slope(nu: f64, r: f64) -> f64 {
    let p = AdhesiveParams {
        nu,
        kappa: 1e-4,
        r,
        f_v: 0.01,
        alpha: 0.6,
        m: 0.0,
    };
    let h = 1e-4;
    (steady_friction(nu * (1.0 + h), &p) - steady_friction(nu * (1.0 - h), &p)) / (2.0 * h * nu)
}

/// Above V_c (96.2 µm/s for the gel) steady friction rises with V:
/// `cycles` answers "no stick-slip", exit 0, with the reason in text and
/// JSON, from a simulation at the scene's K started from a stick.
#[test]
fn cycles_above_v_c_is_a_physical_answer() {
    let dir = temp_dir("adhesive-above-vc");
    let out = dir.to_str().unwrap();
    // V = 200 µm/s is nu = 8000 (V_s = 0.025 µm/s).
    assert!(gel_slope(8000.0, 0.1) > 0.0);
    let (status, v, err) = json_of(&[
        "cycles", "--scene", "gel", "--set", "V=200", "--json", "--out", out,
    ]);
    assert_eq!(status, 0, "{err}");
    assert_eq!(v["status"], "stable_for_all_stiffness", "{v}");
    assert_eq!(v["complete"], true);
    assert!(v["onset"].is_null() && v["cycles"].as_array().unwrap().is_empty());
    let reason = v["reason"].as_str().unwrap();
    assert!(reason.contains("stable at every stiffness"), "{reason}");
    assert!(reason.contains("settles on steady sliding"), "{reason}");
    assert_eq!(v["operating_point"]["regime"], "steady");
    let (status, text, err) = stickslip(&[
        "cycles", "--scene", "gel", "--set", "V=200", "--out", out, "--name", "text",
    ]);
    assert_eq!(status, 0, "{err}");
    assert!(text.contains("no cycles: steady friction rises"), "{text}");
    // No figure of an empty branch.
    assert!(!dir.join("text-cycles-period.png").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// `hopf`, `diagram` (its operating point) and `cycles` on the gel at its
/// 20 µm/s (nu = 800) over `tau_on`: an onset exactly where steady friction
/// falls with V (the closed form's slope), the same onset type in `hopf`
/// and `cycles`, the same regime at the scene's K in `hopf` and `diagram`;
/// `cycles` decides the undecided no-onset case by simulation.
#[test]
fn hopf_diagram_and_cycles_agree_over_tau_on() {
    let dir = temp_dir("adhesive-one-verdict");
    for tau_on in [0.05, 0.3, 0.5, 0.8, 2.0, 20.0] {
        let set = format!("tau_on={tau_on}");
        let weakening = gel_slope(800.0, tau_on) < 0.0;
        let (status, h, err) = json_of(&["hopf", "--scene", "gel", "--set", &set, "--json"]);
        assert_eq!(status, 0, "{set}: {err}");
        let out = dir.join(format!("d{tau_on}"));
        let (status, d, err) = json_of(&[
            "diagram",
            "--scene",
            "gel",
            "--set",
            &set,
            "--json",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(status, 0, "{set}: {err}");
        let (status, c, err) = json_of(&[
            "cycles",
            "--scene",
            "gel",
            "--set",
            &set,
            "--json",
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(status, 0, "{set}: {err}");
        assert_eq!(h["status"] == "onset", weakening, "{set}: {h}");
        assert_eq!(c["onset"].is_object(), weakening, "{set}: {c}");
        let op = &d["operating_point"];
        assert_eq!(op["kappa_c"].is_number(), weakening, "{set}: {op}");
        assert_eq!(h["operating_point"]["regime"], op["regime"], "{set}");
        if weakening {
            assert_eq!(h["critical"]["onset"], c["onset"]["onset"], "{set}");
            assert_eq!(c["operating_point"]["regime"], op["regime"], "{set}");
            // The same onset, or, where `cycles` judged its orbit to need
            // the inertia `hopf` drops at V, raised by the factor 1 + chi.
            let ratio = field(&c["onset"], "kappa_c") / field(&h["critical"], "kappa_c");
            let expected = match (h["model"].as_str(), c["model"].as_str()) {
                (Some("quasi-static"), Some("inertial")) => 1.0 + field(&h, "inertia_ratio"),
                _ => 1.0,
            };
            assert!(
                (ratio / expected - 1.0).abs() < 1e-9,
                "{set}: {ratio} {expected}"
            );
        } else {
            assert_eq!(h["status"], "stable_for_all_stiffness", "{set}");
            assert_eq!(c["status"], "stable_for_all_stiffness", "{set}");
            assert_eq!(op["regime"], "undecided", "{set}");
            assert!(
                h["regime"].as_str().unwrap().starts_with("undecided"),
                "{set}: {h}"
            );
            assert_eq!(c["operating_point"]["regime"], "steady", "{set}: {c}");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The heavy PVA block (10 kg): its cycles grow from the onset at
/// K_c = 25651 N/m until the cycle grazes v = 0 near K = 20172 N/m, where
/// the branch stalls in K while the least velocity falls to nothing. The
/// branch ends there (exit 4, saying why, no repeated rows); `simulate`
/// confirms it: its integration fails just below (the block would stop
/// and be pushed back), and just above, at K = 20250 N/m, its settled
/// cycle is collocation's.
#[test]
fn the_heavy_pva_branch_ends_where_the_cycle_grazes_zero_velocity() {
    let dir = temp_dir("adhesive-grazing");
    let path = dir.join("pva.toml");
    std::fs::write(&path, PVA_HEAVY).unwrap();
    let scene = path.to_str().unwrap();
    let out = dir.to_str().unwrap();
    let (status, v, err) = json_of(&["cycles", "--scene", scene, "--json", "--out", out]);
    assert_eq!(status, 4, "{err}");
    let stop = v["stop"].as_str().unwrap();
    assert!(stop.contains("grazes v = 0"), "{stop}");
    let cycles = v["cycles"].as_array().unwrap();
    let kappas: Vec<f64> = cycles.iter().map(|c| field(c, "kappa")).collect();
    assert!(kappas.len() > 20, "{kappas:?}");
    // The text's row: K, period, force drop, v_max to six digits.
    let row = |c: &serde_json::Value| {
        ["kappa", "period", "s_min", "s_max", "u_max"]
            .map(|k| format!("{:.5e}", field(c, k)))
            .join(" ")
    };
    for w in cycles.windows(2) {
        assert_ne!(row(&w[0]), row(&w[1]), "a repeated row");
    }
    // K = kappa F_a / (V_s tau_out) = 2e5 kappa N/m.
    let k_graze = 2e5 * kappas.last().unwrap();
    assert!((20100.0..20250.0).contains(&k_graze), "{k_graze}");
    let (status, _, err) = stickslip(&[
        "simulate",
        "--scene",
        scene,
        "--set",
        "K=20100",
        "--protocol",
        "10:60",
        "--out",
        out,
    ]);
    assert_eq!(status, 4, "the block reverses below the grazing: {err}");
    assert!(err.contains("step size underflow"), "{err}");

    let (status, c, err) = json_of(&[
        "cycles", "--scene", scene, "--set", "K=20250", "--json", "--out", out,
    ]);
    assert_eq!(status, 0, "{err}");
    let (status, s, err) = json_of(&[
        "simulate",
        "--scene",
        scene,
        "--set",
        "K=20250",
        "--protocol",
        "10:60",
        "--json",
        "--out",
        out,
    ]);
    assert_eq!(status, 0, "{err}");
    let at = &c["at_scene"];
    let units = &c["units"];
    let period_s = field(at, "period") * field(units, "tau_out_s");
    let drop_n = (field(at, "s_max") - field(at, "s_min")) * field(units, "F_a_N");
    assert!(
        rel(period_s, field(&s, "settled_period_s")) < 1e-4,
        "{period_s} {s}"
    );
    assert!(
        rel(drop_n, field(&s, "settled_force_drop_N")) < 1e-4,
        "{drop_n} {s}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The gel at 0.7 µm/s has a subcritical onset (K_c = 39208 N/m): its
/// branch turns at a fold of cycles above K_c, which `cycles` reports and
/// judges the scene's K against. A simulation from a stick (n = 1)
/// settles on large stick-slip 0.5 % below the fold and on none 1 % above.
#[test]
fn a_subcritical_onsets_fold_of_cycles_is_reported() {
    let dir = temp_dir("adhesive-fold");
    let out = dir.to_str().unwrap();
    let (status, v, err) = json_of(&[
        "cycles", "--scene", "gel", "--set", "V=0.7", "--set", "K=1e6", "--json", "--out", out,
    ]);
    assert_eq!(status, 0, "{err}");
    assert_eq!(v["onset"]["onset"], "subcritical");
    let folds = v["folds"].as_array().unwrap();
    assert_eq!(folds.len(), 1, "{v}");
    let kappa_c = field(&v["onset"], "kappa_c");
    let kappa_fold = field(&folds[0], "kappa");
    assert!(kappa_fold > kappa_c * 1.01, "{kappa_fold} {kappa_c}");
    let op = &v["operating_point"];
    assert_eq!(op["regime"], "steady", "{op}");
    assert!(rel(field(op, "kappa_fold"), kappa_fold) < 1e-12);
    let (status, text, err) = stickslip(&[
        "cycles", "--scene", "gel", "--set", "V=0.7", "--set", "K=1e6", "--out", out, "--name",
        "text",
    ]);
    assert_eq!(status, 0, "{err}");
    assert!(text.contains("fold of cycles (lpc) at K = "), "{text}");

    // Bistability below the fold, by simulation from a stick: the bond
    // fraction at rest of the steady state at 0.7 µm/s raised to 1.
    let h = common::hopf_json(&["--scene", "gel", "--set", "V=0.7"]);
    let perturb = format!("{}", 1.0 / field(&h, "steady_bonds") - 1.0);
    let k_fold = 2e6 * kappa_fold; // K = kappa F_a / (V_s tau_out)
    let drop_at = |k: f64| {
        let (status, s, err) = json_of(&[
            "simulate",
            "--scene",
            "gel",
            "--set",
            "V=0.7",
            "--set",
            &format!("K={k}"),
            "--perturb",
            &perturb,
            "--protocol",
            "0.7:200",
            "--json",
            "--out",
            out,
        ]);
        assert_eq!(status, 0, "{err}");
        field(&s, "settled_force_drop_N")
    };
    assert!(
        drop_at(0.995 * k_fold) > 0.05,
        "large stick-slip below the fold"
    );
    assert!(
        drop_at(1.01 * k_fold) < 1e-3,
        "no large stick-slip above it"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The gel at 0.7 µm/s with K = 40000 N/m lies in the bistable band
/// (K_c = 39208 N/m < K < the fold of cycles, 40726 N/m): the cycle
/// `cycles` reports at the scene's K is at that K (kappa = K V_s tau_out /
/// F_a = 0.02 exactly), the stable one of the two the branch passes there,
/// and it is the stick-slip `simulate` settles on from a stick (a second
/// method: Radau IIA in time, started with every chain bonded), period and
/// force drop to 1e-6; a small perturbation of steady sliding decays
/// (steady sliding stable too: bistable). Above the fold (41000 N/m) there
/// is no cycle at K, and `cycles` says why, exit 0; the simulation from a
/// stick settles on steady sliding there. Before, `at_scene` was the cycle
/// at the branch's end, 0.5 K_c.
#[test]
fn the_cycle_at_a_bistable_scenes_k_is_the_stable_one_at_that_k() {
    let dir = temp_dir("adhesive-bistable-at-k");
    let out = dir.to_str().unwrap();
    let run = |cmd: &str, k: &str, extra: &[&str]| {
        let set_k = format!("K={k}");
        let (status, v, err) = json_of(
            &[
                &[
                    cmd, "--scene", "gel", "--set", "V=0.7", "--set", &set_k, "--json", "--out",
                    out, "--force",
                ][..],
                extra,
            ]
            .concat(),
        );
        assert_eq!(status, 0, "{cmd} {k}: {err}");
        v
    };
    let v = run("cycles", "40000", &[]);
    assert_eq!(v["operating_point"]["regime"], "bistable", "{v}");
    let at = &v["at_scene"];
    assert!(rel(field(at, "kappa"), 0.02) < 1e-9, "{at}");
    assert_eq!(at["stable"], true, "{at}");
    assert!(v["at_scene_reason"].is_null());
    let units = &v["units"];
    let period_s = field(at, "period") * field(units, "tau_out_s");
    let drop_n = (field(at, "s_max") - field(at, "s_min")) * field(units, "F_a_N");
    // Every chain bonded: n_ss (1 + perturb) = 1 with n_ss = 0.5080681.
    let h = common::hopf_json(&["--scene", "gel", "--set", "V=0.7"]);
    let stick = format!("{}", 1.0 / field(&h, "steady_bonds") - 1.0);
    let s = run(
        "simulate",
        "40000",
        &["--perturb", &stick, "--protocol", "0.7:200"],
    );
    assert_eq!(s["regime"], "periodic", "{s}");
    assert!(
        rel(period_s, field(&s, "settled_period_s")) < 1e-6,
        "{period_s} {s}"
    );
    assert!(
        rel(drop_n, field(&s, "settled_force_drop_N")) < 1e-6,
        "{drop_n} {s}"
    );
    let s = run(
        "simulate",
        "40000",
        &["--perturb", "0.01", "--protocol", "0.7:3000"],
    );
    assert_eq!(
        s["regime"], "steady",
        "steady sliding is stable at K too: {s}"
    );

    let v = run("cycles", "41000", &[]);
    assert_eq!(v["operating_point"]["regime"], "steady", "{v}");
    assert!(v["at_scene"].is_null(), "{v}");
    let why = v["at_scene_reason"].as_str().unwrap_or_default();
    assert!(
        why.contains("fold of cycles") && why.contains("4.100000e4 N/m"),
        "{why}"
    );
    let s = run(
        "simulate",
        "41000",
        &["--perturb", &stick, "--protocol", "0.7:3000"],
    );
    assert_eq!(s["regime"], "steady", "{s}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `cycles` judges the model on the orbit too, as the rate-and-state
/// cycles do: the gel's 1 g block is quasi-static by `chi` at 20 µm/s
/// (4.4e-4), but on its quasi-static orbit at 200 N/m the dropped inertia
/// force shifts `ln v` by 1.458 at the slip (mpmath on the same formula
/// over a `simulate` run: 1.4577), so the branch runs inertial and says
/// why; with 1 µg the shift is a millionth of that (the quasi-static orbit
/// does not see the mass) and the model stays quasi-static.
#[test]
fn cycles_judge_the_model_on_the_orbit() {
    let dir = temp_dir("adhesive-orbit-model");
    let out = dir.to_str().unwrap();
    let (status, v, err) = json_of(&["cycles", "--scene", "gel", "--json", "--out", out]);
    assert_eq!(status, 0, "{err}");
    assert_eq!(v["model"], "inertial", "{}", v["model_reason"]);
    let chi = field(&v, "orbit_inertia_ratio");
    assert!((chi - 1.4577).abs() < 1e-3, "{chi}");
    let reason = v["model_reason"].as_str().unwrap();
    assert!(
        reason.contains("on the quasi-static orbit at K = 2.000000e2 N/m"),
        "{reason}"
    );
    let (status, light, err) = json_of(&[
        "cycles", "--scene", "gel", "--set", "M=1e-9", "--json", "--out", out,
    ]);
    assert_eq!(status, 0, "{err}");
    assert_eq!(light["model"], "quasi-static");
    assert!(rel(field(&light, "orbit_inertia_ratio"), 1e-6 * chi) < 1e-3);
    // Forced, the model is not judged.
    let (status, forced, err) = json_of(&[
        "cycles",
        "--scene",
        "gel",
        "--model",
        "quasi-static",
        "--json",
        "--out",
        out,
        "--name",
        "forced",
    ]);
    assert_eq!(status, 0, "{err}");
    assert_eq!(forced["model"], "quasi-static");
    assert!(forced["orbit_inertia_ratio"].is_null());
    let _ = std::fs::remove_dir_all(&dir);
}

/// The gel scene's file text with `V_range` replaced.
fn gel_with_range(lo: f64, hi: f64) -> String {
    format!(
        "law = \"adhesive\"
name = \"gelr\"
F_a = 0.05
V_s = 0.025
tau_out = 1.0
tau_on = 0.1
F_v = 5e-4
alpha = 0.6
M = 1e-3
K = 200.0
V = 20.0
V_range = [{lo}, {hi}]
"
    )
}

/// The stability figure: the subcritical stretch below the gel's Bautin
/// point ends at the located point, where `hopf` (another method: the
/// steady branch continued in kappa) finds the onset subcritical 1 % below
/// and supercritical 1 % above; the friction extrema's vertical lines only
/// inside the figure's range; no figure at all without an onset in the
/// range, the text saying why.
#[test]
fn the_stability_figure_draws_what_is_there() {
    let dir = temp_dir("adhesive-stability-figure");
    let out = dir.to_str().unwrap();
    let (status, v, err) = json_of(&["diagram", "--scene", "gel", "--json", "--out", out]);
    assert_eq!(status, 0, "{err}");
    let bautin = v["bautin_points"].as_array().unwrap();
    assert_eq!(bautin.len(), 1, "{v}");
    let b = &bautin[0];
    assert_eq!(b["below"], "subcritical");
    assert_eq!(b["above"], "supercritical");
    let v_b = field(b, "V_um_per_s");
    assert!((0.708..0.794).contains(&v_b), "{v_b}");
    for (factor, onset) in [(0.99, "subcritical"), (1.01, "supercritical")] {
        let h = common::hopf_json(&[
            "--scene",
            "gel",
            "--model",
            v["model"].as_str().unwrap(),
            "--set",
            &format!("V={}", factor * v_b),
        ]);
        assert_eq!(h["critical"]["onset"], onset, "{factor}: {h}");
    }
    let svg = std::fs::read_to_string(dir.join("gel-diagram-stability.svg")).unwrap();
    assert!(svg.contains("friction maximum V_max") && svg.contains("friction minimum V_c"));

    let path = dir.join("gelr.toml");
    std::fs::write(&path, gel_with_range(2.0, 50.0)).unwrap();
    let (status, _, err) = stickslip(&["diagram", "--scene", path.to_str().unwrap(), "--out", out]);
    assert_eq!(status, 0, "{err}");
    let svg = std::fs::read_to_string(dir.join("gelr-diagram-stability.svg")).unwrap();
    assert!(
        !svg.contains("V_max") && !svg.contains("V_c"),
        "lines outside 2..50 µm/s"
    );

    let (status, text, err) = stickslip(&[
        "diagram",
        "--scene",
        "gel",
        "--set",
        "tau_on=20",
        "--out",
        out,
        "--name",
        "slow",
    ]);
    assert_eq!(status, 0, "{err}");
    assert!(
        text.contains("no stability figure: steady sliding is stable"),
        "{text}"
    );
    assert!(!dir.join("slow-diagram-stability.png").exists());
    assert!(dir.join("slow-diagram-steady-friction.png").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Options of the rate-and-state commands that mean nothing on an
/// adhesive scene are refused, exit 2, naming the option and why;
/// `branch --csv` is honoured, its rows the JSON's points.
#[test]
fn adhesive_options_are_honoured_or_refused_with_a_reason() {
    for (args, option, why) in [
        (
            &["branch", "--param", "V", "--max-steps", "10"][..],
            "--max-steps",
            "no continuation steps",
        ),
        (
            &["diagram", "--max-steps", "10"][..],
            "--max-steps",
            "no continuation steps",
        ),
        (
            &["hopf", "--units", "dimensionless"][..],
            "--units",
            "dimensionless one beside",
        ),
        (
            &["cycles", "--units", "dimensionless"][..],
            "--units",
            "dimensionless one beside",
        ),
        (
            &["simulate", "--units", "dimensionless"][..],
            "--units",
            "dimensionless one beside",
        ),
    ] {
        let (status, _, err) = stickslip(&[args, &["--scene", "gel"]].concat());
        assert_eq!(status, 2, "{args:?}: {err}");
        assert!(err.contains(option) && err.contains(why), "{args:?}: {err}");
    }
    let (status, csv, err) = stickslip(&["branch", "--scene", "gel", "--param", "V", "--csv"]);
    assert_eq!(status, 0, "{err}");
    let (status, v, err) = json_of(&["branch", "--scene", "gel", "--param", "V", "--json"]);
    assert_eq!(status, 0, "{err}");
    let rows: Vec<Vec<f64>> = csv
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with('V'))
        .map(|l| l.split(',').filter_map(|x| x.parse().ok()).collect())
        .collect();
    let points = v["points"].as_array().unwrap();
    assert_eq!(rows.len(), points.len());
    for (row, p) in rows.iter().zip(points) {
        assert_eq!(row[0], field(p, "V_um_per_s"));
        assert_eq!(row[1], field(p, "steady_force_N"));
    }
    let hopf_lines = csv.lines().filter(|l| l.starts_with("# hopf")).count();
    assert_eq!(hopf_lines, v["hopf_points"].as_array().unwrap().len());
}

/// A PVA scene without a spring (`K` is optional): `diagram` draws its
/// stability diagram, exit 0, and the critical stiffnesses are those of the
/// same scene with a spring (they do not depend on the scene's `K`);
/// before, the stability change of steady sliding at zero stiffness (a zero
/// eigenvalue where the friction slope changes sign) was located as a Hopf
/// point and the command failed (exit 3, singular Jacobian).
#[test]
fn a_scene_without_a_spring_has_its_stability_diagram() {
    let dir = temp_dir("adhesive-no-spring");
    let scene = |k: &str| {
        let path = dir.join(format!("pva{k}.toml"));
        let text = format!(
            "law = \"adhesive\"\nname = \"pva{k}\"\nF_a = 0.02\nV_s = 0.05\ntau_out = 2.0\n\
             tau_on = 0.2\nF_v = 2e-4\nalpha = 0.5\nM = 2e-3\nV = 10.0\n\
             V_range = [0.1, 1000.0]\n{k}"
        );
        std::fs::write(&path, text).unwrap();
        path.to_str().unwrap().to_string()
    };
    let out = dir.join("out");
    let out = out.to_str().unwrap();
    let run = |path: &str| {
        let (code, v, err) = json_of(&[
            "diagram", "--scene", path, "--out", out, "--force", "--json",
        ]);
        assert_eq!(code, 0, "{err}");
        v
    };
    let (without, with) = (run(&scene("")), run(&scene("K = 500.0")));
    let k_c = |v: &serde_json::Value| -> Vec<Option<f64>> {
        v["points"]
            .as_array()
            .expect("points")
            .iter()
            .map(|p| p["K_N_per_m"].as_f64())
            .collect()
    };
    let (a, b) = (k_c(&without), k_c(&with));
    assert!(a.iter().filter(|k| k.is_some()).count() > 10, "{a:?}");
    assert_eq!(a, b);
}

/// The 10 kg gel: its branch ends where the cycle grazes `v = 0`, and the
/// simulation at the branch's end (the second method) does not finish; the
/// answer keeps the branch, partial (exit 4, `complete: false`, the JSON
/// printed), instead of a numerical failure that dropped it (exit 3).
#[test]
fn a_heavy_gels_branch_is_kept_when_the_second_method_fails() {
    let dir = temp_dir("adhesive-heavy-gel");
    let out = dir.to_str().unwrap();
    let (code, v, err) = json_of(&[
        "cycles", "--scene", "gel", "--set", "M=10", "--out", out, "--force", "--json",
    ]);
    assert_eq!(code, 4, "{err}");
    assert_eq!(v["complete"], false);
    assert!(v["cycles"].as_array().is_some_and(|c| c.len() > 10));
    let stop = v["stop"].as_str().unwrap_or_default();
    assert!(
        stop.contains("grazes v = 0") && stop.contains("second method"),
        "{stop}"
    );
}

/// One model decision for `hopf`, `diagram` and `cycles`, judged on the
/// scene's orbit: the gel's 1 g block is quasi-static by `chi` at 20 µm/s
/// (4.4e-4) but not on its orbit at 200 N/m, so all three locate K_c with
/// its inertia, the mpmath value kappa_c (1 + chi) of
/// docs/reference/adhesive_gel.py (73814.22 N/m; the quasi-static
/// 73781.87 N/m was `hopf`'s alone before), and label it with its model.
/// Where a diagram's V_range needs inertia that the scene at its V does
/// not (a 0.1 mg block swept to 1e5 µm/s), the diagram's curve is inertial
/// and its operating point keeps the scene's quasi-static K_c, the one
/// `hopf` and `cycles` give, each value labelled with its model.
#[test]
fn hopf_diagram_and_cycles_give_one_k_c_labelled_with_its_model() {
    let dir = temp_dir("adhesive-one-k-c");
    let out = dir.to_str().unwrap();
    let reference = |key: &str| -> f64 {
        include_str!("../docs/reference/adhesive_gel_out.txt")
            .lines()
            .skip_while(|l| *l != "[gel]")
            .find_map(|l| l.strip_prefix(&format!("{key} ")))
            .and_then(|v| v.parse().ok())
            .unwrap_or_else(|| panic!("{key} in the reference"))
    };
    let runs = |set: &[&str]| -> Vec<(String, serde_json::Value)> {
        ["hopf", "diagram", "cycles"]
            .into_iter()
            .map(|cmd| {
                let mut args = vec![cmd, "--scene", "gel", "--json"];
                args.extend_from_slice(set);
                if cmd != "hopf" {
                    args.extend_from_slice(&["--out", out, "--force"]);
                }
                let (status, v, err) = json_of(&args);
                assert_eq!(status, 0, "{cmd} {set:?}: {err}");
                (cmd.to_string(), v)
            })
            .collect()
    };
    let k_c = |v: &serde_json::Value| field(&v["operating_point"], "K_c_N_per_m");

    let gel = runs(&[]);
    let expected = reference("K_c_inertial_N_m");
    for (cmd, v) in &gel {
        assert_eq!(v["model"], "inertial", "{cmd}: {}", v["model_reason"]);
        assert!(v.get("scene_model").is_none(), "{cmd}");
        assert_eq!(v["operating_point"]["model"], "inertial", "{cmd}");
        assert_eq!(k_c(v), k_c(&gel[0].1), "{cmd}");
        assert!(
            rel(k_c(v), expected) < 1e-9,
            "{cmd}: {} vs {expected}",
            k_c(v)
        );
        let chi = field(v, "orbit_inertia_ratio");
        assert!((chi - 1.4577).abs() < 1e-3, "{cmd}: {chi}");
    }
    assert_eq!(field(&gel[0].1["critical"], "K_N_per_m"), k_c(&gel[0].1));
    assert!(rel(field(&gel[2].1["onset"], "kappa_c") * 2e6, expected) < 1e-9);
    let (status, text, err) = stickslip(&["hopf", "--scene", "gel"]);
    assert_eq!(status, 0, "{err}");
    assert!(
        text.contains("onset (inertial model): K_c = 7.381422e4 N/m"),
        "{text}"
    );
    assert!(
        text.contains("K_c = 73814 N/m (kappa_c = 3.690711e-2, inertial model)"),
        "{text}"
    );

    let light = runs(&["--set", "M=1e-7", "--set", "V_range=0.1:1e5"]);
    let quasi = reference("K_c_N_m");
    for (cmd, v) in &light {
        assert_eq!(v["operating_point"]["model"], "quasi-static", "{cmd}");
        assert_eq!(k_c(v), k_c(&light[0].1), "{cmd}");
        assert!(rel(k_c(v), quasi) < 1e-9, "{cmd}: {} vs {quasi}", k_c(v));
    }
    let d = &light[1].1;
    assert_eq!(d["model"], "inertial", "{}", d["model_reason"]);
    assert_eq!(d["scene_model"], "quasi-static");
    // The diagram's curve at V: the inertial kappa_c (1 + chi), chi of the
    // 0.1 mg block a ten-thousandth of the gram's.
    let chi = reference("chi") * 1e-4;
    let curve = field(d, "curve_K_c_at_V_N_per_m");
    assert!(rel(curve, quasi * (1.0 + chi)) < 1e-9, "{curve}");
    let (status, text, err) = stickslip(&[
        "diagram",
        "--scene",
        "gel",
        "--set",
        "M=1e-7",
        "--set",
        "V_range=0.1:1e5",
        "--out",
        out,
        "--force",
    ]);
    assert_eq!(status, 0, "{err}");
    assert!(
        text.contains("(kappa_c = 3.689094e-2, quasi-static model)"),
        "{text}"
    );
    assert!(
        text.contains("the diagram's curve (inertial model over V_range) gives K_c"),
        "{text}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Without junction viscosity (F_v = 0) steady friction has a maximum and
/// no minimum above it; with slow readsorption (tau_on = 20 s) neither.
/// `hopf`, `diagram` and `cycles` say only what exists: no `V_c`, no
/// "between V_max and V_c" (which they printed for both before). The
/// extrema against the closed form D2 by central differences: its slope
/// changes sign once, near the V_max printed, for F_v = 0, never for
/// tau_on = 20 s, over 1e-3 to 1e6 µm/s.
#[test]
fn the_text_names_only_the_extrema_that_exist() {
    let dir = temp_dir("adhesive-extrema-text");
    let out = dir.to_str().unwrap();
    // nu = V / V_s from 1e-3 to 1e6 µm/s, 40 points per decade.
    let nus: Vec<f64> = (0..=360)
        .map(|i| 10f64.powf(-3.0 + i as f64 / 40.0) / 0.025)
        .collect();
    let slope = |nu: f64, r: f64, f_v: f64| {
        let p = AdhesiveParams {
            nu,
            kappa: 1e-4,
            r,
            f_v,
            alpha: 0.6,
            m: 0.0,
        };
        let h = 1e-5;
        steady_friction(nu * (1.0 + h), &p) - steady_friction(nu * (1.0 - h), &p)
    };
    let sign_changes = |r: f64, f_v: f64| -> Vec<f64> {
        nus.windows(2)
            .filter(|w| (slope(w[0], r, f_v) > 0.0) != (slope(w[1], r, f_v) > 0.0))
            .map(|w| (w[0] * w[1]).sqrt() * 0.025)
            .collect()
    };
    for (set, changes) in [
        ("F_v=0", sign_changes(0.1, 0.0)),
        ("tau_on=20", sign_changes(20.0, 0.01)),
    ] {
        let run = |cmd: &str, json: bool| {
            let mut args = vec![cmd, "--scene", "gel", "--set", set, "--set", "V=0.2"];
            if cmd != "hopf" {
                args.extend(["--out", out, "--force"]);
            }
            if json {
                args.push("--json");
            }
            let (status, text, err) = stickslip(&args);
            assert_eq!(status, 0, "{cmd} {set}: {err}");
            text
        };
        let v: serde_json::Value = serde_json::from_str(&run("hopf", true)).unwrap();
        assert!(v["V_c_um_per_s"].is_null(), "{set}: {v}");
        match set {
            "F_v=0" => {
                assert_eq!(changes.len(), 1, "{changes:?}");
                let v_max = field(&v, "V_max_um_per_s");
                // Within the grid's spacing, 10^(1/40).
                assert!(rel(v_max, changes[0]) < 0.03, "{v_max} vs {changes:?}");
            }
            _ => {
                assert!(changes.is_empty(), "{changes:?}");
                assert!(v["V_max_um_per_s"].is_null(), "{v}");
            }
        }
        for cmd in ["hopf", "diagram", "cycles"] {
            let text = run(cmd, false);
            assert!(!text.contains("V_c"), "{cmd} {set}: {text}");
            assert!(!text.contains("between V_max"), "{cmd} {set}: {text}");
            let says = match set {
                "F_v=0" => "steady friction falls with V at every velocity above V_max = ",
                _ => "steady friction rises with V at every velocity up to",
            };
            assert!(text.contains(says), "{cmd} {set}: {text}");
            if set == "F_v=0" {
                assert!(text.contains("(F_v = 0: no junction viscosity raises it again)"));
            } else {
                assert!(!text.contains("V_max"), "{cmd} {set}: {text}");
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The region labels ("steady sliding stable", "unstable: stick-slip") of
/// the stability figure are drawn where the Hopf curve spans less than a
/// label's width and vertical lines (V_max, the inertia threshold, V_c)
/// cut every place over it: a PDMS elastomer whose curve spans 35-250
/// µm/s of a 1-10^4 µm/s range, the inertia threshold crossing at 98 µm/s
/// in its middle. Before, both labels were left out there (the gel's
/// figure had them).
#[test]
fn the_stability_figure_labels_its_regions_over_a_narrow_curve() {
    let dir = temp_dir("adhesive-region-labels");
    let out = dir.to_str().unwrap();
    let pdms = dir.join("pdms.toml");
    std::fs::write(
        &pdms,
        "law = \"adhesive\"\nname = \"pdms\"\nF_a = 0.1\nV_s = 0.5\ntau_out = 0.5\n\
         tau_on = 0.02\nF_v = 1e-3\nalpha = 0.3\nM = 5e-3\nK = 500.0\nV = 50.0\n\
         V_range = [1.0, 10000.0]\n",
    )
    .unwrap();
    let pva = dir.join("pva.toml");
    std::fs::write(&pva, PVA_HEAVY).unwrap();
    for (scene, name) in [
        (pdms.to_str().unwrap(), "pdms"),
        (pva.to_str().unwrap(), "pva"),
        ("gel", "gel"),
    ] {
        let (status, v, err) = json_of(&["diagram", "--scene", scene, "--out", out, "--json"]);
        assert_eq!(status, 0, "{name}: {err}");
        if name == "pdms" {
            // The curve's span against the range: under a quarter of it.
            let vs: Vec<f64> = v["points"]
                .as_array()
                .unwrap()
                .iter()
                .filter(|p| p["K_N_per_m"].is_number())
                .map(|p| field(p, "V_um_per_s"))
                .collect();
            let span = (vs[vs.len() - 1] / vs[0]).log10() / 4.0;
            assert!(span < 0.25, "{span}");
            let crossing = field(&v, "inertia_crossing_um_per_s");
            assert!(
                vs[0] < crossing && crossing < vs[vs.len() - 1],
                "{crossing}"
            );
        }
        let svg =
            std::fs::read_to_string(dir.join(format!("{name}-diagram-stability.svg"))).unwrap();
        for label in ["steady sliding stable", "unstable: stick-slip"] {
            assert!(svg.contains(label), "{name}: no '{label}'");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Only `diagram` draws a range the scene's velocity may lie outside: the
/// note that the operating point is "not drawn" belongs to it, not to
/// `hopf` or `cycles` (a stranger, 2026-11-27).
#[test]
fn the_not_drawn_note_is_the_diagrams_alone() {
    let dir = temp_dir("not_drawn_note");
    let out = dir.to_str().unwrap();
    let (code, text, err) = stickslip(&["hopf", "--scene", "gel", "--set", "V=2000"]);
    assert_eq!(code, 0, "{err}");
    assert!(!text.contains("not drawn"), "{text}");
    let (code, text, err) =
        stickslip(&["diagram", "--scene", "gel", "--set", "V=2000", "--out", out]);
    assert!(code == 0 || code == 4, "{err}");
    assert!(
        text.contains("the scene's velocity lies outside the diagram's range: not drawn"),
        "{text}"
    );
}
