//! The Radau IIA (order 5) integrator against exact solutions, literature
//! values and its own convergence behaviour.

use continuation::integrate::{
    EventDirection, EventFunction, IntegrateError, Outcome, Output, Radau5, Settings,
};
use continuation::{Scalar, VectorField};
use std::f64::consts::PI;
use std::ops::ControlFlow;

fn tol(rtol: f64, atol: f64) -> Settings {
    Settings {
        rtol,
        atol,
        ..Settings::default()
    }
}

/// `x' = A x` with `A = [[p0, p1], [p2, p3]]`.
struct Linear;
impl VectorField for Linear {
    fn dim(&self) -> usize {
        2
    }
    fn n_params(&self) -> usize {
        4
    }
    fn rhs<D: Scalar>(&self, x: &[D], p: &[D], out: &mut [D]) {
        out[0] = p[0] * x[0] + p[1] * x[1];
        out[1] = p[2] * x[0] + p[3] * x[1];
    }
}

#[test]
fn stiff_linear_system_matches_the_matrix_exponential() {
    // A = V diag(-1, -1e4) V^-1 with a non-orthogonal V = [[1, 1], [2, -1]].
    let (l1, l2) = (-1.0, -1e4);
    let v = [[1.0, 1.0], [2.0, -1.0]];
    let det = v[0][0] * v[1][1] - v[0][1] * v[1][0];
    let vi = [
        [v[1][1] / det, -v[0][1] / det],
        [-v[1][0] / det, v[0][0] / det],
    ];
    let a = |i: usize, j: usize| v[i][0] * l1 * vi[0][j] + v[i][1] * l2 * vi[1][j];
    let p = [a(0, 0), a(0, 1), a(1, 0), a(1, 1)];
    let x0 = [1.0, 0.5];
    let exact = |t: f64| -> [f64; 2] {
        // x(t) = V exp(D t) V^-1 x0.
        let c = [
            vi[0][0] * x0[0] + vi[0][1] * x0[1],
            vi[1][0] * x0[0] + vi[1][1] * x0[1],
        ];
        let e = [(l1 * t).exp() * c[0], (l2 * t).exp() * c[1]];
        [
            v[0][0] * e[0] + v[0][1] * e[1],
            v[1][0] * e[0] + v[1][1] * e[1],
        ]
    };
    let sol = Radau5::new(&Linear, &p, tol(1e-12, 1e-14))
        .solve(0.0, &x0, 1.0, Output::Grid(vec![1e-4, 1e-3, 0.5, 1.0]))
        .into_result()
        .unwrap();
    let xe = exact(1.0);
    let rel = (0..2)
        .map(|i| ((sol.x_final[i] - xe[i]) / xe[i]).abs())
        .fold(0.0, f64::max);
    eprintln!("linear: rel err at t=1 {rel:.2e}, stats {:?}", sol.stats);
    assert!(rel < 1e-10, "relative error {rel:e}");
    assert_eq!(sol.t_final, 1.0);
    assert_eq!(sol.x.last().unwrap(), &sol.x_final);
    // Inside the fast transient the dense output is still accurate.
    for (t, x) in sol.t.iter().zip(&sol.x) {
        let xe = exact(*t);
        for i in 0..2 {
            let err = (x[i] - xe[i]).abs() / (1.0 + xe[i].abs());
            assert!(err < 1e-9, "t = {t}, component {i}: {err:e}");
        }
    }
}

/// Van der Pol `x'' - mu (1 - x^2) x' + x = 0` as a first-order system.
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
        out[1] = p[0] * ((-(x[0] * x[0]) + 1.0) * x[1]) - x[0];
    }
}

#[test]
fn van_der_pol_mu_1000_converges_with_the_tolerance() {
    let p = [1000.0];
    let x0 = [2.0, 0.0];
    // One relaxation jump (near t = 807) and into the next slow phase.
    let t_end = 1200.0;
    let run = |rtol: f64| {
        Radau5::new(&VanDerPol, &p, tol(rtol, rtol))
            .solve(0.0, &x0, t_end, Output::Final)
            .into_result()
            .unwrap()
    };
    let reference = run(1e-13);
    eprintln!(
        "vdp reference {:?} stats {:?}",
        reference.x_final, reference.stats
    );
    assert!(reference.x_final[0] < -1.0, "after the jump x < -1");
    let mut errors = Vec::new();
    for k in 5..=8 {
        let rtol = 10f64.powi(-k);
        let sol = run(rtol);
        let err = (0..2)
            .map(|i| {
                (sol.x_final[i] - reference.x_final[i]).abs() / (1.0 + reference.x_final[i].abs())
            })
            .fold(0.0, f64::max);
        eprintln!(
            "vdp rtol {rtol:.0e}: err {err:.2e} err/rtol {:.2} accepted {} rejected {}",
            err / rtol,
            sol.stats.accepted,
            sol.stats.rejected
        );
        errors.push((rtol, err));
    }
    // Error roughly proportional to rtol: every decade helps, three decades
    // give at least a factor 100, and the error stays within a modest factor
    // of the request.
    for w in errors.windows(2) {
        assert!(
            w[1].1 < w[0].1,
            "no decrease from {:e} to {:e}",
            w[0].0,
            w[1].0
        );
    }
    let (first, last) = (errors[0], errors[3]);
    assert!(first.1 / last.1 > 100.0, "3 decades: {first:?} -> {last:?}");
    for &(rtol, err) in &errors {
        assert!(err < 3.0 * rtol, "rtol {rtol:e}: error {err:e}");
    }
}

/// `x'' = -x`.
struct Harmonic;
impl VectorField for Harmonic {
    fn dim(&self) -> usize {
        2
    }
    fn n_params(&self) -> usize {
        0
    }
    fn rhs<D: Scalar>(&self, x: &[D], _p: &[D], out: &mut [D]) {
        out[0] = x[1];
        out[1] = -x[0];
    }
}

#[test]
fn harmonic_oscillator_events_and_dense_output() {
    let mut dense_err = 0.0f64;
    let mut samples = 0;
    let mut seed = 0x2545_f491_4f6c_dd1du64;
    let mut uniform = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut solver = Radau5::new(&Harmonic, &[], tol(1e-12, 1e-12))
        .with_event(EventFunction::new(|_, x: &[f64]| x[0]).direction(EventDirection::Rising))
        .with_event(EventFunction::new(|_, x: &[f64]| x[1]).direction(EventDirection::Any));
    let mut xs = [0.0; 2];
    let sol = solver.solve_with(0.0, &[1.0, 0.0], 20.0, Output::Steps, |step| {
        for _ in 0..5 {
            let t = step.t_prev + uniform() * (step.t - step.t_prev);
            step.eval(t, &mut xs);
            dense_err = dense_err
                .max((xs[0] - t.cos()).abs())
                .max((xs[1] + t.sin()).abs());
            samples += 1;
        }
        ControlFlow::Continue(())
    });
    assert_eq!(sol.outcome, Outcome::ReachedEnd);
    let rising: Vec<f64> = sol
        .events
        .iter()
        .filter(|e| e.index == 0)
        .map(|e| e.t)
        .collect();
    assert_eq!(rising.len(), 3, "{rising:?}");
    assert!(sol.events.iter().filter(|e| e.index == 0).all(|e| e.rising));
    let mut period_err = 0.0f64;
    for (k, w) in rising.windows(2).enumerate() {
        period_err = period_err.max((w[1] - w[0] - 2.0 * PI).abs());
        assert!(
            (w[0] - (1.5 + 2.0 * k as f64) * PI).abs() < 1e-10,
            "{}",
            w[0]
        );
    }
    // Zeros of x' = -sin t at k pi, k = 1..6, alternating direction.
    let turns: Vec<_> = sol.events.iter().filter(|e| e.index == 1).collect();
    assert_eq!(turns.len(), 6);
    for (k, e) in turns.iter().enumerate() {
        assert!((e.t - (k + 1) as f64 * PI).abs() < 1e-10);
        assert_eq!(e.rising, k % 2 == 0, "x' = -sin t rises through 0 at pi");
        assert!((e.x[0] - e.t.cos()).abs() < 1e-9);
    }
    assert!(
        sol.events.windows(2).all(|w| w[0].t <= w[1].t),
        "time order"
    );
    eprintln!(
        "harmonic: period err {period_err:.2e}, dense err {dense_err:.2e} over {samples} points, \
         {} steps",
        sol.stats.accepted
    );
    assert!(period_err < 1e-10, "period error {period_err:e}");
    assert!(dense_err < 1e-9, "dense output error {dense_err:e}");
}

#[test]
fn terminal_event_stops_the_integration_on_the_crossing() {
    let mut solver = Radau5::new(&Harmonic, &[], tol(1e-12, 1e-12)).with_event(
        EventFunction::new(|_, x: &[f64]| x[0] - 0.5)
            .direction(EventDirection::Falling)
            .terminal(true),
    );
    let grid: Vec<f64> = (1..=10).map(|k| k as f64 * 0.5).collect();
    let sol = solver.solve(0.0, &[1.0, 0.0], 5.0, Output::Grid(grid));
    assert_eq!(sol.outcome, Outcome::TerminalEvent { index: 0 });
    // cos t = 1/2 first at t = pi/3.
    eprintln!("terminal event: t err {:.2e}", sol.t_final - PI / 3.0);
    assert!((sol.t_final - PI / 3.0).abs() < 1e-9, "{}", sol.t_final);
    assert!((sol.x_final[0] - 0.5).abs() < 1e-9);
    assert_eq!(sol.events.len(), 1);
    assert_eq!(sol.t, vec![0.5, 1.0], "grid stops at the event");
    // Backward integration from the event time returns to the start.
    let back = Radau5::new(&Harmonic, &[], tol(1e-10, 1e-10))
        .solve(sol.t_final, &sol.x_final, 0.0, Output::Final)
        .into_result()
        .unwrap();
    assert!((back.x_final[0] - 1.0).abs() < 1e-8 && back.x_final[1].abs() < 1e-8);
}

/// Robertson's chemical kinetics (Hairer & Wanner II, §IV.1, eq. (1.4)).
struct Robertson;
impl VectorField for Robertson {
    fn dim(&self) -> usize {
        3
    }
    fn n_params(&self) -> usize {
        0
    }
    fn rhs<D: Scalar>(&self, y: &[D], _p: &[D], out: &mut [D]) {
        let r1 = y[0] * 0.04;
        let r2 = y[1] * y[2] * 1e4;
        let r3 = y[1] * y[1] * 3e7;
        out[0] = r2 - r1;
        out[1] = r1 - r2 - r3;
        out[2] = r3;
    }
}

#[test]
fn robertson_conserves_mass_and_matches_the_literature() {
    let settings = Settings {
        rtol: 1e-10,
        atol_components: Some(vec![1e-14, 1e-18, 1e-14]),
        ..Settings::default()
    };
    let sol = Radau5::new(&Robertson, &[], settings.clone())
        .solve(0.0, &[1.0, 0.0, 0.0], 40.0, Output::Final)
        .into_result()
        .unwrap();
    let y = &sol.x_final;
    // Reference values at t = 40 (Hairer & Wanner's test set).
    let y1_err = (y[0] - 0.715_827_068_7).abs();
    eprintln!(
        "robertson t=40: {y:?}, y1 err {y1_err:.2e}, stats {:?}",
        sol.stats
    );
    assert!(y1_err < 1e-9, "y1 error {y1_err:e}");
    assert!((y[1] - 9.185_535e-6).abs() < 1e-12, "y2 = {:e}", y[1]);
    let long = Radau5::new(&Robertson, &[], settings)
        .solve(0.0, &[1.0, 0.0, 0.0], 1e5, Output::Steps)
        .into_result()
        .unwrap();
    let mass_err = long
        .x
        .iter()
        .map(|y| (y[0] + y[1] + y[2] - 1.0).abs())
        .fold(0.0, f64::max);
    eprintln!(
        "robertson to 1e5: mass err {mass_err:.2e}, final {:?}, {} steps",
        long.x_final, long.stats.accepted
    );
    assert!(mass_err < 1e-10, "mass error {mass_err:e}");
    assert!(long.x.iter().all(|y| y.iter().all(|v| *v > -1e-12)));
}

#[test]
fn bad_input_is_an_error_not_a_panic() {
    let sol = Radau5::new(&Harmonic, &[], Settings::default()).solve(
        0.0,
        &[f64::NAN, 0.0],
        1.0,
        Output::Steps,
    );
    match &sol.outcome {
        Outcome::Failed(IntegrateError::NonFiniteState { index: 0, t, .. }) => {
            assert_eq!(*t, 0.0)
        }
        other => panic!("{other:?}"),
    }
    assert!(sol.t.is_empty());
    let err = sol.into_result().unwrap_err();
    assert!(err.to_string().contains("x[0] is not a number"), "{err}");

    let wrong_dim = Radau5::new(&Harmonic, &[], Settings::default())
        .solve(0.0, &[1.0], 1.0, Output::Steps)
        .into_result();
    assert!(matches!(
        wrong_dim,
        Err(IntegrateError::InvalidInput { .. })
    ));
    let bad_tol = Radau5::new(&Harmonic, &[], tol(-1.0, 1e-6))
        .solve(0.0, &[1.0, 0.0], 1.0, Output::Steps)
        .into_result();
    assert!(matches!(bad_tol, Err(IntegrateError::InvalidInput { .. })));
    let bad_grid = Radau5::new(&Harmonic, &[], Settings::default())
        .solve(0.0, &[1.0, 0.0], 1.0, Output::Grid(vec![0.5, 0.2]))
        .into_result();
    assert!(matches!(bad_grid, Err(IntegrateError::InvalidInput { .. })));
}

/// `x' = x^2`: blows up at `t = 1/x0`.
struct BlowUp;
impl VectorField for BlowUp {
    fn dim(&self) -> usize {
        1
    }
    fn n_params(&self) -> usize {
        0
    }
    fn rhs<D: Scalar>(&self, x: &[D], _p: &[D], out: &mut [D]) {
        out[0] = x[0] * x[0];
    }
}

#[test]
fn finite_time_blow_up_is_reported_with_t_and_h() {
    let sol = Radau5::new(&BlowUp, &[], Settings::default()).solve(0.0, &[1.0], 2.0, Output::Final);
    let Outcome::Failed(err) = &sol.outcome else {
        panic!("expected a failure, got {:?}", sol.outcome);
    };
    eprintln!("blow-up: {err}");
    assert!((sol.t_final - 1.0).abs() < 1e-4, "{}", sol.t_final);
    assert!(sol.x_final[0] > 1e6, "{}", sol.x_final[0]);
    let msg = err.to_string();
    assert!(msg.contains("t = 1.0000") && msg.contains("h = "), "{msg}");
}

#[test]
fn interior_samples_catch_two_zeros_in_one_step() {
    // g has two zeros 1e-3 apart; steps are much longer than that.
    let count = |samples: usize| {
        let settings = Settings {
            event_samples: samples,
            ..tol(1e-6, 1e-6)
        };
        let mut solver = Radau5::new(&Harmonic, &[], settings)
            .with_event(EventFunction::new(|t, _: &[f64]| (t - 1.0) * (t - 1.001)));
        let sol = solver.solve(0.0, &[1.0, 0.0], 2.0, Output::Final);
        assert_eq!(sol.outcome, Outcome::ReachedEnd);
        assert!(sol.stats.accepted < 100, "steps much longer than 1e-3");
        sol.events
    };
    assert!(count(1).is_empty(), "both zeros inside one step cancel");
    let found = count(1000);
    assert_eq!(found.len(), 2);
    assert!((found[0].t - 1.0).abs() < 1e-12 && !found[0].rising);
    assert!((found[1].t - 1.001).abs() < 1e-12 && found[1].rising);
}

#[test]
fn observer_can_stop_and_steps_are_recorded() {
    let mut seen = 0;
    let sol = Radau5::new(&Harmonic, &[], Settings::default()).solve_with(
        0.0,
        &[1.0, 0.0],
        10.0,
        Output::Steps,
        |step| {
            seen += 1;
            assert!(step.t > step.t_prev && step.h > 0.0);
            if seen == 3 {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        },
    );
    assert_eq!(sol.outcome, Outcome::ObserverStop);
    assert_eq!(sol.t.len(), 4, "the initial point and three steps");
    assert_eq!(sol.t_final, sol.t[3]);
    assert_eq!(&sol.x_final, &sol.x[3]);
    // The shorthand records every step and ends exactly at t_end.
    let full =
        continuation::integrate::solve(&Harmonic, &[], 0.0, &[1.0, 0.0], 10.0, tol(1e-8, 1e-8))
            .into_result()
            .unwrap();
    assert_eq!(*full.t.last().unwrap(), 10.0);
    assert_eq!(full.t.len(), full.stats.accepted + 1);
    assert!((full.x_final[0] - 10f64.cos()).abs() < 1e-6);
}
