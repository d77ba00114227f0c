//! Figures: PNG and SVG via plotters, with a bundled font (DejaVu Sans) so
//! text renders on a machine without fontconfig.

pub mod colormap;
pub mod lines;
pub mod stability;

use plotters::coord::combinators::{BindKeyPoints, IntoLogRange, LogCoord, WithKeyPoints};
use plotters::coord::ranged1d::{AsRangedCoord, ValueFormatter};
use plotters::coord::Shift;
use plotters::prelude::{
    BitMapBackend, Cartesian2d, ChartBuilder, ChartContext, DrawingArea, DrawingAreaErrorKind,
    DrawingBackend, IntoDrawingArea, RGBColor, SVGBackend, WHITE,
};
use std::path::{Path, PathBuf};
use std::sync::Once;

/// The font family registered for every figure.
pub const FONT: &str = "sans-serif";

static REGISTER: Once = Once::new();

/// Registers the bundled font once per process.
pub fn ensure_font() {
    REGISTER.call_once(|| {
        let bytes: &'static [u8] = include_bytes!("../../assets/fonts/DejaVuSans.ttf");
        // The bundled file is a valid TrueType font; a failure here would be a
        // build defect, and plotters then falls back to drawing no text.
        let _ = plotters::style::register_font(FONT, plotters::style::FontStyle::Normal, bytes);
    });
}

/// Writes `<stem>.png` and `<stem>.svg` (appended, so dots in `stem` stay) of the given size; `png` and `svg` draw
/// the same figure (one generic drawing function instantiated per backend).
pub fn render_both(
    stem: &Path,
    size: (u32, u32),
    png: impl FnOnce(DrawingArea<BitMapBackend<'_>, Shift>) -> Result<(), String>,
    svg: impl FnOnce(DrawingArea<SVGBackend<'_>, Shift>) -> Result<(), String>,
) -> Result<Vec<PathBuf>, PlotError> {
    ensure_font();
    let with = |ext: &str| {
        let mut s = stem.as_os_str().to_owned();
        s.push(ext);
        PathBuf::from(s)
    };
    let (png_path, svg_path) = (with(".png"), with(".svg"));
    let err = |p: &Path, reason: String| PlotError {
        path: p.display().to_string(),
        reason,
    };
    png(BitMapBackend::new(&png_path, size).into_drawing_area()).map_err(|e| err(&png_path, e))?;
    svg(SVGBackend::new(&svg_path, size).into_drawing_area()).map_err(|e| err(&svg_path, e))?;
    Ok(vec![png_path, svg_path])
}

/// The chart type [`frame`] returns for the ranges `X`, `Y`.
pub type Chart<'a, DB, X, Y> = ChartContext<
    'a,
    DB,
    Cartesian2d<<X as AsRangedCoord>::CoordDescType, <Y as AsRangedCoord>::CoordDescType>,
>;

/// An axis of a figure, with what its tick labels need to know.
#[derive(Clone, Copy, Debug)]
pub enum Axis {
    /// Linear over a range of length `span`.
    Linear { span: f64 },
    /// Logarithmic over `decades` decades.
    Log { decades: f64 },
}

impl Axis {
    /// The axis over `lo .. hi`, logarithmic when `log`.
    pub fn over(lo: f64, hi: f64, log: bool) -> Axis {
        if log {
            Axis::Log {
                decades: (hi / lo).log10().abs(),
            }
        } else {
            Axis::Linear {
                span: (hi - lo).abs(),
            }
        }
    }

    /// The label of the tick at `v`: on a linear axis with the digits a
    /// tenth of its span needs; on a log axis (ticks of [`log_ticks`]) with
    /// up to three significant digits, trailing zeros dropped.
    pub fn label(self, v: f64) -> String {
        match self {
            Axis::Linear { span } => tick_label_step(v, span / 10.0),
            Axis::Log { decades } if decades > 0.0 && v > 0.0 => {
                tick_label_step(v, 10f64.powf(v.log10().floor() - 2.0))
            }
            Axis::Log { .. } => tick_label(v),
        }
    }
}

/// A chart on `root` with the common frame of every figure: title, margins,
/// labelled axes ([`Axis::label`]), light grid.
pub fn frame<'a, DB, X, Y>(
    root: &'a DrawingArea<DB, Shift>,
    (title, x_label, y_label): (&str, &str, &str),
    (x_axis, y_axis): (Axis, Axis),
    xr: X,
    yr: Y,
) -> Result<Chart<'a, DB, X, Y>, String>
where
    DB: DrawingBackend,
    X: AsRangedCoord<Value = f64>,
    Y: AsRangedCoord<Value = f64>,
    X::CoordDescType: ValueFormatter<f64>,
    Y::CoordDescType: ValueFormatter<f64>,
{
    let e = |x: DrawingAreaErrorKind<DB::ErrorType>| x.to_string();
    root.fill(&WHITE).map_err(e)?;
    // A long title gets a smaller font (down to 14 pixels) instead of
    // running off both edges.
    let chars = title.chars().count() as f64;
    let size = (23.0 * (68.0 / chars).min(1.0)).max(14.0);
    let mut chart = ChartBuilder::on(root)
        .caption(title, (FONT, size))
        .margin(18)
        .x_label_area_size(55)
        .y_label_area_size(85)
        .build_cartesian_2d(xr, yr)
        .map_err(e)?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .x_label_formatter(&|v| x_axis.label(*v))
        .y_label_formatter(&|v| y_axis.label(*v))
        .label_style((FONT, 16))
        .axis_desc_style((FONT, 19))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(e)?;
    Ok(chart)
}

/// Tick values of a logarithmic axis over `lo .. hi` (positive): labelled
/// ones and grid lines. Labelled: the powers of ten (every k-th beyond ten
/// of them) over more than six decades; `1, 2, 5 x 10^k` over more than a
/// decade and a half; every `1 .. 9 x 10^k` over less, with `1.5` and `2.5`
/// within half a decade; and where that
/// leaves fewer than three in the range (a few percent of variation, within
/// one decade), evenly spaced values of a round step. Grid lines at every
/// `1 .. 9 x 10^k` up to six decades. plotters' own key points start at a
/// power of ten and leave an axis within one decade without any.
pub fn log_ticks(lo: f64, hi: f64) -> (Vec<f64>, Vec<f64>) {
    let (lo, hi) = (lo.min(hi), lo.max(hi));
    if !(lo > 0.0 && hi.is_finite()) {
        return (Vec::new(), Vec::new());
    }
    let decades = (hi / lo).log10();
    let multiples = |set: &[f64]| -> Vec<f64> {
        let (k0, k1) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
        (k0..=k1)
            .flat_map(|k| set.iter().map(move |m| m * 10f64.powi(k)))
            .filter(|v| *v >= lo * (1.0 - 1e-12) && *v <= hi * (1.0 + 1e-12))
            .collect()
    };
    let all: Vec<f64> = (1..=9).map(f64::from).collect();
    let light = if decades <= 6.0 {
        multiples(&all)
    } else {
        multiples(&[1.0])
    };
    let bold = if decades > 6.0 {
        let powers = multiples(&[1.0]);
        let every = powers.len().div_ceil(10).max(1);
        powers.into_iter().step_by(every).collect()
    } else if decades > 1.5 {
        multiples(&[1.0, 2.0, 5.0])
    } else if decades > 0.5 {
        multiples(&all)
    } else {
        // Within half a decade the top of a decade (1.5, 2.5) gets labels too:
        // 7.8e-3 .. 1.6e-2 was labelled only up to 1e-2.
        multiples(&[1.0, 1.5, 2.0, 2.5, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0])
    };
    if bold.len() >= 3 {
        return (bold, light);
    }
    let step = round_step((hi - lo) / 4.0);
    let first = (lo / step).ceil() as i64;
    let last = (hi / step).floor() as i64;
    ((first..=last).map(|i| i as f64 * step).collect(), light)
}

/// The round number `1, 2, 2.5 or 5 x 10^k` nearest above `x` (positive).
fn round_step(x: f64) -> f64 {
    let k = x.log10().floor();
    let unit = 10f64.powf(k);
    [1.0, 2.0, 2.5, 5.0, 10.0]
        .into_iter()
        .map(|m| m * unit)
        .find(|s| *s >= x * (1.0 - 1e-12))
        .unwrap_or(10.0 * unit)
}

/// A logarithmic axis over `lo .. hi` with the key points of [`log_ticks`].
pub fn log_axis(lo: f64, hi: f64) -> WithKeyPoints<LogCoord<f64>> {
    let (bold, light) = log_ticks(lo, hi);
    (lo..hi)
        .log_scale()
        .with_key_points(bold)
        .with_light_points(light)
}

/// Tick label: `0`, plain digits within `[1e-2, 1e4)`, else `a.b e k`, with
/// one digit more than the default three decimals would show.
pub fn tick_label(v: f64) -> String {
    tick_label_step(
        v,
        10f64.powi((v.abs().max(1e-300).log10().floor() as i32) - 1),
    )
}

/// Tick label with as many digits as ticks `step` apart need to differ:
/// `0` for a value within `1e-9 step` of zero (no `-1.1e-16`), plain digits
/// below `1e4` (and down to `1e-2`, or further for ticks at least `1e-3`
/// apart), else mantissa and exponent (`2.55e4`), trailing zeros dropped.
pub fn tick_label_step(v: f64, step: f64) -> String {
    let a = v.abs();
    if a < 1e-300 || a <= 1e-9 * step.abs() {
        return "0".to_string();
    }
    let k = step.abs().max(1e-300).log10().floor() as i32;
    let trim = |s: String| {
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    };
    // Plain digits also below 1e-2 when the ticks are at least 1e-3 apart
    // (0.005 beside 0.01 on a linear axis, not 5e-3).
    if a < 1e4 && (a >= 1e-2 || step.abs() >= 1e-3) {
        let d = (1 - k).max(0) as usize;
        trim(format!("{v:.d$}"))
    } else {
        let e = a.log10().floor() as i32;
        let d = (e - k + 1).clamp(0, 15) as usize;
        let m = v / 10f64.powi(e);
        format!("{}e{e}", trim(format!("{m:.d$}")))
    }
}

/// An error writing a figure (the path and what went wrong).
#[cfg(test)]
mod tests {
    use super::{log_ticks, tick_label, tick_label_step, Axis};

    #[test]
    fn tick_labels_are_short_and_finite() {
        assert_eq!(tick_label(0.0), "0");
        assert_eq!(tick_label(2.5), "2.5");
        assert_eq!(tick_label(1e5), "1e5");
        assert_eq!(tick_label(-3e-4), "-3e-4");
        assert_eq!(tick_label(2.5e-5), "2.5e-5");
    }

    /// Ticks of a short range differ (seen: "0.462" five times, "2.5e4"
    /// three times); a tick at rounding distance from 0 reads 0.
    #[test]
    fn ticks_of_a_short_range_are_distinct() {
        for (lo, step, n) in [
            (0.4620, 0.0002, 6),
            (2.50e4, 250.0, 5),
            (2.7e4, 20.0, 8),
            (1e-6, 2e-9, 5),
        ] {
            let labels: Vec<String> = (0..n)
                .map(|i| tick_label_step(lo + i as f64 * step, step))
                .collect();
            let mut unique = labels.clone();
            unique.dedup();
            assert_eq!(unique.len(), n, "{labels:?}");
        }
        assert_eq!(tick_label_step(-1.1e-16, 0.05), "0");
        // One format along a linear axis from 0 to 0.045.
        assert_eq!(tick_label_step(0.005, 0.005), "0.005");
        assert_eq!(tick_label_step(0.045, 0.005), "0.045");
        // A log axis within one decade labels every integer multiple.
        let axis = Axis::over(6e6, 3e7, true);
        assert_eq!(axis.label(8e6), "8e6");
        assert_eq!(axis.label(2.35e5), "2.35e5");
    }

    /// Every log axis has at least three labelled ticks, in range, distinct
    /// once formatted: over twelve decades, two, a factor 1.7, and 3 %.
    #[test]
    fn log_axes_always_have_labelled_ticks() {
        for (lo, hi, expect) in [
            (1e-3, 1e9, vec![1e-3, 1e-1, 1e1, 1e3, 1e5, 1e7, 1e9]),
            (1e-3, 1e-1, vec![1e-3, 2e-3, 5e-3, 1e-2, 2e-2, 5e-2, 1e-1]),
            (1.7e5, 4e5, vec![2e5, 2.5e5, 3e5, 4e5]),
            (7.8e-3, 1.6e-2, vec![8e-3, 9e-3, 1e-2, 1.5e-2]),
            (2.30e5, 2.37e5, vec![2.3e5, 2.32e5, 2.34e5, 2.36e5]),
        ] {
            let (bold, light) = log_ticks(lo, hi);
            assert_eq!(bold.len(), expect.len(), "{lo} {hi}: {bold:?}");
            for (b, e) in bold.iter().zip(&expect) {
                assert!((b / e - 1.0).abs() < 1e-12, "{lo} {hi}: {bold:?}");
            }
            assert!(light.iter().all(|v| *v >= lo * 0.999 && *v <= hi * 1.001));
            let axis = Axis::over(lo, hi, true);
            let mut labels: Vec<String> = bold.iter().map(|v| axis.label(*v)).collect();
            labels.dedup();
            assert_eq!(labels.len(), bold.len(), "{labels:?}");
        }
    }
}

#[derive(Debug, thiserror::Error)]
#[error("cannot draw {path}: {reason}")]
pub struct PlotError {
    pub path: String,
    pub reason: String,
}
