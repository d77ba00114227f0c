//! Driven sliding in time: velocity jumps and stop-and-go (seed §II.D.2),
//! and the samples handed over as they are computed.

mod common;

use std::ops::ControlFlow;
use stickslip::analysis::simulate::{simulate, simulate_with, Sample, Segment};
use stickslip::model::ModelKind;
use stickslip::params::Params;

fn law(mu2: f64) -> Params {
    Params {
        kappa: 10.0,
        nu: 1.0,
        m: 0.0,
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

fn steady(p: &Params, nu: f64) -> [f64; 3] {
    [p.friction().steady(nu), nu, 1.0 / nu]
}

#[test]
fn velocity_jump_direct_effect_and_relaxation_over_d0() {
    // Stiff spring (kappa = 10, about 1000 kappa_c): friction follows the imposed
    // velocity. The jump V -> 10 V raises it first by the direct effect A ln 10,
    // then it relaxes to the new steady value (A - B) ln 10 over a slip of order D0.
    let p = law(0.0);
    let (vi, vf) = (1.0, 10.0);
    let start = steady(&p, vi);
    let traj = simulate(
        ModelKind::QuasiStatic,
        &p,
        start,
        &[Segment {
            nu: vf,
            duration: 2.0,
        }],
        1e-10,
        None,
    )
    .unwrap();
    let rise: Vec<f64> = traj.s.iter().map(|s| s - start[0]).collect();
    let peak = rise.iter().copied().fold(f64::MIN, f64::max);
    let direct = p.a * (vf / vi).ln();
    assert!(
        (peak / direct - 1.0).abs() < 0.03,
        "peak {peak} vs A ln(Vf/Vi) = {direct}"
    );
    let final_ss = (p.a - p.b) * (vf / vi).ln();
    let excess = |slip: f64| {
        let i = traj.slip.iter().position(|&x| x >= slip).unwrap();
        (rise[i] - final_ss) / (peak - final_ss)
    };
    // Rigid-spring limit: at constant v = Vf the ageing law in slip x (units D0) gives
    // theta v - 1 = (Vf/Vi - 1) e^-x, so the excess friction B ln(theta v) falls as
    // ln(1 + 9 e^-x) / ln 10: the memory of the old state fades over a few D0.
    for x in [0.3f64, 1.0, 3.0] {
        let rigid = (1.0 + 9.0 * (-x).exp()).ln() / 10f64.ln();
        assert!(
            (excess(x) - rigid).abs() < 0.03,
            "after {x} D0: {} vs rigid-spring {rigid}",
            excess(x)
        );
    }
    assert!(
        excess(15.0).abs() < 1e-4,
        "relaxed after 15 D0: {}",
        excess(15.0)
    );
}

/// Slip after the drive stops, at reduced times `V t / D0`, starting from steady sliding at `nu`.
fn stop_and_go(p: &Params, nu: f64, reduced: &[f64]) -> Vec<f64> {
    let grid: Vec<f64> = reduced.iter().map(|r| r / nu).collect();
    let horizon = grid[grid.len() - 1];
    let traj = simulate(
        ModelKind::QuasiStatic,
        p,
        steady(p, nu),
        &[Segment {
            nu: 0.0,
            duration: horizon,
        }],
        1e-11,
        Some(&grid),
    )
    .unwrap();
    assert_eq!(traj.slip.len(), grid.len());
    traj.slip
}

#[test]
fn stop_and_go_relaxation_is_scale_invariant_only_for_the_plain_rr_law() {
    // Plain RR (quasi-static): with v = nu v', theta = theta'/nu, t = t'/nu the equations
    // after the stop do not depend on nu, so slip against V t / D0 is one curve.
    let reduced = [0.5, 2.0, 10.0, 50.0, 300.0];
    let rr = law(0.0);
    let (a, b) = (
        stop_and_go(&rr, 1.0, &reduced),
        stop_and_go(&rr, 10.0, &reduced),
    );
    for (x, y) in a.iter().zip(&b) {
        assert!((x / y - 1.0).abs() < 1e-7, "RR: slip {x} vs {y}");
    }
    assert!(
        a[4] > a[0] && a[4] > 0.0,
        "the block keeps creeping after the stop"
    );
    // With the ln² term the relaxation depends on the prior velocity (seed: 100 % per decade in experiments).
    let ln2 = law(2.4e-4);
    let (c, d) = (
        stop_and_go(&ln2, 1.0, &reduced),
        stop_and_go(&ln2, 10.0, &reduced),
    );
    assert!(
        (c[4] / d[4] - 1.0).abs() > 0.01,
        "ln²: {} vs {}",
        c[4],
        d[4]
    );
}

#[test]
fn samples_stream_in_order_and_the_sink_can_stop_the_run() {
    let p = Params {
        kappa: 0.009,
        ..law(2.4e-4)
    };
    let start = [p.friction().steady(1.0), 1.0, 1.01];
    let protocol = [
        Segment {
            nu: 1.0,
            duration: 50.0,
        },
        Segment {
            nu: 3.0,
            duration: 10.0,
        },
    ];
    let run = |grid: Option<&[f64]>, stop_after: usize| {
        let mut seen: Vec<Sample> = Vec::new();
        let end = simulate_with(
            ModelKind::QuasiStatic,
            &p,
            start,
            &protocol,
            1e-8,
            grid,
            |s| {
                seen.push(*s);
                if seen.len() == stop_after {
                    ControlFlow::Break(())
                } else {
                    ControlFlow::Continue(())
                }
            },
        )
        .unwrap();
        (end, seen)
    };
    let all = simulate(ModelKind::QuasiStatic, &p, start, &protocol, 1e-8, None).unwrap();
    // Every step once, in order, through the change of velocity at t = 50.
    assert!(all.t.windows(2).all(|w| w[1] > w[0]));
    assert!(all.t.contains(&50.0) && all.t.last() == Some(&60.0));
    let (end, seen) = run(None, usize::MAX);
    assert_eq!((end.stopped, end.t, end.t_end), (false, 60.0, 60.0));
    assert_eq!(seen.len(), all.t.len());
    // Stopped by the sink after 25 samples: the same samples, and where it stopped.
    let (end, seen) = run(None, 25);
    assert!(
        end.stopped && end.t == seen[24].t && end.t < 50.0,
        "{end:?}"
    );
    for (i, s) in seen.iter().enumerate() {
        assert_eq!(
            (s.t, s.s, s.v, s.slip),
            (all.t[i], all.s[i], all.v[i], all.slip[i])
        );
    }
    // On a grid: the grid times, stopping after 3 of them.
    let grid: Vec<f64> = (0..=12).map(|k| 5.0 * k as f64).collect();
    let (end, seen) = run(Some(&grid), usize::MAX);
    assert!(!end.stopped);
    assert_eq!(seen.iter().map(|s| s.t).collect::<Vec<_>>(), grid);
    let (end, seen) = run(Some(&grid), 3);
    assert!(end.stopped && end.t == 10.0 && seen.len() == 3, "{end:?}");
}

#[test]
fn a_stop_after_a_long_run_is_resolved_in_the_segment_own_time() {
    // Inertial PMMA block (m = 0.01) on a stiff spring stopped at t = 1e4:
    // it comes to rest within about 1e-11 time units, steps below the
    // rounding level of the absolute time there (10 eps t = 2.2e-11), which
    // failed with a step size underflow. Each segment is integrated from 0.
    let p = Params {
        m: 0.01,
        ..law(0.0)
    };
    let protocol = [
        Segment {
            nu: 1.0,
            duration: 1e4,
        },
        Segment {
            nu: 0.0,
            duration: 100.0,
        },
        Segment {
            nu: 1.0,
            duration: 10.0,
        },
    ];
    let traj = simulate(
        ModelKind::Inertial,
        &p,
        steady(&p, 1.0),
        &protocol,
        1e-8,
        None,
    )
    .unwrap();
    assert_eq!(traj.t.last().copied(), Some(1e4 + 110.0));
    let stopped = traj
        .t
        .iter()
        .zip(&traj.v)
        .filter(|(t, _)| (1e4 + 1.0..1e4 + 100.0).contains(*t))
        .map(|(_, v)| *v)
        .fold(0.0f64, f64::max);
    assert!(
        stopped < 1e-3,
        "fastest slip during the stop: v = {stopped:e}"
    );
}

/// Issue 22, item 7: `simulate --set nu=NU --set kappa=0.01 --protocol
/// NU:T` in one long segment (the PMMA scene driven at 1e-4, 1e-6 and 1e-7
/// um/s) failed after about 50 slips, at `t` near 2e7 D0/V0, where a slip's
/// steps (about 4e-8) reached the rounding of the absolute time `t`. The
/// integrator now keeps the time as a compensated sum: every run reaches
/// the protocol's end (exit 0, the last row at the end, no `# incomplete`),
/// and the period of the slips at nu = 1e-4 is the collocation cycle's at
/// kappa = 0.01 (`cycles --set nu=1e-4 --at-kappa 0.01`: 4.07516e5 D0/V0).
#[test]
fn a_long_single_segment_runs_to_its_end_past_the_rounding_of_t() {
    for (nu, seconds) in [("1e-4", 3e7), ("1e-6", 3e9), ("1e-7", 3e10)] {
        let dir = common::temp_dir(&format!("long_segment_{nu}"));
        let protocol = format!("{nu}:{seconds:e}");
        let (code, out, err) = common::stickslip(&[
            "simulate",
            "--set",
            &format!("nu={nu}"),
            "--set",
            "kappa=0.01",
            "--protocol",
            &protocol,
            "--name",
            "long",
            "--out",
            dir.to_str().unwrap(),
        ]);
        // At 1e-7 um/s the run switches to the inertial model and its sticks
        // fall below v_b: the regime it reaches is the return map's cycle
        // (2026-11-27; before, no extremum of s was located over the
        // settled cycle and the regime was undetermined, status 4); its
        // period is checked against the run's own slips below.
        assert_eq!(code, 0, "nu = {nu}: {err}");
        let csv = std::fs::read_to_string(dir.join("long-simulation.csv")).unwrap();
        assert!(!csv.contains("# incomplete"), "nu = {nu}");
        let rows: Vec<Vec<f64>> = csv
            .lines()
            .filter(|l| l.starts_with(|c: char| c.is_ascii_digit()))
            .map(|l| l.split(',').take(7).map(|x| x.parse().unwrap()).collect())
            .collect();
        let last = rows.last().unwrap();
        assert_eq!(last[0], seconds, "nu = {nu}: the last row's time in s");
        // Slips: log10 v rising through log10 nu + 2 (column 7).
        let threshold = nu.parse::<f64>().unwrap().log10() + 2.0;
        let slips: Vec<f64> = rows
            .windows(2)
            .filter(|w| w[0][6] < threshold && w[1][6] >= threshold)
            .map(|w| w[1][1])
            .collect();
        assert!(slips.len() > 60, "nu = {nu}: {} slips", slips.len());
        if nu == "1e-4" {
            let n = slips.len();
            let period = (slips[n - 1] - slips[n - 11]) / 10.0;
            assert!(
                (period / 4.07516e5 - 1.0).abs() < 1e-4,
                "period {period:e} D0/V0 of the last ten slips"
            );
        }
        if nu == "1e-7" {
            // The regime's period in s against the run's last ten slips
            // (column 0, seconds).
            let slips_s: Vec<f64> = rows
                .windows(2)
                .filter(|w| w[0][6] < threshold && w[1][6] >= threshold)
                .map(|w| w[1][0])
                .collect();
            let n = slips_s.len();
            let run = (slips_s[n - 1] - slips_s[n - 11]) / 10.0;
            let at = out.find("stick-slip, period ").expect("the regime") + 19;
            let regime: f64 = out[at..].split(' ').next().unwrap().parse().unwrap();
            assert!(
                (run / regime - 1.0).abs() < 1e-4,
                "run {run:e} s, regime {regime:e} s"
            );
        }
        let _ = std::fs::remove_dir_all(&dir);
    }
}

/// `simulate` names the regime the run reaches: below the onset the stick-slip
/// cycle with its period in s, force drop and slip per event; the same cycle
/// located by collocation (`cycles --at-kappa`, a second method) gives the
/// same period and `Delta_s` to 1e-6. Above the (supercritical) onset the
/// oscillation decays onto steady sliding.
#[test]
fn simulate_reports_the_regime_it_reaches() {
    let dir = std::env::temp_dir().join(format!("stickslip-regime-{}", std::process::id()));
    let out = dir.to_str().unwrap();
    let number_after = |text: &str, key: &str| -> f64 {
        let at = text
            .find(key)
            .unwrap_or_else(|| panic!("no '{key}' in {text}"))
            + key.len();
        text[at..]
            .split(|c: char| c.is_whitespace() || c == ',' || c == ')')
            .find(|w| !w.is_empty())
            .and_then(|w| w.parse().ok())
            .unwrap_or_else(|| panic!("no number after '{key}' in {text}"))
    };
    let (code, text, err) = common::stickslip(&[
        "cycles",
        "--json",
        "--at-kappa",
        "0.009",
        "--out",
        out,
        "--force",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&text).unwrap();
    let cycle = v["cycles"]
        .as_array()
        .unwrap()
        .iter()
        .find(|c| c["user_point"].as_bool() == Some(true) || c["user_point"].is_object())
        .expect("the cycle at kappa = 0.009")
        .clone();
    let (period, period_s, delta_s) = (
        cycle["period"].as_f64().unwrap(),
        cycle["period_s"].as_f64().unwrap(),
        cycle["delta_s"].as_f64().unwrap(),
    );
    let run = |units: &str| {
        let (code, text, err) = common::stickslip(&[
            "simulate",
            "--set",
            "kappa=0.009",
            "--protocol",
            "1:500",
            "--out",
            out,
            "--force",
            "--units",
            units,
        ]);
        assert_eq!(code, 0, "{err}");
        text.lines()
            .find(|l| l.starts_with("regime reached"))
            .unwrap_or_else(|| panic!("no regime line in {text}"))
            .to_string()
    };
    let close = |a: f64, b: f64| (a / b - 1.0).abs() < 1e-6;
    let line = run("dimensionless");
    assert!(line.contains("stick-slip"), "{line}");
    let p = number_after(&line, "period ");
    assert!(close(p, period), "{p} vs {period}: {line}");
    let d = number_after(&line, "Delta_s = ");
    assert!(close(d, delta_s), "{d} vs {delta_s}: {line}");
    // nu = 1: the slip per event is the drive's advance over one period.
    assert!(
        close(number_after(&line, "slip per event "), period),
        "{line}"
    );
    let line = run("physical");
    let ps = number_after(&line, "period ");
    assert!(close(ps, period_s), "{ps} s vs {period_s} s: {line}");
    assert!(line.contains(" N (Delta_s"), "{line}");
    let (code, text, err) = common::stickslip(&[
        "simulate",
        "--set",
        "kappa=0.012",
        "--protocol",
        "1:200",
        "--out",
        out,
        "--force",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        text.contains("steady sliding (the oscillation decays)"),
        "{text}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The default protocol of the granite rig (40 D0/V0 = 400 s) covers 0.90
/// of the 442 s period of the stick-slip it reaches: the text says so and
/// gives a protocol that covers three periods, which then shows them
/// without the hint.
#[test]
fn a_run_shorter_than_its_regimes_period_says_how_long_to_run() {
    let dir = common::temp_dir("simulate-short");
    let scene = dir.join("granite.toml");
    std::fs::write(&scene, common::GRANITE).unwrap();
    let out = dir.join("out");
    let run = |protocol: &[&str]| {
        let args = [
            &[
                "simulate",
                "--scene",
                scene.to_str().unwrap(),
                "--force",
                "--out",
            ][..],
            &[out.to_str().unwrap()],
            protocol,
        ]
        .concat();
        let (status, text, stderr) = common::stickslip(&args);
        assert_eq!(status, 0, "{stderr}");
        text
    };
    let text = run(&[]);
    assert!(text.contains("period 4.42129"), "{text}");
    assert!(text.contains("covers 0.90 of its periods"), "{text}");
    assert!(text.contains("e.g. 1:1327 for 3 periods"), "{text}");
    let text = run(&["--protocol", "1:1327"]);
    assert!(text.contains("period 4.42129"), "{text}");
    assert!(!text.contains("of its periods"), "{text}");
}

/// A run with `--protocol` starts from steady sliding at the protocol's
/// first velocity and never pulls at the scene's own V: the model is chosen
/// at the protocol's fastest velocity, and the run does not depend on the
/// scene's V (session-18 stranger: `--set nu=10 --protocol 1:400` said the
/// protocol's fastest velocity was 10 um/s and ran the inertial model).
#[test]
fn a_protocol_run_does_not_depend_on_the_scenes_own_velocity() {
    let run = |extra: &[&str]| {
        let dir = common::temp_dir(&format!("protocol_top_{}", extra.len()));
        let mut args = vec!["simulate", "--json", "--set", "kappa=0.01"];
        args.extend_from_slice(extra);
        args.extend_from_slice(&["--protocol", "1:400", "--name", "run", "--out"]);
        args.push(dir.to_str().unwrap());
        let (code, out, err) = common::stickslip(&args);
        assert_eq!(code, 0, "{err}");
        let json: serde_json::Value = serde_json::from_str(&out).unwrap();
        let csv = std::fs::read_to_string(dir.join("run-simulation.csv")).unwrap();
        (json, csv)
    };
    let (scene_v, csv_scene_v) = run(&[]);
    let (fast_v, csv_fast_v) = run(&["--set", "nu=10"]);
    let reason = fast_v["model_reason"].as_str().unwrap();
    assert!(
        reason.contains("fastest pulling velocity, 1.0000e0 µm/s"),
        "{reason}"
    );
    assert_eq!(scene_v["model"], fast_v["model"]);
    assert!(scene_v["regime"]["period_s"].is_f64());
    assert_eq!(scene_v["regime"], fast_v["regime"]);
    // Every row of the run, but for the file's header naming the scene.
    let rows = |csv: &str| -> Vec<String> {
        csv.lines()
            .filter(|l| l.starts_with(|c: char| c.is_ascii_digit()))
            .map(str::to_owned)
            .collect()
    };
    assert_eq!(rows(&csv_scene_v), rows(&csv_fast_v));
}
