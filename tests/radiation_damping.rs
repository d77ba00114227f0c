//! Issue 27: radiation damping, the quasi-dynamic term of earthquake-cycle
//! models: the force `W eta x'` beside friction, `m v' = s - mu(v, theta) -
//! eta_d v` with `eta_d = eta V0` (docs/model.md, "Radiation damping").
//!
//! - `hopf --json`'s `kappa_c` and `omega_c` are Appendix C's closed forms
//!   with `mu_v + eta_d nu` for `mu_v`, written out here.
//! - `l1` against an independent 50-digit computation (quasi-statically
//!   through Lambert's W: docs/reference/radiation_damping_l1.py,
//!   radiation_damping_l1_out.txt).
//! - The quasi-static inversion of `mu + eta_d v`: round trips, huge
//!   forces, monotone (proptest).
//! - `eta = 0` gives what the law without damping gives, bit for bit.
//! - A fault-like scene file: the peak slip velocity is bounded by damping,
//!   near `Delta_s / eta`; `cycles`, `simulate`, `diagram`, `branch` on it;
//!   the physical key, `--set eta`, and the input errors.

mod common;

use common::{all_finite, assert_l1_matches, hopf_json, json_of, run_json, stickslip, temp_dir};
use proptest::prelude::*;
use serde_json::Value;
use stickslip::friction::{Ageing, FrictionLaw};

fn num(v: &Value, k: &str) -> f64 {
    v[k].as_f64()
        .unwrap_or_else(|| panic!("{k} missing in {v}"))
}

fn rel(a: f64, b: f64) -> f64 {
    (a / b - 1.0).abs()
}

#[test]
fn kappa_c_and_omega_c_are_appendix_c_with_the_damped_slope() {
    // Linearized at steady sliding (v = nu, theta = 1/nu) the force balance
    // m dv' = ds - (mu_v / nu + eta_d) dv - mu_phi nu dtheta, with
    // dtheta' = -dtheta nu - dv / nu and ds' = -kappa dv, has the
    // characteristic polynomial (inertial 3x3; written by hand)
    //   m l^3 + (M_v / nu + m nu) l^2 + (kappa + M_v - mu_phi) l + kappa nu,
    //   M_v = mu_v + eta_d nu,
    // and quasi-statically (2x2, m = 0) M_v / nu l^2 + (kappa + M_v - mu_phi) l
    // + kappa nu. l = i w is a root iff kappa + M_v - mu_phi = m w^2 and
    // kappa nu = (M_v / nu + m nu) w^2: kappa_c = (mu_phi - M_v)(1 + m nu^2 /
    // M_v), w_c = nu sqrt(mu_phi / M_v - 1). Located by continuation to its
    // Newton tolerance: 1e-12 relative as for the corrections, nothing for
    // a slope off by the damping (it moves kappa_c by 1e-3 to 0.6 here).
    let mut checked = 0;
    for eta in ["1e-4", "1e-3", "2e-3"] {
        for nu in ["0.3", "1", "3"] {
            for model in [&["--model", "quasi-static"][..], &["--set", "m=0.05"]] {
                let set = [format!("eta_d={eta}"), format!("nu={nu}")];
                let args = [
                    &["--set", &set[0], "--set", &set[1], "--set", "mu2=2.4e-4"][..],
                    model,
                ]
                .concat();
                let v = hopf_json(&args);
                let p = &v["params"];
                let g = |k: &str| num(p, k);
                let (nu, m, eta_d) = (g("nu"), g("m"), g("eta_d"));
                assert_eq!(eta_d, eta.parse::<f64>().unwrap());
                let mu_v = g("A") + eta_d * nu;
                let mu_phi = g("B") - 2.0 * g("mu2") * nu.ln();
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
    assert_eq!(checked, 18);
    // Damping strengthens: with eta_d nu >= mu_phi - mu_v there is no onset
    // (nu = 1: B - A = 0.011).
    let v = hopf_json(&["--set", "eta_d=0.012", "--set", "nu=1"]);
    assert_eq!(v["status"], "stable_for_all_stiffness");
}

/// The cases of docs/reference/radiation_damping_l1.py: the `--set` items,
/// the model, and the reference's `(kappa_c, omega_c, l1)`
/// (radiation_damping_l1_out.txt, as the nearest `f64`).
fn reference_cases() -> Vec<(&'static str, Vec<&'static str>, &'static str, [f64; 3])> {
    let pmma = ["A=0.012", "B=0.023", "mu0=0.6"];
    vec![
        (
            "QS ln2 eta_d=5e-3 nu=1",
            [&pmma[..], &["mu2=2.4e-4", "eta_d=5e-3", "nu=1"]].concat(),
            "quasi-static",
            [0.006, 0.5940885257860046, -0.241261208225795],
        ),
        (
            "QS RR mu_vphi=1e-3 eta_d=2e-2 nu=0.3",
            [
                &pmma[..],
                &["mu2=0", "mu_vphi=1e-3", "eta_d=2e-2", "nu=0.3"],
            ]
            .concat(),
            "quasi-static",
            [
                0.002592054391348128,
                0.11021679267040989,
                -0.02863811841282143,
            ],
        ),
        (
            "QS ln2 eta_d=1e-4 nu=10",
            [&pmma[..], &["mu2=2.4e-4", "eta_d=1e-4", "nu=10"]].concat(),
            "quasi-static",
            [0.008894759155362858, 8.271712293837473, -8.016927522282302],
        ),
        (
            "IN ln2 mu_vv=2e-4 mu_vphi=3e-4 eta_d=1e-3 m=0.1 nu=3",
            vec![
                "A=0.01",
                "B=0.02",
                "mu0=0.6",
                "mu2=5e-4",
                "mu_vv=2e-4",
                "mu_vphi=3e-4",
                "eta_d=1e-3",
                "m=0.1",
                "nu=3",
            ],
            "inertial",
            [
                0.42633907098383056,
                2.049921854156312,
                -0.0007824510654811862,
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
        assert_eq!(v["criticality"], "supercritical", "{label}");
        assert!(rel(num(&v, "kappa_c"), kappa_c) < 1e-12, "{label}: kappa_c");
        assert!(rel(num(&v, "omega_c"), omega_c) < 1e-12, "{label}: omega_c");
    }
}

/// The law of docs/model.md with damping `eta_d` (`mu0 = 0.6`).
fn law(mu_vv: f64, mu_vphi: f64, eta: f64) -> FrictionLaw<f64> {
    FrictionLaw {
        mu0: 0.6,
        a: 0.012,
        eta,
        ageing: Ageing::Log {
            b: 0.023,
            mu2: 2.4e-4,
            mu_vv,
            mu_vphi,
        },
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(400))]

    #[test]
    fn the_damped_inversion_round_trips(
        lv in -40.0f64..40.0,
        lt in -20.0f64..20.0,
        log_eta in -9.0f64..1.0,
        mu_vv in prop_oneof![Just(0.0), -2e-4f64..2e-4],
        mu_vphi in prop_oneof![Just(0.0), -3e-4f64..3e-4],
    ) {
        // Where the force mu + eta_d v rises with ln v at the state, the
        // velocity it gives back is the state's, to rounding of the force:
        // the force's relative rounding over its slope in ln v.
        let f = law(mu_vv, mu_vphi, 10f64.powf(log_eta));
        let (v, theta) = (lv.exp(), lt.exp());
        let slope = f.mu_v(v, theta) + f.eta * v;
        prop_assume!(slope > 1e-3);
        // The smallest root on a rising branch: with mu_vv < 0 the branch
        // of the undamped law (low velocities) comes first.
        let low_branch_first = mu_vv < 0.0 && f.mu_v(v, theta) <= 0.0;
        prop_assume!(!low_branch_first);
        let s = f.mu(v, theta) + f.eta * v;
        let back = f.slip_velocity(s, theta).unwrap();
        let size = f.mu(v, theta).abs() + 0.012 * lv.abs() + f.eta * v + 1.0;
        // ln v itself is resolved to its ulp.
        let tol = 8.0 * f64::EPSILON * (size / slope + lv.abs());
        prop_assert!((back.ln() - lv).abs() <= tol, "{} vs {lv} (tol {tol:e})", back.ln());
    }

    #[test]
    fn the_damped_inversion_is_monotone_and_finite_for_huge_forces(
        s1 in 0.0f64..1e6,
        ds in 1e-9f64..1e6,
        lt in -20.0f64..20.0,
    ) {
        // s up to 1e6 (v = s / eta_d up to 1e12): no overflow, ln v
        // rising with s.
        let f = law(0.0, 0.0, 1e-6);
        let theta = lt.exp();
        let a = f.slip_velocity(s1, theta).unwrap();
        let b = f.slip_velocity(s1 + ds, theta).unwrap();
        prop_assert!(a.is_finite() && b.is_finite() && a > 0.0);
        prop_assert!(b >= a, "{a} {b}");
    }
}

#[test]
fn huge_forces_are_held_by_the_damping() {
    // s = 1e300: undamped, v = exp(1e300 / A) overflows to inf; damped,
    // v = (s - mu) / eta_d is finite.
    let f = law(0.0, 0.0, 0.5);
    let v = f.slip_velocity(1e300, 1.0).unwrap();
    assert!(rel(v, 2e300) < 1e-12, "{v}");
    assert_eq!(
        law(0.0, 0.0, 0.0).slip_velocity(1e300, 1.0),
        Ok(f64::INFINITY)
    );
}

#[test]
fn zero_damping_is_the_law_without_it_bit_for_bit() {
    // The params JSON gains eta_d; every other number is the same f64, in
    // the onset (both models), the cycles, the diagram, a simulation and a
    // branch, with the corrections in ln v (where the inversion is the
    // quadratic's) and without, --set eta_d=0 and --set eta=0 alike.
    let dir = temp_dir("radiation-damping-zero");
    let out = |name: &str| dir.join(name).to_str().unwrap().to_string();
    let runs: Vec<Vec<&str>> = vec![
        vec!["hopf", "--json", "--set", "nu=3"],
        vec!["hopf", "--json", "--set", "nu=0.3", "--set", "m=0.1"],
        vec![
            "hopf",
            "--json",
            "--set",
            "nu=3",
            "--set",
            "mu_vv=1e-3",
            "--set",
            "mu_vphi=-5e-4",
        ],
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
    ];
    for (i, run) in runs.iter().enumerate() {
        for (zero, tag) in [("eta_d=0", "_eta_d=0"), ("eta=0", "_eta_s_per_m=0")] {
            let args = |with: bool| -> Vec<String> {
                let name = format!("{i}-{}", if with { "with" } else { "without" });
                let name = format!("{name}-{zero}");
                let mut a: Vec<String> = run
                    .iter()
                    .map(|s| {
                        if *s == "OUT" {
                            out(&name)
                        } else {
                            s.to_string()
                        }
                    })
                    .collect();
                if with {
                    a.extend(["--set".to_string(), zero.to_string()]);
                }
                a
            };
            let (a, b) = (args(false), args(true));
            let (sa, mut without) = run_json(&a.iter().map(String::as_str).collect::<Vec<_>>());
            let (sb, mut with) = run_json(&b.iter().map(String::as_str).collect::<Vec<_>>());
            assert_eq!(sa, sb, "{run:?}");
            for v in [&mut with, &mut without] {
                let p = v["params"].as_object_mut().unwrap();
                assert_eq!(p.remove("eta_d"), Some(0.0.into()), "{run:?}");
            }
            let without = without
                .to_string()
                .replace(&out(&format!("{i}-without-{zero}")), "OUT");
            let with = with
                .to_string()
                .replace(&out(&format!("{i}-with-{zero}")), "OUT")
                .replace(tag, "");
            assert!(without == with, "{run:?} {zero}: the outputs differ");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A fault-like block: granite-like friction (A = 0.010, B = 0.014), D0 =
/// 10 um, driven at 1 um/s through a spring at half the critical stiffness
/// (K_c = W (B - A) / D0 = 4e9 N/m), a load W = 1e7 N and M = 10 kg: the
/// undamped slip is limited by inertia alone, at about the oscillator's
/// Delta_F / sqrt(K M) (metres per second); eta = 0.5 s/m (G = 30 GPa,
/// c_s = 3 km/s, sigma = 10 MPa) gives W eta = 5e6 N s/m, far above sqrt(K M)
/// = 1.4e5 kg/s, so damping holds the slip instead.
const QUAKE: &str = r#"name = "quake"
description = "a fault-like block: granite-like friction, slip of m/s without damping"
A = 0.010
B = 0.014
D0 = 10
V0 = 1
V = 1
W = 1e7
K = 2e9
M = 10
"#;

/// The column `name` of the CSV a `simulate --json` run `v` wrote (its
/// comment lines skipped).
fn csv_column(v: &Value, name: &str) -> Vec<f64> {
    let csv = v["files"]
        .as_array()
        .unwrap()
        .iter()
        .filter_map(Value::as_str)
        .find(|f| f.ends_with(".csv"))
        .unwrap()
        .to_string();
    let text = std::fs::read_to_string(csv).unwrap();
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    let col = header.iter().position(|h| *h == name).unwrap();
    lines
        .map(|l| l.split(',').nth(col).unwrap().parse().unwrap())
        .collect()
}

/// The largest slip velocity in um/s of a `simulate` CSV, and the run's
/// stress drop `Delta_s` (its settled cycle, JSON `regime`).
fn simulated(scene: &str, out: &str, eta: &str) -> (f64, f64) {
    let (status, v, err) = json_of(&[
        "simulate",
        "--json",
        "--scene",
        scene,
        "--model",
        "inertial",
        "--set",
        &format!("eta={eta}"),
        "--protocol",
        "1:5000",
        "--perturb",
        "0.5",
        "--out",
        out,
        "--force",
    ]);
    assert_eq!(status, 0, "{err}");
    assert_eq!(v["regime"]["kind"], "periodic", "eta = {eta}");
    assert_eq!(
        num(&v["params"], "eta_d"),
        eta.parse::<f64>().unwrap() * 1e-6
    );
    let v_max = csv_column(&v, "v_um_per_s").into_iter().fold(0.0, f64::max);
    (v_max, num(&v["regime"], "delta_s"))
}

#[test]
fn radiation_damping_bounds_the_peak_slip_velocity() {
    let dir = temp_dir("radiation-damping-quake");
    let scene = dir.join("quake.toml");
    std::fs::write(&scene, QUAKE).unwrap();
    let scene = scene.to_str().unwrap();
    let out = dir.join("out");
    let out = out.to_str().unwrap();
    let (free, drop_free) = simulated(scene, out, "0");
    let (damped, drop) = simulated(scene, out, "0.5");
    // Undamped: metres per second (5.1 m/s; Delta_s = 0.173).
    assert!(free > 1e6, "{free} um/s");
    // Damped: the slip velocity where the spring's excess over friction is
    // held by eta_d v, at most the whole stress drop: v_max ~ Delta_s / eta
    // (m/s with eta in s/m, Delta_s the drop of s = force / W) = 0.069 / 0.5
    // = 0.14 m/s. At the peak only part of the drop is unbalanced (friction
    // has not yet fallen to its lowest, the spring has already released
    // some), so v_max is below the estimate, by a factor of order one:
    // 0.078 m/s, 0.57 of it. Between a third and the estimate itself.
    let estimate_um_s = drop / 0.5 * 1e6;
    assert!(damped < free / 10.0, "{damped} vs {free}");
    assert!(
        damped > estimate_um_s / 3.0 && damped < estimate_um_s,
        "{damped} um/s vs Delta_s / eta = {estimate_um_s} um/s"
    );
    // Damping takes energy from the slip: a smaller drop, as in the
    // quasi-dynamic earthquake-cycle models.
    assert!(drop < drop_free, "{drop} vs {drop_free}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn every_command_runs_on_a_scene_with_damping() {
    let dir = temp_dir("radiation-damping-scene");
    let scene = dir.join("quake.toml");
    std::fs::write(&scene, format!("{QUAKE}eta = 0.5\n")).unwrap();
    let scene = scene.to_str().unwrap();
    let out = dir.join("out");
    let out = out.to_str().unwrap();
    let run = |command: &str, extra: &[&str]| -> (i32, Value) {
        let files: &[&str] = if ["hopf", "branch"].contains(&command) {
            &[]
        } else {
            &["--out", out]
        };
        let args = [&[command, "--json", "--scene", scene][..], files, extra].concat();
        let (status, v, err) = json_of(&args);
        assert!(status == 0 || status == 4, "{command}: {err}");
        all_finite(&v, command);
        assert_eq!(num(&v["params"], "eta_d"), 5e-7, "{command}");
        (status, v)
    };
    // kappa_c = B - A - eta_d nu (quasi-static: m nu^2 / mu_v = 1e-11).
    let (_, h) = run("hopf", &[]);
    assert!(rel(num(&h, "kappa_c"), 0.004 - 5e-7) < 1e-12);
    let (_, c) = run("cycles", &["--max-steps", "3"]);
    assert!(c["cycles"].as_array().unwrap().len() >= 3);
    assert!(rel(num(&c["cycles"][0], "kappa"), 0.004 - 5e-7) < 1e-3);
    run("simulate", &[]);
    run("branch", &["--param", "nu"]);
    run("diagram", &[]);
    let _ = std::fs::remove_dir_all(&dir);
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
    fails(&["hopf", "--set", "eta_d=-1e-3"], &["eta_d", ">= 0"]);
    fails(
        &["hopf", "--set", "eta=0.5", "--set", "eta_d=1e-3"],
        &["eta", "eta_d"],
    );
    let dir = temp_dir("radiation-damping-errors");
    let scene = dir.join("bad.toml");
    std::fs::write(&scene, "A = 0.01\neta = -0.5\n").unwrap();
    fails(
        &["hopf", "--scene", scene.to_str().unwrap()],
        &["eta", ">= 0"],
    );
    std::fs::write(&scene, "A = 0.01\neta = 'x'\n").unwrap();
    fails(&["hopf", "--scene", scene.to_str().unwrap()], &["eta"]);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_onset_in_eta_d() {
    // Quasi-static kappa_c = B - A - 2 mu2 ln nu - eta_d nu (pmma, nu = 1):
    // at kappa = 0.005 the onset is at eta_d = 0.011 - 0.005 = 0.006.
    let v = hopf_json(&[
        "--model",
        "quasi-static",
        "--set",
        "kappa=0.005",
        "--param",
        "eta_d",
        "--from",
        "1e-4",
        "--to",
        "1e-2",
    ]);
    let got = num(&v["critical"], "value");
    assert!(rel(got, 0.006) < 1e-8, "{got}");
}

/// The onset in the damping in its own unit, s/m (`--param eta`): on the
/// fault-like scene (K = 2e9 N/m, kappa = K D0 / W = 2e-3, nu = 1,
/// quasi-static) C12 with the damped slope, `kappa_c = B - A - eta_d`,
/// puts it at `eta_d = B - A - kappa = 2e-3`, `eta = eta_d / V0 = 2000 s/m`
/// (V0 = 1 µm/s), with `critical.dimensionless.eta_d` beside it.
#[test]
fn the_onset_in_eta_in_seconds_per_metre() {
    let dir = temp_dir("damping-eta-control");
    let scene = dir.join("quake.toml");
    std::fs::write(&scene, QUAKE).unwrap();
    let v = hopf_json(&[
        "--scene",
        scene.to_str().unwrap(),
        "--param",
        "eta",
        "--from",
        "1",
        "--to",
        "1e4",
    ]);
    let c = &v["critical"];
    assert_eq!(c["unit"], "s/m");
    let eta_d = 0.014 - 0.010 - 2e9 * 10e-6 / 1e7;
    assert!(rel(num(c, "value"), eta_d / 1e-6) < 1e-9, "{c}");
    assert!(rel(num(&c["dimensionless"], "eta_d"), eta_d) < 1e-9, "{c}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A simulated start with damping at a stiffness where steady sliding is
/// stable: the settling run measures its distance from steady sliding with
/// the damped steady force `mu_ss + eta_d nu` (it took `mu_ss` and never
/// saw the orbit decay: the start then failed on every mesh), says the
/// orbit decayed there, starts from `0.9 kappa_c`, and the branch ends at
/// the damped onset `kappa_c = B - A - eta_d = 9e-3` (C12, quasi-static).
#[test]
fn a_simulated_start_with_damping_sees_the_decay() {
    let dir = temp_dir("radiation-damping-settle");
    let (code, v) = run_json(&[
        "cycles",
        "--from-simulation",
        "--set",
        "eta_d=2e-3",
        "--set",
        "kappa=0.0095",
        "--out",
        dir.to_str().unwrap(),
        "--force",
        "--json",
    ]);
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(code, 0, "{v}");
    let rejected = v["start"]["rejected"][0]["outcome"].as_str().unwrap();
    assert!(rejected.contains("decayed to steady sliding"), "{rejected}");
    assert_eq!(v["leg_stops"][0]["reason"], "hopf_point");
    // The last cycle lies just below the damped onset (the undamped one is
    // 0.011); how near depends on the step lengths. Its force drop is the
    // normal form's `C sqrt(kappa_c - kappa)` of the damped onset (`hopf`,
    // a second method), to the next order in `kappa_c - kappa`.
    let top = v["cycles"]
        .as_array()
        .unwrap()
        .iter()
        .max_by(|a, b| num(a, "kappa").total_cmp(&num(b, "kappa")))
        .unwrap();
    let kappa = num(top, "kappa");
    assert!(kappa < 9e-3 && rel(kappa, 9e-3) < 1e-4, "{kappa}");
    let onset = hopf_json(&["--set", "eta_d=2e-3"]);
    assert!(rel(num(&onset, "kappa_c"), 9e-3) < 1e-12, "{onset}");
    let c = num(&onset, "amplitude_coefficient");
    let predicted = c * (9e-3 - kappa).sqrt();
    assert!(
        rel(num(top, "delta_s"), predicted) < 1e-3,
        "Delta_s = {} at kappa = {kappa}, normal form {predicted}",
        num(top, "delta_s")
    );
}

/// `simulate` starts from steady sliding with the damping's share of the
/// spring force, `s = mu_ss(nu) + eta_d nu` (0.5 + 2e-3 at nu = 1): left
/// unperturbed at a stable stiffness it stays there (it started at
/// `mu_ss` and called the decaying transient periodic, `Delta_s` 1.6e-9).
#[test]
fn simulate_starts_from_damped_steady_sliding() {
    let dir = temp_dir("radiation-damping-steady-start");
    let out = dir.to_str().unwrap();
    let args = [
        "simulate",
        "--json",
        "--set",
        "eta_d=2e-3",
        "--set",
        "kappa=0.0095",
        "--perturb",
        "0",
        "--protocol",
        "1:100",
        "--out",
        out,
        "--force",
    ];
    let (status, v, err) = json_of(&args);
    assert_eq!(status, 0, "{err}");
    assert_eq!(v["regime"]["kind"], "steady", "{}", v["regime"]);
    let rows = csv_column(&v, "s");
    assert!(rows.len() >= 10, "{rows:?}");
    for s in rows {
        assert!((s - 0.502).abs() < 1e-12, "{s}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `hopf` reports the slope `mu_v` with the damping's `eta_d nu`, the one
/// Appendix C takes (pmma, nu = 1: `A + eta_d = 0.014`, and quasi-statically
/// `kappa_c = mu_phi - mu_v`); where the damping alone makes steady
/// sliding velocity strengthening it says so (it said friction weakens and
/// the onset lies below the searched stiffnesses).
#[test]
fn hopf_reports_the_damped_slope() {
    let v = hopf_json(&["--set", "eta_d=2e-3"]);
    assert!(rel(num(&v, "mu_v"), 0.014) < 1e-14, "{}", v["mu_v"]);
    let c12 = num(&v, "mu_phi") - num(&v, "mu_v");
    assert!(rel(num(&v, "kappa_c"), c12) < 1e-9, "{}", v["kappa_c"]);
    let (status, out, err) = stickslip(&["hopf", "--set", "eta=1e6"]);
    assert_eq!(status, 0, "{err}");
    assert!(
        out.contains("with the radiation damping eta_d nu is velocity strengthening"),
        "{out}"
    );
}

/// Damping leaves steady friction unchanged: `hopf`'s text gives its slope
/// `d mu_ss / d ln V = A - B` at `nu = 1` (where the ln² term's share
/// vanishes) and says which part of `mu_v` is the damping's (a stranger,
/// 2026-11-27: the slope of the spring force was printed under the name of
/// steady friction's).
#[test]
fn hopf_names_the_steady_slope_and_the_dampings_share_of_mu_v() {
    let (code, text, err) = stickslip(&[
        "hopf", "--set", "eta=1e4", "--set", "A=0.01", "--set", "B=0.015",
    ]);
    assert_eq!(code, 0, "{err}");
    let line = text
        .lines()
        .find(|l| l.starts_with("steady sliding at"))
        .unwrap();
    assert!(line.contains("d mu_ss/d ln V = -5.000000e-3"), "{line}");
    assert!(line.contains("the direct effect 1.000000e-2"), "{line}");
    assert!(
        line.contains("with the damping d (mu_ss + eta_d nu)/d ln V"),
        "{line}"
    );
}

/// Without an onset `cycles` simulates the scene from a stick; its verdict
/// on the rig then says what those simulations found, instead of advising
/// the simulations it has just run (a stranger, 2026-11-27).
#[test]
fn cycles_without_an_onset_reports_its_own_search() {
    let dir = temp_dir("no_onset_search");
    let (code, text, err) = stickslip(&[
        "cycles",
        "--set",
        "eta=1e4",
        "--set",
        "A=0.01",
        "--set",
        "B=0.015",
        "--set",
        "kappa=0.001",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(code == 0 || code == 4, "{err}");
    let all = format!("{text}{err}");
    assert!(
        all.contains("the simulations from a stick found no cycle"),
        "{all}"
    );
    assert!(!all.contains("look for it"), "{all}");
}
