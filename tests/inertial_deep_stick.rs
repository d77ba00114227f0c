//! The inertial block with a small direct effect (docs/hard-cases.md, "An
//! inertial stick phase slower than f64 can relax"): `cycles --model inertial
//! --set A=1e-4 --set B=0.011 --set m=1e-6` through the job the command runs
//! ([`stickslip::jobs::cycles`]): collocation to where the stick falls
//! below what it resolves, the return map of the joined inertial and
//! quasi-static flow from there to the end of the range. The deepest
//! collocated cycle is checked against an independent integration of the
//! same scene at the same stiffness ([`stickslip::jobs::simulate`], Radau
//! IIA) and against the return map's cycle there; the return map's cycles
//! do not depend on where the flow switches models.

use stickslip::analysis::cycles::CycleMethod;
use stickslip::analysis::joined_flow::JoinedFlow;
use stickslip::analysis::return_map::{fixed_point, section_guess, RTOL};
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

/// Issue 22, item 7, third case: the branch goes past the stick velocity
/// collocation resolves (`v_min` near 1e-52, where the block's stop into
/// the stick is a drop of 52 decades in a time below the rounding of `t`) by
/// the return map, to the end of the requested range (`kappa_fraction`
/// 0.5 of `kappa_c`), sticks deeper than 1e-500 `V0`, exit status 0. The
/// deepest collocated cycle is the cycle an integration at its stiffness
/// settles on (period and force drop to 1e-6), and the return map's cycle
/// at that stiffness is the collocated one (to 1e-9).
#[test]
fn the_deep_stick_branch_reaches_the_end_of_its_range_by_the_return_map() {
    let mut result = cycles::Plan::new(&spec(&[]), CyclesRequest::default())
        .expect("the plan")
        .run(&mut Quiet);
    assert!(result.complete, "stop: {}", result.stop);
    result.status().expect("the whole branch");
    let (collocated, mapped): (Vec<_>, Vec<_>) = result
        .records
        .iter()
        .partition(|r| matches!(r.method, CycleMethod::Collocation { .. }));
    assert!(
        mapped.len() > 20,
        "{} cycles of the return map",
        mapped.len()
    );
    let last = mapped.last().unwrap();
    let kappa_c = result.kappa_c.expect("from the Hopf point");
    assert!(
        (last.kappa - 0.5 * kappa_c).abs() <= 1e-12 * kappa_c,
        "ends at kappa = {:e}, kappa_c = {kappa_c:e}",
        last.kappa
    );
    assert!(last.ln_v_min / std::f64::consts::LN_10 < -500.0);
    for r in &mapped {
        assert!(r.stability.is_stable() && r.error_estimate.unwrap() < 1e-8);
    }
    let deepest = (*collocated
        .iter()
        .min_by(|a, b| a.ln_v_min.total_cmp(&b.ln_v_min))
        .expect("collocated cycles"))
    .clone();
    assert!(deepest.v_min < 1e-50, "v_min = {:e}", deepest.v_min);

    // The return map at the deepest collocated cycle's stiffness.
    let params = spec(&[format!("kappa={:e}", deepest.kappa)])
        .setup(|p| *p)
        .expect("the scene")
        .params;
    let fp = fixed_point(
        &JoinedFlow::new(&params, RTOL),
        section_guess(&deepest, params.nu).expect("crosses v = nu"),
        100.0 * deepest.period,
    )
    .expect("the fixed point");
    let delta_s = fp.x[0] - fp.passage.s_min;
    eprintln!(
        "kappa = {:e}: return map period {} Delta_s {delta_s}, collocation {} {}",
        deepest.kappa, fp.passage.period, deepest.period, deepest.delta_s
    );
    assert!((fp.passage.period / deepest.period - 1.0).abs() < 1e-9);
    assert!((delta_s / deepest.delta_s - 1.0).abs() < 1e-9);

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

/// The return map's cycles do not depend on where the joined flow hands
/// the stick to the quasi-static model: with `v_b` a million times lower
/// (deeper into the stick, where inertia matters still less), the cycle at
/// the end of the range keeps its period and fixed point to 1e-9.
#[test]
fn the_return_maps_cycle_does_not_depend_on_the_switching_velocity() {
    let params = spec(&["kappa=0.006".into()])
        .setup(|p| *p)
        .expect("the scene")
        .params;
    let flow = JoinedFlow::new(&params, RTOL);
    let mut deeper = flow.clone();
    deeper.ln_v_b -= 6.0 * std::f64::consts::LN_10;
    // A start on the section from a passage of the flow itself.
    let start = flow.passage([0.5, 3.0], 1e4, false).expect("a passage").end;
    let a = fixed_point(&flow, start, 1e4).expect("the cycle");
    let b = fixed_point(&deeper, start, 1e4).expect("the cycle, switched deeper");
    eprintln!(
        "period {} vs {}, x {:?} vs {:?}, sticks {} {}",
        a.passage.period, b.passage.period, a.x, b.x, a.passage.sticks, b.passage.sticks
    );
    assert_eq!((a.passage.sticks, b.passage.sticks), (1, 1));
    assert!((a.passage.period / b.passage.period - 1.0).abs() < 1e-9);
    for k in 0..2 {
        assert!((a.x[k] - b.x[k]).abs() < 1e-9 * a.x[k].abs().max(1.0));
    }
    assert!(a.passage.chi_at_reentry < 1e-15 && b.passage.chi_at_reentry < 1e-21);
}

/// `simulate` on the same scene at `kappa = 0.008`, where the stick falls to
/// 1e-410 `V0`: the run goes through its sticks by the joined flow (each
/// below `v_b` integrated quasi-statically, rows marked so) to the end of
/// its protocol, and reports the regime it reaches, the return map's cycle.
/// The run's own trajectory (Radau IIA at rtol 1e-10, the stops located as
/// events) repeats with that period: the last two crossings of `v = nu`
/// upward, interpolated in `log10 v` between the accepted steps, lie one
/// period apart to 1e-6.
#[test]
fn simulate_goes_through_sticks_below_f64_and_agrees_with_the_return_map() {
    // 60 s at 1 µm/s: about nine periods.
    let protocol = vec![(1.0, 60.0)];
    let mut watch = Crossings::default();
    let sim = simulate::Plan::new(
        &spec(&["kappa=0.008".into()]),
        SimulateRequest {
            protocol: Some(protocol),
            rtol: 1e-10,
            ..SimulateRequest::default()
        },
    )
    .expect("the simulation plan")
    .run(&mut watch);
    let end = sim.end.as_ref().expect("the run reaches its end");
    assert!(end.sticks.count >= 8, "{} sticks", end.sticks.count);
    assert!(watch.quasi_static > 0 && watch.deepest < -400.0);
    let Some(RegimeReached::Periodic { period, .. }) = sim.regime else {
        panic!("no stick-slip regime: {:?}", sim.regime);
    };
    let n = watch.rising.len();
    assert!(n >= 4, "{n} crossings");
    let run_period = watch.rising[n - 1] - watch.rising[n - 2];
    eprintln!("regime period {period}, the run's last {run_period}");
    assert!((run_period / period - 1.0).abs() < 1e-6);
}

/// Crossings of `v = nu = 1` upward in a run, interpolated in `log10 v`;
/// rows of the quasi-static sticks; the lowest `log10 v`.
#[derive(Default)]
struct Crossings {
    last: Option<(f64, f64)>,
    rising: Vec<f64>,
    quasi_static: usize,
    deepest: f64,
}

impl simulate::Observer for Crossings {
    fn sample(&mut self, p: &stickslip::analysis::simulate::Sample) -> std::io::Result<()> {
        if let Some((t0, l0)) = self.last {
            if l0 < 0.0 && p.log10_v >= 0.0 {
                self.rising.push(t0 + (p.t - t0) * (-l0) / (p.log10_v - l0));
            }
        }
        self.last = Some((p.t, p.log10_v));
        self.quasi_static += usize::from(p.model == ModelKind::QuasiStatic);
        self.deepest = self.deepest.min(p.log10_v);
        Ok(())
    }
}

/// An observer of the simulation that watches nothing.
struct NoWatch;

impl simulate::Observer for NoWatch {}

/// The cycle at a scene's own stiffness where the stick falls below f64
/// (`kappa = 0.008`, sticks near 1e-410 `V0`): the stuck start settles by
/// the joined flow, and the cycle, which collocation cannot correct, is
/// the return map's; its period is that of an independent `simulate` run
/// (the time between the run's last crossings of `v = nu`) to 1e-6.
#[test]
fn the_cycle_at_the_scenes_stiffness_below_f64_is_the_return_maps() {
    let result = cycles::Plan::new(&spec(&["kappa=0.008".into()]), CyclesRequest::default())
        .expect("the plan")
        .run(&mut Quiet);
    let op = result.operating_point.as_ref().expect("the scene gives K");
    let cycle = op.cycle.as_ref().expect("the cycle at the scene's K");
    assert_eq!((cycle.method, cycle.ntst), ("return_map", None));
    assert!(
        cycle.log10_v_min < -400.0,
        "log10 v_min {}",
        cycle.log10_v_min
    );
    let run_period = simulated_period(&["kappa=0.008".into()], 0.01, 60.0);
    eprintln!("operating cycle {} vs the run's {run_period}", cycle.period);
    assert!((run_period / cycle.period - 1.0).abs() < 1e-6);
}

/// At a stiffness between the onset and the fold of cycles (bistable,
/// `kappa = 0.0111`) the cycle at the scene's K is the stable one, which
/// a run started far from steady sliding settles on (not the unstable
/// cycle bounding the basin of steady sliding, met first on the branch).
#[test]
fn a_bistable_scenes_cycle_is_the_stable_one_a_run_settles_on() {
    let result = cycles::Plan::new(&spec(&["kappa=0.0111".into()]), CyclesRequest::default())
        .expect("the plan")
        .run(&mut Quiet);
    let op = result.operating_point.as_ref().expect("the scene gives K");
    let cycle = op.cycle.as_ref().expect("the cycle at the scene's K");
    let run_period = simulated_period(&["kappa=0.0111".into()], 0.5, 120.0);
    eprintln!(
        "operating cycle {} ({:?}) vs the run's {run_period}",
        cycle.period, cycle.stable
    );
    assert!((run_period / cycle.period - 1.0).abs() < 1e-6);
}

/// The period (units `D0/V0`) a `simulate` run of `duration` seconds at
/// 1 µm/s from steady sliding with the age perturbed by `perturb` ends on:
/// the time between its last two crossings of `v = nu` upward.
fn simulated_period(set: &[String], perturb: f64, duration: f64) -> f64 {
    let mut watch = Crossings::default();
    let sim = simulate::Plan::new(
        &spec(set),
        SimulateRequest {
            protocol: Some(vec![(1.0, duration)]),
            perturb,
            rtol: 1e-10,
            ..SimulateRequest::default()
        },
    )
    .expect("the simulation plan")
    .run(&mut watch);
    assert!(sim.end.is_ok(), "the run: {:?}", sim.end.err());
    let n = watch.rising.len();
    assert!(n >= 3, "{n} crossings");
    watch.rising[n - 1] - watch.rising[n - 2]
}
