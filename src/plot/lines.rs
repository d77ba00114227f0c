//! Generic line figures (PNG and SVG): several labelled series on linear or
//! logarithmic axes. Cycle diagrams, orbits and time series use it.

use super::{frame, render_both, Axis, PlotError, FONT};
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

/// A vertical dashed line at `x` over the vertical extent of `series`
/// (finite values), labelled: a marker such as a change of model.
pub fn vertical_marker(series: &[Series], x: f64, label: &str, color: RGBColor) -> Series {
    let (lo, hi) = series
        .iter()
        .flat_map(|s| s.points.iter().map(|p| p.1))
        .filter(|y| y.is_finite())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), y| {
            (a.min(y), b.max(y))
        });
    Series {
        label: Some(label.into()),
        points: vec![(x, lo), (x, hi)],
        color,
        dashed: true,
        markers: false,
    }
}

/// Colour and label of the marker where an analysis changes from the
/// quasi-static to the inertial model.
pub const SWITCH_MARKER: (RGBColor, &str) =
    (RGBColor(20, 140, 60), "quasi-static → inertial model");

/// Smallest value a log axis draws: below it (and at or below 0) a point
/// has no place on a log axis that plotters can lay out.
const LOG_FLOOR: f64 = 1e-300;

/// Whether `(x, y)` can be drawn on the figure's axes.
fn drawable(fig: &LineFigure, (x, y): (f64, f64)) -> bool {
    x.is_finite()
        && y.is_finite()
        && (!fig.log_x || x >= LOG_FLOOR)
        && (!fig.log_y || y >= LOG_FLOOR)
}

/// The figure with the points its axes cannot draw (non-finite, or not
/// above [`LOG_FLOOR`] on a log axis) left out, and a note in the title
/// saying how many.
fn drawable_only(fig: &LineFigure) -> LineFigure {
    let mut out = fig.clone();
    let mut dropped = 0;
    for s in &mut out.series {
        let before = s.points.len();
        s.points.retain(|&p| drawable(fig, p));
        dropped += before - s.points.len();
    }
    if dropped > 0 {
        out.title = format!(
            "{} ({dropped} points not drawn: non-finite, or <= {LOG_FLOOR:e} on a log axis)",
            fig.title
        );
    }
    out
}

/// The axis ranges of `fig` (whose points are all drawable), padded by 5 %;
/// a constant series gets a range around its value (a factor 10 on a log
/// axis, +-5 % or +-1 about 0 on a linear one), an empty figure `1 .. 10`.
fn bounds(fig: &LineFigure) -> ((f64, f64), (f64, f64)) {
    let pts = fig.series.iter().flat_map(|s| s.points.iter());
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
            // At least a factor 10 (so that the axis has a labelled tick).
            let mid = (lo * hi).sqrt();
            let (lo, hi) = if hi / lo < 10.0 {
                (mid / 10f64.sqrt(), mid * 10f64.sqrt())
            } else {
                (lo, hi)
            };
            let r = (hi / lo).powf(0.05);
            ((lo / r).max(LOG_FLOOR), hi * r)
        } else {
            let scale = hi.abs().max(lo.abs());
            let d = hi - lo;
            if d <= 1e-12 * scale || d == 0.0 {
                let half = if scale > 0.0 { 0.05 * scale } else { 1.0 };
                (lo - half, hi + half)
            } else {
                (lo - 0.05 * d, hi + 0.05 * d)
            }
        }
    };
    (pad(x0, x1, fig.log_x), pad(y0, y1, fig.log_y))
}

/// Columns of the min/max decimation: about the plot's width in pixels.
const COLUMNS: usize = 1000;

/// The points of a dense line `points` (x in drawing order) reduced to at
/// most four per column of the x range `(x0, x1)` (split into [`COLUMNS`],
/// evenly in `ln x` on a log axis): the first, lowest, highest and last
/// point of each column, in their order. A line through them covers every
/// pixel the full line covers, with the same extremes: a spike one sample
/// wide is drawn to its tip (thinning every k-th sample would cut it).
fn decimated(points: &[(f64, f64)], (x0, x1): (f64, f64), log_x: bool) -> Vec<(f64, f64)> {
    if points.len() <= 4 * COLUMNS {
        return points.to_vec();
    }
    let map = |x: f64| if log_x { x.ln() } else { x };
    let (a, b) = (map(x0), map(x1));
    let column = |x: f64| (((map(x) - a) / (b - a) * COLUMNS as f64) as usize).min(COLUMNS - 1);
    let mut out = Vec::with_capacity(4 * COLUMNS);
    let mut start = 0;
    while start < points.len() {
        let col = column(points[start].0);
        let mut end = start + 1;
        while end < points.len() && column(points[end].0) == col {
            end += 1;
        }
        let run = &points[start..end];
        let by_y = |f: fn(f64, f64) -> bool| {
            (0..run.len())
                .reduce(|i, j| if f(run[j].1, run[i].1) { j } else { i })
                .unwrap_or(0)
        };
        let mut keep = [0, by_y(|a, b| a < b), by_y(|a, b| a > b), run.len() - 1];
        keep.sort_unstable();
        let mut last = None;
        for k in keep {
            if last != Some(k) {
                out.push(run[k]);
                last = Some(k);
            }
        }
        start = end;
    }
    out
}

/// The corner of the plot where the legend hides the fewest points: the
/// points (log-aware) falling in each corner box of 35 % x 30 % of the axes,
/// counted; ties go to the upper right, then upper left.
fn emptiest_corner(fig: &LineFigure) -> SeriesLabelPosition {
    let ((x0, x1), (y0, y1)) = bounds(fig);
    let unit = |v: f64, lo: f64, hi: f64, log: bool| {
        if log {
            (v.ln() - lo.ln()) / (hi.ln() - lo.ln())
        } else {
            (v - lo) / (hi - lo)
        }
    };
    let corners = [
        (SeriesLabelPosition::UpperRight, (0.65, 1.0), (0.7, 1.0)),
        (SeriesLabelPosition::UpperLeft, (0.0, 0.35), (0.7, 1.0)),
        (SeriesLabelPosition::LowerRight, (0.65, 1.0), (0.0, 0.3)),
        (SeriesLabelPosition::LowerLeft, (0.0, 0.35), (0.0, 0.3)),
    ];
    let count = |(xa, xb): (f64, f64), (ya, yb): (f64, f64)| {
        fig.series
            .iter()
            .flat_map(|s| s.points.iter())
            .filter(|&&(x, y)| {
                let (u, w) = (unit(x, x0, x1, fig.log_x), unit(y, y0, y1, fig.log_y));
                (xa..=xb).contains(&u) && (ya..=yb).contains(&w)
            })
            .count()
    };
    corners
        .into_iter()
        .min_by_key(|(_, xs, ys)| count(*xs, *ys))
        .map_or(SeriesLabelPosition::UpperRight, |c| c.0)
}

/// Writes `stem.png` and `stem.svg`. Never fails on the data: points a
/// log axis cannot draw are left out with a note in the title, and a
/// constant series gets a sane range. Dense lines are drawn from their
/// min/max decimation ([`decimated`]).
pub fn render(fig: &LineFigure, stem: &Path) -> Result<Vec<PathBuf>, PlotError> {
    let mut fig = drawable_only(fig);
    let (xr, _) = bounds(&fig);
    for s in fig.series.iter_mut().filter(|s| !s.markers) {
        s.points = decimated(&s.points, xr, fig.log_x);
    }
    render_both(
        stem,
        (1000, 650),
        |a| draw_any(a, &fig),
        |a| draw_any(a, &fig),
    )
}

fn draw_any<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    fig: &LineFigure,
) -> Result<(), String> {
    let ((x0, x1), (y0, y1)) = bounds(fig);
    let axes = (Axis::over(x0, x1, fig.log_x), Axis::over(y0, y1, fig.log_y));
    match (fig.log_x, fig.log_y) {
        (false, false) => draw(root, fig, axes, x0..x1, y0..y1),
        (true, false) => draw(root, fig, axes, (x0..x1).log_scale(), y0..y1),
        (false, true) => draw(root, fig, axes, x0..x1, (y0..y1).log_scale()),
        (true, true) => draw(root, fig, axes, (x0..x1).log_scale(), (y0..y1).log_scale()),
    }
}

fn draw<DB: DrawingBackend, X, Y>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    fig: &LineFigure,
    axes: (Axis, Axis),
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
        axes,
        xr,
        yr,
    )?;
    let mut any_label = false;
    for s in &fig.series {
        let c = s.color;
        // plotters draws a wide line as a polygon that degenerates on
        // (nearly) vertical pixel steps, the spikes of a dense series: those
        // get a one-pixel line, whose drawing is exact.
        let dense = s.points.len() > COLUMNS;
        let style = c.stroke_width(if dense { 1 } else { 2 });
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
            .position(emptiest_corner(fig))
            .background_style(WHITE.mix(0.9))
            .border_style(BLACK)
            .label_font((FONT, 14))
            .draw()
            .map_err(e)?;
    }
    root.present().map_err(e)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn figure(points: Vec<(f64, f64)>, log_y: bool) -> LineFigure {
        LineFigure {
            title: "t".into(),
            x_label: "x".into(),
            y_label: "y".into(),
            log_x: false,
            log_y,
            series: vec![Series {
                label: None,
                points,
                color: RGBColor(0, 0, 0),
                dashed: false,
                markers: false,
            }],
        }
    }

    #[test]
    fn log_axis_drops_non_positive_points_with_a_note() {
        let f = drawable_only(&figure(
            vec![(0.0, 1.0), (1.0, 0.0), (2.0, 1e-320), (3.0, 5.0)],
            true,
        ));
        assert_eq!(f.series[0].points, vec![(0.0, 1.0), (3.0, 5.0)]);
        assert!(f.title.contains("2 points not drawn"), "{}", f.title);
        let ((_, _), (y0, y1)) = bounds(&f);
        assert!(y0 > 0.0 && y0 < 1.0 && y1 > 5.0, "{y0} {y1}");
    }

    #[test]
    fn constant_series_get_a_range() {
        let ((x0, x1), (y0, y1)) = bounds(&figure(vec![(2.0, 0.0), (2.0, 0.0)], false));
        assert!(
            (x0 - 1.9).abs() < 1e-12 && (x1 - 2.1).abs() < 1e-12,
            "{x0} {x1}"
        );
        assert_eq!((y0, y1), (-1.0, 1.0));
        let (_, (y0, y1)) = bounds(&figure(vec![(1.0, 3.0), (2.0, 3.0)], true));
        assert!(y1 / y0 > 10.0 && y0 < 3.0 && y1 > 3.0, "{y0} {y1}");
    }

    /// A spike train of a million samples, one sample wide each: the
    /// decimated line keeps every tip and the overall extremes, in order, with
    /// at most four points per column.
    /// A curve through the upper right leaves the legend elsewhere.
    #[test]
    fn legend_goes_to_the_emptiest_corner() {
        let fig = figure((0..100).map(|i| (i as f64, i as f64)).collect(), false);
        assert!(matches!(
            emptiest_corner(&fig),
            SeriesLabelPosition::UpperLeft
        ));
    }

    #[test]
    fn decimation_keeps_every_spike_tip() {
        let n = 1_000_000;
        let points: Vec<(f64, f64)> = (0..n)
            .map(|i| {
                (
                    i as f64,
                    if i % 10_000 == 5_000 {
                        1e6 + i as f64
                    } else {
                        1.0 + (i % 7) as f64
                    },
                )
            })
            .collect();
        let d = decimated(&points, (0.0, (n - 1) as f64), false);
        assert!(d.len() <= 4 * COLUMNS);
        let tips: Vec<&(f64, f64)> = d.iter().filter(|p| p.1 >= 1e6).collect();
        assert_eq!(tips.len(), n / 10_000);
        assert!(tips.iter().all(|p| p.0 as usize % 10_000 == 5_000));
        assert!(d.windows(2).all(|w| w[0].0 < w[1].0));
        let lowest = d.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
        assert_eq!(lowest, 1.0);
        assert_eq!((d[0], *d.last().unwrap()), (points[0], points[n - 1]));
    }

    #[test]
    fn rendering_never_fails_on_degenerate_data() {
        let dir = std::env::temp_dir().join(format!("stickslip-lines-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        for (points, log_y) in [
            (vec![(0.0, 0.0), (1.0, 0.0)], true),
            (vec![(0.0, 0.0), (1.0, 0.0)], false),
            (vec![(0.0, 1e-310), (1.0, 1e300)], true),
        ] {
            let files = render(&figure(points, log_y), &dir.join("f")).unwrap();
            assert_eq!(files.len(), 2);
        }
        std::fs::remove_dir_all(&dir).ok();
    }
}
