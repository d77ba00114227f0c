//! Figures: PNG and SVG via plotters, with a bundled font (DejaVu Sans) so
//! text renders on a machine without fontconfig.

pub mod axes;
pub mod colormap;
pub mod cycles;
pub mod diagram;
pub mod fit;
pub mod lines;
pub mod simulation;
pub mod stability;
pub mod ticks;

pub use ticks::Axis;

use image::codecs::png::{CompressionType, FilterType, PngEncoder};
use image::{ColorType, ImageEncoder};
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
/// Each is drawn in memory and written in full or not at all
/// ([`crate::cli::files::write_whole`]): a failed write (a full disk) never
/// leaves a truncated figure under its name.
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
    let (width, height) = size;
    let mut rgb = vec![0u8; width as usize * height as usize * 3];
    png(BitMapBackend::with_buffer(&mut rgb, size).into_drawing_area())
        .map_err(|e| err(&png_path, e))?;
    let mut encoded = Vec::new();
    PngEncoder::new_with_quality(&mut encoded, CompressionType::Fast, FilterType::Paeth)
        .write_image(&rgb, width, height, ColorType::Rgb8)
        .map_err(|e| err(&png_path, e.to_string()))?;
    crate::cli::files::write_whole(&png_path, encoded)
        .map_err(|e| err(&png_path, e.to_string()))?;
    let mut text = String::new();
    svg(SVGBackend::with_string(&mut text, size).into_drawing_area())
        .map_err(|e| err(&svg_path, e))?;
    crate::cli::files::write_whole(&svg_path, text).map_err(|e| err(&svg_path, e.to_string()))?;
    Ok(vec![png_path, svg_path])
}

/// The chart type [`frame`] returns for the ranges `X`, `Y`.
pub type Chart<'a, DB, X, Y> = ChartContext<
    'a,
    DB,
    Cartesian2d<<X as AsRangedCoord>::CoordDescType, <Y as AsRangedCoord>::CoordDescType>,
>;

/// A chart on `root` with the common frame of every figure: title, margins,
/// labelled axes ([`Axis::label`]), light grid.
pub fn frame<'a, DB, X, Y>(
    root: &'a DrawingArea<DB, Shift>,
    (title, x_label, y_label): (&str, &str, &str),
    (x_axis, y_axis): (&Axis, &Axis),
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
        .x_desc(x_axis.title(x_label))
        .y_desc(y_axis.title(y_label))
        .x_label_formatter(&|v| x_axis.label(*v))
        .y_label_formatter(&|v| y_axis.label(*v))
        .label_style((FONT, 16))
        .axis_desc_style((FONT, 19))
        .light_line_style(RGBColor(235, 235, 235))
        .draw()
        .map_err(e)?;
    Ok(chart)
}

/// An error writing a figure (the path and what went wrong).
#[derive(Debug, thiserror::Error)]
#[error("cannot draw {path}: {reason}")]
pub struct PlotError {
    pub path: String,
    pub reason: String,
}
