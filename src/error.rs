//! Errors of the domain layer: bad input (exit status 2) and numerical
//! failures (exit status 3). Every message names the field or the numbers.

use std::fmt;
use thiserror::Error;

/// Input the program refuses, with the field, the value and what is allowed.
#[derive(Debug, Error)]
pub enum InputError {
    #[error("unknown {what} '{name}'{}; allowed: {allowed}", suggestion.as_ref().map(|s| format!(" (did you mean '{s}'?)")).unwrap_or_default())]
    UnknownName {
        what: &'static str,
        name: String,
        suggestion: Option<String>,
        allowed: String,
    },
    #[error("{field} = {value} is out of range: expected {expected}")]
    OutOfRange {
        field: String,
        value: String,
        expected: String,
    },
    #[error("{field}: cannot read '{value}': expected {expected}")]
    Malformed {
        field: String,
        value: String,
        expected: String,
    },
    /// A key of the other family of friction laws (`law`): `A` on an
    /// adhesive scene, `F_a` on a rate-and-state one. `field` names where
    /// it was given (`--set A`, `key A` of a scene file), `keys` which list
    /// `allowed` is (`keys`, `--set keys`).
    #[error(
        "{field}: `{name}` is {family} key; this scene's law is `{law}`, whose {keys} are \
         {allowed}"
    )]
    OtherLaw {
        field: String,
        name: String,
        family: &'static str,
        law: &'static str,
        keys: &'static str,
        allowed: String,
    },
    #[error("{0}")]
    Conflict(String),
    #[error("cannot read scene file {path}: {reason}")]
    File { path: String, reason: String },
    /// A file to restart from (`--from FILE`) that cannot serve: missing,
    /// not the right kind, without orbits, an index out of range, a field
    /// edited out of shape; `field` names the JSON field (or the option).
    #[error("cannot restart from {path}: {field}: {reason}")]
    Restart {
        path: String,
        field: String,
        reason: String,
    },
}

impl InputError {
    /// This error of a value read from the scene file `path`, with the file
    /// named before the field (the errors that name no file otherwise).
    pub fn in_file(self, path: &str) -> Self {
        // Once: a field may already be named in its file.
        let named = |field: String| {
            if field.starts_with(&format!("{path}: ")) {
                field
            } else {
                format!("{path}: {field}")
            }
        };
        match self {
            InputError::OutOfRange {
                field,
                value,
                expected,
            } => InputError::OutOfRange {
                field: named(field),
                value,
                expected,
            },
            InputError::Malformed {
                field,
                value,
                expected,
            } => InputError::Malformed {
                field: named(field),
                value,
                expected,
            },
            InputError::OtherLaw {
                field,
                name,
                family,
                law,
                keys,
                allowed,
            } if !field.starts_with("--set") => InputError::OtherLaw {
                field: named(field),
                name,
                family,
                law,
                keys,
                allowed,
            },
            other => other,
        }
    }

    /// A value outside its allowed range.
    pub fn out_of_range(field: &str, value: f64, expected: &str) -> Self {
        InputError::OutOfRange {
            field: field.to_string(),
            value: if value != 0.0 && !(1e-4..1e6).contains(&value.abs()) {
                format!("{value:e}")
            } else {
                format!("{value}")
            },
            expected: expected.to_string(),
        }
    }
}

/// A numerical method that did not deliver, with what was reached and what to try.
#[derive(Debug, Error)]
pub enum NumericalError {
    /// The engine's message, and what to do about it with this program.
    #[error("{engine}{remedy}", engine = .0, remedy = remedy(.0))]
    Continuation(#[from] continuation::ContinuationError),
    #[error("{0}")]
    Analysis(String),
    /// No stick-slip onset along a control parameter over the range searched.
    #[error(
        "no stick-slip onset in {param} from {lo:.6e} to {hi:.6e} {unit}: {why}; search another \
         range with {remedy} ({unit})"
    )]
    NoOnsetInRange {
        /// The control parameter.
        param: String,
        /// Its unit.
        unit: String,
        /// The range searched.
        lo: f64,
        hi: f64,
        /// What was seen along it.
        why: String,
        /// The options that set the range (`--from and --to`, `--search LO:HI`).
        remedy: &'static str,
    },
    /// No stick-slip onset along a control parameter over the range
    /// searched, nor at any other value: Appendix C excludes one
    /// ([`crate::analysis::control::onset_excluded`]), so no other range is
    /// advised.
    #[error(
        "no stick-slip onset in {param} from {lo:.6e} to {hi:.6e} {unit}, nor at any other \
         value: {why}"
    )]
    NoOnsetAtAnyValue {
        /// The control parameter.
        param: String,
        /// Its unit.
        unit: String,
        /// The range searched.
        lo: f64,
        hi: f64,
        /// Why none exists, with the numbers.
        why: String,
    },
}

/// The command-line remedy for an engine failure, appended to its message
/// (the engine names none: it knows no command line).
fn remedy(e: &continuation::ContinuationError) -> &'static str {
    use continuation::ContinuationError as E;
    match e {
        E::Unresolved { .. } => " (`cycles --ntst-max`)",
        E::FloquetIllConditioned { .. } => " (`stickslip simulate`)",
        E::DegenerateHopf { .. } => " (`cycles --from-simulation`)",
        _ => "",
    }
}

/// Anything the command line reports; decides the exit status.
#[derive(Debug, Error)]
pub enum Error {
    #[error("bad input: {0}")]
    Input(#[from] InputError),
    #[error("numerical failure: {0}")]
    Numerical(#[from] NumericalError),
    #[error("cannot write output: {0}")]
    Output(#[from] std::io::Error),
    /// A run stopped by SIGINT or SIGTERM (exit status 130 or 143).
    #[error("interrupted ({}) {}; everything computed before is kept", .0.signal, .0.at)]
    Interrupted(Interruption),
    /// Results were written but the request is incomplete (exit status 4).
    #[error("partial results: {0}; everything computed is kept")]
    Partial(String),
}

impl Error {
    /// Exit status: 2 for bad input, 3 for a numerical failure, 4 for
    /// partial results (kept, but the request is incomplete), 1 for I/O,
    /// 130 after Ctrl-C (SIGINT), 143 after SIGTERM.
    pub fn exit_code(&self) -> i32 {
        match self {
            Error::Input(_) => 2,
            Error::Numerical(_) => 3,
            Error::Output(_) => 1,
            Error::Interrupted(i) => i.signal.exit_code(),
            Error::Partial(_) => 4,
        }
    }
}

/// The candidate closest to `name` by edit distance, if reasonably close.
pub fn closest<'a>(name: &str, candidates: impl Iterator<Item = &'a str>) -> Option<String> {
    candidates
        .map(|c| (levenshtein(&name.to_lowercase(), &c.to_lowercase()), c))
        .filter(|(d, c)| *d <= 2.max(c.len() / 3))
        .min_by_key(|(d, _)| *d)
        .map(|(_, c)| c.to_string())
}

fn levenshtein(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diag = row[0];
        row[0] = i + 1;
        for (j, &cb) in b.iter().enumerate() {
            let next = (row[j + 1] + 1)
                .min(row[j] + 1)
                .min(diag + usize::from(ca != cb));
            diag = row[j + 1];
            row[j + 1] = next;
        }
    }
    row[b.len()]
}

/// A signal that asks a run to stop and keep its results.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StopSignal {
    /// SIGINT (Ctrl-C): exit status 130.
    Interrupt,
    /// SIGTERM (`kill`, a job scheduler, a shutdown): exit status 143.
    Terminate,
}

impl StopSignal {
    /// The exit status after this signal: 128 + its number, as a shell
    /// reports a process killed by it.
    pub fn exit_code(self) -> i32 {
        match self {
            StopSignal::Interrupt => 130,
            StopSignal::Terminate => 143,
        }
    }
}

impl fmt::Display for StopSignal {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            StopSignal::Interrupt => "Ctrl-C",
            StopSignal::Terminate => "SIGTERM",
        })
    }
}

/// Where and by which signal a run stopped.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Interruption {
    /// The signal.
    pub signal: StopSignal,
    /// Where the run stopped (`after 12 cycles, ...`).
    pub at: String,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn suggests_the_nearest_name() {
        let names = ["kappa", "nu", "theta_c", "mu2"];
        assert_eq!(
            closest("kapa", names.iter().copied()).as_deref(),
            Some("kappa")
        );
        assert_eq!(
            closest("theta-c", names.iter().copied()).as_deref(),
            Some("theta_c")
        );
        assert_eq!(closest("zzzzzzzz", names.iter().copied()), None);
    }
}
