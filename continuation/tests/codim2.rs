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
