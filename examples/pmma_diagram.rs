//! The stability diagram of a PMMA/PMMA multicontact interface (Baumberger &
//! Caroli 2006, §II.D and figure "Dynamic stability diagram"): critical
//! `K/M` against the driving velocity, with the onset type along the curve.
//!
//! Run: `cargo run --release --example pmma_diagram`

use stickslip::analysis::diagram::stability_diagram;
use stickslip::analysis::model_choice::{choose_model, params_for, DEFAULT_INERTIA_THRESHOLD};
use stickslip::scene;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let s = scene::builtin("pmma").ok_or("built-in scene missing")?;
    let (lo, hi) = s.nu_range;
    // Inertia matters most at the top of the range: choose the model there.
    let mut top = s.params;
    top.nu = hi;
    let choice = choose_model(&top, None, DEFAULT_INERTIA_THRESHOLD);
    println!("{}\nmodel: {}", s.description, choice.reason);
    let d = stability_diagram(choice.kind, &params_for(choice.kind, &s.params), (lo, hi))?;
    println!(
        "{:>12} {:>14} {:>14} {:>15}",
        "V [um/s]", "K/W [1/m]", "K/M [1/s^2]", "onset"
    );
    for p in d.points.iter().step_by(6) {
        let km = s.units.k_over_m(p.kappa).unwrap_or(f64::NAN);
        println!(
            "{:>12.4} {:>14.6e} {:>14.6e} {:>15}",
            s.units.velocity_um_s(p.nu),
            s.units.k_over_w(p.kappa),
            km,
            p.criticality.name()
        );
    }
    for sp in &d.special {
        println!(
            "{} at V = {:.4} um/s, K/M = {:.6e} 1/s^2",
            sp.kind,
            s.units.velocity_um_s(sp.nu),
            s.units.k_over_m(sp.kappa).unwrap_or(f64::NAN)
        );
    }
    Ok(())
}
