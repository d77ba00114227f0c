//! The inertial block with a small direct effect (docs/hard-cases.md, "An
//! inertial stick phase slower than f64 can relax"): `cycles --model inertial
//! --set A=1e-4 --set B=0.011 --set m=1e-6` through the job the command runs
//! ([`stickslip::jobs::cycles`]), its deepest cycle checked against an
//! independent integration of the same scene at the same stiffness
//! ([`stickslip::jobs::simulate`], Radau IIA).

use stickslip::analysis::simulate::RegimeReached;
use stickslip::jobs::cycles::{self, CyclesRequest, Quiet};
use stickslip::jobs::simulate::{self, SimulateRequest};
use stickslip::jobs::SceneSpec;
use stickslip::model::ModelKind;

fn spec(extra: &[String]) -> SceneSpec {
    let mut set: Vec<String> = ["A=1e-4", "B=0.011", "m=1e-6"]
        .iter()
        .map(|s| s.to_string())
        .collect();
    set.extend_from_slice(extra);
    SceneSpec {
        set,
        model: Some(ModelKind::Inertial),
        ..SceneSpec::named("pmma")
    }
}

/// What stands (issue 22, item 7, third case): with the force balance
/// collocated in its implicit form `m v d(ln v)/dt = s - mu` and Newton's
/// rises of `ln v` taken as steps in `v`, the branch goes on past
/// `v_min = 6e-42` (where rounding amplified by `A/(m v)` ended it) and past
/// `1e-50`; it still ends where the block's stop into the stick (52 decades
/// of `v` in a time no mesh resolves) leaves `ln v` ill-determined, as a
/// partial result (exit status 4) that says so and keeps the cycles. The
/// deepest cycle is the stick-slip cycle an integration at its stiffness
/// settles on: the same period and force drop.
#[test]
fn the_deepest_inertial_stick_goes_past_f64_rates_and_matches_a_simulation() {
    let mut result = cycles::Plan::new(&spec(&[]), CyclesRequest::default())
        .expect("the plan")
        .run(&mut Quiet);
    let deepest = result
        .records
        .iter()
        .min_by(|a, b| a.v_min.total_cmp(&b.v_min))
        .expect("cycles")
        .clone();
    assert!(
        deepest.v_min < 1e-50,
        "deepest stick v_min = {:e} after {} cycles",
        deepest.v_min,
        result.records.len()
    );
    assert!(!result.complete);
    let failure = result.status().expect_err("a partial branch");
    assert_eq!(failure.exit_code(), 4, "{failure}");
    let text = failure.to_string();
    for words in ["comes to rest", "ill-determined", "--model quasi-static"] {
        assert!(text.contains(words), "{words}: {text}");
    }

    // An integration started far from steady sliding (which is stable at
    // this stiffness, above kappa_c) settles on the cycle.
    let kappa = deepest.kappa;
    let simulation = simulate::Plan::new(
        &spec(&[format!("kappa={kappa:e}")]),
        SimulateRequest {
            perturb: 0.5,
            ..SimulateRequest::default()
        },
    )
    .expect("the simulation plan")
    .run(&mut NoWatch);
    let Some(RegimeReached::Periodic {
        period, delta_s, ..
    }) = simulation.regime
    else {
        panic!("no stick-slip regime: {:?}", simulation.regime);
    };
    let (dt, ds) = (
        (period / deepest.period - 1.0).abs(),
        (delta_s / deepest.delta_s - 1.0).abs(),
    );
    eprintln!(
        "kappa = {kappa:e}: period {period} vs {}, delta_s {delta_s} vs {}",
        deepest.period, deepest.delta_s
    );
    assert!(
        dt < 1e-6,
        "period {period} vs the branch's {}",
        deepest.period
    );
    assert!(
        ds < 1e-6,
        "Delta_s {delta_s} vs the branch's {}",
        deepest.delta_s
    );
}

/// An observer of the simulation that watches nothing.
struct NoWatch;

impl simulate::Observer for NoWatch {}
