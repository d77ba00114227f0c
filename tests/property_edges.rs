//! Property test: arbitrary scenes through the analyses behind `hopf`,
//! `diagram`, `cycles` and `simulate`, called as the CLI calls them. Each
//! result holds only finite numbers (every field of the result structs,
//! walked through their `Debug` form; the JSON of the cycles' start), or it
//! is a typed error whose message is not empty and names no `NaN` or `inf`;
//! a panic is a failure. Not asserted: that an answer agrees with Appendix C.
//!
//! # Verdicts, asserted
//! Each case ends in a class ([`Class`]): delivered (the command's whole
//! answer, including "stable for every stiffness", "no Hopf curve in the
//! range" and "no start for cycles"), partial (a curve or branch cut short
//! by a typed error), bad input (refused by the CLI's validation), or a typed
//! error of one of the kinds below, told apart by its message
//! ([`error_kind`]); an error of any other kind fails the case. With the fixed
//! seed and the default number of cases the counts are pinned ([`Floor`]):
//! the delivered cases, and the delivered and partial ones, may not become
//! fewer; the known failures may not become more. Today (`-- --nocapture`
//! prints them):
//!
//! | property | delivered | partial | outside the reach | known failures |
//! |---|---|---|---|---|
//! | hopf (1024) | 1013 (457 Hopf points, 556 stable for every stiffness) | 0 | 0 | 11 (7 Hopf location, 4 real crossing) |
//! | diagram (256) | 167 (41 curves over the range, 126 no curve) | 88 | 0 | 1 (Hopf location) |
//! | cycles (64) | 58 (18 branches, 40 no start) | 1 | 3 (2 quasi-static blow-up, 1 the test's mesh limit) | 2 (periodic orbit Newton) |
//! | simulate (1024) | 837 (820 whole protocol, 17 step limit) | 0 | 86 (61 quasi-static blow-up, 25 initial state) | 101 (inertial integration stopped) |
//!
//! Typed errors accepted as outside the method's reach (each a row of
//! docs/hard-cases.md):
//! * *quasi-static blow-up* (`simulate`, quasi-static model: "could not go
//!   on past"): the massless block has no solution once its spring cannot
//!   follow the slip it asks for; the slip velocity goes to infinity in
//!   finite time, and no integrator can go past it.
//! * *initial state beyond the range* (`simulate`: "leaves the
//!   floating-point range … this is the initial state"): the perturbed
//!   steady state's slip velocity `nu (1 + perturb)^(-mu_phi/A)` is beyond
//!   `f64` (hard-cases: "Quasi-static start beyond the floating-point
//!   range").
//! * *unresolved at the test's mesh limit* (`cycles`: "no longer resolved …
//!   640 mesh intervals, the limit"): the cycles have become too stiff for
//!   the 640 intervals this test allows (the CLI allows 12 800); a limit of
//!   the test, like a step limit (hard-cases: "Stiff cycles").
//! * *degenerate onset, quasi-static Rice–Ruina* (`cycles`: "degenerate Hopf
//!   point" with the plain law and the quasi-static model): `l1` vanishes
//!   identically, a whole family of cycles exists at `kappa_c`, and the
//!   normal form cannot say on which side the branch lies (hard-cases:
//!   "Degenerate Hopf").
//!
//! Known failures of the program, tolerated up to today's count (issue 22
//! lists them; each should become an answer): *degenerate onset* of any other
//! scene (item 2: `cycles` refuses what `hopf` resolves), *Hopf location
//! failed* (Newton of the Hopf system not converging, mostly at
//! `kappa_c >= 1e12`), *real eigenvalue crossing* reported with two unstable
//! eigenvalues at `kappa >= 1e12`, *Floquet pencil singular* and *periodic
//! orbit Newton* (item 7), and *inertial integration stopped* (`simulate` of
//! the inertial model stopped by its step size, where a solution exists).
//!
//! Drawn (log-uniform where a range spans decades): `m` 1e-14 … 1e3, `A` and
//! `B` 1e-6 … 0.1 independently (so `A >= B`, velocity strengthening, about
//! half the time), `nu` 1e-6 … 1e6, `kappa` 1e-9 … 1e3, `mu0` 0 … 1; the
//! friction law: plain Rice–Ruina, with the ln² term (`mu2` -1e-2 … -1e-8 or
//! 1e-8 … 1), or with the cutoff (`theta_c` 1e-9 … 1e9); the model: chosen
//! from the inertia ratio as the CLI does, or forced inertial or quasi-static.
//! The parameters go through `--set` strings and [`SceneSpec::setup`], the
//! CLI's own validation and model choice.
//!
//! Every call is short and every loop has a limit: the diagram over a range of
//! at most a factor e^2 in `nu` with `--max-steps 15`; the cycles with
//! `--max-steps 1..=8` per leg and at most 640 mesh intervals (without a Hopf
//! point the CLI's search for a simulated orbit runs first, within its own
//! limits: seven stiffnesses, each at most 10 000 oscillations); the
//! simulation for a protocol of one to three segments (drive jumps and stops)
//! of at most 40 memory times each, cut at 3000 steps. The wall time of each
//! case is measured only to report it (`-- --nocapture` prints the count of
//! each outcome and the slowest cases), never asserted.
//!
//! Cases per property: hopf 1024, diagram 256, cycles 64, simulate 1024
//! (about 40 s in all on one core of a shared machine, most of it cycles);
//! `PROPTEST_CASES` sets all four. The seed is fixed (CI draws the same scenes
//! every run); `PROPTEST_RNG_SEED` draws others. Failures are not persisted to
//! files: a failing case is printed, shrunk, and the shrunk cases of the
//! failures found so far are checked by `the_cases_found_stay_fixed`.
//!
//! ```sh
//! cargo test --release --test property_edges
//! PROPTEST_CASES=1000 PROPTEST_RNG_SEED=7 cargo test --release --test property_edges -- --nocapture --test-threads=1
//! ```

use continuation::AsIs;
use proptest::prelude::*;
use proptest::test_runner::{contextualize_config, Config, RngSeed, TestCaseError, TestRunner};
use std::cell::RefCell;
use std::fmt::Debug;
use std::ops::ControlFlow;
use std::time::{Duration, Instant};
use stickslip::analysis::cycles::{CycleRecord, CycleRequest};
use stickslip::analysis::diagram::stability_diagram_with;
use stickslip::analysis::hopf::HopfOutcome;
use stickslip::analysis::model_choice::DEFAULT_INERTIA_THRESHOLD;
use stickslip::analysis::orbit_inertia::InertiaWatch;
use stickslip::analysis::simulate::{simulate_with, Segment};
use stickslip::appendix_c;
use stickslip::jobs::cycle_start::Start;
use stickslip::jobs::{onset_with_degeneracy_resolved, SceneSpec, Setup};
use stickslip::model::ModelKind;
use stickslip::params::Params;

/// The seed unless `PROPTEST_RNG_SEED` says otherwise.
const SEED: u64 = 20_240_611;

/// The ageing term of the friction law.
#[derive(Clone, Copy, Debug)]
enum Law {
    RiceRuina,
    Ln2 { mu2: f64 },
    Cutoff { theta_c: f64 },
}

/// One drawn scene: dimensionless parameters of docs/model.md and the model.
#[derive(Clone, Debug)]
struct Case {
    m: f64,
    a: f64,
    b: f64,
    nu: f64,
    kappa: f64,
    mu0: f64,
    law: Law,
    /// `None`: chosen from the inertia ratio (no `--model`).
    model: Option<ModelKind>,
}

impl Case {
    /// The `--set` overrides of this scene (on the built-in PMMA scene).
    fn overrides(&self) -> Vec<String> {
        let mut set = vec![
            format!("m={:e}", self.m),
            format!("A={:e}", self.a),
            format!("B={:e}", self.b),
            format!("nu={:e}", self.nu),
            format!("kappa={:e}", self.kappa),
            format!("mu0={:e}", self.mu0),
        ];
        set.push(match self.law {
            Law::RiceRuina => "mu2=0".into(),
            Law::Ln2 { mu2 } => format!("mu2={mu2:e}"),
            Law::Cutoff { theta_c } => format!("theta_c={theta_c:e}"),
        });
        set
    }

    fn scene_spec(&self) -> SceneSpec {
        SceneSpec {
            scene: "pmma".into(),
            set: self.overrides(),
            model: self.model,
            inertia_threshold: DEFAULT_INERTIA_THRESHOLD,
        }
    }
}

/// `10^e` with `e` uniform in `[log10 lo, log10 hi]`.
fn log_uniform(lo: f64, hi: f64) -> impl Strategy<Value = f64> {
    (lo.log10()..=hi.log10()).prop_map(|e| 10f64.powf(e))
}

fn law() -> impl Strategy<Value = Law> {
    prop_oneof![
        Just(Law::RiceRuina),
        log_uniform(1e-8, 1e-2).prop_map(|x| Law::Ln2 { mu2: -x }),
        log_uniform(1e-8, 1.0).prop_map(|mu2| Law::Ln2 { mu2 }),
        log_uniform(1e-9, 1e9).prop_map(|theta_c| Law::Cutoff { theta_c }),
    ]
}

fn model() -> impl Strategy<Value = Option<ModelKind>> {
    prop_oneof![
        Just(None),
        Just(Some(ModelKind::Inertial)),
        Just(Some(ModelKind::QuasiStatic)),
    ]
}

fn case() -> impl Strategy<Value = Case> {
    (
        log_uniform(1e-14, 1e3),
        log_uniform(1e-6, 0.1),
        log_uniform(1e-6, 0.1),
        log_uniform(1e-6, 1e6),
        log_uniform(1e-9, 1e3),
        0.0..=1.0,
        law(),
        model(),
    )
        .prop_map(|(m, a, b, nu, kappa, mu0, law, model)| Case {
            m,
            a,
            b,
            nu,
            kappa,
            mu0,
            law,
            model,
        })
}

/// The words of `text` that spell a non-finite number (`NaN`, `inf`, as
/// Rust formats them, in either case).
fn non_finite_words(text: &str) -> Vec<&str> {
    text.split(|c: char| !c.is_ascii_alphanumeric())
        .filter(|w| w.eq_ignore_ascii_case("nan") || w.eq_ignore_ascii_case("inf"))
        .collect()
}

/// Every number in `value`'s `Debug` form is finite: a generic walk over
/// every field of a result (nested structs, vectors, options, complex numbers).
fn check_finite(what: &str, value: &impl Debug) -> Result<(), TestCaseError> {
    let text = format!("{value:?}");
    let bad = non_finite_words(&text);
    prop_assert!(
        bad.is_empty(),
        "{what} holds non-finite numbers ({bad:?}): {text}"
    );
    Ok(())
}

/// Every number in a JSON value is finite, and no number is null (serde_json
/// writes a non-finite `f64` as null).
fn check_json(what: &str, value: &serde_json::Value) -> Result<(), TestCaseError> {
    use serde_json::Value;
    match value {
        Value::Null => Err(TestCaseError::fail(format!(
            "{what}: null where a value is expected"
        ))),
        Value::Number(n) => {
            prop_assert!(
                n.as_f64().is_some_and(f64::is_finite),
                "{what}: non-finite number {n}"
            );
            Ok(())
        }
        Value::Array(items) => items
            .iter()
            .enumerate()
            .try_for_each(|(i, v)| check_json(&format!("{what}[{i}]"), v)),
        Value::Object(fields) => fields
            .iter()
            .try_for_each(|(k, v)| check_json(&format!("{what}.{k}"), v)),
        Value::Bool(_) | Value::String(_) => Ok(()),
    }
}

/// How a case ended, counted per property and checked against [`FLOORS`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Class {
    /// The command's answer, whole: an onset, "stable for every stiffness",
    /// a curve over the range, no Hopf curve in the range, a branch of
    /// cycles, no start for cycles, the whole protocol or the step limit.
    Delivered,
    /// Part of the answer, then a typed error (a curve or a branch cut short).
    Partial,
    /// Refused by the CLI's validation of the drawn parameters (exit 2).
    BadInput,
    /// A typed error of a kind accepted as outside the method's reach
    /// (listed in the module documentation).
    OutsideReach,
    /// A typed error of a kind known to be a failure of the program, not of
    /// the case (listed in the module documentation): its count may not rise.
    Known,
}

/// A class and the label counted in the report (for errors, the kind).
type Outcome = (Class, &'static str);

/// What a case ended in, counted in the report (`-- --nocapture`).
type Verdict = Result<Outcome, TestCaseError>;

/// What the scene of a case is, as far as the error kinds depend on it.
#[derive(Clone, Copy)]
struct Context {
    /// The model the CLI chose.
    quasi_static: bool,
    /// The plain Rice–Ruina law (no ln² term, no cutoff).
    rice_ruina: bool,
}

impl Context {
    fn of(setup: &Setup) -> Self {
        Context {
            quasi_static: setup.choice.kind == ModelKind::QuasiStatic,
            rice_ruina: setup.params.mu2 == 0.0 && setup.params.theta_c.is_none(),
        }
    }
}

/// The kind of a typed error from its message (the analyses' errors are
/// messages; the phrases are theirs), and whether it is accepted as outside
/// the method's reach (see the module documentation). An error of no listed
/// kind fails the case.
fn error_kind(what: &str, text: &str, at: Context) -> Verdict {
    let has = |phrase: &str| text.contains(phrase);
    let outcome = if has("could not go on past") && at.quasi_static {
        (Class::OutsideReach, "quasi-static blow-up")
    } else if has("could not go on past") {
        (Class::Known, "inertial integration stopped")
    } else if has("leaves the floating-point range") && has("this is the initial state") {
        (Class::OutsideReach, "initial state beyond the range")
    } else if has("is no longer resolved") && has("640 mesh intervals, the limit") {
        (Class::OutsideReach, "unresolved at the test's mesh limit")
    } else if has("degenerate Hopf point") && at.quasi_static && at.rice_ruina {
        (Class::OutsideReach, "degenerate onset (quasi-static RR)")
    } else if has("degenerate Hopf point") {
        (Class::Known, "degenerate onset")
    } else if has("without a Hopf point") && has("a real eigenvalue crossed zero") {
        (Class::Known, "real eigenvalue crossing")
    } else if has("Hopf location failed") {
        (Class::Known, "Hopf location failed")
    } else if has("can no longer decide its stability") || has("cannot decide its stability") {
        (Class::Known, "Floquet pencil singular")
    } else if has("Newton did not converge correcting a periodic orbit") {
        (Class::Known, "periodic orbit Newton")
    } else {
        return Err(TestCaseError::fail(format!(
            "{what}: a typed error of no documented kind (see the module \
             documentation): {text}"
        )));
    };
    Ok(outcome)
}

/// [`check_error`], then the error's kind ([`error_kind`]).
fn typed_error(what: &str, e: &impl std::fmt::Display, at: Context) -> Verdict {
    check_error(what, e)?;
    error_kind(what, &e.to_string(), at)
}

/// A typed error: its message is not empty and names no non-finite number.
fn check_error(what: &str, e: &impl std::fmt::Display) -> Result<(), TestCaseError> {
    let text = e.to_string();
    prop_assert!(
        !text.trim().is_empty(),
        "{what}: an error without a message"
    );
    let bad = non_finite_words(&text);
    prop_assert!(
        bad.is_empty(),
        "{what}: the error message names non-finite numbers ({bad:?}): {text}"
    );
    // What it suggests is an option of this program, not a setting of the
    // integrator inside it.
    let settings: Vec<&str> = text
        .split(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
        .filter(|w| ["h_min", "h_max", "h0", "atol", "max_steps"].contains(w))
        .collect();
    prop_assert!(
        settings.is_empty(),
        "{what}: the error message suggests the integrator's settings {settings:?}: {text}"
    );
    Ok(())
}

/// The CLI's setup of `case`; a bad-input refusal is an answer (checked as
/// an error): `Err(Ok((Class::BadInput, "bad input")))` then.
fn setup(case: &Case, at: impl Fn(&Params) -> Params) -> Result<Setup, Verdict> {
    case.scene_spec()
        .setup(at)
        .map_err(|e| check_error("setup", &e).map(|()| (Class::BadInput, "bad input")))
}

/// Wall time and verdict of each case of one property, reported at the end.
struct Report {
    property: &'static str,
    cases: RefCell<Vec<(Duration, Outcome, String)>>,
}

impl Report {
    fn new(property: &'static str) -> Self {
        Report {
            property,
            cases: RefCell::new(Vec::new()),
        }
    }

    /// Runs `f` on `case`, recording its wall time and verdict.
    fn time<X: Debug>(&self, case: &Case, extra: &X, f: impl FnOnce() -> Verdict) -> Verdict {
        let t0 = Instant::now();
        let out = f();
        let verdict = *out.as_ref().unwrap_or(&(Class::Known, "failed"));
        self.cases
            .borrow_mut()
            .push((t0.elapsed(), verdict, format!("{case:?} {extra:?}")));
        out
    }

    /// The number of cases of `class`.
    fn count(&self, class: Class) -> usize {
        self.cases
            .borrow()
            .iter()
            .filter(|c| c.1 .0 == class)
            .count()
    }

    /// Prints the total time, the count of each verdict and the slowest cases.
    fn print(&self) {
        let mut cases = self.cases.borrow_mut();
        let total: Duration = cases.iter().map(|c| c.0).sum();
        let mut verdicts: Vec<(Outcome, usize)> = Vec::new();
        for (_, v, _) in cases.iter() {
            match verdicts.iter_mut().find(|(w, _)| w == v) {
                Some((_, n)) => *n += 1,
                None => verdicts.push((*v, 1)),
            }
        }
        cases.sort_by_key(|c| std::cmp::Reverse(c.0));
        eprintln!(
            "{}: {} case runs (shrinking included) in {:.2} s; {}",
            self.property,
            cases.len(),
            total.as_secs_f64(),
            verdicts
                .iter()
                .map(|((class, label), n)| format!("{label} ({class:?}): {n}"))
                .collect::<Vec<_>>()
                .join(", ")
        );
        // Every case with PROPERTY_CASES_ALL set (to compare two builds), else the slowest three.
        let shown = match std::env::var_os("PROPERTY_CASES_ALL") {
            Some(_) => cases.len(),
            None => 3,
        };
        for (t, (class, v), case) in cases.iter().take(shown) {
            eprintln!("  {:.3} s  {v} ({class:?})  {case}", t.as_secs_f64());
        }
    }
}

/// Today's verdicts of one property at the fixed seed and the default number
/// of cases, pinned: the cases that deliver may not become fewer, nor those
/// that deliver at least part of the answer; the known failures may not
/// become more. A fix raises the first two and lowers the third: then pin the
/// new counts.
#[derive(Clone, Copy, Debug)]
struct Floor {
    /// Least number of [`Class::Delivered`] cases.
    delivered: usize,
    /// Least number of [`Class::Delivered`] and [`Class::Partial`] cases.
    answered: usize,
    /// Most [`Class::Known`] cases.
    known: usize,
}

/// Runs `property` on `cases` drawn scenes (or `PROPTEST_CASES`), each with
/// a draw of `extra` (what the command adds to the scene: a range, a step
/// limit, a protocol); a failure panics with the shrunk case. With the fixed
/// seed and `cases` cases (no `PROPTEST_CASES`, no `PROPTEST_RNG_SEED`) the
/// counts of the classes are checked against `floor`.
fn run<T: Debug + Clone>(
    name: &'static str,
    cases: u32,
    extra: impl Strategy<Value = T>,
    floor: Floor,
    property: impl Fn(&Case, &T) -> Verdict,
) {
    let config = contextualize_config(Config {
        cases,
        failure_persistence: None,
        rng_seed: RngSeed::Fixed(SEED),
        max_shrink_iters: 256,
        ..Config::default()
    });
    let pinned = config.cases == cases && config.rng_seed == RngSeed::Fixed(SEED);
    let report = Report::new(name);
    let result = TestRunner::new(config).run(&(case(), extra), |(c, x)| {
        report.time(&c, &x, || property(&c, &x)).map(|_| ())
    });
    report.print();
    if let Err(e) = result {
        panic!("{name}: {e}");
    }
    if !pinned {
        eprintln!("{name}: other cases than the pinned ones, counts not checked");
        return;
    }
    let delivered = report.count(Class::Delivered);
    let answered = delivered + report.count(Class::Partial);
    let known = report.count(Class::Known);
    assert!(
        delivered >= floor.delivered,
        "{name}: {delivered} of {cases} cases delivered, fewer than the {} pinned",
        floor.delivered
    );
    assert!(
        answered >= floor.answered,
        "{name}: {answered} of {cases} cases delivered at least in part, fewer than the {} pinned",
        floor.answered
    );
    assert!(
        known <= floor.known,
        "{name}: {known} of {cases} cases ended in known failures, more than the {} pinned",
        floor.known
    );
}

/// `hopf`: the onset, with the inertia deciding a degenerate quasi-static
/// onset as the CLI does, and the Appendix C values printed next to it.
fn hopf(case: &Case, _: &()) -> Verdict {
    let mut setup = match setup(case, |p| *p) {
        Ok(s) => s,
        Err(verdict) => return verdict,
    };
    let context = Context::of(&setup);
    let outcome = match onset_with_degeneracy_resolved(&mut setup, case.model.is_some()) {
        Ok(o) => o,
        Err(e) => return typed_error("hopf", &e, context),
    };
    check_finite("hopf outcome", &outcome)?;
    let mut at = setup.params;
    check_finite("mu_v, mu_phi", &(at.mu_v(), at.mu_phi()))?;
    if let HopfOutcome::Found(h) = &outcome {
        at.kappa = h.kappa_c;
        prop_assert!(h.kappa_c > 0.0 && h.omega_c > 0.0, "{h:?}");
        let kappa_ref = appendix_c::critical_stiffness(&at);
        let omega_ref = appendix_c::critical_frequency(&at);
        prop_assert!(
            kappa_ref.is_finite() && kappa_ref != 0.0,
            "Appendix C kappa_c = {kappa_ref} at a Hopf point"
        );
        prop_assert!(
            omega_ref.is_some_and(f64::is_finite),
            "Appendix C omega_c = {omega_ref:?} at a Hopf point"
        );
    } else {
        check_finite("Appendix C", &appendix_c::critical_stiffness(&at))?;
    }
    Ok(match outcome {
        HopfOutcome::Found(_) => (Class::Delivered, "hopf point"),
        HopfOutcome::StableForAllStiffness { .. } => {
            (Class::Delivered, "stable for every stiffness")
        }
    })
}

/// Steps of the Hopf curve each way (`diagram --max-steps`).
const DIAGRAM_STEPS: usize = 15;

/// `diagram` over `nu .. nu e^width`, the model chosen at the top of the
/// range as the CLI does: finite, and the curve within the range.
fn diagram(case: &Case, width: &f64) -> Verdict {
    let (lo, hi) = (case.nu, case.nu * width.exp());
    let setup = match setup(case, |p| Params { nu: hi, ..*p }) {
        Ok(s) => s,
        Err(verdict) => return verdict,
    };
    let d = match stability_diagram_with(
        &AsIs,
        setup.choice.kind,
        &setup.params,
        (lo, hi),
        DIAGRAM_STEPS,
    ) {
        Ok(d) => d,
        Err(e) => return typed_error("diagram", &e, Context::of(&setup)),
    };
    check_finite("diagram", &d)?;
    // The curve is continued in ln nu: its end is the range's to the rounding
    // of exp(ln nu).
    let (lo_r, hi_r) = (lo * (1.0 - 1e-12), hi * (1.0 + 1e-12));
    for p in &d.points {
        prop_assert!(
            p.kappa > 0.0 && p.nu >= lo_r && p.nu <= hi_r,
            "curve point outside nu = {lo:e} .. {hi:e} or with kappa <= 0: {p:?}"
        );
        let mut at = setup.params;
        at.nu = p.nu;
        check_finite(
            "Appendix C along the curve",
            &appendix_c::critical_stiffness(&at),
        )?;
    }
    Ok(match (d.points.is_empty(), d.complete) {
        (true, _) => (Class::Delivered, "no Hopf curve"),
        (false, true) => (Class::Delivered, "curve over the range"),
        (false, false) => (Class::Partial, "partial curve"),
    })
}

/// `cycles` with `--max-steps max_steps` (per leg) and `--ntst-max 640`:
/// the start (Hopf point, simulated orbit, or none) and every cycle finite.
fn cycles(case: &Case, max_steps: &usize) -> Verdict {
    let max_steps = *max_steps;
    let mut setup = match setup(case, |p| *p) {
        Ok(s) => s,
        Err(verdict) => return verdict,
    };
    let context = Context::of(&setup);
    let onset = match onset_with_degeneracy_resolved(&mut setup, case.model.is_some()) {
        Ok(o) => o,
        Err(e) => return typed_error("cycles: onset", &e, context),
    };
    let watch = InertiaWatch::new(
        &setup.scene_params,
        DEFAULT_INERTIA_THRESHOLD,
        case.model.is_none(),
    );
    let start = match Start::choose(&setup, onset, false, &watch) {
        Ok(s) => s,
        Err(e) => return typed_error("cycles: start", &e, context),
    };
    check_json("cycles: start", &start.json())?;
    let kappa_ref = start.reference_kappa();
    prop_assert!(
        kappa_ref.is_finite() && kappa_ref >= 0.0,
        "kappa_ref = {kappa_ref}"
    );
    // As the CLI builds it.
    let req = CycleRequest {
        kappa_min: 0.5 * kappa_ref,
        kappa_max: 10.0 * kappa_ref,
        max_steps,
        ntst: 40,
        at_kappa: Vec::new(),
        ntst_max: 640,
        // Each model's own points (the branch may change model).
        collocation: None,
    };
    let mut records: Vec<CycleRecord> = Vec::new();
    let outcomes = start.trace(&setup, &req, &watch, |c: &CycleRecord| {
        records.push(c.clone());
        Ok(())
    });
    let mut error = None;
    for (leg, outcome) in &outcomes {
        if let Err(e) = outcome {
            error = Some(typed_error(&format!("cycles leg {leg:?}"), e, context)?);
        }
    }
    prop_assert!(
        records.len() <= 2 * (max_steps + 1),
        "{} cycles from {max_steps} steps per leg",
        records.len()
    );
    for r in &records {
        check_finite("cycle", r)?;
    }
    Ok(match (records.is_empty(), error) {
        (true, None) => (Class::Delivered, "no cycles"),
        (true, Some(kind)) => kind,
        (false, None) => (Class::Delivered, "cycles"),
        (false, Some(_)) => (Class::Partial, "cycles, then an error"),
    })
}

/// Steps after which the simulation is stopped (`simulate --max-steps`).
const SIMULATE_STEPS: usize = 3000;

/// A `simulate` request: `--protocol`, `--perturb`, `--rtol`.
#[derive(Clone, Debug)]
struct Protocol {
    /// Duration of the first segment, at the scene's `nu`, in memory times `1/nu`.
    first: f64,
    /// Later segments: `(velocity / nu, or 0 to stop; duration in memory
    /// times of the segment's velocity, of nu when it stops)`.
    later: Vec<(f64, f64)>,
    perturb: f64,
    rtol: f64,
}

fn protocol() -> impl Strategy<Value = Protocol> {
    let later = prop::collection::vec(
        (
            prop_oneof![Just(0.0), log_uniform(1e-2, 1e2)],
            1.0f64..=40.0,
        ),
        0..=2,
    );
    (
        1.0f64..=40.0,
        later,
        -0.9f64..=0.9,
        log_uniform(1e-10, 1e-4),
    )
        .prop_map(|(first, later, perturb, rtol)| Protocol {
            first,
            later,
            perturb,
            rtol,
        })
}

/// `simulate`: every sample handed over is finite, and so is the end.
fn simulate(case: &Case, request: &Protocol) -> Verdict {
    let setup = match setup(case, |p| *p) {
        Ok(s) => s,
        Err(verdict) => return verdict,
    };
    let context = Context::of(&setup);
    let nu0 = setup.params.nu;
    let mut protocol = vec![Segment {
        nu: nu0,
        duration: request.first / nu0,
    }];
    protocol.extend(request.later.iter().map(|&(f, d)| Segment {
        nu: f * nu0,
        duration: d / if f > 0.0 { f * nu0 } else { nu0 },
    }));
    // The CLI's start: steady sliding at nu0 with the age perturbed.
    let s0 = setup.params.friction().steady(nu0);
    let start = [s0, nu0, (1.0 + request.perturb) / nu0];
    let (mut count, mut bad) = (0usize, None);
    let run = simulate_with(
        setup.choice.kind,
        &setup.params,
        start,
        &protocol,
        request.rtol,
        None,
        |p| {
            if !p.is_finite() && bad.is_none() {
                bad = Some(*p);
            }
            count += 1;
            if count >= SIMULATE_STEPS {
                ControlFlow::Break(())
            } else {
                ControlFlow::Continue(())
            }
        },
    );
    prop_assert!(bad.is_none(), "non-finite sample handed over: {bad:?}");
    match run {
        Ok(end) if end.stopped => {
            check_finite("simulation end", &end).map(|()| (Class::Delivered, "step limit"))
        }
        Ok(end) => {
            check_finite("simulation end", &end).map(|()| (Class::Delivered, "whole protocol"))
        }
        Err(e) => typed_error("simulate", &e, context),
    }
}

#[test]
fn hopf_is_finite_or_a_typed_error() {
    let floor = Floor {
        delivered: 1013,
        answered: 1013,
        known: 11,
    };
    run("hopf", 1024, Just(()), floor, hopf);
}

#[test]
fn diagram_is_finite_or_a_typed_error() {
    let floor = Floor {
        delivered: 167,
        answered: 255,
        known: 1,
    };
    run("diagram", 256, 0.1f64..=2.0, floor, diagram);
}

#[test]
fn cycles_are_finite_or_a_typed_error() {
    // 2026-11-27: one case (m = 1.2e-12, A = 0.019, B = 0.049, mu2 = 0.05,
    // kappa = 5.2, inertial) went from "no cycles" (every stuck-start
    // simulation failed at the stop into the stick) to a cycle found by the
    // joined flow whose stability rounding then cannot decide (partial):
    // one fewer delivered, one more answered.
    let floor = Floor {
        delivered: 57,
        answered: 60,
        known: 2,
    };
    run("cycles", 64, 1usize..=8, floor, cycles);
}

#[test]
fn simulate_is_finite_or_a_typed_error() {
    let floor = Floor {
        delivered: 837,
        answered: 837,
        known: 101,
    };
    run("simulate", 1024, protocol(), floor, simulate);
}

/// The shrunk cases of the failures this test found (docs/hard-cases.md),
/// checked whatever the seed.
#[test]
fn the_cases_found_stay_fixed() {
    let pmma = |m, a, b, nu, kappa, mu0, law, model| Case {
        m,
        a,
        b,
        nu,
        kappa,
        mu0,
        law,
        model,
    };
    let verdicts: Vec<(&str, Verdict)> = vec![
        (
            "cycles: Floquet pencil without a trivial multiplier ('off by inf')",
            cycles(
                &pmma(
                    753.8069592225617,
                    0.0009649686931774679,
                    0.1,
                    0.020960465550282432,
                    1.0,
                    0.010474624686067273,
                    Law::Ln2 {
                        mu2: 0.09614657367293634,
                    },
                    None,
                ),
                &1,
            ),
        ),
        (
            "cycles: Newton residual overflowing ('residual inf')",
            cycles(
                &pmma(
                    49.96007150009387,
                    0.02063440012177147,
                    0.0020721630647431988,
                    8603.506540987795,
                    301.6417642338407,
                    0.0,
                    Law::RiceRuina,
                    None,
                ),
                &1,
            ),
        ),
        (
            "diagram: Hopf curve corrected past the top of the range",
            diagram(
                &pmma(
                    1.0,
                    0.0003106939605360484,
                    0.00013043642349540806,
                    0.0016234750613652589,
                    1.0,
                    0.0,
                    Law::Ln2 {
                        mu2: 9.485800885076854e-5,
                    },
                    Some(ModelKind::QuasiStatic),
                ),
                &0.3789182401163461,
            ),
        ),
    ];
    let quasi_static_start = |b| {
        pmma(
            1.0,
            1.9383065062360587e-5,
            b,
            1.0,
            1.0,
            0.0,
            Law::RiceRuina,
            Some(ModelKind::QuasiStatic),
        )
    };
    let perturbed = Protocol {
        first: 1.0,
        later: Vec::new(),
        perturb: -0.13258959853182814,
        rtol: 1e-4,
    };
    let verdicts = verdicts.into_iter().chain([
        (
            "simulate: quasi-static start beyond the floating-point range ('v = inf')",
            simulate(&quasi_static_start(0.1), &perturbed),
        ),
        (
            "simulate: quasi-static start at the edge of the range ('NaN/inf' in the advice)",
            simulate(&quasi_static_start(0.09028184003918337), &perturbed),
        ),
        (
            "simulate: the stage equations not finite ('NaN or infinite')",
            simulate(
                &pmma(
                    6.828755915094742e-11,
                    3.789162871595244e-6,
                    0.010568681368706194,
                    629.4367445302228,
                    7.87873791664691e-7,
                    0.0,
                    Law::Cutoff { theta_c: 1.0 },
                    None,
                ),
                &Protocol {
                    first: 1.0,
                    later: vec![(0.011123666169879623, 1.0)],
                    perturb: 0.0,
                    rtol: 1e-4,
                },
            ),
        ),
    ]);
    for (what, verdict) in verdicts {
        if let Err(e) = verdict {
            panic!("{what}: {e}");
        }
    }
}
