//! Generic line figures (PNG and SVG): several labelled series on linear or
//! logarithmic axes. Cycle diagrams, orbits and time series use it.

use super::colormap::{viridis, LINE_END};
use super::{frame, render_both, Axis, Chart, PlotError, FONT};
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

/// The colour scale of a family of curves (one per value of a parameter,
/// such as cycles at successive stiffnesses), drawn as a bar beside the
/// plot instead of a legend entry per curve.
#[derive(Clone, Debug)]
pub struct Colorbar {
    /// What the colour shows, with its unit.
    pub label: String,
    /// The values at the two ends of the scale.
    pub range: (f64, f64),
    /// Logarithmic (values over more than a decade, all positive).
    pub log: bool,
}

impl Colorbar {
    /// The scale over the finite `values` (`0 .. 1` when there are none).
    pub fn over(label: &str, values: impl IntoIterator<Item = f64>) -> Colorbar {
        let (lo, hi) = values
            .into_iter()
            .filter(|v| v.is_finite())
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                (a.min(v), b.max(v))
            });
        let range = if lo.is_finite() { (lo, hi) } else { (0.0, 1.0) };
        Colorbar {
            label: label.into(),
            range,
            log: range.0 > 0.0 && range.1 > 10.0 * range.0,
        }
    }

    /// The colour of `value`: viridis over the scale (the middle of it for
    /// a scale of one value).
    pub fn color(&self, value: f64) -> RGBColor {
        let (lo, hi) = self.range;
        let t = if hi > lo {
            unit(value, lo, hi, self.log)
        } else {
            0.5
        };
        viridis(t * LINE_END)
    }
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
/// a constant series gets a range around its value (a factor 1.5 on a log
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
            // At least a factor 1.5 (a constant series gets a range about it).
            let mid = (lo * hi).sqrt();
            let (lo, hi) = if hi / lo < 1.5 {
                (mid / 1.5f64.sqrt(), mid * 1.5f64.sqrt())
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

/// Whether the points of a line run in order of increasing `x` (a time
/// series or a branch) rather than around a closed orbit.
fn monotonic_in_x(points: &[(f64, f64)]) -> bool {
    points.windows(2).all(|w| w[1].0 >= w[0].0)
}

/// A curve that is not a function of `x` (an orbit) reduced to the points
/// at least half a pixel apart on a plot of `pixels` over `ranges`: the
/// drawn line differs from the full one by less than half a pixel.
fn thinned(
    points: &[(f64, f64)],
    ranges: ((f64, f64), (f64, f64)),
    (log_x, log_y): (bool, bool),
    pixels: (f64, f64),
) -> Vec<(f64, f64)> {
    let ((x0, x1), (y0, y1)) = ranges;
    let to_px = |(x, y): (f64, f64)| {
        (
            unit(x, x0, x1, log_x) * pixels.0,
            unit(y, y0, y1, log_y) * pixels.1,
        )
    };
    let mut out: Vec<(f64, f64)> = Vec::with_capacity(points.len().min(4 * COLUMNS));
    let mut last = None;
    for (i, &p) in points.iter().enumerate() {
        let q = to_px(p);
        let far = last.is_none_or(|(a, b): (f64, f64)| (q.0 - a).hypot(q.1 - b) >= 0.5);
        if far || i + 1 == points.len() {
            out.push(p);
            last = Some(q);
        }
    }
    out
}

/// Where `v` lies between `lo` and `hi` on a linear or logarithmic axis (0 to 1).
fn unit(v: f64, lo: f64, hi: f64, log: bool) -> f64 {
    if log {
        (v.ln() - lo.ln()) / (hi.ln() - lo.ln())
    } else {
        (v - lo) / (hi - lo)
    }
}

/// Size of the plotting area of a figure `width` x 650 pixels (the frame's
/// margins, caption and label areas taken off).
fn plot_pixels(width: u32) -> (f64, f64) {
    (
        width as f64 - 2.0 * 18.0 - 85.0,
        650.0 - 2.0 * 18.0 - 55.0 - 30.0,
    )
}

/// The legend's size as a fraction of the plotting area `pixels`: rows of
/// 20 pixels, labels of at most 8 pixels a character in the 14-pixel font,
/// a swatch, and padding (an upper bound of what plotters draws).
fn legend_fraction(fig: &LineFigure, pixels: (f64, f64)) -> (f64, f64) {
    let labels: Vec<&String> = fig.series.iter().filter_map(|s| s.label.as_ref()).collect();
    let chars = labels.iter().map(|l| l.chars().count()).max().unwrap_or(0);
    let width = 8.0 * chars as f64 + 60.0;
    let height = 20.0 * labels.len() as f64 + 20.0;
    (width / pixels.0, height / pixels.1)
}

/// How a line figure is laid out: the axis ranges and the legend's corner
/// with its box.
#[derive(Clone, Debug)]
struct Layout {
    x: (f64, f64),
    y: (f64, f64),
    legend: (SeriesLabelPosition, UnitBox),
}

/// A box of the plotting area in unit coordinates: `(x span, y span)`.
pub type UnitBox = ((f64, f64), (f64, f64));

/// Corners of the plotting area as `(position, box)` in unit
/// coordinates, for a legend of size `(w, h)` (fractions of the area).
fn corners((w, h): (f64, f64)) -> [(SeriesLabelPosition, UnitBox); 4] {
    [
        (
            SeriesLabelPosition::UpperRight,
            ((1.0 - w, 1.0), (1.0 - h, 1.0)),
        ),
        (SeriesLabelPosition::UpperLeft, ((0.0, w), (1.0 - h, 1.0))),
        (SeriesLabelPosition::LowerRight, ((1.0 - w, 1.0), (0.0, h))),
        (SeriesLabelPosition::LowerLeft, ((0.0, w), (0.0, h))),
    ]
}

/// How much of every series (its points, and its lines sampled at 1 % of
/// the axes) falls in the box `xs` x `ys` (unit coordinates) of a figure
/// drawn over `ranges`.
fn occupancy(fig: &LineFigure, ranges: ((f64, f64), (f64, f64)), (xs, ys): UnitBox) -> usize {
    let ((x0, x1), (y0, y1)) = ranges;
    let inside = |(u, w): (f64, f64)| (xs.0..=xs.1).contains(&u) && (ys.0..=ys.1).contains(&w);
    let mut count = 0;
    for s in &fig.series {
        let pts: Vec<(f64, f64)> = s
            .points
            .iter()
            .map(|&(x, y)| (unit(x, x0, x1, fig.log_x), unit(y, y0, y1, fig.log_y)))
            .collect();
        count += pts.iter().filter(|&&p| inside(p)).count();
        if !s.markers {
            for w in pts.windows(2) {
                let (a, b) = (w[0], w[1]);
                let n = (((b.0 - a.0).hypot(b.1 - a.1) / 0.01).ceil() as usize).min(100);
                count += (1..n)
                    .map(|k| k as f64 / n as f64)
                    .filter(|t| inside((a.0 + t * (b.0 - a.0), a.1 + t * (b.1 - a.1))))
                    .count();
            }
        }
    }
    count
}

/// The axis ranges ([`bounds`]) and the corner where the legend covers no
/// data: the emptiest corner (ties go to the upper right, then upper left);
/// if every corner holds data, the y axis is extended upward by the legend's
/// height so that the upper corner is free.
fn layout(fig: &LineFigure, pixels: (f64, f64)) -> Layout {
    let (x, y) = bounds(fig);
    let size = legend_fraction(fig, pixels);
    let counts = corners(size).map(|(pos, b)| (pos, b, occupancy(fig, (x, y), b)));
    let best = counts
        .iter()
        .min_by_key(|c| c.2)
        .map(|c| (c.0.clone(), c.1))
        .expect("four corners");
    if counts.iter().any(|c| c.2 == 0) || !fig.series.iter().any(|s| s.label.is_some()) {
        return Layout { x, y, legend: best };
    }
    // Data below a fraction `1 - h` of the extended axis (with 2 % to spare).
    let keep = (1.0 - size.1 - 0.02).max(0.3);
    let top = if fig.log_y {
        y.0 * (y.1 / y.0).powf(1.0 / keep)
    } else {
        y.0 + (y.1 - y.0) / keep
    };
    let y = (y.0, top);
    let upper = corners(size)[..2]
        .iter()
        .min_by_key(|(_, b)| occupancy(fig, (x, y), *b))
        .cloned()
        .expect("two upper corners");
    Layout {
        x,
        y,
        legend: upper,
    }
}

/// Width of the colour bar beside a family's plot, in pixels, for labels
/// of up to [`BAR_LABEL_CHARS`] characters; longer ones widen it
/// ([`colorbar_width`]).
const COLORBAR_WIDTH: u32 = 140;

/// Characters of the colour bar's labels [`COLORBAR_WIDTH`] holds.
const BAR_LABEL_CHARS: usize = 7;

/// Pixels a character of the colour bar's labels takes (font size 16).
const BAR_CHAR_PIXELS: u32 = 9;

/// The colour bar's width for the labels of `axis`: [`COLORBAR_WIDTH`],
/// widened by [`BAR_CHAR_PIXELS`] per character beyond
/// [`BAR_LABEL_CHARS`] (a stiffness branch over 1e-6 relative is labelled
/// `3.999994e2`, whose first digit was cut off).
fn colorbar_width(axis: &Axis) -> u32 {
    let longest = axis
        .labels()
        .iter()
        .map(|l| l.chars().count())
        .max()
        .unwrap_or(0);
    COLORBAR_WIDTH + BAR_CHAR_PIXELS * longest.saturating_sub(BAR_LABEL_CHARS) as u32
}

/// What the plotting layer decides for a line figure before it draws:
/// the points drawn, the axes and the legend's place.
#[derive(Clone, Debug)]
pub struct Plan {
    /// The figure as drawn: the points its axes can draw ([`drawable_only`],
    /// with the title's note), dense lines decimated ([`decimated`]),
    /// orbits thinned ([`thinned`]).
    pub figure: LineFigure,
    /// The x axis drawn.
    pub x: Axis,
    /// The y axis drawn.
    pub y: Axis,
    /// The colour bar's axis, for a family.
    pub bar: Option<Axis>,
    /// The legend's box in unit coordinates of the plotting area; `None`
    /// without a labelled series.
    pub legend: Option<UnitBox>,
    corner: SeriesLabelPosition,
}

/// The [`Plan`] of `fig` (a family coloured by `bar`, if any). Never fails
/// on the data: points a log axis cannot draw are left out with a note in
/// the title, and a constant series gets a sane range. Dense lines keep
/// their min/max decimation, orbits the points half a pixel apart; the
/// legend goes where it covers no data ([`layout`]).
pub fn plan(fig: &LineFigure, bar: Option<&Colorbar>) -> Plan {
    let mut fig = drawable_only(fig);
    let bar_axis = bar.map(bar_axis);
    let pixels = plot_pixels(WIDTH - bar_axis.as_ref().map_or(0, colorbar_width));
    let ranges = bounds(&fig);
    // A line through one point draws nothing: that point is drawn as a
    // marker (a branch of one cycle, a curve of one point).
    for s in fig.series.iter_mut().filter(|s| s.points.len() == 1) {
        s.markers = true;
    }
    for s in fig.series.iter_mut().filter(|s| !s.markers) {
        s.points = if monotonic_in_x(&s.points) {
            decimated(&s.points, ranges.0, fig.log_x)
        } else {
            thinned(&s.points, ranges, (fig.log_x, fig.log_y), pixels)
        };
    }
    let layout = layout(&fig, pixels);
    let labelled = fig.series.iter().any(|s| s.label.is_some());
    let ((x0, x1), (y0, y1)) = (layout.x, layout.y);
    Plan {
        x: Axis::new(x0, x1, fig.log_x),
        y: Axis::new(y0, y1, fig.log_y),
        bar: bar_axis,
        legend: labelled.then_some(layout.legend.1),
        corner: layout.legend.0,
        figure: fig,
    }
}

/// Width of a line figure in pixels (a family's includes its colour bar).
const WIDTH: u32 = 1000;

/// Writes `stem.png` and `stem.svg`, as [`plan`] lays the figure out.
pub fn render(fig: &LineFigure, stem: &Path) -> Result<Vec<PathBuf>, PlotError> {
    render_with(fig, None, stem)
}

/// [`render`] for a family of curves coloured by `bar` ([`Colorbar::color`]),
/// with the colour bar beside the plot.
pub fn render_family(
    fig: &LineFigure,
    bar: &Colorbar,
    stem: &Path,
) -> Result<Vec<PathBuf>, PlotError> {
    render_with(fig, Some(bar), stem)
}

fn render_with(
    fig: &LineFigure,
    bar: Option<&Colorbar>,
    stem: &Path,
) -> Result<Vec<PathBuf>, PlotError> {
    let plan = plan(fig, bar);
    render_both(
        stem,
        (WIDTH, 650),
        |a| draw_any(a, &plan, bar),
        |a| draw_any(a, &plan, bar),
    )
}

fn draw_any<DB: DrawingBackend>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    plan: &Plan,
    bar: Option<&Colorbar>,
) -> Result<(), String> {
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    root.fill(&WHITE).map_err(e)?;
    let root = match (bar, &plan.bar) {
        (Some(bar), Some(axis)) => {
            let width = root.dim_in_pixel().0;
            let (main, side) = root.split_horizontally(width - colorbar_width(axis));
            draw_colorbar(&side, bar, axis)?;
            main
        }
        _ => root,
    };
    let (x, y) = (&plan.x, &plan.y);
    match (x.log, y.log) {
        (false, false) => draw(root, plan, x.linear_coord(), y.linear_coord()),
        (true, false) => draw(root, plan, x.log_coord(), y.linear_coord()),
        (false, true) => draw(root, plan, x.linear_coord(), y.log_coord()),
        (true, true) => draw(root, plan, x.log_coord(), y.log_coord()),
    }
}

/// The axis of a colour bar: its scale, widened about a single value.
fn bar_axis(bar: &Colorbar) -> Axis {
    let (lo, hi) = bar.range;
    let (lo, hi) = if hi > lo {
        (lo, hi)
    } else {
        let half = if lo != 0.0 { 0.05 * lo.abs() } else { 1.0 };
        (lo - half, hi + half)
    };
    Axis::new(lo, hi, bar.log)
}

/// The colour bar of a family: the scale as a strip of 200 colours with
/// the values labelled on `axis`, aligned with the plotting area beside it.
fn draw_colorbar<DB: DrawingBackend>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    bar: &Colorbar,
    axis: &Axis,
) -> Result<(), String> {
    let (lo, hi) = axis.range;
    // The strip in unit steps of the scale (log or linear), labelled on its axis.
    let n = 200;
    let strip: Vec<_> = (0..n)
        .map(|i| {
            let (a, b) = (i as f64 / n as f64, (i + 1) as f64 / n as f64);
            let at = |t: f64| {
                if bar.log {
                    lo * (hi / lo).powf(t)
                } else {
                    lo + t * (hi - lo)
                }
            };
            Rectangle::new(
                [(0.0, at(a)), (1.0, at(b))],
                viridis((a + b) / 2.0 * LINE_END).filled(),
            )
        })
        .collect();
    if bar.log {
        draw_strip(area, &bar.label, axis, axis.log_coord(), strip)
    } else {
        draw_strip(area, &bar.label, axis, axis.linear_coord(), strip)
    }
}

/// The colour bar's chart over `yr`: the `strip` of colours, then its axis
/// labelled by `axis` (after the strip, which would cover the labels'
/// last digits).
fn draw_strip<DB: DrawingBackend, Y>(
    area: &DrawingArea<DB, plotters::coord::Shift>,
    label: &str,
    axis: &Axis,
    yr: Y,
    strip: Vec<Rectangle<(f64, f64)>>,
) -> Result<(), String>
where
    Y: AsRangedCoord<Value = f64>,
    Y::CoordDescType: ValueFormatter<f64>,
{
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    let mut chart = ChartBuilder::on(area)
        .margin_top(18 + 30)
        .margin_bottom(18 + 55)
        .margin_right(40)
        .y_label_area_size(80 + colorbar_width(axis) - COLORBAR_WIDTH)
        .build_cartesian_2d(0.0..1.0, yr)
        .map_err(e)?;
    chart.draw_series(strip).map_err(e)?;
    chart
        .configure_mesh()
        .disable_x_mesh()
        .disable_y_mesh()
        .disable_x_axis()
        .y_desc(label)
        // A space after the value: without it the last digit was cut where
        // the label area meets the strip.
        .y_label_formatter(&|v| format!("{} ", axis.label(*v)))
        .label_style((FONT, 16))
        .axis_desc_style((FONT, 19))
        .draw()
        .map_err(e)?;
    Ok(())
}

/// The pixel path `pixels` with both ends of every right-to-left
/// horizontal step doubled. plotters' bitmap backend fills such a step
/// without its two end pixels (a one-pixel step not at all), and draws a
/// zero-length step as its pixel: the slips of stiff orbits, long leftward
/// runs of short flat steps, were drawn dotted.
fn with_step_ends(pixels: &[(i32, i32)]) -> Vec<(i32, i32)> {
    let leftward = |a: (i32, i32), b: (i32, i32)| a.1 == b.1 && b.0 < a.0;
    let mut out = Vec::with_capacity(pixels.len());
    for (i, &p) in pixels.iter().enumerate() {
        out.push(p);
        let before = i > 0 && leftward(pixels[i - 1], p);
        let after = pixels.get(i + 1).is_some_and(|&q| leftward(p, q));
        if before || after {
            out.push(p);
        }
    }
    out
}

/// A solid line two pixels wide through `points`, drawn as one-pixel lines
/// offset by a pixel right and down: plotters draws a wide line as a polygon
/// that degenerates on (nearly) vertical pixel steps, such as the slips of a
/// stick-slip time series (spikes went missing, stray lines left the frame),
/// while its one-pixel lines are exact but for the ends of leftward
/// horizontal steps ([`with_step_ends`]).
fn thick_line<DB: DrawingBackend, X, Y>(
    chart: &Chart<'_, DB, X, Y>,
    points: &[(f64, f64)],
    color: RGBColor,
) -> Result<(), String>
where
    X: AsRangedCoord<Value = f64>,
    Y: AsRangedCoord<Value = f64>,
{
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    let plot = chart.plotting_area();
    let (bx, by) = plot.get_base_pixel();
    let pixels: Vec<(i32, i32)> = points
        .iter()
        .map(|p| {
            let (x, y) = plot.map_coordinate(p);
            (x - bx, y - by)
        })
        .collect();
    let pixels = with_step_ends(&pixels);
    let area = plot.strip_coord_spec();
    for (dx, dy) in [(0, 0), (1, 0), (0, 1)] {
        let shifted: Vec<(i32, i32)> = pixels.iter().map(|&(x, y)| (x + dx, y + dy)).collect();
        area.draw(&PathElement::new(shifted, color.stroke_width(1)))
            .map_err(e)?;
    }
    Ok(())
}

fn draw<DB: DrawingBackend, X, Y>(
    root: DrawingArea<DB, plotters::coord::Shift>,
    plan: &Plan,
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
    let fig = &plan.figure;
    let mut chart = frame(
        &root,
        (&fig.title, &fig.x_label, &fig.y_label),
        (&plan.x, &plan.y),
        xr,
        yr,
    )?;
    let mut any_label = false;
    for s in &fig.series {
        let c = s.color;
        let drawn = if s.markers {
            chart
                .draw_series(s.points.iter().map(|&p| {
                    EmptyElement::at(p)
                        + Circle::new((0, 0), 6, c.filled())
                        + Circle::new((0, 0), 6, BLACK.stroke_width(1))
                }))
                .map_err(e)?
        } else if s.dashed {
            chart
                .draw_series(DashedLineSeries::new(
                    s.points.clone(),
                    8,
                    5,
                    c.stroke_width(2),
                ))
                .map_err(e)?
        } else {
            thick_line::<DB, X, Y>(&chart, &s.points, c)?;
            // Nothing more to draw: the series only carries the legend entry.
            chart
                .draw_series(std::iter::empty::<Circle<(f64, f64), i32>>())
                .map_err(e)?
        };
        if let Some(label) = &s.label {
            any_label = true;
            let (path, radius) = if s.markers {
                (vec![], 5)
            } else {
                (vec![(0, 0), (22, 0)], 0)
            };
            drawn.label(label).legend(move |(x, y)| {
                EmptyElement::at((x, y))
                    + PathElement::new(path.clone(), c.stroke_width(2))
                    + Circle::new((11, 0), radius, c.filled())
            });
        }
    }
    if any_label {
        chart
            .configure_series_labels()
            .position(plan.corner.clone())
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

    /// The colour bar's label area holds its longest label at
    /// [`BAR_CHAR_PIXELS`] a character, for a branch over 1e-6 relative
    /// (labels such as `3.999994e2`) as for an ordinary one.
    #[test]
    fn the_colour_bar_holds_its_labels() {
        for (lo, hi) in [(2.0e3, 1.8e4), (399.9994, 400.0), (1e-3, 2e-3)] {
            let axis = Axis::new(lo, hi, false);
            let longest = axis
                .labels()
                .iter()
                .map(|l| l.chars().count())
                .max()
                .unwrap();
            let label_area = 80 + colorbar_width(&axis) - COLORBAR_WIDTH;
            assert!(
                label_area >= BAR_CHAR_PIXELS * longest as u32,
                "{lo}..{hi}: {longest} characters in {label_area} px"
            );
        }
    }

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
        assert!(y1 / y0 > 1.5 && y0 < 3.0 && y1 > 3.0, "{y0} {y1}");
    }

    /// A curve through the upper right leaves the legend elsewhere.
    #[test]
    fn legend_goes_to_the_emptiest_corner() {
        let mut fig = figure((0..100).map(|i| (i as f64, i as f64)).collect(), false);
        fig.series[0].label = Some("a line".into());
        assert!(matches!(
            layout(&fig, plot_pixels(1000)).legend.0,
            SeriesLabelPosition::UpperLeft
        ));
    }

    /// A spike train of a million samples, one sample wide each: the
    /// decimated line keeps every tip and the overall extremes, in order, with
    /// at most four points per column.
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

    /// A leftward run of flat steps one or two pixels long (the slip of a
    /// stiff orbit) is drawn solid, both of its rows: plotters' bitmap
    /// backend left out the ends of every right-to-left horizontal step,
    /// and the line's lower row came out dotted.
    #[test]
    fn leftward_flat_steps_are_drawn_solid() {
        let (w, h) = (300u32, 100u32);
        let mut buffer = vec![255u8; (w * h * 3) as usize];
        let pixels: Vec<(i32, i32)> = {
            let root = BitMapBackend::with_buffer(&mut buffer, (w, h)).into_drawing_area();
            let chart = ChartBuilder::on(&root)
                .build_cartesian_2d(0.0..300.0, 0.0..100.0)
                .unwrap();
            let points: Vec<(f64, f64)> =
                (0..180).map(|i| (280.0 - 1.5 * i as f64, 50.0)).collect();
            thick_line::<_, std::ops::Range<f64>, std::ops::Range<f64>>(&chart, &points, BLACK)
                .unwrap();
            root.present().unwrap();
            points
                .iter()
                .map(|p| chart.plotting_area().map_coordinate(p))
                .collect()
        };
        let y = pixels[0].1;
        assert!(pixels.iter().all(|p| p.1 == y));
        let (left, right) = (pixels.last().unwrap().0, pixels[0].0);
        let painted = |x: i32, y: i32| buffer[((y as u32 * w + x as u32) * 3) as usize] < 128;
        for x in left..=right {
            assert!(painted(x, y) && painted(x, y + 1), "gap at x = {x}");
        }
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
