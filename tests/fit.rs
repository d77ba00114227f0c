//! `fit` (issue 26): the seed's PMMA values recovered from the example
//! data (made by docs/reference/fit_data.py with its own formulas), the
//! reported errors honest (coverage of ±1 sigma over many noise draws),
//! what the data cannot determine named and never given a value, the
//! fitted scene read back by the other jobs.
//!
//! The data of the draws are written here with the closed forms of the
//! seed (eqs. RR5, C11, C13), not with the code under test.

mod common;

use common::Normal;
use std::f64::consts::PI;
use std::path::{Path, PathBuf};
use stickslip::fit::data::Kind;
use stickslip::jobs::fit::{run, Fit, FitRequest};
use stickslip::jobs::hopf::HopfRequest;
use stickslip::jobs::{self, SceneSpec};

/// The seed's PMMA values (examples/scenes/pmma.toml): A, B, D0 [µm], mu0, mu2.
const TRUTH: [(&str, f64); 5] = [
    ("A", 0.012),
    ("B", 0.023),
    ("D0", 0.4),
    ("mu0", 0.5),
    ("mu2", 2.4e-4),
];

fn truth(name: &str) -> f64 {
    TRUTH.iter().find(|(n, _)| *n == name).map(|t| t.1).unwrap()
}

/// Steady friction, eq. RR5 with `theta = V0/V` (V0 = 1 µm/s).
fn steady(v: f64) -> f64 {
    let l = v.ln();
    truth("mu0") + (truth("A") - truth("B")) * l + truth("mu2") * l * l
}

/// `(K/W)_c` [1/m] (eq. C11) and `f_c` [Hz] (eq. C13) for a 1 kg block
/// under its weight.
fn onset(v: f64) -> (f64, f64) {
    let (a, d0) = (truth("A"), truth("D0") * 1e-6);
    let mu_phi = truth("B") - 2.0 * truth("mu2") * v.ln();
    let w = 9.81;
    let kw = (mu_phi - a) * (1.0 + (v * 1e-6).powi(2) / (w * d0 * a)) / d0;
    let f = v * 1e-6 / (2.0 * PI * d0) * (mu_phi / a - 1.0).sqrt();
    (kw, f)
}

fn geomspace(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| lo * (hi / lo).powf(i as f64 / (n - 1) as f64))
        .collect()
}

/// Writes one draw of steady and onset data with known errors (sigma
/// columns): 2e-4 on mu, 2 % on (K/W)_c and f_c.
fn draw(dir: &Path, k: usize, noise: &mut Normal) -> (PathBuf, PathBuf) {
    let steady_path = dir.join(format!("steady-{k}.csv"));
    let onset_path = dir.join(format!("onset-{k}.csv"));
    let mut text = String::from("V_um_s,mu,sigma\n");
    for v in geomspace(0.1, 100.0, 13) {
        text += &format!("{v},{},2e-4\n", steady(v) + 2e-4 * noise.next());
    }
    std::fs::write(&steady_path, text).unwrap();
    let mut text = String::from("V_um_s,K_over_W_per_m,sigma,frequency_hz,sigma_frequency_hz\n");
    for v in geomspace(0.1, 100.0, 7) {
        let (kw, f) = onset(v);
        text += &format!(
            "{v},{},{},{},{}\n",
            kw * (1.0 + 0.02 * noise.next()),
            0.02 * kw,
            f * (1.0 + 0.02 * noise.next()),
            0.02 * f
        );
    }
    std::fs::write(&onset_path, text).unwrap();
    (steady_path, onset_path)
}

fn fit(data: Vec<(Kind, PathBuf)>, free: Option<&str>) -> Result<Fit, stickslip::error::Error> {
    fit_with(data, free, true)
}

/// The fit, with or without the fitted scene's stability band and onset type.
fn fit_with(
    data: Vec<(Kind, PathBuf)>,
    free: Option<&str>,
    stability: bool,
) -> Result<Fit, stickslip::error::Error> {
    let request = FitRequest {
        data,
        free: free.map(|f| f.split(',').map(String::from).collect()),
        stability,
    };
    run(&SceneSpec::named("pmma"), &request)
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("stickslip-fit-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

#[test]
fn the_seeds_pmma_values_from_the_example_data() {
    let f = fit(
        vec![
            (Kind::Steady, "examples/data/pmma-steady.csv".into()),
            (Kind::Onset, "examples/data/pmma-onset.csv".into()),
        ],
        None,
    )
    .unwrap();
    assert!(f.outcome.complete && f.summary.not_determined.is_empty());
    for (name, value) in TRUTH {
        let e = &f.summary.parameters[name];
        let sd = e.std_error.unwrap();
        assert!(
            (e.value - value).abs() < 3.0 * sd,
            "{name} = {} ± {sd}, truth {value}",
            e.value
        );
    }
    // As precise as the seed's measurement (A = 0.012 ± 0.002, B = 0.023
    // ± 0.002, D0 = 0.4 ± 0.04 µm) or better, from 20 points.
    assert!(f.summary.parameters["A"].std_error.unwrap() < 0.002);
    assert!(f.summary.parameters["D0"].std_error.unwrap() < 0.04);
    assert!(
        (f.summary.chi2_per_dof - 1.0).abs() < 0.8,
        "{}",
        f.summary.chi2_per_dof
    );
    // The seed's closed-form route beside it agrees to its own precision.
    let c = f.closed_form.as_ref().unwrap();
    assert!((c.b_minus_a - 0.011).abs() < 1e-3 && (c.d0_um.unwrap() - 0.4).abs() < 0.03);
    // The 95 % band of the stability boundary by the delta method (exact
    // gradient) agrees with the quantiles of 1000 parameter sets drawn from
    // the fit's distribution to a tenth of its half width (the errors are
    // small: the boundary is nearly linear in them).
    assert_eq!(f.band.len(), 41);
    for b in &f.band {
        let half = b.hi_95 - b.k_over_w;
        assert!(half > 0.0 && half < 0.03 * b.k_over_w, "{b:?}");
        assert!((b.sampled_lo_95 - b.lo_95).abs() < 0.1 * half, "{b:?}");
        assert!((b.sampled_hi_95 - b.hi_95).abs() < 0.1 * half, "{b:?}");
    }
    // The onset type: supercritical at 1 µm/s for every drawn set, and the
    // ln² law's subcritical stretch near 30 µm/s (the Bautin points of the
    // pmma diagram at 26.6 and 78.5 µm/s) as the fit has it.
    let at = |v: f64| {
        let off = |o: &&stickslip::jobs::fit::OnsetTypeAt| (o.v_um_s / v).ln().abs();
        f.onset_type
            .iter()
            .min_by(|a, b| off(a).total_cmp(&off(b)))
            .unwrap()
    };
    assert_eq!(at(1.0).criticality.name(), "supercritical");
    assert_eq!(at(1.0).share_supercritical, 1.0);
    assert_eq!(at(45.0).criticality.name(), "subcritical");
    // The fitted scene is a scene every command reads: its onset at V = V0
    // (quasi-static there, inertia shifts it by 2e-5) is the fitted B - A.
    let dir = temp_dir("scene");
    let path = dir.join("fitted.toml");
    std::fs::write(&path, &f.outcome.fitted_toml).unwrap();
    let hopf = jobs::hopf::run(
        &SceneSpec::named(path.to_str().unwrap()),
        &HopfRequest::default(),
    )
    .unwrap();
    let kappa_c = serde_json::to_value(&hopf.report).unwrap()["kappa_c"]
        .as_f64()
        .unwrap();
    let b_minus_a = f.summary.parameters["B"].value - f.summary.parameters["A"].value;
    assert!(
        (kappa_c / b_minus_a - 1.0).abs() < 1e-13,
        "{kappa_c} {b_minus_a}"
    );
    let k_over_w = serde_json::to_value(&hopf.report).unwrap()["physical"]["K_over_W_per_m"]
        .as_f64()
        .unwrap();
    let d0 = f.summary.parameters["D0"].value * 1e-6;
    assert!(
        (k_over_w * d0 / b_minus_a - 1.0).abs() < 1e-13,
        "{k_over_w}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// The reported standard errors are honest: over 300 noise draws each
/// parameter's truth lies within ±1 reported sigma in 68 % of the fits
/// (binomial spread 2.7 %: the band 60–76 % fails a correct fit about
/// once in 300 runs of this test, and catches errors off by 20 %).
#[test]
fn one_sigma_covers_the_truth_68_percent_of_the_time() {
    let dir = temp_dir("coverage");
    let mut noise = Normal(20_261_126);
    let draws = 300;
    let mut inside = [0usize; 5];
    for k in 0..draws {
        let (s, o) = draw(&dir, k, &mut noise);
        let f = fit_with(vec![(Kind::Steady, s), (Kind::Onset, o)], None, false).unwrap();
        for (i, (name, value)) in TRUTH.iter().enumerate() {
            let e = &f.summary.parameters[name];
            if (e.value - value).abs() <= e.std_error.unwrap() {
                inside[i] += 1;
            }
        }
    }
    std::fs::remove_dir_all(&dir).ok();
    for (i, (name, _)) in TRUTH.iter().enumerate() {
        let share = inside[i] as f64 / draws as f64;
        println!(
            "coverage of ±1 sigma, {name}: {share:.3} ({} of {draws})",
            inside[i]
        );
        assert!((0.60..=0.76).contains(&share), "{name}: {share}");
    }
}

#[test]
fn what_steady_data_cannot_determine_is_named_not_invented() {
    let f = fit(
        vec![(Kind::Steady, "examples/data/pmma-steady.csv".into())],
        None,
    )
    .unwrap();
    assert!(!f.outcome.complete);
    let names: Vec<&str> = f.summary.not_determined.iter().map(|n| n.name).collect();
    assert!(
        names.contains(&"D0") && (names.contains(&"A") || names.contains(&"B")),
        "{names:?}"
    );
    for n in &f.summary.not_determined {
        let e = &f.summary.parameters[n.name];
        assert!(e.std_error.is_none() && e.value == e.start && e.status == "not_determined");
        assert!(n.remedy.starts_with("add "), "{}", n.remedy);
    }
    // B - A, what steady data do determine, is the truth's within the
    // error of B given A (the closed form's straight line leaves out the
    // mu2 curvature and is off by 5e-4 here).
    let b_minus_a = f.summary.parameters["B"].value - f.summary.parameters["A"].value;
    let sd = f.summary.parameters["B"].std_error.unwrap();
    assert_eq!(f.summary.parameters["B"].given, vec!["A"]);
    assert!((b_minus_a - 0.011).abs() < 3.0 * sd, "{b_minus_a} ± {sd}");
    assert!(f.outcome.stop.as_ref().unwrap().contains("D0"));
    // No stability band that would claim a precision the data do not give.
    assert!(f.band.is_empty() && f.onset_type.is_empty());
    // --free restricts to what is determined: then the answer is complete.
    let f = fit(
        vec![(Kind::Steady, "examples/data/pmma-steady.csv".into())],
        Some("mu0,B,mu2"),
    )
    .unwrap();
    assert!(f.outcome.complete, "{:?}", f.outcome.stop);
    assert_eq!(f.summary.parameters["A"].status, "fixed");
    // A name the law does not have.
    let e = fit(
        vec![(Kind::Steady, "examples/data/pmma-steady.csv".into())],
        Some("tau"),
    )
    .err()
    .unwrap()
    .to_string();
    assert!(e.contains("tau") && e.contains("mu2"), "{e}");
}

/// `fit` treats the files of an earlier run as every command does
/// (README: a run never replaces an earlier finished run's files unless
/// given `--force`): its fitted scene is a file of the run,
/// `<out>/<run>-fitted.toml`, so fits of two scenes in one folder keep both
/// (before, both wrote `fitted.toml` and the second failed, exit 1, which
/// the README gives to write errors); the same fit again is refused
/// before computing, exit 2, naming the file, in the words `diagram` uses;
/// `--force` replaces it; the files of a fit that did not finish (no JSON)
/// are replaced with a note.
#[test]
fn a_second_fit_in_a_folder_is_treated_as_every_commands_rerun() {
    let dir = common::temp_dir("fit-rerun");
    let out = dir.to_str().unwrap();
    let pmma = [
        "fit",
        "--data",
        "steady=examples/data/pmma-steady.csv",
        "--data",
        "onset=examples/data/pmma-onset.csv",
        "--out",
        out,
    ];
    let gel = [
        "fit",
        "--scene",
        "gel",
        "--data",
        "steady=examples/data/gel-steady.csv",
        "--data",
        "onset=examples/data/gel-onset.csv",
        "--out",
        out,
    ];
    let (code, _, err) = common::stickslip(&pmma);
    assert_eq!(code, 0, "{err}");
    let (code, _, err) = common::stickslip(&gel);
    assert_eq!(code, 0, "the second scene's fit beside the first: {err}");
    let (pmma_toml, gel_toml) = (dir.join("pmma-fitted.toml"), dir.join("gel-fitted.toml"));
    for (path, law) in [(&pmma_toml, None), (&gel_toml, Some("adhesive"))] {
        let text = std::fs::read_to_string(path).unwrap();
        let table: toml::Table = text.parse().unwrap();
        assert_eq!(table.get("law").and_then(|l| l.as_str()), law, "{text}");
        let hopf =
            common::hopf_json(&["--scene", path.to_str().unwrap(), "--model", "quasi-static"]);
        assert_eq!(hopf["complete"], true, "{hopf}");
    }
    assert!(!dir.join("fitted.toml").exists());

    // The same fit again: refused as `diagram` refuses its rerun.
    let (code, _, err) = common::stickslip(&pmma);
    assert_eq!(code, 2, "{err}");
    let (diagram_code, _, diagram_err) = common::stickslip(&["diagram", "--out", out]);
    assert_eq!(diagram_code, 0, "{diagram_err}");
    let (diagram_code, _, diagram_err) = common::stickslip(&["diagram", "--out", out]);
    assert_eq!(code, diagram_code);
    let refusal = |e: &str, file: &str| {
        e.contains(&format!(
            "{}/{file} exists (an earlier run of the same name)",
            out
        )) && e.contains("--force replaces its files, --name NAME writes under another name")
    };
    assert!(refusal(&err, "pmma-fit.json"), "{err}");
    assert!(refusal(&diagram_err, "pmma-diagram.json"), "{diagram_err}");

    // --force replaces it.
    std::fs::write(&pmma_toml, "stale").unwrap();
    let (code, _, err) = common::stickslip(&[&pmma[..], &["--force"]].concat());
    assert_eq!(code, 0, "{err}");
    assert_ne!(std::fs::read_to_string(&pmma_toml).unwrap(), "stale");

    // A fit that did not finish (its JSON missing) is replaced, with a note.
    std::fs::remove_file(dir.join("gel-fit.json")).unwrap();
    std::fs::write(&gel_toml, "stale").unwrap();
    let (code, _, err) = common::stickslip(&gel);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("note: replacing the files of an earlier run"),
        "{err}"
    );
    assert_ne!(std::fs::read_to_string(&gel_toml).unwrap(), "stale");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Steady data the law reproduces exactly (a friction that does not depend
/// on the velocity, as a stranger wrote by hand): the errors estimated from
/// zero residuals were 1e-308, the next minimisation went off to
/// non-finite parameters, and nalgebra's SVD of that Jacobian looped
/// forever (a fit that ignored SIGINT and SIGTERM). Now the errors stop at
/// the rounding of the values and the fit ends at once: velocity-neutral
/// friction, `B - A = 0` and `mu2 = 0` to rounding, `mu0` the data's.
#[test]
fn steady_data_reproduced_exactly_end_the_fit_with_the_exact_values() {
    let dir = temp_dir("flat");
    let file = dir.join("flat.csv");
    std::fs::write(
        &file,
        "V_um_s,mu\n1,0.5\n10,0.5\n100,0.5\n1000,0.5\n3,0.5\n30,0.5\n",
    )
    .unwrap();
    let (sender, receiver) = std::sync::mpsc::channel();
    std::thread::spawn(move || {
        let _ = sender.send(fit_with(vec![(Kind::Steady, file)], None, false));
    });
    let f = receiver
        .recv_timeout(std::time::Duration::from_secs(60))
        .expect("the fit did not end within 60 s")
        .unwrap();
    let p = &f.summary.parameters;
    assert!(
        (p["mu0"].value - 0.5).abs() < 1e-12,
        "mu0 {}",
        p["mu0"].value
    );
    assert!((p["B"].value - p["A"].value).abs() < 1e-12);
    assert!(p["mu2"].value.abs() < 1e-12, "mu2 {}", p["mu2"].value);
    for (name, e) in p.iter() {
        assert!(e.value.is_finite(), "{name}");
    }
}

/// The remedy of a parameter the data leave free never asks for the kind
/// of data given (onset data alone: D0 was "add onset data").
#[test]
fn a_remedy_does_not_ask_for_the_data_given() {
    for (kind, file, asked) in [
        (
            Kind::Onset,
            "examples/data/pmma-onset.csv",
            "add onset data",
        ),
        (
            Kind::Steady,
            "examples/data/pmma-steady.csv",
            "add steady-friction data",
        ),
    ] {
        let f = fit_with(vec![(kind, file.into())], None, false).unwrap();
        assert!(!f.summary.not_determined.is_empty(), "{file}");
        for n in &f.summary.not_determined {
            assert!(n.remedy.starts_with("add "), "{}", n.remedy);
            assert!(
                !n.remedy.starts_with(asked),
                "{file}: {}: {}",
                n.name,
                n.remedy
            );
        }
    }
}
