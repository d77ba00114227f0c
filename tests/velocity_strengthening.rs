//! Velocity-strengthening friction (`mu_phi <= mu_v`): steady sliding is
//! linearly stable for every stiffness. `hopf`, `diagram` and `cycles` say
//! so with exit status 0; where only part of a velocity range strengthens,
//! the weakening part is analysed and the rest reported as such.
//! `branch --param nu` without a stiffness is refused as bad input.

mod common;

use common::{stickslip, temp_dir};

use serde_json::Value;
use stickslip::analysis::diagram::{stability_diagram, strengthening_intervals, SpecialKind};
use stickslip::analysis::hopf::{find_hopf, HopfOutcome, STRENGTHENING_FLOOR};
use stickslip::model::ModelKind;

/// `mu_phi - mu_v = B - 2 mu2 ln nu - A` of the ln² law (docs/model.md), written out.
fn weakening(a: f64, b: f64, mu2: f64, nu: f64) -> f64 {
    b - 2.0 * mu2 * nu.ln() - a
}

/// PMMA with `A = 0.03` strengthens over the whole scene range 0.1 .. 100
/// (closed form); the search for the onset ends at its positive floor with
/// "stable for every stiffness" at every velocity the diagram tries, where it
/// used to report a spurious real eigenvalue crossing near kappa = 1e-11.
#[test]
fn strengthening_is_stable_for_every_stiffness_across_the_range() {
    let mut p = common::pmma(2.5e-7, 2.4e-4);
    p.a = 0.03;
    for i in 0..41 {
        p.nu = 0.1 * 1000f64.powf(i as f64 / 40.0);
        assert!(weakening(p.a, p.b, p.mu2, p.nu) < 0.0);
        for kind in [ModelKind::Inertial, ModelKind::QuasiStatic] {
            let mut q = p;
            if kind == ModelKind::QuasiStatic {
                q.m = 0.0;
            }
            match find_hopf(kind, &q) {
                Ok(HopfOutcome::StableForAllStiffness { kappa_min }) => {
                    assert!(kappa_min > 0.0 && kappa_min.is_finite());
                    // The floor relative to a stable stiffness of order A + B, not 1e-12 of it.
                    assert!(
                        kappa_min > 1e-3 * STRENGTHENING_FLOOR * (q.a + q.b),
                        "nu = {}: {kappa_min:e}",
                        q.nu
                    );
                }
                other => panic!("nu = {}, {kind:?}: {other:?}", q.nu),
            }
        }
    }
}

/// The stability diagram of a wholly strengthening range is empty, with a
/// reason naming velocity strengthening and the whole range as the
/// strengthening stretch.
#[test]
fn diagram_of_a_strengthening_range_is_empty_with_a_reason() {
    let mut p = common::pmma(2.5e-7, 2.4e-4);
    p.a = 0.03;
    let d = stability_diagram(ModelKind::Inertial, &p, (0.1, 100.0)).unwrap();
    assert!(d.points.is_empty() && d.special.is_empty());
    assert_eq!(d.strengthening, vec![(0.1, 100.0)]);
    let why = d.reason.unwrap();
    assert!(
        why.contains("velocity strengthening") && why.contains("stable for every stiffness"),
        "{why}"
    );
}

/// With `A = 0.024` the ln² law weakens only below `nu* = exp((B - A)/(2 mu2))`
/// (closed form, docs/model.md): the strengthening stretch starts there, to
/// rounding, and the Hopf curve covers the weakening part, ending at
/// `kappa_c -> 0` next to it.
#[test]
fn partly_strengthening_range_is_split_at_the_closed_form_boundary() {
    let mut p = common::pmma(0.0, 2.4e-4);
    p.a = 0.024;
    let nu_star = ((p.b - p.a) / (2.0 * p.mu2)).exp();
    let s = strengthening_intervals(&p, (0.1, 100.0));
    assert_eq!(s.len(), 1, "{s:?}");
    assert!(
        (s[0].0 / nu_star - 1.0).abs() < 1e-12,
        "{} vs {nu_star}",
        s[0].0
    );
    assert_eq!(s[0].1, 100.0);
    let d = stability_diagram(ModelKind::QuasiStatic, &p, (0.1, 100.0)).unwrap();
    assert!(!d.points.is_empty());
    assert!(d.points.iter().all(|q| q.nu <= nu_star * (1.0 + 1e-6)));
    let end = d
        .special
        .iter()
        .find(|q| q.kind == SpecialKind::Endpoint)
        .expect("an end point");
    assert!(
        (end.nu / nu_star - 1.0).abs() < 1e-10,
        "{} vs {nu_star}",
        end.nu
    );
    let why = d.reason.unwrap();
    assert!(
        why.contains("velocity strengthening") && why.contains("weakening part"),
        "{why}"
    );
    // A range that weakens throughout has no strengthening stretch and no reason.
    assert!(strengthening_intervals(&p, (0.01, 0.1)).is_empty());
}

/// `stickslip diagram --set A=0.03`: exit 0, empty curve, the reason in the
/// JSON; no null or NaN written.
#[test]
fn diagram_cli_answers_velocity_strengthening() {
    let dir = temp_dir("vs-diagram");
    let (code, out, err) = stickslip(&[
        "diagram",
        "--set",
        "A=0.03",
        "--json",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(!out.contains("null") && !out.contains("NaN"), "{out}");
    let v: Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["hopf_curve"].as_array().map(Vec::len), Some(0));
    let why = v["reason"].as_str().unwrap();
    assert!(
        why.contains("velocity strengthening") && why.contains("mu_phi <= mu_v"),
        "{why}"
    );
    assert_eq!(
        v["velocity_strengthening"][0]["nu_from"].as_f64(),
        Some(0.1)
    );
    assert!(dir.join("pmma_A=0.03-stability-physical.png").exists());
    std::fs::remove_dir_all(&dir).ok();
}

/// `stickslip cycles --set A=0.03`: no Hopf point and no cycle by simulation;
/// exit 0 with an empty branch and the reason; a requested stiffness is
/// then not delivered (exit 4, with the reason).
#[test]
fn cycles_cli_answers_an_empty_branch_with_a_reason() {
    let dir = temp_dir("vs-cycles");
    let (code, out, err) = stickslip(&[
        "cycles",
        "--set",
        "A=0.03",
        "--at-kappa",
        "0.001",
        "--json",
        "--out",
        dir.to_str().unwrap(),
    ]);
    // No cycle exists to deliver at the requested stiffness: the request is
    // incomplete (status 4), the reason given.
    assert_eq!(code, 4, "{err}");
    assert!(!out.contains("NaN"), "{out}");
    let v: Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["cycles"].as_array().map(Vec::len), Some(0));
    let why = v["reason"].as_str().unwrap();
    assert!(
        why.contains("velocity strengthening")
            && why.contains("no stick-slip cycle was found by simulation at kappa ="),
        "{why}"
    );
    // The requested stiffness is not delivered: the request is incomplete.
    assert_eq!(v["complete"], Value::Bool(false));
    assert_eq!(v["requested_points"][0]["delivered"], Value::Bool(false));
    assert!(v["requested_points"][0]["reason"]
        .as_str()
        .unwrap()
        .contains("velocity strengthening"));
    let (code, text, err) =
        // The same run as above, as text: its files are replaced.
        stickslip(&[
            "cycles",
            "--set",
            "A=0.03",
            "--out",
            dir.to_str().unwrap(),
            "--force",
        ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        text.contains("no cycles: steady sliding is stable"),
        "{text}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// `branch --param nu` on a scene without a stiffness: bad input naming
/// `--set kappa=` and `kappa_c` at the scene's velocity (0.011 for PMMA at
/// nu = 1, C11); `branch --param kappa --to 0` is refused naming `--to`.
#[test]
fn velocity_branch_without_a_stiffness_is_bad_input() {
    let (code, _, err) = stickslip(&["branch", "--param", "nu"]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("--set kappa=") && err.contains("kappa_c = 1.1000"),
        "{err}"
    );
    let (code, _, err) = stickslip(&["branch", "--param", "kappa", "--to", "0"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--to = 0"), "{err}");
    let (code, out, err) =
        stickslip(&["branch", "--param", "nu", "--set", "kappa=0.0105", "--csv"]);
    assert_eq!(code, 0, "{err}");
    assert!(out.lines().count() > 2);
}
