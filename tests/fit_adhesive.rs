//! `fit` on an adhesive scene: the gel scene's values recovered from data
//! written by docs/reference/fit_adhesive_data.py (mpmath's E1 and its own
//! steady law and critical stiffness, not the code under test): within
//! three standard errors from the noisy example, to 1e-8 from the
//! noise-free files; what the data cannot see (the viscous force below
//! the viscous regime) held and named; bad data named by file, row and
//! column; the fitted scene read back by `hopf` and `diagram`.

mod common;

use common::{json_of, stickslip, temp_dir};
use serde_json::Value;
use std::path::Path;

/// The generating parameters, as the script printed them
/// (docs/reference/fit_adhesive_data_out.txt).
fn truth() -> Vec<(String, f64)> {
    let text = std::fs::read_to_string("docs/reference/fit_adhesive_data_out.txt").unwrap();
    text.lines()
        .skip_while(|l| !l.starts_with("generating parameters"))
        .skip(1)
        .take(6)
        .map(|l| {
            let (name, value) = l.split_once(' ').unwrap();
            (name.to_string(), value.parse().unwrap())
        })
        .collect()
}

/// A value of the script's checks (`NAME... VALUE` lines).
fn script_value(prefix: &str) -> f64 {
    let text = std::fs::read_to_string("docs/reference/fit_adhesive_data_out.txt").unwrap();
    let line = text.lines().find(|l| l.starts_with(prefix)).unwrap();
    line.rsplit(' ').next().unwrap().parse().unwrap()
}

/// Every parameter started 10–25 % off the truth.
const START_OFF: [&str; 6] = [
    "F_a=0.06",
    "V_s=0.03",
    "tau_on=0.12",
    "tau_out=0.8",
    "F_v=4e-4",
    "alpha=0.5",
];

/// The example's steady and onset data (with noise), and the same
/// velocities without noise.
const EXAMPLE: [&str; 2] = [
    "steady=examples/data/gel-steady.csv",
    "onset=examples/data/gel-onset.csv",
];
const EXACT: [&str; 2] = [
    "steady=tests/data/gel-steady-exact.csv",
    "onset=tests/data/gel-onset-exact.csv",
];

/// The fitted scene a fit wrote (`<out>/<run>-fitted.toml`, the run named
/// by the scene and its overrides), from its JSON's `files`, in `dir`.
fn fitted_path(v: &Value, dir: &std::path::Path) -> std::path::PathBuf {
    let path = v["files"]
        .as_array()
        .and_then(|f| {
            f.iter()
                .filter_map(Value::as_str)
                .find(|f| f.ends_with("-fitted.toml"))
        })
        .unwrap_or_else(|| panic!("no fitted scene in {}", v["files"]));
    assert!(path.starts_with(dir.to_str().unwrap()), "{path}");
    std::path::PathBuf::from(path)
}

/// `fit --json --scene gel` with `set` and `data` into a fresh folder: the
/// exit status, the JSON and the folder.
fn fit(name: &str, set: &[&str], data: &[&str]) -> (i32, Value, std::path::PathBuf) {
    let dir = temp_dir(name);
    let mut args = vec![
        "fit",
        "--json",
        "--scene",
        "gel",
        "--out",
        dir.to_str().unwrap(),
    ];
    for s in set {
        args.extend(["--set", s]);
    }
    for d in data {
        args.extend(["--data", d]);
    }
    let (status, v, err) = json_of(&args);
    assert!(v.is_object(), "{args:?}: {err}");
    (status, v, dir)
}

#[test]
fn the_example_recovers_the_gel_within_three_standard_errors() {
    // Steady friction alone: tau_out held (the steady state sees tau_on /
    // tau_out only), the others fitted.
    let (status, v, _) = fit(
        "adh-steady",
        &START_OFF,
        &["steady=examples/data/gel-steady.csv"],
    );
    assert_eq!(status, 0, "{v}");
    let p = &v["parameters"];
    assert_eq!(p["tau_out"]["status"], "fixed");
    assert!(v["held"][0]["reason"].as_str().unwrap().contains("ratio"));
    for (name, truth) in truth() {
        let e = &p[name.as_str()];
        if name == "tau_out" {
            // Held at the scene's (--set) value.
            assert_eq!(e["value"].as_f64().unwrap(), 0.8);
            continue;
        }
        assert_eq!(e["status"], "fitted", "{name}");
        let (value, sd) = (
            e["value"].as_f64().unwrap(),
            e["std_error"].as_f64().unwrap(),
        );
        let scaled_truth = if name == "tau_on" {
            // tau_on is fitted with tau_out held at 0.8 s: the ratio is what
            // the data give, 0.1 / 1.
            truth * 0.8
        } else {
            truth
        };
        assert!(
            (value - scaled_truth).abs() < 3.0 * sd,
            "{name}: {value} +- {sd} vs {scaled_truth}"
        );
        assert!(sd < 0.2 * scaled_truth, "{name}: {sd}");
    }
    let ratio = &v["ratio_tau_on_over_tau_out"];
    let (r, sd) = (
        ratio["value"].as_f64().unwrap(),
        ratio["std_error"].as_f64().unwrap(),
    );
    assert!((r - 0.1).abs() < 3.0 * sd, "{r} +- {sd}");
    assert!((v["chi2_per_dof"].as_f64().unwrap() - 1.0).abs() < 1e-6);
    // The example's noise, 3e-4 N, within a quarter.
    let sigma = v["datasets"][0]["sigma_estimated"].as_f64().unwrap();
    assert!((sigma / 3e-4 - 1.0).abs() < 0.25, "{sigma}");

    // With the onset: all six, tau_out too.
    let (status, v, dir) = fit("adh-joint", &START_OFF, &EXAMPLE);
    assert_eq!(status, 0, "{v}");
    for (name, truth) in truth() {
        let e = &v["parameters"][name.as_str()];
        assert_eq!(e["status"], "fitted", "{name}");
        let (value, sd) = (
            e["value"].as_f64().unwrap(),
            e["std_error"].as_f64().unwrap(),
        );
        assert!(
            (value - truth).abs() < 3.0 * sd,
            "{name}: {value} +- {sd} vs {truth}"
        );
    }
    assert_eq!(v["correlation"]["names"].as_array().unwrap().len(), 6);
    assert_eq!(v["datasets"][1]["quantity"], "K_N_per_m");
    assert_eq!(v["datasets"][1]["sigma"], "given");
    // The fitted scene runs hopf and diagram.
    let fitted = fitted_path(&v, &dir);
    let hopf = common::hopf_json(&["--scene", fitted.to_str().unwrap()]);
    assert_eq!(hopf["scene"], "gel-fitted", "{hopf}");
    let (status, _, err) = stickslip(&[
        "diagram",
        "--scene",
        fitted.to_str().unwrap(),
        "--out",
        dir.join("diagram").to_str().unwrap(),
    ]);
    assert_eq!(status, 0, "{err}");
    for f in v["files"].as_array().unwrap() {
        assert!(Path::new(f.as_str().unwrap()).exists(), "{f}");
    }
}

#[test]
fn noise_free_data_give_the_gel_to_1e_8() {
    let (status, v, dir) = fit("adh-exact", &START_OFF, &EXACT);
    assert_eq!(status, 0, "{v}");
    for (name, truth) in truth() {
        let value = v["parameters"][name.as_str()]["value"].as_f64().unwrap();
        assert!(
            (value / truth - 1.0).abs() < 1e-8,
            "{name}: {value} vs {truth}"
        );
    }
    // The residuals at rounding level of the script's 17 digits.
    for d in v["datasets"].as_array().unwrap() {
        let rms = d["rms"].as_f64().unwrap();
        let scale = if d["quantity"] == "F_N" { 0.05 } else { 2e5 };
        assert!(rms < 1e-12 * scale, "{d}");
    }
    // The fitted scene's hopf locates the onset the script computes at V =
    // 20 µm/s without inertia (the script's quasi-static value; the
    // scene's 1 g makes hopf inertial by its orbit, so the model is
    // given).
    let fitted = fitted_path(&v, &dir);
    let hopf = common::hopf_json(&[
        "--scene",
        fitted.to_str().unwrap(),
        "--model",
        "quasi-static",
    ]);
    let k_c = hopf["critical"]["K_N_per_m"].as_f64().unwrap();
    let expected = script_value("K_c(20 um/s) quasi-static");
    assert!((k_c / expected - 1.0).abs() < 1e-7, "{k_c} vs {expected}");
}

#[test]
fn the_viscous_force_is_held_without_the_viscous_regime() {
    let (status, v, dir) = fit("adh-slow", &[], &["steady=tests/data/gel-steady-slow.csv"]);
    assert_eq!(status, 4, "{v}");
    assert_eq!(v["complete"], false);
    for name in ["F_v", "alpha"] {
        let e = &v["parameters"][name];
        assert_eq!(e["status"], "not_determined", "{name}: {v}");
        assert!(e["std_error"].is_null(), "{name}");
        let n = v["not_determined"]
            .as_array()
            .unwrap()
            .iter()
            .find(|n| n["name"] == name)
            .unwrap();
        assert!(
            n["remedy"].as_str().unwrap().contains("viscous regime"),
            "{n}"
        );
    }
    assert!(v["stop"].as_str().unwrap().contains("F_v"));
    // The rest is fitted given them, with meaningful errors.
    for name in ["F_a", "V_s", "tau_on"] {
        let e = &v["parameters"][name];
        assert_eq!(e["status"], "fitted");
        assert!(e["std_error"].as_f64().unwrap() < 0.2 * e["value"].as_f64().unwrap());
    }
    let toml = std::fs::read_to_string(fitted_path(&v, &dir)).unwrap();
    assert!(toml.starts_with("# not determined by the data"), "{toml}");
    // The same data with all the viscous-regime rows do determine them
    // (the example): not a rule on velocities.
    let (_, v, _) = fit("adh-fast", &[], &["steady=examples/data/gel-steady.csv"]);
    assert_eq!(v["parameters"]["alpha"]["status"], "fitted");
}

#[test]
fn bad_data_name_file_row_and_column() {
    let dir = temp_dir("adh-bad");
    let cases: [(&str, &str, &[&str]); 6] = [
        ("V_um_s\n1\n2\n", "steady", &["row 1", "a column F_N"]),
        // A sign-flipped force (a stranger's row was fitted as data).
        (
            "V_um_s,F_N\n1,0.05\n2,-0.04\n",
            "steady",
            &["row 3, column 2 (F_N)", "> 0 N"],
        ),
        (
            "V_um_s,F_N\n1,0.05\n-2,0.04\n",
            "steady",
            &["row 3, column 1 (V_um_s)", "> 0"],
        ),
        (
            "V_um_s,F_N\n1,0.05\n2,NaN\n",
            "steady",
            &["row 3, column 2 (F_N)", "finite"],
        ),
        (
            "V_um_s,mu\n1,0.05\n2,0.04\n",
            "steady",
            &["row 1, column 2", "F_N"],
        ),
        (
            "V_um_s,K_N_per_m\n1,1e5\n2,-1\n",
            "onset",
            &["row 3, column 2 (K_N_per_m)", "> 0"],
        ),
    ];
    for (i, (text, kind, says)) in cases.iter().enumerate() {
        let file = dir.join(format!("bad-{i}.csv"));
        std::fs::write(&file, text).unwrap();
        let data = format!("{kind}={}", file.display());
        let (status, _, err) = stickslip(&[
            "fit",
            "--scene",
            "gel",
            "--data",
            &data,
            "--out",
            dir.to_str().unwrap(),
        ]);
        assert_eq!(status, 2, "{text}: {err}");
        assert!(err.contains(&file.display().to_string()), "{err}");
        assert!(says.iter().all(|s| err.contains(s)), "{text}: {err}");
    }
    // A kind the adhesive law has no model of.
    let data = "velocity_step=examples/data/pmma-velocity-step.csv";
    let (status, _, err) = stickslip(&["fit", "--scene", "gel", "--data", data]);
    assert_eq!(status, 2, "{err}");
    assert!(
        err.contains("rate-and-state scenes only") && err.contains("steady and onset"),
        "{err}"
    );
    // Both times without onset data: only their ratio is seen.
    let (status, _, err) = stickslip(&[
        "fit",
        "--scene",
        "gel",
        "--free",
        "tau_on,tau_out",
        "--data",
        "steady=examples/data/gel-steady.csv",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(status, 2, "{err}");
    assert!(err.contains("only through"), "{err}");
}

/// The fit's model against the script's values at the generating
/// parameters: steady friction to 1e-13, the critical stiffness (the
/// script's by numerical differentiation at 40 digits) to 1e-9, and the
/// closed form the fit uses against the onset `hopf` locates with the
/// engine.
#[test]
fn the_model_is_the_scripts_and_the_engines() {
    use stickslip::adhesive::fit::Values;
    let scene = stickslip::adhesive::scene::load("gel").unwrap();
    let values = Values::of(&scene);
    let mass = scene.units.mass;
    let rows = |file: &str| -> Vec<(f64, f64)> {
        std::fs::read_to_string(file)
            .unwrap()
            .lines()
            .filter(|l| !l.starts_with('#') && !l.starts_with('V'))
            .map(|l| {
                let (a, b) = l.split_once(',').unwrap();
                (a.parse().unwrap(), b.parse().unwrap())
            })
            .collect()
    };
    for (v, f) in rows("tests/data/gel-steady-exact.csv") {
        let model = values.steady_force_n(mass, v);
        assert!((model / f - 1.0).abs() < 1e-13, "{v}: {model} vs {f}");
    }
    for (v, k) in rows("tests/data/gel-onset-exact.csv") {
        let model = values.critical_stiffness_n_m(mass, v);
        assert!((model / k - 1.0).abs() < 1e-9, "{v}: {model} vs {k}");
    }
    // hopf --model inertial at 50 µm/s locates K_c with the engine.
    let hopf = common::hopf_json(&["--scene", "gel", "--set", "V=50", "--model", "inertial"]);
    let c = &hopf["critical"];
    let located = c["K_N_per_m"].as_f64().unwrap();
    let model = values.critical_stiffness_n_m(mass, 50.0);
    assert!((model / located - 1.0).abs() < 1e-9, "{model} vs {located}");
}

/// `fit --name X` names the fitted scene as it names the run's other
/// files: `<out>/X-fitted.toml` with `name = "X"`, which the next command
/// reads back (its `scene` is X); no `gel-fitted.toml` beside it.
#[test]
fn fit_name_names_the_fitted_scene() {
    let dir = temp_dir("adh-fit-name");
    let mut args = vec![
        "fit",
        "--scene",
        "gel",
        "--name",
        "lab 7",
        "--out",
        dir.to_str().unwrap(),
    ];
    for d in EXACT {
        args.extend(["--data", d]);
    }
    let (status, _, err) = stickslip(&args);
    assert_eq!(status, 0, "{err}");
    assert!(!dir.join("gel-fitted.toml").exists());
    let fitted = dir.join("lab_7-fitted.toml");
    let text = std::fs::read_to_string(&fitted).unwrap();
    assert_eq!(
        text.lines().filter(|l| l.starts_with("name = ")).count(),
        1,
        "{text}"
    );
    let hopf = common::hopf_json(&["--scene", fitted.to_str().unwrap()]);
    assert_eq!(hopf["scene"], "lab 7", "{hopf}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The rows `(V, value)` of a noise-free data file of the reference script.
fn exact_rows(path: &str) -> Vec<(f64, f64)> {
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with('V'))
        .map(|l| {
            let (v, y) = l.split_once(',').unwrap();
            (v.parse().unwrap(), y.parse().unwrap())
        })
        .collect()
}

/// `rows` with Gaussian noise of `sigma` from `rng`, as a CSV without a
/// sigma column (the errors estimated from the residuals).
fn noisy(path: &Path, header: &str, rows: &[(f64, f64)], sigma: f64, rng: &mut common::Normal) {
    let mut text = format!("{header}\n");
    for (v, y) in rows {
        text.push_str(&format!("{v},{}\n", y + sigma * rng.next()));
    }
    std::fs::write(path, text).unwrap();
}

/// Over `n` seeded synthetic data sets (the reference script's noise-free
/// rows plus Gaussian noise, no sigma column) fitted from the truth: how
/// often each parameter's 1-sigma interval holds the truth, and every run's
/// exit status 0 (a joint fit without sigma columns once did not converge
/// from the true values: the onset in N/m weighted 1e7 times the friction
/// in N at the first minimisation).
fn coverage(name: &str, n: u64, with_onset: bool) -> Vec<(String, f64)> {
    let dir = temp_dir(name);
    let truth = truth();
    let steady = exact_rows("tests/data/gel-steady-exact.csv");
    let onset = exact_rows("tests/data/gel-onset-exact.csv");
    let mut inside = vec![0usize; truth.len()];
    let mut fitted = vec![false; truth.len()];
    for seed in 0..n {
        let mut rng = common::Normal(1000 + seed);
        let steady_csv = dir.join(format!("steady-{seed}.csv"));
        noisy(&steady_csv, "V_um_s,F_N", &steady, 3e-4, &mut rng);
        let mut data = vec![format!("steady={}", steady_csv.display())];
        if with_onset {
            let onset_csv = dir.join(format!("onset-{seed}.csv"));
            noisy(&onset_csv, "V_um_s,K_N_per_m", &onset, 1e3, &mut rng);
            data.push(format!("onset={}", onset_csv.display()));
        }
        let out = dir.join(format!("out-{seed}"));
        let mut args = vec![
            "fit",
            "--json",
            "--scene",
            "gel",
            "--out",
            out.to_str().unwrap(),
        ];
        for d in &data {
            args.extend(["--data", d.as_str()]);
        }
        let (status, v, err) = json_of(&args);
        assert_eq!(status, 0, "seed {seed}: {err}");
        for (k, (key, value)) in truth.iter().enumerate() {
            let e = &v["parameters"][key];
            if e["status"] != "fitted" {
                continue;
            }
            fitted[k] = true;
            let (fit, sd) = (
                e["value"].as_f64().unwrap(),
                e["std_error"].as_f64().unwrap(),
            );
            inside[k] += usize::from((fit - value).abs() <= sd);
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
    truth
        .into_iter()
        .zip(inside)
        .zip(fitted)
        .filter(|(_, fitted)| *fitted)
        .map(|(((key, _), k), _)| (key, k as f64 / n as f64))
        .collect()
}

/// The 1-sigma intervals of a fit with errors estimated from the residuals
/// hold the truth as often as they should: with `N - p` degrees of freedom
/// the probability is `P(|t| < 1)`, 0.671 for 20 (steady friction: 25 rows,
/// five parameters) and 0.673 for 27 (with the onset: 33 rows, six), each
/// over 100 seeded data sets within three binomial standard deviations
/// (0.047). A stranger's 10 of 20 (0.5) was within that band of 20 sets;
/// errors too small by a factor 1.5 would give 0.49 here.
#[test]
fn one_sigma_intervals_cover_the_truth_as_often_as_t_says() {
    for (name, with_onset, p_t) in [
        ("adh-coverage-steady", false, 0.6707),
        ("adh-coverage-joint", true, 0.6734),
    ] {
        let n = 100;
        let band = 3.0 * (p_t * (1.0 - p_t) / n as f64).sqrt();
        let covered = coverage(name, n, with_onset);
        assert!(covered.len() >= 5, "{covered:?}");
        for (key, fraction) in covered {
            assert!(
                (fraction - p_t).abs() <= band,
                "{name}: {key} covered {fraction}, expected {p_t} +- {band:.3}"
            );
        }
    }
}
