//! Axis ticks: where the labelled ticks and the grid lines of an axis go,
//! and how the labels read. One axis has one label format: plain decimals
//! when every label fits in [`PLAIN_CHARS`] characters, else every label in
//! mantissa-exponent form where that is no longer (`9e-3` never stands next
//! to `0.01`; `700.08` is not written `7.0008e2`).

use plotters::coord::combinators::{BindKeyPoints, IntoLogRange, LogCoord, WithKeyPoints};
use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint, Ranged};
use plotters::coord::types::RangedCoordf64;
use std::ops::Range;

/// Longest plain label (sign and a leading `0` before the point not
/// counted: `0.0015`, `20000`) an axis writes in plain decimals.
pub const PLAIN_CHARS: usize = 5;

/// An axis of a figure: its range, where its ticks go and how they read.
#[derive(Clone, Debug)]
pub struct Axis {
    /// The drawn range, increasing.
    pub range: (f64, f64),
    /// Logarithmic.
    pub log: bool,
    /// The labelled ticks, increasing, within the range.
    pub ticks: Vec<f64>,
    /// The values of the light grid lines.
    pub grid: Vec<f64>,
    /// Whether every label is in mantissa-exponent form.
    exponent: bool,
    /// Subtracted from every labelled value ([`Axis::title`] says so):
    /// nonzero where the range is so narrow against its values that the
    /// ticks would read alike ([`label_offset`]).
    offset: (f64, usize),
}

impl Axis {
    /// The axis over `lo .. hi` (either order; positive when `log`), with
    /// the ticks of [`log_ticks`] or [`linear_ticks`] and one label format
    /// for all of them.
    pub fn new(lo: f64, hi: f64, log: bool) -> Axis {
        let range = (lo.min(hi), lo.max(hi));
        let (ticks, grid) = if log {
            log_ticks(range.0, range.1)
        } else {
            linear_ticks(range.0, range.1)
        };
        let offset = label_offset(&ticks, log);
        let shifted: Vec<f64> = ticks.iter().map(|&v| less_offset(v, offset)).collect();
        let too_long = shifted.iter().any(|&v| {
            let plain = plain_label(v);
            let digits = plain.trim_start_matches('-');
            digits
                .strip_prefix("0.")
                .map_or(digits.len(), |d| d.len() + 1)
                > PLAIN_CHARS
        });
        // Only where it does not lengthen the labels: `700.08` stays, not
        // `7.0008e2`.
        let longest =
            |label: fn(f64) -> String| shifted.iter().map(|&v| label(v).len()).max().unwrap_or(0);
        let exponent = too_long && longest(exponent_label) <= longest(plain_label);
        Axis {
            range,
            log,
            ticks,
            grid,
            exponent,
            offset,
        }
    }

    /// The label of the tick at `v`, in the axis's format (less the
    /// axis's offset, if any).
    pub fn label(&self, v: f64) -> String {
        let v = less_offset(v, self.offset);
        if self.exponent {
            exponent_label(v)
        } else {
            plain_label(v)
        }
    }

    /// The axis title `label`, with the offset its tick labels leave out
    /// (`spring force [N] − 21.895081`: the ticks read the force less it).
    pub fn title(&self, label: &str) -> String {
        match self.offset {
            (0.0, _) => label.to_string(),
            (offset, d) => format!("{label} − {offset:.d$}"),
        }
    }

    /// The labels of the ticks, in order.
    pub fn labels(&self) -> Vec<String> {
        self.ticks.iter().map(|&v| self.label(v)).collect()
    }

    /// The axis as a logarithmic plotters coordinate with its ticks.
    pub fn log_coord(&self) -> WithKeyPoints<LogCoord<f64>> {
        (self.range.0..self.range.1)
            .log_scale()
            .with_key_points(self.ticks.clone())
            .with_light_points(self.grid.clone())
    }

    /// The axis as a linear plotters coordinate with its ticks.
    pub fn linear_coord(&self) -> LinearCoord {
        LinearCoord {
            inner: (self.range.0..self.range.1).into(),
            ticks: self.ticks.clone(),
            grid: self.grid.clone(),
        }
    }
}

/// A linear plotters coordinate with given ticks and grid lines (plotters'
/// own `WithKeyPoints` of a linear range cannot be labelled by a formatter).
pub struct LinearCoord {
    inner: RangedCoordf64,
    ticks: Vec<f64>,
    grid: Vec<f64>,
}

impl Ranged for LinearCoord {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        self.inner.map(value, limit)
    }

    fn key_points<Hint: KeyPointHint>(&self, hint: Hint) -> Vec<f64> {
        if hint.weight().allow_light_points() {
            self.grid.clone()
        } else {
            self.ticks.clone()
        }
    }

    fn range(&self) -> Range<f64> {
        self.inner.range()
    }
}

/// The value a linear axis subtracts from its tick labels: zero where the
/// labels of its ticks read differently in either format; else, where the
/// range is too narrow against its values for that (a force of 21.9 N
/// varying by 1e-8 N: every tick read `2.189508e1`), the ticks' first value
/// rounded down to a multiple of `10^k`, `10^k` between 10 and 100 tick
/// steps: the labels are then the small round differences from it.
fn label_offset(ticks: &[f64], log: bool) -> (f64, usize) {
    if log || ticks.len() < 2 {
        return (0.0, 0);
    }
    let distinct = |label: fn(f64) -> String| {
        let labels: Vec<String> = ticks.iter().map(|&v| label(v)).collect();
        labels.windows(2).all(|w| w[0] != w[1])
    };
    if distinct(plain_label) || distinct(exponent_label) {
        return (0.0, 0);
    }
    let k = (ticks[1] - ticks[0]).log10().floor() as i32 + 2;
    let unit = 10f64.powi(k);
    ((ticks[0] / unit).floor() * unit, (-k).max(0) as usize)
}

/// `v` less the axis offset `(offset, its decimals)`, rounded to six
/// decimals below the offset's last: the subtraction's rounding would
/// otherwise show in the label (`2.300000e-7`, not `2.3e-7`).
fn less_offset(v: f64, (offset, d): (f64, usize)) -> f64 {
    if offset == 0.0 {
        return v;
    }
    let q = 10f64.powi(-(d as i32) - 6);
    ((v - offset) / q).round() * q
}

/// Fewest decimals (up to 12) that write `v` to 1e-9 of itself.
fn decimals(v: f64) -> usize {
    (0..12)
        .find(|&d| {
            let s = format!("{v:.d$}");
            s.parse::<f64>()
                .is_ok_and(|w| (w - v).abs() <= 1e-9 * v.abs())
        })
        .unwrap_or(12)
}

/// `v` in plain decimals, as few as write it (`0.005`, `25000`, `0`).
fn plain_label(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let d = decimals(v);
    format!("{v:.d$}")
}

/// `v` as mantissa and exponent, as few mantissa digits as write it
/// (`2.35e5`, `9e-3`); `0` as `0`.
fn exponent_label(v: f64) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let mut e = v.abs().log10().floor() as i32;
    let mut m = v / 10f64.powi(e);
    // 9.9999999e2 is 1e3.
    if (m.abs() - 10.0).abs() < 1e-9 {
        e += 1;
        m /= 10.0;
    }
    let d = decimals(m).min(6);
    format!("{m:.d$}e{e}")
}

/// Tick values of a linear axis over `lo .. hi`: labelled ones at
/// multiples of a round step ([`round_step`], five to ten of them), grid
/// lines at a fifth of it.
pub fn linear_ticks(lo: f64, hi: f64) -> (Vec<f64>, Vec<f64>) {
    if !(lo.is_finite() && hi.is_finite() && hi > lo) {
        return (Vec::new(), Vec::new());
    }
    let step = round_step((hi - lo) / 10.0);
    let multiples = |step: f64| -> Vec<f64> {
        let (first, last) = ((lo / step).ceil() as i64, (hi / step).floor() as i64);
        (first..=last).map(|i| i as f64 * step).collect()
    };
    (multiples(step), multiples(step / 5.0))
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

#[cfg(test)]
mod tests {
    use super::{log_ticks, Axis};

    /// A range too narrow against its values for any label format (a
    /// 21.9 N force varying by 1e-8 N: every tick read `2.189508e1`): the
    /// labels differ, read the ticks less the offset the title names, and
    /// an ordinary range keeps its labels and title as they were.
    #[test]
    fn the_ticks_of_a_narrow_range_read_apart_from_an_offset_in_the_title() {
        for (lo, hi) in [
            (21.89507919, 21.89507924),
            (-3.000000001, -3.0000000007),
            (1e6, 1e6 + 1e-4),
            (0.5, 0.5 + 1e-13),
        ] {
            let axis = Axis::new(lo, hi, false);
            let labels = axis.labels();
            assert!(labels.len() >= 3, "{lo} .. {hi}: {labels:?}");
            assert!(labels.windows(2).all(|w| w[0] != w[1]), "{labels:?}");
            let title = axis.title("F [N]");
            let offset: f64 = title.rsplit(" − ").next().unwrap().parse().unwrap();
            let step = axis.ticks[1] - axis.ticks[0];
            for (&v, label) in axis.ticks.iter().zip(&labels) {
                let read = offset + label.parse::<f64>().unwrap();
                assert!((read - v).abs() <= 1e-3 * step, "{title}: {label} at {v}");
            }
        }
        let axis = Axis::new(0.0, 25.0, false);
        assert_eq!(axis.title("F [N]"), "F [N]");
        assert_eq!(axis.labels()[1], "2.5");
    }

    /// Whether every label of `labels` (but a `0`) is in plain decimals, or
    /// every one in mantissa-exponent form.
    fn one_format(labels: &[String]) -> bool {
        let with_e = labels.iter().filter(|l| *l != "0" && l.contains('e'));
        let n = labels.iter().filter(|l| *l != "0").count();
        let e = with_e.count();
        e == 0 || e == n
    }

    fn labels_of(lo: f64, hi: f64, log: bool) -> Vec<String> {
        Axis::new(lo, hi, log).labels()
    }

    /// Ticks of a short range differ (seen: "0.462" five times, "2.5e4"
    /// three times); a tick at rounding distance from 0 reads 0.
    #[test]
    fn ticks_of_a_short_range_are_distinct() {
        for (lo, hi) in [
            (0.4620, 0.4630),
            (2.50e4, 2.51e4),
            (2.7e4, 2.716e4),
            (1e-6, 1.01e-6),
            (-0.05, 0.3),
        ] {
            let labels = labels_of(lo, hi, false);
            let mut unique = labels.clone();
            unique.dedup();
            assert!(labels.len() >= 4, "{lo} {hi}: {labels:?}");
            assert_eq!(unique.len(), labels.len(), "{labels:?}");
            assert!(one_format(&labels), "{labels:?}");
        }
        assert!(labels_of(-0.05, 0.3, false).contains(&"0".to_string()));
        assert_eq!(labels_of(0.0, 0.03, false)[..3], ["0", "0.005", "0.01"]);
    }

    /// One format along an axis: plain where every label is short, else
    /// all in mantissa-exponent form (seen: `9e-3` beside `0.01`, `5000`
    /// beside `1e4`).
    #[test]
    fn an_axis_writes_its_labels_in_one_format() {
        assert_eq!(
            labels_of(7.8e-3, 1.6e-2, true),
            ["0.008", "0.009", "0.01", "0.015"]
        );
        assert_eq!(
            labels_of(30.0, 3e5, true),
            ["5e1", "1e2", "2e2", "5e2", "1e3", "2e3", "5e3", "1e4", "2e4", "5e4", "1e5", "2e5"]
        );
        assert_eq!(labels_of(0.0, 2e4, false)[1..3], ["2000", "4000"]);
        assert_eq!(labels_of(0.0, 2.2e5, false)[1..3], ["2.5e4", "5e4"]);
        assert_eq!(labels_of(1.7e5, 4e5, true), ["2e5", "2.5e5", "3e5", "4e5"]);
        // Plain where the exponent form would be longer (seen: 7.0008e2).
        assert_eq!(labels_of(700.05, 700.12, false)[..2], ["700.05", "700.06"]);
        for (lo, hi, log) in [
            (1e-3, 1e9, true),
            (1e-3, 1e-1, true),
            (6e6, 3e7, true),
            (0.1, 100.0, true),
            (-1e-4, 3e-4, false),
            (0.0, 265.0, false),
        ] {
            let labels = labels_of(lo, hi, log);
            assert!(one_format(&labels), "{lo} {hi}: {labels:?}");
        }
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
            let mut labels = labels_of(lo, hi, true);
            labels.dedup();
            assert_eq!(labels.len(), bold.len(), "{labels:?}");
        }
    }
}
