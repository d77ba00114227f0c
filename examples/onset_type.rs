//! Where does the stick-slip onset change from hysteretic to continuous?
//!
//! For the plain Rice–Ruina law the quasi-static Hopf bifurcation is
//! degenerate (`l1 = 0`); inertia decides it. This example follows the Hopf
//! point in `(kappa, m)` at fixed velocity, prints `l1` along the way, and
//! locates the Bautin point where `l1` changes sign, with its `l2`. The onset
//! type depends on `eta = m nu^2 / A` only: the same `eta*` at every velocity.
//!
//! Run: `cargo run --release --example onset_type`

use stickslip::analysis::diagram::{hopf_curve, SpecialKind};
use stickslip::model::ModelKind;
use stickslip::params::{Param, Params};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    for nu in [0.3, 1.0, 10.0] {
        let p = Params {
            kappa: 0.0,
            nu,
            m: 0.0,
            a: 0.012,
            b: 0.023,
            mu0: 0.6,
            mu2: 0.0,
            theta_c: None,
            state_law: Default::default(),
            mu_vv: 0.0,
            mu_vphi: 0.0,
            eta_d: 0.0,
        };
        let d = hopf_curve(
            ModelKind::Inertial,
            &p,
            Param::M,
            (1e-4 * p.a / (nu * nu), 10.0 * p.a / (nu * nu)),
        )?;
        println!(
            "nu = {nu}: {} points on the Hopf curve in (kappa, m)",
            d.points.len()
        );
        for pt in d.points.iter().step_by(12) {
            println!(
                "  eta = {:>10.4e}  kappa_c = {:.6e}  l1 = {:>12.4e}  {}",
                pt.m * nu * nu / p.a,
                pt.kappa,
                pt.l1,
                pt.criticality.name()
            );
        }
        for b in d.special.iter().filter(|s| s.kind == SpecialKind::Bautin) {
            println!(
                "  Bautin: eta* = m nu^2/A = {:.12e}, m* = {:.12e}, kappa = {:.10e}, l2 = {:.6e}",
                b.m * nu * nu / p.a,
                b.m,
                b.kappa,
                b.l2.unwrap_or(f64::NAN)
            );
        }
    }
    Ok(())
}
