//! Parameters and checks shared by the integration tests (each test crate
//! uses some of them).
#![allow(dead_code)]

use stickslip::analysis::cycles::CycleRecord;
use stickslip::analysis::simulate::cycle_by_integration;
use stickslip::model::ModelKind;
use stickslip::params::Params;

/// Integrates from the first sample of the collocation cycle `r` at `p` with
/// `kappa = r.kappa` (Radau IIA, rtol 1e-12; two periods of transient, then
/// the extremes of `s` over eight) and checks that the period and `Delta_s`
/// agree with the cycle's to 1e-6.
pub fn assert_reproduced_by_integration(kind: ModelKind, p: &Params, r: &CycleRecord, label: &str) {
    let mut at = *p;
    at.kappa = r.kappa;
    // The samples hold (t/T, s, ln v, ln theta).
    let [_, s, ln_v, phi] = r.samples[0];
    let start = [s, ln_v.exp(), phi.exp()];
    let (period, delta_s) =
        cycle_by_integration(kind, &at, start, 2.0 * r.period, 8.0 * r.period, 4, 1e-12).unwrap();
    assert!(
        (period / r.period - 1.0).abs() < 1e-6,
        "{label}: period {period} (simulation) vs {} (collocation)",
        r.period
    );
    assert!(
        (delta_s / r.delta_s - 1.0).abs() < 1e-6,
        "{label}: Delta_s {delta_s} (simulation) vs {} (collocation)",
        r.delta_s
    );
}

/// The PMMA multicontact interface of the seed (A = 0.012, B = 0.023,
/// `nu = 1`, `mu0 = 0.5`) with the ln² coefficient `mu2` and inertia `m`.
pub fn pmma(m: f64, mu2: f64) -> Params {
    Params {
        kappa: 0.0,
        nu: 1.0,
        m,
        a: 0.012,
        b: 0.023,
        mu0: 0.5,
        mu2,
        theta_c: None,
        state_law: Default::default(),
        mu_vv: 0.0,
        mu_vphi: 0.0,
        eta_d: 0.0,
    }
}

/// Cutoff law with V_min = 100 V0 and enough inertia (`m = 1e-3`) for a
/// subcritical onset just below V_min (a Bautin point near nu = 81.35): the
/// Brockley-type scene of the hysteresis tests, at stiffness 0.
pub fn brockley(nu: f64) -> Params {
    Params {
        kappa: 0.0,
        nu,
        m: 1e-3,
        a: 0.012,
        b: 0.023,
        mu0: 0.5,
        mu2: 0.0,
        theta_c: Some((0.023 - 0.012) / (0.012 * 100.0)),
        state_law: Default::default(),
        mu_vv: 0.0,
        mu_vphi: 0.0,
        eta_d: 0.0,
    }
}

/// `branch` across pmma's onset in velocity: `nu` from 0.5 to 10 at
/// `kappa = 0.0105` (the Hopf point at `nu = 2.8446`, eq. C11).
pub const VELOCITY_BRANCH: [&str; 9] = [
    "branch",
    "--param",
    "nu",
    "--set",
    "kappa=0.0105",
    "--from",
    "0.5",
    "--to",
    "10",
];

/// Runs the `stickslip` binary with `args`: `(exit status, stdout, stderr)`.
pub fn stickslip(args: &[&str]) -> (i32, String, String) {
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_stickslip"))
        .args(args)
        .output()
        .expect("run stickslip");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into(),
        String::from_utf8_lossy(&out.stderr).into(),
    )
}

/// A fresh output folder for one test, `stickslip-NAME-PID` under the
/// system's temporary folder (emptied if a previous run left it).
pub fn temp_dir(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("stickslip-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Normal deviates from a fixed seed (SplitMix64, Box–Muller).
pub struct Normal(pub u64);

impl Normal {
    pub fn uniform(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn next(&mut self) -> f64 {
        let (u, v) = (self.uniform().max(1e-300), self.uniform());
        (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
    }
}

/// The `reason` of each entry of a branch JSON's `leg_stops`, in order.
pub fn leg_reasons(v: &serde_json::Value) -> Vec<String> {
    v["leg_stops"]
        .as_array()
        .unwrap()
        .iter()
        .map(|l| l["reason"].as_str().unwrap().to_string())
        .collect()
}

/// A press-loaded granite rig a stranger wrote (quasi-static at its own
/// 1 µm/s, stick-slip at its K, inertial toward 1 mm/s).
#[allow(dead_code)]
pub const GRANITE: &str = r#"
name = "granite"
description = "granite/granite bare-surface rig, press loaded: K = 2e5 N/m, M = 5 kg, W = 1 kN"
A = 0.010
B = 0.014
mu0 = 0.7
mu2 = 2e-4
D0 = 10.0       # µm
V0 = 1.0        # µm/s
M = 5.0         # kg
W = 1000.0      # N
K = 2e5         # N/m
V = 1.0         # µm/s
V_range = [0.01, 1000.0]
"#;

/// A servo-loaded granite pair in double direct shear (plain Rice–Ruina,
/// no stiffness given: a branch spans the onset).
pub const SHEAR_GRANITE: &str = r#"
name = "granite"
description = "Granite/granite, plain Rice-Ruina, 5 MPa on 0.02 m^2"
A = 0.008
B = 0.012
mu0 = 0.7
D0 = 5.0
V0 = 1.0
M = 10.0
W = 1.0e5
V = 10.0
V_range = [0.1, 1000.0]
"#;

/// `stickslip ARGS`: the exit status, the JSON it printed (`null` when it
/// printed none) and its standard error.
pub fn json_of(args: &[&str]) -> (i32, serde_json::Value, String) {
    let (status, out, err) = stickslip(args);
    (
        status,
        serde_json::from_str(&out).unwrap_or(serde_json::Value::Null),
        err,
    )
}

/// `hopf --json ARGS`, which must succeed.
pub fn hopf_json(args: &[&str]) -> serde_json::Value {
    let (status, v, err) = json_of(&[&["hopf", "--json"], args].concat());
    assert_eq!(status, 0, "{args:?}: {err}");
    v
}

/// The JSON of `args` (exit 0 or 4) without what names the run (its
/// overrides) or times it: two runs of the same numbers compare equal.
pub fn run_json(args: &[&str]) -> (i32, serde_json::Value) {
    let (status, mut v, err) = json_of(args);
    assert!(status == 0 || status == 4, "{args:?}: {err}");
    let o = v.as_object_mut().unwrap();
    for key in [
        "elapsed_s",
        "source",
        "files",
        "orbits_file",
        "label",
        "name",
    ] {
        o.remove(key);
    }
    (status, v)
}

/// Every number in `v` is finite (JSON has no NaN: it would be null).
pub fn all_finite(v: &serde_json::Value, at: &str) {
    use serde_json::Value;
    match v {
        Value::Array(a) => a.iter().for_each(|x| all_finite(x, at)),
        Value::Object(o) => o
            .iter()
            .for_each(|(k, x)| all_finite(x, &format!("{at}.{k}"))),
        Value::Number(n) => assert!(n.as_f64().unwrap().is_finite(), "{at}"),
        _ => {}
    }
}

/// `hopf`'s `l1` in `v` against a high-precision reference `l1`: within
/// its own rounding bound plus 4 ulps of the reference (the reference
/// carries 30 digits, within half an ulp as an f64; the bound is an
/// estimate of rounding, good to its order), the bound below 1e-8 of `l1`.
pub fn assert_l1_matches(v: &serde_json::Value, l1: f64, label: &str) {
    let number = |k: &str| {
        v[k].as_f64()
            .unwrap_or_else(|| panic!("{label}: {k} missing"))
    };
    let (got, bound) = (number("l1"), number("l1_error_bound"));
    let allowed = bound + 4.0 * f64::EPSILON * l1.abs();
    assert!(
        (got - l1).abs() <= allowed,
        "{label}: l1 = {got} vs {l1} (bound {bound:.1e})"
    );
    assert!(bound < 1e-8 * l1.abs(), "{label}: l1 resolved");
}
