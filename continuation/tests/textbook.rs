//! The engine on textbook systems whose bifurcations are known in closed form.

use continuation::StepControl;
use continuation::{Branch, ContinuationSettings, Direction, EventKind, Scalar, VectorField};

/// Collects all located events of a branch, failing the test on any error.
fn events_of<S: VectorField>(
    sys: &S,
    x0: &[f64],
    p0: &[f64],
    k: usize,
    s: ContinuationSettings,
) -> Vec<continuation::Event> {
    let mut out = Vec::new();
    for point in Branch::new(sys, x0, p0, k, s).expect("start") {
        out.extend(point.expect("branch point").events);
    }
    out
}

/// Fold normal form `x' = p - x^2`: a limit point at `p = 0, x = 0`.
struct FoldNormalForm;
impl VectorField for FoldNormalForm {
    fn dim(&self) -> usize {
        1
    }
    fn n_params(&self) -> usize {
        1
    }
    fn rhs<D: Scalar>(&self, x: &[D], p: &[D], out: &mut [D]) {
        out[0] = p[0] - x[0] * x[0];
    }
}

#[test]
fn fold_normal_form_limit_point_at_origin() {
    let settings = ContinuationSettings {
        direction: Direction::Decreasing,
        step: StepControl {
            ds: 0.05,
            ..ContinuationSettings::default().step
        },
        max_steps: 200,
        p_max: 1.0,
        ..Default::default()
    };
    let events = events_of(&FoldNormalForm, &[1.0], &[1.0], 0, settings);
    assert_eq!(events.len(), 1, "{events:?}");
    let e = &events[0];
    // y = x - x_fold on the centre manifold: x' = p - x^2 gives a = -1 with q = p = 1.
    let EventKind::Fold { a } = e.kind else {
        panic!("not a fold: {:?}", e.kind)
    };
    assert!((a + 1.0).abs() < 1e-14, "a = {a}");
    assert!(
        e.point.param().abs() < 1e-14 && e.point.x[0].abs() < 1e-7,
        "p = {}, x = {}",
        e.point.param(),
        e.point.x[0]
    );
    // At a fold the equilibrium is a double root: x = O(sqrt(p)) explains the looser x bound.
    assert!(e.point.eigenvalues[0].norm() < 1e-7);
}

/// Hopf normal form in Cartesian coordinates with a shifted parameter:
/// `z' = (p - p0 + i w) z + c z |z|^2`, Hopf at `p = p0` with frequency `w`.
struct HopfNormalForm {
    p0: f64,
    w: f64,
    c: (f64, f64),
}
impl VectorField for HopfNormalForm {
    fn dim(&self) -> usize {
        2
    }
    fn n_params(&self) -> usize {
        1
    }
    fn rhs<D: Scalar>(&self, x: &[D], p: &[D], out: &mut [D]) {
        let beta = p[0] - self.p0;
        let r2 = x[0] * x[0] + x[1] * x[1];
        out[0] = beta * x[0] - x[1] * self.w + (x[0] * self.c.0 - x[1] * self.c.1) * r2;
        out[1] = x[0] * self.w + beta * x[1] + (x[0] * self.c.1 + x[1] * self.c.0) * r2;
    }
}

#[test]
fn hopf_normal_form_hopf_point_and_frequency() {
    let sys = HopfNormalForm {
        p0: 0.37,
        w: 2.5,
        c: (-1.0, 0.3),
    };
    let settings = ContinuationSettings {
        step: StepControl {
            ds: 0.1,
            ..ContinuationSettings::default().step
        },
        p_max: 1.0,
        ..Default::default()
    };
    let events = events_of(&sys, &[0.0, 0.0], &[-0.5], 0, settings);
    assert_eq!(events.len(), 1, "{events:?}");
    let EventKind::Hopf { omega } = events[0].kind else {
        panic!("not a Hopf point")
    };
    assert!((events[0].point.param() / 0.37 - 1.0).abs() < 1e-12);
    assert!((omega / 2.5 - 1.0).abs() < 1e-12);
}

/// Branch switching from a located Hopf point: the cycles born there
/// (`CycleBranch::from_hopf_event`) have the Hopf frequency at their start,
/// and the radius `sqrt(-(p - p0) / c)` of the normal form at every orbit.
#[test]
fn cycles_switch_from_a_located_hopf_point() {
    use continuation::periodic::{CycleBranch, CycleSettings};
    let sys = HopfNormalForm {
        p0: 0.37,
        w: 2.5,
        c: (-1.0, 0.0),
    };
    let settings = ContinuationSettings {
        p_max: 1.0,
        ..Default::default()
    };
    let events = events_of(&sys, &[0.0, 0.0], &[-0.5], 0, settings);
    let settings = CycleSettings {
        max_steps: 10,
        ..Default::default()
    };
    let branch = CycleBranch::from_hopf_event(&sys, &events[0], settings)
        .expect("a Hopf event")
        .unwrap();
    let mut n = 0;
    for pt in branch {
        let pt = pt.unwrap();
        let (lo, hi) = pt.cycle.range(&sys, 0);
        let beta = pt.cycle.p[0] - 0.37;
        assert!(beta > 0.0, "supercritical: cycles for p > p0");
        assert!((0.5 * (hi - lo) / beta.sqrt() - 1.0).abs() < 1e-6);
        assert!((pt.cycle.period * 2.5 / std::f64::consts::TAU - 1.0).abs() < 1e-9);
        n += 1;
    }
    assert_eq!(n, 11);
}

/// Brusselator `x' = a - (b + 1) x + x^2 y, y' = b x - x^2 y`:
/// equilibrium `(a, b/a)`, Hopf at `b = 1 + a^2` with frequency `a`.
struct Brusselator;
impl VectorField for Brusselator {
    fn dim(&self) -> usize {
        2
    }
    fn n_params(&self) -> usize {
        2
    }
    fn rhs<D: Scalar>(&self, x: &[D], p: &[D], out: &mut [D]) {
        let (a, b) = (p[0], p[1]);
        out[0] = a - (b + 1.0) * x[0] + x[0] * x[0] * x[1];
        out[1] = b * x[0] - x[0] * x[0] * x[1];
    }
}

#[test]
fn brusselator_hopf_at_one_plus_a_squared() {
    for a in [0.3, 1.0, 2.7] {
        let b0 = 0.5 * (1.0 + a * a);
        let settings = ContinuationSettings {
            step: StepControl {
                ds: 0.05,
                ..ContinuationSettings::default().step
            },
            p_max: 3.0 * (1.0 + a * a),
            ..Default::default()
        };
        let events = events_of(&Brusselator, &[a, b0 / a], &[a, b0], 1, settings);
        assert_eq!(events.len(), 1, "a = {a}: {events:?}");
        let e = &events[0];
        let EventKind::Hopf { omega } = e.kind else {
            panic!("not a Hopf point")
        };
        let b_c = 1.0 + a * a;
        assert!(
            (e.point.param() / b_c - 1.0).abs() < 1e-12,
            "b = {} vs {b_c}",
            e.point.param()
        );
        assert!((omega / a - 1.0).abs() < 1e-12, "omega = {omega} vs {a}");
        assert!(
            (e.point.x[0] / a - 1.0).abs() < 1e-12
                && (e.point.x[1] / (b_c / a) - 1.0).abs() < 1e-12
        );
    }
}

/// `x' = p x + x^2 + y, y' = x - y`: Jacobian at 0 is `[[p, 1], [1, -1]]`, trace
/// `p - 1`, determinant `-p - 1`. At `p = 1` the eigenvalues are `+-sqrt(2)`:
/// the bialternate test vanishes at this neutral saddle, but it is no Hopf point.
struct NeutralSaddle;
impl VectorField for NeutralSaddle {
    fn dim(&self) -> usize {
        2
    }
    fn n_params(&self) -> usize {
        1
    }
    fn rhs<D: Scalar>(&self, x: &[D], p: &[D], out: &mut [D]) {
        out[0] = p[0] * x[0] + x[0] * x[0] + x[1];
        out[1] = x[0] - x[1];
    }
}

#[test]
fn neutral_saddle_is_not_reported_as_hopf() {
    let settings = ContinuationSettings {
        step: StepControl {
            ds: 0.05,
            ..ContinuationSettings::default().step
        },
        p_max: 2.0,
        ..Default::default()
    };
    let mut crossed = false;
    let mut prev_test: Option<f64> = None;
    for point in Branch::new(&NeutralSaddle, &[0.0, 0.0], &[0.5], 0, settings).unwrap() {
        let point = point.unwrap();
        assert!(
            point.events.is_empty(),
            "spurious event at p = {}: {:?}",
            point.param(),
            point.events
        );
        let t = continuation::hopf_test(&point.eigenvalues);
        crossed |= prev_test.is_some_and(|a| a * t < 0.0);
        prev_test = Some(t);
    }
    assert!(
        crossed,
        "the Hopf test function must change sign here, or the test proves nothing"
    );
}
