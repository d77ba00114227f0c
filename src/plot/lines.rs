//! Generic line figures (PNG and SVG): several labelled series on linear or
//! logarithmic axes. Cycle diagrams, orbits and time series use it.

use super::{frame, render_both, PlotError, FONT};
use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::prelude::*;
use std::path::{Path, PathBuf};

/// One curve of a figure.
#[derive(Clone, Debug)]
pub struct Series {
    pub label: Option<String>,
    pub points: Vec<(f64, f64)>,
    pub color: RGBColor,
    pub dashed: bool,
    /// Draw markers instead of a line.
    pub markers: bool,
}

/// A figure: title, axes, series.
#[derive(Clone, Debug)]
pub struct LineFigure {
    pub title: String,
    pub x_label: String,
    pub y_label: String,
    pub log_x: bool,
    pub log_y: bool,
    pub series: Vec<Series>,
}

fn bounds(fig: &LineFigure) -> ((f64, f64), (f64, f64)) {
    let pts = fig
        .series
        .iter()
        .flat_map(|s| s.points.iter())
        .filter(|(x, y)| {
            x.is_finite() && y.is_finite() && (!fig.log_x || *x > 0.0) && (!fig.log_y || *y > 0.0)
        });
    let (mut x0, mut x1, mut y0, mut y1) = (
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
    );
    for &(x, y) in pts {
        (x0, x1, y0, y1) = (x0.min(x), x1.max(x), y0.min(y), y1.max(y));
    }
    let pad = |lo: f64, hi: f64, log: bool| {
        if !lo.is_finite() {
            return (1.0, 10.0);
        }
        if log {
            let r = (hi / lo).max(1.0001).powf(0.05);
            (lo / r, hi * r)
        } else {
            let d = (hi - lo).max(1e-12 * hi.abs().max(1e-300));
            (lo - 0.05 * d, hi + 0.05 * d)
        }
    };
    (pad(x0, x1, fig.log_x), pad(y0, y1, fig.log_y))
}

/// Writes `stem.png` and `stem.svg`.
pub fn render(fig: &LineFigure, stem: &Path) -> Result<Vec<PathBuf>, PlotError> {
    render_both(
        stem,
        (1000, 650),
        |a| draw_any(a, fig),
        |a| draw_any(a, fig),
    )
}

fn draw_any<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    fig: &LineFigure,
) -> Result<(), String> {
    let ((x0, x1), (y0, y1)) = bounds(fig);
    match (fig.log_x, fig.log_y) {
        (false, false) => draw(root, fig, x0..x1, y0..y1),
        (true, false) => draw(root, fig, (x0..x1).log_scale(), y0..y1),
        (false, true) => draw(root, fig, x0..x1, (y0..y1).log_scale()),
        (true, true) => draw(root, fig, (x0..x1).log_scale(), (y0..y1).log_scale()),
    }
}

fn draw<DB: DrawingBackend, X, Y>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    fig: &LineFigure,
    xr: X,
    yr: Y,
) -> Result<(), String>
where
    X: AsRangedCoord<Value = f64>,
    Y: AsRangedCoord<Value = f64>,
    X::CoordDescType: ValueFormatter<f64>,
    Y::CoordDescType: ValueFormatter<f64>,
{
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    let mut chart = frame(
        &root,
        (&fig.title, &fig.x_label, &fig.y_label),
        (fig.log_x, fig.log_y),
        xr,
        yr,
    )?;
    let mut any_label = false;
    for s in &fig.series {
        let c = s.color;
        let style = c.stroke_width(2);
        let drawn = if s.markers {
            chart
                .draw_series(s.points.iter().map(|&p| Circle::new(p, 3, c.filled())))
                .map_err(e)?
        } else if s.dashed {
            chart
                .draw_series(DashedLineSeries::new(s.points.clone(), 8, 5, style))
                .map_err(e)?
        } else {
            chart
                .draw_series(LineSeries::new(s.points.clone(), style))
                .map_err(e)?
        };
        if let Some(label) = &s.label {
            any_label = true;
            drawn.label(label).legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 22, y)], c.stroke_width(2))
            });
        }
    }
    if any_label {
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.9))
            .border_style(BLACK)
            .label_font((FONT, 14))
            .draw()
            .map_err(e)?;
    }
    root.present().map_err(e)?;
    Ok(())
}
