#![doc = include_str!("../README.md")]

pub mod arclength;
pub mod branch;
pub mod codim2;
pub mod counted;
pub mod defining;
pub mod double_double;
pub mod driver;
pub mod error;
pub mod events;
pub mod hopf_extended;
pub mod hopf_pencil;
pub mod hopf_series;
pub mod integrate;
pub mod linalg;
pub mod multilinear;
pub mod newton;
pub mod normal_form;
pub mod periodic;
pub mod predictor_corrector;
pub mod root;
pub mod system;

pub use branch::{Branch, BranchPoint, ContinuationSettings, Direction};
pub use counted::{AsIs, Counted, Counting, EvalCounts, Wrap};
pub use driver::{Driver, Stop};
pub use error::ContinuationError;
pub use events::{Event, EventKind};
pub use newton::{NewtonReport, NewtonSettings};
pub use num_complex::Complex64;
pub use predictor_corrector::StepControl;
pub use system::{LogParameters, Scalar, VectorField};
