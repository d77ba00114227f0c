//! Stick-slip growing from steady sliding just below the critical stiffness
//! (the seed's paper/paper figure of spring elongation against time):
//! simulate the PMMA block at several stiffnesses below `K_c` and print the
//! final peak-to-peak spring force, next to the cycle the collocation branch
//! finds at the same stiffness.
//!
//! Run: `cargo run --release --example stick_slip_growth`

use stickslip::analysis::cycles::{trace_cycles, CycleRequest};
use stickslip::analysis::simulate::{simulate, Segment};
use stickslip::model::ModelKind;
use stickslip::params::Params;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let base = Params {
        kappa: 0.0,
        nu: 1.0,
        m: 0.0,
        a: 0.012,
        b: 0.023,
        mu0: 0.5,
        mu2: 2.4e-4,
        theta_c: None,
        state_law: Default::default(),
        mu_vv: 0.0,
        mu_vphi: 0.0,
        eta_d: 0.0,
    };
    let kappa_c = base.mu_phi() - base.mu_v();
    let fractions = [0.99, 0.98, 0.97];
    let req = CycleRequest {
        kappa_min: 0.94 * kappa_c,
        kappa_max: 1.0,
        max_steps: 200,
        ntst: 40,
        at_kappa: fractions.iter().map(|f| f * kappa_c).collect(),
        ntst_max: 400,
        collocation: None,
    };
    let mut branch = Vec::new();
    trace_cycles(ModelKind::QuasiStatic, &base, &req, |c| {
        branch.extend(c.user.iter().map(|u| (u.kappa, u.delta_s, u.period)));
        Ok(())
    })?;
    println!("kappa/kappa_c   Delta_s (simulation, last period)   Delta_s (collocation)   period");
    for (kappa, delta_s, period) in branch {
        let mut p = base;
        p.kappa = kappa;
        // From slightly perturbed steady sliding, long enough for the amplitude to saturate.
        let start = [p.friction().steady(1.0), 1.0, 1.01];
        let t_end = 300.0 * period;
        let traj = simulate(
            ModelKind::QuasiStatic,
            &p,
            start,
            &[Segment {
                nu: 1.0,
                duration: t_end,
            }],
            1e-8,
            None,
        )?;
        let last: Vec<f64> = traj
            .t
            .iter()
            .zip(&traj.s)
            .filter(|(t, _)| **t > t_end - period)
            .map(|(_, s)| *s)
            .collect();
        let (lo, hi) = last
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), s| {
                (a.min(*s), b.max(*s))
            });
        println!(
            "{:>12.4} {:>30.6e} {:>23.6e} {:>10.4}",
            kappa / kappa_c,
            hi - lo,
            delta_s,
            period
        );
    }
    Ok(())
}
