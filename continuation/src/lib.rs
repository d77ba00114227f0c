#![doc = include_str!("../README.md")]

mod arclength;
mod branch;
pub mod codim2;
mod counted;
mod defining;
mod double_double;
mod driver;
mod error;
mod events;
mod hopf_extended;
mod hopf_pencil;
mod hopf_series;
pub mod integrate;
mod linalg;
mod multilinear;
mod newton;
pub mod normal_form;
pub mod periodic;
mod predictor_corrector;
mod root;
pub mod system;

pub use arclength::CurveControl;
pub use branch::{Branch, BranchPoint, ContinuationSettings, Direction};
pub use counted::{AsIs, Counted, Counting, EvalCounts, Wrap, EVAL_KINDS, N_EVAL_KINDS};
pub use double_double::DoubleDouble;
pub use driver::{Driver, Stop};
pub use error::{ContinuationError, NewtonFailure};
pub use events::{hopf_test, locate_hopf, Event, EventKind};
pub use linalg::{count_unstable, eigenpair_near, eigenvalues};
pub use newton::{NewtonReport, NewtonSettings};
pub use num_complex::Complex64;
pub use predictor_corrector::StepControl;
pub use root::illinois;
pub use system::{LogParameters, Scalar, VectorField};
