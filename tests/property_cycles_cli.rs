//! Property test over the command-line space of `cycles` (issue 22, "No
//! panic anywhere"): requested stiffnesses (`--at-kappa`) at, near and beyond
//! the ends of the range (`kappa_c`, `--kappa-fraction` times `kappa_c`, the
//! top `10 kappa_c`) and near a fold of cycles, repeated and unsorted;
//! tiny and huge `--kappa-fraction`; small `--max-steps`. Each request goes
//! through the job `stickslip cycles` runs ([`stickslip::jobs::cycles`]:
//! the same validation, setup, onset, start and branch; no files), inside
//! `catch_unwind`: a panic fails the case; every cycle delivered must be
//! finite and every typed error must have a message. Whether the requested
//! points are delivered is not asserted here (tests/requested_points.rs
//! does).
//!
//! The requested points are drawn relative to the reference stiffness of the
//! start (`kappa_c`), so they land at the range's ends whatever the scene:
//! an anchor (`kappa_c`, the bottom `fraction kappa_c`, the top `10 kappa_c`,
//! or the fold) times `1 + delta` with `delta` from 0 to a factor 2 either
//! way. The scenes: PMMA as the issue found the panic (inertial, `m = 0.01`,
//! `mu0 = 0.6`), the built-in PMMA scene (quasi-static), and PMMA with
//! `mu2 = -1e-3` (subcritical: the branch turns at a fold of cycles at
//! `kappa = 1.190226 kappa_c`, from `cycles --set mu2=-1e-3`: K/W = 3.27312e4
//! against 2.75e4 1/m at the Hopf point).
//!
//! `the_found_panic_stays_fixed` runs the request of issue 22, item 1, that
//! panicked in nalgebra ("The slice must contain the same number of elements
//! as the matrix": after a mesh refinement the coarse mesh's tangent was used
//! with the finer mesh's Jacobian). The drawn cases (16, fixed seed;
//! `PROPTEST_CASES`, `PROPTEST_RNG_SEED` draw others; `--max-steps` 1 to 6 or
//! 20 to 150) take about 50 s on one core; before that fix the 14th of them
//! found the same panic by itself (shrunk: the subcritical scene,
//! `--kappa-fraction 0.001`, `--at-kappa` twice at 1.1455 `kappa_c`,
//! `--max-steps 70`).
//!
//! ```sh
//! cargo test --release --test property_cycles_cli -- --nocapture
//! ```

use proptest::prelude::*;
use proptest::test_runner::{contextualize_config, Config, RngSeed, TestCaseError, TestRunner};
use std::panic::{catch_unwind, AssertUnwindSafe};
use stickslip::analysis::model_choice::DEFAULT_INERTIA_THRESHOLD;
use stickslip::jobs::cycles::{CyclesRequest, Plan, Quiet};
use stickslip::jobs::SceneSpec;
use stickslip::model::ModelKind;
use stickslip::records::cycle::Asked;

/// The seed unless `PROPTEST_RNG_SEED` says otherwise.
const SEED: u64 = 20_250_122;

/// `--max-steps` of the CLI (its default).
const DEFAULT_MAX_STEPS: usize = 500;

/// The fold of cycles of the subcritical scene, in units of its `kappa_c`.
const FOLD: f64 = 1.190226;

/// The scenes drawn from: `(--set overrides, --model, fold in kappa_c)`.
fn scene(index: usize) -> (Vec<&'static str>, Option<ModelKind>, Option<f64>) {
    match index {
        // Issue 22, item 1.
        0 => (
            vec![
                "A=0.012",
                "B=0.023",
                "mu2=0.00024",
                "m=0.01",
                "nu=1",
                "mu0=0.6",
            ],
            Some(ModelKind::Inertial),
            None,
        ),
        1 => (Vec::new(), None, None),
        _ => (vec!["mu2=-1e-3"], None, Some(FOLD)),
    }
}

/// Where a requested stiffness is drawn near.
#[derive(Clone, Copy, Debug)]
enum Anchor {
    /// The start's reference stiffness (`kappa_c`).
    Onset,
    /// The bottom of the range, `--kappa-fraction` times it.
    Bottom,
    /// The top of the range, 10 times it.
    Top,
    /// The fold of cycles (the subcritical scene; elsewhere `kappa_c`).
    Fold,
    /// None: the factor is the stiffness itself (the found cases).
    Absolute,
}

/// One `stickslip cycles` request on scene `scene`.
#[derive(Clone, Debug)]
struct Request {
    scene: usize,
    kappa_fraction: f64,
    /// `(anchor, factor)`: `--at-kappa` at `factor` times the anchor, in the
    /// order drawn (unsorted); a repeat is drawn as its own entry.
    at: Vec<(Anchor, f64)>,
    max_steps: usize,
}

/// `10^e` with `e` uniform in `[log10 lo, log10 hi]`.
fn log_uniform(lo: f64, hi: f64) -> impl Strategy<Value = f64> {
    (lo.log10()..=hi.log10()).prop_map(|e| 10f64.powf(e))
}

/// `1 + delta`: exactly at the anchor, within rounding, near, or a factor
/// away.
fn factor() -> impl Strategy<Value = f64> {
    prop_oneof![
        Just(1.0),
        Just(1.0 + 4.0 * f64::EPSILON),
        Just(1.0 - 4.0 * f64::EPSILON),
        (-12.0f64..=-3.0).prop_map(|e| 1.0 + 10f64.powf(e)),
        (-12.0f64..=-3.0).prop_map(|e| 1.0 - 10f64.powf(e)),
        0.5f64..=2.0,
    ]
}

fn anchor() -> impl Strategy<Value = Anchor> {
    prop_oneof![
        Just(Anchor::Onset),
        Just(Anchor::Bottom),
        Just(Anchor::Top),
        Just(Anchor::Fold),
    ]
}

fn request() -> impl Strategy<Value = Request> {
    let fraction = prop_oneof![
        log_uniform(1e-6, 1e-3),
        log_uniform(1e-3, 0.999),
        Just(1e-12),
        Just(1.0 - 1e-9),
    ];
    let at = prop::collection::vec((anchor(), factor()), 0..=4).prop_flat_map(|at| {
        // Repeat one of them (or none) at a drawn place.
        let n = at.len();
        (Just(at), 0..=n, 0..=n).prop_map(|(mut at, from, to)| {
            if from < at.len() {
                let repeated = at[from];
                at.insert(to.min(at.len()), repeated);
            }
            at
        })
    });
    (
        0usize..3,
        fraction,
        at,
        prop_oneof![1usize..=6, 20usize..=150],
    )
        .prop_map(|(scene, kappa_fraction, at, max_steps)| Request {
            scene,
            kappa_fraction,
            at,
            max_steps,
        })
}

/// How a request ended (not asserted beyond "no panic, finite, typed").
#[derive(Debug)]
enum Ending {
    /// Refused before computing (bad input, no onset, no start).
    Refused,
    /// Traced: the cycles delivered and whether a leg ended in an error
    /// (read only through `Debug`, in the printed report).
    #[allow(dead_code)]
    Traced { cycles: usize, error: bool },
}

/// Runs `request` as `stickslip cycles` does, up to the branch (no files):
/// `Err` on a panic, a non-finite cycle or an error without a message.
fn cycles(request: &Request) -> Result<Ending, String> {
    let (set, model, fold) = scene(request.scene);
    let spec = SceneSpec {
        scene: "pmma".into(),
        set: set.iter().map(|s| s.to_string()).collect(),
        model,
        inertia_threshold: DEFAULT_INERTIA_THRESHOLD,
    };
    let outcome = catch_unwind(AssertUnwindSafe(|| -> Result<Ending, String> {
        let typed = |e: &dyn std::fmt::Display| {
            let text = e.to_string();
            if text.trim().is_empty() {
                Err("a typed error without a message".to_string())
            } else {
                Ok(Ending::Refused)
            }
        };
        let job = CyclesRequest {
            kappa_fraction: request.kappa_fraction,
            max_steps: request.max_steps,
            ..CyclesRequest::default()
        };
        let mut plan = match Plan::new(&spec, job) {
            Ok(p) => p,
            Err(e) => return typed(&e),
        };
        // The requested points, relative to where the branch starts.
        let kappa_ref = plan.start.reference_kappa();
        let at_kappa: Vec<f64> = request
            .at
            .iter()
            .map(|&(anchor, factor)| {
                factor
                    * match anchor {
                        Anchor::Onset => kappa_ref,
                        Anchor::Bottom => request.kappa_fraction * kappa_ref,
                        Anchor::Top => 10.0 * kappa_ref,
                        Anchor::Fold => fold.unwrap_or(1.0) * kappa_ref,
                        Anchor::Absolute => 1.0,
                    }
            })
            .collect();
        // The CLI refuses a requested point that is not finite and positive.
        if at_kappa.iter().any(|k| !(k.is_finite() && *k > 0.0)) {
            return Ok(Ending::Refused);
        }
        plan.request.at = at_kappa
            .into_iter()
            .map(|value| Asked {
                name: "kappa",
                value,
                unit: "1",
            })
            .collect();
        let result = plan.run(&mut Quiet);
        let error = match &result.failure {
            Some(e) => {
                typed(e).map_err(|why| format!("a leg: {why}"))?;
                true
            }
            None => false,
        };
        for r in &result.records {
            let text = format!("{r:?}");
            let non_finite = text
                .split(|c: char| !c.is_ascii_alphanumeric())
                .any(|w| w.eq_ignore_ascii_case("nan") || w.eq_ignore_ascii_case("inf"));
            if non_finite {
                return Err(format!("a cycle with non-finite numbers: {text}"));
            }
        }
        Ok(Ending::Traced {
            cycles: result.records.len(),
            error,
        })
    }));
    match outcome {
        Ok(result) => result,
        Err(panic) => {
            let what = panic
                .downcast_ref::<String>()
                .cloned()
                .or_else(|| panic.downcast_ref::<&str>().map(|s| s.to_string()))
                .unwrap_or_default();
            Err(format!("panicked: {what}"))
        }
    }
}

/// Drawn requests: no panic, finite cycles, typed errors.
#[test]
fn cycles_requests_never_panic() {
    let config = contextualize_config(Config {
        cases: 16,
        failure_persistence: None,
        rng_seed: RngSeed::Fixed(SEED),
        max_shrink_iters: 64,
        ..Config::default()
    });
    let result = TestRunner::new(config).run(&request(), |r| {
        let t0 = std::time::Instant::now();
        let ending = cycles(&r).map_err(TestCaseError::fail)?;
        eprintln!("{:.2} s {ending:?} {r:?}", t0.elapsed().as_secs_f64());
        Ok(())
    });
    if let Err(e) = result {
        panic!("{e}");
    }
}

/// The requests of issue 22 that panicked, as the CLI makes them.
#[test]
fn the_found_panic_stays_fixed() {
    let requests = [
        // Issue 22, item 1: `cycles --json --model inertial --set A=0.012
        // --set B=0.023 --set mu2=0.00024 --set m=0.01 --set nu=1 --set
        // mu0=0.6 --kappa-fraction 0.023223 --at-kappa 4.68e-4` exited 101,
        // "panicked at nalgebra matrix.rs:1244: The slice must contain the
        // same number of elements as the matrix" (`pin` in
        // continuation/src/periodic/branch/mod.rs: after a mesh refinement
        // the coarse mesh's tangent `t0` went into `tangent_from` with the
        // finer mesh's Jacobian). Also with --kappa-fraction 0.02.
        (0.023223, 4.68e-4),
        (0.02, 4.68e-4),
    ];
    for (kappa_fraction, at) in requests {
        let request = Request {
            scene: 0,
            kappa_fraction,
            at: vec![(Anchor::Absolute, at)],
            max_steps: DEFAULT_MAX_STEPS,
        };
        if let Err(e) = cycles(&request) {
            panic!("--kappa-fraction {kappa_fraction} --at-kappa {at}: {e}");
        }
    }
}
