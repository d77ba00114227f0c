//! Every figure kind, on awkward data (a sub-decade log range, a constant
//! series, a spike train of a million samples, a family of 40 cycles): what
//! the plotting layer decides (axis ranges, tick labels, the legend's box)
//! holds every series' extremes, labels every axis distinctly in one format,
//! and keeps the legend off the data. The expectations are computed here from
//! the data, not by the plotting layer's own measures.

use plotters::style::RGBColor;
use std::f64::consts::TAU;
use stickslip::analysis::hopf::Criticality;
use stickslip::plot::lines::{plan, vertical_marker, Colorbar, LineFigure, Plan, Series};
use stickslip::plot::stability::{panels, segments, StabilityFigure};
use stickslip::plot::Axis;

const BLUE: RGBColor = RGBColor(31, 90, 180);

fn line(label: Option<&str>, points: Vec<(f64, f64)>, dashed: bool) -> Series {
    Series {
        label: label.map(str::to_string),
        points,
        color: BLUE,
        dashed,
        markers: false,
    }
}

fn figure(log: (bool, bool), series: Vec<Series>) -> LineFigure {
    LineFigure {
        title: "t".into(),
        x_label: "x".into(),
        y_label: "y".into(),
        log_x: log.0,
        log_y: log.1,
        series,
    }
}

/// `(min, max)` of `values`.
fn extent(values: impl Iterator<Item = f64>) -> (f64, f64) {
    values.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
        (a.min(v), b.max(v))
    })
}

/// The labels of `axis` are at least two, distinct, all plain decimals or
/// all mantissa-exponent (a `0` is either), and its ticks lie in its range.
fn assert_labelled(axis: &Axis, what: &str) {
    let labels = axis.labels();
    assert!(labels.len() >= 2, "{what}: {labels:?}");
    let mut unique = labels.clone();
    unique.sort();
    unique.dedup();
    assert_eq!(
        unique.len(),
        labels.len(),
        "{what}: repeated labels {labels:?}"
    );
    let exponents = labels.iter().filter(|l| l.contains('e')).count();
    let nonzero = labels.iter().filter(|l| *l != "0").count();
    assert!(
        exponents == 0 || exponents == nonzero,
        "{what}: mixed formats {labels:?}"
    );
    let (lo, hi) = axis.range;
    assert!(
        axis.ticks.iter().all(|t| *t >= lo && *t <= hi),
        "{what}: ticks {:?} outside {lo}..{hi}",
        axis.ticks
    );
}

/// Where `v` lies across `axis` (0 to 1).
fn unit(axis: &Axis, v: f64) -> f64 {
    let (lo, hi) = axis.range;
    if axis.log {
        (v / lo).ln() / (hi / lo).ln()
    } else {
        (v - lo) / (hi - lo)
    }
}

/// Whether the segment `p`–`q` has a point in the box `((x0, x1), (y0, y1))`
/// (Liang-Barsky clipping).
type UnitBox = ((f64, f64), (f64, f64));
fn segment_meets_box(p: (f64, f64), q: (f64, f64), ((x0, x1), (y0, y1)): UnitBox) -> bool {
    let (dx, dy) = (q.0 - p.0, q.1 - p.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (d, lo, hi, start) in [(dx, x0, x1, p.0), (dy, y0, y1, p.1)] {
        if d == 0.0 {
            if start < lo || start > hi {
                return false;
            }
            continue;
        }
        let (a, b) = ((lo - start) / d, (hi - start) / d);
        t0 = t0.max(a.min(b));
        t1 = t1.min(a.max(b));
    }
    t0 <= t1
}

/// The checks on one line figure `fig` (a family coloured by `bar`):
/// every series' drawable extremes inside the drawn axes, drawn to within
/// half a pixel (of a plot at least 400 pixels each way) by the decimated
/// or thinned line; every axis labelled; the legend's box clear of every
/// drawn segment and marker.
fn check(kind: &str, fig: &LineFigure, bar: Option<&Colorbar>) -> Plan {
    let p = plan(fig, bar);
    assert_labelled(&p.x, &format!("{kind}: x"));
    assert_labelled(&p.y, &format!("{kind}: y"));
    if let Some(axis) = &p.bar {
        assert_labelled(axis, &format!("{kind}: colour bar"));
        let (lo, hi) = bar.unwrap().range;
        assert!(
            axis.range.0 <= lo && axis.range.1 >= hi,
            "{kind}: colour bar"
        );
    }
    let ok = |(x, y): &(f64, f64)| {
        x.is_finite() && y.is_finite() && (!fig.log_x || *x > 0.0) && (!fig.log_y || *y > 0.0)
    };
    for (i, (s, drawn)) in fig.series.iter().zip(&p.figure.series).enumerate() {
        let pts: Vec<(f64, f64)> = s.points.iter().copied().filter(ok).collect();
        if pts.is_empty() {
            continue;
        }
        for (axis, pick, name) in [
            (&p.x, (|p: &(f64, f64)| p.0) as fn(&(f64, f64)) -> f64, "x"),
            (&p.y, |p: &(f64, f64)| p.1, "y"),
        ] {
            let (lo, hi) = extent(pts.iter().map(pick));
            let (a, b) = axis.range;
            assert!(
                a <= lo && hi <= b,
                "{kind}: series {i} {name} {lo}..{hi} outside the axis {a}..{b}"
            );
            let (dlo, dhi) = extent(drawn.points.iter().map(pick));
            let half_pixel = 0.5 / 400.0;
            assert!(
                (unit(axis, dlo) - unit(axis, lo)).abs() <= half_pixel
                    && (unit(axis, dhi) - unit(axis, hi)).abs() <= half_pixel,
                "{kind}: series {i} {name} drawn {dlo}..{dhi}, data {lo}..{hi}"
            );
        }
    }
    if let Some(legend) = p.legend {
        let to_unit = |q: &(f64, f64)| (unit(&p.x, q.0), unit(&p.y, q.1));
        for s in &p.figure.series {
            let pts: Vec<(f64, f64)> = s.points.iter().map(to_unit).collect();
            if s.markers {
                assert!(pts.iter().all(|&q| !segment_meets_box(q, q, legend)));
            }
            for w in pts.windows(2) {
                assert!(
                    !segment_meets_box(w[0], w[1], legend),
                    "{kind}: legend {legend:?} over {w:?}"
                );
            }
        }
    }
    p
}

/// A branch of 40 cycles over a narrow stiffness range (K/W 2.50e4 ..
/// 2.51e4): stable then unstable, a fold marked, a model switch.
fn branch(f: impl Fn(f64) -> f64) -> Vec<Series> {
    let k = |i: usize| 2.50e4 + 2.5 * i as f64;
    let stable = line(
        Some("stable cycles"),
        (0..=20).map(|i| (k(i), f(k(i)))).collect(),
        false,
    );
    let unstable = line(
        Some("unstable cycles"),
        (20..40).map(|i| (k(i), f(k(i)))).collect(),
        true,
    );
    let mut series = vec![stable, unstable];
    series.push(vertical_marker(
        &series,
        k(10),
        "quasi-static → inertial model",
        RGBColor(20, 140, 60),
    ));
    series.push(Series {
        label: Some("fold of cycles (LPC)".into()),
        points: vec![(k(20), f(k(20)))],
        color: RGBColor(150, 60, 150),
        dashed: false,
        markers: true,
    });
    series
}

/// 40 closed orbits in `(s, v)`, slip velocities over eleven decades, and
/// their spring force over one period; coloured by stiffness on a bar.
fn family() -> (Vec<Series>, Vec<Series>, Colorbar) {
    let stiffness: Vec<f64> = (0..40).map(|i| 300.0 * 1.14f64.powi(i)).collect();
    let bar = Colorbar::over("K/W [1/m]", stiffness.iter().copied());
    let orbit = |j: usize| -> Vec<(f64, f64)> {
        let r = 0.005 + 0.0035 * j as f64;
        (0..=2000)
            .map(|i| {
                let a = i as f64 / 2000.0 * TAU;
                (
                    0.5 + r * a.cos(),
                    10f64.powf(-9.0 * (j as f64 / 39.0) * a.sin() + 1.0),
                )
            })
            .collect()
    };
    let series = |f: &dyn Fn(usize) -> Vec<(f64, f64)>| -> Vec<Series> {
        (0..40)
            .map(|j| Series {
                label: None,
                points: f(j),
                color: bar.color(stiffness[j]),
                dashed: j % 3 == 0,
                markers: false,
            })
            .collect()
    };
    let orbits = series(&orbit);
    let times = series(&|j| {
        let period = 2.0 + 6.0 * j as f64;
        (0..=500)
            .map(|i| {
                let t = i as f64 / 500.0;
                (t * period, 0.45 + 0.004 * j as f64 * (1.0 - t))
            })
            .collect()
    });
    (orbits, times, bar)
}

/// A run of a million steps: slips one sample wide up to 9e5 µm/s over a
/// creep of 1e-4 µm/s, a sawtooth spring force, the protocol's V(t) as a
/// dashed staircase, the model switch.
fn run() -> (Vec<Series>, Vec<Series>) {
    let n = 1_000_000;
    let t = |i: usize| i as f64 * 3e-4;
    let v: Vec<(f64, f64)> = (0..n)
        .map(|i| {
            (
                t(i),
                if i % 10_000 == 5_000 {
                    9e5
                } else {
                    1e-4 * (1.0 + (i % 7) as f64)
                },
            )
        })
        .collect();
    let s: Vec<(f64, f64)> = (0..n)
        .map(|i| (t(i), 0.4 + 0.2 * ((i % 10_000) as f64 / 10_000.0)))
        .collect();
    let mut velocity = vec![
        line(Some("v(t)"), v, false),
        line(
            Some("pulling velocity V(t)"),
            vec![(0.0, 1.0), (100.0, 1.0), (100.0, 10.0), (t(n - 1), 10.0)],
            true,
        ),
    ];
    velocity.push(vertical_marker(
        &velocity,
        25.0,
        "quasi-static → inertial model",
        RGBColor(20, 140, 60),
    ));
    (velocity, vec![line(Some("s(t)"), s, false)])
}

#[test]
fn every_line_figure_kind_draws_its_extremes_with_clean_labels() {
    // Amplitude over a narrow stiffness range; period constant.
    check(
        "amplitude",
        &figure((false, false), branch(|k| 0.1 + (k - 2.5e4) * 1e-6)),
        None,
    );
    check("period", &figure((false, false), branch(|_| 12.5)), None);
    let (orbits, times, bar) = family();
    check("orbits", &figure((false, true), orbits), Some(&bar));
    check("time series", &figure((false, false), times), Some(&bar));
    let (velocity, force) = run();
    check("simulate V(t)", &figure((false, true), velocity), None);
    check("simulate s(t)", &figure((false, false), force), None);
    // The fold curve over less than a decade of velocity, with the Hopf curve.
    let fold: Vec<(f64, f64)> = (0..=60)
        .map(|i| {
            let v = 30.0 * 1.5f64.powf(i as f64 / 60.0);
            (v, 2.30e5 + 70.0 * i as f64)
        })
        .collect();
    let hopf: Vec<(f64, f64)> = fold.iter().map(|&(v, k)| (v, 0.995 * k)).collect();
    check(
        "fold curve",
        &figure(
            (true, true),
            vec![
                line(Some("fold of cycles (LPC)"), fold, false),
                line(
                    Some("Hopf curve (critical stiffness, Appendix C)"),
                    hopf,
                    false,
                ),
            ],
        ),
        None,
    );
    // A constant series, on both kinds of axes.
    for log in [(false, false), (true, true)] {
        check(
            "constant",
            &figure(
                log,
                vec![line(Some("a constant"), vec![(2.0, 3.0); 50], false)],
            ),
            None,
        );
    }
}

/// A legend entry long enough to need a corner of its own, on a constant
/// series, a zig-zag through every corner, a family of 40 curves and a
/// spike train of a million samples: its box holds no data.
#[test]
fn legends_never_cover_data() {
    let labelled = |points: Vec<(f64, f64)>, log_y: bool| {
        figure(
            (false, log_y),
            vec![line(Some("a fairly long legend entry"), points, false)],
        )
    };
    let zigzag = (0..400)
        .map(|i| (i as f64, if i % 2 == 0 { 0.0 } else { 1.0 }))
        .collect();
    let (orbits, _, _) = family();
    let mut with_label = figure((false, true), orbits);
    with_label.series[0].label = Some("switch".into());
    let (velocity, _) = run();
    for fig in [
        labelled(vec![(0.0, 3.0), (1.0, 3.0)], false),
        labelled(zigzag, false),
        with_label,
        figure((false, true), velocity),
    ] {
        let p = check("legend", &fig, None);
        assert!(p.legend.is_some());
    }
}

/// A stability diagram of the Hopf curve `curve` alone over `x_range`.
fn diagram(curve: &[(f64, f64, Criticality)], x_range: (f64, f64)) -> StabilityFigure {
    StabilityFigure {
        title: "t".into(),
        x_label: "x".into(),
        y_label: "y".into(),
        segments: segments(curve),
        reference: Vec::new(),
        reference_label: "Appendix C".into(),
        markers: Vec::new(),
        operating_point: None,
        vlines: Vec::new(),
        lpc: Vec::new(),
        unknown: Vec::new(),
        bistable: Vec::new(),
        x_range,
        notes: Vec::new(),
        stable_above: true,
    }
}

/// A stability diagram whose curves vary by less than a decade (physical:
/// K/M 1.7e5 .. 4e5; dimensionless: kappa 7.8e-3 .. 1.6e-2), a thin
/// hysteretic band with a span where its fold curve was not computed, and
/// a flat curve: the axes hold every curve and marker, the band panel the
/// widest band, and every axis is labelled distinctly in one format.
#[test]
fn stability_diagrams_draw_their_extremes_with_clean_labels() {
    for (kind, (k_lo, k_hi)) in [
        ("physical", (1.7e5, 4e5)),
        ("dimensionless", (7.8e-3, 1.6e-2)),
    ] {
        let k = |v: f64| k_lo + (k_hi - k_lo) * (v / 100.0).powf(0.7);
        let curve: Vec<(f64, f64, Criticality)> = (0..=100)
            .map(|i| {
                let v = 0.1 * 1000f64.powf(i as f64 / 100.0);
                let c = if v < 80.0 {
                    Criticality::Subcritical
                } else {
                    Criticality::Supercritical
                };
                (v, k(v), c)
            })
            .collect();
        let band: Vec<(f64, f64, Option<f64>)> = curve
            .iter()
            .filter(|p| p.0 > 0.4 && p.0 < 80.0)
            .map(|p| (p.0, p.1 * (1.0 + 0.007 * (p.0 / 80.0).sqrt()), Some(p.1)))
            .collect();
        let fig = StabilityFigure {
            reference: curve.iter().step_by(4).map(|p| (p.0, p.1)).collect(),
            markers: vec![("Bautin (l1 = 0)".into(), 80.0, k(80.0))],
            lpc: vec![band.iter().map(|p| (p.0, p.1)).collect()],
            unknown: vec![(0.1, 0.4)],
            bistable: vec![band.clone()],
            ..diagram(&curve, (0.1, 100.0))
        };
        let axes = panels(&fig);
        assert_labelled(&axes.x, kind);
        assert_labelled(&axes.y, kind);
        let (x0, x1) = axes.x.range;
        assert!(x0 <= 0.1 && x1 >= 100.0, "{kind}: x {x0}..{x1}");
        let ys = curve
            .iter()
            .map(|p| p.1)
            .chain(band.iter().map(|p| p.1))
            .chain([k(80.0)]);
        let (lo, hi) = extent(ys);
        let (y0, y1) = axes.y.range;
        assert!(
            y0 <= lo && hi <= y1,
            "{kind}: {lo}..{hi} outside {y0}..{y1}"
        );
        let widest = band
            .iter()
            .map(|p| 100.0 * (p.1 / p.2.unwrap() - 1.0))
            .fold(0.0, f64::max);
        let panel = axes.band.expect("a band of 0.7 % gets its panel");
        assert_labelled(&panel, &format!("{kind}: band"));
        assert!(
            panel.range.0 <= 0.0 && panel.range.1 >= widest,
            "{kind}: band {widest}"
        );
    }
    let flat: Vec<(f64, f64, Criticality)> = (0..10)
        .map(|i| (1.0 + i as f64, 3e-3, Criticality::Supercritical))
        .collect();
    let axes = panels(&diagram(&flat, (1.0, 10.0)));
    assert_labelled(&axes.x, "flat");
    assert_labelled(&axes.y, "flat");
    assert!(axes.y.range.0 < 3e-3 && axes.y.range.1 > 3e-3);
    assert!(axes.band.is_none());
}

/// A Hopf curve plunging to `kappa_c -> 0` at a friction minimum (drawn as
/// a vertical line, the y axis cut four decades below the top) with a fold
/// curve running on beyond it seven decades down (brockley's reaches the end
/// of its velocity range): the axes still hold the whole fold curve (it was
/// drawn along the bottom frame, at a false height).
#[test]
fn a_fold_curve_below_a_plunging_hopf_curve_stays_inside_the_axes() {
    let v_min = 2000.0;
    let curve: Vec<(f64, f64, Criticality)> = (0..=60)
        .map(|i| {
            let v = 100.0 + (v_min - 100.0) * (1.0 - 10f64.powf(-(i as f64) / 6.0));
            (
                v,
                1e6 * (1.0 - v / v_min).max(1e-12),
                Criticality::Subcritical,
            )
        })
        .collect();
    let fold: Vec<(f64, f64)> = (0..=50)
        .map(|i| {
            let v = 1700.0 * (1e5 / 1700.0f64).powf(i as f64 / 50.0);
            (v, 1.2e6 * (v / 1700.0).powf(-3.0))
        })
        .collect();
    let fig = StabilityFigure {
        vlines: vec![("friction minimum".into(), v_min)],
        lpc: vec![fold.clone()],
        ..diagram(&curve, (100.0, 1e5))
    };
    let axes = panels(&fig);
    let (lo, hi) = extent(fold.iter().map(|p| p.1));
    let (y0, y1) = axes.y.range;
    assert!(y0 <= lo && hi <= y1, "fold {lo}..{hi} outside {y0}..{y1}");
    // The plunge itself is still cut: the axis does not reach its 1e-6.
    assert!(y0 > 1e-6, "{y0}");
}
