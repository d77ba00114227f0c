//! `diagram --x P --y Q` (issue 24): the Hopf curve in a pair of control
//! parameters, each point checked by two independent methods:
//!
//! * Appendix C's closed form (C11, exact for this model at any inertia,
//!   docs/model.md), `kappa_c(nu, m) = (mu_phi - mu_v)(1 + m nu^2 / mu_v)`
//!   with `mu_v = A`, `mu_phi = B - 2 mu2 ln nu`, solved here for the
//!   plotted parameter: the critical mass `M_c = K D0 / (g kappa_c)` (W = M
//!   g), the critical load `W_c = K D0 / c - M V^2 / (D0 A)` (`c = mu_phi -
//!   A`), the critical `B`;
//! * `hopf --param Q` with the curve's `P` set by `--set` (a one-parameter
//!   onset, located by another path through the code).
//!
//! Also: the default diagram's JSON fields and CSV columns are those of
//! before, and bad `--x`/`--y` are typed errors naming the field.

mod common;

use common::{stickslip, temp_dir};
use serde_json::Value;
use std::path::{Path, PathBuf};

const A: f64 = 0.012;
const B: f64 = 0.023;
const MU2: f64 = 1e-3;
/// Memory length and reference velocity [m], [m/s].
const D0: f64 = 0.4e-6;
const V0: f64 = 1e-6;
const K: f64 = 2e5;
const M: f64 = 1.0;
const W: f64 = 300.0;
const G: f64 = 9.81;
/// The motor's velocity [µm/s].
const V: f64 = 10.0;

/// Issue 24's rig with its load its weight (`W = M g`).
const WEIGHED: &str = r#"
name = "rigw"
description = "PMMA rig, load its weight"
A = 0.012
B = 0.023
mu0 = 0.6
mu2 = 1e-3
D0 = 0.4
V0 = 1.0
K = 2e5
M = 1.0
V = 10.0
V_range = [0.1, 100.0]
"#;

/// The same rig under a press (`W = 300 N`).
fn pressed() -> String {
    WEIGHED
        .replace("M = 1.0\n", "M = 1.0\nW = 300.0\n")
        .replace("rigw", "rigp")
}

fn scene(name: &str, text: &str) -> (PathBuf, PathBuf) {
    let dir = temp_dir(&format!("axes-{name}"));
    let path = dir.join(format!("{name}.toml"));
    std::fs::write(&path, text).unwrap();
    (dir, path)
}

fn json(out: &str) -> Value {
    serde_json::from_str(out).unwrap_or_else(|e| panic!("{e}: {out}"))
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// `c = mu_phi - mu_v` at `nu`.
fn weakening(nu: f64, a: f64, b: f64) -> f64 {
    b - 2.0 * MU2 * nu.ln() - a
}

/// `diagram --json` with `args`, exit 0, its JSON (no NaN written as null).
fn diagram(path: &Path, dir: &Path, args: &[&str]) -> Value {
    let p = path.to_str().unwrap();
    let d = dir.to_str().unwrap();
    let mut all = vec!["diagram", "--scene", p, "--out", d, "--force", "--json"];
    all.extend(args);
    let (code, out, err) = stickslip(&all);
    assert_eq!(code, 0, "{all:?}: {err}");
    assert!(!out.contains("null") && !out.contains("NaN"), "{out}");
    json(&out)
}

/// `hopf --param Q --set P=x --json`: the critical value of `Q`.
fn hopf_in(path: &Path, q: &str, set: &str, extra: &[&str]) -> f64 {
    let p = path.to_str().unwrap();
    let mut all = vec!["hopf", "--scene", p, "--param", q, "--set", set, "--json"];
    all.extend(extra);
    let (code, out, err) = stickslip(&all);
    assert_eq!(code, 0, "{all:?}: {err}");
    json(&out)["critical"]["value"].as_f64().unwrap()
}

/// The curve's points as `(x, y, point)`, checking the named columns.
fn points<'a>(d: &'a Value, cx: &str, cy: &str) -> Vec<(f64, f64, &'a Value)> {
    assert_eq!(d["x"]["column"], cx);
    assert_eq!(d["y"]["column"], cy);
    let pts: Vec<_> = d["hopf_curve"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| {
            let (x, y) = (p[cx].as_f64().unwrap(), p[cy].as_f64().unwrap());
            assert_eq!((x, y), (p["x"].as_f64().unwrap(), p["y"].as_f64().unwrap()));
            (x, y, p)
        })
        .collect();
    assert!(pts.len() > 20, "{} points", pts.len());
    assert_eq!(d["complete"], true, "{}", d["stop"]);
    pts
}

/// Three points inside the curve (a quarter, half, three quarters along).
fn inner<T: Copy>(pts: &[T]) -> [T; 3] {
    let n = pts.len();
    [pts[n / 4], pts[n / 2], pts[3 * n / 4]]
}

#[test]
fn critical_mass_against_velocity_with_the_load_its_weight() {
    let (dir, path) = scene("rigw", WEIGHED);
    let d = diagram(
        &path,
        &dir,
        &["--x", "V", "--y", "M", "--model", "inertial"],
    );
    let pts = points(&d, "x_V_um_per_s", "y_M_kg");
    // m = M V0^2 / (W D0) = V0^2 / (g D0) with W = M g.
    let m = V0 * V0 / (G * D0);
    let mut worst: f64 = 0.0;
    for &(v, mc, _) in &pts {
        let nu = v * 1e-6 / V0;
        let kappa_c = weakening(nu, A, B) * (1.0 + m * nu * nu / A);
        worst = worst.max(rel(mc, K * D0 / (G * kappa_c)));
    }
    eprintln!(
        "M_c against K D0/(g kappa_c): worst {worst:.1e} over {} points",
        pts.len()
    );
    assert!(worst < 1e-9, "M_c against K D0/(g kappa_c): {worst:e}");
    for (v, mc, _) in inner(&pts) {
        let one = hopf_in(&path, "M", &format!("V={v:.17e}"), &["--model", "inertial"]);
        eprintln!("V point: {} against hopf --param: {:.1e}", mc, rel(mc, one));
        assert!(
            rel(mc, one) < 1e-9,
            "V = {v}: {mc} against hopf --param M {one}"
        );
    }
    // More mass, less K/M: stick-slip above the curve; the scene's (V, M) marked.
    assert_eq!(d["stable_side"], "below");
    assert_eq!(d["operating_point"]["x_V_um_per_s"], V);
    assert_eq!(d["operating_point"]["y_M_kg"], M);
    assert_eq!(d["onset_type"], "supercritical");
}

#[test]
fn critical_load_against_stiffness_under_a_press() {
    let (dir, path) = scene("rigp", &pressed());
    let d = diagram(&path, &dir, &["--x", "K", "--y", "W"]);
    assert_eq!(d["model"], "inertial", "W moves m: {}", d["model_reason"]);
    // W moves kappa and m together.
    assert_eq!(d["y"]["moves"], serde_json::json!(["kappa", "m"]));
    let pts = points(&d, "x_K_N_per_m", "y_W_N");
    let nu = V * 1e-6 / V0;
    let c = weakening(nu, A, B);
    let mut worst: f64 = 0.0;
    for &(k, wc, p) in &pts {
        // K D0 / W = c (1 + M V^2 / (W D0 A)), solved for W.
        let closed = k * D0 / c - M * (V * 1e-6).powi(2) / (D0 * A);
        worst = worst.max(rel(wc, closed));
        assert!(rel(p["K_N_per_m"].as_f64().unwrap(), k) < 1e-12);
        assert!(rel(p["W_N"].as_f64().unwrap(), wc) < 1e-12);
    }
    eprintln!(
        "W_c against its closed form: worst {worst:.1e} over {} points",
        pts.len()
    );
    assert!(worst < 1e-9, "W_c against its closed form: {worst:e}");
    for (k, wc, _) in inner(&pts) {
        let one = hopf_in(&path, "W", &format!("K={k:.17e}"), &[]);
        eprintln!("K point: {} against hopf --param: {:.1e}", wc, rel(wc, one));
        assert!(
            rel(wc, one) < 1e-8,
            "K = {k}: {wc} against hopf --param W {one}"
        );
    }
    assert_eq!(d["operating_point"]["x_K_N_per_m"], K);
    assert_eq!(d["operating_point"]["y_W_N"], W);
}

#[test]
fn friction_law_pair() {
    let (dir, path) = scene("rigab", &pressed());
    let d = diagram(
        &path,
        &dir,
        &["--x", "A", "--y", "B", "--model", "inertial"],
    );
    let pts = points(&d, "x_A", "y_B");
    let nu = V * 1e-6 / V0;
    let (kappa, m) = (K * D0 / W, M * V0 * V0 / (W * D0));
    let mut worst: f64 = 0.0;
    for &(a, b, _) in &pts {
        let closed = kappa / (1.0 + m * nu * nu / a) + a + 2.0 * MU2 * nu.ln();
        worst = worst.max(rel(b, closed));
    }
    eprintln!(
        "B_c against C11 solved for B: worst {worst:.1e} over {} points",
        pts.len()
    );
    assert!(worst < 1e-9, "B_c against C11 solved for B: {worst:e}");
    for (a, b, _) in inner(&pts) {
        let one = hopf_in(&path, "B", &format!("A={a:.17e}"), &["--model", "inertial"]);
        eprintln!("A point: {} against hopf --param: {:.1e}", b, rel(b, one));
        assert!(
            rel(b, one) < 1e-8,
            "A = {a}: {b} against hopf --param B {one}"
        );
    }
    // More B, more weakening: stick-slip above.
    assert_eq!(d["stable_side"], "below");
}

/// The default diagram keeps its JSON fields and CSV columns, and writes
/// no file of a pair.
#[test]
fn default_output_unchanged() {
    let (dir, path) = scene("rigdefault", WEIGHED);
    let d = diagram(&path, &dir, &[]);
    let mut keys: Vec<&str> = d.as_object().unwrap().keys().map(String::as_str).collect();
    keys.sort();
    assert_eq!(
        keys,
        [
            "complete",
            "elapsed_s",
            "files",
            "hopf_curve",
            "lpc_complete",
            "lpc_curve",
            "lpc_gaps",
            "lpc_stops",
            "model",
            "model_reason",
            "nu_range",
            "onset_type",
            "operating_point",
            "params",
            "scene",
            "special_points",
            "stop",
            "stop_reason",
            "units",
            "velocity_strengthening"
        ]
    );
    let mut point: Vec<&str> = d["hopf_curve"][0]
        .as_object()
        .unwrap()
        .keys()
        .map(String::as_str)
        .collect();
    point.sort();
    assert_eq!(
        point,
        [
            "K_N_per_m",
            "K_over_M_per_s2",
            "K_over_W_per_m",
            "V_um_per_s",
            "criticality",
            "frequency_hz",
            "kappa",
            "kappa_appendix_c",
            "l1",
            "l1_error_bound",
            "nu",
            "omega",
            "omega_appendix_c"
        ]
    );
    let csv = std::fs::read_to_string(dir.join("rigw-hopf-curve.csv")).unwrap();
    assert_eq!(
        csv.lines().nth(1).unwrap(),
        "nu,kappa,omega,l1,criticality,kappa_appendix_c,V_um_per_s,K_over_W_per_m,\
         K_over_M_per_s2,frequency_hz,l1_error_bound,omega_appendix_c,K_N_per_m"
    );
    let files: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    assert!(!files.iter().any(|f| f.contains("-vs-")), "{files:?}");
}

/// Bad axes: typed input errors (exit 2) naming the field, never a panic.
#[test]
fn bad_axes_are_named() {
    let (dir, path) = scene("rigbad", WEIGHED);
    let p = path.to_str().unwrap();
    let d = dir.to_str().unwrap();
    let cases: [(&[&str], &str); 6] = [
        (&["--x", "Q"], "unknown --x value 'Q'"),
        (&["--y", "mass"], "unknown --y value 'mass'"),
        (&["--x", "K", "--y", "K"], "--x and --y both name K"),
        (&["--x", "kappa", "--y", "K"], "cannot vary independently"),
        // W = M g: K and M both move kappa alone.
        (&["--x", "K", "--y", "M"], "cannot vary independently"),
        (&["--x", "tau"], "--x tau"),
    ];
    for (args, words) in cases {
        let mut all = vec!["diagram", "--scene", p, "--out", d, "--force"];
        all.extend(args);
        let (code, _, err) = stickslip(&all);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(words), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
}

/// Under a press `K` and `M` move different parameters (`kappa`; `m`):
/// the critical mass `M_c = (K D0/(W c) - 1)(A/nu^2)(W D0/V0^2)` (C11 solved
/// for `m`), which exists only above `K = c W / D0`.
#[test]
fn critical_mass_against_stiffness_under_a_press() {
    let (dir, path) = scene("rigkm", &pressed());
    let d = diagram(
        &path,
        &dir,
        &["--x", "K", "--y", "M", "--x-range", "5e6:2e7"],
    );
    let pts = points(&d, "x_K_N_per_m", "y_M_kg");
    let nu = V * 1e-6 / V0;
    let c = weakening(nu, A, B);
    let mut worst: f64 = 0.0;
    for &(k, mc, _) in &pts {
        let closed = (k * D0 / (W * c) - 1.0) * (A / (nu * nu)) * (W * D0 / (V0 * V0));
        worst = worst.max(rel(mc, closed));
    }
    eprintln!(
        "M_c against C11 solved for m: worst {worst:.1e} over {} points",
        pts.len()
    );
    assert!(worst < 1e-8, "M_c against C11 solved for m: {worst:e}");
    let (k, mc, _) = inner(&pts)[0];
    let one = hopf_in(
        &path,
        "M",
        &format!("K={k:.17e}"),
        &["--from", "1", "--to", "1e6"],
    );
    eprintln!("K point: {} against hopf --param: {:.1e}", mc, rel(mc, one));
    assert!(
        rel(mc, one) < 1e-8,
        "K = {k}: {mc} against hopf --param M {one}"
    );
    // More mass, more inertia, a larger kappa_c: stick-slip above.
    assert_eq!(d["stable_side"], "below");
}
