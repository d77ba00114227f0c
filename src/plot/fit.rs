//! Figures of `fit`: per measured quantity of each dataset, the data with
//! the fitted model (and the scene's model it started from) against the
//! driving velocity (against time for the time series), and the residuals.

use super::lines::{render, LineFigure, Series};
use super::PlotError;
use crate::adhesive::fit::AdhesiveFit;
use crate::file_names::with_suffix;
use crate::fit::data::Dataset;
use crate::jobs::fit::Fit;
use plotters::style::RGBColor;
use std::path::{Path, PathBuf};

/// What the figures of a fit draw: its datasets, and the model of each
/// measured quantity with the fitted values and with the scene's.
pub trait Drawn {
    /// The scene's name.
    fn title(&self) -> &str;
    fn data(&self) -> &[Dataset];
    /// The model of the quantity `column` at `v` µm/s, with the fitted
    /// values (`fitted`) or the scene's.
    fn model(&self, fitted: bool, column: &str, v: f64) -> f64;
    /// The model of the time series `i` at its rows' times (`None`: not a
    /// time series, or it does not integrate).
    fn series_model(&self, _i: usize, _fitted: bool) -> Option<Vec<f64>> {
        None
    }
}

impl Drawn for Fit {
    fn title(&self) -> &str {
        &self.scene
    }
    fn data(&self) -> &[Dataset] {
        &self.outcome.data
    }
    fn model(&self, fitted: bool, column: &str, v: f64) -> f64 {
        self.predict(self.values_of(fitted), column, v)
    }
    fn series_model(&self, i: usize, fitted: bool) -> Option<Vec<f64>> {
        Fit::series_model(self, i, self.values_of(fitted))
    }
}

impl Drawn for AdhesiveFit {
    fn title(&self) -> &str {
        &self.scene
    }
    fn data(&self) -> &[Dataset] {
        &self.outcome.data
    }
    fn model(&self, fitted: bool, column: &str, v: f64) -> f64 {
        let values = if fitted {
            &self.outcome.values
        } else {
            &self.outcome.start
        };
        values.predict(self.mass_kg, column, v)
    }
}

/// The figures of a rate-and-state fit: the stability band, and
/// [`data_figures`].
pub fn figures(fit: &Fit, stem: &Path) -> Result<Vec<PathBuf>, PlotError> {
    let mut files = if fit.band.len() > 1 {
        band_figure(fit, stem)?
    } else {
        Vec::new()
    };
    files.extend(data_figures(fit, stem)?);
    Ok(files)
}

/// Writes `<stem>-fit-<kind>-<quantity>` (data and models) and
/// `...-residuals` for every measured quantity of the fit's data.
pub fn data_figures<F: Drawn>(fit: &F, stem: &Path) -> Result<Vec<PathBuf>, PlotError> {
    let title = fit.title();
    let model = |fitted: bool, column: &str, v: f64| fit.model(fitted, column, v);
    let (fitted, start) = (true, false);
    let mut files = Vec::new();
    let data = fit.data();
    for (i, d) in data.iter().enumerate() {
        // The second dataset of a kind is `<kind>2`, and so on.
        let nth = data[..i].iter().filter(|e| e.kind == d.kind).count();
        let kind = match nth {
            0 => d.kind.name().to_string(),
            n => format!("{}{}", d.kind.name(), n + 1),
        };
        // The abscissa: the driving velocity, or the time of a time series
        // (a relaxation's on a log scale, from its first time after 0).
        let series = d.kind.is_series();
        let log_x = !series || d.kind == crate::fit::data::Kind::Relaxation;
        let x: &[f64] = if series { &d.t_s } else { &d.v_um_s };
        let shown = |t: f64| !log_x || t > 0.0;
        let (lo, hi) = x
            .iter()
            .filter(|t| shown(**t))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                (a.min(*v), b.max(*v))
            });
        let grid: Vec<f64> = (0..=200)
            .map(|i| lo / 1.5 * (2.25 * hi / lo).powf(i as f64 / 200.0))
            .collect();
        let x_label = if series {
            "time t [s]"
        } else {
            "driving velocity V [µm/s]"
        };
        // The residuals' zero line over the data's abscissa.
        let (left, right) = if log_x {
            (lo / 1.5, hi * 1.5)
        } else {
            (lo, hi)
        };
        let file = d.file.file_name().map_or_else(
            || d.file.display().to_string(),
            |f| f.to_string_lossy().into(),
        );
        for q in &d.measured {
            // A time series' model at its rows' times (nothing where it
            // does not integrate), the others on a grid of velocities.
            let curve = |p: bool| -> Vec<(f64, f64)> {
                if series {
                    let values = fit.series_model(i, p).unwrap_or_default();
                    x.iter()
                        .copied()
                        .zip(values)
                        .filter(|(t, _)| shown(*t))
                        .collect()
                } else {
                    // A critical stiffness only where there is an onset
                    // (steady friction falling with V).
                    let stiffness = q.column.starts_with('K');
                    grid.iter()
                        .map(|&v| (v, model(p, q.column, v)))
                        .filter(|(_, m)| m.is_finite() && !(stiffness && *m <= 0.0))
                        .collect()
                }
            };
            let points: Vec<(f64, f64)> = x
                .iter()
                .copied()
                .zip(q.values.iter().copied())
                .filter(|(t, _)| shown(*t))
                .collect();
            let fitted_curve = curve(fitted);
            let points_marked = points.len() <= 300;
            let figure = LineFigure {
                title: format!("{title}: {} data ({file}) and the fit", d.kind.name()),
                x_label: x_label.into(),
                y_label: label(q.column, series).into(),
                log_x,
                // Onset frequencies grow with V over decades.
                log_y: q.column == "frequency_hz",
                series: {
                    let data = Series {
                        label: Some("data".into()),
                        points: points.clone(),
                        color: if series && !points_marked {
                            RGBColor(240, 160, 160)
                        } else {
                            RGBColor(214, 39, 40)
                        },
                        dashed: false,
                        markers: !series || points_marked,
                    };
                    let models = [
                        Series {
                            label: Some("scene before the fit".into()),
                            points: curve(start),
                            color: RGBColor(150, 150, 150),
                            dashed: true,
                            markers: false,
                        },
                        Series {
                            label: Some("fitted".into()),
                            points: fitted_curve.clone(),
                            color: RGBColor(31, 119, 180),
                            dashed: false,
                            markers: false,
                        },
                    ];
                    // Each marked row's error bar, y ± sigma, where the file
                    // gives sigma.
                    let bars = error_bars(x, q, points_marked, q.column == "frequency_hz", shown);
                    // A time series' data under the models (long as a line,
                    // short as markers: either would hide them on top).
                    if series {
                        std::iter::once(data).chain(bars).chain(models).collect()
                    } else {
                        models
                            .into_iter()
                            .chain(bars)
                            .chain(std::iter::once(data))
                            .collect()
                    }
                },
            };
            let base = with_suffix(stem, &format!("-fit-{kind}-{}", q.column));
            files.extend(render(&figure, &base)?);
            let residuals: Vec<(f64, f64)> = if series {
                points
                    .iter()
                    .zip(&fitted_curve)
                    .map(|(&(t, y), &(_, m))| (t, y - m))
                    .collect()
            } else {
                points
                    .iter()
                    .map(|&(v, y)| (v, y - model(fitted, q.column, v)))
                    .collect()
            };
            let figure = LineFigure {
                title: format!("{title}: residuals of the {} data ({file})", d.kind.name()),
                x_label: x_label.into(),
                y_label: format!("data - fit: {}", label(q.column, series)),
                log_x,
                log_y: false,
                series: vec![
                    Series {
                        label: None,
                        points: vec![(left, 0.0), (right, 0.0)],
                        color: RGBColor(150, 150, 150),
                        dashed: true,
                        markers: false,
                    },
                    Series {
                        label: Some("residual".into()),
                        points: residuals,
                        color: RGBColor(214, 39, 40),
                        dashed: false,
                        markers: true,
                    },
                ],
            };
            files.extend(render(&figure, &with_suffix(&base, "-residuals"))?);
        }
    }
    Ok(files)
}

/// The error bars `y ± sigma` of the rows of `q` at the abscissae `x` that
/// are `shown`, one vertical segment each, where the file gives `sigma` and
/// the rows are drawn as markers (`marked`); on a log axis (`log_y`) a bar
/// reaching 0 or below ends at a tenth of the value.
fn error_bars(
    x: &[f64],
    q: &crate::fit::data::Measured,
    marked: bool,
    log_y: bool,
    shown: impl Fn(f64) -> bool,
) -> Vec<Series> {
    let Some(sigma) = q.sigma.as_ref().filter(|_| marked) else {
        return Vec::new();
    };
    x.iter()
        .zip(&q.values)
        .zip(sigma)
        .filter(|((t, _), _)| shown(**t))
        .map(|((&t, &y), &e)| Series {
            label: None,
            points: vec![
                (
                    t,
                    if log_y && y - e <= 0.0 {
                        0.1 * y
                    } else {
                        y - e
                    },
                ),
                (t, y + e),
            ],
            color: RGBColor(214, 39, 40),
            dashed: false,
            markers: false,
        })
        .collect()
}

/// `<stem>-fit-stability-band`: the fitted scene's critical stiffness over
/// its velocity range with the 95 % band (delta method, and the quantiles
/// of the sampled parameter sets), and the onset data if any.
fn band_figure(fit: &Fit, stem: &Path) -> Result<Vec<PathBuf>, PlotError> {
    let line = |f: fn(&crate::jobs::fit::BandPoint) -> f64| -> Vec<(f64, f64)> {
        fit.band.iter().map(|b| (b.v_um_s, f(b))).collect()
    };
    let blue = RGBColor(31, 119, 180);
    let grey = RGBColor(120, 120, 120);
    let mut series = vec![
        Series {
            label: Some("fitted (K/W)_c".into()),
            points: line(|b| b.k_over_w),
            color: blue,
            dashed: false,
            markers: false,
        },
        Series {
            label: Some("95 % band (delta method)".into()),
            points: line(|b| b.lo_95),
            color: blue,
            dashed: true,
            markers: false,
        },
        Series {
            label: None,
            points: line(|b| b.hi_95),
            color: blue,
            dashed: true,
            markers: false,
        },
        Series {
            label: Some("95 % of sampled parameter sets".into()),
            points: line(|b| b.sampled_lo_95),
            color: grey,
            dashed: true,
            markers: false,
        },
        Series {
            label: None,
            points: line(|b| b.sampled_hi_95),
            color: grey,
            dashed: true,
            markers: false,
        },
    ];
    for d in fit
        .outcome
        .data
        .iter()
        .filter(|d| d.kind == crate::fit::data::Kind::Onset)
    {
        series.extend(error_bars(&d.v_um_s, &d.measured[0], true, false, |_| true));
        series.push(Series {
            label: Some("onset data".into()),
            points: d
                .v_um_s
                .iter()
                .copied()
                .zip(d.measured[0].values.iter().copied())
                .collect(),
            color: RGBColor(214, 39, 40),
            dashed: false,
            markers: true,
        });
    }
    let figure = LineFigure {
        title: format!(
            "{}: stability boundary of the fitted scene (stick-slip below)",
            fit.scene
        ),
        x_label: "driving velocity V [µm/s]".into(),
        y_label: label("K_over_W_per_m", false).into(),
        log_x: true,
        log_y: false,
        series,
    };
    render(&figure, &with_suffix(stem, "-fit-stability-band"))
}

/// The axis label of a measured quantity (of a time series or not).
fn label(column: &str, series: bool) -> &'static str {
    match column {
        "mu" if series => "friction coefficient mu (spring force / load)",
        "mu" => "steady friction coefficient mu_ss",
        "K_over_W_per_m" => "critical stiffness over load (K/W)_c [1/m]",
        "slip_um" => "slip since the drive stopped [µm]",
        "F_N" => "steady friction force F_ss [N]",
        "K_N_per_m" => "critical stiffness K_c [N/m]",
        _ => "onset frequency f_c [Hz]",
    }
}
