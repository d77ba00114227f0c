//! Restarts (issue 24): every cycle `cycles` writes carries a label and its
//! orbit, written exactly to `<run>-cycles-orbits.jsonl`; `cycles --from
//! FILE.json --index N` corrects that orbit at its own parameters (the
//! same cycle to rounding) and continues the branch both ways, matching
//! the original branch where both have a cycle; the file's faults are
//! typed input errors naming the file and the field.

mod common;

use common::{json_of, stickslip, temp_dir};
use serde_json::Value;
use std::path::Path;
use stickslip::analysis::settle::{settle, stuck_start, SettleSettings};
use stickslip::analysis::simulate::cycle_by_integration;
use stickslip::jobs::cycles::{CyclesRequest, Observer, Plan};
use stickslip::jobs::SceneSpec;
use stickslip::log_model::LogBlock;
use stickslip::model::ModelKind;
use stickslip::records::orbit::StoredOrbit;

/// `cycles ARGS --json --out DIR`: the exit status, the JSON and stderr.
fn cycles(dir: &Path, args: &[&str]) -> (i32, Value, String) {
    let out = dir.to_str().unwrap();
    json_of(&[&["cycles", "--json", "--out", out], args].concat())
}

/// The entry labelled `label` in the JSON's list `list`.
fn entry<'a>(json: &'a Value, list: &str, label: u64) -> &'a Value {
    json[list]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["label"] == label)
        .unwrap()
}

/// The cycle labelled `label` in the JSON's branch cycles.
fn labelled(json: &Value, label: u64) -> &Value {
    entry(json, "cycles", label)
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

/// A restart's first cycle is the stored one, bit for bit (the stored orbit
/// solves its system to the corrector's tolerances and is taken as it is,
/// not moved by a Newton step at the rounding of the solve); the
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
    // the exponential of `ln v`, on the same orbit: the same values.
    for k in ["period", "delta_s", "s_min", "v_max"] {
        assert_eq!(f(restarted, k), f(stored, k), "{k}");
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
    // Independently: a long simulation at the restarted cycle's parameters
    // (the PMMA block at its stiffness, with its inertia: the model of the
    // cycle), from a stuck block, not from the orbit: settled by the return
    // map (Radau IIA, rtol 1e-10), then integrated on (rtol 1e-12, two
    // periods, then the extremes of `s` over eight).
    assert_eq!(restarted["stable"], true);
    assert_eq!(restarted["model"], "inertial");
    let p = stickslip::params::Params {
        kappa: f(restarted, "kappa"),
        ..common::pmma(f(restarted, "m"), 2.4e-4)
    };
    let kind = ModelKind::Inertial;
    let settled = settle(kind, &p, stuck_start(&p), &SettleSettings::for_params(&p)).unwrap();
    let start = LogBlock::new(kind, &p).to_model(&settled.section, &p.to_vec());
    let period = f(restarted, "period");
    let (t, delta_s) =
        cycle_by_integration(kind, &p, start, 2.0 * period, 8.0 * period, 4, 1e-12).unwrap();
    for (k, sim) in [("period", t), ("delta_s", delta_s)] {
        let e = rel(sim, f(restarted, k));
        assert!(
            e < 1e-6,
            "{k}: simulation {sim} vs restart {}: {e:e}",
            f(restarted, k)
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// An unstable cycle and a fold of cycles (brockley's hysteretic branch)
/// restart as they were, bit for bit: the unstable one, and the fold
/// (singular at fixed stiffness, checked at fixed period) as it was
/// located, with a stable and an unstable side and not reported again.
/// (Corrected by a Newton step, the first unstable cycle moved by 2e-14 in
/// `Delta_s` on one branch and by 3e-15 on another.)
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
        assert_eq!(f(first_cycle, k), f(unstable, k), "{k}");
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
    // The fold is the start, on its own mesh, read as a point (its error
    // estimate the located fold's, not the ill-posed one at fixed
    // stiffness), reported as the fold once (not found again a step
    // later), its legs toward longer and shorter periods.
    assert_eq!(again["start"]["lpc"], true);
    let start = labelled(&again, 0);
    for k in ["kappa", "period", "delta_s"] {
        assert_eq!(f(start, k), f(fold, k), "{k}");
    }
    assert_eq!(start["ntst"], fold["ntst"]);
    assert!(f(start, "error_estimate") < 1e-10);
    let specials = again["special_points"].as_array().unwrap();
    assert_eq!(specials.len(), 1);
    assert_eq!(specials[0]["kind"], "lpc");
    assert_eq!(f(&specials[0], "delta_s"), f(start, "delta_s"));
    let stop = again["stop"].as_str().unwrap();
    assert!(
        stop.contains("toward longer periods") && stop.contains("toward shorter periods"),
        "{stop}"
    );
    // Its two-parameter curve starts from it.
    let label = fold["label"].to_string();
    let a = args(&label);
    let a: Vec<&str> = a.iter().map(String::as_str).collect();
    let (_, curve, stderr) = cycles(&dir.join("d"), &[&a[..], &["--lpc-curve"]].concat());
    assert!(
        curve["lpc_curve"].as_array().is_some_and(|c| !c.is_empty()),
        "{stderr}"
    );
    // The file's scene is brockley: another one named on the command line,
    // the default's name included, is refused, not replaced.
    let (status, _, stderr) = stickslip(&[
        "cycles",
        "--from",
        file.to_str().unwrap(),
        "--index",
        "0",
        "--scene",
        "pmma",
    ]);
    assert_eq!(status, 2, "{stderr}");
    assert!(
        stderr.contains("source.scene") && stderr.contains("not --scene pmma"),
        "{stderr}"
    );
    // A label is a whole number from 0: -1 is refused in those words.
    let (status, _, stderr) =
        stickslip(&["cycles", "--from", file.to_str().unwrap(), "--index", "-1"]);
    assert_eq!(status, 2, "{stderr}");
    assert!(
        stderr.contains("labels are whole numbers from 0"),
        "{stderr}"
    );
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
    // A branch's JSON is no cycles file.
    let branch = dir.join("branch.json");
    std::fs::write(
        &branch,
        stickslip(&["branch", "--param", "kappa", "--json", "--max-steps", "3"]).1,
    )
    .unwrap();
    fails(
        &branch,
        "0",
        &[],
        &["`cycles --from` takes the JSON of `cycles --json`"],
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

/// `branch ARGS --json`: the exit status, the JSON and stderr.
fn branch(args: &[&str]) -> (i32, Value, String) {
    json_of(&[&["branch", "--json"], args].concat())
}

/// The point labelled `label` of a branch's JSON.
fn point(json: &Value, label: u64) -> &Value {
    entry(json, "points", label)
}

/// `branch --from FILE.json --index N` continues steady sliding from the
/// written point: in the file's parameter (`K`) its first point is the
/// stored one bit for bit and it ends where the file's branch ends; in
/// another (`nu`) it is the branch of a fresh run with `--set kappa=` of
/// the point's stiffness, row for row; a restart of a restart keeps both
/// (`source.at`). Independent values: the original run's point, and the
/// fresh run.
#[test]
fn branch_restarts_from_a_written_point() {
    let dir = temp_dir("restart-branch");
    let (status, first, _) = branch(&["--param", "K"]);
    assert_eq!(status, 0);
    assert_eq!(first["source"]["scene"], "pmma");
    let labels: Vec<u64> = first["points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["label"].as_u64().unwrap())
        .collect();
    assert_eq!(labels, (0..labels.len() as u64).collect::<Vec<_>>());
    let file = dir.join("k.json");
    std::fs::write(&file, first.to_string()).unwrap();
    let from = file.to_str().unwrap();
    // The Hopf point the branch located, and a point before it.
    let hopf = first["points"]
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["event"] == "hopf")
        .unwrap();
    let n = hopf["label"].as_u64().unwrap() - 3;
    let (status, again, stderr) = branch(&["--from", from, "--index", &n.to_string()]);
    assert_eq!(status, 0, "{stderr}");
    assert_eq!(again["param"], "kappa");
    assert_eq!(again["control"]["param"], "K");
    assert_eq!(again["to"], first["to"]);
    assert_eq!(again["restarted_from"]["label"], n);
    assert_eq!(again["restarted_from"]["kind"], "branch point");
    // In kappa, the parameter K moves: to the file's end as well.
    let (status, in_kappa, _) = branch(&[
        "--from",
        from,
        "--index",
        &n.to_string(),
        "--param",
        "kappa",
        "--max-steps",
        "2",
    ]);
    assert_eq!(status, 4);
    assert_eq!(in_kappa["to"], first["to"]);
    assert_eq!(in_kappa["points"][0]["kappa"], point(&first, n)["kappa"]);
    let (stored, restarted) = (point(&first, n), &again["points"][0]);
    for k in ["kappa", "s", "theta", "eig_re_1", "eig_re_2", "K_N_per_m"] {
        assert_eq!(restarted[k], stored[k], "{k}");
    }
    // The onset is located again on the restarted branch.
    let refound = again["points"]
        .as_array()
        .unwrap()
        .iter()
        .find(|p| p["event"] == "hopf")
        .expect("the Hopf point again");
    assert!(rel(f(refound, "kappa"), f(hopf, "kappa")) < 1e-10);
    assert!(rel(f(refound, "omega"), f(hopf, "omega")) < 1e-10);

    // In nu from the point: the fresh run with --set kappa of the point.
    let kappa = stored["kappa"].as_f64().unwrap();
    let (status, in_nu, stderr) = branch(&[
        "--from",
        from,
        "--index",
        &n.to_string(),
        "--param",
        "nu",
        "--to",
        "3",
    ]);
    assert_eq!(status, 0, "{stderr}");
    assert_eq!(in_nu["source"]["at"]["kappa"], stored["kappa"]);
    let set = format!("kappa={kappa:?}");
    let (status, fresh, _) = branch(&[
        "--param",
        "nu",
        "--from",
        "1",
        "--to",
        "3",
        "--set",
        &set,
        "--model",
        "quasi-static",
    ]);
    assert_eq!(status, 0);
    let (a, b) = (
        in_nu["points"].as_array().unwrap(),
        fresh["points"].as_array().unwrap(),
    );
    assert_eq!(a.len(), b.len());
    for (x, y) in a.iter().zip(b) {
        for k in ["nu", "K_over_W_per_m", "s", "theta", "eig_re_1", "eig_im_1"] {
            let (x, y) = (x[k].as_f64().unwrap(), y[k].as_f64().unwrap());
            assert!(
                (x - y).abs() <= 1e-12 * y.abs().max(1e-300),
                "{k}: {x} vs {y}"
            );
        }
    }
    // A restart of that restart, and the onset at one of its points: at
    // kappa of the first point and nu of this one.
    let nu_file = dir.join("nu.json");
    std::fs::write(&nu_file, in_nu.to_string()).unwrap();
    let (status, hopf_json, stderr) = json_of(&[
        "hopf",
        "--json",
        "--from",
        nu_file.to_str().unwrap(),
        "--index",
        "4",
    ]);
    assert_eq!(status, 0, "{stderr}");
    let nu = point(&in_nu, 4)["nu"].as_f64().unwrap();
    let (status, direct, _) = json_of(&[
        "hopf",
        "--json",
        "--set",
        &set,
        "--set",
        &format!("nu={nu:?}"),
    ]);
    assert_eq!(status, 0);
    for k in ["kappa_c", "omega_c", "l1"] {
        assert_eq!(hopf_json[k], direct[k], "{k}");
    }
    assert_eq!(hopf_json["operating_point"], direct["operating_point"]);
    assert_eq!(hopf_json["restarted_from"]["params"]["nu"], nu);
    let _ = std::fs::remove_dir_all(&dir);
}

/// `hopf --from FILE.json --index N` at a cycle of a branch in the driving
/// velocity is `hopf` with `--set` of that cycle's parameters (the same
/// onset to the last bit), in the stiffness and in V.
#[test]
fn hopf_at_a_written_cycle_is_hopf_with_its_parameters() {
    let dir = temp_dir("restart-hopf");
    let (status, first, _) = cycles(
        &dir.join("a"),
        &[
            "--set",
            "K=2.5e5",
            "--param",
            "V",
            "--to",
            "3",
            "--max-steps",
            "6",
        ],
    );
    assert_eq!(status, 4);
    let file = dir.join("a.json");
    std::fs::write(&file, first.to_string()).unwrap();
    let cycle = labelled(&first, 6);
    let nu = f(cycle, "nu");
    assert!(nu != first["source"]["scene_params"][1].as_f64().unwrap());
    let json = |args: &[&str]| -> Value {
        let (status, json, err) = json_of(args);
        assert_eq!(status, 0, "{err}");
        json
    };
    let from = file.to_str().unwrap();
    let set_nu = format!("nu={nu:?}");
    for param in [None, Some("V")] {
        let mut a = vec!["hopf", "--json", "--from", from, "--index", "6"];
        let mut b = vec!["hopf", "--json", "--set", "K=2.5e5", "--set", &set_nu];
        if let Some(p) = param {
            a.extend(["--param", p]);
            b.extend(["--param", p]);
        }
        let (a, b) = (json(&a), json(&b));
        assert_eq!(a["restarted_from"]["kind"], "cycle");
        assert_eq!(a["restarted_from"]["label"], 6);
        assert_eq!(a["model"], b["model"]);
        for k in ["kappa_c", "omega_c", "l1"] {
            // The same onset; in V located along a continuation in nu,
            // whose steps round differently (1e-14).
            let e = rel(f(&a, k), f(&b, k));
            assert!(e < 1e-12, "{param:?} {k}: {e:e}");
        }
        if param.is_some() {
            let (x, y) = (f(&a["critical"], "value"), f(&b["critical"], "value"));
            assert!(rel(x, y) < 1e-12, "V_c {x} vs {y}");
        } else {
            assert_eq!(a["kappa_c"], b["kappa_c"]);
        }
    }
    let text = stickslip(&["hopf", "--from", from, "--index", "6"]).1;
    assert!(
        text.contains(&format!("at the parameters of cycle #6 of {from}")),
        "{text}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The faults of `branch --from` and `hopf --from` are input errors (exit
/// status 2) naming the file and the field: a cycles file to `branch`, an
/// index out of range, a file without `source`, the end point without
/// `--to`, `--set` beside it, a `--from` that is neither a number nor a
/// file with `--index`, a file of neither kind to `hopf`.
#[test]
fn branch_and_hopf_restart_errors_name_the_file_and_the_field() {
    let dir = temp_dir("restart-branch-errors");
    let (status, json, _) = branch(&["--param", "kappa", "--max-steps", "3"]);
    assert_eq!(status, 4);
    let n = json["points"].as_array().unwrap().len();
    let good = dir.join("good.json");
    std::fs::write(&good, json.to_string()).unwrap();
    let (_, cycles_json, _) = cycles(&dir.join("c"), &["--max-steps", "2"]);
    let cycles_file = dir.join("cycles.json");
    std::fs::write(&cycles_file, cycles_json.to_string()).unwrap();
    let mut old = json.clone();
    old.as_object_mut().unwrap().remove("source");
    let old_file = dir.join("old.json");
    std::fs::write(&old_file, old.to_string()).unwrap();
    let mut ended = json.clone();
    ended["to"] = json["points"][n - 1]["kappa"].clone();
    let ended_file = dir.join("ended.json");
    std::fs::write(&ended_file, ended.to_string()).unwrap();
    let hopf_file = dir.join("hopf.json");
    std::fs::write(&hopf_file, stickslip(&["hopf", "--json"]).1).unwrap();
    let fails = |command: &str, file: &Path, index: &str, extra: &[&str], words: &[&str]| {
        let mut args = vec![command, "--from", file.to_str().unwrap(), "--index", index];
        args.extend_from_slice(extra);
        let (status, _, stderr) = stickslip(&args);
        assert_eq!(status, 2, "{args:?}: {stderr}");
        assert!(stderr.contains(file.to_str().unwrap()), "{stderr}");
        for w in words {
            assert!(stderr.contains(w), "{w}: {stderr}");
        }
    };
    fails("branch", &dir.join("missing.json"), "0", &[], &["--from"]);
    fails(
        "branch",
        &cycles_file,
        "0",
        &[],
        &["points", "`branch --from` continues steady sliding"],
    );
    fails(
        "branch",
        &good,
        "99",
        &[],
        &[
            "--index",
            &format!(
                "no point labelled 99: the file's points are labelled 0 to {}",
                n - 1
            ),
        ],
    );
    fails(
        "branch",
        &old_file,
        "0",
        &[],
        &["source", "rerun `branch` with this version"],
    );
    fails(
        "branch",
        &ended_file,
        &(n - 1).to_string(),
        &[],
        &["--to", "the end of the file's branch"],
    );
    fails("branch", &good, "1", &["--set", "nu=2"], &["--set/--model"]);
    // A quasi-static point continued in the inertia: the model chosen
    // afresh, as `branch --param m` at its parameters chooses it.
    let (status, in_m, stderr) = branch(&[
        "--from",
        good.to_str().unwrap(),
        "--index",
        "1",
        "--param",
        "m",
        "--max-steps",
        "2",
    ]);
    assert_eq!(status, 4, "{stderr}");
    assert_eq!(in_m["model"], "inertial");
    fails(
        "hopf",
        &hopf_file,
        "0",
        &[],
        &["not the JSON of `stickslip cycles --json`"],
    );
    fails("hopf", &good, "99", &[], &["--index"]);
    fails("hopf", &old_file, "0", &[], &["source"]);
    // A Python result (no orbits file) gives no cycle's parameters exactly.
    let mut python = cycles_json.clone();
    python["orbits_file"] = Value::Null;
    let python_file = dir.join("python.json");
    std::fs::write(&python_file, python.to_string()).unwrap();
    fails("hopf", &python_file, "0", &[], &["orbits_file", "null"]);
    for command in ["branch", "hopf"] {
        let mut args = vec![command, "--from", "k.json"];
        if command == "branch" {
            args.extend(["--param", "kappa"]);
        }
        let (status, _, stderr) = stickslip(&args);
        assert_eq!(status, 2, "{stderr}");
        assert!(
            stderr.contains("--from") && stderr.contains("--index N"),
            "{stderr}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A run whose `--out` was relative is restarted from another directory:
/// the orbits file is found from the JSON's directory (a stranger's
/// `cd ..` failed with "cannot read run1/...jsonl (nor ...)").
#[test]
fn a_restart_from_another_directory_finds_the_orbits() {
    let dir = common::temp_dir("restart-elsewhere");
    let work = dir.join("work");
    std::fs::create_dir_all(&work).unwrap();
    let run = |cwd: &std::path::Path, args: &[&str]| {
        let out = std::process::Command::new(env!("CARGO_BIN_EXE_stickslip"))
            .current_dir(cwd)
            .args(args)
            .output()
            .unwrap();
        (
            out.status.code().unwrap_or(-1),
            String::from_utf8_lossy(&out.stdout).to_string(),
            String::from_utf8_lossy(&out.stderr).to_string(),
        )
    };
    let (code, json, err) = run(
        &work,
        &[
            "cycles",
            "--kappa-fraction",
            "0.95",
            "--json",
            "--out",
            "run1",
        ],
    );
    assert_eq!(code, 0, "{err}");
    std::fs::write(work.join("run1.json"), &json).unwrap();
    let (code, _, err) = run(
        &dir,
        &[
            "cycles",
            "--from",
            "work/run1.json",
            "--index",
            "3",
            "--out",
            "again",
        ],
    );
    assert_eq!(code, 0, "{err}");
}

/// A restart from a large cycle (PMMA with m = 0.01, label 40 and the last
/// label of a branch to 0.2 kappa_c; 51 when this was found) goes back up
/// to the Hopf point and ends there: a
/// long step over the Hopf point, where the parameter turns and the orbit
/// collapses, failed to locate that turn ("Newton did not converge after 30
/// iterations", exit 4: a stranger's find); the step is now taken again
/// shorter.
#[test]
fn a_restart_from_a_large_cycle_ends_at_the_hopf_point() {
    let dir = common::temp_dir("restart-large");
    let out = dir.join("run");
    let (code, json, err) = common::stickslip(&[
        "cycles",
        "--set",
        "m=0.01",
        "--kappa-fraction",
        "0.2",
        "--json",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let file = dir.join("run.json");
    std::fs::write(&file, &json).unwrap();
    let first: serde_json::Value = serde_json::from_str(&json).unwrap();
    let last = (first["cycles"].as_array().unwrap().len() - 1).to_string();
    for label in ["40", last.as_str()] {
        let again = dir.join(format!("again{label}"));
        let (code, json, err) = common::stickslip(&[
            "cycles",
            "--from",
            file.to_str().unwrap(),
            "--index",
            label,
            "--kappa-fraction",
            "0.19",
            "--json",
            "--out",
            again.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "label {label}: {err}");
        let v: serde_json::Value = serde_json::from_str(&json).unwrap();
        assert_eq!(
            v["leg_stops"][0]["reason"], "hopf_point",
            "label {label}: {json}"
        );
    }
}

/// A point of a stiffness branch continued in V chooses its model along
/// the velocity range as a fresh `branch --param V` at the point's K does
/// (inertial toward 1 mm/s here, where the K branch was quasi-static): the
/// same Hopf velocity to 1e-12. A stand-in for the scene file (moved since
/// the run) is taken where it gives the run's parameters; one that does
/// not, or an inertia threshold beside --from, is refused.
#[test]
fn a_branch_point_continued_in_another_parameter_chooses_its_model_afresh() {
    let dir = temp_dir("restart-granite");
    let scene = dir.join("granite.toml");
    std::fs::write(&scene, common::GRANITE).unwrap();
    let scene = scene.to_str().unwrap();
    let (status, k, stderr) = branch(&["--scene", scene, "--param", "K"]);
    assert_eq!(status, 0, "{stderr}");
    assert_eq!(k["model"], "quasi-static");
    let file = dir.join("k.json");
    std::fs::write(&file, k.to_string()).unwrap();
    let file = file.to_str().unwrap();
    let label = k["points"].as_array().unwrap().len() as u64 - 3;
    let at = point(&k, label);
    let hopf_v = |json: &Value| {
        let hopf: Vec<f64> = json["points"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|p| p["event"] == "hopf")
            .map(|p| f(p, "V_um_per_s"))
            .collect();
        assert_eq!(hopf.len(), 1, "{hopf:?}");
        hopf[0]
    };
    let index = label.to_string();
    let v_args = ["--param", "V", "--to", "1000"];
    let (status, restarted, stderr) =
        branch(&[&["--from", file, "--index", &index][..], &v_args].concat());
    assert_eq!(status, 0, "{stderr}");
    let k_set = format!("K={}", f(at, "K_N_per_m"));
    let (status, fresh, stderr) =
        branch(&[&["--scene", scene, "--set", &k_set][..], &v_args].concat());
    assert_eq!(status, 0, "{stderr}");
    assert_eq!(fresh["model"], "inertial");
    assert_eq!(restarted["model"], fresh["model"]);
    assert!(rel(hopf_v(&restarted), hopf_v(&fresh)) < 1e-12);
    // The scene file moved: named again with --scene it stands in.
    let moved = dir.join("moved.toml");
    std::fs::rename(scene, &moved).unwrap();
    let moved = moved.to_str().unwrap();
    let (status, _, stderr) = branch(&["--from", file, "--index", &index, "--max-steps", "2"]);
    assert_eq!(status, 2, "{stderr}");
    assert!(stderr.contains("granite.toml"), "{stderr}");
    let (status, _, stderr) = branch(&[
        "--from",
        file,
        "--index",
        &index,
        "--max-steps",
        "2",
        "--scene",
        moved,
    ]);
    assert!(status == 0 || status == 4, "{stderr}");
    // Another rig is no stand-in; nor is the inertia threshold the file's to change.
    std::fs::write(moved, common::GRANITE.replace("B = 0.014", "B = 0.015")).unwrap();
    let (status, _, stderr) = branch(&["--from", file, "--index", &index, "--scene", moved]);
    assert_eq!(status, 2, "{stderr}");
    assert!(stderr.contains("B = 1.5e-2"), "{stderr}");
    let (status, _, stderr) = branch(&[
        "--from",
        file,
        "--index",
        &index,
        "--inertia-threshold",
        "1e-2",
    ]);
    assert_eq!(status, 2, "{stderr}");
    assert!(stderr.contains("--inertia-threshold"), "{stderr}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// `json` as written before `mu_vv` and `mu_vphi` existed (`keep = 8`) or
/// before `eta_d` (`keep = 10`): the parameter vectors
/// (`source.scene_params`, and each orbit's `params` in a copy of its
/// orbits file `orbits`, which the returned JSON names) hold their first
/// `keep` entries, `kappa` to `theta_c` or to `mu_vphi`.
fn before_corrections(json: &Value, orbits: &Path, keep: usize) -> Value {
    let truncate = |v: &mut Value| {
        let a = v.as_array_mut().unwrap();
        assert_eq!(a.len(), 11);
        assert!(a.split_off(keep).iter().all(|x| *x == 0.0));
    };
    let mut old = json.clone();
    truncate(&mut old["source"]["scene_params"]);
    if let Some(file) = json["orbits_file"].as_str() {
        let lines: Vec<String> = std::fs::read_to_string(file)
            .unwrap()
            .lines()
            .map(|l| {
                let mut orbit: Value = serde_json::from_str(l).unwrap();
                truncate(&mut orbit["params"]);
                orbit.to_string()
            })
            .collect();
        std::fs::write(orbits, lines.join("\n") + "\n").unwrap();
        old["orbits_file"] = Value::from(orbits.to_str().unwrap());
    }
    old
}

/// Files written before `mu_vv` and `mu_vphi` (8 parameters) or before
/// `eta_d` (10) restart with them 0, as the run that wrote them computed:
/// `cycles --from`, `hopf --from` and `branch --from` give what they give
/// from the same file in today's layout (11 parameters), bit for bit.
#[test]
fn files_from_before_the_corrections_in_ln_v_restart() {
    let dir = temp_dir("restart-before-corrections");
    let (status, json, _) = cycles(&dir.join("a"), &["--set", "nu=3", "--max-steps", "5"]);
    assert_eq!(status, 4);
    let (status, branch_json, _) = branch(&["--param", "nu", "--set", "kappa=0.009"]);
    assert_eq!(status, 0);
    let write = |name: &str, v: &Value| {
        let file = dir.join(name);
        std::fs::write(&file, v.to_string()).unwrap();
        file.to_str().unwrap().to_string()
    };
    let (new, new_branch) = (
        write("new.json", &json),
        write("new-branch.json", &branch_json),
    );
    for keep in [8, 10] {
        let orbits = dir.join(format!("old-orbits-{keep}.jsonl"));
        let old = write(
            &format!("old-{keep}.json"),
            &before_corrections(&json, &orbits, keep),
        );
        let old_branch = write(
            &format!("old-branch-{keep}.json"),
            &before_corrections(&branch_json, &dir.join("none"), keep),
        );
        restarts_agree(&dir, (&new, &old), (&new_branch, &old_branch), keep);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The restarts from `new` and `old` (a file in today's layout and the same
/// written with `keep` parameters) agree: `hopf --from`, `cycles --from`
/// and `branch --from`.
fn restarts_agree(
    dir: &Path,
    (new, old): (&str, &str),
    (new_branch, old_branch): (&str, &str),
    keep: usize,
) {
    // Everything but the timing and the files written.
    let result = |args: &[&str]| -> Value {
        let (status, mut v, err) = json_of(args);
        assert!(status == 0 || status == 4, "{args:?}: {err}");
        for key in [
            "elapsed_s",
            "files",
            "orbits_file",
            "restarted_from",
            "figures",
            "csv",
        ] {
            v.as_object_mut().unwrap().remove(key);
        }
        v
    };
    for (a, b) in [(new, old), (new_branch, old_branch)] {
        let hopf = |from: &str| result(&["hopf", "--json", "--from", from, "--index", "2"]);
        assert_eq!(hopf(a), hopf(b));
    }
    let restart = |from: &str, out: &str| {
        let out = dir.join(out);
        result(&[
            "cycles",
            "--json",
            "--out",
            out.to_str().unwrap(),
            "--from",
            from,
            "--index",
            "2",
            "--max-steps",
            "3",
        ])
    };
    let (a, b) = (
        restart(new, &format!("r-new-{keep}")),
        restart(old, &format!("r-old-{keep}")),
    );
    assert_eq!(a["cycles"], b["cycles"]);
    assert_eq!(a["source"], b["source"]);
    assert_eq!(a["source"]["scene_params"][keep], 0.0);
    // The text names the file restarted from.
    let again = |from: &str| {
        let v = result(&["branch", "--json", "--from", from, "--index", "5"]);
        v.to_string()
            .replace(&format!("old-branch-{keep}.json"), "new-branch.json")
    };
    assert_eq!(again(new_branch), again(old_branch));
}
