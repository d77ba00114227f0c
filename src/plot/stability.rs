//! Stability diagrams: the Hopf curve on log axes, sub- and supercritical
//! parts drawn differently, the Appendix C curve overlaid, special points
//! marked, stable and unstable regions labelled.

use super::{frame, render_both, Axis, PlotError, FONT};
use crate::analysis::hopf::Criticality;
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
    /// Vertical lines (label, x): the end of the curve where kappa_c -> 0.
    pub vlines: Vec<(String, f64)>,
    /// Curves of folds of cycles (LPC).
    pub lpc: Vec<Vec<(f64, f64)>>,
    /// Hysteretic regions below each LPC curve: `(x, upper y, lower y)`,
    /// the lower bound `None` where it is the bottom of the axes (no Hopf
    /// point at that velocity: steady sliding stable for every stiffness).
    pub bistable: Vec<Vec<(f64, f64, Option<f64>)>>,
    /// x range of the axes.
    pub x_range: (f64, f64),
    /// Lines of text written in the plot (e.g. "velocity strengthening: stable
    /// for every stiffness" where there is no Hopf curve).
    pub notes: Vec<String>,
}

const SUPER: RGBColor = RGBColor(31, 90, 180);
const SUB: RGBColor = RGBColor(200, 40, 40);
const DEGEN: RGBColor = RGBColor(120, 120, 120);
const FOLD: RGBColor = RGBColor(150, 60, 150);

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

/// Writes `stem.png` and `stem.svg`; returns their paths.
pub fn render(fig: &StabilityFigure, stem: &Path) -> Result<Vec<PathBuf>, PlotError> {
    render_both(stem, (1000, 700), |a| draw(a, fig), |a| draw(a, fig))
}

fn y_range(fig: &StabilityFigure) -> (f64, f64) {
    let ys = fig
        .segments
        .iter()
        .flat_map(|s| s.points.iter().map(|p| p.1))
        .chain(fig.reference.iter().map(|p| p.1))
        .chain(fig.lpc.iter().flatten().map(|p| p.1));
    let (lo, hi) = ys
        .filter(|y| *y > 0.0)
        .fold((f64::INFINITY, 0.0f64), |(a, b), y| (a.min(y), b.max(y)));
    if !lo.is_finite() {
        return (1e-3, 1.0);
    }
    // At least a decade with room for the region labels; at most four decades
    // below the top (a curve that plunges to kappa_c -> 0 is cut there).
    let lo = lo.max(hi * 1e-4);
    let mid = (lo * hi).sqrt();
    let half = (hi / lo).sqrt().max(10f64.sqrt()) * 1.8;
    (mid / half, mid * half)
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    fig: &StabilityFigure,
) -> Result<(), String> {
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    let (y0, y1) = y_range(fig);
    // A little room at both ends so the end ticks and markers show.
    let (x0, x1) = (fig.x_range.0 / 1.12, fig.x_range.1 * 1.12);
    let mut chart = frame(
        &root,
        (&fig.title, &fig.x_label, &fig.y_label),
        (Axis::over(x0, x1, true), Axis::over(y0, y1, true)),
        (x0..x1).log_scale(),
        (y0..y1).log_scale(),
    )?;
    // Region labels: steady sliding is stable at high stiffness (top) and, past a
    // friction minimum, at high velocity; stick-slip lives at low stiffness (bottom left).
    let at = |fx: f64, fy: f64| (x0 * (x1 / x0).powf(fx), y0 * (y1 / y0).powf(fy));
    let text = TextStyle::from((FONT, 20).into_font()).color(&RGBColor(60, 60, 60));
    let centred = text.pos(Pos::new(HPos::Center, VPos::Center));
    let left = text.pos(Pos::new(HPos::Left, VPos::Center));
    chart
        .draw_series([Text::new("steady sliding stable", at(0.5, 0.93), centred)])
        .map_err(e)?;
    if !fig.segments.is_empty() {
        chart
            .draw_series([Text::new("unstable: stick-slip", at(0.02, 0.06), left)])
            .map_err(e)?;
    }
    let note_style = TextStyle::from((FONT, 18).into_font())
        .color(&RGBColor(90, 140, 60))
        .pos(Pos::new(HPos::Center, VPos::Center));
    chart
        .draw_series(fig.notes.iter().enumerate().map(|(i, line)| {
            Text::new(
                line.clone(),
                at(0.5, 0.5 - 0.06 * i as f64),
                note_style.clone(),
            )
        }))
        .map_err(e)?;
    for (i, region) in fig.bistable.iter().enumerate() {
        let mut polygon: Vec<(f64, f64)> = region.iter().map(|&(x, hi, _)| (x, hi)).collect();
        polygon.extend(region.iter().rev().map(|&(x, _, lo)| (x, lo.unwrap_or(y0))));
        let series = chart
            .draw_series([Polygon::new(polygon, FOLD.mix(0.18).filled())])
            .map_err(e)?;
        if i == 0 {
            series
                .label("bistable: stick-slip coexists with steady sliding")
                .legend(|(x, y)| {
                    Rectangle::new([(x, y - 6), (x + 24, y + 6)], FOLD.mix(0.18).filled())
                });
        }
    }
    for (i, curve) in fig.lpc.iter().enumerate() {
        let series = chart
            .draw_series(LineSeries::new(curve.clone(), FOLD.stroke_width(3)))
            .map_err(e)?;
        if i == 0 {
            series
                .label("fold of cycles (LPC): hysteresis boundary")
                .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], FOLD.stroke_width(3)));
        }
    }
    let mut labelled = Vec::new();
    for s in &fig.segments {
        let c = color(s.criticality);
        let style = c.stroke_width(3);
        let series = if s.criticality == Criticality::Subcritical {
            chart.draw_series(DashedLineSeries::new(s.points.clone(), 10, 6, style))
        } else {
            chart.draw_series(LineSeries::new(s.points.clone(), style))
        }
        .map_err(e)?;
        if !labelled.contains(&s.criticality) {
            labelled.push(s.criticality);
            series.label(label(s.criticality)).legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 24, y)], c.stroke_width(3))
            });
        }
    }
    if !fig.reference.is_empty() {
        chart
            .draw_series(
                fig.reference
                    .iter()
                    .map(|&p| Circle::new(p, 4, BLACK.stroke_width(1))),
            )
            .map_err(e)?
            .label(&fig.reference_label)
            .legend(|(x, y)| Circle::new((x + 12, y), 4, BLACK.stroke_width(1)));
    }
    let mut marker_labels: Vec<&str> = Vec::new();
    for (name, x, y) in &fig.markers {
        let series = chart
            .draw_series([TriangleMarker::new((*x, *y), 9, BLACK.filled())])
            .map_err(e)?;
        if !marker_labels.contains(&name.as_str()) {
            marker_labels.push(name);
            series
                .label(name)
                .legend(|(x, y)| TriangleMarker::new((x + 12, y), 7, BLACK.filled()));
        }
    }
    for (name, x) in &fig.vlines {
        let c = RGBColor(90, 140, 60);
        chart
            .draw_series(DashedLineSeries::new(
                vec![(*x, y0), (*x, y1)],
                8,
                6,
                c.stroke_width(2),
            ))
            .map_err(e)?
            .label(name)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], c.stroke_width(2)));
    }
    let has_legend = !(fig.segments.is_empty()
        && fig.reference.is_empty()
        && fig.markers.is_empty()
        && fig.vlines.is_empty()
        && fig.bistable.is_empty()
        && fig.lpc.is_empty());
    if !has_legend {
        root.present().map_err(e)?;
        return Ok(());
    }
    chart
        .configure_series_labels()
        // With a hysteretic region the lower right is taken by it.
        .position(if fig.lpc.is_empty() {
            SeriesLabelPosition::LowerRight
        } else {
            SeriesLabelPosition::UpperRight
        })
        .background_style(WHITE.mix(0.9))
        .border_style(BLACK)
        .label_font((FONT, 15))
        .draw()
        .map_err(e)?;
    root.present().map_err(e)?;
    Ok(())
}
