//! The engine on its own, on a textbook system: the Brusselator
//! `x' = a - (b + 1) x + x^2 y, y' = b x - x^2 y`.
//!
//! Steady state `(a, b/a)`, Hopf bifurcation at `b = 1 + a^2` with frequency
//! `a`. The example continues the steady state in `b`, locates the Hopf point,
//! computes its first Lyapunov coefficient, traces the Hopf curve in the
//! `(a, b)` plane, and continues the limit cycles born at the Hopf point in
//! `b`, with their period, amplitude and Floquet multipliers, checked
//! against theory: the period `2 pi / a` at the Hopf point, the trivial
//! multiplier 1, and in the plane the other multiplier
//! `exp(int_0^T tr J(x(t)) dt)` (Liouville). The Hopf curve and the cycles
//! start from the located Hopf point by branch switching
//! (`HopfCurve::from_event`, `CycleBranch::from_hopf_event`).
//!
//! Run: `cargo run --release -p continuation --example brusselator`

use continuation::codim2::{CurveSettings, HopfCurve};
use continuation::normal_form::hopf_normal_form;
use continuation::periodic::{CycleBranch, CyclePoint, CycleSettings, Discretization};
use continuation::{
    Branch, ContinuationSettings, Event, EventKind, Scalar, StepControl, VectorField,
};

struct Brusselator;

impl VectorField for Brusselator {
    fn dim(&self) -> usize {
        2
    }
    fn n_params(&self) -> usize {
        2
    }
    fn rhs<D: Scalar>(&self, x: &[D], p: &[D], out: &mut [D]) {
        let (a, b) = (p[0], p[1]);
        out[0] = a - (b + 1.0) * x[0] + x[0] * x[0] * x[1];
        out[1] = b * x[0] - x[0] * x[0] * x[1];
    }
}

fn main() -> Result<(), continuation::ContinuationError> {
    let a = 1.5;
    let settings = ContinuationSettings {
        step: StepControl {
            ds: 0.05,
            ..ContinuationSettings::default().step
        },
        p_max: 6.0,
        ..Default::default()
    };
    let mut hopf = None;
    for point in Branch::new(&Brusselator, &[a, 1.0 / a], &[a, 1.0], 1, settings)? {
        let point = point?;
        for e in point.events {
            if let EventKind::Hopf { omega } = e.kind {
                println!(
                    "Hopf at b = {:.15} (exact 1 + a^2 = {}), omega = {:.15} (exact a = {a})",
                    e.point.param(),
                    1.0 + a * a,
                    omega
                );
                hopf = Some(e);
            }
        }
    }
    let Some(hopf) = hopf else {
        println!("no Hopf point found");
        return Ok(());
    };
    let (at, omega) = hopf.hopf().expect("a Hopf event");
    let nf = hopf_normal_form(&Brusselator, &at.x, &at.p, omega)?;
    println!(
        "first Lyapunov coefficient l1 = {:.12e} ({})",
        nf.l1,
        if nf.l1 < 0.0 {
            "supercritical"
        } else {
            "subcritical"
        }
    );
    cycles(&hopf)?;
    let curve = HopfCurve::from_event(
        &Brusselator,
        &hopf,
        0,
        CurveSettings {
            bounds: [(0.0, 50.0), (0.2, 3.0)],
            ..Default::default()
        },
    )
    .expect("a Hopf event")?;
    println!("Hopf curve in the (a, b) plane:");
    println!(
        "{:>10} {:>14} {:>14} {:>12}",
        "a", "b", "b - (1 + a^2)", "l1"
    );
    for pt in curve {
        let pt = pt?;
        let (a, b) = (pt.p[0], pt.p[1]);
        println!(
            "{a:>10.5} {b:>14.10} {:>14.2e} {:>12.4e}",
            b - (1.0 + a * a),
            pt.l1
        );
    }
    Ok(())
}

/// Values of `b` at which cycles are reported.
const REPORTED_B: [f64; 4] = [3.5, 4.0, 4.5, 5.0];

/// Continues the cycles born at the Hopf point `hopf` in `b` up to `b = 5`
/// and prints the first one and those at [`REPORTED_B`].
fn cycles(hopf: &Event) -> Result<(), continuation::ContinuationError> {
    let p = &hopf.point.p;
    let defaults = CycleSettings::default();
    let settings = CycleSettings {
        mesh: Discretization {
            ntst: 40,
            ..Default::default()
        },
        step: StepControl {
            ds: 0.01,
            ds_max: 0.2,
            ..defaults.step
        },
        p_max: 5.05,
        user_points: REPORTED_B.to_vec(),
        ..defaults
    };
    let mut branch =
        CycleBranch::from_hopf_event(&Brusselator, hopf, settings).expect("a Hopf event")?;
    println!("cycles born at the Hopf point, continued in b:");
    println!(
        "{:>9} {:>10} {:>11} {:>10} {:>12} {:>12} {:>7}",
        "b", "period", "x_max-x_min", "|mu1 - 1|", "mu2", "Liouville", "stable"
    );
    let first = branch.next().expect("the first cycle")?;
    // At the Hopf point the period is 2 pi / omega, omega = a; the first
    // cycle lies O(r^2) beyond it (r the start amplitude), and the period
    // changes by O(b - b_c).
    let hopf_period = 2.0 * std::f64::consts::PI / p[0];
    let (b0, b_c) = (first.cycle.p[1], 1.0 + p[0] * p[0]);
    assert!(
        (first.cycle.period / hopf_period - 1.0).abs() < 10.0 * (b0 - b_c).abs().max(1e-9),
        "period {} at b = {b0} against 2 pi / a = {hopf_period}",
        first.cycle.period
    );
    print_cycle(&first);
    println!("  (2 pi / a = {hopf_period:.6} at the Hopf point b = {b_c})");
    for pt in branch {
        for user in pt?.user_points() {
            print_cycle(user);
        }
    }
    Ok(())
}

/// One line of the cycle table; asserts the trivial multiplier and Liouville's formula.
fn print_cycle(pt: &CyclePoint) {
    let c = &pt.cycle;
    let (lo, hi) = c.range(&Brusselator, 0);
    let trivial = pt
        .trivial
        .map(|i| pt.multipliers[i])
        .expect("trivial multiplier");
    assert!(
        (trivial - 1.0).norm() < 1e-6,
        "trivial multiplier {trivial}"
    );
    let other = pt
        .multipliers
        .iter()
        .enumerate()
        .find(|(i, _)| Some(*i) != pt.trivial);
    let other = other.expect("the nontrivial multiplier").1;
    // exp(T int_0^1 tr J dtau), tr J = -(b + 1) + 2 x y - x^2, by the
    // trapezoidal rule on samples of the orbit.
    let b = c.p[1];
    let samples = c.samples(200);
    let tr = |x: &[f64]| -(b + 1.0) + 2.0 * x[0] * x[1] - x[0] * x[0];
    let integral: f64 = samples
        .windows(2)
        .map(|w| 0.5 * (w[1].0 - w[0].0) * (tr(&w[0].1) + tr(&w[1].1)))
        .sum();
    let liouville = (c.period * integral).exp();
    // Compared in the exponent (the multiplier falls to 1e-6 and below as
    // the cycles turn into relaxation oscillations).
    assert!(
        (other.re.ln() - c.period * integral).abs() < 1e-5 && other.im.abs() < 1e-9,
        "multiplier {other} against Liouville's {liouville}"
    );
    println!(
        "{b:>9.5} {:>10.6} {:>11.6} {:>10.1e} {:>12.6e} {liouville:>12.6e} {:>7}",
        c.period,
        hi - lo,
        (trivial - 1.0).norm(),
        other.re,
        pt.stability.is_stable()
    );
}
