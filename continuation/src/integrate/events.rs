//! Event functions `g(t, x)` and the location of their zeros on the dense
//! output by the Illinois variant of regula falsi ([`crate::root`]).
//!
//! After each accepted step `[t_prev, t_new]` every event function is
//! evaluated at the step end (and at `event_samples - 1` interior points of
//! the collocation polynomial); a sign change that matches the function's
//! [`EventDirection`] is bracketed and then narrowed on the polynomial until
//! the bracket is shorter than `event_tol * max(|t|, |h|)` (rounding of `t`
//! permitting). The Illinois rule halves the function value kept at a stale
//! bracket end, which makes regula falsi superlinear (order about 1.44;
//! Dowell & Jarratt, BIT 11 (1971) 168–174) while it never leaves the bracket.

/// Which sign changes of `g` count, along the direction of integration.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum EventDirection {
    /// From negative to non-negative.
    Rising,
    /// From positive to non-positive.
    Falling,
    /// Either.
    #[default]
    Any,
}

/// The boxed closure `g(t, x)` of an [`EventFunction`].
type BoxedEventFn<'a> = Box<dyn FnMut(f64, &[f64]) -> f64 + 'a>;

/// A scalar event function `g(t, x)` whose zeros are located during the
/// integration, with a direction filter and a terminal flag.
///
/// ```
/// use continuation::integrate::{EventDirection, EventFunction};
/// // Upward zero crossings of x[0]; stop the integration at the first one.
/// let ev = EventFunction::new(|_t, x: &[f64]| x[0])
///     .direction(EventDirection::Rising)
///     .terminal(true);
/// assert!(ev.is_terminal());
/// ```
pub struct EventFunction<'a> {
    g: BoxedEventFn<'a>,
    direction: EventDirection,
    terminal: bool,
}

impl<'a> EventFunction<'a> {
    /// A non-terminal event for sign changes of `g` in either direction.
    pub fn new(g: impl FnMut(f64, &[f64]) -> f64 + 'a) -> Self {
        EventFunction {
            g: Box::new(g),
            direction: EventDirection::Any,
            terminal: false,
        }
    }

    /// Sets the direction filter.
    pub fn direction(mut self, direction: EventDirection) -> Self {
        self.direction = direction;
        self
    }

    /// Sets whether the integration stops at the first crossing.
    pub fn terminal(mut self, terminal: bool) -> Self {
        self.terminal = terminal;
        self
    }

    /// Whether the integration stops at the first crossing.
    pub fn is_terminal(&self) -> bool {
        self.terminal
    }

    /// The direction filter.
    pub fn get_direction(&self) -> EventDirection {
        self.direction
    }

    /// Evaluates `g(t, x)`.
    pub fn value(&mut self, t: f64, x: &[f64]) -> f64 {
        (self.g)(t, x)
    }

    /// Whether a change from `ga` (at the earlier time) to `gb` is a crossing
    /// this event reports; `Some(true)` for rising, `Some(false)` for falling.
    pub(crate) fn crossing(&self, ga: f64, gb: f64) -> Option<bool> {
        let rising = ga < 0.0 && gb >= 0.0;
        let falling = ga > 0.0 && gb <= 0.0;
        match self.direction {
            EventDirection::Rising if rising => Some(true),
            EventDirection::Falling if falling => Some(false),
            EventDirection::Any if rising || falling => Some(rising),
            _ => None,
        }
    }
}

/// A located zero of an event function.
#[derive(Clone, Debug, PartialEq)]
pub struct Crossing {
    /// Index of the event function (order of registration).
    pub index: usize,
    /// Time of the zero (the bracket end past the sign change).
    pub t: f64,
    /// State from the dense output at `t`.
    pub x: Vec<f64>,
    /// `true` if `g` went from negative to non-negative.
    pub rising: bool,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn direction_filter() {
        let e = EventFunction::new(|_, _| 0.0).direction(EventDirection::Rising);
        assert_eq!(e.crossing(-1.0, 1.0), Some(true));
        assert_eq!(e.crossing(1.0, -1.0), None);
        assert_eq!(e.crossing(0.0, 1.0), None);
        let e = EventFunction::new(|_, _| 0.0);
        assert_eq!(e.crossing(1.0, 0.0), Some(false));
        assert_eq!(e.crossing(1.0, 2.0), None);
    }
}
