//! # continuation
//!
//! Numerical continuation and bifurcation analysis of `x' = f(x, p)`:
//! equilibria, Hopf and fold curves, periodic orbits by collocation with
//! their Floquet multipliers, curves of folds of cycles, and an implicit
//! integrator, with exact derivatives from dual numbers.
//!
//! * [`system`]: the [`VectorField`] trait — `f(x, p)` written once, generic over
//!   the scalar — and the exact Jacobian and higher derivatives derived from it.
//! * [`driver`]: the one [`Driver`] that iterates every curve, the one
//!   [`Event`] type of located points and the one [`Stop`] of curves that
//!   ended without an error.
//! * [`branch`]: pseudo-arclength continuation of equilibria as an iterator.
//! * [`codim2`], [`periodic`]: Hopf and fold curves; cycle branches and
//!   curves of folds of cycles.
//! * [`events`]: test functions and the location of folds and Hopf points by
//!   Newton's method on minimally augmented systems.
//! * [`predictor_corrector`]: the one pseudo-arclength step, with its
//!   step-size control, of every curve (equilibria, codimension-2 curves,
//!   cycle branches, curves of folds of cycles).
//! * [`linalg`], [`newton`], [`error`]: eigenvalues, the one Newton loop with
//!   a typed outcome (dense, collocation and fold-of-cycles systems), errors
//!   that carry the numbers.
//! * [`counted`]: a wrapper that counts a field's evaluations by derivative
//!   order, and the [`Wrap`] an analysis builds its fields through.
//!
//! The crate knows nothing about the application; `stickslip` builds on it.

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
