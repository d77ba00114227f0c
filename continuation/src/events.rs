//! Test functions along a branch of equilibria, and the location of the
//! bifurcations they detect by Newton's method on minimally augmented systems
//! (Govaerts 2000, ch. 4; Kuznetsov 1998, §10.2).
//!
//! * Fold (limit point): `psi_F = dp/ds`, the parameter component of the
//!   tangent. Located on `f(x, p) = 0, g(x, p) = 0`, where `g` is the last
//!   component of the solution of `[[J, b], [c^T, 0]] (v, g) = (0, 1)`.
//! * Hopf: `psi_H = prod_{i<j} (lambda_i + lambda_j)`, the bialternate-product
//!   determinant. It also vanishes at neutral saddles (a real pair `+-lambda`);
//!   those are recognised from the eigenvalues and never reported. Located on
//!   `f(x, p) = 0, Re g = Im g = 0` with unknowns `(x, p, omega)`, where `g`
//!   comes from `[[J - i omega I, b], [c^H, 0]] (v, g) = (0, 1)`.
//!
//! The defining systems live in [`crate::defining`].

use crate::defining::{DefiningSystem, FoldSystem, FreeParams, HopfSystem};
use crate::error::ContinuationError;
use crate::linalg::eigenvalues;
use crate::newton::{self, NewtonReport, NewtonSettings};
use crate::normal_form::fold_coefficient;
use crate::system::{jacobian, VectorField};
use nalgebra::{DMatrix, DVector};
use num_complex::Complex64;

/// What kind of bifurcation an event is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum EventKind {
    /// A limit point of the equilibrium branch (one real eigenvalue crosses 0).
    Fold {
        /// Normal-form coefficient `a` of `y' = beta + a y^2`
        /// ([`crate::normal_form::fold_coefficient`]).
        a: f64,
    },
    /// A pair `+-i omega` crosses the imaginary axis.
    Hopf {
        /// Angular frequency at the bifurcation (positive).
        omega: f64,
    },
}

impl EventKind {
    /// Short name: `fold` or `hopf`.
    pub fn name(&self) -> &'static str {
        match self {
            EventKind::Fold { .. } => "fold",
            EventKind::Hopf { .. } => "hopf",
        }
    }
}

/// A located bifurcation of equilibria: the one `Event`
/// with an [`EventKind`] and the `Equilibrium` at it; its `error` is the
/// last Newton step of the location.
pub type Event = crate::driver::Event<EventKind, Equilibrium>;

/// The equilibrium at a located bifurcation.
#[derive(Clone, Debug)]
pub struct Equilibrium {
    /// The equilibrium at the bifurcation.
    pub x: Vec<f64>,
    /// The full parameter vector at the bifurcation.
    pub p: Vec<f64>,
    /// Index of the continuation parameter in `p`.
    pub param_index: usize,
    /// Eigenvalues at the bifurcation, by decreasing real part.
    pub eigenvalues: Vec<Complex64>,
    /// How the locating Newton run went.
    pub newton: NewtonReport,
}

impl Event {
    /// The equilibrium and the frequency of a Hopf point; `None` for a fold.
    pub fn hopf(&self) -> Option<(&Equilibrium, f64)> {
        match self.kind {
            EventKind::Hopf { omega } => Some((&self.point, omega)),
            EventKind::Fold { .. } => None,
        }
    }
}

impl Equilibrium {
    /// Value of the continuation parameter at the bifurcation.
    pub fn param(&self) -> f64 {
        self.p[self.param_index]
    }
}

/// Hopf test function `Re prod_{i<j} (lambda_i + lambda_j)`.
pub fn hopf_test(ev: &[Complex64]) -> f64 {
    let mut prod = Complex64::new(1.0, 0.0);
    for i in 0..ev.len() {
        for j in i + 1..ev.len() {
            prod *= ev[i] + ev[j];
        }
    }
    prod.re
}

/// The eigenvalue pair with the smallest `|lambda_i + lambda_j|`: the pair that
/// makes the Hopf test function vanish. Returns `(lambda_i, lambda_j)`.
pub fn critical_pair(ev: &[Complex64]) -> Option<(Complex64, Complex64)> {
    let mut best: Option<(f64, Complex64, Complex64)> = None;
    for i in 0..ev.len() {
        for j in i + 1..ev.len() {
            let d = (ev[i] + ev[j]).norm();
            if best.is_none_or(|b| d < b.0) {
                best = Some((d, ev[i], ev[j]));
            }
        }
    }
    best.map(|(_, a, b)| (a, b))
}

/// Whether the critical pair is a complex-conjugate pair (a Hopf candidate)
/// rather than a real pair `+-lambda` (a neutral saddle).
pub fn is_complex_pair(pair: (Complex64, Complex64)) -> bool {
    let (a, b) = pair;
    let scale = a.norm().max(b.norm()).max(f64::MIN_POSITIVE);
    a.im.abs() > 1e-8 * scale && (a.im + b.im).abs() <= 1e-6 * scale
}

/// " locating the Hopf point (from kappa = 1.05e-2)": the starting value of
/// the free parameter, named by the field.
fn context<S: VectorField>(sys: &S, kind: &str, k: usize, value: f64) -> String {
    format!(
        " locating the {kind} point (from {} = {value:e})",
        sys.param_name(k)
    )
}

/// Newton's method on a square defining system, from `z`.
fn solve_square<G: DefiningSystem>(
    system: &G,
    z: &mut DVector<f64>,
    settings: &NewtonSettings,
    context: &str,
) -> Result<NewtonReport, ContinuationError> {
    let m = system.n_equations();
    let mut gs = DVector::zeros(m);
    let mut dgs = DMatrix::zeros(m, z.len());
    newton::solve_scaled(z, settings, context, |z, g, dg| {
        system.eval(z, &mut gs, &mut dgs);
        g.copy_from(&gs);
        dg.copy_from(&dgs);
    })
}

/// Locates a Hopf point from the guess `(x0, p0[k], omega0)` by Newton's
/// method on the minimally augmented system (`HopfSystem`); `p0` holds the
/// other parameters.
pub fn locate_hopf<S: VectorField>(
    sys: &S,
    k: usize,
    x0: &[f64],
    p0: &[f64],
    omega0: f64,
    settings: &NewtonSettings,
) -> Result<Event, ContinuationError> {
    let n = sys.dim();
    let mut z = DVector::from_iterator(n + 2, x0.iter().copied().chain([omega0.abs(), p0[k]]));
    let params = FreeParams {
        base: p0.to_vec(),
        free: vec![k],
    };
    let system = HopfSystem::new(sys, params, &z)?;
    let report = solve_square(&system, &mut z, settings, &context(sys, "Hopf", k, p0[k]))?;
    let x = z.as_slice()[..n].to_vec();
    let p = system.params.with(&[z[n + 1]]);
    let ev = eigenvalues(&jacobian(sys, &x, &p))?;
    Ok(Event {
        kind: EventKind::Hopf { omega: z[n].abs() },
        error: report.step,
        point: Equilibrium {
            x,
            p,
            param_index: k,
            eigenvalues: ev,
            newton: report,
        },
    })
}

/// Locates a fold (limit point) from the guess `(x0, p0[k])` by Newton's
/// method on the minimally augmented system ([`FoldSystem`]).
pub fn locate_fold<S: VectorField>(
    sys: &S,
    k: usize,
    x0: &[f64],
    p0: &[f64],
    settings: &NewtonSettings,
) -> Result<Event, ContinuationError> {
    let n = sys.dim();
    let mut z = DVector::from_iterator(n + 1, x0.iter().copied().chain([p0[k]]));
    let params = FreeParams {
        base: p0.to_vec(),
        free: vec![k],
    };
    let system = FoldSystem::new(sys, params, &z)?;
    let report = solve_square(&system, &mut z, settings, &context(sys, "fold", k, p0[k]))?;
    let x = z.as_slice()[..n].to_vec();
    let p = system.params.with(&[z[n]]);
    let ev = eigenvalues(&jacobian(sys, &x, &p))?;
    Ok(Event {
        kind: EventKind::Fold {
            a: fold_coefficient(sys, &x, &p)?,
        },
        error: report.step,
        point: Equilibrium {
            x,
            p,
            param_index: k,
            eigenvalues: ev,
            newton: report,
        },
    })
}
