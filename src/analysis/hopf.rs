//! The stick-slip onset: the Hopf point of steady sliding in the stiffness.
//!
//! The steady branch is continued in `kappa` from a stable stiffness downward;
//! the Hopf test function's sign change is located by Newton's method on the
//! minimally augmented Hopf system (engine, [`continuation::locate_hopf`]). The
//! closed forms of Appendix C are not used to find the point.

use crate::appendix_c;
use crate::error::NumericalError;
use crate::model::{full_state, steady_state, DrivenBlock, ModelKind};
use crate::params::{Param, Params};
use continuation::normal_form::hopf_normal_form_extended;
use continuation::normal_form::hopf_series;
use continuation::normal_form::{
    eigenvalue_derivative, hopf_normal_form, onset_law, HopfNormalForm,
};
use continuation::system::jacobian;
use continuation::DoubleDouble;
use continuation::StepControl;
use continuation::{count_unstable, eigenvalues};
use continuation::{
    AsIs, Branch, Complex64, ContinuationError, ContinuationSettings, Direction, EventKind,
    NewtonSettings, VectorField, Wrap,
};

/// Sub- or supercritical onset, from the sign of `l1` (JSON and CSV: its
/// [`name`](Criticality::name)). The default only fills the record a CSV
/// header is named from.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Criticality {
    /// `l1 < 0`: stick-slip amplitude grows continuously below `kappa_c`.
    Supercritical,
    /// `l1 > 0`: an unstable cycle surrounds stable sliding; the onset is hysteretic.
    Subcritical,
    /// `|l1|` within its rounding-error bound: the cubic terms do not decide
    /// (e.g. quasi-static plain RR law, where `l1 = 0` exactly).
    #[default]
    Degenerate,
}

impl Criticality {
    /// The onset type from `l1` and the bound on its rounding error: the
    /// sign of `l1` counts only where `|l1|` exceeds the bound.
    pub fn of(l1: f64, error_bound: f64) -> Criticality {
        // NaN in either compares as "not above": degenerate, never a sign.
        match l1.abs().partial_cmp(&error_bound) {
            Some(std::cmp::Ordering::Greater) if l1 < 0.0 => Criticality::Supercritical,
            Some(std::cmp::Ordering::Greater) => Criticality::Subcritical,
            _ => Criticality::Degenerate,
        }
    }

    /// `supercritical`, `subcritical` or `degenerate`.
    pub fn name(self) -> &'static str {
        match self {
            Criticality::Supercritical => "supercritical",
            Criticality::Subcritical => "subcritical",
            Criticality::Degenerate => "degenerate",
        }
    }
}

/// The normal form at the onset and what it predicts for the emerging cycle.
#[derive(Clone, Debug)]
pub struct Onset {
    /// First Lyapunov coefficient in docs/model.md's coordinates and normalization.
    pub l1: f64,
    /// Cubic normal-form coefficient `c1` (`l1 = Re c1 / omega`).
    pub c1: Complex64,
    /// Size of the terms `l1` is made of.
    pub l1_scale: f64,
    /// Bound on the rounding error of `l1`; `|l1|` below it is "degenerate".
    pub l1_error_bound: f64,
    /// The arithmetic `l1` was computed in.
    pub arithmetic: Arithmetic,
    /// Sub-, supercritical or degenerate.
    pub criticality: Criticality,
    /// `d lambda / d kappa` of the critical eigenvalue (transversality).
    pub dlambda_dkappa: Complex64,
    /// `C` in `Delta_s ~ C sqrt|kappa - kappa_c|` (peak-to-peak spring force);
    /// `None` at a degenerate point.
    pub amplitude_coefficient: Option<f64>,
    /// `-1`: the cycle exists for `kappa < kappa_c`; `+1`: for `kappa > kappa_c`.
    pub side: Option<f64>,
    /// `d Omega / d kappa` of the cycle's angular frequency at onset.
    pub frequency_slope: Option<f64>,
}

/// A located Hopf point of steady sliding.
#[derive(Clone, Debug)]
pub struct HopfPoint {
    /// Critical stiffness `kappa_c = K_c D0 / W`.
    pub kappa_c: f64,
    /// Angular frequency at onset, units `V0/D0`.
    pub omega_c: f64,
    /// The steady state at onset as `(s, v, theta)`.
    pub state: [f64; 3],
    /// Eigenvalues at onset, by decreasing real part.
    pub eigenvalues: Vec<Complex64>,
    /// Newton iterations of the location and its final residual.
    pub newton_iterations: usize,
    pub residual: f64,
    /// Accepted continuation steps before the point was bracketed.
    pub steps: usize,
    /// Normal form and onset law.
    pub onset: Onset,
}

/// The arithmetic a normal-form coefficient was computed in (JSON: its
/// [`name`](Arithmetic::name)).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Arithmetic {
    /// `f64` throughout.
    Double,
    /// The Hopf point and the normal form recomputed in double-double
    /// ([`continuation::normal_form::hopf_normal_form_extended`]), where `f64` left fewer than
    /// [`EXTENDED_DIGITS`] digits.
    DoubleDouble,
}

impl Arithmetic {
    /// `double` or `double-double` (the name used in JSON).
    pub fn name(self) -> &'static str {
        match self {
            Arithmetic::Double => "double",
            Arithmetic::DoubleDouble => "double-double",
        }
    }
}

/// Significant digits of `l1` below which the normal form is recomputed in
/// double-double: the `f64` bound above `10^-8 |l1|`.
pub const EXTENDED_DIGITS: i32 = 8;

/// The normal form of the Hopf point of `block` at state `x` (model
/// coordinates, which are docs/model.md's) and parameters `p`, located to
/// within `kappa_error` in the stiffness.
///
/// The bound on `l1` adds, to the engine's rounding bound, the change of
/// `l1` over the location error, `|dl1/dkappa| kappa_error`, the slope taken
/// by a central difference over `1e-6 kappa` (the equilibrium does not move
/// with `kappa`). Where that bound leaves fewer than [`EXTENDED_DIGITS`]
/// digits (small inertia on the plain Rice–Ruina law: `l1 ~ m` under terms
/// of order one), the point and the normal form are recomputed in
/// double-double and the location error is that of its Newton refinement.
/// The double-double result is kept only where it agrees with the `f64` one
/// within the `f64` bound; its bound adds the rounding of the parameters
/// themselves ([`input_rounding`]), which `f64` rounding hides.
pub fn onset_at<S: VectorField>(
    block: &S,
    x: &[f64],
    p: &[f64],
    omega: f64,
    kappa_error: f64,
) -> Result<Onset, NumericalError> {
    let (nf, arithmetic) = resolved_normal_form(block, x, p, omega, kappa_error)?;
    let k = Param::Kappa as usize;
    let dl = eigenvalue_derivative(block, x, p, k, &nf)?;
    let criticality = Criticality::of(nf.l1, nf.l1_error_bound);
    let degenerate = criticality == Criticality::Degenerate;
    let law = (!degenerate).then(|| onset_law(&nf, dl, 0));
    Ok(Onset {
        l1: nf.l1,
        c1: nf.c1,
        l1_scale: nf.term_scale,
        l1_error_bound: nf.l1_error_bound,
        arithmetic,
        criticality,
        dlambda_dkappa: dl,
        amplitude_coefficient: law.map(|l| l.coefficient),
        side: law.map(|l| l.side),
        frequency_slope: law.map(|l| l.frequency_slope),
    })
}

/// The normal form of the Hopf point of `block` at `x`, `p` (frequency
/// `omega`, located to within `kappa_error` in the stiffness) in the
/// arithmetic its error bound asks for, as described at [`onset_at`]: every
/// onset type stickslip reports (`hopf`, each point of a `diagram` curve,
/// the start of a cycle branch) comes from here, so no command calls
/// degenerate what another resolves. `block` may be in any coordinates
/// (the cycles' log variables too): the sign of `l1` does not depend on them.
pub fn resolved_normal_form<S: VectorField>(
    block: &S,
    x: &[f64],
    p: &[f64],
    omega: f64,
    kappa_error: f64,
) -> Result<(HopfNormalForm, Arithmetic), NumericalError> {
    let nf64 = hopf_normal_form(block, x, p, omega)?;
    let k = Param::Kappa as usize;
    let h = 1e-6 * p[k].abs();
    let l1_at = |dk: f64| {
        let mut q = p.to_vec();
        q[k] += dk;
        hopf_normal_form(block, x, &q, omega).map(|n| n.l1)
    };
    let slope = ((l1_at(h)? - l1_at(-h)?) / (2.0 * h)).abs();
    let bound64 = nf64.l1_error_bound + slope * kappa_error;
    let extended = (bound64 > 10f64.powi(-EXTENDED_DIGITS) * nf64.l1.abs())
        .then(|| hopf_normal_form_extended(block, x, p, k, &nf64).ok())
        .flatten()
        .map(|ext| {
            let location = ext
                .param_step
                .max(4.0 * DoubleDouble::EPSILON * ext.param.hi().abs());
            let mut nf = ext.normal_form;
            nf.l1_error_bound += slope * location + input_rounding(block, x, p, &nf64);
            nf
        })
        .filter(|nf| (nf.l1 - nf64.l1).abs() <= bound64 + nf.l1_error_bound);
    Ok(match extended {
        Some(nf) => (nf, Arithmetic::DoubleDouble),
        None => {
            let mut nf = nf64;
            nf.l1_error_bound = bound64;
            (nf, Arithmetic::Double)
        }
    })
}

/// The change of `l1` from the rounding of the scene's parameters to `f64`
/// (a decimal `A = 0.012` is stored to within `eps/2` relative):
/// `sum_i |dl1/dp_i| |p_i| eps/2` over the given parameters, the stiffness
/// excepted (it is solved for). The slopes are double-double central
/// differences over `1e-6 p_i`, each at its own refined Hopf point. Only the
/// double-double path needs it: in `f64` the rounding bound is far larger.
/// A slope that cannot be computed counts as `|l1| / |p_i|` per unit
/// relative change (a power law of degree one).
fn input_rounding<S: VectorField>(block: &S, x: &[f64], p: &[f64], nf64: &HopfNormalForm) -> f64 {
    let k = Param::Kappa as usize;
    let l1_at = |i: usize, factor: f64| {
        let mut q = p.to_vec();
        q[i] *= factor;
        hopf_normal_form_extended(block, x, &q, k, nf64).map(|e| e.normal_form.l1)
    };
    let h = 1e-6;
    (0..p.len())
        .filter(|&i| i != k && p[i] != 0.0 && p[i].is_finite())
        .map(|i| {
            // d l1 / d ln p_i
            let slope = match (l1_at(i, 1.0 + h), l1_at(i, 1.0 - h)) {
                (Ok(up), Ok(down)) => ((up - down) / (2.0 * h)).abs(),
                _ => nf64.l1.abs(),
            };
            slope * 0.5 * f64::EPSILON
        })
        .sum()
}

/// The second Lyapunov coefficient at the Hopf point `h` of `params` and
/// its error bound: the engine's rounding bound plus the change of `l2` over
/// the location error of `kappa_c` (as for `l1` in [`onset_at`]).
pub fn second_lyapunov(
    kind: ModelKind,
    params: &Params,
    h: &HopfPoint,
) -> Result<(f64, f64), NumericalError> {
    let block = DrivenBlock::new(kind, params);
    let mut p = *params;
    p.kappa = h.kappa_c;
    let x: Vec<f64> = match kind {
        ModelKind::Inertial => h.state.to_vec(),
        ModelKind::QuasiStatic => vec![h.state[0], h.state[2]],
    };
    let at = |dk: f64| {
        let mut q = p;
        q.kappa += dk;
        hopf_series(&block, &x, &q.to_vec(), h.omega_c)
    };
    let s = at(0.0)?;
    let dk = 1e-6 * p.kappa;
    let slope = (at(dk)?.l2 - at(-dk)?.l2) / (2.0 * dk);
    let bound = s.l2_error_bound + slope.abs() * location_error(kind, params, h.kappa_c);
    Ok((s.l2, bound))
}

/// How far a located `kappa_c` may be from the exact one: its distance from
/// the closed form of Appendix C (exact for this model at any inertia,
/// docs/model.md), and at least the rounding of `kappa_c` itself. Where the Hopf
/// system is ill-conditioned (small `omega`, e.g. near `V_min` of the cutoff
/// law) this is well above rounding.
pub(crate) fn location_error(kind: ModelKind, params: &Params, kappa: f64) -> f64 {
    let exact = closed_form_kappa_c(kind, params);
    (kappa - exact).abs().max(4.0 * f64::EPSILON * kappa.abs())
}

/// The critical stiffness of Appendix C for the model `kind`: eq. C11 with
/// inertia, C12 without.
fn closed_form_kappa_c(kind: ModelKind, params: &Params) -> f64 {
    match kind {
        ModelKind::Inertial => appendix_c::critical_stiffness(params),
        ModelKind::QuasiStatic => appendix_c::critical_stiffness_quasi_static(params),
    }
}

/// Where the search for the onset stops, relative to its stable starting
/// stiffness, when steady friction is velocity strengthening
/// (`mu_phi <= mu_v`, the friction law's own slopes at the steady state).
///
/// As `kappa -> 0` the characteristic polynomial (Appendix C, C9) has a root
/// going to zero with its constant coefficient `a0 = kappa nu`; rounding can
/// push that root across zero near `1e-11` of the starting stiffness, which a
/// continuation down to `1e-12` of it would report as a real eigenvalue
/// crossing. With `mu_phi <= mu_v` no crossing exists for any `kappa > 0`:
/// every coefficient of the cubic is positive and the Routh–Hurwitz
/// determinant `a2 a1 - a3 a0 = (mu_v/nu)(kappa + mu_v - mu_phi) + m nu (mu_v - mu_phi)`
/// is positive. So the continuation checks stability down to this floor and
/// the verdict below it rests on that sign.
pub const STRENGTHENING_FLOOR: f64 = 1e-8;

/// Whether steady friction at `params.nu` is velocity strengthening, or
/// neutral: `mu_phi <= mu_v` (the steady-state slopes of the friction law,
/// docs/model.md; `mu_v + eta_d nu` with radiation damping). Then steady
/// sliding is linearly stable for every stiffness.
pub fn velocity_strengthening(params: &Params) -> bool {
    params.mu_phi() <= params.mu_v_damped()
}

/// What the search for the stick-slip onset found.
#[derive(Clone, Debug)]
pub enum HopfOutcome {
    /// Steady sliding loses stability at a Hopf point.
    Found(HopfPoint),
    /// Steady sliding stays linearly stable down to `kappa_min`. For
    /// velocity-strengthening friction ([`velocity_strengthening`]) the
    /// search stops at [`STRENGTHENING_FLOOR`] of its starting stiffness and
    /// the verdict holds for every `kappa > 0`.
    StableForAllStiffness { kappa_min: f64 },
}

/// A stiffness at which steady sliding is linearly stable, found by doubling
/// from a bound on the friction law's steady-state slopes (times the inertia
/// factor of eq. C11), for `block`, the model of `kind` (as it is, or
/// wrapped). Errors when none is found (the steady state is unstable at
/// every stiffness tried).
pub fn stable_stiffness<S: VectorField>(
    block: &S,
    kind: ModelKind,
    params: &Params,
) -> Result<f64, NumericalError> {
    // A bound on the friction law's steady-state slopes, |mu_phi| + mu_v <=
    // B + A + 2 (|mu2| + |mu_vv| + |mu_vphi|) |ln nu| (logarithmic form:
    // mu_phi = B + (mu_vphi - 2 mu2) ln nu, mu_v = A + (2 mu_vv - mu_vphi) ln nu;
    // cutoff: mu_phi <= B, mu_v = A): kappa_c of Appendix C is
    // (mu_phi - mu_v)(1 + m nu^2 / mu_v).
    let mu_v = params.mu_v();
    if mu_v.is_nan() || mu_v <= 0.0 {
        return Err(NumericalError::Analysis(format!(
            "the direct effect at steady sliding mu_v = A + (2 mu_vv - mu_vphi) ln nu is \
             {mu_v:e} at nu = {:e}: friction falls with the slip velocity there, and steady \
             sliding is unstable at every stiffness (Appendix C needs mu_v > 0)",
            params.nu
        )));
    }
    let corrections = params.mu2.abs() + params.mu_vv.abs() + params.mu_vphi.abs();
    let scale =
        (params.b + params.a + 2.0 * corrections * params.nu.ln().abs() + params.eta_d * params.nu)
            * (1.0 + params.inertia_ratio());
    let x = steady_state(kind, params);
    let mut kappa = 4.0 * scale;
    for _ in 0..60 {
        let mut p = *params;
        p.kappa = kappa;
        let ev = eigenvalues(&jacobian(block, &x, &p.to_vec())).map_err(NumericalError::from)?;
        if count_unstable(&ev) == 0 {
            return Ok(kappa);
        }
        kappa *= 2.0;
    }
    Err(NumericalError::Analysis(format!(
        "steady sliding is unstable at every stiffness up to kappa = {kappa:.3e}; \
         check the friction parameters (is A > 0?)"
    )))
}

/// Steady friction within this fraction of velocity neutral, `mu_phi - mu_v <
/// NEUTRAL_SHARE mu_v`, is next to the friction minimum: the onset frequency
/// `omega_c = nu sqrt(mu_phi/mu_v - 1)` (C13) is below 1 % of `nu`.
const NEUTRAL_SHARE: f64 = 1e-4;

/// A failure of the steady-sliding branch `e`, explained where steady friction
/// is all but velocity neutral: `kappa_c` is there the difference `mu_phi -
/// mu_v` of two slopes that cancel to a small fraction of their size, and
/// rounding in the Hopf system moves its solution by more than the location
/// accepts (near the Bogdanov-Takens point of the friction minimum, where
/// `omega_c -> 0`). Appendix C's critical stiffness (C11/C12) and frequency
/// (C13) are given instead.
fn near_velocity_neutral(kind: ModelKind, params: &Params, e: ContinuationError) -> NumericalError {
    let margin = params.mu_phi() - params.mu_v_damped();
    if !(margin > 0.0 && margin < NEUTRAL_SHARE * params.mu_v_damped()) {
        return e.into();
    }
    let kappa_c = closed_form_kappa_c(kind, params);
    NumericalError::Analysis(format!(
        "{e}: steady friction is within {:.1e} of velocity neutral here (mu_phi - mu_v = \
         {margin:.3e}, next to the friction minimum): kappa_c is a difference of friction \
         slopes that cancel to that fraction of their size, and rounding keeps the Hopf system \
         from locating it; Appendix C gives kappa_c = {kappa_c:.6e} (eq. C11/C12) and \
         omega_c = {:.3e} (C13); the onset type was not computed",
        margin / params.mu_v_damped(),
        appendix_c::critical_frequency(params).unwrap_or(0.0),
    ))
}

/// Continues steady sliding in `kappa` downward from a stable stiffness and
/// locates the first Hopf point.
pub fn find_hopf(kind: ModelKind, params: &Params) -> Result<HopfOutcome, NumericalError> {
    find_hopf_with(
        &AsIs,
        kind,
        params,
        &ContinuationSettings::default().locator,
    )
}

/// [`find_hopf`] with the model built through `fields` (e.g. counted) and
/// the Newton settings of the Hopf location given (the accuracy knob of the
/// work-precision study).
pub fn find_hopf_with<F: Wrap>(
    fields: &F,
    kind: ModelKind,
    params: &Params,
    locator: &NewtonSettings,
) -> Result<HopfOutcome, NumericalError> {
    let searched = search_hopf(fields, kind, params, locator);
    if matches!(searched, Ok(HopfOutcome::Found(_))) {
        return searched;
    }
    // Where the search failed or found none but Appendix C (exact for the
    // linear stability of steady sliding) puts a Hopf point, it is located
    // from there; the closed form only starts Newton's method.
    match hopf_from_closed_form(fields, kind, params, locator) {
        None => searched,
        Some(Ok(h)) => Ok(HopfOutcome::Found(h)),
        Some(Err(e)) => {
            // The engine's advice (a smaller step, a better guess) is no
            // knob of `hopf`: the failure in numbers, the reason after it.
            let searched = match searched {
                Ok(_) => "found no Hopf point on the way down".to_string(),
                Err(NumericalError::Continuation(c)) => c.without_hint().to_string(),
                Err(s) => s.to_string(),
            };
            Err(NumericalError::Analysis(format!(
                "the search for the onset failed ({searched}), and Newton's method on the Hopf \
                 system from Appendix C's kappa_c = {:.10e} failed too ({e}): the Jacobian of \
                 steady sliding spans too many decades here (m = {:e}, kappa_c = {:.3e}) for \
                 the onset to be located in double precision",
                closed_form_kappa_c(kind, params),
                params.m,
                closed_form_kappa_c(kind, params)
            )))
        }
    }
}

/// The Hopf point located by Newton's method on the Hopf system from
/// Appendix C's `kappa_c` (eqs. C11, C12) and `omega_c` (C13) at the
/// steady state; `None` where the closed form has no onset (velocity
/// strengthening, or `kappa_c <= 0`).
fn hopf_from_closed_form<F: Wrap>(
    fields: &F,
    kind: ModelKind,
    params: &Params,
    locator: &NewtonSettings,
) -> Option<Result<HopfPoint, NumericalError>> {
    let kappa_c = closed_form_kappa_c(kind, params);
    let omega_c = appendix_c::critical_frequency(params)?;
    if !(kappa_c > 0.0 && kappa_c.is_finite() && omega_c.is_finite()) {
        return None;
    }
    let block = fields.field(DrivenBlock::new(kind, params));
    let mut p = *params;
    p.kappa = kappa_c;
    let x0 = steady_state(kind, &p);
    let located = continuation::locate_hopf(
        &block,
        Param::Kappa as usize,
        &x0,
        &p.to_vec(),
        omega_c,
        locator,
    )
    .map_err(|e| match e {
        // Said in the onset's terms: the engine's advice on step sizes and
        // guesses does not apply to a start from the exact linear onset.
        ContinuationError::Newton {
            iterations,
            residual,
            step,
            ..
        } => NumericalError::Analysis(format!(
            "after {iterations} Newton iterations the residual is {residual:.1e} but the \
             iterate still moves by {step:.1e}, {:.1e} of kappa_c",
            step / kappa_c
        )),
        other => other.into(),
    })
    .and_then(|e| {
        let EventKind::Hopf { omega } = e.kind else {
            return Err(NumericalError::Analysis(
                "Newton's method on the Hopf system returned no Hopf point".into(),
            ));
        };
        let point = &e.point;
        Ok(HopfPoint {
            kappa_c: point.param(),
            omega_c: omega,
            state: full_state(kind, params, &point.x),
            eigenvalues: point.eigenvalues.clone(),
            newton_iterations: point.newton.iterations,
            residual: point.newton.residual,
            steps: 0,
            onset: onset_at(
                &block,
                &point.x,
                &point.p,
                omega,
                location_error(kind, params, point.param()),
            )?,
        })
    });
    Some(located)
}

/// [`find_hopf_with`]'s search: steady sliding continued from a stable
/// stiffness toward smaller ones until a Hopf point is detected and located.
fn search_hopf<F: Wrap>(
    fields: &F,
    kind: ModelKind,
    params: &Params,
    locator: &NewtonSettings,
) -> Result<HopfOutcome, NumericalError> {
    let block = fields.field(DrivenBlock::new(kind, params));
    let k0 = stable_stiffness(&block, kind, params)?;
    let mut p = *params;
    p.kappa = k0;
    // Velocity strengthening: stable for every kappa > 0 (see STRENGTHENING_FLOOR);
    // checked numerically down to a floor clear of the cubic's vanishing root.
    let kappa_min = if velocity_strengthening(params) {
        STRENGTHENING_FLOOR * k0
    } else {
        1e-12 * k0
    };
    let settings = ContinuationSettings {
        step: StepControl {
            ds: 0.02 * k0,
            ds_max: 0.1 * k0,
            ds_min: 1e-12 * k0,
            ..ContinuationSettings::default().step
        },
        p_min: kappa_min,
        direction: Direction::Decreasing,
        max_steps: 10_000,
        locator: *locator,
        ..Default::default()
    };
    let x0 = steady_state(kind, &p);
    let branch = Branch::new(&block, &x0, &p.to_vec(), Param::Kappa as usize, settings)
        .map_err(NumericalError::from)?;
    for (steps, point) in branch.enumerate() {
        let point = point.map_err(|e| near_velocity_neutral(kind, params, e))?;
        let hopf = point.events.iter().find_map(|e| match e.kind {
            EventKind::Hopf { omega } => Some((&e.point, omega)),
            EventKind::Fold { .. } => None,
        });
        if let Some((e, omega)) = hopf {
            return Ok(HopfOutcome::Found(HopfPoint {
                kappa_c: e.param(),
                omega_c: omega,
                state: full_state(kind, params, &e.x),
                eigenvalues: e.eigenvalues.clone(),
                newton_iterations: e.newton.iterations,
                residual: e.newton.residual,
                steps,
                onset: onset_at(
                    &block,
                    &e.x,
                    &e.p,
                    omega,
                    location_error(kind, params, e.param()),
                )?,
            }));
        }
        if point.n_unstable > 0 {
            return Err(NumericalError::Analysis(format!(
                "steady sliding became unstable at kappa = {:.6e} without a Hopf point \
                 ({} unstable eigenvalues): a real eigenvalue crossed zero",
                point.param(),
                point.n_unstable
            )));
        }
    }
    Ok(HopfOutcome::StableForAllStiffness { kappa_min })
}
