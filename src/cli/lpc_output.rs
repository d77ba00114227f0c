//! Curves of folds of cycles (the hysteresis boundary) as CSV and text, from
//! their records ([`FoldPoint`]): shared by `diagram` (curves from Bautin
//! points) and `cycles --lpc-curve` (curves through the folds of a branch).

use super::TextUnits;
use crate::analysis::lpc_curve::{LpcStop, LpcStopReason};
use crate::file_names::with_suffix;
use crate::records::csv::{header, row};
use crate::records::diagram::FoldPoint;
use std::path::{Path, PathBuf};

/// The text lines of the summary: the extent of every curve of `folds` and
/// why an end stopped (`stops`).
pub fn lpc_summary(folds: &[FoldPoint], stops: &[LpcStop], units: TextUnits) -> Vec<String> {
    let extents = folds
        .chunk_by(|a, b| a.curve == b.curve)
        .filter_map(|curve| {
            let (a, b) = (curve.first()?, curve.last()?);
            Some(format!(
                "  fold of cycles (LPC) curve: {} points from V = {:.6e} µm/s ({}) to \
             V = {:.6e} µm/s ({}); below it stick-slip coexists with stable steady \
             sliding (hysteresis) down to the Hopf curve, where there is one",
                curve.len(),
                a.physical.v_um_per_s,
                units.stiffness(a.kappa, a.physical.k_over_w_per_m, 6),
                b.physical.v_um_per_s,
                units.stiffness(b.kappa, b.physical.k_over_w_per_m, 6)
            ))
        });
    let stops = stops
        .iter()
        .map(|stop| format!("  fold-of-cycles curve stopped: {stop}"));
    extents.chain(stops).collect()
}

/// Writes `<stem>-lpc-curve.csv`: the folds of scene `scene`, one row
/// each; in full or not at all ([`crate::cli::files::write`]). A curve that
/// stopped short of the request (`stops`: those that are no expected end
/// at a Bautin point or the range's edge) ends with a `# incomplete` line
/// naming why.
pub fn write_lpc_csv(
    stem: &Path,
    scene: &str,
    folds: &[FoldPoint],
    stops: &[LpcStop],
) -> std::io::Result<PathBuf> {
    let path = with_suffix(stem, "-lpc-curve.csv");
    let mut text = format!(
        "# folds of cycles (LPC) of scene {scene}: the hysteresis boundary\n{}\n",
        header::<FoldPoint>()?
    );
    for p in folds {
        text.push_str(&row(p)?);
        text.push('\n');
    }
    let short: Vec<&str> = stops
        .iter()
        .filter(|s| {
            !matches!(
                s.reason,
                LpcStopReason::BautinPoint | LpcStopReason::EndOfRange
            )
        })
        .map(|s| s.message.as_str())
        .collect();
    if !short.is_empty() {
        text.push_str(&format!(
            "{} {}\n",
            crate::cli::files::INCOMPLETE,
            short.join("; ")
        ));
    }
    crate::cli::files::write(&path, text)?;
    Ok(path)
}
