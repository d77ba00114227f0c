//! Curves of folds of cycles (the hysteresis boundary) as CSV and JSON, in
//! docs/model.md's variables and physical units: shared by `diagram` (curves from
//! Bautin points) and `cycles --lpc-curve` (curves through the folds of a
//! branch).

use super::files::with_suffix;
use super::TextUnits;
use crate::analysis::lpc_curve::LpcCurves;
use crate::scene::Units;
use serde_json::{json, Value};
use std::io::Write;
use std::path::{Path, PathBuf};

/// The points of every curve as JSON objects (`lpc_curve`; `curve` numbers
/// the curves as in the CSV).
pub fn lpc_json(curves: &LpcCurves, u: &Units) -> Vec<Value> {
    curves
        .points
        .iter()
        .enumerate()
        .flat_map(|(i, curve)| curve.iter().map(move |p| (i, p)))
        .map(|(i, p)| {
            json!({
                "curve": i,
                "nu": p.nu, "kappa": p.kappa, "period": p.period, "delta_s": p.delta_s,
                "V_um_per_s": u.velocity_um_s(p.nu),
                "K_over_W_per_m": u.k_over_w(p.kappa),
                "K_over_M_per_s2": u.k_over_m(p.kappa),
            })
        })
        .collect()
}

/// The text lines of the summary: the extent of every curve and why an end
/// stopped.
pub fn lpc_summary(curves: &LpcCurves, u: &Units, units: TextUnits) -> Vec<String> {
    let extents = curves.points.iter().filter_map(|curve| {
        let (a, b) = (curve.first()?, curve.last()?);
        Some(format!(
            "  fold of cycles (LPC) curve: {} points from V = {:.6e} um/s ({}) to \
             V = {:.6e} um/s ({}); below it stick-slip coexists with stable steady \
             sliding (hysteresis) down to the Hopf curve, where there is one",
            curve.len(),
            u.velocity_um_s(a.nu),
            units.stiffness(a.kappa, u, 6),
            u.velocity_um_s(b.nu),
            units.stiffness(b.kappa, u, 6)
        ))
    });
    let stops = curves
        .stops
        .iter()
        .map(|stop| format!("  fold-of-cycles curve stopped: {stop}"));
    extents.chain(stops).collect()
}

/// Writes `<stem>-lpc-curve.csv` (one row per fold, numbered by curve).
pub fn write_lpc_csv(
    stem: &Path,
    scene: &str,
    curves: &LpcCurves,
    u: &Units,
) -> std::io::Result<PathBuf> {
    let path = with_suffix(stem, "-lpc-curve.csv");
    let mut w = crate::cli::files::create_file(&path)?;
    writeln!(
        w,
        "# folds of cycles (LPC) of scene {scene}: the hysteresis boundary"
    )?;
    writeln!(w, "curve,nu,kappa,period,delta_s,V_um_per_s,K_over_W_per_m")?;
    for (i, curve) in curves.points.iter().enumerate() {
        for p in curve {
            writeln!(
                w,
                "{i},{:.15e},{:.15e},{:.15e},{:.15e},{:.12e},{:.12e}",
                p.nu,
                p.kappa,
                p.period,
                p.delta_s,
                u.velocity_um_s(p.nu),
                u.k_over_w(p.kappa)
            )?;
        }
    }
    w.flush()?;
    Ok(path)
}
