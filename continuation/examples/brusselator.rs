//! The engine on its own, on a textbook system: the Brusselator
//! `x' = a - (b + 1) x + x^2 y, y' = b x - x^2 y`.
//!
//! Steady state `(a, b/a)`, Hopf bifurcation at `b = 1 + a^2` with frequency
//! `a`. The example continues the steady state in `b`, locates the Hopf point,
//! computes its first Lyapunov coefficient, and traces the Hopf curve in the
//! `(a, b)` plane.
//!
//! Run: `cargo run --release -p continuation --example brusselator`

use continuation::codim2::{CurveSettings, HopfCurve};
use continuation::normal_form::hopf_normal_form;
use continuation::{Branch, ContinuationSettings, EventKind, Scalar, StepControl, VectorField};

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
                    e.param(),
                    1.0 + a * a,
                    omega
                );
                hopf = Some((e.x, e.p, omega));
            }
        }
    }
    let Some((x, p, omega)) = hopf else {
        println!("no Hopf point found");
        return Ok(());
    };
    let nf = hopf_normal_form(&Brusselator, &x, &p, omega)?;
    println!(
        "first Lyapunov coefficient l1 = {:.12e} ({})",
        nf.l1,
        if nf.l1 < 0.0 {
            "supercritical"
        } else {
            "subcritical"
        }
    );
    let curve = HopfCurve::new(
        &Brusselator,
        &x,
        omega,
        &p,
        [1, 0],
        CurveSettings {
            bounds: [(0.0, 50.0), (0.2, 3.0)],
            ..Default::default()
        },
    )?;
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
