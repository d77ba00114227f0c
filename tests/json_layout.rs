//! One JSON layout across the commands (issue 24): every job's JSON has
//! the scene, its parameters, a `units` block (the scene's D0 in µm and V0
//! in µm/s, from which each dimensionless value beside a physical one
//! converts), `complete` and `stop` — for the rig of docs/index.md §6 and
//! for a scene without a stiffness.

use serde_json::Value;
use stickslip::analysis::axes::Axes;
use stickslip::analysis::control::Control;
use stickslip::error::Error;
use stickslip::jobs::branch::BranchRequest;
use stickslip::jobs::cycles::{CyclesRequest, Quiet};
use stickslip::jobs::cycles_in::CyclesInControlRequest;
use stickslip::jobs::diagram::DiagramRequest;
use stickslip::jobs::hopf::HopfRequest;
use stickslip::jobs::simulate::SimulateRequest;
use stickslip::jobs::{self, SceneSpec};
use stickslip::records::branch::BranchRow;

const RIG: &str = "examples/scenes/rig.toml";

/// The rig's scales: D0 = 0.4 µm, V0 = 1 µm/s.
fn assert_layout(command: &str, json: &Value, complete: bool) {
    let units = &json["units"];
    assert!(
        (units["D0_um"].as_f64().unwrap() - 0.4).abs() < 1e-15
            && units["V0_um_per_s"].as_f64() == Some(1.0),
        "{command}: units {units}"
    );
    assert_eq!(json["complete"].as_bool(), Some(complete), "{command}");
    assert!(
        if complete {
            json["stop"].is_null() || json["stop"].is_string()
        } else {
            json["stop"].as_str().is_some_and(|s| !s.is_empty())
        },
        "{command}: stop {}",
        json["stop"]
    );
    assert!(json["scene"].is_string(), "{command}: scene");
    assert!(json["params"]["kappa"].is_number() || json["params"]["kappa"].is_null());
}

struct Rows;
impl jobs::branch::Observer for Rows {
    fn point(&mut self, _row: &BranchRow) -> Result<(), Error> {
        Ok(())
    }
}

#[test]
fn every_command_has_units_complete_and_stop() {
    let rig = SceneSpec::named(RIG);

    let hopf = jobs::hopf::run(&rig, &HopfRequest::default()).unwrap();
    assert_layout("hopf", &serde_json::to_value(&hopf.report).unwrap(), true);
    let in_v = HopfRequest {
        param: Control::from_param(Some("V")).unwrap(),
        ..HopfRequest::default()
    };
    let hopf_v = jobs::hopf::run(&rig, &in_v).unwrap();
    assert_layout(
        "hopf --param V",
        &serde_json::to_value(&hopf_v.report).unwrap(),
        true,
    );

    let request = BranchRequest {
        param: Control::from_param(Some("V")).unwrap().unwrap(),
        from: Some(100.0),
        to: Some(300.0),
        max_steps: 2000,
    };
    let branch = jobs::branch::Plan::new(&rig, &request)
        .unwrap()
        .run(&mut Rows);
    assert_layout("branch", &serde_json::to_value(&branch).unwrap(), true);
    let short = BranchRequest {
        max_steps: 2,
        ..request
    };
    let branch = jobs::branch::Plan::new(&rig, &short)
        .unwrap()
        .run(&mut Rows);
    assert_layout(
        "branch --max-steps 2",
        &serde_json::to_value(&branch).unwrap(),
        false,
    );

    let request = DiagramRequest {
        nu_range: None,
        max_steps: stickslip::analysis::diagram::DEFAULT_CURVE_STEPS,
    };
    let diagram = jobs::diagram::run_with(&continuation::AsIs, &rig, &request).unwrap();
    assert_layout("diagram", &diagram.to_json(), true);
    let axes = Axes::parse(Some("M"), Some("V")).unwrap().unwrap();
    let pair = jobs::diagram::run_pair(&rig, axes, None, None, &request).unwrap();
    assert_layout("diagram --x M --y V", &pair.to_json(), true);

    let cycles = jobs::cycles::Plan::new(
        &rig,
        CyclesRequest {
            kappa_fraction: 0.9,
            ..CyclesRequest::default()
        },
    )
    .unwrap()
    .run(&mut Quiet);
    assert_layout("cycles", &serde_json::to_value(&cycles).unwrap(), true);

    let request = CyclesInControlRequest {
        control: Control::from_param(Some("V")).unwrap().unwrap(),
        to: 150.0,
        search: None,
        at: Vec::new(),
        from_simulation: false,
        max_steps: 500,
        ntst: 40,
        ntst_max: 1280,
        collocation: None,
        from: None,
    };
    let in_v = jobs::cycles_in::Plan::new(&rig, &request)
        .unwrap()
        .run(&mut Quiet)
        .unwrap();
    assert_layout(
        "cycles --param V",
        &serde_json::to_value(&in_v).unwrap(),
        true,
    );

    let request = SimulateRequest {
        protocol: Some(vec![(10.0, 60.0)]),
        ..SimulateRequest::default()
    };
    let sim = jobs::simulate::Plan::new(&rig, request.clone())
        .unwrap()
        .run(&mut NoSamples);
    // Sixty seconds are two periods of the rig's 25 s cycle: whole, and the
    // regime reached from its end.
    assert_layout("simulate", &sim.to_json(), true);
    let short = SimulateRequest {
        max_steps: 10,
        ..request
    };
    let sim = jobs::simulate::Plan::new(&rig, short)
        .unwrap()
        .run(&mut NoSamples);
    assert_layout("simulate --max-steps 10", &sim.to_json(), false);
}

struct NoSamples;
impl jobs::simulate::Observer for NoSamples {}
