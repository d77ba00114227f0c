//! Stability diagrams: the Hopf curve on log axes, sub- and supercritical
//! parts drawn differently, the Appendix C curve overlaid, special points
//! marked, stable and unstable regions labelled.

use super::{frame, render_both, Axis, PlotError, FONT};
use crate::analysis::hopf::Criticality;
use plotters::coord::ranged1d::Ranged;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::path::{Path, PathBuf};

/// A run of the Hopf curve with one onset type.
#[derive(Clone, Debug)]
pub struct Segment {
    pub points: Vec<(f64, f64)>,
    pub criticality: Criticality,
}

/// Everything a stability diagram shows, in the units of its axes.
#[derive(Clone, Debug)]
pub struct StabilityFigure {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    /// The continuation result, split where the onset type changes.
    pub segments: Vec<Segment>,
    /// The closed form (Appendix C) at a subset of the same velocities.
    pub reference: Vec<(f64, f64)>,
    pub reference_label: String,
    /// Codimension-2 points: (label, x, y).
    pub markers: Vec<(String, f64, f64)>,
    /// The rig's own stiffness and velocity, when the scene gives `K`,
    /// drawn as a large orange diamond.
    pub operating_point: Option<OperatingMarker>,
    /// Vertical lines (label, x): the end of the curve where kappa_c -> 0.
    pub vlines: Vec<(String, f64)>,
    /// Curves of folds of cycles (LPC).
    pub lpc: Vec<Vec<(f64, f64)>>,
    /// Hysteretic regions below each LPC curve: `(x, upper y, lower y)`,
    /// the lower bound `None` where it is the bottom of the axes (no Hopf
    /// point at that velocity: steady sliding stable for every stiffness).
    pub bistable: Vec<Vec<(f64, f64, Option<f64>)>>,
    /// x spans where the fold-of-cycles curve, the hysteretic region's
    /// upper edge, was not computed (it stopped short): the region there is
    /// unknown, drawn hatched and labelled, not left blank as if absent.
    pub unknown: Vec<(f64, f64)>,
    /// x range of the axes.
    pub x_range: (f64, f64),
    /// Text written in the plot (e.g. "velocity strengthening: stable for
    /// every stiffness" where there is no Hopf curve).
    pub notes: Vec<Note>,
    /// Whether steady sliding is stable above the curve (larger y): the
    /// stiffness, and most controls; below it for e.g. the mass at `W = M g`.
    pub stable_above: bool,
}

/// The operating point in a figure: its legend label, its place `(x, y)`
/// and its margin `K / K_c - 1` over the onset at its velocity (where the
/// magnified hysteretic band shows it, when it lies within that band's range).
#[derive(Clone, Debug)]
pub struct OperatingMarker {
    pub label: String,
    pub x: f64,
    pub y: f64,
    pub margin: Option<f64>,
}

/// A note written in the plot, over the x span it is about (in the axis
/// unit) or, without one, across the plot.
#[derive(Clone, Debug)]
pub struct Note {
    pub text: String,
    pub span: Option<(f64, f64)>,
}

const SUPER: RGBColor = RGBColor(31, 90, 180);
const SUB: RGBColor = RGBColor(200, 40, 40);
const DEGEN: RGBColor = RGBColor(120, 120, 120);
const FOLD: RGBColor = RGBColor(150, 60, 150);
const STRENGTHENING: RGBColor = RGBColor(90, 140, 60);

fn color(c: Criticality) -> RGBColor {
    match c {
        Criticality::Supercritical => SUPER,
        Criticality::Subcritical => SUB,
        Criticality::Degenerate => DEGEN,
    }
}

fn label(c: Criticality) -> &'static str {
    match c {
        Criticality::Supercritical => "Hopf curve, supercritical (continuous onset)",
        Criticality::Subcritical => "Hopf curve, subcritical (hysteretic onset)",
        Criticality::Degenerate => "Hopf curve, degenerate (l1 = 0)",
    }
}

/// Splits curve points into runs of equal criticality (adjacent runs share a point).
pub fn segments(points: &[(f64, f64, Criticality)]) -> Vec<Segment> {
    let mut out: Vec<Segment> = Vec::new();
    for &(x, y, c) in points {
        match out.last_mut() {
            Some(s) if s.criticality == c => s.points.push((x, y)),
            Some(s) => {
                let join = *s.points.last().unwrap_or(&(x, y));
                out.push(Segment {
                    points: vec![join, (x, y)],
                    criticality: c,
                });
            }
            None => out.push(Segment {
                points: vec![(x, y)],
                criticality: c,
            }),
        }
    }
    out
}

/// Width of the figure and height of its main panel, in pixels.
const WIDTH: u32 = 1000;
const MAIN_HEIGHT: u32 = 620;
/// Height of the panel magnifying a thin hysteretic band.
const BAND_HEIGHT: u32 = 210;
/// Height of one legend row (two entries side by side).
const LEGEND_ROW: u32 = 24;
/// A hysteretic band thinner than this many pixels in the main panel gets a
/// panel of its own.
const THIN_BAND_PX: f64 = 8.0;

/// What a legend entry shows beside its text.
#[derive(Clone, Copy, Debug)]
enum Swatch {
    Line { color: RGBColor, dashed: bool },
    Fill(RGBColor),
    Circle,
    Triangle,
    Diamond,
    Hatch,
}

/// Colour of the operating point's marker.
const OPERATING: RGBColor = RGBColor(230, 120, 0);

/// Grey of the hatching over spans where the fold curve was not computed.
const UNKNOWN: RGBColor = RGBColor(150, 150, 150);
/// What the hatching over such a span says.
const UNKNOWN_LABEL: &str = "fold curve not computed here";

/// The legend of `fig`, in drawing order.
fn legend(fig: &StabilityFigure) -> Vec<(String, Swatch)> {
    let mut out = Vec::new();
    if !fig.bistable.is_empty() {
        out.push((
            "bistable: stick-slip coexists with steady sliding".to_string(),
            Swatch::Fill(FOLD),
        ));
    }
    if !fig.unknown.is_empty() {
        out.push((
            "fold curve not computed: hysteresis there unknown".to_string(),
            Swatch::Hatch,
        ));
    }
    if !fig.lpc.is_empty() {
        out.push((
            "fold of cycles (LPC): hysteresis boundary".to_string(),
            Swatch::Line {
                color: FOLD,
                dashed: false,
            },
        ));
    }
    let mut seen = Vec::new();
    for s in &fig.segments {
        if !seen.contains(&s.criticality) {
            seen.push(s.criticality);
            out.push((
                label(s.criticality).to_string(),
                Swatch::Line {
                    color: color(s.criticality),
                    dashed: s.criticality == Criticality::Subcritical,
                },
            ));
        }
    }
    if !fig.reference.is_empty() {
        out.push((fig.reference_label.clone(), Swatch::Circle));
    }
    let mut names: Vec<&str> = Vec::new();
    for (name, _, _) in &fig.markers {
        if !names.contains(&name.as_str()) {
            names.push(name);
            out.push((name.clone(), Swatch::Triangle));
        }
    }
    if let Some(op) = &fig.operating_point {
        out.push((op.label.clone(), Swatch::Diamond));
    }
    for (name, _) in &fig.vlines {
        if !names.contains(&name.as_str()) {
            names.push(name);
            out.push((
                name.clone(),
                Swatch::Line {
                    color: vline_color(fig, name),
                    dashed: true,
                },
            ));
        }
    }
    out
}

/// Colours of the vertical lines, one per distinct label in the order
/// they first appear (the rate-and-state diagram's `κ_c → 0` ends share
/// the first; an adhesive diagram's friction maximum, minimum and inertia
/// threshold get one each).
const VLINE_COLORS: [RGBColor; 3] = [
    STRENGTHENING,
    RGBColor(110, 110, 110),
    RGBColor(140, 70, 170),
];

/// The colour of the vertical lines labelled `name` in `fig`.
fn vline_color(fig: &StabilityFigure, name: &str) -> RGBColor {
    let mut labels: Vec<&str> = Vec::new();
    for (label, _) in &fig.vlines {
        if !labels.contains(&label.as_str()) {
            labels.push(label);
        }
    }
    let index = labels.iter().position(|l| *l == name).unwrap_or(0);
    VLINE_COLORS[index % VLINE_COLORS.len()]
}

/// The relative width `K_fold / K_c - 1` of each hysteretic region along
/// its velocities (where the region has a lower bound on the Hopf curve).
fn band_widths(fig: &StabilityFigure) -> Vec<Vec<(f64, f64)>> {
    fig.bistable
        .iter()
        .map(|region| {
            region
                .iter()
                .filter_map(|&(x, hi, lo)| lo.map(|lo| (x, (hi / lo - 1.0).max(0.0))))
                .collect::<Vec<_>>()
        })
        .filter(|r| r.len() >= 2)
        .collect()
}

/// Whether the hysteretic band is too thin to be seen in the main panel
/// over `(y0, y1)`: at most [`THIN_BAND_PX`] pixels wide anywhere.
fn band_is_thin(fig: &StabilityFigure, (y0, y1): (f64, f64)) -> bool {
    let widths = band_widths(fig);
    let widest = widths.iter().flatten().map(|p| p.1).fold(0.0f64, f64::max);
    let px = (1.0 + widest).ln() / (y1 / y0).ln() * MAIN_HEIGHT as f64;
    !widths.is_empty() && px < THIN_BAND_PX
}

/// The axes of a stability diagram, as the plotting layer draws them.
#[derive(Clone, Debug)]
pub struct Panels {
    /// Velocity, shared by both panels (log).
    pub x: Axis,
    /// Stiffness in the main panel (log).
    pub y: Axis,
    /// Band width in percent, in the panel magnifying a thin hysteretic band
    /// ([`band_is_thin`]); `None` without that panel.
    pub band: Option<Axis>,
}

/// The [`Panels`] of `fig`: the x range with a little room at both ends (so
/// the end ticks and markers show), the y range of [`y_range`], and the
/// band panel's `0 ..` 1.15 times the widest band.
pub fn panels(fig: &StabilityFigure) -> Panels {
    let (x0, x1) = (fig.x_range.0 / 1.12, fig.x_range.1 * 1.12);
    let (y0, y1) = y_range(fig);
    let band = band_is_thin(fig, (y0, y1)).then(|| {
        let top = band_widths(fig)
            .iter()
            .flatten()
            .map(|p| 100.0 * p.1)
            .fold(0.0f64, f64::max);
        Axis::new(0.0, if top > 0.0 { 1.15 * top } else { 1.0 }, false)
    });
    Panels {
        x: Axis::new(x0, x1, true),
        y: Axis::new(y0, y1, true),
        band,
    }
}

/// Writes `stem.png` and `stem.svg`; returns their paths. The figure is the
/// main panel, a panel magnifying the hysteretic band when it is too thin to
/// see ([`band_is_thin`]), and the legend below them (outside the data).
pub fn render(fig: &StabilityFigure, stem: &Path) -> Result<Vec<PathBuf>, PlotError> {
    let rows = legend(fig).len().div_ceil(2) as u32;
    let axes = panels(fig);
    let band = if axes.band.is_some() { BAND_HEIGHT } else { 0 };
    let height = MAIN_HEIGHT + band + rows * LEGEND_ROW + 16;
    render_both(
        stem,
        (WIDTH, height),
        |a| draw(a, fig, &axes),
        |a| draw(a, fig, &axes),
    )
}

/// The y range of the main panel: the curves with room above and below for
/// the region labels (a quarter of their log span, at least a factor 1.35);
/// where a curve plunges to `kappa_c -> 0` (an end point, drawn as a
/// vertical line), at most four decades below the top, unless a curve of
/// folds of cycles reaches lower. Without one the whole curve is shown,
/// however many decades it spans (a wide velocity range was drawn along the
/// bottom frame, at a false height; so was a fold curve below the four
/// decades).
fn y_range(fig: &StabilityFigure) -> (f64, f64) {
    let span = |ys: &mut dyn Iterator<Item = f64>| {
        ys.filter(|y| *y > 0.0 && y.is_finite())
            .fold((f64::INFINITY, 0.0f64), |(a, b), y| (a.min(y), b.max(y)))
    };
    let (lo, hi) = span(
        &mut fig
            .segments
            .iter()
            .flat_map(|s| s.points.iter().map(|p| p.1))
            .chain(fig.reference.iter().map(|p| p.1))
            .chain(fig.markers.iter().map(|m| m.2))
            .chain(fig.operating_point.iter().map(|m| m.y)),
    );
    let (fold_lo, fold_hi) = span(&mut fig.lpc.iter().flatten().map(|p| p.1));
    let hi = hi.max(fold_hi);
    if !lo.min(fold_lo).is_finite() {
        return (1e-3, 1.0);
    }
    let lo = if fig.vlines.is_empty() {
        lo
    } else {
        lo.max(hi * 1e-4)
    }
    .min(fold_lo);
    let room = (hi / lo).powf(0.25).max(1.35);
    (lo / room, hi * room)
}

/// Unit coordinates (0 to 1 across the axes) of the curves of `fig` on the
/// log-log axes `x`, `y`: the Hopf segments and the fold curves, and every
/// vertical line as a line across the whole height.
fn curves_in_unit(fig: &StabilityFigure, x: (f64, f64), y: (f64, f64)) -> Vec<Vec<(f64, f64)>> {
    let u = |(px, py): (f64, f64)| {
        (
            (px / x.0).ln() / (x.1 / x.0).ln(),
            (py / y.0).ln() / (y.1 / y.0).ln(),
        )
    };
    let mut out: Vec<Vec<(f64, f64)>> = fig
        .segments
        .iter()
        .map(|s| s.points.iter().map(|&p| u(p)).collect())
        .chain(fig.lpc.iter().map(|c| c.iter().map(|&p| u(p)).collect()))
        .collect();
    for &(_, vx) in &fig.vlines {
        let ux = u((vx, y.0)).0;
        out.push(vec![(ux, -1.0), (ux, 2.0)]);
    }
    out
}

/// The vertical extent `(lowest, highest)` of `curves` (unit coordinates)
/// over the unit x span `xs`, sampling each segment; `None` where no curve
/// passes.
fn extent_over(curves: &[Vec<(f64, f64)>], xs: (f64, f64)) -> Option<(f64, f64)> {
    let mut range: Option<(f64, f64)> = None;
    let mut add = |y: f64| {
        range = Some(range.map_or((y, y), |(a, b)| (a.min(y), b.max(y))));
    };
    for c in curves {
        if let [only] = c.as_slice() {
            if (xs.0..=xs.1).contains(&only.0) {
                add(only.1);
            }
        }
        for w in c.windows(2) {
            let (a, b) = (w[0], w[1]);
            for k in 0..=20 {
                let t = k as f64 / 20.0;
                let (px, py) = (a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1));
                if (xs.0..=xs.1).contains(&px) {
                    add(py);
                }
            }
            // A segment that spans the whole box without a sample inside.
            if a.0.min(b.0) <= xs.0 && a.0.max(b.0) >= xs.1 {
                add(a.1);
                add(b.1);
            }
        }
    }
    range
}

/// Where a region label of `size` (unit fractions) goes, centred at one of
/// `centres` (unit x, tried in order): the first where it fits between the
/// curves and the `above` (top) or bottom edge, half-way between them;
/// else the first centre at the edge.
fn place_label(
    curves: &[Vec<(f64, f64)>],
    size: (f64, f64),
    centres: &[f64],
    above: bool,
) -> (f64, f64) {
    place_label_where(curves, size, centres, above, |_| true).unwrap_or_else(|| {
        let cx = centres.first().copied().unwrap_or(0.5);
        (cx, if above { 1.0 - size.1 } else { size.1 })
    })
}

/// A region label ("steady sliding stable", "unstable: stick-slip"): only
/// over velocities where a curve crosses its whole width, since elsewhere
/// the side of the curve says nothing (no onset there: one regime at every
/// value); the preferred `centres` first, then any. Where no curve is that
/// wide, or the vertical lines (the last `vlines` of `curves`) cut every
/// such place (a Hopf curve spanning a narrow range of velocities, with a
/// line in it), the label centred over a curve's span instead (it may
/// overhang the curve's ends), drawn over the vertical lines on a white
/// box: the second element `true`. `None` where no place fits (the label
/// is left out). Without curves, at the edge.
fn place_region_label(
    curves: &[Vec<(f64, f64)>],
    vlines: usize,
    size: (f64, f64),
    centres: &[f64],
    above: bool,
) -> Option<((f64, f64), bool)> {
    if curves.is_empty() {
        return Some((place_label(curves, size, centres, above), false));
    }
    let spans: Vec<(f64, f64)> = curves
        .iter()
        .map(|c| {
            c.iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
                    (a.min(p.0), b.max(p.0))
                })
        })
        .collect();
    let covered = |xs: (f64, f64)| spans.iter().any(|&(a, b)| a <= xs.0 && b >= xs.1);
    let scan: Vec<f64> = centres
        .iter()
        .copied()
        .chain((1..20).map(|i| i as f64 / 20.0))
        .collect();
    if let Some(spot) = place_label_where(curves, size, &scan, above, covered) {
        return Some((spot, false));
    }
    // The curves that bound regions, without the vertical lines.
    let bounding = &curves[..curves.len() - vlines.min(curves.len())];
    let centred = |xs: (f64, f64)| {
        let mid = 0.5 * (xs.0 + xs.1);
        spans[..bounding.len()]
            .iter()
            .any(|&(a, b)| a <= mid && mid <= b)
    };
    let fine: Vec<f64> = centres
        .iter()
        .copied()
        .chain((1..100).map(|i| i as f64 / 100.0))
        .collect();
    place_label_where(bounding, size, &fine, above, centred).map(|spot| (spot, true))
}

/// [`place_label`] over the centres whose label span `xs` satisfies `allowed`.
fn place_label_where(
    curves: &[Vec<(f64, f64)>],
    size: (f64, f64),
    centres: &[f64],
    above: bool,
    allowed: impl Fn((f64, f64)) -> bool,
) -> Option<(f64, f64)> {
    let gap = 0.02;
    for &cx in centres {
        let xs = (cx - size.0 / 2.0, cx + size.0 / 2.0);
        if xs.0 < 0.0 || xs.1 > 1.0 || !allowed(xs) {
            continue;
        }
        match (extent_over(curves, xs), above) {
            (None, true) => return Some((cx, 1.0 - size.1)),
            (None, false) => return Some((cx, size.1)),
            (Some((_, top)), true) if top + size.1 + 2.0 * gap < 1.0 => {
                return Some((cx, ((top + 1.0) / 2.0).max(top + gap + size.1 / 2.0)));
            }
            (Some((bottom, _)), false) if bottom - size.1 - 2.0 * gap > 0.0 => {
                return Some((cx, (bottom / 2.0).min(bottom - gap - size.1 / 2.0)));
            }
            _ => {}
        }
    }
    None
}

/// Width of a region label in unit fractions of the plotting area (20-pixel
/// font, at most 11 pixels a character) and its height.
fn label_size(text: &str, plot: (f64, f64)) -> (f64, f64) {
    (11.0 * text.chars().count() as f64 / plot.0, 28.0 / plot.1)
}

/// `text` broken at spaces into lines of at most `width` characters (a
/// longer word stands on its own line).
fn wrap(text: &str, width: usize) -> Vec<String> {
    let mut lines: Vec<String> = Vec::new();
    for word in text.split_whitespace() {
        match lines.last_mut() {
            Some(line) if line.chars().count() + 1 + word.chars().count() <= width => {
                line.push(' ');
                line.push_str(word);
            }
            _ => lines.push(word.to_string()),
        }
    }
    lines
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    fig: &StabilityFigure,
    axes: &Panels,
) -> Result<(), String> {
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    root.fill(&WHITE).map_err(e)?;
    let (main, rest) = root.split_vertically(MAIN_HEIGHT);
    let band = axes.band.is_some();
    let (band_area, legend_area) = rest.split_vertically(if band { BAND_HEIGHT } else { 0 });
    let ((x0, x1), (y0, y1)) = (axes.x.range, axes.y.range);
    let mut chart = frame(
        &main,
        (&fig.title, &fig.x_label, &fig.y_label),
        (&axes.x, &axes.y),
        axes.x.log_coord(),
        axes.y.log_coord(),
    )?;
    let plot_px = {
        let (w, h) = chart.plotting_area().dim_in_pixel();
        (w as f64, h as f64)
    };
    let at = |(fx, fy): (f64, f64)| (x0 * (x1 / x0).powf(fx), y0 * (y1 / y0).powf(fy));
    for region in &fig.bistable {
        let mut polygon: Vec<(f64, f64)> = region.iter().map(|&(x, hi, _)| (x, hi)).collect();
        polygon.extend(region.iter().rev().map(|&(x, _, lo)| (x, lo.unwrap_or(y0))));
        chart
            .draw_series([Polygon::new(polygon, FOLD.mix(0.18).filled())])
            .map_err(e)?;
    }
    if !band {
        hatch_unknown(chart.plotting_area(), &fig.unknown)?;
    }
    for curve in &fig.lpc {
        chart
            .draw_series(LineSeries::new(curve.clone(), FOLD.stroke_width(3)))
            .map_err(e)?;
    }
    for s in &fig.segments {
        let style = color(s.criticality).stroke_width(3);
        if s.criticality == Criticality::Subcritical {
            chart.draw_series(DashedLineSeries::new(s.points.clone(), 10, 6, style))
        } else {
            chart.draw_series(LineSeries::new(s.points.clone(), style))
        }
        .map_err(e)?;
    }
    chart
        .draw_series(
            fig.reference
                .iter()
                .map(|&p| Circle::new(p, 4, BLACK.stroke_width(1))),
        )
        .map_err(e)?;
    chart
        .draw_series(
            fig.markers
                .iter()
                .map(|(_, x, y)| TriangleMarker::new((*x, *y), 9, BLACK.filled())),
        )
        .map_err(e)?;
    if let Some(op) = &fig.operating_point {
        let corners = diamond(0, 0, 11);
        chart
            .draw_series([EmptyElement::at((op.x, op.y))
                + Polygon::new(corners.clone(), OPERATING.filled())
                + PathElement::new(corners, BLACK.stroke_width(1))])
            .map_err(e)?;
    }
    for (name, x) in &fig.vlines {
        chart
            .draw_series(DashedLineSeries::new(
                vec![(*x, y0), (*x, y1)],
                8,
                6,
                vline_color(fig, name).stroke_width(2),
            ))
            .map_err(e)?;
    }
    // Region labels: steady sliding is stable above the curves (and, past a
    // friction minimum, at high velocity); stick-slip lives below them.
    let curves = curves_in_unit(fig, (x0, x1), (y0, y1));
    let text = TextStyle::from((FONT, 20).into_font()).color(&RGBColor(60, 60, 60));
    let centred = text.pos(Pos::new(HPos::Center, VPos::Center));
    // A label placed across vertical lines stands on a white box.
    let backing = |spot: (f64, f64), size: (f64, f64)| {
        // The text's own width (about 10 of the 11 pixels a character
        // `label_size` reserves) and 4 pixels either side.
        let (hw, hh) = (0.45 * size.0 + 4.0 / plot_px.0, 0.5 * size.1);
        Rectangle::new(
            [
                at((spot.0 - hw, spot.1 - hh)),
                at((spot.0 + hw, spot.1 + hh)),
            ],
            WHITE.filled(),
        )
    };
    let vlines = fig.vlines.len();
    let stable = "steady sliding stable";
    let size = label_size(stable, plot_px);
    if let Some((spot, boxed)) = place_region_label(
        &curves,
        vlines,
        size,
        &[0.5, 0.3, 0.7, 0.2, 0.8, 0.15, 0.85],
        fig.stable_above,
    ) {
        if boxed {
            chart.draw_series([backing(spot, size)]).map_err(e)?;
        }
        chart
            .draw_series([Text::new(stable, at(spot), centred.clone())])
            .map_err(e)?;
    }
    if !fig.segments.is_empty() {
        let unstable = "unstable: stick-slip";
        let size = label_size(unstable, plot_px);
        if let Some((spot, boxed)) = place_region_label(
            &curves,
            vlines,
            size,
            &[0.15, 0.3, 0.5, 0.7, 0.85],
            !fig.stable_above,
        ) {
            if boxed {
                chart.draw_series([backing(spot, size)]).map_err(e)?;
            }
            chart
                .draw_series([Text::new(unstable, at(spot), centred)])
                .map_err(e)?;
        }
    }
    let note_style = TextStyle::from((FONT, 18).into_font())
        .color(&STRENGTHENING)
        .pos(Pos::new(HPos::Center, VPos::Center));
    let unit_x = |x: f64| (x / x0).ln() / (x1 / x0).ln();
    for note in &fig.notes {
        let (a, b) = note.span.map_or((0.05, 0.95), |(a, b)| {
            (unit_x(a).clamp(0.0, 1.0), unit_x(b).clamp(0.0, 1.0))
        });
        // Lines as wide as the span allows (10 pixels a character, at least 18).
        let chars = (((b - a) * plot_px.0 / 10.0) as usize).max(18);
        let lines = wrap(&note.text, chars);
        let widest = lines.iter().map(|l| l.chars().count()).max().unwrap_or(0);
        let size = (
            (10.0 * widest as f64 / plot_px.0).min(1.0),
            24.0 * lines.len() as f64 / plot_px.1,
        );
        let centres: Vec<f64> = [0.5, 0.35, 0.65, 0.25, 0.75]
            .iter()
            .map(|f| a + f * (b - a))
            .collect();
        let fits = |above: bool| {
            let spot = place_label(&curves, size, &centres, above);
            let xs = (spot.0 - size.0 / 2.0, spot.0 + size.0 / 2.0);
            let clear = extent_over(&curves, xs)
                .is_none_or(|(lo, hi)| spot.1 - size.1 / 2.0 > hi || spot.1 + size.1 / 2.0 < lo);
            clear.then_some(spot)
        };
        let spot = fits(true)
            .or_else(|| fits(false))
            .unwrap_or(((a + b) / 2.0, 0.5));
        let line_h = 24.0 / plot_px.1;
        let top = spot.1 + line_h * (lines.len() as f64 - 1.0) / 2.0;
        chart
            .draw_series(lines.iter().enumerate().map(|(i, line)| {
                Text::new(
                    line.clone(),
                    at((spot.0, top - line_h * i as f64)),
                    note_style.clone(),
                )
            }))
            .map_err(e)?;
    }
    if let Some(band) = &axes.band {
        draw_band(&band_area, fig, (&axes.x, band))?;
    }
    draw_legend(&legend_area, &legend(fig))?;
    root.present().map_err(e)?;
    Ok(())
}

/// The panel magnifying a thin hysteretic band: its relative width
/// `K_fold / K_c - 1` in percent (axis `ya`) against velocity, on the main
/// panel's x axis `xa`; the spans where the fold curve was not computed
/// hatched.
fn draw_band<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    fig: &StabilityFigure,
    (xa, ya): (&Axis, &Axis),
) -> Result<(), String> {
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    let widths = band_widths(fig);
    let mut chart = ChartBuilder::on(area)
        .margin_left(18)
        .margin_right(18)
        .margin_top(30)
        .x_label_area_size(45)
        .y_label_area_size(85)
        .build_cartesian_2d(xa.log_coord(), ya.linear_coord())
        .map_err(e)?;
    chart
        .configure_mesh()
        .x_desc(fig.x_label.as_str())
        .y_desc("band width [%]")
        .x_label_formatter(&|v| xa.label(*v))
        .y_label_formatter(&|v| ya.label(*v))
        .label_style((FONT, 15))
        .axis_desc_style((FONT, 17))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(e)?;
    for w in &widths {
        let mut polygon: Vec<(f64, f64)> = w.iter().map(|&(x, r)| (x, 100.0 * r)).collect();
        polygon.extend(w.iter().rev().map(|&(x, _)| (x, 0.0)));
        chart
            .draw_series([Polygon::new(polygon, FOLD.mix(0.18).filled())])
            .map_err(e)?;
        chart
            .draw_series(LineSeries::new(
                w.iter().map(|&(x, r)| (x, 100.0 * r)),
                FOLD.stroke_width(2),
            ))
            .map_err(e)?;
    }
    // The operating point where its margin lies within the band's axis.
    let inside = |v: f64| ya.range.0 <= v && v <= ya.range.1;
    if let Some((x, percent)) = fig
        .operating_point
        .as_ref()
        .and_then(|op| op.margin.map(|r| (op.x, 100.0 * r)))
        .filter(|&(_, percent)| inside(percent))
    {
        let corners = diamond(0, 0, 9);
        chart
            .draw_series([EmptyElement::at((x, percent))
                + Polygon::new(corners.clone(), OPERATING.filled())
                + PathElement::new(corners, BLACK.stroke_width(1))])
            .map_err(e)?;
    }
    hatch_unknown(chart.plotting_area(), &fig.unknown)?;
    let text = TextStyle::from((FONT, 16).into_font())
        .color(&RGBColor(60, 60, 60))
        .pos(Pos::new(HPos::Left, VPos::Top));
    let caption = if fig.unknown.is_empty() {
        "hysteretic band magnified: fold-of-cycles stiffness over critical stiffness, minus 1"
    } else {
        "hysteretic band magnified: fold-of-cycles stiffness over critical stiffness, minus 1 \
         (hatched: not computed)"
    };
    area.draw(&Text::new(caption, (110, 6), text)).map_err(e)?;
    Ok(())
}

/// Hatches the x spans `unknown` of a plotting area over its whole height
/// and writes [`UNKNOWN_LABEL`] in each, wrapped to its width.
fn hatch_unknown<DB: DrawingBackend, X, Y>(
    plot: &DrawingArea<DB, Cartesian2d<X, Y>>,
    unknown: &[(f64, f64)],
) -> Result<(), String>
where
    X: Ranged<ValueType = f64>,
    Y: Ranged<ValueType = f64>,
{
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    let (base, (w, h)) = (plot.get_base_pixel(), plot.dim_in_pixel());
    let y_lo = plot.get_y_range().start;
    let area = plot.strip_coord_spec();
    let text = TextStyle::from((FONT, 15).into_font())
        .color(&RGBColor(70, 70, 70))
        .pos(Pos::new(HPos::Center, VPos::Center));
    for &(a, b) in unknown {
        let px = |x: f64| (plot.map_coordinate(&(x, y_lo)).0 - base.0).clamp(0, w as i32);
        let (left, right) = (px(a.min(b)), px(a.max(b)));
        if right <= left {
            continue;
        }
        hatch(&area, ((left, 0), (right, h as i32)))?;
        let chars = ((right - left) as usize / 9).max(8);
        let lines = wrap(UNKNOWN_LABEL, chars);
        let top = h as i32 / 2 - 9 * (lines.len() as i32 - 1);
        for (i, line) in lines.iter().enumerate() {
            area.draw(&Text::new(
                line.clone(),
                ((left + right) / 2, top + 18 * i as i32),
                text.clone(),
            ))
            .map_err(e)?;
        }
    }
    Ok(())
}

/// A light grey box `corners` (pixels of `area`) hatched by diagonal lines
/// 8 pixels apart.
fn hatch<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    ((x0, y0), (x1, y1)): ((i32, i32), (i32, i32)),
) -> Result<(), String> {
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    area.draw(&Rectangle::new(
        [(x0, y0), (x1, y1)],
        UNKNOWN.mix(0.12).filled(),
    ))
    .map_err(e)?;
    // Lines x - y = c, clipped to the box.
    let style = UNKNOWN.mix(0.6).stroke_width(1);
    for c in (x0 - y1..=x1 - y0).step_by(8) {
        let (from, to) = (x0.max(c + y0), x1.min(c + y1));
        if from <= to {
            let line = vec![(from, from - c), (to, to - c)];
            area.draw(&PathElement::new(line, style)).map_err(e)?;
        }
    }
    Ok(())
}

/// The legend below the panels, two entries a row.
fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    entries: &[(String, Swatch)],
) -> Result<(), String> {
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    let text = TextStyle::from((FONT, 15).into_font())
        .color(&BLACK)
        .pos(Pos::new(HPos::Left, VPos::Center));
    for (i, (label, swatch)) in entries.iter().enumerate() {
        let x = 103 + (i as i32 % 2) * 440;
        let y = 12 + (i as i32 / 2) * LEGEND_ROW as i32;
        match *swatch {
            Swatch::Line { color, dashed } => {
                let style = color.stroke_width(3);
                if dashed {
                    area.draw(&PathElement::new(vec![(x, y), (x + 10, y)], style))
                        .map_err(e)?;
                    area.draw(&PathElement::new(vec![(x + 16, y), (x + 28, y)], style))
                        .map_err(e)?;
                } else {
                    area.draw(&PathElement::new(vec![(x, y), (x + 28, y)], style))
                        .map_err(e)?;
                }
            }
            Swatch::Fill(color) => {
                area.draw(&Rectangle::new(
                    [(x, y - 7), (x + 28, y + 7)],
                    color.mix(0.18).filled(),
                ))
                .map_err(e)?;
            }
            Swatch::Circle => {
                area.draw(&Circle::new((x + 14, y), 4, BLACK.stroke_width(1)))
                    .map_err(e)?;
            }
            Swatch::Triangle => {
                area.draw(&TriangleMarker::new((x + 14, y), 8, BLACK.filled()))
                    .map_err(e)?;
            }
            Swatch::Diamond => {
                let corners = diamond(x + 14, y, 9);
                area.draw(&Polygon::new(corners.clone(), OPERATING.filled()))
                    .map_err(e)?;
                area.draw(&PathElement::new(corners, BLACK.stroke_width(1)))
                    .map_err(e)?;
            }
            Swatch::Hatch => hatch(area, ((x, y - 7), (x + 28, y + 7)))?,
        }
        area.draw(&Text::new(label.clone(), (x + 38, y), text.clone()))
            .map_err(e)?;
    }
    Ok(())
}

/// The corners of a diamond of half-diagonal `r` pixels around `(x, y)`,
/// closed (the first corner again at the end).
fn diamond(x: i32, y: i32, r: i32) -> Vec<(i32, i32)> {
    vec![(x, y - r), (x + r, y), (x, y + r), (x - r, y), (x, y - r)]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn figure(points: Vec<(f64, f64)>) -> StabilityFigure {
        StabilityFigure {
            title: "t".into(),
            x_label: "x".into(),
            y_label: "y".into(),
            segments: vec![Segment {
                points,
                criticality: Criticality::Supercritical,
            }],
            reference: Vec::new(),
            reference_label: "ref".into(),
            markers: Vec::new(),
            operating_point: None,
            vlines: Vec::new(),
            lpc: Vec::new(),
            bistable: Vec::new(),
            unknown: Vec::new(),
            x_range: (0.1, 100.0),
            notes: Vec::new(),
            stable_above: true,
        }
    }

    /// A region label goes above (or below) every curve over its width,
    /// also where the curve rises to the top at the preferred centre.
    #[test]
    fn region_labels_clear_the_curves() {
        let peak = |x: f64| 0.3 + 0.6 * (-((x - 0.5) / 0.1).powi(2)).exp();
        let curves = vec![
            (0..=100)
                .map(|i| (i as f64 / 100.0, peak(i as f64 / 100.0)))
                .collect::<Vec<_>>(),
            vec![(0.8, -1.0), (0.8, 2.0)],
        ];
        let size = (0.2, 0.06);
        for above in [true, false] {
            let (cx, cy) = place_label(&curves, size, &[0.5, 0.3, 0.7, 0.2, 0.9], above);
            // The curve's extent under the label, from its formula (finely
            // sampled), not from the placement's own measure.
            let under = (0..=1000).map(|i| peak(cx - 0.1 + 0.2 * i as f64 / 1000.0));
            let (lo, hi) = under.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), y| {
                (a.min(y), b.max(y))
            });
            assert!(
                if above {
                    cy - size.1 / 2.0 > hi
                } else {
                    cy + size.1 / 2.0 < lo
                },
                "{above}: ({cx}, {cy}) against {lo}..{hi}"
            );
            assert!((cx - 0.8).abs() > 0.1, "{cx} over the vertical line");
        }
    }

    /// A region label stands only where a curve crosses its whole width:
    /// beside a curve that starts at x = 0.6 (no onset at smaller x, one
    /// regime at every value there) the labels sit over x >= 0.6. Over a
    /// curve too narrow for them, or where a vertical line cuts every such
    /// place, they are centred over the curve, on a white box (`true`).
    #[test]
    fn region_labels_stand_only_over_the_curve() {
        let curve: Vec<(f64, f64)> = (0..=40)
            .map(|i| (0.6 + 0.4 * i as f64 / 40.0, 0.5))
            .collect();
        let size = (0.2, 0.06);
        for above in [true, false] {
            let ((cx, cy), boxed) = place_region_label(
                std::slice::from_ref(&curve),
                0,
                size,
                &[0.5, 0.3, 0.15],
                above,
            )
            .unwrap();
            assert!(cx - size.0 / 2.0 >= 0.6 && cx + size.0 / 2.0 <= 1.0, "{cx}");
            assert!(if above { cy > 0.5 } else { cy < 0.5 }, "{cy}");
            assert!(!boxed);
        }
        let narrow = vec![vec![(0.45, 0.5), (0.55, 0.5)]];
        let ((cx, cy), boxed) = place_region_label(&narrow, 0, size, &[0.5], true).unwrap();
        assert!(
            (0.45..=0.55).contains(&cx) && cy > 0.5 && boxed,
            "{cx} {cy}"
        );
        // The curve wide enough, but vertical lines at x = 0.7 and 0.85 in
        // the way of every place over it: centred over the curve, across
        // a line.
        let cut = vec![
            curve.clone(),
            vec![(0.7, -1.0), (0.7, 2.0)],
            vec![(0.85, -1.0), (0.85, 2.0)],
        ];
        let ((cx, cy), boxed) = place_region_label(&cut, 2, size, &[0.8], true).unwrap();
        assert!((0.6..=1.0).contains(&cx) && cy > 0.5 && boxed, "{cx} {cy}");
    }

    /// The magnifying panel appears exactly when the band is a few pixels
    /// wide: 0.25 % over a factor 2 of stiffness is, 50 % is not.
    #[test]
    fn a_thin_hysteretic_band_gets_its_own_panel() {
        for (width, thin) in [(2.5e-3, true), (0.5, false)] {
            let mut fig = figure(vec![(1.0, 1.0), (10.0, 2.0)]);
            fig.bistable = vec![vec![
                (2.0, 1.2 * (1.0 + width), Some(1.2)),
                (5.0, 1.6 * (1.0 + width), Some(1.6)),
            ]];
            fig.lpc = vec![vec![(2.0, 1.2 * (1.0 + width)), (5.0, 1.6 * (1.0 + width))]];
            assert_eq!(band_is_thin(&fig, y_range(&fig)), thin, "{width}");
        }
    }

    /// A span where the fold curve was not computed has its legend entry,
    /// and the legend does not otherwise change: the band's own entries
    /// stay as they are.
    /// An operating point far below (or above) the curve widens the y
    /// range to show it, and gets its legend entry.
    #[test]
    fn the_operating_point_is_inside_the_axes_and_in_the_legend() {
        for y in [1e-3, 1e3] {
            let mut fig = figure(vec![(1.0, 1.0), (10.0, 2.0)]);
            fig.operating_point = Some(OperatingMarker {
                label: "operating point".into(),
                x: 3.0,
                y,
                margin: None,
            });
            let (lo, hi) = y_range(&fig);
            assert!(lo < y && y < hi, "{y} outside ({lo}, {hi})");
            assert!(legend(&fig).iter().any(|e| e.0 == "operating point"));
        }
    }

    #[test]
    fn an_uncomputed_fold_curve_is_in_the_legend() {
        let mut fig = figure(vec![(1.0, 1.0), (10.0, 2.0)]);
        fig.lpc = vec![vec![(2.0, 1.3), (5.0, 1.7)]];
        fig.bistable = vec![vec![(2.0, 1.3, Some(1.2)), (5.0, 1.7, Some(1.6))]];
        let before: Vec<String> = legend(&fig).into_iter().map(|e| e.0).collect();
        fig.unknown = vec![(0.1, 2.0)];
        let after: Vec<String> = legend(&fig).into_iter().map(|e| e.0).collect();
        assert_eq!(after.len(), before.len() + 1);
        assert!(after.iter().any(|l| l.contains("not computed")));
        assert!(before.iter().all(|l| after.contains(l)));
    }

    #[test]
    fn rendering_never_fails_on_awkward_diagrams() {
        let dir = std::env::temp_dir().join(format!("stickslip-stab-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let mut thin = figure(vec![(0.1, 2.4e5), (30.0, 2.3e5), (100.0, 2.6e5)]);
        thin.bistable = vec![vec![
            (30.0, 2.3e5 * 1.002, Some(2.3e5)),
            (60.0, 2.4e5 * 1.001, Some(2.4e5)),
        ]];
        thin.lpc = vec![vec![(30.0, 2.3e5 * 1.002), (60.0, 2.4e5 * 1.001)]];
        thin.markers = vec![("Bautin (l1 = 0)".into(), 30.0, 2.3e5)];
        thin.unknown = vec![(0.1, 30.0)];
        let mut empty = figure(Vec::new());
        empty.segments.clear();
        empty.notes = vec![Note {
            text: "velocity strengthening over the whole range: stable for every stiffness".into(),
            span: None,
        }];
        let mut plunge = figure(vec![(0.1, 1e5), (10.0, 1e3), (16.0, 1e-30)]);
        plunge.vlines = vec![("κ_c → 0".into(), 16.0)];
        plunge.notes = vec![Note {
            text: "velocity strengthening for V = 16 .. 100 µm/s: stable for every stiffness"
                .into(),
            span: Some((16.0, 100.0)),
        }];
        for (i, fig) in [thin, empty, plunge, figure(vec![(1.0, 5.0)])]
            .iter()
            .enumerate()
        {
            let files = render(fig, &dir.join(format!("f{i}"))).unwrap();
            assert_eq!(files.len(), 2);
            assert!(std::fs::metadata(&files[0]).unwrap().len() > 1000);
        }
        std::fs::remove_dir_all(&dir).ok();
    }
}
