//! Periodic orbits by collocation on systems with known cycles, and the
//! collocation system's kernels (Floquet pencil, residual, Jacobian, Newton's
//! storage) checked against them.

use super::bordered::CyclicReduction;
use super::collocation::{Collocation, Linearization};
use super::floquet::pencil_multipliers;
use super::newton::{newton_bordered, solves_bordered, unit_row};
use super::{
    locate_lpc, CollocationPoints, Cycle, CycleBranch, CycleEvent, CyclePoint, CycleSettings,
    Discretization, FloquetPolicy, LpcCurve, LpcCurveSettings, Mesh,
};
use crate::{
    Complex64, ContinuationError, NewtonFailure, NewtonSettings, Scalar, StepControl, Stop,
    VectorField,
};
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

/// Stuart–Landau `Z' = (beta + i w) Z - Z |Z|^2 + i g Z |Z|^2` (beta = p):
/// cycle `|Z|^2 = beta`, angular frequency `w + g beta`, nontrivial Floquet
/// multiplier `exp(-2 beta T)`.
struct StuartLandau {
    w: f64,
    g: f64,
}
impl VectorField for StuartLandau {
    fn dim(&self) -> usize {
        2
    }
    fn n_params(&self) -> usize {
        1
    }
    fn rhs<D: Scalar>(&self, x: &[D], p: &[D], out: &mut [D]) {
        let r2 = x[0] * x[0] + x[1] * x[1];
        let rot = r2 * self.g + self.w;
        out[0] = (p[0] - r2) * x[0] - rot * x[1];
        out[1] = rot * x[0] + (p[0] - r2) * x[1];
    }
}

#[test]
fn stuart_landau_cycles_radius_period_and_multipliers() {
    stuart_landau_branch_is_the_closed_form(&StuartLandau { w: 2.0, g: 0.5 });
}

/// The cycle branch of the Stuart–Landau system `sys` (written explicitly
/// or in an implicit form) from its Hopf point against the closed forms:
/// period `2 pi / (w + g beta)`, radius `sqrt(beta)`, trivial multiplier 1,
/// the other `exp(-2 beta T)` by Liouville's formula (what the branch
/// reports for planar systems) and from the Floquet pencil.
fn stuart_landau_branch_is_the_closed_form<S: VectorField>(sys: &S) {
    let settings = CycleSettings {
        mesh: Discretization {
            ntst: 20,
            ..Default::default()
        },
        p_max: 1.0,
        step: StepControl {
            ds: 1e-2,
            ..CycleSettings::default().step
        },
        max_steps: 300,
        ..Default::default()
    };
    let branch = CycleBranch::from_hopf(sys, &[0.0, 0.0], 2.0, &[0.0], 0, settings).unwrap();
    let (mut count, mut last_beta) = (0, 0.0);
    for pt in branch {
        let pt = pt.unwrap();
        let c = &pt.cycle;
        let beta = c.p[0];
        let (lo, hi) = c.range(sys, 0);
        let period = 2.0 * std::f64::consts::PI / (2.0 + 0.5 * beta);
        assert!(
            (c.period / period - 1.0).abs() < 1e-9,
            "beta = {beta}: T = {} vs {period}",
            c.period
        );
        assert!(
            (0.5 * (hi - lo) / beta.sqrt() - 1.0).abs() < 1e-8,
            "beta = {beta}: radius"
        );
        assert!(
            pt.trivial_error < 1e-9,
            "trivial multiplier off by {}",
            pt.trivial_error
        );
        let exact = (-2.0 * beta * period).exp();
        let smallest = |mu: &[Complex64]| mu.iter().map(|z| z.norm()).fold(f64::INFINITY, f64::min);
        let liouville = smallest(&pt.multipliers);
        assert!(
            (liouville / exact - 1.0).abs() < 1e-9,
            "beta = {beta}: Liouville mu = {liouville} vs {exact}"
        );
        let coll = Collocation::new(sys, c, 0);
        let pencil = smallest(
            &pencil_multipliers(&CyclicReduction::new(&coll.linearize(&coll.unknowns(c)), 2))
                .unwrap(),
        );
        assert!(
            (pencil / exact - 1.0).abs() < 1e-7,
            "beta = {beta}: pencil mu = {pencil} vs {exact}"
        );
        assert_eq!(pt.n_unstable, 0);
        count += 1;
        last_beta = beta;
    }
    assert!(
        count > 5 && last_beta > 0.9,
        "{count} cycles up to beta = {last_beta}"
    );
}

#[test]
fn fold_of_cycles_is_located_and_stability_changes_there() {
    // The Bautin system at alpha = 1: `Z' = (beta + i w) Z + Z |Z|^2 - Z |Z|^4`,
    // subcritical Hopf at beta = 0, cycles on beta = r^4 - r^2, a fold of
    // cycles at r^2 = 1/2, beta = -1/4; nontrivial multiplier
    // exp(2 r^2 (1 - 2 r^2) T) (unstable below the fold's radius).
    let sys = Bautin { w: 1.5 };
    let settings = bautin_settings(120);
    let branch = CycleBranch::from_hopf(&sys, &[0.0, 0.0], 1.5, &[0.0, 1.0], 0, settings).unwrap();
    let period = 2.0 * std::f64::consts::PI / 1.5;
    let mut lpcs = Vec::new();
    let mut last_r2 = 0.0;
    for pt in branch {
        let pt = pt.unwrap();
        let (lo, hi) = pt.cycle.range(&sys, 0);
        let r2 = (0.5 * (hi - lo)).powi(2);
        let beta = pt.cycle.p[0];
        assert!(
            (beta - (r2 * r2 - r2)).abs() < 1e-8,
            "on the branch: beta = {beta}, r^2 = {r2}: {:.2e}",
            beta - (r2 * r2 - r2)
        );
        if (r2 - 0.5).abs() > 1e-2 {
            let mu = (2.0 * r2 * (1.0 - 2.0 * r2) * period).exp();
            let nontrivial = pt
                .multipliers
                .iter()
                .map(|z| z.norm())
                .min_by(|a, b| (a - mu).abs().total_cmp(&(b - mu).abs()))
                .unwrap();
            assert!(
                (nontrivial - mu).abs() < 1e-7 * mu + 1e-13,
                "r^2 = {r2}: {nontrivial} vs {mu}"
            );
            assert_eq!(pt.n_unstable, usize::from(r2 < 0.5), "r^2 = {r2}");
        }
        lpcs.extend(pt.event(CycleEvent::Fold).cloned());
        last_r2 = r2;
    }
    assert!(
        last_r2 > 0.9,
        "the branch must pass the fold: r^2 reached {last_r2}"
    );
    assert_eq!(lpcs.len(), 1);
    let lpc = &lpcs[0];
    let (lo, hi) = lpc.cycle.range(&sys, 0);
    assert!(
        (lpc.cycle.p[0] + 0.25).abs() < 1e-10,
        "LPC at beta = {}",
        lpc.cycle.p[0]
    );
    assert!(((0.5 * (hi - lo)).powi(2) - 0.5).abs() < 1e-5, "LPC radius");
    assert!(lpc.dp_ds.abs() < 1e-8);
}

#[test]
fn a_branch_lands_on_a_bound_next_to_a_fold_and_drops_the_fold_beyond() {
    // The Bautin system of the test above, its fold of cycles at beta =
    // -1/4, the range ending 1e-9 before it: the orbit at the bound is
    // nearly a fold (r^2 = 1/2 -+ 3.2e-5), and the fold past the bound is
    // not reported.
    let sys = Bautin { w: 1.5 };
    let p_min = -0.25 + 1e-9;
    let settings = CycleSettings {
        p_min,
        ..bautin_settings(120)
    };
    let mut branch =
        CycleBranch::from_hopf(&sys, &[0.0, 0.0], 1.5, &[0.0, 1.0], 0, settings).unwrap();
    let points: Vec<CyclePoint> = branch.by_ref().map(|pt| pt.unwrap()).collect();
    let last = points.last().unwrap();
    let beta = last.cycle.p[0];
    assert!(
        (beta - p_min).abs() < 1e-11 * p_min.abs(),
        "ended at {beta}"
    );
    assert!(matches!(branch.stop(), Some(Stop::Bound { bound, .. }) if bound == p_min));
    let (lo, hi) = last.cycle.range(&sys, 0);
    let r2 = (0.5 * (hi - lo)).powi(2);
    assert!((beta - (r2 * r2 - r2)).abs() < 1e-8, "r^2 = {r2}");
    assert!(points.iter().all(|pt| pt.event(CycleEvent::Fold).is_none()));
}

/// Van der Pol `x' = y, y' = mu (1 - x^2) y - x` (parameter mu).
struct VanDerPol;
impl VectorField for VanDerPol {
    fn dim(&self) -> usize {
        2
    }
    fn n_params(&self) -> usize {
        1
    }
    fn rhs<D: Scalar>(&self, x: &[D], p: &[D], out: &mut [D]) {
        out[0] = x[1];
        out[1] = p[0] * (-(x[0] * x[0]) + 1.0) * x[1] - x[0];
    }
}

fn vdp_period(ntst: usize, degree: usize, points: CollocationPoints) -> f64 {
    vdp_cycle(ntst, degree, points).cycle.period
}

/// The van der Pol cycle at mu = 1, corrected on a fixed uniform mesh.
fn vdp_cycle(ntst: usize, degree: usize, points: CollocationPoints) -> CyclePoint {
    let mesh = Mesh::uniform(ntst, degree, points);
    let mut u = Vec::new();
    for i in 0..ntst {
        for l in 0..degree {
            let t = 2.0 * std::f64::consts::PI * mesh.node_time(i, l);
            u.extend([2.0 * t.cos(), -2.0 * t.sin()]);
        }
    }
    let guess = Cycle {
        mesh,
        u,
        period: 6.66,
        p: vec![1.0],
        n: 2,
    };
    let settings = CycleSettings {
        mesh: Discretization {
            adapt_every: 0,
            mesh_tol: None,
            points,
            ..Default::default()
        },
        floquet: FloquetPolicy {
            trivial_tol: None,
            ..Default::default()
        },
        ..Default::default()
    };
    let mut branch = CycleBranch::from_cycle(&VanDerPol, guess, 0, None, settings).unwrap();
    let first = branch.next().unwrap().unwrap();
    assert!(
        (first.cycle.p[0] - 1.0).abs() < 1e-14,
        "the first orbit is corrected at fixed mu"
    );
    first
}

#[test]
fn liouville_and_the_floquet_pencil_agree_on_van_der_pol() {
    // Two methods for the nontrivial multiplier of a planar cycle with no
    // closed form: exp(int_0^T mu (1 - x^2) dt) by the collocation quadrature
    // (what the branch reports) and the eigenvalue of the Floquet pencil.
    let pt = vdp_cycle(80, 4, CollocationPoints::Gauss);
    let c = &pt.cycle;
    let smallest = |mu: &[Complex64]| mu.iter().map(|z| z.norm()).fold(f64::INFINITY, f64::min);
    let liouville = smallest(&pt.multipliers);
    let coll = Collocation::new(&VanDerPol, c, 0);
    let pencil = smallest(
        &pencil_multipliers(&CyclicReduction::new(&coll.linearize(&coll.unknowns(c)), 2)).unwrap(),
    );
    assert!(
        (liouville / pencil - 1.0).abs() < 1e-9,
        "Liouville {liouville} vs pencil {pencil}"
    );
    assert!(liouville > 1e-4 && liouville < 0.1, "{liouville}");
}

/// Observed orders of the period error of van der Pol (mu = 1) on uniform
/// meshes of `ntsts` intervals, against a 400-interval Gauss reference.
fn vdp_orders(m: usize, points: CollocationPoints, ntsts: [usize; 3]) -> Vec<f64> {
    let reference = vdp_period(400, 4, CollocationPoints::Gauss);
    assert!(
        (reference - 6.66328685932313).abs() < 1e-10,
        "van der Pol mu = 1 period {reference}"
    );
    let errs: Vec<f64> = ntsts
        .iter()
        .map(|&n| (vdp_period(n, m, points) - reference).abs())
        .collect();
    errs.windows(2).map(|w| (w[0] / w[1]).log2()).collect()
}

#[test]
fn period_converges_at_order_2m_in_ntst() {
    // Gauss collocation of degree m: superconvergence O(h^(2m)) at mesh points and for the period.
    let m = 2;
    for order in vdp_orders(m, CollocationPoints::Gauss, [20, 40, 80]) {
        assert!(
            (order - 2.0 * m as f64).abs() < 0.6,
            "observed order {order}"
        );
    }
}

#[test]
fn radau_period_converges_at_order_2m_minus_1_in_ntst() {
    // Radau IIA collocation of degree m: O(h^(2m - 1)) at mesh points
    // (asymptotic from 40 intervals on for m = 3).
    for m in [2, 3] {
        for order in vdp_orders(m, CollocationPoints::Radau, [40, 80, 160]) {
            assert!(
                (order - (2 * m - 1) as f64).abs() < 0.6,
                "m = {m}: observed order {order}"
            );
        }
    }
}

#[test]
fn user_points_land_exactly_on_the_requested_parameters() {
    let sys = StuartLandau { w: 2.0, g: 0.5 };
    let settings = CycleSettings {
        mesh: Discretization {
            ntst: 20,
            ..Default::default()
        },
        p_max: 0.8,
        step: StepControl {
            ds: 1e-2,
            ..CycleSettings::default().step
        },
        user_points: vec![0.25, 0.5],
        ..Default::default()
    };
    let mut found = Vec::new();
    for pt in CycleBranch::from_hopf(&sys, &[0.0, 0.0], 2.0, &[0.0], 0, settings).unwrap() {
        found.extend(pt.unwrap().user_points().cloned());
    }
    assert_eq!(found.len(), 2);
    for (u, beta) in found.iter().zip([0.25, 0.5]) {
        assert!(
            (u.cycle.p[0] - beta).abs() < 1e-12,
            "landed at {}",
            u.cycle.p[0]
        );
        let (lo, hi) = u.cycle.range(&sys, 0);
        assert!((0.5 * (hi - lo) / f64::sqrt(beta) - 1.0).abs() < 1e-8);
    }
}

#[test]
fn a_cycle_branch_lands_on_its_range_bound() {
    let sys = StuartLandau { w: 2.0, g: 0.5 };
    let p_max = 0.8;
    let settings = CycleSettings {
        mesh: Discretization {
            ntst: 20,
            ..Default::default()
        },
        p_max,
        step: StepControl {
            ds: 1e-2,
            ..CycleSettings::default().step
        },
        user_points: vec![0.5],
        ..Default::default()
    };
    let mut branch = CycleBranch::from_hopf(&sys, &[0.0, 0.0], 2.0, &[0.0], 0, settings).unwrap();
    let points: Vec<CyclePoint> = branch.by_ref().map(|pt| pt.unwrap()).collect();
    assert_eq!(
        branch.stop(),
        Some(Stop::Bound {
            index: 0,
            value: p_max,
            bound: p_max
        })
    );
    let (last, inside) = points.split_last().unwrap();
    assert_eq!(last.cycle.p[0], p_max);
    assert!(inside.iter().all(|pt| pt.cycle.p[0] < p_max));
    // The closed form r = sqrt(beta) on the bound, and the user point
    // passed on the way kept.
    let (lo, hi) = last.cycle.range(&sys, 0);
    assert!((0.5 * (hi - lo) / f64::sqrt(p_max) - 1.0).abs() < 1e-8);
    assert_eq!(points.iter().flat_map(|pt| pt.user_points()).count(), 1);
}

/// `Z' = (beta + i w) Z + alpha Z |Z|^2 - Z |Z|^4` (parameters `beta`, `alpha`):
/// cycles on `beta = r^4 - alpha r^2`; folds of cycles where `2 r^2 = alpha`,
/// i.e. on the curve `beta = -alpha^2 / 4`, ending at the Bautin point `alpha = 0`.
struct Bautin {
    w: f64,
}
impl VectorField for Bautin {
    fn dim(&self) -> usize {
        2
    }
    fn n_params(&self) -> usize {
        2
    }
    fn rhs<D: Scalar>(&self, x: &[D], p: &[D], out: &mut [D]) {
        let r2 = x[0] * x[0] + x[1] * x[1];
        let g = p[0] + p[1] * r2 - r2 * r2;
        out[0] = g * x[0] - x[1] * self.w;
        out[1] = x[0] * self.w + g * x[1];
    }
}

#[test]
fn fold_of_cycles_by_two_routes_and_its_curve_in_two_parameters() {
    let sys = Bautin { w: 1.5 };
    let alpha = 1.2;
    let settings = bautin_settings(200);
    let branch =
        CycleBranch::from_hopf(&sys, &[0.0, 0.0], 1.5, &[0.0, alpha], 0, settings).unwrap();
    // Route 1: the sign change of dp/ds on the branch; route 2: Newton on the
    // minimally augmented system from the orbit before the fold.
    let mut previous = None;
    let mut routes = None;
    for pt in branch {
        let pt = pt.unwrap();
        if let Some(lpc) = pt.event(CycleEvent::Fold) {
            let before: &CyclePoint = previous.as_ref().unwrap();
            let newton = NewtonSettings {
                step_tol: 1e-12,
                residual_tol: 1e-11,
                max_iter: 20,
            };
            let second = locate_lpc(&sys, &before.cycle, 0, &newton).unwrap();
            routes = Some((lpc.cycle.clone(), second.cycle));
            break;
        }
        previous = Some(pt);
    }
    let (first, second) = routes.expect("a fold of cycles on the branch");
    let exact = -alpha * alpha / 4.0;
    assert!(
        (first.p[0] - exact).abs() < 1e-10,
        "route 1: {}",
        first.p[0]
    );
    assert!(
        (second.p[0] - exact).abs() < 1e-10,
        "route 2: {}",
        second.p[0]
    );
    assert!((first.p[0] - second.p[0]).abs() < 1e-8 * exact.abs());
    let (lo, hi) = second.range(&sys, 0);
    assert!(((0.5 * (hi - lo)).powi(2) - alpha / 2.0).abs() < 1e-6);
    // The curve of folds, both ways: on beta = -alpha^2/4 up to alpha = 2, and
    // down to the Bautin point, where the cycles shrink to nothing.
    for (direction, bound) in [(1.0, 2.0), (-1.0, 0.0)] {
        let curve_settings = LpcCurveSettings {
            p2_min: 0.05,
            p2_max: 2.0,
            min_amplitude: 0.3,
            ..Default::default()
        };
        let curve = LpcCurve::new(&sys, &second, (0, 1), direction, curve_settings).unwrap();
        let mut last_alpha = alpha;
        let mut count = 0;
        for pt in curve {
            let c = pt.unwrap().cycle;
            let (beta, a) = (c.p[0], c.p[1]);
            assert!(
                (beta + a * a / 4.0).abs() < 1e-9,
                "alpha = {a}: beta = {beta} vs {}",
                -a * a / 4.0
            );
            let (lo, hi) = c.range(&sys, 0);
            assert!(
                ((0.5 * (hi - lo)).powi(2) - a / 2.0).abs() < 1e-5,
                "radius at alpha = {a}"
            );
            last_alpha = a;
            count += 1;
        }
        assert!(count > 5, "{count} folds");
        assert!(
            (last_alpha - bound).abs() < 0.3,
            "direction {direction}: the curve reached alpha = {last_alpha}"
        );
    }
}

/// A unit circle `x' = x - y - x r^2, y' = x + y - y r^2` (period 2 pi) with
/// a normal plane `zeta' = (a + b M) zeta`, `M = [[x, y], [y, -x]]` (params
/// `a`, `b`). On the circle `M` is a reflection whose axis turns by half a
/// turn per period, so in a frame turning with it `zeta` obeys the constant
/// `K = [[a + b, 1/2], [-1/2, a - b]]` and comes back reversed: the normal
/// multipliers are `-exp(2 pi eig(K))`, `eig(K) = a +- sqrt(b^2 - 1/4)`.
/// Period doubling where `a + sqrt(b^2 - 1/4) = 0` (`b = 1/sqrt 2` at
/// `a = -1/2`); for `b < 1/2` a complex pair of modulus `exp(2 pi a)`: a
/// torus bifurcation at `a = 0`.
struct TwistedBand;
impl VectorField for TwistedBand {
    fn dim(&self) -> usize {
        4
    }
    fn n_params(&self) -> usize {
        2
    }
    fn rhs<D: Scalar>(&self, x: &[D], p: &[D], out: &mut [D]) {
        let r2 = x[0] * x[0] + x[1] * x[1];
        out[0] = x[0] - x[1] - x[0] * r2;
        out[1] = x[0] + x[1] - x[1] * r2;
        out[2] = (p[0] + p[1] * x[0]) * x[2] + p[1] * x[1] * x[3];
        out[3] = p[1] * x[1] * x[2] + (p[0] - p[1] * x[0]) * x[3];
    }
}

/// The unit circle of the twisted band, exact, on 20 intervals, at parameters `p`.
fn twisted_band_cycle(p: [f64; 2]) -> Cycle {
    let mesh = Mesh::uniform(20, 4, Default::default());
    let mut u = Vec::new();
    for i in 0..mesh.ntst() {
        for l in 0..mesh.degree {
            let t = 2.0 * std::f64::consts::PI * mesh.node_time(i, l);
            u.extend([t.cos(), t.sin(), 0.0, 0.0]);
        }
    }
    Cycle {
        mesh,
        u,
        period: 2.0 * std::f64::consts::PI,
        p: p.to_vec(),
        n: 4,
    }
}

fn twisted_band_branch(p: [f64; 2], k: usize, p_max: f64) -> Vec<CyclePoint> {
    let guess = twisted_band_cycle(p);
    let settings = CycleSettings {
        step: StepControl {
            ds: 1e-2,
            ds_max: 0.05,
            ..CycleSettings::default().step
        },
        p_max,
        max_steps: 100,
        ..Default::default()
    };
    CycleBranch::from_cycle(&TwistedBand, guess, k, None, settings)
        .unwrap()
        .map(Result::unwrap)
        .collect()
}

#[test]
fn period_doubling_and_torus_bifurcations_are_located() {
    let pd: Vec<_> = twisted_band_branch([-0.5, 0.6], 1, 0.8)
        .into_iter()
        .filter_map(|pt| pt.event(CycleEvent::PeriodDoubling).cloned())
        .collect();
    assert_eq!(pd.len(), 1, "one period doubling");
    let b = pd[0].cycle.p[1];
    assert!((b - 0.5f64.sqrt()).abs() < 1e-10, "PD at b = {b}");
    assert!(pd[0].multipliers.iter().any(|m| (m + 1.0).norm() < 1e-8));
    let ns: Vec<_> = twisted_band_branch([-0.2, 0.3], 0, 0.2)
        .into_iter()
        .filter_map(|pt| pt.event(CycleEvent::Torus).cloned())
        .collect();
    assert_eq!(ns.len(), 1, "one torus bifurcation");
    let a = ns[0].cycle.p[0];
    assert!(a.abs() < 1e-10, "NS at a = {a}");
    // The critical pair: -e^{+- 2 pi i 0.4} on the unit circle.
    let angle = 2.0 * std::f64::consts::PI * (0.25f64 - 0.09).sqrt();
    let expected = -Complex64::from_polar(1.0, angle);
    assert!(ns[0]
        .multipliers
        .iter()
        .any(|m| (m - expected).norm() < 1e-8 || (m - expected.conj()).norm() < 1e-8));
}

#[test]
fn undecidable_stability_is_a_typed_error() {
    // On the twisted band with a = 0 and b < 1/2 a complex pair of multipliers
    // lies on the unit circle for every b. Once the trivial multiplier's error
    // exceeds `trivial_limit` (here: any error at all) and another multiplier
    // is within ten times that error of the circle, stability cannot be
    // decided, and the branch says so instead of guessing.
    let guess = twisted_band_cycle([0.0, 0.3]);
    let settings = CycleSettings {
        step: StepControl {
            ds: 1e-2,
            ..CycleSettings::default().step
        },
        max_steps: 5,
        floquet: FloquetPolicy {
            trivial_limit: Some(0.0),
            trivial_tol: Some(1.0),
            ..Default::default()
        },
        ..Default::default()
    };
    let outcome: Result<Vec<_>, _> =
        CycleBranch::from_cycle(&TwistedBand, guess, 1, None, settings)
            .unwrap()
            .collect();
    let err = outcome.expect_err("stability is undecidable").to_string();
    assert!(err.contains("can no longer decide its stability"), "{err}");
}

/// Largest `x` on the van der Pol cycle at `mu = 1`, by shooting in 30-digit
/// arithmetic (mpmath's Taylor integrator `odefun`, Newton on the return map
/// to the section `y = 0`): 2.0086198608748431365.
const VDP_AMPLITUDE: f64 = 2.008_619_860_874_843;

#[test]
fn extremes_converge_at_the_order_of_the_mesh_points() {
    // Read off the collocation polynomials, the largest x of the van der Pol
    // cycle converges at O(h^(m+1)) only (and irregularly: it depends on
    // where in its interval the extreme falls); `Cycle::range` (one
    // collocation step from the mesh point before the extreme) at the order
    // of the mesh points, 2m with Gauss and 2m - 1 with Radau points.
    for (points, order) in [
        (CollocationPoints::Gauss, 8.0),
        (CollocationPoints::Radau, 7.0),
    ] {
        let errors = |n: usize| {
            let c = vdp_cycle(n, 4, points).cycle;
            let (lo, hi) = c.range(&VanDerPol, 0);
            let poly = c
                .samples(64)
                .iter()
                .map(|(_, x)| x[0])
                .fold(f64::NEG_INFINITY, f64::max);
            (
                (hi - VDP_AMPLITUDE).abs().max((lo + VDP_AMPLITUDE).abs()),
                (poly - VDP_AMPLITUDE).abs(),
            )
        };
        let ((r40, _), (r80, p80)) = (errors(40), errors(80));
        let observed = (r40 / r80).log2();
        assert!(
            (observed - order).abs() < 0.6,
            "{points:?}: observed order {observed} ({r40:e}, {r80:e})"
        );
        assert!(
            p80 > 10.0 * r80,
            "{points:?}: polynomial {p80:e}, range {r80:e}"
        );
    }
}

#[test]
fn a_step_over_a_whole_interval_is_the_orbits_own() {
    // `Cycle::step_from_node` solves the collocation equations of one
    // interval from its first mesh point: over the whole interval they are
    // the orbit's, and the step ends on the next mesh point.
    for points in [CollocationPoints::Gauss, CollocationPoints::Radau] {
        let c = vdp_cycle(30, 4, points).cycle;
        for i in [0, 7, 29] {
            let h = c.mesh.t[i + 1] - c.mesh.t[i];
            let end = c.step_from_node(&VanDerPol, i, h);
            let next = c.node(c.mesh.node(i + 1, 0));
            for j in 0..2 {
                assert!(
                    (end[j] - next[j]).abs() < 1e-13,
                    "{points:?}, interval {i}: {} vs {}",
                    end[j],
                    next[j]
                );
            }
        }
    }
}

/// [`StuartLandau`] in an implicit form `rho(x, p) x' = g(x, p)` with
/// state- and parameter-dependent scales (`g = rho f`): the same orbits,
/// so the same closed forms.
struct ImplicitStuartLandau(StuartLandau);
impl ImplicitStuartLandau {
    fn scales<D: Scalar>(x: &[D], p: &[D]) -> [D; 2] {
        [
            (x[0] * x[0] + 1.0) * (p[0] + 1.0),
            (x[1] * 0.5 + 2.0).exp() * 1e-3,
        ]
    }
}
impl VectorField for ImplicitStuartLandau {
    fn dim(&self) -> usize {
        2
    }
    fn n_params(&self) -> usize {
        1
    }
    fn rhs<D: Scalar>(&self, x: &[D], p: &[D], out: &mut [D]) {
        self.0.rhs(x, p, out)
    }
    fn has_implicit_form(&self) -> bool {
        true
    }
    fn implicit_rhs<D: Scalar>(&self, x: &[D], p: &[D], rho: &mut [D], g: &mut [D]) {
        self.0.rhs(x, p, g);
        let s = Self::scales(x, p);
        rho[..2].copy_from_slice(&s);
        for (g, s) in g.iter_mut().zip(s) {
            *g *= s;
        }
    }
}

#[test]
fn implicit_form_gives_the_closed_form_cycles_and_multipliers() {
    // Liouville's formula from the implicit form's trace of D_x f, and the
    // Floquet pencil of the row-scaled equations.
    stuart_landau_branch_is_the_closed_form(&ImplicitStuartLandau(StuartLandau { w: 2.0, g: 0.5 }));
}

/// An orbit off the solution of the Stuart–Landau field on 6 intervals of
/// degree 3 (an ellipse with a third harmonic, period 3.1, parameter
/// 0.4): where every term of the collocation equations counts.
fn perturbed_orbit(points: CollocationPoints) -> Cycle {
    let mesh = Mesh::uniform(6, 3, points);
    let u: Vec<f64> = (0..mesh.n_nodes())
        .flat_map(|g| {
            let a = 2.0 * std::f64::consts::PI * mesh.node_time(g / 3, g % 3);
            [0.7 * a.cos() + 0.05 * (3.0 * a).sin(), 0.6 * a.sin()]
        })
        .collect();
    Cycle {
        mesh,
        u,
        period: 3.1,
        p: vec![0.4],
        n: 2,
    }
}

#[test]
fn implicit_form_jacobian_matches_central_differences_of_its_residual() {
    // Off the solution (a perturbed orbit) every term of the Jacobian counts,
    // also d rho / dx times x' and d rho / dp.
    let sys = ImplicitStuartLandau(StuartLandau { w: 2.0, g: 0.5 });
    let c = perturbed_orbit(CollocationPoints::Gauss);
    let coll = Collocation::new(&sys, &c, 0);
    let z0 = coll.unknowns(&c);
    let lin = coll.linearize(&z0);
    let (n, m) = (2, 3);
    let nn = z0.len() - 2;
    for i in [0, 4] {
        let columns: Vec<(usize, usize)> = (0..=m)
            .flat_map(|l| {
                let g = coll.mesh.node(i, l);
                (0..n).map(move |cc| (l * n + cc, g * n + cc))
            })
            .chain([((m + 1) * n, nn), ((m + 1) * n + 1, nn + 1)])
            .collect();
        for (col, j) in columns {
            let h = 1e-6 * z0[j].abs().max(1.0);
            let at = |d: f64| {
                let mut z = z0.clone();
                z[j] += d;
                coll.linearize(&z).residual[i * m * n..(i + 1) * m * n].to_vec()
            };
            let (up, down) = (at(h), at(-h));
            for r in 0..m * n {
                let fd = (up[r] - down[r]) / (2.0 * h);
                let exact = lin.blocks.block(i)[(r, col)];
                assert!(
                    (fd - exact).abs() <= 1e-7 * (1.0 + exact.abs()),
                    "interval {i} row {r} column {col}: {exact} vs differences {fd}"
                );
            }
        }
    }
}

#[test]
fn the_residual_alone_is_the_linearizations() {
    // `Collocation::residual_into` (what chord iterations evaluate) against
    // the residual `linearize` writes, off the solution, in the explicit and
    // the implicit form: the same values, summed in the same order.
    let c = perturbed_orbit(CollocationPoints::Radau);
    let explicit = StuartLandau { w: 2.0, g: 0.5 };
    let implicit = ImplicitStuartLandau(StuartLandau { w: 2.0, g: 0.5 });
    let compare = |coll_residual: Vec<f64>, lin_residual: &[f64], form: &str| {
        assert_eq!(coll_residual.len(), lin_residual.len());
        for (i, (a, b)) in coll_residual.iter().zip(lin_residual).enumerate() {
            assert!(
                (a - b).abs() <= 1e-15 * (1.0 + b.abs()),
                "{form}, residual {i}: {a:e} vs {b:e}"
            );
        }
    };
    let coll = Collocation::new(&explicit, &c, 0);
    let z = coll.unknowns(&c);
    let mut residual = Vec::new();
    coll.residual_into(&z, &mut residual);
    compare(residual, &coll.linearize(&z).residual, "explicit");
    let coll = Collocation::new(&implicit, &c, 0);
    let mut residual = Vec::new();
    coll.residual_into(&z, &mut residual);
    compare(residual, &coll.linearize(&z).residual, "implicit");
}

#[test]
fn the_shapes_with_constant_sizes_are_the_code_for_any_size() {
    // Degree 4 and `n = 2` (Stuart–Landau, explicit and implicit form) are
    // compiled with their sizes constant: the linearization and the
    // residual alone equal those of the code for any size, to the bit.
    let mesh = Mesh::uniform(7, 4, CollocationPoints::Radau);
    let u: Vec<f64> = (0..mesh.n_nodes())
        .flat_map(|g| {
            let a = 2.0 * std::f64::consts::PI * mesh.node_time(g / 4, g % 4);
            [0.7 * a.cos() + 0.05 * (3.0 * a).sin(), 0.6 * a.sin()]
        })
        .collect();
    let c = Cycle {
        mesh,
        u,
        period: 3.1,
        p: vec![0.4],
        n: 2,
    };
    let explicit = StuartLandau { w: 2.0, g: 0.5 };
    let implicit = ImplicitStuartLandau(StuartLandau { w: 2.0, g: 0.5 });
    fn check<S: VectorField>(coll: &Collocation<'_, S>, c: &Cycle, form: &str) {
        let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        let z = coll.unknowns(c);
        let (mut lin, mut any) = (Linearization::default(), Linearization::default());
        coll.linearize_into(&z, &mut lin);
        coll.linearize_shaped::<0, 0>(&z, &mut any);
        let blocks = |l: &Linearization| l.blocks.slices().flatten().copied().collect::<Vec<_>>();
        assert_eq!(bits(&blocks(&lin)), bits(&blocks(&any)), "{form}: blocks");
        assert_eq!(bits(&lin.residual), bits(&any.residual), "{form}: residual");
        assert_eq!(bits(&lin.phase), bits(&any.phase), "{form}: phase row");
        assert_eq!(lin.term_scale.to_bits(), any.term_scale.to_bits(), "{form}");
        assert_eq!(
            lin.trace_integral.to_bits(),
            any.trace_integral.to_bits(),
            "{form}"
        );
        let (mut r, mut r_any) = (Vec::new(), Vec::new());
        coll.residual_into(&z, &mut r);
        coll.residual_shaped::<0, 0>(&z, &mut r_any);
        assert_eq!(bits(&r), bits(&r_any), "{form}: residual alone");
    }
    check(&Collocation::new(&explicit, &c, 0), &c, "explicit");
    check(&Collocation::new(&implicit, &c, 0), &c, "implicit");
}

#[test]
fn an_orbit_that_solves_its_system_is_recognised_and_no_other() {
    // A cycle restarts as it was only if it already solves its system:
    // `solves_bordered` says no for an orbit off the solution and for one
    // holding a NaN, and yes for the orbit Newton's method converged to.
    let sys = StuartLandau { w: 2.0, g: 0.5 };
    let c = perturbed_orbit(CollocationPoints::Radau);
    let coll = Collocation::new(&sys, &c, 0);
    let z0 = coll.unknowns(&c);
    let row = unit_row(z0.len(), z0.len() - 1);
    let settings = NewtonSettings {
        step_tol: 1e-10,
        residual_tol: 1e-10,
        max_iter: 20,
    };
    assert!(!solves_bordered(&coll, &z0, &settings, &row, &z0));
    let mut z = z0.clone();
    newton_bordered(&coll, &mut z, &settings, &row, &z0).unwrap();
    assert!(solves_bordered(&coll, &z, &settings, &row, &z0));
    let mut broken = z.clone();
    broken[3] = f64::NAN;
    assert!(!solves_bordered(&coll, &broken, &settings, &row, &z0));
}

// Newton's method on the collocation system allocates nothing per
// iteration once its storage is warm: a counting global allocator (this
// test thread's allocations only) compares a run of 2 iterations with one
// of 6 from the same start.

thread_local! {
    static ALLOCATIONS: Cell<usize> = const { Cell::new(0) };
}

struct Counting;

fn count() {
    // `try_with`: nothing to count while the thread is being torn down.
    let _ = ALLOCATIONS.try_with(|c| c.set(c.get() + 1));
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count();
        unsafe { System.alloc(layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        count();
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count();
        unsafe { System.realloc(ptr, layout, new_size) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

fn allocations() -> usize {
    ALLOCATIONS.with(|c| c.get())
}

#[test]
fn a_newton_iteration_on_the_collocation_system_allocates_nothing() {
    let sys = StuartLandau { w: 2.0, g: 0.5 };
    // Off the cycle at beta = 1 (radius 1.05, period 2 % long), so that
    // every iteration takes a step; 20 intervals: the intervals run in turn.
    let mesh = Mesh::uniform(20, 4, Default::default());
    let mut u = Vec::new();
    for i in 0..mesh.ntst() {
        for l in 0..mesh.degree {
            let t = 2.0 * std::f64::consts::PI * mesh.node_time(i, l);
            u.extend([1.05 * t.cos(), 1.05 * t.sin()]);
        }
    }
    let cycle = Cycle {
        mesh,
        u,
        period: 1.02 * 2.0 * std::f64::consts::PI / 2.5,
        p: vec![1.0],
        n: 2,
    };
    let coll = Collocation::new(&sys, &cycle, 0);
    let z0 = coll.unknowns(&cycle);
    let row = unit_row(z0.len(), z0.len() - 1);
    // Tolerances nobody meets: the runs end at the iteration limit.
    let run = |max_iter: usize| {
        let settings = NewtonSettings {
            step_tol: 0.0,
            residual_tol: 0.0,
            max_iter,
        };
        let mut z = z0.clone();
        let before = allocations();
        let result = newton_bordered(&coll, &mut z, &settings, &row, &z0);
        let used = allocations() - before;
        match result {
            Err(ContinuationError::Newton {
                iterations, reason, ..
            }) => {
                assert_eq!(reason, NewtonFailure::MaxIterations);
                assert_eq!(iterations, max_iter);
            }
            other => panic!("expected the iteration limit, got {other:?}"),
        }
        used
    };
    let (short, long) = (run(2), run(6));
    assert!(short > 0, "the first iterations allocate the storage");
    assert_eq!(
        long,
        short,
        "iterations 3 to 6 allocated {} times",
        long as isize - short as isize
    );
}

/// Cycle branches of the Bautin normal form: 20 intervals, `p` in
/// `[-1, 0.5]`, first step `1e-2`, at most `max_steps` steps.
fn bautin_settings(max_steps: usize) -> CycleSettings {
    CycleSettings {
        mesh: Discretization {
            ntst: 20,
            ..Default::default()
        },
        p_min: -1.0,
        p_max: 0.5,
        step: StepControl {
            ds: 1e-2,
            ..CycleSettings::default().step
        },
        max_steps,
        ..Default::default()
    }
}

#[test]
fn samples_are_the_orbit_where_the_mesh_locates_them_to_the_bit() {
    // Uneven intervals, down to a few ulps of their mesh point, where the
    // sample's time may round onto the next mesh point.
    let base = Mesh::uniform(1, 4, CollocationPoints::Radau);
    let mut t = vec![0.0, 0.1, 0.1 + 1e-9, 0.3];
    t.push(0.3 + 4.0 * f64::EPSILON);
    t.extend([0.55, 0.9, 1.0]);
    let mesh = base.on(t);
    let n = 3;
    let u: Vec<f64> = (0..mesh.n_nodes() * n)
        .map(|k| (0.37 * k as f64).sin())
        .collect();
    let cycle = Cycle {
        mesh,
        u,
        period: 1.0,
        p: vec![],
        n,
    };
    let mut count = 0;
    cycle.each_sample(8, |tau, x| {
        let at = cycle.state_at(tau);
        assert!(
            x.iter().zip(&at).all(|(a, b)| a.to_bits() == b.to_bits()),
            "tau = {tau}: {x:?} against {at:?}"
        );
        count += 1;
    });
    assert_eq!(count, 7 * 8 + 1);
}
