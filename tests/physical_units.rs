//! The experimenter's units (issue 24): `--set` takes the scene's keys in
//! their physical units, `cycles --at` takes a stiffness in N/m or 1/m,
//! the CSV columns say their units, and `hopf` places the rig's own
//! stiffness against the onset. Every number is checked against one
//! computed here from the scene's numbers (docs/model.md: `kappa = K D0 /
//! W`, `m = M V0^2 / (W D0)`, `nu = V / V0`; Appendix C, C12).

mod common;

use common::{stickslip, temp_dir};
use serde_json::Value;
use std::path::Path;

/// A press-loaded PMMA rig, as the issue's user wrote it: `W` given (not
/// `M g`), `K = 2e5 N/m`.
const RIG: &str = r#"
name = "rig"
description = "press-loaded PMMA rig"
A = 0.012
B = 0.023
mu0 = 0.5
mu2 = 1e-3
D0 = 0.4
V0 = 1.0
M = 1.0
W = 300.0
K = 2e5
V = 1.0
V_range = [0.1, 100.0]
"#;

/// The rig's numbers in SI: `D0` [m], `V0` [m/s], `M` [kg], `W` [N], `K` [N/m].
const D0: f64 = 0.4e-6;
const V0: f64 = 1e-6;
const MASS: f64 = 1.0;
const LOAD: f64 = 300.0;
const K: f64 = 2e5;

/// The pmma scene's load `W = M g` [N] and memory length `D0` [m].
const PMMA_W: f64 = 9.81;
const PMMA_D0: f64 = 0.4e-6;

fn rig(dir: &Path) -> String {
    let path = dir.join("rig.toml");
    std::fs::write(&path, RIG).unwrap();
    path.to_str().unwrap().to_string()
}

fn json(text: &str) -> Value {
    serde_json::from_str(text).unwrap_or_else(|e| panic!("{e}: {text}"))
}

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

fn rel(a: f64, b: f64) -> f64 {
    ((a - b) / b).abs()
}

/// `hopf --json` with `args`, exit status 0.
fn hopf(args: &[&str]) -> Value {
    let mut full = vec!["hopf", "--json"];
    full.extend(args);
    let (code, text, err) = stickslip(&full);
    assert_eq!(code, 0, "{full:?}: {err}");
    json(&text)
}

/// A CSV's header and rows (comment lines skipped).
fn csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{path:?}: {e}"));
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let split = |l: &str| l.split(',').map(str::to_string).collect::<Vec<_>>();
    let header = split(lines.next().unwrap());
    (header, lines.map(split).collect())
}

/// The column `name` of `rows` as numbers.
fn column(header: &[String], rows: &[Vec<String>], name: &str) -> Vec<f64> {
    let i = header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name} in {header:?}"));
    rows.iter().map(|r| r[i].parse().unwrap()).collect()
}

/// `--set K` and `--set W` go through the scene: kappa = K D0/W and
/// m = M V0^2/(W D0) with the scene's other numbers; `W` changes both.
#[test]
fn physical_overrides_give_the_dimensionless_parameters_of_the_scene() {
    let dir = temp_dir("units-set");
    let scene = rig(&dir);
    // The scene's own K, then --set K.
    let h = hopf(&["--scene", &scene]);
    let op = &h["operating_point"];
    assert!(rel(f(&op["kappa"]), K * D0 / LOAD) < 1e-15, "{op}");
    let h = hopf(&["--scene", &scene, "--set", "K=3.5e5"]);
    let op = &h["operating_point"];
    assert!(rel(f(&op["kappa"]), 3.5e5 * D0 / LOAD) < 1e-15, "{op}");
    assert!(rel(f(&op["K_N_per_m"]), 3.5e5) < 1e-15, "{op}");
    // --set W: kappa with the scene's K, and m (inertial model keeps it).
    let h = hopf(&["--scene", &scene, "--set", "W=600", "--model", "inertial"]);
    assert!(rel(f(&h["operating_point"]["kappa"]), K * D0 / 600.0) < 1e-15);
    let m = f(&h["params"]["m"]);
    assert!(rel(m, MASS * V0 * V0 / (600.0 * D0)) < 1e-15, "m = {m}");
    // Physical results use the new load: K_c = kappa_c W / D0.
    let kc = f(&h["kappa_c"]);
    assert!(rel(f(&h["physical"]["K_N_per_m"]), kc * 600.0 / D0) < 1e-14);
    // --set M with W given: only m changes.
    let h = hopf(&["--scene", &scene, "--set", "M=4", "--model", "inertial"]);
    assert!(rel(f(&h["params"]["m"]), 4.0 * V0 * V0 / (LOAD * D0)) < 1e-15);
    assert!(rel(f(&h["operating_point"]["kappa"]), K * D0 / LOAD) < 1e-15);
    // --set D0 and V0 (µm, µm/s) change kappa, nu, m together.
    let h = hopf(&[
        "--scene", &scene, "--set", "D0=0.8", "--set", "V0=2", "--model", "inertial",
    ]);
    let (d0, v0) = (0.8e-6, 2e-6);
    assert!(rel(f(&h["operating_point"]["kappa"]), K * d0 / LOAD) < 1e-15);
    assert!(rel(f(&h["params"]["nu"]), 1e-6 / v0) < 1e-15);
    assert!(rel(f(&h["params"]["m"]), MASS * v0 * v0 / (LOAD * d0)) < 1e-15);
    // tau (s) selects the cutoff form: theta_c = tau V0 / D0 (mu2 dropped).
    let h = hopf(&["--scene", &scene, "--set", "tau=0.01"]);
    assert!(rel(f(&h["params"]["theta_c"]), 0.01 * V0 / D0) < 1e-15);
    assert!(h["params"].get("mu2").is_none(), "{}", h["params"]);
    let _ = std::fs::remove_dir_all(&dir);
}

/// A physical override and the equivalent dimensionless one give the same
/// numbers: `V` and `nu` exactly (V0 = 1 µm/s); `W` and the `m` it implies
/// to rounding; `K` and `kappa` the same time series, digit for digit.
#[test]
fn physical_and_dimensionless_overrides_agree() {
    let a = hopf(&["--set", "V=3"]);
    let b = hopf(&["--set", "nu=3"]);
    for field in ["kappa_c", "omega_c", "l1"] {
        assert_eq!(a[field], b[field], "{field}");
    }
    // pmma: M = 1 kg, W = M g; with W = 50 N, m = M V0^2 / (W D0).
    let m = MASS * V0 * V0 / (50.0 * PMMA_D0);
    let a = hopf(&["--set", "W=50", "--set", "nu=3", "--model", "inertial"]);
    let b = hopf(&[
        "--set",
        &format!("m={m}"),
        "--set",
        "nu=3",
        "--model",
        "inertial",
    ]);
    for field in ["kappa_c", "omega_c"] {
        assert!(rel(f(&a[field]), f(&b[field])) < 1e-14, "{field}: {a} {b}");
    }
    // The spring in N/m against kappa = K D0 / W computed here, written in
    // its shortest exact spelling: the same simulation to the last digit.
    let dir = temp_dir("units-simulate");
    let out = dir.to_str().unwrap();
    let k = 2.4e5;
    let kappa = k * PMMA_D0 / PMMA_W;
    let run = |set: &str, name: &str| {
        let (code, _, err) = stickslip(&[
            "simulate",
            "--set",
            set,
            "--protocol",
            "1:100",
            "--out",
            out,
            "--name",
            name,
        ]);
        assert_eq!(code, 0, "{set}: {err}");
        std::fs::read_to_string(dir.join(format!("{name}-simulation.csv"))).unwrap()
    };
    let physical = run(&format!("K={k}"), "physical");
    let dimensionless = run(&format!("kappa={kappa}"), "dimensionless");
    assert!(physical.lines().count() > 50);
    assert_eq!(physical, dimensionless);
    let _ = std::fs::remove_dir_all(&dir);
}

/// One quantity both ways is refused naming both; unknown names list both
/// kinds; bad values name the field (exit status 2, no panic).
#[test]
fn bad_overrides_are_refused_naming_the_field() {
    for (set, says) in [
        (
            vec!["K=2e5", "kappa=0.01"],
            vec!["--set K and --set kappa both set kappa"],
        ),
        (vec!["m=0.1", "M=2"], vec!["--set m and --set M both set m"]),
        (
            vec!["V=10", "nu=3"],
            vec!["--set V and --set nu both set nu"],
        ),
        (
            vec!["tau=1e-3", "theta_c=1"],
            vec!["--set tau and --set theta_c both set theta_c"],
        ),
        (
            vec!["tau=1e-3", "mu2=1e-4"],
            vec!["--set tau and --set mu2 select different ageing forms"],
        ),
        (
            vec!["Kappa=1"],
            vec![
                "unknown parameter 'Kappa'",
                "kappa, nu, m, A, B, mu0, mu2, theta_c",
                "K [N/m], M [kg], W [N], V [µm/s], V0 [µm/s], D0 [µm], tau [s], g [m/s^2]",
            ],
        ),
        (
            vec!["M=-1"],
            vec!["--set M = -1 is out of range: expected a finite number >= 0 (kg"],
        ),
        (
            vec!["W=0"],
            vec!["--set W = 0 is out of range: expected a finite number > 0 (N"],
        ),
        (vec!["D0=nan"], vec!["--set D0 = NaN is out of range"]),
        (vec!["K=stiff"], vec!["--set K: cannot read 'stiff'"]),
        (vec!["g=-9.81"], vec!["--set g = -9.81 is out of range"]),
        (
            vec!["V_range=10:1"],
            vec!["--set V_range (HI) = 1 is out of range"],
        ),
        // pmma's load is its weight: no mass, no load.
        (vec!["M=0"], vec!["--set M=0", "give the load W"]),
        (vec!["V=1e300"], vec!["nu = V / V0"]),
    ] {
        let mut args = vec!["hopf"];
        for s in &set {
            args.extend(["--set", s]);
        }
        let (code, _, err) = stickslip(&args);
        assert_eq!(code, 2, "{set:?}: {err}");
        for s in says {
            assert!(err.contains(s), "{set:?}: {err}");
        }
    }
    // Every command takes them.
    let dir = temp_dir("units-commands");
    let out = dir.to_str().unwrap();
    for args in [
        vec!["branch", "--param", "kappa", "--set", "W=-3"],
        vec!["diagram", "--set", "W=-3", "--out", out],
        vec!["cycles", "--set", "W=-3", "--out", out],
        vec!["simulate", "--set", "W=-3", "--out", out],
    ] {
        let (code, _, err) = stickslip(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(
            err.contains("--set W = -3 is out of range"),
            "{args:?}: {err}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Run names: a physical override names its unit (never the file of a
/// dimensionless one, also where file names ignore case), in one spelling.
#[test]
fn run_names_of_physical_overrides_are_stable_and_distinct() {
    let dir = temp_dir("units-names");
    let out = dir.to_str().unwrap();
    let run = |set: &[&str]| {
        let mut args = vec!["simulate", "--protocol", "1:20", "--out", out];
        for s in set {
            args.extend(["--set", s]);
        }
        stickslip(&args)
    };
    let (code, _, err) = run(&["K=2.4e5"]);
    assert_eq!(code, 0, "{err}");
    assert!(dir.join("pmma_K_N_per_m=2.4e5-simulation.csv").exists());
    // The same run however the number is written: refused without --force.
    let (code, _, err) = run(&["K=240000.0"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("pmma_K_N_per_m=2.4e5-simulation.csv exists"),
        "{err}"
    );
    // M (kg) and m (dimensionless) name different runs.
    let (code, _, err) = run(&["M=2", "kappa=0.009"]);
    assert_eq!(code, 0, "{err}");
    let (code, _, err) = run(&["m=2", "kappa=0.009"]);
    assert_eq!(code, 0, "{err}");
    for name in [
        "pmma_M_kg=2_kappa=0.009-simulation.csv",
        "pmma_kappa=0.009_m=2-simulation.csv",
    ] {
        assert!(dir.join(name).exists(), "{name}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `cycles --at K=...` and `--at K_over_W=...` deliver the cycle at
/// `kappa = K D0 / W` (`(K/W) D0`), the same as `--at-kappa` at that
/// value; `--at kappa=` equals `--at-kappa`; a value asked twice in two
/// units is reported once; each requested point says how it was asked.
#[test]
fn cycles_at_a_stiffness_in_any_unit() {
    let dir = temp_dir("units-at");
    let out = dir.to_str().unwrap();
    let cycles = |extra: &[&str], name: &str| {
        let mut args = vec![
            "cycles",
            "--kappa-fraction",
            "0.99",
            "--json",
            "--out",
            out,
            "--name",
            name,
        ];
        args.extend(extra);
        let (code, text, err) = stickslip(&args);
        assert_eq!(code, 0, "{extra:?}: {err}");
        json(&text)
    };
    let k = 2.68e5;
    let kappa = k * PMMA_D0 / PMMA_W;
    let k_over_w = 2.74e4;
    let physical = cycles(
        &[
            "--at",
            &format!("K={k},{k}"),
            "--at",
            &format!("K_over_W={k_over_w}"),
            "--at-kappa",
            &format!("{kappa}"),
        ],
        "physical",
    );
    let requested = physical["requested_points"].as_array().unwrap();
    // --at-kappa first, then --at: K equals it (once), K_over_W.
    assert_eq!(requested.len(), 2, "{requested:?}");
    assert_eq!(requested[0]["asked"]["name"], "kappa");
    assert_eq!(requested[1]["asked"]["name"], "K_over_W");
    assert_eq!(requested[1]["asked"]["unit"], "1/m");
    assert_eq!(f(&requested[1]["asked"]["value"]), k_over_w);
    assert!(rel(f(&requested[1]["kappa"]), k_over_w * PMMA_D0) < 1e-15);
    for r in requested {
        assert_eq!(r["delivered"], true, "{r}");
        let kappa = f(&r["kappa"]);
        assert!(rel(f(&r["K_N_per_m"]), kappa * PMMA_W / PMMA_D0) < 1e-15);
        assert!(rel(f(&r["K_over_W_per_m"]), kappa / PMMA_D0) < 1e-15);
    }
    let only_k = cycles(&["--at", &format!("K={k}")], "only-k");
    let r = &only_k["requested_points"][0];
    assert_eq!(r["asked"]["name"], "K");
    assert_eq!(r["asked"]["unit"], "N/m");
    assert_eq!(f(&r["asked"]["value"]), k);
    assert!(rel(f(&r["kappa"]), kappa) < 1e-15, "{r}");
    // The cycle there, against --at-kappa and --at kappa=: the same numbers.
    let user_cycle = |v: &Value| -> Value {
        v["cycles"]
            .as_array()
            .unwrap()
            .iter()
            .find(|c| c["user_point"] == true)
            .cloned()
            .unwrap()
    };
    let by_kappa = cycles(&["--at-kappa", &format!("{kappa}")], "by-kappa");
    let by_at_kappa = cycles(&["--at", &format!("kappa={kappa}")], "by-at-kappa");
    let (a, b, c) = (
        user_cycle(&only_k),
        user_cycle(&by_kappa),
        user_cycle(&by_at_kappa),
    );
    assert_eq!(b, c);
    for field in ["kappa", "period", "delta_s", "v_max"] {
        assert!(rel(f(&a[field]), f(&b[field])) < 1e-12, "{field}: {a} {b}");
    }
    assert_eq!(
        by_kappa["requested_points"],
        by_at_kappa["requested_points"]
    );
    // Bad requests name the option.
    for (at, says) in [
        ("k=1", "unknown --at stiffness 'k'"),
        ("K=-1", "--at K = -1 is out of range"),
        ("K_over_W=x", "--at K_over_W: cannot read 'x'"),
        ("1e5", "--at: cannot read '1e5'"),
    ] {
        let (code, _, err) = stickslip(&["cycles", "--at", at, "--out", out]);
        assert_eq!(code, 2, "{at}: {err}");
        assert!(err.contains(says), "{at}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
    let (_, _, err) = stickslip(&["cycles", "--at", "k=1", "--out", out]);
    assert!(err.contains("kappa [1], K [N/m], K_over_W [1/m]"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Every CSV column is dimensionless (docs/model.md's names) or says its
/// unit; the physical columns are the dimensionless ones times the scene's
/// scales, and the columns written before come first, in their order.
#[test]
fn csv_columns_carry_units() {
    let dir = temp_dir("units-csv");
    let out = dir.to_str().unwrap();
    let units = [
        "_s", "_N", "_per_m", "_per_s", "_um", "_hz", "_per_s2", "_N_per_m",
    ];
    let dimensionless = [
        "t",
        "s",
        "v",
        "theta",
        "slip",
        "log10_v",
        // log10 of the slowest slip velocity in units of V0 (cycles).
        "log10_v_min",
        "model",
        "kappa",
        "nu",
        "period",
        "delta_s",
        "s_min",
        "s_max",
        "v_min",
        "v_max",
        "stable",
        "trivial_multiplier_error",
        "error_estimate",
        "ntst",
        "user_point",
        "inertial_imbalance",
        "m",
        "friction_min",
        "direct_effect_min",
        "omega",
        "l1",
        "criticality",
        "kappa_appendix_c",
        "l1_error_bound",
        "omega_appendix_c",
        "curve",
        "n_unstable",
        "event",
        // The cycle's label in the run (a count, restarts name it).
        "label",
    ];
    let check = |header: &[String]| {
        for h in header {
            let ok = dimensionless.contains(&h.as_str())
                || h.starts_with("eig_")
                || units.iter().any(|u| h.ends_with(u));
            assert!(ok, "column {h} names no unit");
        }
    };
    // simulate: time, force, velocity, slip in physical units.
    let (code, _, err) = stickslip(&[
        "simulate",
        "--set",
        "kappa=0.009",
        "--protocol",
        "1:100",
        "--out",
        out,
    ]);
    assert_eq!(code, 0, "{err}");
    let (header, rows) = csv(&dir.join("pmma_kappa=0.009-simulation.csv"));
    check(&header);
    assert_eq!(
        header[..8].join(","),
        "t_s,t,s,v,theta,slip,log10_v,model",
        "the columns simulate has always written, first"
    );
    let col = |name: &str| column(&header, &rows, name);
    let pairs = [
        ("s", "spring_force_N", PMMA_W),
        ("v", "v_um_per_s", 1.0),
        ("slip", "slip_um", 0.4),
        ("theta", "theta_s", PMMA_D0 / V0),
        ("t", "t_s", PMMA_D0 / V0),
    ];
    for (dimensionless, physical, scale) in pairs {
        for (x, y) in col(dimensionless).iter().zip(col(physical)) {
            assert!(
                (y - x * scale).abs() <= 1e-11 * (x * scale).abs() + 1e-300,
                "{physical} = {y} vs {dimensionless} = {x} times {scale}"
            );
        }
    }
    // cycles: the force drop in N, the stiffness in N/m.
    let (code, _, err) = stickslip(&["cycles", "--kappa-fraction", "0.95", "--out", out]);
    assert_eq!(code, 0, "{err}");
    let (header, rows) = csv(&dir.join("pmma-cycles.csv"));
    check(&header);
    assert!(header.len() > 20);
    let col = |name: &str| column(&header, &rows, name);
    for (x, y) in col("delta_s").iter().zip(col("delta_s_N")) {
        assert!(rel(y, x * PMMA_W) < 1e-14, "{y} vs {x}");
    }
    for (x, y) in col("kappa").iter().zip(col("K_N_per_m")) {
        assert!(rel(y, x * PMMA_W / PMMA_D0) < 1e-14, "{y} vs {x}");
    }
    // The Hopf curve of the diagram and the branch.
    let (code, _, err) = stickslip(&["diagram", "--nu-range", "1:3", "--out", out]);
    assert_eq!(code, 0, "{err}");
    let (header, rows) = csv(&dir.join("pmma-hopf-curve.csv"));
    check(&header);
    for (x, y) in column(&header, &rows, "kappa")
        .iter()
        .zip(column(&header, &rows, "K_N_per_m"))
    {
        assert!(rel(y, x * PMMA_W / PMMA_D0) < 1e-14);
    }
    let mut branch = common::VELOCITY_BRANCH.to_vec();
    branch.push("--csv");
    let (code, text, err) = stickslip(&branch);
    assert_eq!(code, 0, "{err}");
    let path = dir.join("branch.csv");
    std::fs::write(&path, text).unwrap();
    let (header, rows) = csv(&path);
    check(&header);
    for (x, y) in column(&header, &rows, "s")
        .iter()
        .zip(column(&header, &rows, "spring_force_N"))
    {
        assert!(rel(y, x * PMMA_W) < 1e-14);
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `hopf` places the scene's K against K_c of Appendix C (C12, computed
/// here): below it stick-slip, above it with a supercritical onset steady;
/// within rounding of K_c, with a subcritical onset, without an onset, or
/// within the shift of dropped inertia, undecided with the reason.
#[test]
fn hopf_places_the_operating_point() {
    let dir = temp_dir("units-operating");
    let scene = rig(&dir);
    // C12 at nu = 1: kappa_c = mu_phi - mu_v = B - A (the ln² term silent).
    let kappa_c = 0.023 - 0.012;
    let k_c = kappa_c * LOAD / D0;
    let h = hopf(&["--scene", &scene]);
    let op = &h["operating_point"];
    assert_eq!(op["regime"], "stick-slip", "{op}");
    assert!(rel(f(&op["K_N_per_m"]), K) < 1e-15, "{op}");
    assert!((f(&op["margin"]) - (K - k_c) / k_c).abs() < 1e-12, "{op}");
    let (_, text, _) = stickslip(&["hopf", "--scene", &scene]);
    let line = text
        .lines()
        .find(|l| l.starts_with("operating point:"))
        .unwrap();
    assert!(
        line.starts_with(
            "operating point: K = 2.000000e5 N/m, (K - K_c)/K_c = -9.758e-1: stick-slip"
        ),
        "{line}"
    );
    // Above K_c, supercritical (as this scene's onset is).
    assert_eq!(h["criticality"], "supercritical");
    let h = hopf(&["--scene", &scene, "--set", "K=9e6"]);
    assert_eq!(h["operating_point"]["regime"], "steady");
    assert!((f(&h["operating_point"]["margin"]) - (9e6 - k_c) / k_c).abs() < 1e-12);
    // At K_c to rounding: undecided, never a side.
    let h = hopf(&["--scene", &scene, "--set", &format!("kappa={kappa_c}")]);
    let op = &h["operating_point"];
    assert_eq!(op["regime"], "undecided", "{op}");
    assert!(f(&op["margin"]).abs() <= 1e-12, "{op}");
    assert!(op["reason"].as_str().unwrap().contains("rounding"), "{op}");
    // Subcritical (pmma-rr: the inertia decides): the fold is not located.
    let h = hopf(&["--scene", "pmma-rr", "--set", "K=3e5"]);
    assert_eq!(h["criticality"], "subcritical");
    let op = &h["operating_point"];
    assert_eq!(op["regime"], "undecided", "{op}");
    assert!(
        op["reason"].as_str().unwrap().contains("fold of cycles"),
        "{op}"
    );
    // No onset (brockley, velocity strengthening): no margin.
    let h = hopf(&["--scene", "brockley", "--set", "K=3e5"]);
    assert_eq!(h["operating_point"]["regime"], "undecided");
    assert!(h["operating_point"]["margin"].is_null());
    // Just above the quasi-static K_c, within the shift of dropped inertia.
    let h = hopf(&[
        "--set",
        "kappa=0.011005",
        "--set",
        "m=1e-4",
        "--model",
        "quasi-static",
    ]);
    let op = &h["operating_point"];
    assert_eq!(op["regime"], "undecided", "{op}");
    assert!(op["reason"].as_str().unwrap().contains("--model inertial"));
    // The inertial model decides it: 0.011005 < 0.011 (1 + 1e-4/0.012).
    let h = hopf(&["--set", "kappa=0.011005", "--set", "m=1e-4"]);
    assert_eq!(h["operating_point"]["regime"], "stick-slip");
    // No K: no operating point.
    assert!(hopf(&[])["operating_point"].is_null());
    let _ = std::fs::remove_dir_all(&dir);
}

/// One spelling of the micrometre in every human-readable output: `µm/s`
/// and `µm` in texts, messages, help, CSV comment lines and figures (as the
/// README and docs write them), never `um/s` or `um`; the CSV column names
/// and JSON field names keep their ASCII `um_per_s`.
#[test]
fn the_micrometre_is_spelt_one_way_in_human_readable_outputs() {
    let dir = common::temp_dir("micrometre");
    let out = dir.to_str().unwrap();
    let runs: Vec<Vec<&str>> = vec![
        vec!["hopf"],
        vec!["hopf", "--set", "K=4e5", "--param", "V", "--to", "1000"],
        vec!["hopf", "--scene", "gel"],
        vec![
            "branch",
            "--param",
            "nu",
            "--set",
            "kappa=0.0105",
            "--units",
            "physical",
        ],
        vec!["branch", "--scene", "gel", "--param", "V"],
        vec!["diagram", "--out", out],
        vec!["diagram", "--scene", "gel", "--out", out],
        vec![
            "cycles",
            "--set",
            "K=4e5",
            "--param",
            "V",
            "--to",
            "300",
            "--search",
            "1:1000",
            "--max-steps",
            "15",
            "--out",
            out,
        ],
        vec![
            "simulate",
            "--set",
            "kappa=0.009",
            "--protocol",
            "1:30",
            "--out",
            out,
        ],
        vec!["simulate", "--scene", "gel", "--out", out],
        vec![
            "fit",
            "--data",
            "steady=examples/data/pmma-steady.csv",
            "--data",
            "onset=examples/data/pmma-onset.csv",
            "--out",
            out,
        ],
        vec![
            "fit",
            "--scene",
            "gel",
            "--data",
            "steady=examples/data/gel-steady.csv",
            "--out",
            out,
        ],
        vec!["hopf", "--set", "V_range=3"],
        vec!["hopf", "--set", "D0=abc"],
        vec!["hopf", "--scene", "gel", "--set", "V=abc"],
        vec!["simulate", "--protocol", "x", "--out", out],
        vec!["cycles", "--param", "V", "--out", out],
        vec!["hopf", "--param", "V", "--from", "1e-6", "--to", "1e-5"],
        vec!["hopf", "--help"],
        vec!["cycles", "--help"],
        vec!["simulate", "--help"],
        vec!["branch", "--help"],
    ];
    let ascii = |text: &str| {
        text.split(|c: char| !(c.is_alphanumeric() || c == '/' || c == '_'))
            .any(|w| w == "um/s" || w == "um")
    };
    let mut micro = 0;
    for args in &runs {
        let (_, stdout, stderr) = common::stickslip(args);
        for text in [&stdout, &stderr] {
            assert!(!ascii(text), "{args:?}: {text}");
            micro += text.matches('µ').count();
        }
    }
    assert!(micro > 50, "{micro}");
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.to_str().unwrap().to_string();
        let text = std::fs::read_to_string(&path).unwrap_or_default();
        if name.ends_with(".svg") {
            assert!(!ascii(&text), "{name}");
        } else if name.ends_with(".csv") {
            for line in text.lines().filter(|l| l.starts_with('#')) {
                assert!(!ascii(line), "{name}: {line}");
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}
