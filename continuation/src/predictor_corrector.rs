//! One step of pseudo-arclength continuation with step-size control (Keller
//! 1977; Allgower & Georg 1990, §2.2 and §6.1), shared by every curve of the
//! crate: the curves of [`crate::arclength`] (equilibria, Hopf and fold
//! curves), cycle branches and curves of folds of cycles.
//!
//! From a point `z` on the curve with unit tangent `t`, a step of length `ds`
//! predicts `z + ds t` and corrects the prediction onto the curve (Newton on
//! the defining system closed by `<t, z - prediction>_w = 0`, or by another
//! constraint such as a bound to land on). The corrected point is accepted
//! when its tangent `t'` turns by little, `<t', t>_w >= min_tangent_cos`;
//! then `ds <- min(growth ds, ds_max)` after an easy correction (at most
//! `easy_iterations` Newton iterations), but no longer than the step whose
//! turn would be [`TURN_MARGIN`] of the largest allowed ([`next_step`]).
//! A failed correction or a sharp turn
//! rejects the step, `ds <- ds / 2`, and below `ds_min` the step fails with
//! [`ContinuationError::StepTooSmall`]. What is particular to a curve — its
//! corrector, weights, bounds, meshes — lies in its [`CurveProblem`].

use crate::error::{ContinuationError, NewtonFailure};
use crate::newton::NewtonReport;

/// Step-size control of pseudo-arclength continuation. Each curve has its
/// own defaults (see the settings of the curve).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StepControl {
    /// Initial step.
    pub ds: f64,
    /// Smallest step: a step halved below it fails.
    pub ds_min: f64,
    /// Largest step.
    pub ds_max: f64,
    /// Growth factor after an easy correction: `ds <- min(growth ds, ds_max)`
    /// (and no further than the tangent's turn allows, [`next_step`]).
    pub growth: f64,
    /// A correction is easy in at most this many Newton iterations.
    pub easy_iterations: usize,
    /// Smallest cosine (in the curve's inner product) between the unit
    /// tangents at consecutive points: a sharper turn rejects the step.
    pub min_tangent_cos: f64,
}

/// Factor of the step after a rejected one.
pub const SHRINK: f64 = 0.5;

/// Why a step is rejected when the corrector converged but the tangent turned
/// by more than [`StepControl::min_tangent_cos`] allows.
const TURNED: &str = "the tangent turned too sharply";

/// Whether the cosine `cos` of a tangent's turn is at least
/// [`StepControl::min_tangent_cos`] (not when it is NaN).
fn turns_by_little(cos: f64, control: &StepControl) -> bool {
    cos >= control.min_tangent_cos
}

/// The fraction of the largest turn of the tangent
/// ([`StepControl::min_tangent_cos`]) that the next step is sized to turn by
/// at most ([`next_step`]).
pub const TURN_MARGIN: f64 = 0.9;

/// The step after an accepted one of length `ds` whose correction took
/// `iterations` and whose tangent turned by the angle of cosine `cos`:
/// `growth ds` after an easy correction, `ds` after another, and in either
/// case no longer than the step whose turn, proportional to the step
/// (the curvature taken as constant over it), is [`TURN_MARGIN`] of the
/// largest allowed, but not below `ds_min`; at most `ds_max`. Grown
/// without regard to the turn, a step on a curve that bends more and more
/// sharply (a stiffening cycle branch) grows until its tangent turns too
/// far, is rejected and halved, and grows again: every third or fourth
/// correction wasted, the steps half what they could be.
pub fn next_step(ds: f64, iterations: usize, cos: f64, control: &StepControl) -> f64 {
    let grown = if iterations <= control.easy_iterations {
        ds * control.growth
    } else {
        ds
    };
    let turned = cos.clamp(-1.0, 1.0).acos();
    let allowed = control.min_tangent_cos.clamp(-1.0, 1.0).acos();
    let by_turn = if turned > 0.0 {
        ds * TURN_MARGIN * allowed / turned
    } else {
        f64::INFINITY
    };
    // Not below `ds_min`: a step that small which turns too far is
    // rejected, and the next one fails (`step`).
    grown.min(by_turn).max(control.ds_min).min(control.ds_max)
}

/// A prediction corrected onto the curve.
pub struct Corrected<P> {
    /// The point, with what its tangent needs (e.g. the Jacobian there).
    pub point: P,
    /// The corrector's work.
    pub report: NewtonReport,
    /// The step length taken (the one asked for unless a constraint changed it).
    pub ds: f64,
    /// Corrected on a constraint other than the arclength condition (a bound
    /// landed on): accepted whatever the turn of its tangent, and the step
    /// does not grow after it.
    pub constrained: bool,
}

/// What a curve makes of a corrected point its tangent accepts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Review {
    /// Accept it.
    Keep,
    /// Take the step again at the same `ds` (the curve has changed its
    /// prediction, e.g. to land on a bound the point lies beyond).
    Retake,
    /// Reject it, for this reason: the step is halved.
    Reject(&'static str),
}

/// A curve traced by [`step`]: the current point and tangent are its own.
pub trait CurveProblem {
    /// A corrected point with what its tangent needs.
    type Point;
    /// A unit tangent.
    type Tangent;

    /// Predicts the point `ds` along the current tangent and corrects it onto
    /// the curve.
    fn correct(&mut self, ds: f64) -> Result<Corrected<Self::Point>, ContinuationError>;

    /// The unit tangent at a corrected point, oriented along the current one.
    fn tangent(&mut self, point: &mut Self::Point) -> Result<Self::Tangent, ContinuationError>;

    /// The cosine `<tangent, t>_w` of the turn from the current tangent `t`.
    fn turn(&self, tangent: &Self::Tangent) -> f64;

    /// Reviews a corrected point before it is accepted. Default: keep it.
    fn review(&mut self, _corrected: &Corrected<Self::Point>) -> Review {
        Review::Keep
    }

    /// Moves to the accepted point and its tangent.
    fn accept(
        &mut self,
        point: Self::Point,
        tangent: Self::Tangent,
    ) -> Result<(), ContinuationError>;

    /// The name and value of the parameter the curve is at, for
    /// [`ContinuationError::StepTooSmall`].
    fn location(&self) -> (String, f64);
}

/// An accepted step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stepped {
    /// The corrector's work.
    pub report: NewtonReport,
    /// The step length taken.
    pub ds: f64,
}

/// Takes one step of `curve` that its corrector and tangent accept, from
/// step size `ds`, which is left at the size of the next step (grown after an
/// easy correction, halved after each rejection).
///
/// A correction that stalled at the rounding floor of its system
/// ([`NewtonFailure::Stalled`]) ends the step: smaller steps do not lower
/// that floor. A rejected step fails with
/// [`ContinuationError::StepTooSmall`] once `ds < ds_min`, with the last
/// rejection's cause.
pub fn step<C: CurveProblem>(
    curve: &mut C,
    control: &StepControl,
    ds: &mut f64,
) -> Result<Stepped, ContinuationError> {
    loop {
        let cause = match curve.correct(*ds) {
            Err(
                e @ ContinuationError::Newton {
                    reason: NewtonFailure::Stalled,
                    ..
                },
            ) => return Err(e),
            Err(e) => e.to_string(),
            Ok(mut corrected) => match curve
                .tangent(&mut corrected.point)
                .map(|t| (curve.turn(&t), t))
            {
                Err(e) => e.to_string(),
                Ok((cos, _)) if !corrected.constrained && !turns_by_little(cos, control) => {
                    TURNED.into()
                }
                Ok((cos, t)) => match curve.review(&corrected) {
                    Review::Retake => continue,
                    Review::Reject(cause) => cause.into(),
                    Review::Keep => {
                        let Corrected {
                            point,
                            report,
                            ds: taken,
                            constrained,
                        } = corrected;
                        curve.accept(point, t)?;
                        if !constrained {
                            *ds = next_step(*ds, report.iterations, cos, control);
                        }
                        return Ok(Stepped { report, ds: taken });
                    }
                },
            },
        };
        *ds *= SHRINK;
        if *ds < control.ds_min {
            let (param_name, param) = curve.location();
            return Err(ContinuationError::StepTooSmall {
                param_name,
                param,
                ds: *ds,
                ds_min: control.ds_min,
                cause,
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::newton::Failure;

    /// A curve whose corrector always fails for `reason`.
    struct Failing(NewtonFailure);

    impl CurveProblem for Failing {
        type Point = ();
        type Tangent = ();
        fn correct(&mut self, _ds: f64) -> Result<Corrected<()>, ContinuationError> {
            let failure = Failure {
                iterations: 1,
                residual: 1.0,
                step: 1.0,
                reason: self.0.clone(),
            };
            Err(failure.error(String::new(), ""))
        }
        fn tangent(&mut self, _point: &mut ()) -> Result<(), ContinuationError> {
            Ok(())
        }
        fn turn(&self, _tangent: &()) -> f64 {
            1.0
        }
        fn accept(&mut self, _point: (), _tangent: ()) -> Result<(), ContinuationError> {
            Ok(())
        }
        fn location(&self) -> (String, f64) {
            ("p".into(), 2.0)
        }
    }

    const CONTROL: StepControl = StepControl {
        ds: 1.0,
        ds_min: 0.1,
        ds_max: 1.0,
        growth: 1.5,
        easy_iterations: 3,
        min_tangent_cos: 0.9,
    };

    #[test]
    fn failed_corrections_halve_the_step_down_to_ds_min() {
        let mut ds = 1.0;
        let err = step(
            &mut Failing(NewtonFailure::MaxIterations),
            &CONTROL,
            &mut ds,
        );
        match err {
            Err(ContinuationError::StepTooSmall {
                param_name, param, ..
            }) => assert_eq!((param_name.as_str(), param), ("p", 2.0)),
            other => panic!("{other:?}"),
        }
        assert_eq!(ds, 0.0625);
    }

    #[test]
    fn a_stalled_corrector_ends_the_step_at_once() {
        let mut ds = 1.0;
        let err = step(&mut Failing(NewtonFailure::Stalled), &CONTROL, &mut ds);
        assert!(matches!(
            err,
            Err(ContinuationError::Newton {
                reason: NewtonFailure::Stalled,
                ..
            })
        ));
        assert_eq!(ds, 1.0);
    }

    /// On a curve of constant curvature `c` (a step `ds` turns the tangent
    /// by `c ds`), steps from `ds = 1e-3` grow by `growth` until their turn
    /// nears the largest allowed, then hold at [`TURN_MARGIN`] of the step
    /// that turns that far, and none turns too far (none would be
    /// rejected); small turns leave the growth as it was, and `ds_max`
    /// bounds the step.
    #[test]
    fn steps_grow_no_further_than_the_turn_allows() {
        let control = StepControl {
            ds_min: 1e-6,
            ds_max: 10.0,
            ..CONTROL
        };
        let allowed = control.min_tangent_cos.acos();
        for c in [0.3, 1.0, 5.0] {
            let mut ds: f64 = 1e-3;
            for _ in 0..60 {
                let turned = c * ds;
                assert!(
                    turned <= allowed * (1.0 + 1e-12),
                    "c {c}: ds {ds} turns too far"
                );
                ds = next_step(ds, 1, turned.cos(), &control);
            }
            let held = TURN_MARGIN * allowed / c;
            assert!(
                (ds - held).abs() <= 1e-12 * held,
                "c {c}: ds {ds}, expected {held}"
            );
        }
        // A turn far below the limit: grown by `growth`, up to `ds_max`.
        assert_eq!(next_step(0.1, 1, 1.0, &control), 0.1 * control.growth);
        assert_eq!(next_step(9.0, 1, 1.0, &control), control.ds_max);
        // A hard correction does not grow the step; a turn near the limit
        // shrinks it.
        assert_eq!(next_step(0.1, 5, 1.0, &control), 0.1);
        let near = (0.95 * allowed).cos();
        assert!((next_step(0.1, 1, near, &control) - 0.1 * TURN_MARGIN / 0.95).abs() < 1e-12);
        // Not below `ds_min`, where a turn too far fails the step.
        assert_eq!(next_step(control.ds_min, 1, near, &control), control.ds_min);
    }
}
