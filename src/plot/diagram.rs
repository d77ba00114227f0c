//! The figures of the stability diagram (`diagram`): the stability diagram in physical
//! and dimensionless axes, with the hysteretic region.

use super::stability::{render, segments, Note, OperatingMarker, StabilityFigure};
use super::PlotError;
use crate::analysis::diagram::{SpecialKind, StabilityDiagram};
use crate::appendix_c;
use crate::file_names::with_suffix;
use crate::jobs::diagram::OperatingPoint;
use crate::jobs::Setup;
use crate::records::significant;
use std::path::{Path, PathBuf};

/// One pair of axes: how `(nu, kappa)` map to the plotted coordinates.
struct Axes {
    suffix: &'static str,
    fx: Box<dyn Fn(f64) -> f64>,
    fy: Box<dyn Fn(f64) -> f64>,
    x_label: String,
    y_label: String,
    title: String,
    /// How a stretch `[a, b]` of x values reads in words (`V = a .. b µm/s`).
    x_span: fn(f64, f64) -> String,
}

/// Draws the diagram `d` of `setup` over `(lo, hi)` in physical and
/// dimensionless axes, with the operating point when given.
pub fn write_figures(
    setup: &Setup,
    d: &StabilityDiagram,
    (lo, hi): (f64, f64),
    operating: Option<&OperatingPoint>,
    stem: &Path,
) -> Result<Vec<PathBuf>, PlotError> {
    let u = setup.scene.units;
    let model = setup.choice.kind.name();
    let reference_every = (d.points.len() / 25).max(1);
    let mut files = Vec::new();
    // Physical axes: (V, K/M) when the load is the block's weight, W = M g
    // (the seed's diagram, where K/M alone decides); (V, K/W) when the scene
    // gives its own load (a press-loaded rig, whose K/M would say nothing of
    // its stiffness against the load) or the block is massless.
    let (y_of, y_label): (Box<dyn Fn(f64) -> f64>, &str) = match u.k_over_m(1.0) {
        Some(_) if u.load_is_weight => (
            Box::new(move |k| u.k_over_m(k).unwrap_or(f64::NAN)),
            "critical K/M [1/s²]  (W = M g)",
        ),
        _ => (Box::new(move |k| u.k_over_w(k)), "critical K/W [1/m]"),
    };
    let axes = [
        Axes {
            suffix: "-stability-physical",
            fx: Box::new(move |nu| u.velocity_um_s(nu)),
            fy: y_of,
            x_label: "driving velocity V [µm/s]".into(),
            y_label: y_label.into(),
            title: format!(
                "Stability diagram, {} ({model} model){}",
                setup.label,
                short_fold_curve_note(d)
            ),
            x_span: |a, b| format!("V = {} .. {} µm/s", significant(a), significant(b)),
        },
        Axes {
            suffix: "-stability-dimensionless",
            fx: Box::new(|nu| nu),
            fy: Box::new(|k| k),
            x_label: "ν = V / V0".into(),
            y_label: "κ = K D0 / W".into(),
            title: format!(
                "Stability diagram, {}: (κ, ν) ({model} model){}",
                setup.label,
                short_fold_curve_note(d)
            ),
            x_span: |a, b| format!("ν = {} .. {}", significant(a), significant(b)),
        },
    ];
    for Axes {
        suffix,
        fx,
        fy,
        x_label,
        y_label,
        title,
        x_span,
    } in axes
    {
        let pts: Vec<_> = d
            .points
            .iter()
            .filter(|p| p.kappa > 0.0)
            .map(|p| (fx(p.nu), fy(p.kappa), p.criticality))
            .collect();
        let reference = d
            .points
            .iter()
            .step_by(reference_every)
            .filter_map(|p| {
                let mut at = setup.params;
                at.nu = p.nu;
                let k = appendix_c::critical_stiffness(&at);
                (k > 0.0).then(|| (fx(p.nu), fy(k)))
            })
            .collect();
        let markers = d
            .special
            .iter()
            .filter(|s| s.kind == SpecialKind::Bautin)
            .map(|s| ("Bautin (l1 = 0)".to_string(), fx(s.nu), fy(s.kappa)))
            .collect();
        let vlines = d
            .special
            .iter()
            .filter(|s| s.kind == SpecialKind::Endpoint)
            .map(|s| ("κ_c → 0: friction minimum".to_string(), fx(s.nu)))
            .collect();
        let lpc: Vec<Vec<(f64, f64)>> = d
            .lpc
            .points
            .iter()
            .map(|c| c.iter().map(|p| (fx(p.nu), fy(p.kappa))).collect())
            .collect();
        let bistable = d
            .lpc
            .points
            .iter()
            .map(|c| {
                c.iter()
                    .map(|p| {
                        // Below the Hopf curve steady sliding is unstable: the
                        // region ends there (where the curve exists at this
                        // velocity), at kappa_c of Appendix C (the Hopf
                        // condition in closed form, which the computed curve
                        // matches to rounding; interpolating that curve was
                        // off by 5e-5 relative, as much as the band's width
                        // near a Bautin point).
                        let mut at = setup.params;
                        at.nu = p.nu;
                        let kappa_c = appendix_c::critical_stiffness(&at);
                        let lower = (kappa_c > 0.0).then(|| fy(kappa_c.min(p.kappa)));
                        (fx(p.nu), fy(p.kappa), lower)
                    })
                    .collect()
            })
            .collect();
        let fig = StabilityFigure {
            title,
            x_label,
            y_label,
            segments: segments(&pts),
            reference,
            reference_label: format!(
                "Appendix C, eq. {}",
                if setup.choice.kind == crate::model::ModelKind::Inertial {
                    "C11"
                } else {
                    "C12"
                }
            ),
            markers,
            operating_point: operating
                .filter(|op| op.in_range)
                .map(|op| OperatingMarker {
                    label: format!(
                        "operating point: K = {} N/m at V = {} µm/s ({})",
                        significant(op.k_n_per_m),
                        significant(op.v_um_per_s),
                        op.regime.name()
                    ),
                    x: fx(op.nu),
                    y: fy(op.kappa),
                    margin: op.margin,
                }),
            vlines,
            lpc,
            bistable,
            unknown: d.lpc.gaps.iter().map(|&(a, b)| (fx(a), fx(b))).collect(),
            x_range: (fx(lo), fx(hi)),
            notes: strengthening_notes(d, &fx, &x_span),
            stable_above: true,
        };
        files.extend(render(&fig, &with_suffix(stem, suffix))?);
    }
    Ok(files)
}

/// The plot's words on velocity strengthening: the whole range, or each
/// stretch of it (over its velocities `fx`, in words by `span`).
fn strengthening_notes(
    d: &StabilityDiagram,
    fx: &dyn Fn(f64) -> f64,
    span: &dyn Fn(f64, f64) -> String,
) -> Vec<Note> {
    if d.points.is_empty() && !d.strengthening.is_empty() {
        return vec![Note {
            text: "velocity strengthening over the whole range (μ_φ ≤ μ_v): steady sliding \
                   stable for every stiffness, no Hopf point"
                .to_string(),
            span: None,
        }];
    }
    d.strengthening
        .iter()
        .map(|&(a, b)| Note {
            text: format!(
                "velocity strengthening for {}: stable for every stiffness",
                span(fx(a), fx(b))
            ),
            span: Some((fx(a), fx(b))),
        })
        .collect()
}

/// A title note when a fold-of-cycles curve stopped short of the range (a
/// failure away from its Bautin point, `lpc_stops` in the JSON): the
/// hysteresis boundary is drawn only as far as it was computed.
fn short_fold_curve_note(d: &StabilityDiagram) -> &'static str {
    if d.lpc.incomplete {
        " — fold-of-cycles curve incomplete (see lpc_stops)"
    } else {
        ""
    }
}
