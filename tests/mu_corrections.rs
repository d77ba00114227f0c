//! Issue 27: the corrections of seed §II.D.2 in the friction law,
//! `mu_vv (ln v)^2 + mu_vphi (ln theta)(ln v)` (docs/model.md), end to end.
//!
//! - `hopf --json`'s `kappa_c` and `omega_c` are Appendix C's closed forms
//!   (C11/C12, C13) with the steady slopes `mu_v = A + (2 mu_vv - mu_vphi)
//!   ln nu`, `mu_phi = B + (mu_vphi - 2 mu2) ln nu`, written out here.
//! - `l1` against an independent 50-digit computation
//!   (docs/reference/mu_corrections_l1.py, mu_corrections_l1_out.txt).
//! - Steady friction against its formula; the quasi-static inversion
//!   round trip over a wide range, and its typed error where the law has no
//!   velocity (proptest).
//! - Both corrections 0 give what the law without them gives, bit for bit.
//! - `cycles`, `simulate` and `diagram` on a scene file with the new keys;
//!   the control `--param mu_vv`; the input errors naming the field.

mod common;

use common::{all_finite, assert_l1_matches, hopf_json, json_of, run_json, stickslip, temp_dir};
use proptest::prelude::*;
use serde_json::Value;
use stickslip::friction::{Ageing, FrictionLaw, NoSlipVelocity};

fn num(v: &Value, k: &str) -> f64 {
    v[k].as_f64()
        .unwrap_or_else(|| panic!("{k} missing in {v}"))
}

fn rel(a: f64, b: f64) -> f64 {
    (a / b - 1.0).abs()
}

/// The steady slopes of docs/model.md, `(mu_v, mu_phi)`, from the reported
/// parameters, written out here rather than taken from the library.
fn slopes(params: &Value) -> (f64, f64) {
    let g = |k: &str| num(params, k);
    let ln_nu = g("nu").ln();
    (
        g("A") + (2.0 * g("mu_vv") - g("mu_vphi")) * ln_nu,
        g("B") + (g("mu_vphi") - 2.0 * g("mu2")) * ln_nu,
    )
}

#[test]
fn kappa_c_and_omega_c_are_appendix_c_with_the_corrected_slopes() {
    // Located by continuation and the minimally augmented Hopf system to
    // its Newton tolerance (residuals of 1e-16): 1e-12 relative leaves
    // room for the conditioning of the location, nothing for a slope off
    // by a term (the corrections move kappa_c by 1e-2 to 1 relative here).
    let laws = [
        ["--set", "mu_vv=1e-3", "--set", "mu_vphi=-5e-4"],
        ["--set", "mu_vv=-4e-4", "--set", "mu_vphi=6e-4"],
    ];
    let mut checked = 0;
    for law in laws {
        for nu in ["0.1", "0.5", "3", "10"] {
            let set_nu = format!("nu={nu}");
            for model in [&["--model", "quasi-static"][..], &["--set", "m=0.05"]] {
                let args = [&law[..], &["--set", &set_nu, "--set", "mu2=2.4e-4"], model].concat();
                let v = hopf_json(&args);
                let p = &v["params"];
                let (mu_v, mu_phi) = slopes(p);
                assert!(rel(num(&v, "mu_v"), mu_v) < 1e-14, "{args:?}: mu_v");
                assert!(rel(num(&v, "mu_phi"), mu_phi) < 1e-14, "{args:?}: mu_phi");
                assert!(mu_phi > mu_v, "{args:?}: the cases weaken");
                let (nu, m) = (num(p, "nu"), num(p, "m"));
                assert_eq!(
                    v["model"],
                    if m > 0.0 { "inertial" } else { "quasi-static" }
                );
                let kappa_c = (mu_phi - mu_v) * (1.0 + m * nu * nu / mu_v);
                let omega_c = nu * (mu_phi / mu_v - 1.0).sqrt();
                let (k, w) = (num(&v, "kappa_c"), num(&v, "omega_c"));
                assert!(
                    rel(k, kappa_c) < 1e-12,
                    "{args:?}: kappa_c {k} vs {kappa_c}"
                );
                assert!(
                    rel(w, omega_c) < 1e-12,
                    "{args:?}: omega_c {w} vs {omega_c}"
                );
                checked += 1;
            }
        }
    }
    assert_eq!(checked, 16);
    // Where the corrected slopes strengthen steady friction (mu_phi <=
    // mu_v: at nu = 30, 0.019667 <= 0.020503) there is no onset.
    let v = hopf_json(&[
        "--set",
        "mu_vv=1e-3",
        "--set",
        "mu_vphi=-5e-4",
        "--set",
        "nu=30",
    ]);
    let (mu_v, mu_phi) = slopes(&v["params"]);
    assert!(mu_phi <= mu_v);
    assert_eq!(v["status"], "stable_for_all_stiffness");
}

/// The cases of docs/reference/mu_corrections_l1.py: the `--set` items,
/// the model, and the reference's `(kappa_c, omega_c, l1)`
/// (mu_corrections_l1_out.txt, as the nearest `f64`).
fn reference_cases() -> Vec<(&'static str, Vec<&'static str>, &'static str, [f64; 3])> {
    let pmma = ["A=0.012", "B=0.023", "mu0=0.6"];
    vec![
        (
            "QS ln2 mu_vv=1e-3 mu_vphi=-5e-4 nu=3",
            [
                &pmma[..],
                &["mu2=2.4e-4", "mu_vv=1e-3", "mu_vphi=-5e-4", "nu=3"],
            ]
            .concat(),
            "quasi-static",
            [0.007176829235434978, 2.092871823849682, -0.6959883427242496],
        ),
        (
            "QS RR mu_vv=-1e-3 nu=1",
            [&pmma[..], &["mu2=0", "mu_vv=-1e-3", "mu_vphi=0", "nu=1"]].concat(),
            "quasi-static",
            [0.011, 0.9574271077563381, 0.11118814959207127],
        ),
        (
            "QS RR mu_vv=5e-4 mu_vphi=1e-3 nu=0.2",
            [
                &pmma[..],
                &["mu2=0", "mu_vv=5e-4", "mu_vphi=1e-3", "nu=0.2"],
            ]
            .concat(),
            "quasi-static",
            [
                0.009390562087565899,
                0.1769233552282447,
                0.0009420199347512523,
            ],
        ),
        (
            "IN ln2 mu_vv=2e-4 mu_vphi=3e-4 m=0.1 nu=3",
            vec![
                "A=0.01",
                "B=0.02",
                "mu0=0.6",
                "mu2=5e-4",
                "mu_vv=2e-4",
                "mu_vphi=3e-4",
                "m=0.1",
                "nu=3",
            ],
            "inertial",
            [
                0.8211005198092003,
                2.8495252405271563,
                -0.0006224163532289521,
            ],
        ),
    ]
}

#[test]
fn l1_against_the_high_precision_reference() {
    for (label, set, model, [kappa_c, omega_c, l1]) in reference_cases() {
        let mut args = vec!["--model", model];
        for s in &set {
            args.extend(["--set", s]);
        }
        let v = hopf_json(&args);
        assert_eq!(v["model"], model, "{label}");
        assert_l1_matches(&v, l1, label);
        let criticality = if l1 < 0.0 {
            "supercritical"
        } else {
            "subcritical"
        };
        assert_eq!(v["criticality"], criticality, "{label}");
        assert!(rel(num(&v, "kappa_c"), kappa_c) < 1e-12, "{label}: kappa_c");
        assert!(rel(num(&v, "omega_c"), omega_c) < 1e-12, "{label}: omega_c");
    }
}

#[test]
fn a_correction_lifts_the_degeneracy_of_the_plain_quasi_static_law() {
    // The plain quasi-static law is degenerate (l1 = 0 exactly, Ranjith &
    // Rice); with mu_vv alone it is not (reference case 2: l1 = 0.111).
    let plain = hopf_json(&["--model", "quasi-static", "--set", "mu2=0"]);
    assert_eq!(plain["criticality"], "degenerate");
    let (status, text, err) = stickslip(&["hopf", "--model", "quasi-static", "--set", "mu2=0"]);
    assert_eq!(status, 0, "{err}");
    assert!(
        text.contains("a correction in ln v (mu_vv, mu_vphi)"),
        "{text}"
    );
    let lifted = hopf_json(&[
        "--model",
        "quasi-static",
        "--set",
        "mu2=0",
        "--set",
        "mu_vv=-1e-3",
    ]);
    assert_eq!(lifted["criticality"], "subcritical");
}

/// The law of docs/model.md with both corrections (`mu0 = 0.6`).
fn law(a: f64, b: f64, mu2: f64, mu_vv: f64, mu_vphi: f64) -> FrictionLaw<f64> {
    FrictionLaw {
        mu0: 0.6,
        a,
        eta: 0.0,
        ageing: Ageing::Log {
            b,
            mu2,
            mu_vv,
            mu_vphi,
        },
    }
}

#[test]
fn steady_friction_is_the_law_at_steady_sliding() {
    // mu_ss = mu0 + (A - B) L + (mu2 + mu_vv - mu_vphi) L^2, L = ln nu
    // (theta = 1/nu), and its slope (A - B) + 2 (mu2 + mu_vv - mu_vphi) L.
    for (mu2, mu_vv, mu_vphi) in [(2.4e-4, 1e-3, -5e-4), (0.0, -4e-4, 6e-4), (1e-4, 0.0, 3e-4)] {
        let f = law(0.012, 0.023, mu2, mu_vv, mu_vphi);
        let c = mu2 + mu_vv - mu_vphi;
        for nu in [1e-6, 0.03, 1.0, 7.0, 1e5] {
            let l: f64 = f64::ln(nu);
            let formula = 0.6 + (0.012 - 0.023) * l + c * l * l;
            let size = 0.6 + 0.035 * l.abs() + 2.0e-3 * l * l;
            assert!(
                (f.steady(nu) - formula).abs() < 4.0 * f64::EPSILON * size,
                "nu = {nu}: {} vs {formula}",
                f.steady(nu)
            );
            let slope = (0.012 - 0.023) + 2.0 * c * l;
            assert!((f.steady_slope(nu) - slope).abs() < 1e-17 + 4.0 * f64::EPSILON * slope.abs());
        }
    }
}

/// Terms of `mu(e^lv, e^lt)`, for the size of its rounding.
fn size(f: &FrictionLaw<f64>, lv: f64, lt: f64) -> f64 {
    let Ageing::Log {
        b,
        mu2,
        mu_vv,
        mu_vphi,
    } = f.ageing
    else {
        unreachable!()
    };
    f.mu0.abs()
        + (f.a * lv).abs()
        + (b * lt).abs()
        + (mu2 * lt * lt).abs()
        + (mu_vv * lv * lv).abs()
        + (mu_vphi * lt * lv).abs()
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 4000,
        max_global_rejects: 40_000,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    /// `mu(slip_velocity(s, theta), theta) = s` for every friction the law
    /// gives on its rising branch, over 35 decades of `v` and `theta` and
    /// coefficients of both signs: to the rounding of `mu`'s terms, and the
    /// velocity found is on the rising branch.
    #[test]
    fn the_quasi_static_inversion_round_trips(
        a in 1e-3f64..0.1,
        b in 0.0f64..0.1,
        mu2 in -1e-3f64..1e-3,
        mu_vv in -1e-2f64..1e-2,
        mu_vphi in -1e-2f64..1e-2,
        lv in -40.0f64..40.0,
        lt in -40.0f64..40.0,
    ) {
        let f = law(a, b, mu2, mu_vv, mu_vphi);
        let (v, theta) = (lv.exp(), lt.exp());
        // Only on the rising branch does the law give v back.
        prop_assume!(f.mu_v(v, theta) > 1e-6 * size(&f, lv, lt));
        let s = f.mu(v, theta);
        let back = f.slip_velocity(s, theta).unwrap();
        prop_assert!(back.is_finite() && back > 0.0);
        let err = (f.mu(back, theta) - s).abs();
        prop_assert!(err <= 64.0 * f64::EPSILON * size(&f, lv, lt), "{err:e}");
        prop_assert!(f.mu_v(back, theta) > 0.0);
    }

    /// Beyond the extremum of `mu` in `ln v` (`mu_vv != 0`: the parabola's
    /// vertex), and wherever the slope `A + mu_vphi ln theta` is not
    /// positive without `mu_vv`, the law has no velocity: the typed error,
    /// with the friction and the age.
    #[test]
    fn no_velocity_is_the_typed_error(
        a in 1e-3f64..0.1,
        mu_vv in prop_oneof![-1e-2f64..-1e-5, 1e-5f64..1e-2],
        mu_vphi in -1e-2f64..1e-2,
        lt in -40.0f64..40.0,
        beyond in 1e-6f64..1.0,
    ) {
        let f = law(a, 0.02, 1e-4, mu_vv, mu_vphi);
        let theta = lt.exp();
        // mu(L) = mu(1, theta) + b L + mu_vv L^2, b = A + mu_vphi ln theta:
        // extremum mu(1, theta) - b^2 / (4 mu_vv), a minimum for mu_vv > 0.
        let slope = a + mu_vphi * lt;
        let vertex = f.mu(1.0, theta) - slope * slope / (4.0 * mu_vv);
        let s = vertex - mu_vv.signum() * beyond * (slope * slope / (4.0 * mu_vv)).abs().max(1e-3);
        prop_assert_eq!(f.slip_velocity(s, theta), Err(NoSlipVelocity { s, theta }));
        let linear = law(a, 0.02, 1e-4, 0.0, mu_vphi);
        let fails = linear.slip_velocity(0.6, theta).is_err();
        prop_assert_eq!(fails, slope <= 0.0);
    }
}

#[test]
fn zero_corrections_are_the_law_without_them_bit_for_bit() {
    // The params JSON gains mu_vv and mu_vphi; every other number is the
    // same f64 (serde_json writes the shortest decimal that reads back to
    // it), in the onset, the cycles, the diagram and a simulation, at nu != 1
    // (where ln nu != 0 multiplies the zero coefficients).
    let dir = temp_dir("mu-corrections-zero");
    let out = |name: &str| dir.join(name).to_str().unwrap().to_string();
    let zero = ["--set", "mu_vv=0", "--set", "mu_vphi=0"];
    let runs: Vec<Vec<String>> = vec![
        vec!["hopf", "--json", "--set", "nu=3"],
        vec!["hopf", "--json", "--set", "nu=0.3", "--set", "m=0.1"],
        vec![
            "cycles",
            "--json",
            "--max-steps",
            "5",
            "--set",
            "nu=3",
            "--out",
            "OUT",
        ],
        vec!["diagram", "--json", "--out", "OUT"],
        vec![
            "simulate",
            "--json",
            "--set",
            "kappa=0.009",
            "--set",
            "nu=2",
            "--out",
            "OUT",
        ],
        vec!["branch", "--json", "--param", "nu", "--set", "kappa=0.009"],
    ]
    .into_iter()
    .map(|r| r.into_iter().map(str::to_string).collect())
    .collect();
    for (i, run) in runs.iter().enumerate() {
        let args = |with: bool, tag: &str| -> Vec<String> {
            let mut a: Vec<String> = run
                .iter()
                .map(|s| {
                    if s == "OUT" {
                        out(&format!("{i}-{tag}"))
                    } else {
                        s.clone()
                    }
                })
                .collect();
            if with {
                a.extend(zero.iter().map(|s| s.to_string()));
            }
            a
        };
        let (a, b) = (args(false, "without"), args(true, "with"));
        let (sa, mut without) = run_json(&a.iter().map(String::as_str).collect::<Vec<_>>());
        let (sb, mut with) = run_json(&b.iter().map(String::as_str).collect::<Vec<_>>());
        assert_eq!(sa, sb, "{run:?}");
        let params = |v: &mut Value| {
            let p = v["params"].as_object_mut().unwrap();
            (p.remove("mu_vv"), p.remove("mu_vphi"))
        };
        assert_eq!(
            params(&mut with),
            (Some(0.0.into()), Some(0.0.into())),
            "{run:?}"
        );
        assert_eq!(
            params(&mut without),
            (Some(0.0.into()), Some(0.0.into())),
            "{run:?}"
        );
        let text = |v: &Value| v.to_string().replace(&out(&format!("{i}-with")), "OUT");
        let without = text(&without).replace(&out(&format!("{i}-without")), "OUT");
        // The run's name carries its overrides.
        let with = text(&with).replace("_mu_vphi=0_mu_vv=0", "");
        assert!(without == with, "{run:?}: the outputs differ");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A PMMA-like scene file with both corrections, the spring below the
/// onset at its velocity (kappa_c = 7.1768e-3 there, quasi-static).
const SCENE: &str = r#"name = "corrected"
description = "PMMA with the corrections in ln v of seed II.D.2"
A = 0.012
B = 0.023
mu0 = 0.5
mu2 = 2.4e-4
mu_vv = 1e-3
mu_vphi = -5e-4
D0 = 0.4
V = 3
K = 1.68e5
"#;

#[test]
fn cycles_simulate_and_diagram_run_on_a_scene_with_the_corrections() {
    let dir = temp_dir("mu-corrections-scene");
    let scene = dir.join("corrected.toml");
    std::fs::write(&scene, SCENE).unwrap();
    let scene = scene.to_str().unwrap();
    let out = dir.join("out");
    let out = out.to_str().unwrap();
    let run = |command: &str, extra: &[&str]| -> (i32, Value) {
        let args = [
            &[command, "--json", "--scene", scene, "--out", out][..],
            extra,
        ]
        .concat();
        let (status, v, err) = json_of(&args);
        assert!(status == 0 || status == 4, "{command}: {err}");
        all_finite(&v, command);
        (status, v)
    };
    let (status, cycles) = run("cycles", &["--max-steps", "40"]);
    let p = &cycles["params"];
    assert_eq!((num(p, "mu_vv"), num(p, "mu_vphi")), (1e-3, -5e-4));
    // The operating point's cycle and the branch from the Hopf point.
    assert!(cycles["cycles"].as_array().unwrap().len() > 10, "{status}");
    let c = &cycles["cycles"][5];
    assert!(num(c, "delta_s") > 0.0 && num(c, "period") > 0.0);
    let (status, sim) = run("simulate", &[]);
    assert_eq!(status, 0);
    assert_eq!(num(&sim["params"], "mu_vv"), 1e-3);
    let (_, diagram) = run("diagram", &[]);
    // Steady friction strengthens above nu = 23.59 ((A - B) + 2 (mu2 + mu_vv
    // - mu_vphi) ln nu = 0): the curve covers the range below.
    let from = num(&diagram["velocity_strengthening"][0], "nu_from");
    let expect = (0.011f64 / (2.0 * (2.4e-4 + 1e-3 + 5e-4))).exp();
    assert!(rel(from, expect) < 1e-9, "{from} vs {expect}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_onset_in_mu_vv() {
    // Quasi-static kappa_c = (B - A) - 2 (mu2 + mu_vv - mu_vphi) ln nu: at
    // kappa = 0.009, nu = 3 the onset is at mu_vv = (0.002 / (2 ln 3)) - mu2.
    let v = hopf_json(&[
        "--model",
        "quasi-static",
        "--set",
        "kappa=0.009",
        "--set",
        "nu=3",
        "--param",
        "mu_vv",
        "--from",
        "1e-4",
        "--to",
        "2e-3",
    ]);
    let expect = 0.002 / (2.0 * 3f64.ln()) - 2.4e-4;
    let got = num(&v["critical"], "value");
    assert!(rel(got, expect) < 1e-8, "{got} vs {expect}");
}

#[test]
fn input_errors_name_the_field() {
    let fails = |args: &[&str], words: &[&str]| {
        let (status, _, err) = stickslip(args);
        assert_eq!(status, 2, "{args:?}: {err}");
        for w in words {
            assert!(err.contains(w), "{args:?}: {w}: {err}");
        }
    };
    // The direct effect at steady sliding must stay positive.
    fails(
        &["hopf", "--set", "mu_vv=1e-2", "--set", "nu=0.01"],
        &["mu_v = A + (2 mu_vv - mu_vphi) ln nu", "> 0"],
    );
    // The corrections belong to the logarithmic form: not with the cutoff.
    fails(
        &["hopf", "--set", "tau=0.1", "--set", "mu_vphi=1e-4"],
        &["--set tau and --set mu_vphi select different ageing forms"],
    );
    fails(
        &[
            "hopf",
            "--scene",
            "brockley",
            "--set",
            "kappa=0.5",
            "--param",
            "mu_vv",
        ],
        &["--param mu_vv", "the scene uses the other ageing form"],
    );
    let dir = temp_dir("mu-corrections-errors");
    let scene = dir.join("cutoff.toml");
    std::fs::write(&scene, "A = 0.012\nB = 0.023\ntau = 0.1\nmu_vv = 1e-4\n").unwrap();
    fails(
        &["hopf", "--scene", scene.to_str().unwrap()],
        &["scene keys tau and mu_vv select different ageing forms"],
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A rig whose stick phases slow the block below the velocity where the
/// direct effect `A + 2 mu_vv ln v + mu_vphi ln theta` vanishes (at the
/// steady age, `ln v* = (mu_vphi ln nu - A) / (2 mu_vv)`): `simulate`
/// cannot settle, and says that the law leaves its range there, with v*.
#[test]
fn a_stick_phase_below_the_laws_range_is_named() {
    let dir = common::temp_dir("mu-range");
    let scene = dir.join("pm.toml");
    std::fs::write(
        &scene,
        "name = \"pm\"\ndescription = \"corrections\"\nA = 0.012\nB = 0.023\nmu0 = 0.5\n\
         mu2 = 2.4e-4\nmu_vv = 3e-4\nmu_vphi = -2e-4\nD0 = 0.4\nV0 = 1.0\nM = 1.0\nW = 300.0\n\
         K = 2e5\nV = 10.0\nV_range = [0.1, 100.0]\n",
    )
    .unwrap();
    let out = dir.join("out");
    let (status, _, stderr) = common::stickslip(&[
        "simulate",
        "--scene",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(status, 4, "{stderr}");
    let v_star = ((-2e-4 * 10f64.ln() - 0.012) / (2.0 * 3e-4)).exp();
    assert!(
        stderr.contains(&format!("vanishes at v = {v_star:.3e} µm/s")),
        "{v_star:.3e}: {stderr}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// A cycle's orbit spans decades of `v` the scene's velocity does not: with
/// `mu_vv < 0` its fast slips reach the side where the direct effect
/// `A + 2 mu_vv ln v + mu_vphi ln theta` is negative, outside the law's
/// domain. `cycles` reports the least direct effect of each orbit and warns
/// with the cycles concerned (a stranger's serpentinite scene, 2026-11-27:
/// slips to 0.47 m/s at a slope of -0.009, with no word). Near the onset the
/// orbit is small and its least direct effect is the steady one,
/// `A + (2 mu_vv - mu_vphi) ln nu` (docs/model.md); without the
/// corrections it is `A` itself.
#[test]
fn cycles_that_leave_the_laws_domain_are_named() {
    let dir = temp_dir("outside_domain");
    let scene = dir.join("serp.toml");
    std::fs::write(
        &scene,
        "A = 0.008\nB = 0.012\nmu0 = 0.6\nmu_vv = -5e-4\nmu_vphi = 3e-4\nD0 = 20.0\n\
         V0 = 1.0\nM = 2.0\nW = 5000.0\nK = 1.5e6\nV = 5.0\n",
    )
    .unwrap();
    let out = dir.join("out");
    let (code, v, err) = json_of(&[
        "cycles",
        "--scene",
        scene.to_str().unwrap(),
        "--json",
        "--max-steps",
        "60",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert!(code == 0 || code == 4, "{err}");
    let cycles = v["cycles"].as_array().unwrap();
    let first = cycles[0]["direct_effect_min"].as_f64().unwrap();
    let steady = 0.008 + (2.0 * -5e-4 - 3e-4) * 5f64.ln();
    assert!((first / steady - 1.0).abs() < 5e-3, "{first} vs {steady}");
    let least = cycles
        .iter()
        .map(|c| c["direct_effect_min"].as_f64().unwrap())
        .fold(f64::INFINITY, f64::min);
    assert!(least < 0.0, "{least}");
    let o = &v["outside_domain"];
    assert_eq!(o["direct_effect_min"].as_f64().unwrap(), least);
    let bad = cycles
        .iter()
        .filter(|c| c["direct_effect_min"].as_f64().unwrap() <= 0.0)
        .count();
    assert_eq!(o["cycles"].as_u64().unwrap() as usize, bad);
    assert!(err.contains("leaves its domain"), "{err}");
    // The plain law: the direct effect is A on every orbit, no warning.
    let (code, v, err) = json_of(&[
        "cycles",
        "--json",
        "--max-steps",
        "20",
        "--out",
        dir.join("plain").to_str().unwrap(),
    ]);
    assert!(code == 0 || code == 4, "{err}");
    let a = v["params"]["A"].as_f64().unwrap();
    for c in v["cycles"].as_array().unwrap() {
        assert_eq!(c["direct_effect_min"].as_f64().unwrap(), a);
    }
    assert!(v.get("outside_domain").is_none());
}

/// `--set mu_vv=1e-3` on pmma: the branch's orbits reach stick velocities
/// where the direct effect `A + 2 mu_vv ln v + mu_vphi ln theta` is
/// negative (the law outside its domain). There the inertial imbalance
/// `chi` has no meaning (it measures the error of a quasi-static reduction
/// that does not exist): the CSV says `n/a`, the JSON `null` with the
/// reason, never the largest `f64`. Where collocation then fails, the
/// branch ends naming the law's domain, and the return map, whose
/// quasi-static stick needs a positive direct effect, does not take over
/// (it ended with its integrator's "event function ... above the
/// floating-point range" before).
#[test]
fn orbits_outside_the_laws_domain_have_no_inertial_imbalance_and_end_the_branch_in_words() {
    let dir = temp_dir("mu-vv-domain");
    let out = dir.to_str().unwrap();
    let (status, v, err) = json_of(&[
        "cycles",
        "--json",
        "--set",
        "mu_vv=1e-3",
        "--max-steps",
        "52",
        "--out",
        out,
        "--force",
    ]);
    assert_eq!(status, 4, "{err}");
    let cycles = v["cycles"].as_array().unwrap();
    let outside: Vec<&Value> = cycles
        .iter()
        .filter(|c| num(c, "direct_effect_min") <= 0.0)
        .collect();
    assert!(outside.len() >= 10, "{} of {}", outside.len(), cycles.len());
    for c in cycles {
        if num(c, "direct_effect_min") <= 0.0 {
            assert!(c["inertial_imbalance"].is_null(), "{c}");
            let why = c["inertial_imbalance_reason"].as_str().unwrap();
            assert!(why.contains("direct effect"), "{why}");
        } else {
            assert!(num(c, "inertial_imbalance").is_finite(), "{c}");
            assert!(c.get("inertial_imbalance_reason").is_none(), "{c}");
        }
    }
    let csv = std::fs::read_to_string(dir.join("pmma_mu_vv=0.001-cycles.csv")).unwrap();
    assert!(!csv.contains("e308"), "the largest f64 in the CSV");
    let header = csv.lines().find(|l| l.starts_with("kappa,")).unwrap();
    let column = header
        .split(',')
        .position(|h| h == "inertial_imbalance")
        .unwrap();
    let na = csv
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("kappa,"))
        .filter(|l| l.split(',').nth(column) == Some("n/a"))
        .count();
    assert_eq!(na, outside.len());

    // The whole branch: it fails where collocation no longer converges on
    // orbits outside the domain, and says so.
    let (status, v, err) = json_of(&[
        "cycles",
        "--json",
        "--set",
        "mu_vv=1e-3",
        "--out",
        out,
        "--force",
    ]);
    assert!(status == 0 || status == 4, "{err}");
    assert!(!err.contains("event function"), "{err}");
    let cycles = v["cycles"].as_array().unwrap();
    assert!(
        cycles.iter().all(|c| c["method"] == "collocation"),
        "the return map took over"
    );
    if status == 4 && err.contains("collocation failed") {
        assert!(err.contains("outside the friction law's domain"), "{err}");
        let last = cycles.last().unwrap();
        assert!(num(last, "direct_effect_min") <= 0.0, "{last}");
    }
}
