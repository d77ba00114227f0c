//! Continuation of periodic orbits in one parameter by pseudo-arclength on
//! the collocation system, from a Hopf point or from a given orbit, with
//! Floquet multipliers at every orbit and periodic mesh adaptation.
//!
//! The arclength norm is relative in the period and the parameter
//! ([`ArcWeights`]). The branch is the [`Curve`] [`Cycles`], traced by the
//! [`Driver`] ([`CycleBranch`]).

use super::collocation::Collocation;
mod detect;
mod refine;

use super::adapt::equidistribute;
use super::cycle::Cycle;
use super::floquet::multipliers_and_trivial;
use super::mesh::{CollocationPoints, Mesh};
use super::newton::{
    correct_along, correct_bordered, newton_bordered, solves_bordered, tangent, tangent_from,
    unit_row, ArcWeights, BorderedPoint, OrbitJacobian,
};
use crate::driver::{Advance, Curve, Driver, Event, Stop};
use crate::error::ContinuationError;
use crate::newton::{NewtonReport, NewtonSettings};
use crate::normal_form::{eigenvalue_derivative, hopf_normal_form, HopfNormalForm};
use crate::predictor_corrector::{self, Corrected, CurveProblem, StepControl};
use crate::system::{jacobian, param_derivative, VectorField};
use num_complex::Complex64;
use std::sync::OnceLock;

/// Steps during which a mesh size the multipliers needed bounds halving.
const MULTIPLIER_MEMORY: usize = 5;

/// Steps during which an orbit's error estimate found to be its rounding
/// floor (refining did not reduce it) raises the mesh tolerance to twice
/// that floor.
const ORBIT_FLOOR_MEMORY: usize = 5;

/// How the quantities of an orbit are read, for its error estimate
/// (`refine`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Reading {
    /// At its own parameter value: its period and extremes as functions of
    /// the parameter (the orbits of the branch, user points, period
    /// doublings and torus bifurcations).
    AtParameter,
    /// As a point whose parameter value is one of its coordinates: a fold of
    /// cycles, where the orbits at fixed parameter are not isolated.
    Point,
}

/// Settings of a cycle branch: the shared step control, the
/// [`Discretization`] and the [`FloquetPolicy`], each with its defaults, and
/// what is particular to the branch.
#[derive(Clone, Debug)]
pub struct CycleSettings {
    /// The mesh and how it adapts.
    pub mesh: Discretization,
    /// How the Floquet multipliers are made accurate enough to decide.
    pub floquet: FloquetPolicy,
    /// Step-size control of the pseudo-arclength steps (norm of
    /// `ArcWeights`). Default: `ds = 1e-3`, `ds_min = 1e-12`,
    /// `ds_max = 0.5`, growth 1.3 after at most 3 Newton iterations, turns of
    /// the tangent up to `acos 0.8`.
    pub step: StepControl,
    /// Largest number of steps after the first orbit. Default 200.
    pub max_steps: usize,
    /// Bounds of the parameter; the branch lands on them and stops there
    /// (the orbit on the bound solved with the parameter held there,
    /// `Cycles::orbit_on_bound`). Default unbounded.
    pub p_min: f64,
    pub p_max: f64,
    /// Stop when the period exceeds this. Default `None`: no limit.
    pub max_period: Option<f64>,
    /// Corrector. Default: steps and residuals to `1e-10`, 10 iterations.
    pub corrector: NewtonSettings,
    /// Relative amplitude of the first orbit off the Hopf point
    /// (`|z| / (1 + |x0|)`). Default `1e-3`.
    pub start_amplitude: f64,
    /// Parameter values at which an orbit is located exactly and reported
    /// (AUTO's user points). Default none.
    pub user_points: Vec<f64>,
    /// Smallest scale of the parameter in the arclength weights: below it
    /// steps in the parameter are absolute, above it relative. Default 1
    /// (parameters that pass through 0 need a floor; set it to the smallest
    /// scale of interest for branches spanning decades).
    pub param_floor: f64,
}

/// The collocation mesh of a cycle branch and how it adapts (AUTO's `NTST`,
/// `NCOL`, `IAD`; the refinement by the error estimate is `refine`'s).
#[derive(Clone, Debug)]
pub struct Discretization {
    /// Mesh intervals of the first orbit, and the fewest the mesh is
    /// coarsened to. Default 50.
    pub ntst: usize,
    /// Collocation degree. Default 4.
    pub degree: usize,
    /// Collocation points. Default Gauss (Radau for stiff orbits).
    pub points: CollocationPoints,
    /// Re-equidistribute the mesh every this many steps (0: never). Default 1.
    pub adapt_every: usize,
    /// Largest acceptable estimate of an orbit's discretization error
    /// (relative to the period and the amplitudes, see `refine`) before the
    /// mesh is refined. Default `Some(1e-8)`; `None`: the mesh is sized by
    /// the multipliers alone.
    pub mesh_tol: Option<f64>,
    /// Most mesh intervals the refinement may use. Default 400.
    pub ntst_max: usize,
    /// At `ntst_max`, orbits whose error estimate is below this are still
    /// accepted (and reported with it). Default `Some(1e-6)`; `None`: every
    /// orbit at `ntst_max` is.
    pub mesh_accept: Option<f64>,
}

impl Default for Discretization {
    fn default() -> Self {
        Discretization {
            ntst: 50,
            degree: 4,
            points: CollocationPoints::Gauss,
            adapt_every: 1,
            mesh_tol: Some(1e-8),
            ntst_max: 400,
            mesh_accept: Some(1e-6),
        }
    }
}

impl Discretization {
    /// [`Discretization::mesh_tol`] as a bound (none: no bound).
    fn tol(&self) -> f64 {
        self.mesh_tol.unwrap_or(f64::INFINITY)
    }

    /// [`Discretization::mesh_accept`] as a bound (none: no bound).
    fn accept(&self) -> f64 {
        self.mesh_accept.unwrap_or(f64::INFINITY)
    }
}

/// How a cycle branch treats the error of its Floquet multipliers.
#[derive(Clone, Debug)]
pub struct FloquetPolicy {
    /// The mesh is also refined while the trivial multiplier is off by more
    /// than this and refining reduces that error (it is then discretization,
    /// not rounding) — where a nontrivial multiplier lies within `1e7` times
    /// this of the unit circle; farther, while it is off by more than `1e-7`
    /// of that distance (which decides stability, period doublings and
    /// tori). Default `Some(1e-8)`; `None`: never for the multipliers.
    pub trivial_tol: Option<f64>,
    /// Beyond this distance of the trivial multiplier from 1, the
    /// multipliers no longer decide stability when another lies within ten
    /// times that distance of the unit circle or the distance exceeds 0.1;
    /// what the branch then does is `when_undecidable`. Default
    /// `Some(1e-3)`; `None`: the multipliers are taken as they are.
    pub trivial_limit: Option<f64>,
    /// What the branch does once rounding swamps the multipliers (see
    /// `trivial_limit`). Default [`WhenUndecidable::Stop`].
    pub when_undecidable: WhenUndecidable,
}

impl Default for FloquetPolicy {
    fn default() -> Self {
        FloquetPolicy {
            trivial_tol: Some(1e-8),
            trivial_limit: Some(1e-3),
            when_undecidable: WhenUndecidable::Stop,
        }
    }
}

/// What a branch does at an orbit whose Floquet multipliers rounding has
/// swamped (the orbit itself resolved).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WhenUndecidable {
    /// End with [`ContinuationError::FloquetIllConditioned`].
    Stop,
    /// The branch's first orbit is handed out with
    /// [`Stability::IllConditioned`] (an orbit whose stability is unknown
    /// rather than none at all); a later one ends the branch as `Stop`
    /// does. Going on past it would trace orbits whose stability, period
    /// doublings and tori cannot be decided, on ever finer meshes.
    KeepFirst,
}

impl Default for CycleSettings {
    fn default() -> Self {
        CycleSettings {
            mesh: Discretization::default(),
            floquet: FloquetPolicy::default(),
            step: StepControl {
                ds: 1e-3,
                ds_min: 1e-12,
                ds_max: 0.5,
                growth: 1.3,
                easy_iterations: 3,
                min_tangent_cos: 0.8,
            },
            max_steps: 200,
            p_min: f64::NEG_INFINITY,
            p_max: f64::INFINITY,
            max_period: None,
            corrector: NewtonSettings {
                step_tol: 1e-10,
                residual_tol: 1e-10,
                max_iter: 10,
            },
            start_amplitude: 1e-3,
            user_points: Vec::new(),
            param_floor: 1.0,
        }
    }
}

/// Whether an orbit is stable, decided with the error of its multipliers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Stability {
    /// Every nontrivial multiplier inside the unit circle by more than its error.
    Stable,
    /// A nontrivial multiplier outside the unit circle by more than its error.
    Unstable,
    /// None is outside by more than its error, but the nontrivial
    /// multiplier `modulus` lies within `error` of the unit circle.
    Undecidable { modulus: f64, error: f64 },
    /// The Floquet pencil left `missing` nontrivial multipliers undetermined
    /// (singular to rounding, see `pencil_multipliers`).
    Undetermined { missing: usize },
    /// Rounding swamps the multipliers: the trivial one is off by
    /// `trivial_error` (`None`: the pencil did not determine it), beyond
    /// `trivial_limit`, and another is that close to the unit circle, or
    /// the error exceeds 0.1 ([`WhenUndecidable::KeepFirst`]).
    IllConditioned { trivial_error: Option<f64> },
}

impl Stability {
    /// Decided stable.
    pub fn is_stable(&self) -> bool {
        *self == Stability::Stable
    }
    /// Decided unstable.
    pub fn is_unstable(&self) -> bool {
        *self == Stability::Unstable
    }
}

/// Error of the nontrivial Floquet multipliers of an orbit in dimension `n`
/// whose trivial multiplier is off by `trivial_error`.
///
/// From the pencil (`n > 2`): ten times the distance of the computed
/// trivial multiplier from 1, at least `1e-9`. That distance is a direct
/// sample of the pencil's error (the exact value is 1); the nontrivial
/// multipliers are eigenvalues of the same pencil and carry errors of the
/// same order, but not the same: when one of them is near 1 as well (near a
/// Hopf point or a fold of cycles) the two form a nearly double eigenvalue
/// and split by the square root of the perturbation on either side of
/// their exact values, so the nontrivial one can be off by more than the
/// trivial one. The factor 10 covers that split; it is the band in which
/// the branch already refused to decide stability past `trivial_limit`.
/// The floor `1e-9` is the rounding of multipliers near 1 on smooth orbits.
///
/// In the plane the nontrivial multiplier is Liouville's `exp(int tr J)`,
/// as accurate as the collocation quadrature, independent of the pencil:
/// `1e-9`.
pub fn multiplier_error(n: usize, trivial_error: f64) -> f64 {
    if n == 2 {
        1e-9
    } else {
        (10.0 * trivial_error).max(1e-9)
    }
}

/// A located fold of cycles is accepted when a nontrivial multiplier lies
/// within `max(multiplier_error, FOLD_MULTIPLIER)` of 1: at a fold the
/// branch's tangent is vertical because a second multiplier passes through
/// one. A sign change of `dp/ds` without it is the rounding of a branch
/// that is vertical to the corrector's tolerance (a canard-like explosion
/// of the amplitude at fixed stiffness), not a fold.
const FOLD_MULTIPLIER: f64 = 1e-3;

/// Samples per orbit of [`deviation`].
const DEVIATION_SAMPLES: usize = 64;

/// The orbit's state at [`DEVIATION_SAMPLES`] evenly spaced times minus its
/// mean there, each component scaled by its range (concatenated): how the
/// orbit winds around its centre, comparable between orbits on different
/// meshes.
fn deviation(c: &Cycle) -> Vec<f64> {
    let xs: Vec<Vec<f64>> = (0..DEVIATION_SAMPLES)
        .map(|i| c.state_at(i as f64 / DEVIATION_SAMPLES as f64))
        .collect();
    let mut out = Vec::with_capacity(DEVIATION_SAMPLES * c.n);
    for j in 0..c.n {
        let column = xs.iter().map(|x| x[j]);
        let mean = column.clone().sum::<f64>() / DEVIATION_SAMPLES as f64;
        let (lo, hi) = column
            .clone()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                (lo.min(v), hi.max(v))
            });
        let range = if hi > lo { hi - lo } else { 1.0 };
        out.extend(column.map(|v| (v - mean) / range));
    }
    out
}

/// An orbit whose every observable's amplitude is below this fraction of
/// the largest the branch has had, followed by a larger one, is where the
/// branch passed through the equilibrium (a Hopf point) between steps
/// without the parameter turn being seen.
const PASSED: f64 = 0.05;

/// A turn of the parameter whose located orbit has, on every observable,
/// less than this fraction of the amplitude of the orbit before it is the
/// branch passing through the equilibrium (a Hopf point), not a fold.
const COLLAPSE: f64 = 1e-2;

/// Whether `located` (where the parameter turns) is the equilibrium the
/// cycles shrink to: every observable's amplitude there below
/// [`COLLAPSE`] of its amplitude on `before`, the orbit of the step before.
fn collapsed<S: VectorField>(sys: &S, located: &CyclePoint, before: &Cycle) -> bool {
    located
        .extremes(sys)
        .iter()
        .enumerate()
        .all(|(k, &(lo, hi))| {
            let (b_lo, b_hi) = before.observable_range(sys, k);
            hi - lo <= COLLAPSE * (b_hi - b_lo)
        })
}

/// One orbit of the branch.
#[derive(Clone, Debug)]
pub struct CyclePoint {
    pub cycle: Cycle,
    /// Floquet multipliers by decreasing modulus (including the trivial one),
    /// those the pencil determined (`pencil_multipliers`).
    pub multipliers: Vec<Complex64>,
    /// Index of the trivial multiplier in `multipliers`, when determined.
    pub trivial: Option<usize>,
    /// `min |mu - 1|`: rounding in the multipliers, amplified by the
    /// orbit's transient growth (not a measure of the mesh). Infinite when
    /// the pencil did not determine the trivial multiplier.
    pub trivial_error: f64,
    /// Least and greatest value of every observable on the orbit, found
    /// once ([`CyclePoint::extremes`]).
    extremes: OnceLock<Vec<(f64, f64)>>,
    /// Estimated discretization error of the period (relative) and of the
    /// extremes of every observable (relative to its amplitude), at the
    /// orbit's own parameter (see `refine`); while far below `mesh_tol` it is
    /// renewed every fifth orbit, and the last estimate is reported in between.
    pub error_estimate: f64,
    /// Multipliers outside the unit circle by more than their error
    /// (`multiplier_error`), the trivial one excluded.
    pub n_unstable: usize,
    /// Stability decided with the multipliers' error.
    pub stability: Stability,
    pub newton: NewtonReport,
    /// `d p / d s` along the branch: its sign change marks a fold of cycles.
    pub dp_ds: f64,
    /// The orbits located between the previous orbit and this one: a fold
    /// of cycles, a period doubling, a torus bifurcation (at most one of
    /// each), and the orbits at the user's parameter values passed; each
    /// with its [`CyclePoint::error_estimate`] as its error.
    pub events: Vec<Event<CycleEvent, CyclePoint>>,
}

/// What a located orbit of a cycle branch is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CycleEvent {
    /// A fold of cycles (limit point of cycles, LPC).
    Fold,
    /// A period doubling: a multiplier through -1.
    PeriodDoubling,
    /// A Neimark–Sacker (torus) bifurcation: a complex pair through the
    /// unit circle.
    Torus,
    /// The orbit at a parameter value the user asked for
    /// ([`CycleSettings::user_points`]).
    User {
        /// The value asked for.
        value: f64,
    },
}

impl CyclePoint {
    /// The located orbit of `kind` (not a user point) attached to this one.
    pub fn event(&self, kind: CycleEvent) -> Option<&CyclePoint> {
        self.events
            .iter()
            .find(|e| e.kind == kind)
            .map(|e| &e.point)
    }

    /// The orbits at the user's parameter values attached to this one.
    pub fn user_points(&self) -> impl Iterator<Item = &CyclePoint> {
        self.events
            .iter()
            .filter(|e| matches!(e.kind, CycleEvent::User { .. }))
            .map(|e| &e.point)
    }

    /// Attaches the located orbit `point` of `kind`.
    fn attach(&mut self, kind: CycleEvent, point: CyclePoint) {
        self.events.push(Event {
            kind,
            error: point.error_estimate,
            point,
        });
    }

    /// Least and greatest value of every observable of `sys` (the field
    /// the orbit solves) over the orbit, by [`Cycle::observable_range`]:
    /// computed at the first call, then kept (the error estimate and the
    /// caller's record read the same values).
    pub fn extremes<S: VectorField>(&self, sys: &S) -> &[(f64, f64)] {
        self.extremes.get_or_init(|| {
            (0..sys.n_observables())
                .map(|k| self.cycle.observable_range(sys, k))
                .collect()
        })
    }
}

/// A branch of periodic orbits being traced; iterate it to get the orbits.
/// It ends at a [`Stop`] ([`Driver::stop`]): [`Stop::Bound`] (the orbit
/// on `p_min` or `p_max`, which the branch lands on), [`Stop::MaxSteps`],
/// [`Stop::MaxPeriod`] or [`Stop::HopfPoint`] (the cycles shrank to the
/// equilibrium: the last orbit is the one the step through it reached, or
/// the one before where the branch passed through it between steps), or
/// after the first error.
pub type CycleBranch<'a, S> = Driver<Cycles<'a, S>>;

/// The [`Curve`] of a [`CycleBranch`].
pub struct Cycles<'a, S: VectorField> {
    sys: &'a S,
    k: usize,
    settings: CycleSettings,
    z: Vec<f64>,
    tangent: Vec<f64>,
    coll: Collocation<'a, S>,
    /// The current orbit is held at its parameter — the first orbit
    /// corrected there (no orbit part in the seed), or the orbit landed on a
    /// range bound: its refinement keeps the parameter.
    held: bool,
    /// The first orbit was corrected at its period (the seed along the
    /// period alone): the caller starts at a fold of cycles, where the
    /// orbits at fixed parameter are not isolated. The first orbit is read
    /// as a point ([`Reading::Point`]), like a located fold, and the turn
    /// of the parameter within the first step is that fold, not a new one.
    start_at_fold: bool,
    ds: f64,
    /// Orbits handed out (or failed).
    steps: usize,
    /// Floquet multipliers of the last orbit handed out (for the PD and NS tests).
    previous_mu: Vec<Complex64>,
    /// Their trivial multiplier's distance from 1 (their error's measure).
    previous_trivial_error: f64,
    /// The continuation parameter of the last orbit handed out.
    previous_param: f64,
    /// The largest amplitude of each observable on the branch so far, and
    /// the last orbit's amplitude relative to it (the largest over the
    /// observables), with whether it had shrunk from the orbit before.
    largest_amplitude: Vec<f64>,
    last_relative: Option<(f64, bool)>,
    /// The last orbit's deviation from its mean ([`deviation`]).
    last_deviation: Vec<f64>,
    /// The last discretization error estimate, the mesh size it was made
    /// on, and the orbits since (see `refine`).
    last_estimate: f64,
    last_ntst: usize,
    since_estimate: usize,
    /// Tolerance on the trivial multiplier in force: raised to the rounding
    /// floor of stiff orbits when refining no longer reduces its error.
    trivial_tol: f64,
    /// The rounding floor of the error estimate last found (twice the
    /// estimate a doubling of the mesh did not reduce) and the step it was
    /// found at (see `refine`).
    orbit_floor: (f64, usize),
    /// Intervals the multipliers were last found to need (a doubling that
    /// divided their error by 4) and the step it was found at: for the next
    /// [`MULTIPLIER_MEMORY`] steps the mesh is not halved below it (the
    /// need changes along the branch). Reset when their error turns out to
    /// be rounding.
    multiplier_ntst: (usize, usize),
    /// The collocation Jacobian at the orbit `z` the last step (or
    /// correction on a new mesh) ended on, with that `z`: its reduction gives
    /// the orbit's multipliers without linearizing again (its phase row may
    /// be the reference's before the orbit became it, which they do not
    /// involve).
    jacobian: Option<(Vec<f64>, OrbitJacobian)>,
    /// A Jacobian no longer needed (replaced by the last accepted step's),
    /// whose storage the next correction along the branch linearizes into.
    spare: Option<OrbitJacobian>,
}

impl<'a, S: VectorField> Driver<Cycles<'a, S>> {
    /// Starts from the Hopf point `(x0, omega, p0)` in parameter `k`: the first
    /// orbit comes from the normal form (`x0 + 2 r Re(q e^{2 pi i tau})` at
    /// `p_k = p_c - Re(c1) r^2 / Re(lambda')`) and is corrected at that parameter.
    pub fn from_hopf(
        sys: &'a S,
        x0: &[f64],
        omega: f64,
        p0: &[f64],
        k: usize,
        settings: CycleSettings,
    ) -> Result<Self, ContinuationError> {
        let nf = hopf_normal_form(sys, x0, p0, omega)?;
        // The normal-form start needs |c1| well above rounding: the first
        // orbit's parameter offset is `-Re(c1) r^2 / Re(lambda')`.
        if nf.l1.abs() <= 1e-9 * nf.term_scale {
            return Err(ContinuationError::DegenerateHopf {
                l1: nf.l1,
                scale: nf.term_scale,
            });
        }
        Self::from_hopf_normal_form(sys, x0, p0, k, &nf, settings)
    }

    /// [`from_hopf`](Self::from_hopf) with the normal form `nf` at the Hopf
    /// point computed by the caller (e.g. in extended precision where `l1`
    /// is small against its terms): only its sign must be known, `|l1|`
    /// above `nf.l1_error_bound`, else the point is degenerate and the
    /// side of the cycles unknown.
    pub fn from_hopf_normal_form(
        sys: &'a S,
        x0: &[f64],
        p0: &[f64],
        k: usize,
        nf: &HopfNormalForm,
        settings: CycleSettings,
    ) -> Result<Self, ContinuationError> {
        if nf.is_degenerate() {
            return Err(ContinuationError::DegenerateHopf {
                l1: nf.l1,
                scale: nf.term_scale,
            });
        }
        let omega = nf.omega;
        let dl = eigenvalue_derivative(sys, x0, p0, k, nf)?;
        let n = sys.dim();
        let scale = 1.0 + x0.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        let r = settings.start_amplitude * scale;
        let dp = -nf.c1.re * r * r / dl.re;
        let xp = crate::linalg::solve(jacobian(sys, x0, p0), &(-param_derivative(sys, x0, p0, k)))?;
        let mesh = Mesh::uniform(
            settings.mesh.ntst,
            settings.mesh.degree,
            settings.mesh.points,
        );
        let mut u = Vec::with_capacity(mesh.n_nodes() * n);
        let mut du = Vec::with_capacity(mesh.n_nodes() * n);
        for i in 0..mesh.ntst() {
            for l in 0..mesh.degree {
                let phase =
                    Complex64::new(0.0, 2.0 * std::f64::consts::PI * mesh.node_time(i, l)).exp();
                for j in 0..n {
                    let wave = 2.0 * (nf.q[j] * phase).re;
                    u.push(x0[j] + xp[j] * dp + r * wave);
                    du.push(wave);
                }
            }
        }
        let mut p = p0.to_vec();
        p[k] += dp;
        let period = 2.0 * std::f64::consts::PI / (omega + dl.im * dp);
        let guess = Cycle {
            mesh,
            u,
            period,
            p,
            n,
        };
        // Seed of the tangent: growing amplitude, d p / d r = -2 r Re(c1) / Re(lambda').
        let mut seed = du;
        seed.push(0.0);
        seed.push(-2.0 * r * nf.c1.re / dl.re);
        Self::from_cycle(sys, guess, k, Some(seed), settings)
    }

    /// Branch switching: the cycles born at a Hopf point located on a branch
    /// of equilibria (`event`), continued in the parameter it was located
    /// in ([`from_hopf`](Self::from_hopf)). `None` for a fold.
    pub fn from_hopf_event(
        sys: &'a S,
        event: &crate::events::Event,
        settings: CycleSettings,
    ) -> Option<Result<Self, ContinuationError>> {
        let (e, omega) = event.hopf()?;
        Some(Self::from_hopf(
            sys,
            &e.x,
            omega,
            &e.p,
            e.param_index,
            settings,
        ))
    }

    /// Starts from an approximate orbit (corrected at its parameter first);
    /// `seed` orients the tangent (default: increasing parameter). An orbit
    /// that already solves the system to the corrector's tolerances
    /// ([`solves_bordered`]: a cycle computed before, restarted) is taken as
    /// it is, bit for bit: a Newton step from it would move it by the
    /// rounding of the solve, and its extremes with it.
    pub fn from_cycle(
        sys: &'a S,
        guess: Cycle,
        k: usize,
        seed: Option<Vec<f64>>,
        settings: CycleSettings,
    ) -> Result<Self, ContinuationError> {
        if guess.mesh.ntst() < 2 {
            return Err(ContinuationError::Sparse(
                "a cycle mesh needs at least 2 intervals".into(),
            ));
        }
        // The node values do not depend on where the equations are imposed.
        let guess = Cycle {
            mesh: Mesh::with_points(
                guess.mesh.t.clone(),
                guess.mesh.degree,
                settings.mesh.points,
            ),
            ..guess
        };
        let coll = Collocation::new(sys, &guess, k);
        let mut z = coll.unknowns(&guess);
        let nz = z.len();
        // Correct along the seed when one is given (near a Hopf point the
        // amplitude is ill-determined at fixed parameter), else at fixed parameter.
        let seed = seed.unwrap_or_else(|| {
            let mut s = vec![0.0; nz];
            s[nz - 1] = 1.0;
            s
        });
        let start_at_fixed_parameter = seed[..nz - 1].iter().all(|v| *v == 0.0);
        let start_at_fold =
            seed[..nz - 2].iter().all(|v| *v == 0.0) && seed[nz - 2] != 0.0 && seed[nz - 1] == 0.0;
        let w = ArcWeights::at(&z, settings.param_floor);
        let z0 = z.clone();
        let row = w.row(&seed);
        if !solves_bordered(&coll, &z, &settings.corrector, &row, &z0) {
            newton_bordered(&coll, &mut z, &settings.corrector, &row, &z0)?;
        }
        let coll = Collocation::new(sys, &coll.cycle(&z), k);
        let jacobian = OrbitJacobian::new(coll.linearize(&z), sys.dim());
        let tangent = tangent_from(&jacobian, &seed, &w)?;
        let max_steps = settings.max_steps;
        let cycles = Cycles {
            jacobian: Some((z.clone(), jacobian)),
            spare: None,
            sys,
            k,
            ds: settings.step.ds,
            trivial_tol: settings.floquet.trivial_tol.unwrap_or(f64::INFINITY),
            multiplier_ntst: (0, 0),
            orbit_floor: (0.0, 0),
            settings,
            z,
            tangent,
            coll,
            held: start_at_fixed_parameter,
            start_at_fold,
            steps: 0,
            previous_param: f64::NAN,
            previous_mu: Vec::new(),
            previous_trivial_error: f64::INFINITY,
            largest_amplitude: Vec::new(),
            last_relative: None,
            last_deviation: Vec::new(),
            last_estimate: f64::INFINITY,
            last_ntst: 0,
            since_estimate: 0,
        };
        Ok(Driver::trace(cycles, max_steps))
    }
}

impl<'a, S: VectorField> Cycles<'a, S> {
    /// Takes one accepted step ([`predictor_corrector::step`], norm of the
    /// [`ArcWeights`] at the current orbit); returns the corrector's report
    /// and the step length.
    fn step(&mut self) -> Result<(NewtonReport, f64), ContinuationError> {
        let w = ArcWeights::at(&self.z, self.settings.param_floor);
        let norm = w.dot(&self.tangent, &self.tangent).sqrt();
        self.tangent.iter_mut().for_each(|v| *v /= norm);
        let mut curve = CycleStep {
            coll: &self.coll,
            z: &mut self.z,
            tangent: &mut self.tangent,
            w,
            corrector: &self.settings.corrector,
            k: self.k,
            jacobian: &mut self.jacobian,
            spare: &mut self.spare,
        };
        let stepped = predictor_corrector::step(&mut curve, &self.settings.step, &mut self.ds)?;
        Ok((stepped.report, stepped.ds))
    }

    /// Locates the zero of a test function `f(z, tangent)` between `z0`
    /// (tangent `t0`, where `f = f0`) and the orbit `ds` further (`f = f1`):
    /// regula falsi (Illinois, [`crate::root::illinois`]) on the arclength,
    /// each trial corrected onto
    /// the branch. Folds of cycles use `f = dp/ds`; user points `f = p - p_user`.
    /// Returns the orbit (without error estimate) and the branch's tangent
    /// there, with its arclength from `z0`.
    #[allow(clippy::too_many_arguments)]
    fn locate(
        &self,
        coll: &Collocation<'a, S>,
        z0: &[f64],
        t0: &[f64],
        (f0, f1): (f64, f64),
        ds: f64,
        f: impl Fn(&[f64], &[f64]) -> Result<f64, ContinuationError>,
    ) -> Result<((CyclePoint, Vec<f64>), f64), ContinuationError> {
        let mut best = None;
        let w = ArcWeights::at(z0, self.settings.param_floor);
        crate::root::illinois(
            |sigma| {
                let (z, rep, at) = correct_along(coll, (z0, t0, sigma), &w, &LOCATOR, None)?;
                let t = tangent_from(&at.jacobian, t0, &w)?;
                let fz = f(&z, &t)?;
                best = Some(((point_at(coll, &z, &at.jacobian, &t, rep)?, t), sigma));
                Ok(fz)
            },
            (0.0, f0),
            (ds, f1),
            1e-12 * ds.abs(),
            60,
        )?;
        best.ok_or(ContinuationError::Singular)
    }

    /// A located orbit with its error estimate, read as `reading`.
    fn estimated(&self, (mut pt, t): (CyclePoint, Vec<f64>), reading: Reading) -> CyclePoint {
        pt.error_estimate = self.error_estimate(&pt, &t, reading);
        pt
    }

    /// The located orbit `pt` (tangent `t` there) solved again with the
    /// parameter fixed at `target` (Newton on the collocation system bordered
    /// by `p_k = target`, from `pt`): a user point then lies on the value
    /// asked for, not within the locator's tolerance of it (about `1e-11`
    /// relative). `t0`, on the mesh of `coll0`, orients the tangent. Like the orbits of the branch,
    /// it is then put on a mesh fine enough for `mesh_tol` (doubled up to
    /// `ntst_max` while the error estimate exceeds it and doubling divides
    /// it by 4 or more; see `refine`). Where that Newton fails — at a fold
    /// of cycles the orbit at fixed parameter is ill-determined — `pt` is
    /// kept as located, with its own parameter value.
    fn pin(
        &self,
        coll0: &Collocation<'a, S>,
        (pt, t): (CyclePoint, Vec<f64>),
        t0: &[f64],
        target: f64,
    ) -> Result<CyclePoint, ContinuationError> {
        let solve = |coll: &Collocation<'a, S>, orbit: &Cycle| {
            let mut z = coll.unknowns(orbit);
            let nz = z.len();
            z[nz - 1] = target;
            let anchor = z.clone();
            let (rep, at) =
                correct_bordered(coll, &mut z, &LOCATOR, &unit_row(nz, nz - 1), &anchor)?;
            let w = ArcWeights::at(&z, self.settings.param_floor);
            // `t0` lives on the mesh of `coll0`; a refined orbit is oriented
            // by it moved onto its own mesh.
            let reference = if coll.mesh.t == coll0.mesh.t {
                t0.to_vec()
            } else {
                self.tangent_on(&coll0.mesh, t0, &coll.mesh, &z)
            };
            let t = tangent_from(&at.jacobian, &reference, &w)?;
            let mut pinned = point_at(coll, &z, &at.jacobian, &t, rep)?;
            pinned.error_estimate = self.error_estimate(&pinned, &t, Reading::AtParameter);
            Ok::<_, ContinuationError>(pinned)
        };
        let Ok(mut pinned) = solve(coll0, &pt.cycle) else {
            return Ok(self.estimated((pt, t), Reading::AtParameter));
        };
        loop {
            let ntst = pinned.cycle.mesh.ntst();
            if pinned.error_estimate <= self.settings.mesh.tol()
                || ntst >= self.settings.mesh.ntst_max
            {
                return Ok(pinned);
            }
            let finer = equidistribute(&pinned.cycle, (2 * ntst).min(self.settings.mesh.ntst_max));
            match solve(&Collocation::new(self.sys, &finer, self.k), &finer) {
                Ok(finer) if finer.error_estimate <= 0.25 * pinned.error_estimate => {
                    pinned = finer;
                }
                // The rounding floor, or no solution on the finer mesh.
                _ => return Ok(pinned),
            }
        }
    }
}

impl<S: VectorField> Cycles<'_, S> {
    /// Whether the branch went through the equilibrium between the last
    /// orbit and `pt`: the last one had shrunk and `pt` is larger again, and
    /// either the last one was below [`PASSED`] of the branch's largest
    /// amplitude (on every observable) or `pt` is the last one turned
    /// around (their deviations from their means anticorrelated: through
    /// the equilibrium the phase condition keeps the phase and the small
    /// orbit changes sign, half a period). A branch through a Hopf point
    /// whose parameter turn fell between the steps (or was too flat to be
    /// seen) would otherwise retrace itself: a stranger's subcritical rig
    /// stepped from 8 % of its largest amplitude through the Hopf point
    /// and back along its stable cycles.
    fn passed_through_equilibrium(&mut self, pt: &CyclePoint) -> bool {
        let deviation = deviation(&pt.cycle);
        let turned_around = deviation.len() == self.last_deviation.len()
            && crate::defining::dot(&deviation, &self.last_deviation) < 0.0;
        self.last_deviation = deviation;
        let amplitudes: Vec<f64> = pt
            .extremes(self.sys)
            .iter()
            .map(|(lo, hi)| hi - lo)
            .collect();
        if self.largest_amplitude.len() != amplitudes.len() {
            self.largest_amplitude = vec![0.0; amplitudes.len()];
        }
        for (big, a) in self.largest_amplitude.iter_mut().zip(&amplitudes) {
            *big = big.max(*a);
        }
        let relative = amplitudes
            .iter()
            .zip(&self.largest_amplitude)
            .map(|(a, big)| if *big > 0.0 { a / big } else { 1.0 })
            .fold(0.0f64, f64::max);
        let passed = matches!(
            self.last_relative,
            Some((last, shrinking)) if shrinking && (last < PASSED || turned_around) && relative > last
        );
        let shrinking = self.last_relative.is_some_and(|(last, _)| relative < last);
        self.last_relative = Some((relative, shrinking));
        passed
    }

    /// How well the corrector fixes an orbit's parameter, relative to the
    /// parameter itself: `step_tol |p|`. A sign change of `dp/ds` whose
    /// parameter excursion stays below it is noise, not a fold: near a
    /// nearly degenerate Hopf point (`l1` close to zero) the branch is flat
    /// in the parameter far below this resolution (granite rig: excursions of
    /// 4e-12 relative, against real folds at 1e-7 and more).
    fn parameter_resolution(&self, z: &[f64]) -> f64 {
        self.settings.corrector.step_tol * z[z.len() - 1].abs()
    }
}

/// How often a step across whose orbits the parameter's turn could not be
/// located is taken again, a quarter as long, from where it started
/// ([`Curve::advance`]).
const TURN_RETRIES: usize = 3;

/// How often a step that failed is taken again from the previous orbit on a
/// finer mesh ([`Cycles::stepped_point`]).
const REFINEMENT_RETRIES: usize = 3;

/// Newton iterations allowed to correct an orbit moved onto a finer mesh
/// before a retried step (three times the corrector's default).
const REMESH_ITERATIONS: usize = 30;

/// Where a step started: the collocation system, the orbit's unknowns and
/// the tangent.
type StepStart<'a, S> = (Collocation<'a, S>, Vec<f64>, Vec<f64>);

/// A step that crossed a range bound ([`Cycles::orbit_on_bound`]): from
/// `z0` (tangent `t0`, on the mesh of `coll0`) to the
/// arclength `sigma` along it, where the parameter is `p_end` beyond the
/// bound — the step's end, or where the parameter turned (`turned`).
struct Crossing<'c, 'a, S: VectorField> {
    coll0: &'c Collocation<'a, S>,
    z0: &'c [f64],
    t0: &'c [f64],
    sigma: f64,
    p_end: f64,
    turned: bool,
}

impl<'a, S: VectorField> Cycles<'a, S> {
    /// Corrects the orbit just moved onto a finer mesh (up to
    /// [`REMESH_ITERATIONS`] Newton iterations) and recomputes its tangent
    /// there: on stiff orbits the interpolated orbit can lie farther from the
    /// solution than the corrector's iterations reach (on the stiff branch of
    /// `tests/hard_cases.rs`, 11 iterations from a residual of 2e2), and the
    /// interpolated tangent can be off by more than a step may turn.
    fn settle(&mut self) -> Result<(), ContinuationError> {
        let patient = NewtonSettings {
            max_iter: REMESH_ITERATIONS,
            ..self.settings.corrector
        };
        self.correct_on_mesh(&patient)?;
        let w = ArcWeights::at(&self.z, self.settings.param_floor);
        self.tangent = tangent(&self.coll, &self.z, &self.tangent, &w)?;
        Ok(())
    }

    /// One step from the current orbit, on the mesh it is given
    /// ([`Self::mesh_size`], re-equidistributed every `adapt_every` steps),
    /// and the orbit reached, refined as it needs; returns it with the step
    /// length and where the step started. On stiff orbits the interpolation
    /// onto a new mesh (or of a step's result onto a finer one) can be a
    /// guess Newton's method diverges from: the step is then taken again from
    /// the converged orbit moved onto twice its intervals and corrected there
    /// (up to [`REMESH_ITERATIONS`] Newton iterations), with half the first
    /// step length, up to [`REFINEMENT_RETRIES`] times.
    fn stepped_point(&mut self) -> Result<(CyclePoint, f64, StepStart<'a, S>), ContinuationError> {
        self.held = false;
        let converged = (self.coll.cycle(&self.z), self.tangent.clone());
        let ds = self.ds;
        let mut ntst = self.mesh_size();
        let mut retries = 0;
        loop {
            if retries > 0
                || ntst != self.coll.mesh.ntst()
                || (self.settings.mesh.adapt_every > 0
                    && self.steps.is_multiple_of(self.settings.mesh.adapt_every))
            {
                self.adapt(ntst);
            }
            let settled = if retries > 0 { self.settle() } else { Ok(()) };
            let attempt = settled.and_then(|()| {
                let (z0, t0) = (self.z.clone(), self.tangent.clone());
                let (rep, ds) = self.step()?;
                // The system the step started from is the one it was taken
                // on: `self.coll` is always built on the orbit `self.z`
                // (`from_cycle`, `adapt`, `restore`, `correct_on_mesh` and
                // here), so it is kept, not built again.
                let next = Collocation::new(self.sys, &self.coll.cycle(&self.z), self.k);
                let coll0 = std::mem::replace(&mut self.coll, next);
                Ok((self.refined_point(rep)?, ds, (coll0, z0, t0)))
            });
            match attempt {
                Ok(stepped) => return Ok(stepped),
                Err(ContinuationError::Newton { .. } | ContinuationError::StepTooSmall { .. })
                    if retries < REFINEMENT_RETRIES =>
                {
                    retries += 1;
                    self.restore(converged.clone());
                    ntst = (2 * converged.0.mesh.ntst()).min(self.settings.mesh.ntst_max);
                    self.ds = ds * 0.5f64.powi(retries as i32);
                }
                // What the engine's own advice would say was done: say so.
                Err(ContinuationError::Newton {
                    context,
                    iterations,
                    residual,
                    step,
                    reason,
                    ..
                }) if retries > 0 => {
                    return Err(ContinuationError::Newton {
                        context: format!(
                            "{context} (the step taken {} times from the last orbit, on up to {} \
                             mesh intervals, the last with ds = {:.1e})",
                            retries + 1,
                            self.coll.mesh.ntst(),
                            self.ds
                        ),
                        iterations,
                        residual,
                        step,
                        reason,
                        hint: "smaller steps on finer meshes did not correct it",
                    })
                }
                Err(e) => return Err(e),
            }
        }
    }
}

/// One step of a [`Cycles`] as a [`CurveProblem`]: the collocation
/// system closed by the pseudo-arclength condition in the norm `w`.
struct CycleStep<'b, 'a, S: VectorField> {
    coll: &'b Collocation<'a, S>,
    z: &'b mut Vec<f64>,
    tangent: &'b mut Vec<f64>,
    w: ArcWeights,
    corrector: &'b NewtonSettings,
    k: usize,
    /// Where the accepted step keeps its orbit's Jacobian.
    jacobian: &'b mut Option<(Vec<f64>, OrbitJacobian)>,
    /// The storage the corrections linearize into (the Jacobian the last
    /// accepted step replaced, or a rejected correction's).
    spare: &'b mut Option<OrbitJacobian>,
}

impl<S: VectorField> CurveProblem for CycleStep<'_, '_, S> {
    type Point = (Vec<f64>, BorderedPoint);
    type Tangent = Vec<f64>;

    fn correct(&mut self, ds: f64) -> Result<Corrected<Self::Point>, ContinuationError> {
        let (z, report, at) = correct_along(
            self.coll,
            (self.z, self.tangent, ds),
            &self.w,
            self.corrector,
            self.spare.take(),
        )?;
        Ok(Corrected {
            point: (z, at),
            report,
            ds,
            constrained: false,
        })
    }

    /// From the corrector's last linearization, at the orbit.
    fn tangent(&mut self, (_, at): &mut Self::Point) -> Result<Vec<f64>, ContinuationError> {
        tangent_from(&at.jacobian, self.tangent, &self.w)
    }

    fn turn(&self, tangent: &Vec<f64>) -> f64 {
        self.w.dot(tangent, self.tangent)
    }

    fn accept(&mut self, (z, at): Self::Point, tangent: Vec<f64>) -> Result<(), ContinuationError> {
        if let Some((_, replaced)) = self.jacobian.replace((z.clone(), at.jacobian)) {
            *self.spare = Some(replaced);
        }
        *self.z = z;
        *self.tangent = tangent;
        Ok(())
    }

    fn location(&self) -> (String, f64) {
        (self.coll.sys.param_name(self.k), self.z[self.z.len() - 1])
    }
}

/// Newton settings of located points (folds, user points), tighter than the
/// corrector's, with more iterations: a turn of the parameter at the Hopf
/// point the branch returns to is a singular solution of the collocation
/// system (zero amplitude), where Newton's method converges only linearly
/// until the last few iterations (`tests/cycles.rs`, Brockley's inertial
/// branch back to its Hopf point: 15 iterations left the step at 1e-9, the
/// residual at 1e-17, in the implicit form of the force balance).
const LOCATOR: NewtonSettings = NewtonSettings {
    step_tol: 1e-13,
    residual_tol: 1e-12,
    max_iter: 30,
};

/// Whether the located orbit `lpc` is a fold of cycles: a nontrivial
/// multiplier within `max(multiplier_error, FOLD_MULTIPLIER)` of 1.
fn is_fold(lpc: &CyclePoint, n: usize) -> bool {
    let band = multiplier_error(n, lpc.trivial_error).max(FOLD_MULTIPLIER);
    lpc.multipliers
        .iter()
        .enumerate()
        .any(|(i, z)| Some(i) != lpc.trivial && (*z - 1.0).norm() <= band)
}

/// The orbit at `z` (its collocation Jacobian `jacobian`) with its Floquet
/// multipliers.
fn point_at<S: VectorField>(
    coll: &Collocation<S>,
    z: &[f64],
    jacobian: &OrbitJacobian,
    tangent: &[f64],
    newton: NewtonReport,
) -> Result<CyclePoint, ContinuationError> {
    let n = coll.sys.dim();
    let (mu, trivial) = multipliers_and_trivial(jacobian.reduction(), jacobian.lin.trace_integral)?;
    let trivial_error = trivial.map_or(f64::INFINITY, |t| (mu[t] - 1.0).norm());
    let error = multiplier_error(n, trivial_error);
    let nontrivial: Vec<Complex64> = mu
        .iter()
        .enumerate()
        .filter(|(i, _)| Some(*i) != trivial)
        .map(|(_, z)| *z)
        .collect();
    let n_unstable = nontrivial.iter().filter(|z| z.norm() > 1.0 + error).count();
    let near = nontrivial
        .iter()
        .map(|z| z.norm())
        .filter(|r| (r - 1.0).abs() <= error)
        .max_by(|a, b| (a - 1.0).abs().total_cmp(&(b - 1.0).abs()));
    let stability = if n_unstable > 0 {
        Stability::Unstable
    } else if nontrivial.len() + 1 < n {
        Stability::Undetermined {
            missing: n - 1 - nontrivial.len(),
        }
    } else if let Some(modulus) = near {
        Stability::Undecidable { modulus, error }
    } else {
        Stability::Stable
    };
    Ok(CyclePoint {
        cycle: coll.cycle(z),
        multipliers: mu,
        trivial,
        trivial_error,
        extremes: OnceLock::new(),
        error_estimate: 0.0,
        n_unstable,
        stability,
        newton,
        dp_ds: tangent[tangent.len() - 1],
        events: Vec::new(),
    })
}

impl<S: VectorField> Curve for Cycles<'_, S> {
    type Point = CyclePoint;

    fn start(&mut self) -> Result<(CyclePoint, Option<Stop>), ContinuationError> {
        // The first orbit, like every other, on a mesh fine enough for it.
        let result = self.refined_point(NewtonReport::NONE);
        self.steps += 1;
        Ok(self.handed_out(result?, false, None))
    }

    fn advance(&mut self) -> Result<Advance<CyclePoint>, ContinuationError> {
        // The branch came back to a Hopf point (see `Stop::HopfPoint`).
        let mut at_hopf = false;
        // The range bound the step went past, which the orbit handed out
        // lies on.
        let mut landed = None;
        let mut retries = 0;
        let result = loop {
            let attempt = self
                .stepped_point()
                .and_then(|(mut pt, ds, (coll0, z0, t0))| {
                    let nz = z0.len();
                    // Where the parameter turned within the step: the
                    // arclength of the turn from `z0`, and the turn.
                    let mut turn = None;
                    // From a fold the parameter's turn within the first
                    // step is the fold the branch started at.
                    let from_fold = self.steps == 1 && self.start_at_fold;
                    if t0[nz - 1] * pt.dp_ds < 0.0 && !from_fold {
                        let located =
                            self.locate(&coll0, &z0, &t0, (t0[nz - 1], pt.dp_ds), ds, |_, t| {
                                Ok(t[nz - 1])
                            });
                        let lpc = match located {
                            Ok((lpc, sigma)) => {
                                turn = Some((sigma, lpc.0.cycle.p[self.k]));
                                self.estimated(lpc, Reading::Point)
                            }
                            // The turn of the parameter between the two orbits
                            // is not found (a long step over a Hopf point,
                            // where the orbit collapses): taken again shorter.
                            Err(e) => return Ok(Err((e, ds, (coll0, z0, t0)))),
                        };
                        let p_fold = lpc.cycle.p[self.k];
                        let excursion = (p_fold - z0[nz - 1])
                            .abs()
                            .max((p_fold - pt.cycle.p[self.k]).abs());
                        if collapsed(self.sys, &lpc, &coll0.cycle(&z0)) {
                            at_hopf = true;
                        } else if is_fold(&lpc, self.sys.dim())
                            && excursion > self.parameter_resolution(&z0)
                        {
                            pt.attach(CycleEvent::Fold, lpc);
                        }
                    }
                    self.detect_multiplier_crossings(&mut pt, &coll0, (&z0, &t0), ds)?;
                    // The mesh (hence the length of z) may have been refined since z0.
                    let (p0, p1) = (z0[nz - 1], self.z[self.z.len() - 1]);
                    for &target in &self.settings.user_points {
                        if (p0 - target) * (p1 - target) < 0.0 || p1 == target {
                            let (user, _) = self.locate(
                                &coll0,
                                &z0,
                                &t0,
                                (p0 - target, p1 - target),
                                ds,
                                |z, _| Ok(z[nz - 1] - target),
                            )?;
                            let user = self.pin(&coll0, user, &t0, target)?;
                            pt.attach(CycleEvent::User { value: target }, user);
                        }
                    }
                    // The range's bound crossed first: where the parameter
                    // turned beyond it, on the way to the turn.
                    let (sigma, p_end, turned) = match turn {
                        Some((sigma, p_turn)) if self.bound_crossed(p_turn).is_some() => {
                            (sigma, p_turn, true)
                        }
                        _ => (ds, p1, false),
                    };
                    if let Some(bound) = self.bound_crossed(p_end).filter(|_| !at_hopf) {
                        let step = Crossing {
                            coll0: &coll0,
                            z0: &z0,
                            t0: &t0,
                            sigma,
                            p_end,
                            turned,
                        };
                        pt = self.orbit_on_bound(&step, bound, pt)?;
                        landed = Some(bound);
                    }
                    Ok(Ok(pt))
                });
            match attempt {
                Ok(Ok(pt)) => break Ok(pt),
                Ok(Err((_, ds, (coll0, z0, t0)))) if retries < TURN_RETRIES => {
                    retries += 1;
                    self.restore((coll0.cycle(&z0), t0));
                    self.ds = 0.25 * ds;
                }
                // What the engine's own advice would say was done: say so.
                Ok(Err((
                    ContinuationError::Newton {
                        context,
                        iterations,
                        residual,
                        step,
                        reason,
                        ..
                    },
                    ds,
                    _,
                ))) => {
                    break Err(ContinuationError::Newton {
                        context: format!(
                            "{context} (locating the turn of {} between two orbits; the step \
                             taken {} times, the last with ds = {ds:.1e})",
                            self.sys.param_name(self.k),
                            retries + 1
                        ),
                        iterations,
                        residual,
                        step,
                        reason,
                        hint: "shorter steps did not locate it",
                    })
                }
                Ok(Err((e, ..))) | Err(e) => break Err(e),
            }
        };
        self.steps += 1;
        let pt = result?;
        if self.passed_through_equilibrium(&pt) {
            // This orbit retraces the branch shifted by half a period: not
            // handed out.
            return Ok(Advance::End(Stop::HopfPoint {
                param: self.previous_param,
            }));
        }
        let (pt, stop) = self.handed_out(pt, at_hopf, landed);
        Ok(Advance::Point(pt, stop))
    }
}

impl<'a, S: VectorField> Cycles<'a, S> {
    /// The range bound (`p_min` or `p_max`) that a step from inside the
    /// range to the parameter `p1` reached or went past.
    fn bound_crossed(&self, p1: f64) -> Option<f64> {
        let (p_min, p_max) = (self.settings.p_min, self.settings.p_max);
        if p1 < p_min {
            Some(p_min)
        } else if p1 > p_max {
            Some(p_max)
        } else {
            None
        }
    }

    /// The orbit on the range bound `bound` that `step` crossed on its way
    /// to the branch's current orbit `beyond`, with the branch's state put
    /// on it. Predicted along the tangent of whichever end of the step lies
    /// nearer the bound in the parameter (its start where the parameter
    /// turned beyond the bound), solved with the parameter held on the
    /// bound, and refined as every orbit of the branch is
    /// ([`Self::refined_point`]: the mesh its error estimate and its
    /// multipliers need). Where that correction fails or reaches an orbit
    /// the parameter runs the other way on (near a fold of cycles the orbit
    /// at a fixed parameter is ill-determined, and there are two), the
    /// orbit is located on the step like a user point (the zero of `p -
    /// bound`, [`Self::locate`]) and kept as located, within the locator's
    /// tolerance of the bound. It carries the events of `beyond` that lie
    /// within the range (those the branch met before the bound).
    fn orbit_on_bound(
        &mut self,
        step: &Crossing<'_, 'a, S>,
        bound: f64,
        beyond: CyclePoint,
    ) -> Result<CyclePoint, ContinuationError> {
        let (z0, t0) = (step.z0, step.t0);
        let p0 = z0[z0.len() - 1];
        let crossed = (self.coll.cycle(&self.z), self.tangent.clone());
        if step.turned || (bound - p0).abs() < (bound - step.p_end).abs() {
            self.restore((step.coll0.cycle(z0), t0.to_vec()));
        }
        let last = self.z.len() - 1;
        let s = (bound - self.z[last]) / self.tangent[last];
        // The direction the parameter runs in at the end predicted from:
        // the orbit reached has the same (not the one across a fold).
        let direction = self.tangent[last];
        let patient = NewtonSettings {
            max_iter: REMESH_ITERATIONS,
            ..self.settings.corrector
        };
        let mut held = || {
            if !s.is_finite() {
                return Err(ContinuationError::Singular);
            }
            for (z, t) in self.z.iter_mut().zip(&self.tangent) {
                *z += s * t;
            }
            self.z[last] = bound;
            self.held = true;
            let rep = self.correct_on_mesh(&patient)?;
            let w = ArcWeights::at(&self.z, self.settings.param_floor);
            if let Some((_, jacobian)) = &self.jacobian {
                self.tangent = tangent_from(jacobian, &self.tangent, &w)?;
            }
            let last = self.z.len() - 1;
            if self.tangent[last] * direction > 0.0 {
                Ok(rep)
            } else {
                Err(ContinuationError::Singular)
            }
        };
        let mut on_bound = match held() {
            Ok(rep) => self.refined_point(rep)?,
            Err(_) => {
                self.held = false;
                self.restore(crossed);
                let nz = z0.len();
                let (located, _) = self.locate(
                    step.coll0,
                    z0,
                    t0,
                    (p0 - bound, step.p_end - bound),
                    step.sigma,
                    |z, _| Ok(z[nz - 1] - bound),
                )?;
                self.restore((located.0.cycle.clone(), located.1.clone()));
                self.estimated(located, Reading::AtParameter)
            }
        };
        let (p_min, p_max) = (self.settings.p_min, self.settings.p_max);
        on_bound.events = beyond
            .events
            .into_iter()
            .filter(|e| (p_min..=p_max).contains(&e.point.cycle.p[self.k]))
            .collect();
        Ok(on_bound)
    }

    /// The orbit `pt` handed out, with the reason the branch ends on it
    /// (`at_hopf`: its step went through the equilibrium at a Hopf point;
    /// `landed`: its step went past this range bound, and `pt` is the orbit
    /// on it). A branch that passed through the equilibrium between steps
    /// ends before this ([`Curve::advance`]).
    fn handed_out(
        &mut self,
        pt: CyclePoint,
        at_hopf: bool,
        landed: Option<f64>,
    ) -> (CyclePoint, Option<Stop>) {
        let p = pt.cycle.p[self.k];
        self.previous_mu.clone_from(&pt.multipliers);
        self.previous_trivial_error = pt.trivial_error;
        self.previous_param = p;
        let (p_min, p_max) = (self.settings.p_min, self.settings.p_max);
        let stop = if at_hopf {
            Some(Stop::HopfPoint { param: p })
        } else if let Some(bound) = landed {
            Some(Stop::Bound {
                index: self.k,
                value: p,
                bound,
            })
        } else if p <= p_min || p >= p_max {
            // The first orbit, outside the range or on its bound.
            Some(Stop::Bound {
                index: self.k,
                value: p,
                bound: if p <= p_min { p_min } else { p_max },
            })
        } else if let Some(max_period) = self
            .settings
            .max_period
            .filter(|max| pt.cycle.period > *max)
        {
            Some(Stop::MaxPeriod {
                period: pt.cycle.period,
                max_period,
            })
        } else {
            None
        };
        (pt, stop)
    }
}
