//! No NaN or infinity in any output: cycles whose Floquet pencil is singular
//! to rounding, stability decided with the multipliers' error, folds of
//! cycles that are not there, and a simulation whose velocity underflows.
//! Each check recomputes what it asserts from the printed numbers.

mod common;

use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// A fresh output directory for one test.
fn out_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("stickslip-finite-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Runs the binary through `sh` under a 4 GB address-space limit and a
/// time bound; returns the exit status, stdout and stderr.
fn run_bounded(args: &[&str], seconds: u64) -> (i32, String, String) {
    let script = format!(
        "ulimit -v 4000000; exec \"$0\" {}",
        args.iter()
            .map(|a| format!("'{a}'"))
            .collect::<Vec<_>>()
            .join(" ")
    );
    let mut child = Command::new("sh")
        .arg("-c")
        .arg(script)
        .arg(env!("CARGO_BIN_EXE_stickslip"))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run stickslip");
    // The pipes are drained while the child runs: output beyond a pipe's
    // buffer would otherwise block it until the time bound.
    let drain = |pipe: Option<Box<dyn std::io::Read + Send>>| {
        std::thread::spawn(move || {
            let mut text = Vec::new();
            if let Some(mut pipe) = pipe {
                std::io::Read::read_to_end(&mut pipe, &mut text).ok();
            }
            String::from_utf8_lossy(&text).into_owned()
        })
    };
    let stdout = drain(child.stdout.take().map(|p| Box::new(p) as _));
    let stderr = drain(child.stderr.take().map(|p| Box::new(p) as _));
    let start = Instant::now();
    let status = loop {
        if let Some(s) = child.try_wait().unwrap() {
            break s;
        }
        if start.elapsed() > Duration::from_secs(seconds) {
            child.kill().ok();
            panic!("stickslip {args:?} still running after {seconds} s");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    (
        status.code().unwrap_or(-1),
        stdout.join().unwrap(),
        stderr.join().unwrap(),
    )
}

/// No `NaN` or `inf` anywhere in `text` (case-insensitive words).
fn assert_no_nan_or_inf(text: &str, what: &str) {
    for word in text.split(|c: char| !c.is_ascii_alphanumeric()) {
        let w = word.to_ascii_lowercase();
        assert!(
            w != "nan" && w != "inf" && w != "infinity",
            "{what} contains '{word}'"
        );
    }
}

fn csv_of(dir: &Path, suffix: &str) -> String {
    let file = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.to_string_lossy().ends_with(suffix))
        .unwrap_or_else(|| panic!("no *{suffix} in {}", dir.display()));
    std::fs::read_to_string(file).unwrap()
}

/// `(re, im)` of every multiplier of a JSON cycle; a null is a failure.
fn multipliers(c: &Value) -> Vec<(f64, f64)> {
    c["multipliers"]
        .as_array()
        .unwrap()
        .iter()
        .map(|z| {
            let re = z[0].as_f64().expect("multiplier real part is a number");
            let im = z[1]
                .as_f64()
                .expect("multiplier imaginary part is a number");
            (re, im)
        })
        .collect()
}

/// Checks every cycle of a `cycles --json` output against its own
/// multipliers: `stable: true` only with every nontrivial multiplier (all
/// but `trivial_multiplier_index`) inside the unit circle; `stable: false`
/// only with one outside; `stable: null` only with a reason; an unavailable
/// error only with a reason. Returns how many cycles were undecidable.
fn check_stability_against_multipliers(v: &Value) -> usize {
    let mut undecidable = 0;
    for c in v["cycles"].as_array().unwrap() {
        let mu = multipliers(c);
        let trivial = c["trivial_multiplier_index"].as_u64().map(|i| i as usize);
        let moduli: Vec<f64> = (0..mu.len())
            .filter(|i| Some(*i) != trivial)
            .map(|i| mu[i].0.hypot(mu[i].1))
            .collect();
        match &c["stable"] {
            Value::Bool(true) => assert!(
                moduli.iter().all(|r| *r <= 1.0),
                "kappa = {}: labelled stable with multipliers {mu:?}",
                c["kappa"]
            ),
            Value::Bool(false) => assert!(
                moduli.iter().any(|r| *r > 1.0),
                "kappa = {}: labelled unstable with multipliers {mu:?}",
                c["kappa"]
            ),
            Value::Null => {
                undecidable += 1;
                assert!(
                    c["stability_reason"]
                        .as_str()
                        .is_some_and(|r| !r.is_empty()),
                    "undecidable without a reason: {c}"
                );
            }
            other => panic!("stable = {other}"),
        }
        for (field, reason) in [
            (
                "trivial_multiplier_error",
                "trivial_multiplier_error_reason",
            ),
            ("error_estimate", "error_estimate_reason"),
        ] {
            if c[field].is_null() {
                assert!(c[reason].is_string(), "{field} null without {reason}: {c}");
            } else {
                assert!(c[field].as_f64().unwrap().is_finite());
            }
        }
    }
    undecidable
}

#[test]
fn rr_cycles_near_the_hopf_point_are_undecidable_and_finite() {
    let dir = out_dir("rr");
    let (code, out, err) = run_bounded(
        &[
            "cycles",
            "--scene",
            "pmma-rr",
            "--json",
            "--out",
            dir.to_str().unwrap(),
        ],
        60,
    );
    assert_eq!(code, 0, "{err}");
    assert_no_nan_or_inf(&out, "cycles --json");
    assert_no_nan_or_inf(&csv_of(&dir, "-cycles.csv"), "cycles CSV");
    let v: Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["complete"], true);
    let undecidable = check_stability_against_multipliers(&v);
    // Just past the Hopf point a nontrivial multiplier is 1 + O(amplitude^2):
    // the first cycle's must lie within ten times the trivial one's error of 1.
    let first = &v["cycles"][0];
    let mu = multipliers(first);
    let dist = |(re, im): (f64, f64)| (re - 1.0).hypot(im);
    let mut by_distance: Vec<f64> = mu.iter().map(|z| dist(*z)).collect();
    by_distance.sort_by(f64::total_cmp);
    let modulus_gap = mu
        .iter()
        .map(|z| (z.0.hypot(z.1) - 1.0).abs())
        .filter(|d| *d <= 10.0 * by_distance[0])
        .count();
    assert!(modulus_gap >= 2, "first cycle: {mu:?}");
    assert!(first["stable"].is_null() && undecidable >= 1, "{first}");
}

/// `stickslip CMD --scene granite.toml --json` in a fresh folder `dir`:
/// exit 0, no NaN or inf, the parsed JSON.
fn granite_json(cmd: &str, dir: &str) -> Value {
    let dir = out_dir(dir);
    let scene = dir.join("granite.toml");
    std::fs::write(&scene, common::SHEAR_GRANITE).unwrap();
    let args = [
        cmd,
        "--scene",
        scene.to_str().unwrap(),
        "--json",
        "--out",
        dir.to_str().unwrap(),
    ];
    let (code, out, err) = run_bounded(&args, 60);
    assert_eq!(code, 0, "{err}");
    assert_no_nan_or_inf(&out, &format!("{cmd} --json"));
    serde_json::from_str(&out).unwrap()
}

#[test]
fn no_cycle_with_a_multiplier_outside_the_unit_circle_is_stable() {
    let v = granite_json("cycles", "granite");
    assert_eq!(v["model"], "inertial");
    let undecidable = check_stability_against_multipliers(&v);
    assert!(undecidable > 0);
    // Past the fold the cycles are decided stable, before it not.
    let cycles = v["cycles"].as_array().unwrap();
    let stable: Vec<bool> = cycles.iter().map(|c| c["stable"] == true).collect();
    let first_stable = stable
        .iter()
        .position(|s| *s)
        .expect("stable cycles past the fold");
    assert!(stable[first_stable..].iter().all(|s| *s), "{stable:?}");
    let fold = v["special_points"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|p| p["kind"] == "lpc")
        .count();
    assert_eq!(fold, 1);
}

#[test]
fn a_branch_vertical_to_rounding_reports_no_folds() {
    let dir = out_dir("mu2");
    let (code, out, err) = run_bounded(
        &[
            "cycles",
            "--set",
            "mu2=1",
            "--json",
            "--out",
            dir.to_str().unwrap(),
        ],
        60,
    );
    // The branch ends on a numerical failure after many cycles: partial.
    assert_eq!(code, 4, "{err}");
    assert_no_nan_or_inf(&out, "cycles --json");
    assert_no_nan_or_inf(&csv_of(&dir, "-cycles.csv"), "cycles CSV");
    let v: Value = serde_json::from_str(&out).unwrap();
    check_stability_against_multipliers(&v);
    // A fold of cycles is a turning point of kappa along the branch: on both
    // sides the cycles lie at smaller (or both at larger) kappa, by more than
    // the corrector's tolerance. Every reported fold must be one, from the
    // cycles printed around it.
    let kappas: Vec<f64> = v["cycles"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["kappa"].as_f64().unwrap())
        .collect();
    for p in v["special_points"].as_array().unwrap() {
        let k = p["kappa"].as_f64().unwrap();
        let resolved = kappas
            .iter()
            .filter(|x| ((*x - k) / k).abs() > 1e-6)
            .count();
        assert!(resolved >= 2, "fold at kappa = {k} among kappas {kappas:?}");
    }
    let folds: Vec<f64> = v["special_points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["kappa"].as_f64().unwrap())
        .collect();
    for (i, a) in folds.iter().enumerate() {
        for b in &folds[i + 1..] {
            assert!(((a - b) / a).abs() > 1e-6, "two folds at kappa {a}, {b}");
        }
    }
}

#[test]
fn an_underflowing_velocity_is_written_from_its_logarithm_within_bounds() {
    let dir = out_dir("sim");
    let t0 = Instant::now();
    let (code, out, err) = run_bounded(
        &[
            "simulate",
            "--set",
            "kappa=0.005",
            "--set",
            "mu2=1",
            "--out",
            dir.to_str().unwrap(),
        ],
        30,
    );
    assert!(t0.elapsed() < Duration::from_secs(30));
    assert!(code == 0 || code == 4, "status {code}: {err}");
    assert_no_nan_or_inf(&out, "simulate output");
    let csv = csv_of(&dir, "-simulation.csv");
    assert!(csv.len() < 50_000_000, "CSV of {} bytes", csv.len());
    assert_no_nan_or_inf(&csv, "simulation CSV");
    // Rows, without the comment a run cut short ends with.
    let mut lines = csv.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let (iv, il) = (
        header.iter().position(|h| *h == "v").unwrap(),
        header.iter().position(|h| *h == "log10_v").unwrap(),
    );
    let mut smallest = f64::INFINITY;
    for row in lines {
        let cells: Vec<&str> = row.split(',').collect();
        let log10_v: f64 = cells[il].parse().unwrap();
        // The decimal text of v, read as mantissa and exponent (it may lie
        // below the range of f64): its logarithm is log10_v.
        let (m, e) = cells[iv].split_once('e').expect("v in scientific notation");
        let (m, e): (f64, f64) = (m.parse().unwrap(), e.parse().unwrap());
        assert!((1.0..10.0).contains(&m), "v = {}", cells[iv]);
        assert!(
            (m.log10() + e - log10_v).abs() < 1e-9 * log10_v.abs().max(1.0),
            "v = {} vs log10 v = {log10_v}",
            cells[iv]
        );
        smallest = smallest.min(log10_v);
    }
    // The case of the issue: the velocity falls below the range of f64.
    assert!(smallest < -308.0, "smallest log10 v = {smallest}");
    for fig in ["-velocity.png", "-velocity.svg", "-spring-force.png"] {
        let name = format!("pmma_kappa=0.005_mu2=1-simulation{fig}");
        assert!(std::fs::metadata(dir.join(name)).is_ok());
    }
}

/// The granite rig's stability diagram (m = 2e-11 at 1 um/s, 2e-7 at
/// 100 um/s): l1 ~ m is resolved in double-double along the curve's onset
/// and judged against its bound along the curve, so no Bautin point (there
/// were 11, from rounding) and every criticality subcritical (l1 > 0 for
/// the plain RR law with small inertia).
#[test]
fn the_granite_diagram_has_no_spurious_bautin_points() {
    let v = granite_json("diagram", "granite-diagram");
    assert_eq!(
        v["special_points"].as_array().unwrap().len(),
        0,
        "{}",
        v["special_points"]
    );
    let curve = v["hopf_curve"].as_array().unwrap();
    assert!(curve.len() > 20);
    assert!(
        curve.iter().all(|p| p["criticality"] != "supercritical"),
        "a supercritical point on the granite curve"
    );
}
