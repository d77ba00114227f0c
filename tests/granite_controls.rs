//! A stranger's granite rig (A = 0.010, B = 0.014, mu2 = 2e-4, D0 = 10 µm,
//! V0 = 1 µm/s, K = 2e5 N/m, M = 5 kg, the motor at V = 1 µm/s; pressed
//! with W = 1 kN, or loaded by its weight) through `cycles --param P` and
//! `hopf --param P`: the switch to the inertial model said as the stiffness
//! branch says it, the requested values not delivered with the span of the
//! cycles computed and each one's reason, a restart's provenance, and no
//! futile advice where Appendix C excludes an onset at every value. The
//! numbers are checked against what the scene gives here, with eq. C11
//!
//!     K_c = (mu_phi - mu_v)(W + M V^2 / (mu_v D0)) / D0,
//!     mu_v = A, mu_phi = B - 2 mu2 ln(V / V0).

mod common;

use common::{stickslip, temp_dir};
use serde_json::Value;
use std::path::{Path, PathBuf};

/// The pressed rig, as the stranger wrote it.
const A: f64 = 0.010;
const B: f64 = 0.014;
const MU2: f64 = 2e-4;
/// Memory length [m], stiffness [N/m], mass [kg], load [N].
const D0: f64 = 10e-6;
const K: f64 = 2e5;
const M: f64 = 5.0;
const W: f64 = 1000.0;

/// The rig loaded by its weight, `W = M g` (no `W` key).
fn weighed() -> String {
    common::GRANITE
        .replace("W = 1000.0      # N\n", "")
        .replace("name = \"granite\"", "name = \"granite-w\"")
}

/// `text` written as `name.toml` in a fresh folder: (the folder, the file).
fn scene(name: &str, text: &str) -> (PathBuf, PathBuf) {
    let dir = temp_dir(&format!("granite-{name}"));
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).unwrap();
    (dir, path)
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

fn json(out: &str) -> Value {
    serde_json::from_str(out).unwrap_or_else(|e| panic!("{e}: {out}"))
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

fn num(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

/// The first number after `key` in `text` (up to a space, comma or colon).
fn after(text: &str, key: &str) -> f64 {
    let rest = &text[text
        .find(key)
        .unwrap_or_else(|| panic!("no {key} in {text}"))
        + key.len()..];
    let end = rest.find([' ', ',', ':', ')']).unwrap_or(rest.len());
    rest[..end]
        .parse()
        .unwrap_or_else(|e| panic!("{e}: {key} in {text}"))
}

/// The mass branch of the weighed rig crosses the inertia threshold: one
/// switch, said in the text where it happens (between the two rows at the
/// same M, the quasi-static and the inertial cycle, whose periods differ
/// by the inertia the first drops: 144.143 s and 144.185 s), in the JSON as
/// `cycles`' `model_switch` with the control's value, in the CSV's column
/// `model`, and in the figures.
#[test]
fn the_switch_to_the_inertial_model_in_mass_is_said_once() {
    let (dir, path) = scene("w", &weighed());
    let run = |out: &str, json: bool| {
        let mut args = vec![
            "cycles",
            "--scene",
            s(&path),
            "--param",
            "M",
            "--to",
            "80",
            "--at",
            "M=60",
            "--out",
            out,
        ];
        if json {
            args.push("--json");
        }
        let (code, stdout, err) = stickslip(&args);
        assert_eq!(code, 0, "{err}");
        stdout
    };
    let text_out = dir.join("text");
    let text = run(s(&text_out), false);
    let lines: Vec<&str> = text.lines().collect();
    let switches: Vec<usize> = (0..lines.len())
        .filter(|&i| lines[i].starts_with("switching to the inertial model at M = "))
        .collect();
    assert_eq!(switches.len(), 1, "{text}");
    let i = switches[0];
    let at = after(lines[i], "at M = ");
    assert!(
        lines[i].contains("(--inertia-threshold); the same orbit, corrected with the scene's inertia, continues the branch"),
        "{}",
        lines[i]
    );
    // The rows either side: at the same M, the quasi-static cycle and the inertial one.
    let (before, next) = (lines[i - 1], lines[i + 1]);
    assert_eq!(after(before, "M = "), at, "{before}");
    assert_eq!(after(next, "M = "), at, "{next}");
    let (p0, p1) = (after(before, "period "), after(next, "period "));
    assert!(
        p0 != p1 && rel(p1, p0) < 1e-3,
        "periods {p0} and {p1} s at M = {at}"
    );

    let out = dir.join("json");
    let j = json(&run(s(&out), true));
    assert_eq!(j["model"], "quasi-static", "the model at the start");
    let sw = &j["model_switch"];
    assert_eq!(sw["param"], "M", "{sw}");
    assert_eq!(sw["unit"], "kg", "{sw}");
    assert_eq!(
        (&sw["from"], &sw["to"]),
        (&"quasi-static".into(), &"inertial".into())
    );
    assert_eq!(num(&sw["threshold"]), 1e-3);
    assert!(num(&sw["inertial_imbalance"]) > 1e-3, "{sw}");
    let value = num(&sw["value"]);
    assert!(rel(value, at) < 1e-8, "JSON {value} kg, text {at} kg");
    assert!(sw["reason"].as_str().unwrap().starts_with(&format!(
        "switching to the inertial model at M = {value:.8e} kg: on the last quasi-static cycle"
    )));
    // One change of model along the rows, between two cycles at that M.
    let cycles = j["cycles"].as_array().unwrap();
    let changes: Vec<usize> = (1..cycles.len())
        .filter(|&k| cycles[k]["model"] != cycles[k - 1]["model"])
        .collect();
    assert_eq!(changes.len(), 1, "{changes:?}");
    let k = changes[0];
    assert_eq!(cycles[k - 1]["model"], "quasi-static");
    assert_eq!(cycles[k]["model"], "inertial");
    for c in [&cycles[k - 1], &cycles[k]] {
        assert!(rel(num(&c["M_kg"]), value) < 1e-12, "{}", c["M_kg"]);
    }
    assert_eq!(num(&sw["kappa"]), num(&cycles[k]["kappa"]));
    // The CSV carries each row's model; the figures draw the switch.
    let csv = std::fs::read_to_string(out.join("granite-w-cycles-in-M.csv")).unwrap();
    let mut rows = csv.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = rows.next().unwrap().split(',').collect();
    let col = header
        .iter()
        .position(|h| *h == "model")
        .expect("model column");
    let models: Vec<String> = rows
        .map(|r| r.split(',').nth(col).unwrap().to_string())
        .collect();
    assert_eq!(models.len(), cycles.len());
    assert_eq!(models.iter().filter(|m| *m == "quasi-static").count(), k);
    assert!(csv.starts_with("# scene granite-w; cycles in M [kg]; model at the start quasi-static"));
    for figure in ["amplitude", "period"] {
        let svg = std::fs::read_to_string(out.join(format!("granite-w-cycles-in-M-{figure}.svg")))
            .unwrap();
        assert!(
            svg.contains(&format!(
                "quasi-static → inertial model at M = {value:.4e} kg"
            )),
            "{figure}: no switch in the title"
        );
    }
}

/// The velocity of the pressed rig's onset, eq. C11 with its inertia
/// (`kappa = K D0/W`, `m = M V0^2/(W D0)`, `nu = V/V0`), by bisection: the
/// cycles exist below it.
fn onset_velocity() -> f64 {
    let (kappa, m) = (K * D0 / W, M * 1e-12 / (W * D0));
    let g = |nu: f64| (B - 2.0 * MU2 * nu.ln() - A) * (1.0 + m * nu * nu / A) - kappa;
    let (mut lo, mut hi) = (10.0, 1000.0);
    assert!(g(lo) > 0.0 && g(hi) < 0.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if g(mid) > 0.0 {
            lo = mid
        } else {
            hi = mid
        }
    }
    0.5 * (lo + hi)
}

/// A value asked for above the onset in V (the cycles are born below it,
/// supercritical) is not delivered: the JSON says why, and the stop states
/// the span of the cycles computed (100 .. 149.24 µm/s: from the end of
/// the range asked for, which the branch lands on, to the last cycle below
/// the onset), not the bound of the search (1492 µm/s, ten times the
/// onset).
#[test]
fn a_velocity_not_delivered_says_why_and_the_cycles_span() {
    let (dir, path) = scene("v", common::GRANITE);
    let out = dir.join("out");
    let args = |json: bool| {
        let mut a = vec![
            "cycles",
            "--scene",
            s(&path),
            "--param",
            "V",
            "--to",
            "100",
            "--at",
            "V=200,120",
            "--out",
            s(&out),
            "--force",
        ];
        if json {
            a.push("--json");
        }
        stickslip(&a)
    };
    let (code, stdout, err) = args(true);
    assert_eq!(code, 4, "{err}");
    let j = json(&stdout);
    let v_c = onset_velocity();
    assert!(
        rel(num(&j["critical"]["value"]), v_c) < 1e-9,
        "{}",
        j["critical"]
    );
    let asked = j["requested_points"].as_array().unwrap();
    assert_eq!(asked.len(), 2);
    assert_eq!(
        (num(&asked[0]["value"]), &asked[0]["delivered"]),
        (200.0, &false.into())
    );
    assert_eq!(asked[0]["cycles"], 0);
    let why = asked[0]["reason"].as_str().expect("a reason for V = 200");
    assert!(
        why.starts_with("above V_c = ") && why.ends_with("exist for V < V_c"),
        "{why}"
    );
    assert!(rel(after(why, "V_c = "), v_c) < 1e-9, "{why}");
    // The one delivered has no reason.
    assert_eq!(
        (num(&asked[1]["value"]), &asked[1]["delivered"]),
        (120.0, &true.into())
    );
    assert_eq!(asked[1]["cycles"], 1);
    assert!(asked[1].get("reason").is_none(), "{}", asked[1]);
    // The span: the least and the largest V over the cycles computed.
    let vs: Vec<f64> = j["cycles"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| num(&c["V_um_per_s"]))
        .collect();
    let (lo, hi) = vs
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(a, b), v| (a.min(*v), b.max(*v)));
    assert!(
        rel(lo, 100.0) < 1e-12 && hi < v_c && hi > 149.2,
        "{lo} .. {hi}"
    );
    let stop = j["stop"].as_str().unwrap();
    let span = "1 of the 2 requested values not delivered (see requested_points): the cycles \
                computed span V = ";
    assert!(stop.contains(span), "{stop}");
    assert!(rel(after(stop, span), lo) < 1e-6, "{stop}");
    assert!(rel(after(stop, " .. "), hi) < 1e-6, "{stop}");
    assert!(stop.ends_with(" µm/s"), "{stop}");
    // The text and the CSV say it too.
    let (code, text, _) = args(false);
    assert_eq!(code, 4);
    assert!(
        text.contains("requested V = 2.0000000000e2 µm/s: not delivered: above V_c = "),
        "{text}"
    );
    let csv = std::fs::read_to_string(out.join("granite-cycles-in-V.csv")).unwrap();
    assert!(csv.contains("# requested V = 2.000000000000000e2 µm/s not delivered: above V_c = "));
}

/// A restart in V says where it came from: `start` stays `"restart"` and
/// `restarted_from` holds the file, the label and the cycle (its model,
/// parameters, `kappa` and period exactly as written); the model line is
/// the cycle's, with why the run that wrote it started inertial (judged
/// over its range of V), not the scene's own quasi-static choice at 1 µm/s.
#[test]
fn a_restart_in_velocity_names_the_cycle_and_its_model() {
    let (dir, path) = scene("r", common::GRANITE);
    let out = dir.join("out");
    let (code, first, err) = stickslip(&[
        "cycles",
        "--scene",
        s(&path),
        "--param",
        "V",
        "--to",
        "100",
        "--out",
        s(&out),
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let fresh = json(&first);
    assert!(fresh["restarted_from"].is_null());
    assert_eq!(fresh["model"], "inertial");
    let file = dir.join("v.json");
    std::fs::write(&file, &first).unwrap();
    let cycle = fresh["cycles"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["label"] == 10)
        .unwrap();
    let restart = |json: bool| {
        let mut a = vec![
            "cycles",
            "--param",
            "V",
            "--from",
            s(&file),
            "--index",
            "10",
            "--to",
            "120",
            "--out",
            s(&out),
            "--force",
        ];
        if json {
            a.push("--json");
        }
        stickslip(&a)
    };
    let (code, again, err) = restart(true);
    assert_eq!(code, 0, "{err}");
    let again = json(&again);
    assert_eq!(again["start"], "restart");
    let from = &again["restarted_from"];
    assert_eq!(from["file"], s(&file), "{from}");
    assert_eq!(from["label"], 10);
    assert_eq!(from["kind"], "cycle");
    assert_eq!(from["model"], "inertial");
    assert_eq!(from["lpc"], false);
    assert_eq!(from["period"], cycle["period"]);
    assert_eq!(from["kappa"], cycle["kappa"]);
    assert_eq!(from["params"]["nu"], cycle["nu"]);
    assert!(rel(num(&from["params"]["m"]), M * 1e-12 / (W * D0)) < 1e-12);
    let run_reason = fresh["model_reason"].as_str().unwrap();
    let reason =
        format!("inertial: the model of the cycle restarted from (the run started {run_reason})");
    assert_eq!(again["model_reason"], reason.as_str());
    let (code, text, _) = restart(false);
    assert_eq!(code, 0);
    assert!(text.contains(&format!("\nmodel: {reason}\n")), "{text}");
    assert!(!text.contains("quasi-static"), "{text}");
    let csv = std::fs::read_to_string(out.join("granite_restart-10-cycles-in-V.csv")).unwrap();
    assert!(csv.lines().next().unwrap().contains(&reason), "{csv}");
}

/// `hopf --param` where no value of the control gives an onset says so
/// with K against Appendix C's K_c, exit status 3, without advising
/// another range; where one may lie beyond the range searched, it still
/// advises one (and the onset is there).
#[test]
fn no_onset_at_any_value_is_said_with_the_closed_form() {
    let (_dir, path) = scene("h", common::GRANITE);
    let hopf = |extra: &[&str]| {
        let mut a = vec!["hopf", "--scene", s(&path)];
        a.extend_from_slice(extra);
        let (code, _, err) = stickslip(&a);
        (code, err)
    };
    // K_c = (B - A) W / D0 at M = 0 (C12), growing with M: K below it
    // slides by stick-slip at every mass.
    let k_c0 = (B - A) * W / D0;
    assert!(rel(k_c0, 4e5) < 1e-12);
    let (code, err) = hopf(&["--param", "M"]);
    assert_eq!(code, 3, "{err}");
    assert!(
        err.contains(
            "no stick-slip onset in M from 5.000000e-3 to 5.000000e3 kg, nor at any other value: \
             steady sliding is unstable (stick-slip) at every M: K = 2.000000e5 N/m is at or \
             below K_c = 4.000000e5 N/m at M = 0 (C12), and K_c grows with M"
        ),
        "{err}"
    );
    assert!(!err.contains("search another range"), "{err}");
    // Velocity strengthening (B < A): stable at every mass.
    let (code, err) = hopf(&["--param", "M", "--set", "B=0.005"]);
    assert_eq!(code, 3, "{err}");
    assert!(
        err.contains(
            "steady sliding is linearly stable at every M: steady friction is velocity \
                      strengthening (mu_phi - mu_v = -5.000000e-3"
        ),
        "{err}"
    );
    assert!(!err.contains("search another range"), "{err}");
    // The load: K_c grows with W from (B - A) M V^2 / (A D0^2) as W -> 0,
    // 4e6 N/m with M = 1e9 kg, above K.
    let (code, err) = hopf(&["--param", "W", "--set", "M=1e9"]);
    assert_eq!(code, 3, "{err}");
    let k_c_w0 = (B - A) * 1e9 * 1e-12 / (A * D0 * D0);
    assert!(rel(k_c_w0, 4e6) < 1e-12);
    assert!(
        err.contains(
            "unstable (stick-slip) at every W: K = 2.000000e5 N/m is at or below K_c = \
                      4.000000e6 N/m as W -> 0"
        ),
        "{err}"
    );
    // The velocity with mu2 = 0: mu_phi = B at every V, and K_c grows with
    // V from (B - A) W / D0.
    let (code, err) = hopf(&["--param", "V", "--set", "mu2=0"]);
    assert_eq!(code, 3, "{err}");
    assert!(
        err.contains(
            "unstable (stick-slip) at every V: K = 2.000000e5 N/m is at or below K_c = \
                      4.000000e5 N/m as V -> 0"
        ),
        "{err}"
    );
    // With K = 5e5 N/m above that least K_c the rig's inertia brings the
    // onset, at V = sqrt((K/K_c0 - 1) A / m) V0 = 2236.07 µm/s (C11),
    // beyond the scene's V_range: the advice to search another range
    // stands, and that range holds it.
    let (code, err) = hopf(&["--param", "V", "--set", "mu2=0", "--set", "K=5e5"]);
    assert_eq!(code, 3, "{err}");
    assert!(
        err.contains("search another range with --from and --to (µm/s)"),
        "{err}"
    );
    let (code, out, err) = stickslip(&[
        "hopf",
        "--scene",
        s(&path),
        "--param",
        "V",
        "--set",
        "mu2=0",
        "--set",
        "K=5e5",
        "--to",
        "1e4",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let m = M * 1e-12 / (W * D0);
    let v_c = ((5e5 / k_c0 - 1.0) * A / m).sqrt();
    let found = num(&json(&out)["critical"]["value"]);
    assert!(rel(found, v_c) < 1e-9, "{found} vs {v_c} µm/s");
}

/// A pair diagram (V, M) of the granite rig judges the scene's own
/// operating point as `hopf` does: K = 2e5 N/m against K_c of C11 at its
/// V = 1 µm/s, M = 5 kg (mu_v = A, mu_phi = B - 2 mu2 ln nu = B at nu = 1,
/// so K_c = (B - A) W / D0 (1 + m / A) = 4.0e5 N/m): stick-slip, in the
/// text and the JSON.
#[test]
fn a_pair_diagram_gives_the_operating_points_regime() {
    let (dir, path) = scene("pair", common::GRANITE);
    let m = M * 1e-12 / (W * D0); // M V0^2 / (W D0), V0 = 1 µm/s
    let k_c = (B - A) * W / D0 * (1.0 + m / A);
    assert!(K < k_c, "{K} {k_c}");
    let out = dir.join("out");
    let args = [
        "diagram",
        "--scene",
        s(&path),
        "--x",
        "V",
        "--y",
        "M",
        "--out",
        s(&out),
        "--force",
    ];
    let (code, text, err) = stickslip(&args);
    assert_eq!(code, 0, "{err}");
    assert!(
        text.contains("M = 5.0000 kg: stick-slip (K < K_c"),
        "{text}"
    );
    let (code, stdout, err) = stickslip(&[&args[..], &["--json"]].concat());
    assert_eq!(code, 0, "{err}");
    let j = json(&stdout);
    let j = if j.is_array() { j[0].clone() } else { j };
    assert_eq!(j["operating_point"]["regime"], "stick-slip");
    let _ = std::fs::remove_dir_all(&dir);
}
