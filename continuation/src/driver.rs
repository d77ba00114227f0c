//! The one continuation driver: every curve of the crate — branches of
//! equilibria ([`crate::branch::Branch`]), Hopf and fold curves
//! ([`crate::codim2`]), cycle branches
//! ([`crate::periodic::CycleBranch`]) and curves of folds of cycles
//! ([`crate::periodic::LpcCurve`]) — is a [`Curve`] (its start, and
//! one step on from its last point, with the step of
//! [`crate::predictor_corrector`] inside) iterated by [`Driver`], which owns
//! the count of steps, the [`Stop`] and the end after an error.
//!
//! Special points located along a curve (folds and Hopf points of
//! equilibria, Bautin points of Hopf curves, folds of cycles, period
//! doublings, tori and user points of cycle branches) are each an [`Event`]:
//! what it is, the located point, and its error, attached to the first point
//! past it.
//!
//! A curve ends in one of two ways: with an error
//! ([`crate::ContinuationError`], the last item), or without one, for a
//! reason the driver keeps ([`Driver::stop`]): one [`Stop`] for every curve,
//! each variant with the numbers that explain it.

use crate::error::ContinuationError;
use std::fmt;

/// A special point located between two points of a curve, attached to the
/// later one: its `kind` (the curve's vocabulary:
/// [`crate::events::EventKind`], [`crate::codim2::HopfCurveEvent`],
/// [`crate::periodic::CycleEvent`]), the located `point` (a point of
/// the curve, or of the equilibrium at the bifurcation), and its `error`.
#[derive(Clone, Debug)]
pub struct Event<K, P> {
    /// What the point is.
    pub kind: K,
    /// The located point.
    pub point: P,
    /// Its error: the last Newton step of the location (equilibria), the
    /// bound on the rounding error of `l1` (a Bautin point), the estimated
    /// discretization error of the orbit (cycles; see
    /// [`crate::periodic::CyclePoint::error_estimate`]).
    pub error: f64,
}

/// Why a curve ended without an error (the one stop vocabulary of the
/// engine); every variant carries its numbers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Stop {
    /// A bounded parameter reached an end of its range: `value` of the
    /// parameter `index` (in the field's parameter vector) at or beyond
    /// `bound`. Every curve lands on the bound (`value == bound`), except
    /// where the point on it could not be solved with the parameter fixed
    /// (then the located point, within the locator's tolerance of it) and a
    /// cycle branch whose first orbit already lies outside the range.
    Bound {
        /// Index of the parameter in the field's parameter vector.
        index: usize,
        /// Its value on the last point.
        value: f64,
        /// The bound reached.
        bound: f64,
    },
    /// The step limit: `steps` steps after the start were taken.
    MaxSteps {
        /// Steps taken after the first point.
        steps: usize,
    },
    /// A cycle branch's period exceeded its limit.
    MaxPeriod {
        /// The period of the last orbit.
        period: f64,
        /// The limit ([`CycleSettings::max_period`](crate::periodic::CycleSettings::max_period)).
        max_period: f64,
    },
    /// A cycle branch came back to a Hopf point: its cycles shrank to the
    /// equilibrium, where they are born (the amplitude passes through zero
    /// and the parameter turns; past it the same cycles would return,
    /// shifted by half a period). `param` is the continuation parameter of
    /// the last orbit handed out.
    HopfPoint {
        /// The continuation parameter of the last orbit.
        param: f64,
    },
    /// A Hopf curve's frequency fell below its limit: a Bogdanov–Takens
    /// point is near, where the Hopf system degenerates.
    FrequencyVanishing {
        /// The frequency of the last point.
        omega: f64,
        /// The limit ([`crate::codim2::CurveSettings::omega_min`]).
        omega_min: f64,
    },
    /// A curve of folds of cycles passed through a Bautin point: the folded
    /// cycles' amplitude went through zero within the last step (the fold
    /// past it is not handed out). `param` is the second parameter of the
    /// last fold handed out.
    BautinPoint {
        /// The second parameter of the last fold.
        param: f64,
    },
    /// A curve of folds of cycles reached folded cycles smaller than its
    /// limit: a Bautin point is near.
    SmallAmplitude {
        /// The largest range of a component over the last orbit's nodes.
        amplitude: f64,
        /// The limit ([`LpcCurveSettings::min_amplitude`](crate::periodic::LpcCurveSettings::min_amplitude)).
        min_amplitude: f64,
    },
}

/// The reason in the engine's words (the application adds its own by
/// matching the variant).
impl fmt::Display for Stop {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            Stop::Bound {
                index,
                value,
                bound,
            } => write!(
                f,
                "p[{index}] = {value:.10e} reached its bound {bound:.10e}"
            ),
            Stop::MaxSteps { steps } => write!(f, "the step limit: {steps} steps taken"),
            Stop::MaxPeriod { period, max_period } => {
                write!(
                    f,
                    "the period {period:.6e} exceeds the limit {max_period:.6e}"
                )
            }
            Stop::HopfPoint { param } => write!(
                f,
                "the cycles shrink to the equilibrium at a Hopf point (last orbit at {param:.10e})"
            ),
            Stop::FrequencyVanishing { omega, omega_min } => write!(
                f,
                "the Hopf frequency {omega:.3e} fell below {omega_min:.3e}: a Bogdanov-Takens \
                 point is near"
            ),
            Stop::BautinPoint { param } => write!(
                f,
                "the folded cycles passed through zero amplitude (a Bautin point) after \
                 {param:.10e}"
            ),
            Stop::SmallAmplitude {
                amplitude,
                min_amplitude,
            } => write!(
                f,
                "the folded cycles' amplitude {amplitude:.3e} fell below {min_amplitude:.3e}: \
                 a Bautin point is near"
            ),
        }
    }
}

/// What one step of a [`Curve`] gave.
pub enum Advance<P> {
    /// The next point, and the reason the curve ends on it, if it does.
    Point(P, Option<Stop>),
    /// The curve ended without a further point.
    End(Stop),
}

/// A curve the [`Driver`] traces: its start and its steps. The curve keeps
/// its own current point, tangent and step size between calls.
pub trait Curve {
    /// A point handed out.
    type Point;

    /// The first point (the corrected start), and the reason the curve ends
    /// on it, if it does.
    fn start(&mut self) -> Result<(Self::Point, Option<Stop>), ContinuationError>;

    /// One step on from the last point handed out.
    fn advance(&mut self) -> Result<Advance<Self::Point>, ContinuationError>;
}

/// The driver of every curve: an iterator over its points that takes at
/// most `max_steps` steps after the start, ends at the first [`Stop`]
/// (kept, [`Driver::stop`]) or after the first error (its last item).
pub struct Driver<C: Curve> {
    curve: C,
    max_steps: usize,
    /// Points handed out.
    points: usize,
    stop: Option<Stop>,
    failed: bool,
}

impl<C: Curve> Driver<C> {
    /// Traces `curve` with at most `max_steps` steps after its start.
    pub fn trace(curve: C, max_steps: usize) -> Self {
        Driver {
            curve,
            max_steps,
            points: 0,
            stop: None,
            failed: false,
        }
    }

    /// Why the curve ended, once it has ended without an error (`None`
    /// while it goes on, or after an error).
    pub fn stop(&self) -> Option<Stop> {
        self.stop
    }

    /// The curve traced.
    pub fn curve(&self) -> &C {
        &self.curve
    }
}

impl<C: Curve> Iterator for Driver<C> {
    type Item = Result<C::Point, ContinuationError>;

    fn next(&mut self) -> Option<Self::Item> {
        if self.failed || self.stop.is_some() {
            return None;
        }
        let outcome = if self.points == 0 {
            self.curve.start().map(|(p, stop)| Advance::Point(p, stop))
        } else if self.points > self.max_steps {
            Ok(Advance::End(Stop::MaxSteps {
                steps: self.max_steps,
            }))
        } else {
            self.curve.advance()
        };
        match outcome {
            Ok(Advance::Point(point, stop)) => {
                self.points += 1;
                self.stop = stop;
                Some(Ok(point))
            }
            Ok(Advance::End(stop)) => {
                self.stop = Some(stop);
                None
            }
            Err(e) => {
                self.failed = true;
                Some(Err(e))
            }
        }
    }
}
