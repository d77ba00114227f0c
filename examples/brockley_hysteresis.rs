//! Hysteresis of a subcritical (Brockley-type) stick-slip onset, by
//! simulation: the stiffness is lowered and then raised again in slow steps,
//! the state carried over from step to step, and the peak-to-peak spring
//! force `Delta_s` recorded at each (0 for steady sliding).
//!
//! Friction of the `brockley` scene (cutoff ageing, V_min = 100 V0) at
//! `nu = 90` with a heavy block, `m = 1e-3`: the Hopf point is subcritical,
//! so on the way down steady sliding holds until `kappa_c` and then jumps to
//! large stick-slip; on the way up stick-slip persists until the fold of
//! cycles (LPC), where it jumps back to steady sliding. Both jump
//! stiffnesses are compared with `kappa_c` (continuation of steady sliding)
//! and the LPC (continuation of the cycles from a simulated orbit).
//!
//! Writes `docs/figures/brockley-hysteresis.png` and `.svg`.
//!
//! Run: `cargo run --release --example brockley_hysteresis`

use plotters::style::RGBColor;
use std::path::Path;
use stickslip::analysis::cycles::{
    along_branch, trace_cycles_from_orbit, CycleRecord, CycleRequest,
};
use stickslip::analysis::hopf::{find_hopf, HopfOutcome};
use stickslip::analysis::model_choice::DEFAULT_INERTIA_THRESHOLD;
use stickslip::analysis::orbit_inertia::InertiaWatch;
use stickslip::analysis::settle::{settle, stuck_start, SettleSettings};
use stickslip::analysis::simulate::{simulate, Segment};
use stickslip::model::ModelKind;
use stickslip::params::Params;
use stickslip::plot::lines::{render, LineFigure, Series};

const KIND: ModelKind = ModelKind::Inertial;
/// Stiffness range and step of the sweep.
const KAPPA_HIGH: f64 = 0.50;
const KAPPA_LOW: f64 = 0.34;
const STEP: f64 = 0.004;
/// Each stiffness is integrated in pieces of [`PIECE`] (units `D0/V0`)
/// until `Delta_s` changes by less than [`SETTLED`] (relative) from one piece
/// to the next, at most [`MAX_PIECES`] of them (1e4, about 33 000 periods).
/// Steady sliding gains or loses stability slowly here: its growth rate is
/// `Re lambda = 7.8e-3 (kappa_c - kappa)` near `kappa_c`, an e-folding time
/// of 1.3e4 at `kappa_c - 0.01`, so below `kappa_c` every step runs to the
/// limit until the oscillation has grown.
const PIECE: f64 = 50.0;
const MAX_PIECES: usize = 200;
const SETTLED: f64 = 1e-4;
/// Relative tolerance of the integration: at `1e-9` Radau IIA's steps grow
/// to a fraction of the period and damp the slowly growing oscillation
/// (see `analysis::settle`); at `1e-12` they stay near a thirteenth of it.
const RTOL: f64 = 1e-12;
/// Inertial periods `2 pi sqrt(m/kappa)` at the end of each step over which
/// `Delta_s` is measured.
const WINDOW: f64 = 20.0;
/// `Delta_s` above this is stick-slip (the cycles have `Delta_s` of 2 to 3);
/// below it, steady sliding or an oscillation still growing or decaying.
const STICK_SLIP: f64 = 1.0;
/// `Delta_s` below this is steady sliding to rounding, reported as 0.
const ROUNDING: f64 = 1e-9;
/// Relative kick to the age at the start of every step: the noise of a real
/// experiment, without which an unstable steady state, met exactly, is kept.
const KICK: f64 = 1e-3;

fn params(kappa: f64) -> Params {
    Params {
        kappa,
        nu: 90.0,
        m: 1e-3,
        a: 0.012,
        b: 0.023,
        mu0: 0.5,
        mu2: 0.0,
        theta_c: Some((0.023 - 0.012) / (0.012 * 100.0)),
        state_law: Default::default(),
        mu_vv: 0.0,
        mu_vphi: 0.0,
        eta_d: 0.0,
    }
}

/// `(kappa, Delta_s)` along a sweep.
type Sweep = Vec<(f64, f64)>;

/// One quasi-static step: from `state` (age kicked by [`KICK`]), integrate
/// at `kappa` piece by piece until `Delta_s` has settled.
fn step(kappa: f64, state: [f64; 3]) -> Result<(f64, [f64; 3]), Box<dyn std::error::Error>> {
    let mut state = [state[0], state[1], state[2] * (1.0 + KICK)];
    let mut last = f64::INFINITY;
    for _ in 0..MAX_PIECES {
        let (delta_s, next) = piece(kappa, state)?;
        state = next;
        if (delta_s - last).abs() <= SETTLED * delta_s {
            break;
        }
        last = delta_s;
    }
    Ok((last, state))
}

/// Integrates [`PIECE`] at `kappa` from `state`; the peak-to-peak spring
/// force over the last [`WINDOW`] inertial periods (dense output, 200 points
/// a period) and the final state.
fn piece(kappa: f64, state: [f64; 3]) -> Result<(f64, [f64; 3]), Box<dyn std::error::Error>> {
    let p = params(kappa);
    let window = WINDOW * 2.0 * std::f64::consts::PI * (p.m / kappa).sqrt();
    let n = 200 * WINDOW as usize;
    let grid: Vec<f64> = (0..=n)
        .map(|i| PIECE - window * (1.0 - i as f64 / n as f64))
        .collect();
    let segment = Segment {
        nu: p.nu,
        duration: PIECE,
    };
    let tail = simulate(KIND, &p, state, &[segment], RTOL, Some(&grid))?;
    let (lo, hi) = tail
        .s
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), s| {
            (a.min(*s), b.max(*s))
        });
    let last = tail.s.len() - 1;
    Ok((hi - lo, [tail.s[last], tail.v[last], tail.theta[last]]))
}

/// Sweeps through `kappas` from `state`; returns `(kappa, Delta_s)` and the final state.
fn sweep(
    kappas: &[f64],
    mut state: [f64; 3],
) -> Result<(Sweep, [f64; 3]), Box<dyn std::error::Error>> {
    let mut out = Vec::new();
    for &kappa in kappas {
        let (delta_s, next) = step(kappa, state)?;
        out.push((kappa, if delta_s < ROUNDING { 0.0 } else { delta_s }));
        state = next;
    }
    Ok((out, state))
}

/// The stiffnesses between which the sweep changed regime (from steady to
/// stick-slip or back).
fn jump(sweep: &[(f64, f64)]) -> Option<(f64, f64)> {
    sweep
        .windows(2)
        .find(|w| (w[0].1 > STICK_SLIP) != (w[1].1 > STICK_SLIP))
        .map(|w| (w[0].0, w[1].0))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let n = ((KAPPA_HIGH - KAPPA_LOW) / STEP).round() as usize;
    let down: Vec<f64> = (0..=n).map(|i| KAPPA_HIGH - STEP * i as f64).collect();
    let up: Vec<f64> = down.iter().rev().copied().collect();

    // Continuation: the Hopf point of steady sliding, and the cycles through a
    // simulated orbit at a stiffness where they coexist with steady sliding.
    let HopfOutcome::Found(hopf) = find_hopf(KIND, &params(KAPPA_HIGH))? else {
        return Err("no Hopf point: these parameters should have one".into());
    };
    let p = params(0.45);
    let orbit = settle(KIND, &p, stuck_start(&p), &SettleSettings::for_params(&p))?;
    let req = CycleRequest {
        kappa_min: KAPPA_LOW,
        kappa_max: KAPPA_HIGH,
        max_steps: 60,
        ntst: 40,
        at_kappa: Vec::new(),
        ntst_max: 1600,
        collocation: None,
    };
    let mut cycles: Vec<CycleRecord> = Vec::new();
    let watch = InertiaWatch::new(&p, DEFAULT_INERTIA_THRESHOLD, false);
    let legs = trace_cycles_from_orbit(KIND, &p, &orbit, &req, &watch, |c: &CycleRecord| {
        cycles.push(c.clone());
        Ok(())
    })?;
    for leg in legs.iter().filter_map(|l| l.1.as_ref().err()) {
        println!("a continuation leg ended: {leg}");
    }
    let lpc = cycles
        .iter()
        .find_map(|c| c.lpc.as_deref())
        .map(|l| l.kappa);

    // The sweeps: down from steady sliding (age perturbed by 1 %), then back up.
    let steady = params(KAPPA_HIGH).friction().steady(90.0);
    let (down_sweep, state) = sweep(&down, [steady, 90.0, 1.01 / 90.0])?;
    let (up_sweep, _) = sweep(&up, state)?;

    println!("kappa     Delta_s (down)   Delta_s (up)");
    for ((k, d), (_, u)) in down_sweep.iter().zip(up_sweep.iter().rev()) {
        println!("{k:.3}  {d:>14.6e}  {u:>14.6e}");
    }
    println!(
        "critical stiffness kappa_c = {:.8} (continuation; l1 = {:.3e}, {})",
        hopf.kappa_c,
        hopf.onset.l1,
        hopf.onset.criticality.name()
    );
    match lpc {
        Some(k) => println!("fold of cycles (LPC)  kappa = {k:.8} (continuation)"),
        None => println!("fold of cycles (LPC) not located by the continuation"),
    }
    if let Some((a, b)) = jump(&down_sweep) {
        println!("way down: steady sliding jumps to stick-slip between kappa = {a:.3} and {b:.3}");
    }
    if let Some((a, b)) = jump(&up_sweep) {
        println!("way up:   stick-slip jumps to steady sliding between kappa = {a:.3} and {b:.3}");
    }
    figure(&down_sweep, &up_sweep, &cycles, hopf.kappa_c, lpc)
}

/// Delta_s against kappa: both sweeps, the continued cycles (stable solid,
/// unstable dashed), and the two bifurcation stiffnesses.
fn figure(
    down: &[(f64, f64)],
    up: &[(f64, f64)],
    cycles: &[CycleRecord],
    kappa_c: f64,
    lpc: Option<f64>,
) -> Result<(), Box<dyn std::error::Error>> {
    let grey = RGBColor(120, 120, 120);
    let top = down
        .iter()
        .chain(up)
        .map(|p| p.1)
        .chain(cycles.iter().map(|c| c.delta_s))
        .fold(0.0f64, f64::max)
        * 1.35; // room above the curves for the legend
    let line = |label: &str, points: Vec<(f64, f64)>, color, dashed, markers| Series {
        label: Some(label.to_string()),
        points,
        color,
        dashed,
        markers,
    };
    // Each branch ends at the located fold, the cycle where they meet
    // (between the last continued cycle of one and the first of the other).
    let ordered = along_branch(cycles);
    let fold = cycles.iter().find_map(|c| c.lpc.as_deref());
    let branch = |stable: bool| -> Vec<(f64, f64)> {
        let mut points = Vec::new();
        for (i, c) in ordered.iter().enumerate() {
            let turns = ordered
                .get(i + 1)
                .is_some_and(|d| d.stability.is_stable() != c.stability.is_stable());
            if c.stability.is_stable() == stable {
                points.push((c.kappa, c.delta_s));
                if let (true, Some(f)) = (turns, fold) {
                    points.push((f.kappa, f.delta_s));
                }
            } else if let (true, Some(f)) = (turns, fold) {
                points.push((f.kappa, f.delta_s));
            }
        }
        points
    };
    let mut series = vec![
        line(
            "stable cycles (continuation)",
            branch(true),
            RGBColor(31, 90, 180),
            false,
            false,
        ),
        line(
            "unstable cycles (continuation)",
            branch(false),
            RGBColor(200, 40, 40),
            true,
            false,
        ),
        line(
            "simulation, stiffness decreasing",
            down.to_vec(),
            RGBColor(20, 150, 60),
            false,
            true,
        ),
        line(
            "simulation, stiffness increasing",
            up.to_vec(),
            RGBColor(230, 130, 0),
            false,
            true,
        ),
        line(
            "Hopf point kappa_c",
            vec![(kappa_c, 0.0), (kappa_c, top)],
            grey,
            true,
            false,
        ),
    ];
    if let Some(k) = lpc {
        series.push(line(
            "fold of cycles (LPC)",
            vec![(k, 0.0), (k, top)],
            RGBColor(0, 0, 0),
            true,
            false,
        ));
    }
    let fig = LineFigure {
        title: "Hysteresis of stick-slip: cutoff ageing law, nu = 90, m = 1e-3".into(),
        x_label: "stiffness kappa = K D0 / W".into(),
        y_label: "peak-to-peak spring force Δs (0: steady sliding)".into(),
        log_x: false,
        log_y: false,
        series,
    };
    for f in render(&fig, Path::new("docs/figures/brockley-hysteresis"))? {
        println!("wrote {}", f.display());
    }
    Ok(())
}
