//! The figure of a diagram in a pair of control parameters (`diagram --x P
//! --y Q`): the Hopf curve `Q_c(P)` on log axes labelled with units, its
//! onset type, Bautin points and the scene's own `(P, Q)`.

use super::stability::{segments, OperatingMarker, StabilityFigure};
use crate::analysis::axes::AxesDiagram;
use crate::analysis::control::Control;
use crate::params::Param;

/// An axis label for a control, with its unit.
pub fn axis_label(c: Control) -> String {
    match c {
        Control::K => "spring stiffness K [N/m]".into(),
        Control::V => "driving velocity V [µm/s]".into(),
        Control::M => "block mass M [kg]".into(),
        Control::W => "normal load W [N]".into(),
        Control::Tau => "ageing cutoff τ [s]".into(),
        Control::Eta => "radiation damping η [s/m]".into(),
        Control::Dimensionless(p) => match p {
            Param::Kappa => "κ = K D0 / W".into(),
            Param::Nu => "ν = V / V0".into(),
            Param::M => "m = M V0² / (W D0)".into(),
            Param::ThetaC => "θ_c = τ V0 / D0".into(),
            Param::Mu2 => "μ2 (ln² ageing)".into(),
            Param::MuVv => "μ_vv ((ln v)² term)".into(),
            Param::MuVphi => "μ_vφ ((ln θ)(ln v) term)".into(),
            p => format!("{} (friction law)", p.name()),
        },
    }
}

/// A value with five significant digits and its unit, for labels.
fn with_unit(c: Control, v: f64) -> String {
    let unit = match c.unit() {
        "1" => String::new(),
        "um/s" => " µm/s".into(),
        u => format!(" {u}"),
    };
    // Five significant digits, trailing zeros dropped.
    let text = format!("{v:.4e}");
    let value = match text.split_once('e') {
        Some((mantissa, exp)) => {
            let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
            match exp {
                "0" => mantissa.to_string(),
                e => format!("{mantissa}e{e}"),
            }
        }
        None => text,
    };
    format!("{} = {value}{unit}", c.name())
}

/// The figure of `d`, titled with the scene's `label`.
pub fn axes_figure(d: &AxesDiagram, label: &str) -> StabilityFigure {
    let (x, y) = (d.axes.x, d.axes.y);
    let pts: Vec<_> = d.points.iter().map(|p| (p.x, p.y, p.criticality)).collect();
    let (lo, hi) = d.x_range;
    StabilityFigure {
        title: format!(
            "Stability diagram, {label}: critical {} against {} ({} model)",
            y.name(),
            x.name(),
            d.choice.kind.name()
        ),
        x_label: axis_label(x),
        y_label: format!("critical {}", axis_label(y)),
        segments: segments(&pts),
        reference: Vec::new(),
        reference_label: String::new(),
        markers: d
            .bautin
            .iter()
            .map(|b| ("Bautin (l1 = 0)".to_string(), b.x, b.y))
            .collect(),
        operating_point: d
            .operating
            .filter(|(px, _)| (lo..=hi).contains(px))
            .map(|(px, py)| OperatingMarker {
                label: format!(
                    "operating point: {}, {}",
                    with_unit(x, px),
                    with_unit(y, py)
                ),
                x: px,
                y: py,
                margin: None,
            }),
        vlines: Vec::new(),
        lpc: Vec::new(),
        bistable: Vec::new(),
        unknown: Vec::new(),
        x_range: (lo, hi),
        notes: Vec::new(),
        stable_above: d.stable_above.unwrap_or(true),
    }
}
