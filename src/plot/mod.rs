//! Figures: PNG and SVG via plotters, with a bundled font (DejaVu Sans) so
//! text renders on a machine without fontconfig.

pub mod lines;
pub mod stability;

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

/// A chart on `root` with the common frame of every figure: title, margins,
/// labelled axes with [`tick_label`] ticks, light grid.
pub fn frame<'a, DB, X, Y>(
    root: &'a DrawingArea<DB, Shift>,
    (title, x_label, y_label): (&str, &str, &str),
    (log_x, log_y): (bool, bool),
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
    let mut chart = ChartBuilder::on(root)
        .caption(title, (FONT, 23))
        .margin(18)
        .x_label_area_size(55)
        .y_label_area_size(85)
        .build_cartesian_2d(xr, yr)
        .map_err(e)?;
    chart
        .configure_mesh()
        .x_desc(x_label)
        .y_desc(y_label)
        .x_label_formatter(&|v| axis_label(*v, log_x))
        .y_label_formatter(&|v| axis_label(*v, log_y))
        .label_style((FONT, 16))
        .axis_desc_style((FONT, 19))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(e)?;
    Ok(chart)
}

/// Tick label on a linear or logarithmic axis: on a log axis only the ticks
/// `1, 2, 5 x 10^k` are labelled (a log axis over less than two decades gets
/// ticks at every integer multiple, whose labels would overlap).
fn axis_label(v: f64, log: bool) -> String {
    if !log || v <= 0.0 {
        return tick_label(v);
    }
    let mantissa = v / 10f64.powf(v.log10().floor());
    let m = mantissa.round();
    if (mantissa - m).abs() < 1e-6 && [1.0, 2.0, 5.0, 10.0].contains(&m) {
        tick_label(v)
    } else {
        String::new()
    }
}

/// Tick label: `0`, plain digits within `[1e-2, 1e4)`, else `a.b e k`.
pub fn tick_label(v: f64) -> String {
    let a = v.abs();
    if a < 1e-300 {
        "0".to_string()
    } else if (1e-2..1e4).contains(&a) {
        let s = format!("{v:.3}");
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        let e = a.log10().floor() as i32;
        let m = v / 10f64.powi(e);
        if (m - m.round()).abs() < 1e-9 {
            format!("{}e{e}", m.round())
        } else {
            format!("{m:.1}e{e}")
        }
    }
}

/// An error writing a figure (the path and what went wrong).
#[cfg(test)]
mod tests {
    use super::tick_label;

    #[test]
    fn tick_labels_are_short_and_finite() {
        assert_eq!(tick_label(0.0), "0");
        assert_eq!(tick_label(2.5), "2.5");
        assert_eq!(tick_label(1e5), "1e5");
        assert_eq!(tick_label(-3e-4), "-3e-4");
        assert_eq!(tick_label(2.5e-5), "2.5e-5");
    }
}

#[derive(Debug, thiserror::Error)]
#[error("cannot draw {path}: {reason}")]
pub struct PlotError {
    pub path: String,
    pub reason: String,
}
