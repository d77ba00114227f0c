//! Restarts (issue 24): every cycle `cycles` writes carries a label and its
//! orbit, written exactly to `<run>-cycles-orbits.jsonl`; `cycles --from
//! FILE.json --index N` corrects that orbit at its own parameters (the
//! same cycle to rounding) and continues the branch both ways, matching
//! the original branch where both have a cycle; the file's faults are
//! typed input errors naming the file and the field.

mod common;

use common::{stickslip, temp_dir};
use serde_json::Value;
use std::path::Path;
use stickslip::jobs::cycles::{CyclesRequest, Observer, Plan};
use stickslip::jobs::SceneSpec;
use stickslip::records::orbit::StoredOrbit;

/// `cycles ARGS --json --out DIR`: the exit status, the JSON and stderr.
fn cycles(dir: &Path, args: &[&str]) -> (i32, Value, String) {
    let out = dir.to_str().unwrap();
    let mut all = vec!["cycles", "--json", "--out", out];
    all.extend_from_slice(args);
    let (status, stdout, stderr) = stickslip(&all);
    (
        status,
        serde_json::from_str(&stdout).unwrap_or(Value::Null),
        stderr,
    )
}

/// The cycle labelled `label` in the JSON's branch cycles.
fn labelled(json: &Value, label: u64) -> &Value {
    json["cycles"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["label"] == label)
        .unwrap()
}

fn f(v: &Value, k: &str) -> f64 {
    v[k].as_f64().unwrap()
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// The orbits a run hands its observer.
#[derive(Default)]
struct Orbits(Vec<StoredOrbit>);

impl Observer for Orbits {
    fn orbit(&mut self, orbit: &StoredOrbit) -> Result<(), stickslip::error::Error> {
        self.0.push(orbit.clone());
        Ok(())
    }
}

/// Every stored number reads back to the same `f64`, bit for bit
/// (serde_json writes the shortest decimals that round-trip), and the
/// stored period is the reported one.
#[test]
fn stored_orbits_round_trip_bit_for_bit() {
    let request = CyclesRequest {
        max_steps: 30,
        ..CyclesRequest::default()
    };
    let plan = Plan::new(&SceneSpec::named("pmma"), request).unwrap();
    let mut orbits = Orbits::default();
    let result = plan.run(&mut orbits);
    assert_eq!(orbits.0.len(), result.cycles.len());
    let bits = |o: &StoredOrbit| -> Vec<u64> {
        let mut all = vec![o.period.to_bits()];
        for v in [&o.params, &o.mesh, &o.u, &o.origin.to_vec()] {
            all.extend(v.iter().map(|x| x.to_bits()));
        }
        all
    };
    for (o, c) in orbits.0.iter().zip(&result.cycles) {
        assert_eq!(o.label, c.label);
        assert_eq!(o.period.to_bits(), c.period.to_bits());
        let line = serde_json::to_string(o).unwrap();
        assert!(line.starts_with(&format!("{{\"label\":{},", o.label)));
        let back: StoredOrbit = serde_json::from_str(&line).unwrap();
        assert_eq!(bits(&back), bits(o), "label {}", o.label);
        let (_, cycle) = back.cycle().unwrap();
        assert_eq!(cycle.u.len(), o.u.len());
    }
    // Labels are 0, 1, 2, ... in the order written.
    let labels: Vec<usize> = result.cycles.iter().map(|c| c.label).collect();
    assert_eq!(labels, (0..labels.len()).collect::<Vec<_>>());
}

/// A restart's first cycle is the stored one (period and force drop to
/// 1e-14 after Newton's correction at the stored stiffness); the
/// restarted branch reaches a stiffness asked of both runs with the
/// original branch's cycle there (to the discretization tolerance).
#[test]
fn restart_reproduces_the_cycle_and_continues_the_branch() {
    let dir = temp_dir("restart-pmma");
    // Between the cycles labelled 40 and 41 of the default branch.
    let at = "kappa=0.01075";
    let (status, first, _) = cycles(&dir.join("a"), &["--at", at]);
    assert_eq!(status, 0);
    let file = dir.join("a.json");
    std::fs::write(&file, first.to_string()).unwrap();
    let orbits = first["orbits_file"].as_str().unwrap();
    assert!(Path::new(orbits).exists(), "{orbits}");
    assert!(first["files"]
        .as_array()
        .unwrap()
        .iter()
        .any(|f| f == orbits));
    // The cycle before the requested one, on the branch toward smaller kappa.
    let asked = first["cycles"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["user_point"] == true)
        .unwrap();
    let n = asked["label"].as_u64().unwrap() - 1;
    let stored = labelled(&first, n);
    assert!(f(stored, "kappa") > 0.01075);
    let (status, again, stderr) = cycles(
        &dir.join("b"),
        &[
            "--from",
            file.to_str().unwrap(),
            "--index",
            &n.to_string(),
            "--at",
            at,
            "--max-steps",
            "40",
        ],
    );
    assert_eq!(status, 4, "{stderr}");
    assert_eq!(again["start"]["kind"], "restart");
    assert_eq!(again["start"]["label"], n);
    let restarted = labelled(&again, 0);
    assert_eq!(restarted["kappa"], stored["kappa"]);
    // The extremes are maximised anew (Brent on the polynomials), `v` as
    // the exponential of `ln v`: to a few rounding errors.
    for (k, tol) in [
        ("period", 1e-14),
        ("delta_s", 1e-14),
        ("s_min", 1e-14),
        ("v_max", 1e-12),
    ] {
        let e = rel(f(restarted, k), f(stored, k));
        assert!(
            e < tol,
            "{k}: {} vs {}: {e:e}",
            f(restarted, k),
            f(stored, k)
        );
    }
    assert_eq!(restarted["stable"], stored["stable"]);
    // The scene is the file's.
    assert_eq!(again["source"], first["source"]);
    let reached = again["cycles"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["user_point"] == true)
        .expect("the restarted branch reaches kappa = 0.01075");
    for k in ["period", "delta_s"] {
        let e = rel(f(reached, k), f(asked, k));
        assert!(e < 1e-8, "{k} at kappa = 0.01075: {e:e}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// An unstable cycle and a fold of cycles (brockley's hysteretic branch)
/// restart as they were: the unstable one unchanged, the fold (singular at
/// fixed stiffness, corrected at fixed period) located again at its
/// stiffness, with a stable and an unstable side.
#[test]
fn unstable_cycles_and_folds_restart() {
    let dir = temp_dir("restart-brockley");
    let (status, first, _) = cycles(&dir.join("a"), &["--scene", "brockley"]);
    assert_eq!(status, 0);
    let file = dir.join("a.json");
    std::fs::write(&file, first.to_string()).unwrap();
    let unstable = first["cycles"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["stable"] == false)
        .unwrap();
    let n = unstable["label"].as_u64().unwrap().to_string();
    let args = |n: &str| {
        [
            "--from",
            file.to_str().unwrap(),
            "--index",
            n,
            "--max-steps",
            "3",
        ]
        .map(String::from)
    };
    let run = |out: &str, n: &str| {
        let a = args(n);
        let a: Vec<&str> = a.iter().map(String::as_str).collect();
        cycles(&dir.join(out), &a)
    };
    let (status, again, stderr) = run("b", &n);
    assert_eq!(status, 4, "{stderr}");
    let first_cycle = labelled(&again, 0);
    assert_eq!(first_cycle["stable"], false);
    for k in ["period", "delta_s"] {
        assert!(rel(f(first_cycle, k), f(unstable, k)) < 1e-14, "{k}");
    }
    let fold = &first["special_points"][0];
    assert_eq!(fold["kind"], "lpc");
    let (status, again, stderr) = run("c", &fold["label"].to_string());
    assert_eq!(status, 4, "{stderr}");
    let stabilities: Vec<&Value> = again["cycles"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| &c["stable"])
        .collect();
    assert!(
        stabilities.contains(&&Value::Bool(true)) && stabilities.contains(&&Value::Bool(false))
    );
    let refound = &again["special_points"][0];
    assert_eq!(refound["kind"], "lpc");
    assert!(rel(f(refound, "kappa"), f(fold, "kappa")) < 1e-9);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A file that cannot serve is an input error (exit status 2) naming the
/// file and the field: missing, not a cycles JSON, an index out of range
/// (with the valid range), a file from before orbits, an edited orbit, an
/// override beside --from.
#[test]
fn restart_errors_name_the_file_and_the_field() {
    let dir = temp_dir("restart-errors");
    let (status, json, _) = cycles(&dir.join("a"), &["--max-steps", "5"]);
    assert_eq!(status, 4);
    let n = json["cycles"].as_array().unwrap().len();
    let good = dir.join("good.json");
    std::fs::write(&good, json.to_string()).unwrap();
    let fails = |file: &Path, index: &str, extra: &[&str], words: &[&str]| {
        let out = dir.join("r");
        let mut args = vec![
            "cycles",
            "--out",
            out.to_str().unwrap(),
            "--from",
            file.to_str().unwrap(),
            "--index",
            index,
        ];
        args.extend_from_slice(extra);
        let (status, _, stderr) = stickslip(&args);
        assert_eq!(status, 2, "{stderr}");
        assert!(stderr.contains(file.to_str().unwrap()), "{stderr}");
        for w in words {
            assert!(stderr.contains(w), "{w}: {stderr}");
        }
    };
    fails(&dir.join("missing.json"), "0", &[], &["--from"]);
    let hopf = dir.join("hopf.json");
    std::fs::write(&hopf, stickslip(&["hopf", "--json"]).1).unwrap();
    fails(
        &hopf,
        "0",
        &[],
        &["cycles", "not the JSON of `stickslip cycles --json`"],
    );
    fails(
        &good,
        "99",
        &[],
        &["--index", &format!("labelled 0 to {}", n - 1)],
    );
    let mut old = json.clone();
    old.as_object_mut().unwrap().remove("orbits_file");
    old.as_object_mut().unwrap().remove("source");
    let old_file = dir.join("old.json");
    std::fs::write(&old_file, old.to_string()).unwrap();
    fails(
        &old_file,
        "0",
        &[],
        &["this file has no orbits: rerun `cycles` with this version"],
    );
    // An orbit edited out of shape.
    let orbits = json["orbits_file"].as_str().unwrap();
    let text = std::fs::read_to_string(orbits).unwrap();
    let mut first: Value = serde_json::from_str(text.lines().next().unwrap()).unwrap();
    first["u"].as_array_mut().unwrap().pop();
    let edited: Vec<String> = std::iter::once(first.to_string())
        .chain(text.lines().skip(1).map(str::to_string))
        .collect();
    std::fs::write(orbits, edited.join("\n")).unwrap();
    fails(&good, "0", &[], &["label 0: u", "expected"]);
    fails(&good, "1", &["--set", "nu=2"], &["--set/--model"]);
    fails(&good, "1", &["--scene", "rig"], &["source.scene"]);
    let _ = std::fs::remove_dir_all(&dir);
}
