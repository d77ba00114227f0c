//! The exit status tells the truth: 0 only when everything requested was
//! delivered, 4 ("partial") when results were kept but the request is
//! incomplete, with the reason on stderr and in the JSON (`complete`,
//! `stop`).

mod common;

use common::{stickslip, temp_dir};

use serde_json::Value;

#[test]
fn cycles_cut_by_the_step_limit_are_partial() {
    let dir = temp_dir("cycles");
    let (code, out, err) = stickslip(&[
        "cycles",
        "--max-steps",
        "3",
        "--json",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 4, "{err}");
    assert!(
        err.contains("partial") && err.contains("--max-steps"),
        "{err}"
    );
    let v: Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["complete"], false);
    let stop = v["stop"].as_str().unwrap();
    assert!(
        stop.contains("step limit") && !stop.contains("end of the requested range"),
        "{stop}"
    );
    // The first cycle and three steps, each kept in the CSV as well.
    assert_eq!(v["cycles"].as_array().unwrap().len(), 4);
    let csv = std::fs::read_to_string(dir.join("pmma-cycles.csv")).unwrap();
    assert_eq!(csv.lines().filter(|l| !l.starts_with('#')).count(), 1 + 4);
    // The CSV alone says it is not the whole branch, and why.
    assert_eq!(
        csv.lines().last(),
        Some(format!("# incomplete: {stop}").as_str()),
        "{csv}"
    );
}

/// A branch that fails after many cycles (here a stiff branch that outgrows
/// a small mesh limit, as `cycles --set nu=1e-6` outgrows its Floquet
/// pencil) keeps them and says so: status 4, `complete: false`, the failure
/// as the stop reason (it said "numerical failure" with status 0). (With a
/// limit of 80 intervals, since the steps grow only as far as the tangent's
/// turn allows, this branch's collocation fails by Newton's method at a
/// stiffer cycle before its error estimate fails, and the return map
/// completes the branch: which failure comes first at a mesh limit depends
/// on the steps taken.)
#[test]
fn cycles_that_fail_after_some_are_partial() {
    let dir = temp_dir("cycles-failure");
    let (code, out, err) = stickslip(&[
        "cycles",
        "--set",
        "m=0.01",
        "--kappa-fraction",
        "0.01",
        "--ntst-max",
        "60",
        "--json",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 4, "{err}");
    assert!(
        err.contains("partial") && err.contains("numerical failure"),
        "{err}"
    );
    let v: Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["complete"], false);
    let stop = v["stop"].as_str().unwrap();
    assert!(
        stop.contains("no longer resolved") && stop.contains("60 mesh intervals"),
        "{stop}"
    );
    assert!(v["cycles"].as_array().unwrap().len() > 10);
}

#[test]
fn cycles_that_reach_the_range_are_complete() {
    let dir = temp_dir("rr");
    let (code, out, err) = stickslip(&[
        "cycles",
        "--scene",
        "pmma-rr",
        "--json",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let v: Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["complete"], true);
    assert_eq!(v["stop"], "end of the requested range");
    let csv = std::fs::read_to_string(dir.join("pmma-rr-cycles.csv")).unwrap();
    assert!(!csv.contains("# incomplete"), "a complete branch's CSV");
    // The last cycle lies beyond the requested end, kappa_fraction * kappa_c.
    let kappa_c = v["kappa_c"].as_f64().unwrap();
    let last = v["cycles"].as_array().unwrap().last().unwrap()["kappa"]
        .as_f64()
        .unwrap();
    assert!(last <= 0.5 * kappa_c, "{last} vs kappa_c {kappa_c}");
}

#[test]
fn a_hopf_curve_cut_by_the_step_limit_is_partial() {
    let dir = temp_dir("diagram");
    let (code, out, err) = stickslip(&[
        "diagram",
        "--nu-range",
        "1e-6:1e6",
        "--max-steps",
        "50",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 4, "{err}");
    assert!(err.contains("--max-steps"), "{err}");
    assert!(out.contains("step limit (50 steps, --max-steps)"), "{out}");
    // Small velocities with significant digits, never 0.0000.
    assert!(
        out.contains("V = 1.0000e-6 µm/s") && !out.contains("0.0000 µm/s"),
        "{out}"
    );
    let (code, out, err) = stickslip(&[
        "diagram",
        "--nu-range",
        "1e-6:1e6",
        "--max-steps",
        "50",
        "--json",
        "--out",
        dir.to_str().unwrap(),
        // The same run as above, as JSON: its files are replaced.
        "--force",
    ]);
    assert_eq!(code, 4, "{err}");
    let v: Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["complete"], false);
    assert!(v["stop"].as_str().unwrap().contains("step limit"));
}

#[test]
fn the_default_step_limit_covers_twelve_decades_of_velocity() {
    let dir = temp_dir("diagram-full");
    let (code, out, err) = stickslip(&[
        "diagram",
        "--nu-range",
        "1e-6:1e6",
        "--json",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let v: Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["complete"], true);
    let nus: Vec<f64> = v["hopf_curve"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["nu"].as_f64().unwrap())
        .collect();
    // Steps follow (ln kappa, ln nu), not the state: theta = 1/nu spans 12
    // decades (it took 21 840 points, 9 000 in the first decade).
    assert!(nus.len() < 1000, "{} points", nus.len());
    let (lo, hi) = (nus[0], *nus.last().unwrap());
    assert!(
        (lo / 1e-6 - 1.0).abs() < 1e-9 && (hi / 1e6 - 1.0).abs() < 1e-9,
        "{lo} .. {hi}"
    );
}

#[test]
fn a_simulation_cut_by_the_step_limit_is_partial() {
    let dir = temp_dir("sim");
    let (code, out, err) = stickslip(&[
        "simulate",
        "--set",
        "kappa=0.009",
        "--max-steps",
        "10",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 4, "{err}");
    assert!(
        err.contains("step limit") && err.contains("--max-steps"),
        "{err}"
    );
    assert!(out.contains("10 steps"), "{out}");
    let csv = std::fs::read_to_string(dir.join("pmma_kappa=0.009-simulation.csv")).unwrap();
    assert_eq!(csv.lines().filter(|l| !l.starts_with('#')).count(), 1 + 10);
    // The CSV alone says it stops short, and why.
    let last = csv.lines().last().unwrap();
    assert!(
        last.starts_with("# incomplete: stopped by --max-steps at t = "),
        "{last}"
    );
    // The whole default protocol is delivered without the limit (the same
    // run again, its files replaced).
    let (code, _, err) = stickslip(&[
        "simulate",
        "--set",
        "kappa=0.009",
        "--out",
        dir.to_str().unwrap(),
        "--force",
    ]);
    assert_eq!(code, 0, "{err}");
}

#[test]
fn a_steady_branch_cut_by_the_step_limit_is_partial() {
    let args = [
        "branch",
        "--param",
        "kappa",
        "--set",
        "kappa=0.0105",
        "--csv",
    ];
    let (code, out, err) = stickslip(&[&args[..], &["--max-steps", "3"]].concat());
    assert_eq!(code, 4, "{err}");
    assert!(err.contains("--max-steps 3"), "{err}");
    // The rows computed are kept: a header and the start and three steps.
    let rows = out.lines().filter(|l| !l.starts_with('#')).count();
    assert!(rows >= 4, "{out}");
    let (code, full, err) = stickslip(&args);
    assert_eq!(code, 0, "{err}");
    assert!(full.lines().count() > out.lines().count());
    // With --json the points computed are kept, with complete: false and
    // the reason.
    let json_args = [&args[..5], &["--json", "--max-steps", "3"]].concat();
    let (code, json, err) = stickslip(&json_args);
    assert_eq!(code, 4, "{err}");
    let v: Value = serde_json::from_str(&json).unwrap();
    assert_eq!(v["complete"], Value::Bool(false));
    assert!(v["stop"].as_str().unwrap().contains("--max-steps 3"), "{v}");
    assert_eq!(v["points"].as_array().unwrap().len(), rows - 1);
}

#[test]
fn help_documents_status_4_and_the_limits() {
    for (cmd, needle) in [
        ("cycles", "status 4"),
        ("diagram", "status 4"),
        ("simulate", "status 4"),
        ("branch", "status 4"),
    ] {
        let (code, out, _) = stickslip(&[cmd, "--help"]);
        assert_eq!(code, 0);
        assert!(
            out.contains(needle) && out.contains("--max-steps"),
            "{cmd}: {out}"
        );
    }
}
