//! Two-parameter curves on systems whose curves are known in closed form.

use continuation::codim2::{fold_curve, CurveSettings, HopfCurve};
use continuation::Stop;
use continuation::{Scalar, VectorField};

/// `z' = (p0 - p1^2 + i w) z + (p1 - 0.3) z |z|^2 - z |z|^4` in real coordinates:
/// Hopf curve `p0 = p1^2`, `l1 = 2 (p1 - 0.3) / w` (unit eigenvector), Bautin
/// point at `(p0, p1) = (0.09, 0.3)`.
struct BautinNormalForm {
    w: f64,
}

impl VectorField for BautinNormalForm {
    fn dim(&self) -> usize {
        2
    }
    fn n_params(&self) -> usize {
        2
    }
    fn rhs<D: Scalar>(&self, x: &[D], p: &[D], out: &mut [D]) {
        let r2 = x[0] * x[0] + x[1] * x[1];
        let g = p[0] - p[1] * p[1] + (p[1] - 0.3) * r2 - r2 * r2;
        out[0] = g * x[0] - x[1] * self.w;
        out[1] = x[0] * self.w + g * x[1];
    }
}

#[test]
fn hopf_curve_follows_the_parabola_and_locates_the_bautin_point() {
    let sys = BautinNormalForm { w: 1.3 };
    let settings = CurveSettings {
        bounds: [(-10.0, 10.0), (-1.0, 1.0)],
        ..Default::default()
    };
    let curve = HopfCurve::new(&sys, &[0.0, 0.0], 1.3, &[0.25, -0.5], [0, 1], settings).unwrap();
    let mut bautins = Vec::new();
    let mut n = 0;
    for point in curve {
        let point = point.unwrap();
        n += 1;
        let (p0, p1) = (point.p[0], point.p[1]);
        assert!((p0 - p1 * p1).abs() < 1e-13, "off the Hopf curve at {p1}");
        assert!((point.omega / 1.3 - 1.0).abs() < 1e-13);
        assert!(
            (point.l1 - 2.0 * (p1 - 0.3) / 1.3).abs() < 1e-12,
            "l1 at p1 = {p1}"
        );
        bautins.extend(point.events.into_iter().map(|e| e.point));
    }
    assert!(n > 5);
    assert_eq!(bautins.len(), 1);
    let b = &bautins[0];
    assert!(
        (b.p[1] - 0.3).abs() < 1e-12 && (b.p[0] - 0.09).abs() < 1e-12,
        "Bautin at {:?}",
        b.p
    );
}

#[test]
fn hopf_curve_stops_on_its_bound() {
    let sys = BautinNormalForm { w: 2.0 };
    let settings = CurveSettings {
        bounds: [(-10.0, 10.0), (-1.0, 0.7)],
        ..Default::default()
    };
    let mut curve = HopfCurve::new(&sys, &[0.0, 0.0], 2.0, &[0.0, 0.0], [0, 1], settings).unwrap();
    let last = curve.by_ref().last().unwrap().unwrap();
    assert_eq!(
        curve.stop(),
        Some(Stop::Bound {
            index: 1,
            value: 0.7,
            bound: 0.7
        })
    );
    assert!((last.p[1] - 0.7).abs() < 1e-14);
}

/// Cusp `x' = a + b x - x^3`: folds on `27 a^2 = 4 b^3`.
struct Cusp;
impl VectorField for Cusp {
    fn dim(&self) -> usize {
        1
    }
    fn n_params(&self) -> usize {
        2
    }
    fn rhs<D: Scalar>(&self, x: &[D], p: &[D], out: &mut [D]) {
        out[0] = p[0] + p[1] * x[0] - x[0] * x[0] * x[0];
    }
}

#[test]
fn fold_curve_of_the_cusp() {
    // Start at the fold x = 1: b = 3, a = -2.
    let settings = CurveSettings {
        bounds: [(-10.0, 10.0), (0.3, 3.0)],
        increase_second: false,
        ..Default::default()
    };
    let points = fold_curve(&Cusp, &[1.0], &[-2.0, 3.0], [0, 1], &settings).unwrap();
    assert!(points.len() > 5);
    for pt in &points {
        let (x, p) = (&pt.x, &pt.p);
        let (a, b) = (p[0], p[1]);
        assert!(
            (27.0 * a * a - 4.0 * b * b * b).abs() < 1e-11 * b.powi(3),
            "a = {a}, b = {b}"
        );
        assert!((3.0 * x[0] * x[0] - b).abs() < 1e-12 * b);
    }
    assert!((points.last().unwrap().p[1] - 0.3).abs() < 1e-14);
}

/// Branch switching from a Bautin point to its curve of folds of cycles.
/// In polar coordinates the system of [`BautinNormalForm`] is
/// `rho' = rho (beta1 + beta2 rho^2 - rho^4)` with `beta1 = p0 - p1^2`,
/// `beta2 = p1 - 0.3`, `theta' = w`: its cycles fold where
/// `beta2 - 2 rho^2 = 0`, i.e. on `p0 = p1^2 - (p1 - 0.3)^2 / 4` (`p1 > 0.3`),
/// with amplitude `rho^2 = (p1 - 0.3) / 2` and period `2 pi / w`.
#[test]
fn curve_of_folds_of_cycles_from_the_bautin_point() {
    use continuation::periodic::{CycleSettings, LpcCurve, LpcCurveSettings};
    let w = 1.3;
    let sys = BautinNormalForm { w };
    let settings = CurveSettings {
        bounds: [(-10.0, 10.0), (-1.0, 0.6)],
        control: continuation::CurveControl {
            step: continuation::StepControl {
                ds: 0.05,
                ds_max: 0.05,
                ..CurveSettings::default().control.step
            },
            ..CurveSettings::default().control
        },
        ..Default::default()
    };
    let curve = HopfCurve::new(&sys, &[0.0, 0.0], w, &[0.25, -0.5], [0, 1], settings).unwrap();
    let points: Vec<_> = curve.map(Result::unwrap).collect();
    let at = points.iter().position(|p| !p.events.is_empty()).unwrap();
    let bautin = &points[at].events[0].point;
    // The first point past the Bautin point, on its subcritical side
    // (l1 > 0), is where the folded cycles are born.
    let beside = &points[at];
    assert!(beside.l1 > 0.0 && beside.p[1] > 0.3);
    let cycles = CycleSettings {
        p_min: -10.0,
        p_max: 10.0,
        ..Default::default()
    };
    let lpc = LpcCurveSettings {
        p2_min: 0.0,
        p2_max: 0.9,
        ..Default::default()
    };
    let folds = LpcCurve::from_bautin(&sys, bautin, beside, (0, 1), 1.0, cycles, lpc).unwrap();
    let mut n = 0;
    let mut last_p1 = 0.0;
    for fold in folds {
        let c = fold.unwrap().cycle;
        let (p0, p1) = (c.p[0], c.p[1]);
        let exact = p1 * p1 - (p1 - 0.3) * (p1 - 0.3) / 4.0;
        assert!(
            (p0 - exact).abs() < 1e-12,
            "p0 = {p0} against {exact} at p1 = {p1}"
        );
        let period = 2.0 * std::f64::consts::PI / w;
        assert!(
            (c.period / period - 1.0).abs() < 1e-12,
            "period {}",
            c.period
        );
        let (lo, hi) = c.range(&sys, 0);
        let rho = ((p1 - 0.3) / 2.0).sqrt();
        assert!(
            (0.5 * (hi - lo) / rho - 1.0).abs() < 1e-9,
            "amplitude at p1 = {p1}"
        );
        n += 1;
        last_p1 = p1;
    }
    assert!(n > 5, "{n} folds");
    assert!(
        (last_p1 - 0.9).abs() < 1e-12,
        "the curve ends at p1 = {last_p1}"
    );
}

/// From the supercritical side of a Bautin point there is no fold to start
/// from: the typed error says so.
#[test]
fn no_curve_of_folds_from_the_supercritical_side() {
    use continuation::periodic::{CycleSettings, LpcCurve, LpcCurveSettings};
    use continuation::ContinuationError;
    let sys = BautinNormalForm { w: 1.0 };
    let curve = HopfCurve::new(
        &sys,
        &[0.0, 0.0],
        1.0,
        &[0.25, -0.5],
        [0, 1],
        CurveSettings {
            bounds: [(-10.0, 10.0), (-1.0, 0.6)],
            ..Default::default()
        },
    )
    .unwrap();
    let points: Vec<_> = curve.map(Result::unwrap).collect();
    let at = points.iter().position(|p| !p.events.is_empty()).unwrap();
    let bautin = &points[at].events[0].point;
    let before = &points[at - 1];
    assert!(before.l1 < 0.0);
    let result = LpcCurve::from_bautin(
        &sys,
        bautin,
        before,
        (0, 1),
        1.0,
        CycleSettings::default(),
        LpcCurveSettings::default(),
    );
    assert!(
        matches!(result, Err(ContinuationError::NotSubcritical { .. })),
        "{:?}",
        result.err()
    );
}
