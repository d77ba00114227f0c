//! Stiffnesses requested with `--at-kappa`: each is delivered as a cycle at
//! exactly that stiffness, or named with the reason it is not; requested
//! values beyond the default range extend the branch to them.

mod common;

use common::{stickslip, temp_dir};

use serde_json::Value;
use stickslip::analysis::cycles::{trace_cycles, CycleRecord, CycleRequest};
use stickslip::model::ModelKind;

/// `a` and `b` are equal or adjacent doubles.
fn within_one_ulp(a: f64, b: f64) -> bool {
    a == b || a.next_up() == b || a.next_down() == b
}

fn requested(v: &Value, kappa: f64) -> &Value {
    v["requested_points"]
        .as_array()
        .expect("requested_points array")
        .iter()
        .find(|r| r["kappa"].as_f64() == Some(kappa))
        .unwrap_or_else(|| panic!("kappa = {kappa} missing from requested_points: {v}"))
}

/// The library: user points lie on the requested stiffness to one ulp, and
/// the orbit there is the cycle at that stiffness — a Radau integration
/// from its first sample reproduces its period and `Delta_s` to 1e-6.
#[test]
fn user_points_land_on_the_requested_stiffness() {
    let p = common::pmma(0.0, 2.4e-4);
    let targets = [0.0105, 0.0095];
    let req = CycleRequest {
        kappa_min: 0.009,
        kappa_max: 0.1,
        max_steps: 200,
        ntst: 40,
        at_kappa: targets.to_vec(),
        ntst_max: 12800,
        collocation: None,
    };
    let mut users: Vec<CycleRecord> = Vec::new();
    trace_cycles(ModelKind::QuasiStatic, &p, &req, |c| {
        users.extend(c.user.iter().cloned());
        Ok(())
    })
    .unwrap();
    for target in targets {
        let hits: Vec<&CycleRecord> = users
            .iter()
            .filter(|u| (u.kappa / target - 1.0).abs() < 1e-6)
            .collect();
        assert_eq!(
            hits.len(),
            1,
            "one cycle at kappa = {target}: {:?}",
            users.iter().map(|u| u.kappa).collect::<Vec<_>>()
        );
        let u = hits[0];
        assert!(u.user_point);
        assert!(
            within_one_ulp(u.kappa, target),
            "kappa {:e} asked, {:e} delivered",
            target,
            u.kappa
        );
        common::assert_reproduced_by_integration(
            ModelKind::QuasiStatic,
            &p,
            u,
            &format!("user point {target}"),
        );
    }
}

/// The command line: a value below the default range (`0.9 kappa_c` with
/// `--kappa-fraction 0.9`) extends the branch and is delivered; a value
/// above `kappa_c` of this supercritical onset is named with that reason in
/// JSON, text and CSV.
#[test]
fn requested_points_are_delivered_or_explained() {
    let dir = temp_dir("requested");
    let out = dir.to_str().unwrap();
    let (code, stdout, err) = stickslip(&[
        "cycles",
        "--kappa-fraction",
        "0.9",
        "--at-kappa",
        "0.0105,0.0095,0.02",
        "--out",
        out,
        "--json",
    ]);
    // 0.02 lies above kappa_c, where no cycle exists: not delivered, so the
    // request is incomplete (status 4), with the reason below.
    assert_eq!(code, 4, "{err}");
    assert!(
        err.contains("1 of the 3 requested stiffnesses not delivered"),
        "{err}"
    );
    // No number is missing (the run's `source` says `model: null` where the
    // model was not forced).
    let mut numbers: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    numbers.as_object_mut().unwrap().remove("source");
    let numbers = numbers.to_string();
    assert!(
        !numbers.contains("null") && !numbers.contains("NaN"),
        "{stdout}"
    );
    let v: Value = serde_json::from_str(&stdout).unwrap();
    let kappa_c = v["kappa_c"].as_f64().unwrap();
    // 0.0095 lies below the default lower end 0.9 kappa_c = 0.0099.
    assert!(0.0095 < 0.9 * kappa_c);
    for target in [0.0105, 0.0095] {
        let r = requested(&v, target);
        assert_eq!(r["delivered"], Value::Bool(true), "{r}");
        let cycles = v["cycles"].as_array().unwrap();
        let hit = cycles
            .iter()
            .filter(|c| c["user_point"] == Value::Bool(true))
            .find(|c| (c["kappa"].as_f64().unwrap() / target - 1.0).abs() < 1e-6)
            .unwrap_or_else(|| panic!("no user point at {target}"));
        let k = hit["kappa"].as_f64().unwrap();
        assert!(
            within_one_ulp(k, target),
            "kappa {target:e} asked, {k:e} in the JSON"
        );
    }
    let above = requested(&v, 0.02);
    assert_eq!(above["delivered"], Value::Bool(false));
    let why = above["reason"].as_str().unwrap();
    assert!(why.contains("above kappa_c = 1.1000000000e-2"), "{why}");
    let csv = std::fs::read_to_string(dir.join("pmma-cycles.csv")).unwrap();
    assert!(
        csv.contains("# requested kappa = 2.000000000000000e-2 not delivered: above kappa_c"),
        "{csv}"
    );
    let (code, text, err) = stickslip(&[
        "cycles",
        "--kappa-fraction",
        "0.9",
        "--at-kappa",
        "0.02",
        "--out",
        out,
        // The same run as above, as text: its files are replaced.
        "--force",
    ]);
    assert_eq!(code, 4, "{err}");
    assert!(
        text.contains(
            "requested kappa = 2.0000000000e-2 (K/W = 5.00000000e4 1/m): not delivered: above kappa_c"
        ),
        "{text}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// A branch cut short by the step limit names where it stopped for a value
/// it did not reach.
#[test]
fn a_value_past_the_end_of_a_short_branch_says_where_it_stopped() {
    let dir = temp_dir("requested-short");
    let (code, stdout, err) = stickslip(&[
        "cycles",
        "--max-steps",
        "5",
        "--at-kappa",
        "0.0095",
        "--out",
        dir.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(code, 4, "{err}"); // a step-limited branch: partial
    let v: Value = serde_json::from_str(&stdout).unwrap();
    let r = requested(&v, 0.0095);
    assert_eq!(r["delivered"], Value::Bool(false));
    let why = r["reason"].as_str().unwrap();
    let smallest = v["cycles"]
        .as_array()
        .unwrap()
        .iter()
        .map(|c| c["kappa"].as_f64().unwrap())
        .fold(f64::INFINITY, f64::min);
    assert!(
        smallest > 0.0095,
        "the short branch should not reach 0.0095 (smallest {smallest})"
    );
    assert!(
        why.contains("the branch stopped at kappa")
            && why.contains(&format!("{smallest:.10e}"))
            && why.contains("step limit: 5 continuation steps (--max-steps)"),
        "{why}"
    );
    std::fs::remove_dir_all(&dir).ok();
}
