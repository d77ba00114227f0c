//! The command line as a user runs it: the public JSON of `hopf`, the
//! branch table, and bad input (exit status 2, a message naming the field).

mod common;

use common::{stickslip, VELOCITY_BRANCH};

use serde_json::Value;

fn hopf_json(extra: &[&str]) -> Value {
    let mut args = vec!["hopf", "--json"];
    args.extend_from_slice(extra);
    let (code, out, err) = stickslip(&args);
    assert_eq!(code, 0, "{err}");
    serde_json::from_str(&out).expect("valid JSON")
}

/// `(mu_phi - mu_v)(1 + m nu^2 / mu_v)` from the reported parameters, with
/// `mu_phi = B - 2 mu2 ln nu` for the ln² law (docs/model.md), written out here
/// rather than taken from the library.
fn c11_from_json(params: &Value) -> f64 {
    let g = |k: &str| {
        params[k]
            .as_f64()
            .unwrap_or_else(|| panic!("params.{k} missing"))
    };
    let (a, b, mu2, nu, m) = (g("A"), g("B"), g("mu2"), g("nu"), g("m"));
    let mu_phi = b - 2.0 * mu2 * nu.ln();
    (mu_phi - a) * (1.0 + m * nu * nu / a)
}

#[test]
fn hopf_json_default_scene_matches_c11() {
    let v = hopf_json(&[]);
    assert_eq!(v["model"], "quasi-static");
    assert_eq!(
        v["params"]["m"], 0.0,
        "the quasi-static model reports the inertia it used"
    );
    let kappa_c = v["kappa_c"].as_f64().unwrap();
    let expect = c11_from_json(&v["params"]);
    assert!(
        (kappa_c - expect).abs() < 1e-10 * expect,
        "{kappa_c} vs {expect}"
    );
    assert!(v["omega_c"].as_f64().unwrap() > 0.0);
}

#[test]
fn hopf_json_inertial_override_matches_c11() {
    let v = hopf_json(&[
        "--set", "A=0.01", "--set", "B=0.02", "--set", "mu2=5e-4", "--set", "m=0.1", "--set",
        "nu=3",
    ]);
    assert_eq!(v["model"], "inertial");
    for (k, want) in [
        ("A", 0.01),
        ("B", 0.02),
        ("mu2", 5e-4),
        ("m", 0.1),
        ("nu", 3.0),
    ] {
        assert_eq!(v["params"][k].as_f64(), Some(want), "params.{k}");
    }
    let kappa_c = v["kappa_c"].as_f64().unwrap();
    let expect = c11_from_json(&v["params"]);
    assert!(
        (kappa_c - expect).abs() < 1e-10 * expect,
        "{kappa_c} vs {expect}"
    );
    // C13 with mu_phi = B - 2 mu2 ln nu.
    let mu_phi = 0.02 - 2.0 * 5e-4 * 3f64.ln();
    let omega = 3.0 * (mu_phi / 0.01 - 1.0).sqrt();
    assert!((v["omega_c"].as_f64().unwrap() / omega - 1.0).abs() < 1e-10);
}

#[test]
fn velocity_strengthening_is_stable_for_all_stiffness() {
    let v = hopf_json(&["--set", "B=0.005"]);
    assert_eq!(v["status"], "stable_for_all_stiffness");
    assert!(v["kappa_c"].is_null());
    // No negative "critical stiffness" from eq. C11 either.
    assert!(v["appendix_c"]["kappa_c"].is_null(), "{}", v["appendix_c"]);
    // Nor a stiffness of zero among the parameters, in the JSON or the text.
    assert!(v["params"]["kappa"].is_null(), "{}", v["params"]);
    let (code, text, err) = stickslip(&["hopf", "--set", "B=0.005"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        text.contains("no onset, hence no kappa") && !text.contains("kappa = 0"),
        "{text}"
    );
}

#[test]
fn branch_csv_has_a_located_hopf_row_and_no_nan() {
    let (code, out, err) = stickslip(&[&VELOCITY_BRANCH[..], &["--csv"]].concat());
    assert_eq!(code, 0, "{err}");
    assert!(!out.to_lowercase().contains("nan") && !out.contains("inf"));
    let hopf: Vec<&str> = out.lines().filter(|l| l.contains(",hopf,")).collect();
    assert_eq!(hopf.len(), 1, "{out}");
    let nu: f64 = hopf[0].split(',').next().unwrap().parse().unwrap();
    // At fixed kappa the onset velocity solves kappa = (B - A - 2 mu2 ln nu)(1 + m nu^2/A)
    // (C11 with the ln² law); pmma has m = V0^2/(g D0) if the model kept inertia.
    assert!(
        out.starts_with("# scene pmma; model inertial; "),
        "nu up to 10 makes the inertia ratio 2e-3: {out}"
    );
    let (a, b, mu2, kappa, m) = (0.012, 0.023, 2.4e-4, 0.0105, 1e-12 / (9.81 * 0.4e-6));
    let c11 = |nu: f64| (b - a - 2.0 * mu2 * nu.ln()) * (1.0 + m * nu * nu / a) - kappa;
    let (mut lo, mut hi) = (0.5f64, 10.0f64);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if c11(mid) > 0.0 {
            lo = mid
        } else {
            hi = mid
        }
    }
    assert!((nu / lo - 1.0).abs() < 1e-10, "{nu} vs {lo}");
}

#[test]
fn bad_input_exits_2_naming_the_field() {
    for (args, needle) in [
        (vec!["hopf", "--set", "A=-1"], "A"),
        (vec!["hopf", "--set", "A=0"], "A"),
        (vec!["hopf", "--set", "nu=nan"], "nu"),
        (vec!["hopf", "--set", "kapa=0.1"], "kappa"),
        (
            vec!["hopf", "--set", "mu2=1e-4", "--set", "theta_c=0.1"],
            "theta_c",
        ),
        (vec!["hopf", "--set", "kappa"], "NAME=VALUE"),
        (vec!["hopf", "--scene", "pmmaa"], "pmma"),
        (vec!["hopf", "--scene", "/nonexistent/scene.toml"], "scene"),
        (vec!["branch", "--param", "nu", "--from=-1"], "--from"),
        (vec!["hopf", "--set", "m=0", "--model", "inertial"], "m = 0"),
        // Beyond what products like m nu^2 / A keep within the float range.
        (vec!["hopf", "--set", "A=1e-300"], "A = 1e-300"),
        (
            vec!["diagram", "--nu-range", "1e-300:1"],
            "--nu-range = 1e-300",
        ),
        (vec!["cycles", "--set", "theta_c=1e200"], "theta_c = 1e200"),
    ] {
        let (code, out, err) = stickslip(&args);
        assert_eq!(code, 2, "{args:?}: {out}{err}");
        assert!(
            err.contains(needle),
            "{args:?}: message should name '{needle}': {err}"
        );
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
    // A scene whose units make the dimensionless inertia overflow-prone.
    let dir = common::temp_dir("extreme_units");
    let scene = dir.join("tiny_load.toml");
    std::fs::write(
        &scene,
        "name = \"tiny\"\nA = 0.01\nB = 0.015\nmu0 = 0.6\nM = 10.0\nW = 1e-300\nV = 1.0\nV_range = [0.1, 10.0]\n",
    )
    .unwrap();
    let (code, _, err) = stickslip(&["hopf", "--scene", scene.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("W = 1e-300"), "{err}");
    // A value out of range in a scene file: the message names the file too.
    let negative = dir.join("negative_d0.toml");
    std::fs::write(&negative, "name = \"neg\"\nA = 0.01\nB = 0.015\nD0 = -5\n").unwrap();
    let path = negative.to_str().unwrap();
    let (code, _, err) = stickslip(&["hopf", "--scene", path]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains(&format!("{path}: D0 = -5")), "{err}");
}

/// A quasi-static block below its critical stiffness (plain law) slips
/// without bound in finite time: `simulate` fails with exit 3 and names
/// what the user can change with this program's options, not the
/// integrator's settings.
#[test]
fn a_quasi_static_blow_up_names_the_options_that_help() {
    let dir = common::temp_dir("blow_up");
    let scene = dir.join("massless.toml");
    std::fs::write(
        &scene,
        "name = \"massless\"\nA = 0.01\nB = 0.02\nM = 0\nW = 100\nD0 = 2\nV = 3\n",
    )
    .unwrap();
    let (code, _, err) = stickslip(&[
        "simulate",
        "--scene",
        scene.to_str().unwrap(),
        "--set",
        "kappa=0.005",
        "--out",
        dir.to_str().unwrap(),
    ]);
    // The rows before the blow-up are kept: partial, not a failure.
    assert_eq!(code, 4, "{err}");
    for option in ["--rtol", "--model inertial"] {
        assert!(err.contains(option), "should suggest {option}: {err}");
    }
    assert!(!err.contains("h_min") && !err.contains("atol"), "{err}");
}

#[test]
fn hopf_json_reports_the_onset_type() {
    let v = hopf_json(&[]);
    assert_eq!(v["criticality"], "supercritical");
    assert!(v["l1"].as_f64().unwrap() < 0.0);
    // Quasi-static ln² closed form: C = 4 sqrt(mu_phi (mu_phi - A) / mu2) at nu = 1.
    let c = 4.0 * (0.023f64 * 0.011 / 2.4e-4).sqrt();
    assert!((v["amplitude_coefficient"].as_f64().unwrap() / c - 1.0).abs() < 1e-10);
    let rr = hopf_json(&["--scene", "pmma-rr", "--model", "quasi-static"]);
    assert_eq!(rr["criticality"], "degenerate");
    assert!(rr["amplitude_coefficient"].is_null());
    // Unforced, the tiny inertia of the scene decides the degenerate onset: subcritical
    // (eta = m nu^2/A = 2.1e-5 < eta* = 0.1345).
    let rr = hopf_json(&["--scene", "pmma-rr"]);
    assert_eq!(rr["model"], "inertial");
    assert_eq!(rr["criticality"], "subcritical");
}

#[test]
fn diagram_json_and_files() {
    let dir = std::env::temp_dir().join(format!("stickslip-diagram-{}", std::process::id()));
    let out = dir.to_str().unwrap();
    let (code, text, err) =
        stickslip(&["diagram", "--json", "--out", out, "--nu-range", "0.1:100"]);
    assert_eq!(code, 0, "{err}");
    assert!(!text.contains("NaN") && !text.contains("nan"));
    let v: Value = serde_json::from_str(&text).unwrap();
    let curve = v["hopf_curve"].as_array().unwrap();
    assert!(curve.len() > 20);
    for p in curve {
        for k in ["nu", "kappa", "omega", "l1"] {
            assert!(
                p[k].as_f64().is_some_and(f64::is_finite),
                "hopf_curve point lacks {k}: {p}"
            );
        }
    }
    let special = v["special_points"].as_array().unwrap();
    assert!(
        special
            .iter()
            .any(|s| s["kind"] == "bautin" && s["l2"].as_f64().is_some()),
        "{special:?}"
    );
    for f in v["files"].as_array().unwrap() {
        let len = std::fs::metadata(f.as_str().unwrap())
            .map(|m| m.len())
            .unwrap_or(0);
        assert!(len > 1000, "{f} missing or empty");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn diagram_rejects_a_bad_range() {
    let (code, _, err) = stickslip(&[
        "diagram",
        "--nu-range",
        "10:1",
        "--out",
        "/tmp/stickslip-never",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("--nu-range"), "{err}");
}

#[test]
fn physical_axis_is_k_over_m_with_w_equal_m_g_and_k_over_w_for_a_loaded_rig() {
    let dir = std::env::temp_dir().join(format!("stickslip-load-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let loaded = dir.join("loaded.toml");
    std::fs::write(
        &loaded,
        "name = \"loaded\"\nA = 0.012\nB = 0.023\nmu2 = 2.4e-4\nD0 = 0.4\nM = 1\nW = 50\nV_range = [0.1, 10]\n",
    )
    .unwrap();
    for (scene, stem, weight) in [
        ("pmma", "pmma", true),
        (loaded.to_str().unwrap(), "loaded", false),
    ] {
        let (code, _, err) =
            stickslip(&["diagram", "--scene", scene, "--out", dir.to_str().unwrap()]);
        assert_eq!(code, 0, "{err}");
        let svg =
            std::fs::read_to_string(dir.join(format!("{stem}-stability-physical.svg"))).unwrap();
        // K/M where the load is the weight (the seed's axes), K/W for a
        // press-loaded rig, whose K/M says nothing of its stiffness against the load.
        let axis = if weight {
            "critical K/M"
        } else {
            "critical K/W"
        };
        assert!(svg.contains(axis), "{stem}: no {axis} axis");
        assert_eq!(
            svg.contains("W = M g"),
            weight,
            "{stem}: W = M g shown iff W is derived"
        );
        // Neither scene gives K: no operating point.
        assert!(!svg.contains("operating point"), "{stem}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn cycles_json_lands_on_the_requested_stiffnesses() {
    let dir = std::env::temp_dir().join(format!("stickslip-user-points-{}", std::process::id()));
    let out = dir.to_str().unwrap();
    let (code, text, err) = stickslip(&[
        "cycles",
        "--json",
        "--max-steps",
        "40",
        "--at-kappa",
        "0.0109,0.0108",
        "--out",
        out,
    ]);
    // 40 steps do not reach the end of the range: partial (status 4).
    assert_eq!(code, 4, "{err}");
    let v: Value = serde_json::from_str(&text).unwrap();
    assert_eq!(v["complete"], false);
    let cycles = v["cycles"].as_array().unwrap();
    for c in cycles {
        for k in [
            "kappa",
            "period",
            "delta_s",
            "v_min",
            "v_max",
            "multipliers",
        ] {
            assert!(!c[k].is_null(), "cycle lacks {k}");
        }
        assert!(
            c["stable"].is_boolean() || c["stability_reason"].is_string(),
            "cycle lacks stable or its reason: {c}"
        );
    }
    let users: Vec<f64> = cycles
        .iter()
        .filter(|c| c["user_point"] == true)
        .map(|c| c["kappa"].as_f64().unwrap())
        .collect();
    assert_eq!(users.len(), 2, "{users:?}");
    assert!(
        (users[0] / 0.0109 - 1.0).abs() < 1e-12 && (users[1] / 0.0108 - 1.0).abs() < 1e-12,
        "{users:?}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn diagram_json_has_the_curve_of_folds_of_the_cutoff_scene() {
    let dir = std::env::temp_dir().join(format!("stickslip-lpc-curve-{}", std::process::id()));
    let (code, text, err) = stickslip(&[
        "diagram",
        "--scene",
        "brockley",
        "--json",
        "--out",
        dir.to_str().unwrap(),
    ]);
    // The fold curve stops short at high velocity (cycles too stiff for its
    // mesh, the gap hatched): the diagram is partial, status 4.
    assert_eq!(code, 4, "{err}");
    let v: Value = serde_json::from_str(&text).unwrap();
    assert_eq!(v["lpc_complete"], false);
    assert_eq!(v["complete"], false, "partial, as the exit status says");
    let curve = v["lpc_curve"].as_array().expect("lpc_curve");
    assert!(curve.len() > 20, "{} folds", curve.len());
    let bautin = v["special_points"]
        .as_array()
        .unwrap()
        .iter()
        .find(|s| s["kind"] == "bautin")
        .expect("a Bautin point");
    let nu_b = bautin["nu"].as_f64().unwrap();
    let v_min = 2000.0;
    for p in curve {
        for k in [
            "nu",
            "kappa",
            "period",
            "delta_s",
            "V_um_per_s",
            "K_over_M_per_s2",
        ] {
            assert!(p[k].as_f64().is_some_and(f64::is_finite), "{k} in {p}");
        }
    }
    // From the Bautin point, across the friction minimum.
    let nus: Vec<f64> = curve.iter().map(|p| p["nu"].as_f64().unwrap()).collect();
    assert!(nus.iter().any(|nu| (nu / nu_b - 1.0).abs() < 1e-2));
    assert!(nus.iter().any(|nu| *nu > 2.0 * v_min));
    assert!(dir.join("brockley-lpc-curve.csv").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn cycles_lpc_curve_json_continues_the_fold_of_the_branch() {
    // The light cutoff setting (nu = 90, m = 1e-3): subcritical onset, one
    // fold of cycles on the branch (AUTO-07p: kappa = 0.48441890476), and
    // the curve of folds through it down to the Bautin point (nu = 81.35).
    let dir = std::env::temp_dir().join(format!("stickslip-cycles-lpc-{}", std::process::id()));
    let (code, text, err) = stickslip(&[
        "cycles",
        "--scene",
        "brockley",
        "--set",
        "theta_c=0.0091666667",
        "--set",
        "nu=90",
        "--set",
        "m=1e-3",
        "--lpc-curve",
        "--json",
        "--out",
        dir.to_str().unwrap(),
    ]);
    // Toward large nu the curve plunges (kappa ~ 1e-8 at nu ~ 1e4) and takes
    // its 300 steps short of the range's end: a stop entry, status 4.
    assert_eq!(code, 4, "{err}");
    let v: Value = serde_json::from_str(&text).unwrap();
    let stops: Vec<&str> = v["lpc_stops"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s["reason"].as_str().unwrap())
        .collect();
    assert_eq!(stops, ["bautin_point", "step_limit"], "{err}");
    assert_eq!(v["complete"], false);
    assert_eq!(v["collocation"], "radau", "the inertial block");
    let folds: Vec<f64> = v["special_points"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|p| p["kind"] == "lpc")
        .map(|p| p["kappa"].as_f64().unwrap())
        .collect();
    assert_eq!(folds.len(), 1, "{folds:?}");
    assert!((folds[0] / 0.48441890476 - 1.0).abs() < 1e-6, "{folds:?}");
    let curve = v["lpc_curve"].as_array().unwrap();
    for p in curve {
        for k in ["curve", "nu", "kappa", "period", "delta_s"] {
            assert!(p[k].is_number(), "curve point lacks {k}: {p}");
        }
    }
    let nu = |p: &Value| p["nu"].as_f64().unwrap();
    let lowest = curve.iter().map(nu).fold(f64::INFINITY, f64::min);
    assert!((lowest / 81.35 - 1.0).abs() < 5e-3, "ends at nu = {lowest}");
    assert!(curve.iter().map(nu).any(|n| n > 150.0), "crosses V_min");
    let at_90 = curve
        .iter()
        .find(|p| (nu(p) - 90.0).abs() < 1e-9)
        .expect("the fold itself");
    assert!((at_90["kappa"].as_f64().unwrap() / folds[0] - 1.0).abs() < 1e-9);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A folder that cannot be created: exit status 1, and the message names it.
#[test]
fn unwritable_output_folder_is_named() {
    for args in [
        vec!["diagram"],
        vec!["cycles", "--kappa-fraction", "0.9"],
        vec!["simulate", "--set", "kappa=0.009"],
    ] {
        let mut full = args.clone();
        full.extend(["--out", "/proc/no-such-folder/out"]);
        let (code, _, err) = stickslip(&full);
        assert_eq!(code, 1, "{args:?}: {err}");
        assert!(
            err.contains("cannot write output: /proc/no-such-folder/out:"),
            "{args:?}: {err}"
        );
    }
}

/// `hopf` searches the stiffness: a given one is reported as unused.
#[test]
fn hopf_says_a_given_stiffness_is_not_used() {
    let (code, _, err) = stickslip(&["hopf", "--set", "kappa=0.5"]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("kappa = 5e-1 (--set) is not used"), "{err}");
    let (_, _, err) = stickslip(&["hopf"]);
    assert!(!err.contains("is not used"), "{err}");
}

/// The normal-form example amplitude gets a caveat where it exceeds mu0.
#[test]
fn hopf_flags_an_example_amplitude_beyond_mu0() {
    let (code, out, err) = stickslip(&["hopf", "--set", "mu0=0.01"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("more than mu0 = 1.000e-2"), "{out}");
    let (_, out, _) = stickslip(&["hopf"]);
    assert!(!out.contains("more than mu0"), "{out}");
}

/// A memory length given in metres by mistake is accepted with a warning.
#[test]
fn implausible_memory_length_is_warned_about() {
    let dir = common::temp_dir("d0_in_metres");
    let scene = dir.join("metres.toml");
    std::fs::write(
        &scene,
        "name = \"metres\"\nA = 0.01\nB = 0.015\nmu0 = 0.6\nD0 = 5e-6\nM = 10.0\nV = 1.0\nV_range = [0.1, 10.0]\n",
    )
    .unwrap();
    let (code, _, err) = stickslip(&["hopf", "--scene", scene.to_str().unwrap()]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("warning: scene metres: D0 = 5e-6 µm"), "{err}");
    let (_, _, err) = stickslip(&["hopf"]);
    assert!(!err.contains("warning"), "{err}");
}

/// `simulate --every N` writes from each run of N steps at most six rows,
/// among them the extremes: the fastest slip and the lowest spring force of
/// the full-resolution run are in the decimated CSV to the digit.
#[test]
fn simulate_every_keeps_the_extremes_of_the_full_run() {
    let dir = std::env::temp_dir().join(format!("stickslip-every-{}", std::process::id()));
    let run = |every: &str, sub: &str| {
        let out = dir.join(sub);
        let (code, _, err) = stickslip(&[
            "simulate",
            "--set",
            "kappa=0.009",
            "--protocol",
            "1:200",
            "--every",
            every,
            "--out",
            out.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{err}");
        let text = std::fs::read_to_string(out.join("pmma_kappa=0.009-simulation.csv")).unwrap();
        let rows: Vec<Vec<f64>> = text
            .lines()
            .skip(1)
            .map(|l| l.split(',').take(7).map(|x| x.parse().unwrap()).collect())
            .collect();
        rows
    };
    let full = run("1", "full");
    let thin = run("50", "thin");
    assert!(
        thin.len() * 50 <= full.len() * 6 + 6 * 50,
        "{} of {}",
        thin.len(),
        full.len()
    );
    assert!(
        thin.len() * 25 >= full.len(),
        "{} of {}",
        thin.len(),
        full.len()
    );
    let column = |rows: &[Vec<f64>], k: usize, f: fn(f64, f64) -> f64, init: f64| {
        rows.iter().map(|r| r[k]).fold(init, f)
    };
    // Columns: t_s, t, s, v, theta, slip, log10_v.
    for (k, f, init) in [
        (6, f64::max as fn(f64, f64) -> f64, f64::NEG_INFINITY),
        (6, f64::min, f64::INFINITY),
        (2, f64::min, f64::INFINITY),
        (2, f64::max, f64::NEG_INFINITY),
    ] {
        assert_eq!(
            column(&thin, k, f, init),
            column(&full, k, f, init),
            "column {k}"
        );
    }
    assert_eq!(thin.last().unwrap()[0], full.last().unwrap()[0]);
    let _ = std::fs::remove_dir_all(&dir);
}

/// `cycles` writes its text lines in physical units by default and in
/// dimensionless ones with `--units dimensionless`; the CSV carries both,
/// related by the scene's D0 and V0 (pmma: 0.4 um, 1 um/s).
#[test]
fn cycles_text_and_csv_in_both_units() {
    let dir = common::temp_dir("units");
    let out = dir.to_str().unwrap();
    let args = [
        "cycles",
        "--kappa-fraction",
        "0.99",
        "--out",
        out,
        "--force",
    ];
    let (code, physical, err) = stickslip(&args);
    assert_eq!(code, 0, "{err}");
    let mut dimensionless_args = args.to_vec();
    dimensionless_args.extend(["--units", "dimensionless"]);
    let (code, dimensionless, err) = stickslip(&dimensionless_args);
    assert_eq!(code, 0, "{err}");
    let first = |text: &str, start: &str| {
        text.lines()
            .find(|l| l.starts_with(start))
            .unwrap_or_else(|| panic!("no line starting {start}: {text}"))
            .split_whitespace()
            .nth(1)
            .unwrap()
            .parse::<f64>()
            .unwrap()
    };
    let (k_over_w, kappa) = (first(&physical, "K/W "), first(&dimensionless, "kappa "));
    assert!(
        physical.contains(" s  force drop ")
            && physical.contains(" N  Delta_s")
            && physical.contains(" µm/s")
    );
    let csv = std::fs::read_to_string(dir.join("pmma-cycles.csv")).unwrap();
    let mut rows = csv.lines().skip_while(|l| !l.starts_with("kappa,"));
    let header: Vec<&str> = rows.next().unwrap().split(',').collect();
    let col = |name: &str| header.iter().position(|h| *h == name).unwrap();
    let (d0, v0) = (0.4e-6, 1e-6);
    for row in rows.filter(|l| !l.starts_with('#')) {
        let cell: Vec<f64> = row
            .split(',')
            .map(|x| x.parse().unwrap_or(f64::NAN))
            .collect();
        let rel = |a: f64, b: f64| ((a - b) / b).abs();
        assert!(rel(cell[col("K_over_W_per_m")], cell[col("kappa")] / d0) < 1e-14);
        assert!(rel(cell[col("period_s")], cell[col("period")] * d0 / v0) < 1e-14);
        assert!(rel(cell[col("v_max_um_per_s")], cell[col("v_max")] * 1.0) < 1e-14);
    }
    assert!(
        ((k_over_w * d0 - kappa) / kappa).abs() < 1e-7,
        "{k_over_w} {kappa}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// `diagram` gives stiffnesses as K/W by default and as kappa with
/// `--units dimensionless`: the same numbers through D0 (pmma: 0.4 um).
#[test]
fn diagram_text_in_both_units() {
    let dir = common::temp_dir("diagram-units");
    let out = dir.to_str().unwrap();
    let first_value = |units: &str, marker: &str| {
        let (code, text, err) = stickslip(&["diagram", "--out", out, "--force", "--units", units]);
        assert_eq!(code, 0, "{err}");
        let line = text
            .lines()
            .find(|l| l.contains("critical stiffness from"))
            .unwrap_or_else(|| panic!("{text}"));
        let after = &line[line.find(marker).unwrap() + marker.len()..];
        after
            .split_whitespace()
            .next()
            .unwrap()
            .parse::<f64>()
            .unwrap()
    };
    let k_over_w = first_value("physical", "K/W = ");
    let kappa = first_value("dimensionless", "kappa = ");
    assert!(
        ((k_over_w * 0.4e-6 - kappa) / kappa).abs() < 1e-6,
        "{k_over_w} {kappa}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// Several scenes under one `--name` get one name each, and a repeated run
/// is refused before anything is computed if any of its files exists.
#[test]
fn named_runs_of_several_scenes_keep_every_scene() {
    let dir = common::temp_dir("several-named");
    let out = dir.to_str().unwrap();
    let args = [
        "diagram",
        "--scene",
        "pmma,pmma-rr",
        "--name",
        "foo",
        "--out",
        out,
    ];
    let (code, _, err) = stickslip(&args);
    // pmma-rr's fold curve stops short (cycles too stiff): partial, status 4.
    assert_eq!(code, 4, "{err}");
    for scene in ["pmma", "pmma-rr"] {
        let json = std::fs::read_to_string(dir.join(format!("foo_{scene}-diagram.json"))).unwrap();
        let v: Value = serde_json::from_str(&json).unwrap();
        assert_eq!(v["scene"], scene);
    }
    std::fs::remove_file(dir.join("foo_pmma-rr-diagram.json")).unwrap();
    let (code, text, err) = stickslip(&args);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("foo_pmma-") && err.contains("exists"), "{err}");
    assert!(!text.contains("wrote"), "{text}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `cycles` opens its text as `hopf` and `diagram` do: the scene, the
/// model, and where the branch starts (pmma: kappa_c = 0.011 quasi-statically,
/// K/W = kappa_c / D0 = 0.011 / 0.4 um = 2.75e4 1/m).
#[test]
fn cycles_text_opens_with_the_scene_the_model_and_the_start() {
    let dir = common::temp_dir("cycles_header");
    let (code, out, err) =
        stickslip(&["cycles", "--max-steps", "2", "--out", dir.to_str().unwrap()]);
    assert!(code == 0 || code == 4, "{err}");
    let mut lines = out.lines();
    assert!(lines.next().unwrap().starts_with("scene: pmma — "), "{out}");
    assert!(
        lines.next().unwrap().starts_with("model: quasi-static"),
        "{out}"
    );
    let start = lines.next().unwrap();
    let k_over_w: f64 = start
        .strip_prefix("from the Hopf point at K/W = ")
        .and_then(|r| r.strip_suffix(" 1/m"))
        .and_then(|v| v.parse().ok())
        .unwrap_or_else(|| panic!("{start}"));
    assert!((k_over_w / (0.011 / 0.4e-6) - 1.0).abs() < 1e-9, "{start}");
}

/// Next to the friction minimum (brockley's V_min = 2000 µm/s, here 5e-8
/// below it) the Hopf point degenerates: the failure says why and gives
/// Appendix C's stiffness, not only "reduce the step size".
#[test]
fn a_degenerate_hopf_point_at_the_friction_minimum_is_explained() {
    let (code, _, err) = stickslip(&["hopf", "--scene", "brockley", "--set", "nu=1999.9999"]);
    assert_eq!(code, 3, "{err}");
    assert!(err.contains("velocity neutral"), "{err}");
    assert!(err.contains("Appendix C gives kappa_c = 2.46"), "{err}");
}

/// `diagram` states the onset type when the whole curve shares it, and the
/// type it states is the one `hopf` gives at a velocity inside the range:
/// pmma is subcritical between its two Bautin points (nu = 26.6 and 78.5)
/// and supercritical outside them.
#[test]
fn diagram_states_an_onset_type_shared_by_the_whole_curve() {
    let dir = std::env::temp_dir().join(format!("stickslip-onset-type-{}", std::process::id()));
    let out = dir.to_str().unwrap();
    for (range, nu, expected) in [
        ("2:5", "3", "supercritical"),
        ("30:70", "50", "subcritical"),
        ("0.1:100", "50", "mixed"),
    ] {
        let (code, text, err) = stickslip(&[
            "diagram",
            "--json",
            "--out",
            out,
            "--force",
            "--nu-range",
            range,
        ]);
        assert_eq!(code, 0, "{err}");
        let v: Value = serde_json::from_str(&text).unwrap();
        assert_eq!(v["onset_type"], expected, "range {range}");
        let types: Vec<&str> = v["hopf_curve"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| p["criticality"].as_str().unwrap())
            .collect();
        assert!(types.len() > 5, "range {range}: {} points", types.len());
        let shared = types.iter().all(|t| *t == types[0]);
        assert_eq!(shared, expected != "mixed", "range {range}: {types:?}");
        if expected != "mixed" {
            assert_eq!(types[0], expected, "range {range}");
            let onset = hopf_json(&["--set", &format!("nu={nu}")]);
            assert_eq!(onset["criticality"], expected, "hopf at nu = {nu}: {onset}");
        }
        let (code, text, err) =
            stickslip(&["diagram", "--out", out, "--force", "--nu-range", range]);
        assert_eq!(code, 0, "{err}");
        let said = match expected {
            "mixed" => "onset type changes along the curve".to_string(),
            t => format!("onset {t} ("),
        };
        assert!(text.contains(&said), "range {range}: {text}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The stiffness of the fold of cycles `cycles --json` located on its branch.
fn branch_fold(cycles: &Value) -> f64 {
    cycles["special_points"]
        .as_array()
        .unwrap()
        .iter()
        .find(|s| s["kind"] == "lpc")
        .and_then(|s| s["kappa"].as_f64())
        .expect("a fold of cycles on the branch")
}

/// `diagram` places a scene's own stiffness: below `K_c` stick-slip, between
/// `K_c` and the fold of cycles bistable, above the fold steady. Independent
/// values: `K_c` from `hopf` at the scene's velocity, and the fold located
/// on the cycle branch at that velocity by `cycles` (a second method: the
/// diagram reads it off its traced curve of folds, within the error bound
/// it reports). pmma at nu = 50 lies between its two Bautin points.
#[test]
fn diagram_places_the_operating_point_against_the_onset_and_the_fold() {
    let dir = std::env::temp_dir().join(format!("stickslip-operating-{}", std::process::id()));
    let out = dir.to_str().unwrap();
    let onset = hopf_json(&["--set", "nu=50"]);
    let kappa_c = onset["params"]["kappa"].as_f64().unwrap();
    let (code, text, err) = stickslip(&["cycles", "--json", "--set", "nu=50", "--out", out]);
    assert_eq!(code, 0, "{err}");
    let cycles: Value = serde_json::from_str(&text).unwrap();
    let fold = branch_fold(&cycles);
    assert!(fold > kappa_c, "fold {fold} vs kappa_c {kappa_c}");
    let between = 0.5 * (kappa_c + fold);
    for (kappa, regime) in [
        (0.99 * kappa_c, "stick-slip"),
        (between, "bistable"),
        (1.01 * fold, "steady"),
    ] {
        let set = format!("kappa={kappa}");
        let (code, text, err) = stickslip(&[
            "diagram", "--json", "--out", out, "--force", "--set", "nu=50", "--set", &set,
        ]);
        assert_eq!(code, 0, "{err}");
        let v: Value = serde_json::from_str(&text).unwrap();
        let op = &v["operating_point"];
        assert_eq!(op["regime"], regime, "kappa = {kappa}: {op}");
        let kc = op["kappa_c"].as_f64().unwrap();
        assert!(
            (kc / kappa_c - 1.0).abs() < 1e-13,
            "kappa_c {kc} vs hopf {kappa_c}"
        );
        let margin = op["margin"].as_f64().unwrap();
        assert!((margin - (kappa - kappa_c) / kappa_c).abs() < 1e-12, "{op}");
        let read = op["kappa_fold"].as_f64().unwrap();
        let error = op["kappa_fold_error"].as_f64().unwrap();
        assert!(
            (read - fold).abs() <= error,
            "fold read {read} ± {error} vs located {fold}"
        );
        let stem = format!("pmma_{set}_nu=50-stability-physical.svg");
        let svg = std::fs::read_to_string(dir.join(stem)).unwrap();
        assert!(
            svg.contains(&format!("({regime})")),
            "figure legend names {regime}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Without a Hopf point at the scene's velocity (brockley's cutoff law past
/// its friction minimum) steady sliding is stable at every stiffness, yet
/// stick-slip coexists with it below the fold of cycles: `diagram` says
/// `bistable` for a stiffness below the fold it reads off its traced curve.
/// Independent values: `cycles --from-simulation` finds a stick-slip cycle
/// at that stiffness and locates the fold on its branch, within the error
/// bound the diagram reports.
#[test]
fn diagram_finds_bistability_without_an_onset_below_the_fold_of_cycles() {
    let dir = std::env::temp_dir().join(format!("stickslip-no-onset-{}", std::process::id()));
    let out = dir.to_str().unwrap();
    let (code, text, err) = stickslip(&[
        "diagram", "--json", "--out", out, "--scene", "brockley", "--set", "K=1e5",
    ]);
    // The fold curve stops short at the top of the range: partial (4).
    assert!(code == 0 || code == 4, "{err}");
    let v: Value = serde_json::from_str(&text).unwrap();
    let op = &v["operating_point"];
    assert_eq!(op["regime"], "bistable", "{op}");
    assert!(op["kappa_c"].is_null(), "{op}");
    let (code, text, err) = stickslip(&[
        "cycles",
        "--json",
        "--out",
        out,
        "--scene",
        "brockley",
        "--set",
        "K=1e5",
        "--from-simulation",
    ]);
    assert_eq!(code, 0, "{err}");
    let cycles: Value = serde_json::from_str(&text).unwrap();
    assert_eq!(cycles["start"]["kind"], "simulation", "{}", cycles["start"]);
    let kappa = op["kappa"].as_f64().unwrap();
    let start = cycles["start"]["kappa"].as_f64().unwrap();
    assert!(
        (start / kappa - 1.0).abs() < 1e-12,
        "stick-slip settled at the scene's K"
    );
    let fold = branch_fold(&cycles);
    let read = op["kappa_fold"].as_f64().unwrap();
    let error = op["kappa_fold_error"].as_f64().unwrap();
    assert!(kappa < fold, "{kappa} below the fold {fold}");
    assert!(
        (read - fold).abs() <= error,
        "fold read {read} ± {error} vs located {fold}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A branch in a parameter other than the stiffness and the velocity
/// shows that parameter in the first column of the physical text (the
/// heading and the range say so), not the stiffness it holds fixed: at `nu
/// = 3`, `mu2` from 1e-4 to 1e-3 crosses the onset where `kappa = B - A -
/// 2 mu2 ln nu` (C12; the inertia ratio there is 2e-4).
#[test]
fn branch_text_leads_with_the_continued_parameter() {
    let args = [
        "branch",
        "--param",
        "mu2",
        "--set",
        "kappa=0.0105",
        "--set",
        "nu=3",
        "--from",
        "1e-4",
        "--to",
        "1e-3",
    ];
    let (code, out, err) = stickslip(&args);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("continuing steady sliding in mu2 from 1.000000e-4 to 1.000000e-3"));
    let head = out.lines().find(|l| l.contains("#u")).unwrap();
    assert_eq!(head.split_whitespace().next(), Some("mu2"), "{head}");
    let rows: Vec<&str> = out
        .lines()
        .filter(|l| l.contains("  #") && !l.contains("#u"))
        .collect();
    let first = |l: &str| l.split_whitespace().next().unwrap().parse::<f64>().unwrap();
    assert!(rows.windows(2).all(|w| first(w[1]) > first(w[0])), "{out}");
    let hopf = rows
        .iter()
        .find(|l| l.contains("<- HOPF"))
        .expect("a Hopf row");
    let c12 = (0.023 - 0.012 - 0.0105) / (2.0 * 3f64.ln());
    assert!((first(hopf) / c12 - 1.0).abs() < 1e-3, "{hopf} vs {c12}");
}

/// `scenes --json`: every built-in scene with its law, as the text lists them.
#[test]
fn scenes_json_lists_every_builtin_with_its_law() {
    let (code, out, err) = stickslip(&["scenes", "--json"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let listed: Vec<(&str, &str)> = v
        .as_array()
        .unwrap()
        .iter()
        .map(|s| (s["name"].as_str().unwrap(), s["law"].as_str().unwrap()))
        .collect();
    assert_eq!(
        listed,
        [
            ("pmma", "rate-and-state"),
            ("pmma-rr", "rate-and-state"),
            ("brockley", "rate-and-state"),
            ("gel", "adhesive")
        ]
    );
    let (_, text, _) = stickslip(&["scenes"]);
    assert_eq!(text.lines().count(), listed.len());
}

/// The diagram of the deep-stick scene (`--model inertial --set A=1e-4 --set
/// B=0.011 --set m=1e-6`) lists two Bautin points; where their curves of
/// folds of cycles do not start (their folds too stiff for the fold
/// system), the stops say so, and the text no longer adds that no Bautin
/// point lies in the range (session-18 stranger). The stops carry no advice
/// on where to start: the start is the located fold, not the user's.
#[test]
fn the_deep_stick_diagram_does_not_deny_its_bautin_points() {
    let dir = common::temp_dir("deep_stick_diagram");
    let (code, out, err) = common::stickslip(&[
        "diagram",
        "--model",
        "inertial",
        "--set",
        "A=1e-4",
        "--set",
        "B=0.011",
        "--set",
        "m=1e-6",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(code == 0 || code == 4, "{err}");
    let bautin = out
        .lines()
        .filter(|l| l.trim_start().starts_with("bautin"))
        .count();
    assert_eq!(bautin, 2, "{out}");
    assert!(!out.contains("no Bautin point lies in the range"), "{out}");
    assert!(!out.contains("start closer to the fold"), "{out}");
    if code == 4 {
        assert!(out.contains("fold-of-cycles curve stopped"), "{out}");
    }
}
