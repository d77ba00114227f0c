//! Stick-slip cycles as fixed points of the return map of the joined flow
//! ([`super::joined_flow`]): where the inertial block's stick lies below the
//! resolution of `f64` and collocation cannot resolve where it comes to rest.
//!
//! The return map `P` takes `(s, ln theta)` on the section `v = nu`
//! (rising) to the next crossing. A cycle is a root of `F(x) = P(x) - x`,
//! found by Newton's method with the Jacobian of `P` by central differences
//! (steps `h_j = 1e-6 max(1, |x_j|)`: the integration's rounding `rtol`
//! over `h` against the truncation `h^2 |P'''|`); the chord Jacobian is
//! kept while each step is at most a tenth of the one before, and Newton
//! stops at `1e-11` relative or where its steps stall below `1e-6` (the
//! rounding floor of the integration). The eigenvalues of `P'` at the
//! root are the cycle's nontrivial Floquet multipliers (the trivial one,
//! along the flow, the section removes); their error is taken as the
//! change of the eigenvalues between difference steps `h` and `2 h`, and
//! stability is decided only beyond it.

use super::cycles::{direct_effect_min, friction_min, CycleMethod, CycleRecord, CycleRequest, Leg};
use super::joined_flow::{stick_threshold, JoinedFlow, Passage, PassageError, State};
use super::settle::SettledOrbit;
use super::settle::{SettleError, SettleSettings};
use super::simulate::{RegimeReached, Unsettled};
use crate::error::{Error, NumericalError};
use crate::log_model::LogBlock;
use crate::params::{Param, Params};
use continuation::periodic::Stability;
use continuation::{Complex64, Stop};

/// Relative tolerance of the integration of a period.
pub const RTOL: f64 = 1e-12;

/// The coarser tolerance of the error estimate, as a multiple of [`RTOL`].
const COARSER: f64 = 10.0;

/// Newton iterations before a fixed point is given up.
const MAX_ITERATIONS: usize = 12;

/// Relative difference step of the Jacobian.
const H: f64 = 1e-6;

/// A cycle: a fixed point of the return map.
#[derive(Clone, Debug)]
pub struct FixedPoint {
    /// `(s, ln theta)` on the section.
    pub x: [f64; 2],
    /// The passage from it, sampled.
    pub passage: Passage,
    /// The Jacobian of the return map there.
    pub jacobian: [[f64; 2]; 2],
    /// Its eigenvalues by decreasing modulus: the nontrivial multipliers.
    pub multipliers: [Complex64; 2],
    /// Their error (the change between difference steps `h` and `2 h`).
    pub multiplier_error: f64,
    /// Newton iterations taken.
    pub iterations: usize,
    /// The last Newton step, relative: how well the fixed point is known
    /// (at most `1e-6`, where the steps stall at the integration's floor).
    pub last_step: f64,
}

/// Why no fixed point was found.
#[derive(Clone, Debug)]
pub enum FixedPointError {
    /// A passage could not be integrated.
    Passage(PassageError),
    /// Newton's method did not converge (last step size, relative).
    NoConvergence { step: f64, iterations: usize },
    /// `P' - I` is singular: a multiplier at 1 (a fold of cycles).
    Singular,
    /// The leading multiplier jumped between neighbouring stiffnesses.
    Jump { from: f64, to: f64 },
    /// Newton's method reached steady sliding (the orbit never slows
    /// through `v = nu`), not a cycle.
    SteadySliding,
}

impl std::fmt::Display for FixedPointError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            FixedPointError::Passage(e) => write!(f, "{e}"),
            FixedPointError::NoConvergence { step, iterations } => write!(
                f,
                "Newton's method on the return map did not converge ({iterations} iterations, \
                 last step {step:.1e} relative)"
            ),
            FixedPointError::Singular => write!(
                f,
                "the return map's Jacobian has an eigenvalue at 1 (a fold of cycles)"
            ),
            FixedPointError::SteadySliding => write!(
                f,
                "Newton's method on the return map reached steady sliding, not a cycle (the \
                 cycles shrink onto it, or end here)"
            ),
            FixedPointError::Jump { from, to } => write!(
                f,
                "the leading multiplier jumps from {from:.4} to {to:.4} between neighbouring \
                 stiffnesses however short the step: the return map's fixed points are not \
                 resolved here"
            ),
        }
    }
}

impl From<PassageError> for FixedPointError {
    fn from(e: PassageError) -> Self {
        FixedPointError::Passage(e)
    }
}

fn step_sizes(x: [f64; 2], scale: f64) -> [f64; 2] {
    [
        scale * H * x[0].abs().max(1.0),
        scale * H * x[1].abs().max(1.0),
    ]
}

/// The Jacobian of the return map at `x` by central differences with
/// `scale` times the default steps.
fn jacobian(
    flow: &JoinedFlow,
    x: [f64; 2],
    t_max: f64,
    scale: f64,
) -> Result<[[f64; 2]; 2], PassageError> {
    let h = step_sizes(x, scale);
    let mut j = [[0.0; 2]; 2];
    for k in 0..2 {
        let (mut up, mut down) = (x, x);
        up[k] += h[k];
        down[k] -= h[k];
        let (pu, pd) = (
            flow.passage(up, t_max, false)?.end,
            flow.passage(down, t_max, false)?.end,
        );
        for i in 0..2 {
            j[i][k] = (pu[i] - pd[i]) / (2.0 * h[k]);
        }
    }
    Ok(j)
}

/// Eigenvalues of a 2 x 2 matrix, by decreasing modulus.
fn eigenvalues(j: [[f64; 2]; 2]) -> [Complex64; 2] {
    let tr = j[0][0] + j[1][1];
    let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
    let disc = Complex64::new(tr * tr / 4.0 - det, 0.0).sqrt();
    let half = Complex64::new(tr / 2.0, 0.0);
    // The larger root directly, the smaller from the product (no
    // cancellation).
    let big = if tr >= 0.0 { half + disc } else { half - disc };
    let small = if big.norm() > 0.0 {
        Complex64::new(det, 0.0) / big
    } else {
        Complex64::new(0.0, 0.0)
    };
    [big, small]
}

/// The fixed point of the return map of `flow` near `guess`, with each
/// passage bounded by `t_max`.
pub fn fixed_point(
    flow: &JoinedFlow,
    guess: [f64; 2],
    t_max: f64,
) -> Result<FixedPoint, FixedPointError> {
    let mut x = guess;
    let mut chord = jacobian(flow, x, t_max, 1.0)?;
    let mut last_step = f64::INFINITY;
    for iteration in 1..=MAX_ITERATIONS {
        let px = flow.passage(x, t_max, false)?.end;
        let f = [px[0] - x[0], px[1] - x[1]];
        // (P' - I) dx = -f
        let a = [
            [chord[0][0] - 1.0, chord[0][1]],
            [chord[1][0], chord[1][1] - 1.0],
        ];
        let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
        if det == 0.0 || !det.is_finite() {
            return Err(FixedPointError::Singular);
        }
        let dx = [
            -(f[0] * a[1][1] - f[1] * a[0][1]) / det,
            -(a[0][0] * f[1] - a[1][0] * f[0]) / det,
        ];
        x = [x[0] + dx[0], x[1] + dx[1]];
        let step = (dx[0].abs() / x[0].abs().max(1.0)).max(dx[1].abs() / x[1].abs().max(1.0));
        // Converged, or stalled at the rounding floor of the integration
        // (a step no longer halving below 1e-6: long periods whose slip
        // lasts a microsecond time the slip to relative 1e-9 at best); the
        // error estimate of the cycle includes that last step.
        if step <= 1e-11 || (step > 0.5 * last_step && last_step <= 1e-6) {
            let passage = flow.passage(x, t_max, true)?;
            // A cycle slows through v = nu once a period; a "fixed point"
            // that never does is steady sliding on the section.
            if !passage.s_min.is_finite() {
                return Err(FixedPointError::SteadySliding);
            }
            let jac = jacobian(flow, x, t_max, 1.0)?;
            let coarse = eigenvalues(jacobian(flow, x, t_max, 2.0)?);
            let multipliers = eigenvalues(jac);
            let multiplier_error = multipliers
                .iter()
                .zip(&coarse)
                .map(|(a, b)| (a - b).norm())
                .fold(0.0f64, f64::max);
            return Ok(FixedPoint {
                x,
                passage,
                jacobian: jac,
                multipliers,
                multiplier_error,
                iterations: iteration,
                last_step: step,
            });
        }
        if step > 0.1 * last_step {
            chord = jacobian(flow, x, t_max, 1.0)?;
        }
        last_step = step;
    }
    Err(FixedPointError::NoConvergence {
        step: last_step,
        iterations: MAX_ITERATIONS,
    })
}

/// Why the cycle `c` of the return map follows the collocated cycle
/// `prev` on its branch (the text of `cycles` and its JSON `method_switch`).
pub fn handover_reason(log: &LogBlock, prev: &CycleRecord, c: &CycleRecord) -> String {
    let ln_v_b = stick_threshold(&params_of(log, &c.params));
    format!(
        "from kappa = {:.10e} on, the cycles are fixed points of the return map: collocation \
         could not resolve the block coming to rest from its slip onto a stick velocity of \
         v = 10^{:.1} V0 (kappa = {:.10e}); the stick is integrated quasi-statically below \
         v_b = 10^{:.1} V0, where inertia shifts ln v by less than rounding, the slip with \
         inertia (the return map reproduced the last collocated cycle: their periods agree \
         to 1e-6, or the branch would have stopped there)",
        c.kappa,
        prev.ln_v_min / std::f64::consts::LN_10,
        prev.kappa,
        ln_v_b / std::f64::consts::LN_10
    )
}

/// `(s, ln theta)` where the sampled orbit of `rec` crosses `v = nu`
/// upward (linear in `ln v` between samples): a guess of the fixed point.
pub fn section_guess(rec: &CycleRecord, nu: f64) -> Option<[f64; 2]> {
    let ln_nu = nu.ln();
    let n = rec.samples.len();
    (0..n).find_map(|i| {
        let [_, s0, w0, phi0] = rec.samples[i];
        let [_, s1, w1, phi1] = rec.samples[(i + 1) % n];
        (w0 < ln_nu && w1 >= ln_nu).then(|| {
            let f = (ln_nu - w0) / (w1 - w0);
            [s0 + f * (s1 - s0), phi0 + f * (phi1 - phi0)]
        })
    })
}

/// The parameters of a cycle of `log` with parameter vector `p`.
fn params_of(log: &LogBlock, p: &[f64]) -> Params {
    // Every value is read from `p`; only the form is `log`'s.
    let form = Params {
        kappa: 0.0,
        nu: 1.0,
        m: 0.0,
        a: 0.0,
        b: 0.0,
        mu0: 0.0,
        mu2: 0.0,
        theta_c: log.cutoff.then_some(1.0),
        state_law: log.state_law,
        mu_vv: 0.0,
        mu_vphi: 0.0,
        eta_d: 0.0,
    };
    form.with_vec(p)
}

/// Stable, unstable, or undecidable: the largest multiplier's modulus
/// against 1, beyond `error`.
fn stability(multipliers: &[Complex64; 2], error: f64) -> Stability {
    let modulus = multipliers[0].norm();
    if modulus < 1.0 - error {
        Stability::Stable
    } else if modulus > 1.0 + error {
        Stability::Unstable
    } else {
        Stability::Undecidable { modulus, error }
    }
}

/// The record of the cycle `fp` of `flow` at `params` (variables `log`,
/// leg `leg`): extremes of `s` at the section and at the event where `v`
/// falls through `nu`, of `v` over the accepted steps, and the error
/// estimate from a passage at a [`COARSER`] tolerance, carried to the fixed
/// point through `(I - P')^-1`.
fn record(
    params: &Params,
    fp: &FixedPoint,
    t_max: f64,
    log: &LogBlock,
    leg: Leg,
) -> Result<CycleRecord, PassageError> {
    let pas = &fp.passage;
    let (s_max, s_min) = (fp.x[0], pas.s_min);
    let delta_s = s_max - s_min;
    let coarse = JoinedFlow::new(params, RTOL * COARSER).passage(fp.x, t_max, false)?;
    let d = [coarse.end[0] - pas.end[0], coarse.end[1] - pas.end[1]];
    let j = fp.jacobian;
    let a = [[1.0 - j[0][0], -j[0][1]], [-j[1][0], 1.0 - j[1][1]]];
    let det = a[0][0] * a[1][1] - a[0][1] * a[1][0];
    let shift_s = ((d[0] * a[1][1] - d[1] * a[0][1]) / det).abs();
    // With the fixed point's own uncertainty: the last Newton step.
    let error_estimate = ((coarse.period - pas.period).abs() / pas.period)
        .max((coarse.s_min - pas.s_min).abs() / delta_s)
        .max(shift_s / delta_s)
        .max(fp.last_step * fp.x[0].abs().max(1.0) / delta_s);
    let (mut ln_v_min, mut ln_v_max) = (f64::INFINITY, f64::NEG_INFINITY);
    for &[_, _, ln_v, _] in &pas.samples {
        ln_v_min = ln_v_min.min(ln_v);
        ln_v_max = ln_v_max.max(ln_v);
    }
    let samples: Vec<[f64; 4]> = pas
        .samples
        .iter()
        .map(|&[t, s, ln_v, phi]| [t / pas.period, s, ln_v, phi])
        .collect();
    let mut multipliers = vec![
        Complex64::new(1.0, 0.0),
        fp.multipliers[0],
        fp.multipliers[1],
    ];
    multipliers.sort_by(|a, b| b.norm().total_cmp(&a.norm()));
    let trivial = multipliers
        .iter()
        .position(|z| *z == Complex64::new(1.0, 0.0));
    Ok(CycleRecord {
        kappa: params.kappa,
        params: params.to_vec(),
        period: pas.period,
        delta_s,
        s_min,
        s_max,
        v_min: ln_v_min.exp(),
        v_max: ln_v_max.exp(),
        ln_v_min,
        multipliers,
        trivial,
        trivial_error: None,
        error_estimate: Some(error_estimate),
        stability: stability(&fp.multipliers, fp.multiplier_error),
        method: CycleMethod::ReturnMap,
        model: log.kind,
        m: params.m,
        friction_min: friction_min(&params.friction(), &samples),
        direct_effect_min: direct_effect_min(&params.friction(), &samples),
        inertial_imbalance: pas.chi,
        samples,
        lpc: None,
        pd: None,
        ns: None,
        user: Vec::new(),
        user_point: false,
        leg,
        orbit: None,
        log: *log,
    })
}

/// Continues a cycle branch in `kappa` by the return map from its last
/// collocated cycle `last` (in the variables of `log`), where collocation
/// could not resolve the block coming to rest (`why`, collocation's own
/// failure): in the direction and with the first step `step` (the branch's
/// last step in `kappa`), for at most `max_cycles` cycles ([`follow`]).
/// The first fixed point is taken at `last`'s own stiffness and must
/// reproduce its period (to 1e-6): the two methods meet there.
#[allow(clippy::too_many_arguments)]
pub fn continue_branch(
    log: &LogBlock,
    last: &CycleRecord,
    step: f64,
    why: &str,
    req: &CycleRequest,
    max_cycles: usize,
    leg: Leg,
    sink: &mut impl FnMut(&CycleRecord) -> Result<(), Error>,
) -> Result<Stop, Error> {
    // The stick is integrated quasi-statically, `s = mu(v, theta)` solved
    // for `v`: where the law leaves its domain on the orbit (`d mu / d ln v
    // <= 0`) that has no solution, and the map cannot take over.
    if last.direct_effect_min <= 0.0 {
        return Err(NumericalError::Analysis(format!(
            "{why}; the orbits there lie outside the friction law's domain: the direct effect \
             d mu / d ln v = A + 2 mu_vv ln v + mu_vphi ln theta is down to {:.4e} on the last \
             one, where friction falls as the slip speeds up; the return map, which continues a \
             branch where collocation fails, solves s = mu(v, theta) for v in the stick and needs \
             it positive, so the branch ends here (a smaller mu_vv or mu_vphi keeps the law in \
             its domain, docs/model.md)",
            last.direct_effect_min
        ))
        .into());
    }
    let base = params_of(log, &last.params);
    let failed = |kappa: f64, e: String| -> Error {
        NumericalError::Analysis(format!(
            "{why}; the return map (the stick integrated quasi-statically below v_b, where \
             inertia is below rounding) took over at kappa = {:.10e} and failed at kappa = \
             {kappa:.10e}: {e}",
            last.kappa
        ))
        .into()
    };
    let guess = section_guess(last, base.nu).ok_or_else(|| {
        failed(
            last.kappa,
            "the last collocated orbit does not cross v = nu upward".into(),
        )
    })?;
    let first = fixed_point(&JoinedFlow::new(&base, RTOL), guess, 100.0 * last.period)
        .map_err(|e| failed(last.kappa, e.to_string()))?;
    let agreement = (first.passage.period - last.period).abs() / last.period;
    if agreement > 1e-6 {
        return Err(failed(
            last.kappa,
            format!(
                "its cycle at the last collocated stiffness has the period {:.10e}, the \
                 collocated one {:.10e} ({agreement:.1e} apart): the two methods do not meet",
                first.passage.period, last.period
            ),
        ));
    }
    let start = Start {
        base,
        fp: first,
        stability: last.stability,
    };
    follow(log, start, step, req, max_cycles, leg, sink, &failed)
}

/// The cycle of the return map at `params` from the simulated orbit
/// `orbit` (its section state, `v = nu` rising, in the variables of
/// [`LogBlock::new`]), as the record of a cycle of `leg` in the variables
/// of `log`: where collocation cannot resolve the orbit in normalized time
/// (a slip of microseconds in a period of days).
pub fn cycle_through_orbit(
    log: &LogBlock,
    params: &Params,
    orbit: &SettledOrbit,
    leg: Leg,
) -> Result<CycleRecord, FixedPointError> {
    orbit_cycle(log, params, orbit, leg).map(|(_, rec)| rec)
}

/// The fixed point through the simulated orbit `orbit` and its record
/// ([`cycle_through_orbit`]).
fn orbit_cycle(
    log: &LogBlock,
    params: &Params,
    orbit: &SettledOrbit,
    leg: Leg,
) -> Result<(FixedPoint, CycleRecord), FixedPointError> {
    let t_max = 100.0 * orbit.period;
    let guess = [orbit.section[0], orbit.section[2]];
    let fp = fixed_point(&JoinedFlow::new(params, RTOL), guess, t_max)?;
    let rec = record(params, &fp, t_max, log, leg).map_err(FixedPointError::Passage)?;
    Ok((fp, rec))
}

/// The branch through the simulated orbit `orbit` of `params` by the return
/// map, in `kappa` toward the side of `sign`, where collocation could not
/// correct the orbit (`why`): its cycle at `params.kappa` (handed to `sink`
/// when `hand_first`, the first leg), then [`follow`] with a first step of
/// `1e-3 kappa`.
#[allow(clippy::too_many_arguments)]
pub fn branch_through_orbit(
    log: &LogBlock,
    params: &Params,
    orbit: &SettledOrbit,
    sign: f64,
    why: &str,
    req: &CycleRequest,
    leg: Leg,
    hand_first: bool,
    sink: &mut impl FnMut(&CycleRecord) -> Result<(), Error>,
) -> Result<Stop, Error> {
    let failed = |kappa: f64, e: String| -> Error {
        NumericalError::Analysis(format!(
            "{why}; the return map (slips with inertia, sticks below v_b quasi-statically) \
             from the simulated orbit at kappa = {:.10e} failed at kappa = {kappa:.10e}: {e}",
            params.kappa
        ))
        .into()
    };
    let (fp, first) =
        orbit_cycle(log, params, orbit, leg).map_err(|e| failed(params.kappa, e.to_string()))?;
    if hand_first {
        sink(&first)?;
    }
    let start = Start {
        base: *params,
        fp,
        stability: first.stability,
    };
    let step = sign * 1e-3 * params.kappa;
    follow(log, start, step, req, req.max_steps, leg, sink, &failed)
}

/// Where a leg of the return map starts: a fixed point at `base.kappa`,
/// its stability.
struct Start {
    base: Params,
    fp: FixedPoint,
    stability: Stability,
}

/// Continues the cycles of the return map from `start` in `kappa`, in the
/// direction and with the first step `step`, to the bound of `req` on that
/// side, landing on it and on each stiffness `req` asks for on the way, for
/// at most `max_cycles` cycles, each handed to `sink`; `failed` words a
/// failure at a stiffness.
///
/// Steps in `kappa` grow by half after a fixed point found within three
/// Newton iterations, and halve on a failure; the next fixed point is
/// predicted linearly from the last two. The leg ends, with what it
/// delivered, where the leading multiplier crosses the unit circle (a
/// bifurcation of cycles, which it does not follow) or steps fall below
/// `1e-10 kappa`.
#[allow(clippy::too_many_arguments)]
fn follow(
    log: &LogBlock,
    start: Start,
    step: f64,
    req: &CycleRequest,
    max_cycles: usize,
    leg: Leg,
    sink: &mut impl FnMut(&CycleRecord) -> Result<(), Error>,
    failed: &dyn Fn(f64, String) -> Error,
) -> Result<Stop, Error> {
    let Start {
        base,
        fp: first,
        stability: mut last_stability,
    } = start;
    let kappa0 = base.kappa;
    let bound = if step < 0.0 {
        req.kappa_min
    } else {
        req.kappa_max
    };
    let ahead = |k: f64| (k - kappa0) * step.signum() > 0.0 && (bound - k) * step.signum() >= 0.0;
    // Started at or past the bound on this side (a simulated orbit outside
    // the range): the leg is its start.
    if (bound - kappa0) * step.signum() <= 0.0 {
        return Ok(Stop::Bound {
            index: Param::Kappa as usize,
            value: kappa0,
            bound,
        });
    }
    let mut targets: Vec<f64> = req.at_kappa.iter().copied().filter(|&k| ahead(k)).collect();
    targets.sort_by(|a, b| (a * step.signum()).total_cmp(&(b * step.signum())));
    targets.dedup();
    let mut t_max = 100.0 * first.passage.period;
    let mut last_modulus = first.multipliers[0].norm();
    let mut points = vec![(kappa0, first.x)];
    let mut h = step;
    let mut delivered = 0;
    loop {
        let &(kappa, x) = points.last().expect("starts with a point");
        if kappa == bound {
            return Ok(Stop::Bound {
                index: Param::Kappa as usize,
                value: kappa,
                bound,
            });
        }
        if delivered == max_cycles {
            return Ok(Stop::MaxSteps { steps: max_cycles });
        }
        let mut next = kappa + h;
        let mut user = false;
        if let Some(&t) = targets.first() {
            if (next - t) * step.signum() >= 0.0 {
                (next, user) = (t, true);
            }
        }
        if (next - bound) * step.signum() > 0.0 {
            (next, user) = (bound, false);
        }
        let guess = match points.len() {
            1 => x,
            n => {
                let (k0, x0) = points[n - 2];
                let f = (next - kappa) / (kappa - k0);
                [x[0] + f * (x[0] - x0[0]), x[1] + f * (x[1] - x0[1])]
            }
        };
        let params = Params {
            kappa: next,
            ..base
        };
        let attempt = fixed_point(&JoinedFlow::new(&params, RTOL), guess, t_max).and_then(|fp| {
            record(&params, &fp, t_max, log, leg)
                .map(|r| (fp, r))
                .map_err(FixedPointError::Passage)
        });
        // A leading multiplier that moves by more than 0.5 in one step is
        // not a crossing resolved by the step: the step is taken shorter.
        let attempt = attempt.and_then(|(fp, rec)| {
            let moved = (fp.multipliers[0].norm() - last_modulus).abs();
            if moved > 0.5 {
                Err(FixedPointError::Jump {
                    from: last_modulus,
                    to: fp.multipliers[0].norm(),
                })
            } else {
                Ok((fp, rec))
            }
        });
        match attempt {
            Ok((fp, mut rec)) => {
                let stability = rec.stability;
                let crossed = (last_stability.is_stable() && stability.is_unstable())
                    || (last_stability.is_unstable() && stability.is_stable());
                if crossed {
                    return Err(failed(
                        next,
                        format!(
                            "the leading multiplier crossed the unit circle since kappa = \
                             {kappa:.10e} (now {:.6} at {:.6} degrees): a bifurcation of cycles, \
                             which the return map's continuation does not follow",
                            fp.multipliers[0].norm(),
                            fp.multipliers[0].arg().to_degrees()
                        ),
                    ));
                }
                last_stability = stability;
                last_modulus = fp.multipliers[0].norm();
                if user {
                    targets.remove(0);
                    rec.user_point = true;
                } else if fp.iterations <= 3 {
                    h *= 1.5;
                }
                sink(&rec)?;
                delivered += 1;
                t_max = 100.0 * fp.passage.period;
                points.push((next, fp.x));
            }
            Err(e) => {
                h /= 2.0;
                if h.abs() < 1e-10 * kappa.abs() {
                    // Next to a fold of cycles the map's fixed point is
                    // singular in kappa, and the branch turns back.
                    let why = if last_modulus > 0.9 {
                        format!(
                            "the cycles fold back there: the leading multiplier reached \
                             {last_modulus:.4} on the way, and continuation in kappa cannot \
                             pass a fold ({e})"
                        )
                    } else {
                        e.to_string()
                    };
                    return Err(failed(next, why));
                }
            }
        }
    }
}

/// The joined flow of `params` from `start` continued by passages from
/// section to section until two successive crossings agree to
/// `settings.tol` (relative: `s` to the orbit's extent, `ln theta` to `1 +
/// |ln theta|`; at most `settings.max_periods` passages of at most
/// `settings.max_time` each): [`super::settle::settle`] for an inertial
/// block whose sticks fall below `v_b`, where the inertial integration
/// cannot follow the stop. The section state is in the variables of
/// [`LogBlock::new`] (`v = nu`).
pub fn settle(
    params: &Params,
    start: State,
    settings: &SettleSettings,
) -> Result<SettledOrbit, SettleError> {
    let flow = JoinedFlow::new(params, RTOL);
    let failed = |time: f64, e: &dyn std::fmt::Display| SettleError::Integration {
        kappa: params.kappa,
        time,
        cause: format!("continuing by the joined flow: {e}"),
    };
    let mut x = flow
        .to_section(start, settings.max_time)
        .map_err(|e| failed(0.0, &e))?;
    let (mut time, mut difference, mut extents) = (0.0, f64::INFINITY, (0.0, 0.0));
    for periods in 1..=settings.max_periods {
        let p = flow
            .passage(x, settings.max_time, false)
            .map_err(|e| failed(time, &e))?;
        time += p.period;
        let extent = x[0] - p.s_min;
        extents = (if periods == 1 { extent } else { extents.0 }, extent);
        difference = ((p.end[0] - x[0]).abs() / extent.max(f64::MIN_POSITIVE))
            .max((p.end[1] - x[1]).abs() / (1.0 + x[1].abs()));
        x = p.end;
        if difference <= settings.tol {
            return Ok(SettledOrbit {
                section: flow.on_section(x).to_vec(),
                period: p.period,
                periods,
                time,
                difference,
            });
        }
    }
    Err(SettleError::NotSettled {
        kappa: params.kappa,
        time,
        periods: settings.max_periods,
        difference,
        extent_first: extents.0,
        extent_last: extents.1,
    })
}

/// The regime the joined flow of `params` reaches from `start` (an
/// inertial run whose sticks fell below `v_b`): [`settle`], then the cycle
/// there located exactly ([`fixed_point`]), its period and `Delta_s` those
/// of the fixed point.
pub fn regime(params: &Params, start: State, settings: &SettleSettings) -> RegimeReached {
    let orbit = match settle(params, start, settings) {
        Ok(orbit) => orbit,
        Err(e) => return RegimeReached::Unsettled(Unsettled::Settle(e)),
    };
    let x = [orbit.section[0], orbit.section[2]];
    match fixed_point(&JoinedFlow::new(params, RTOL), x, 100.0 * orbit.period) {
        Ok(fp) => RegimeReached::Periodic {
            period: fp.passage.period,
            delta_s: fp.x[0] - fp.passage.s_min,
            slip: params.nu * fp.passage.period,
            on_cycle: [fp.x[0], params.nu, fp.x[1].exp()],
        },
        Err(e) => RegimeReached::Unsettled(Unsettled::Settle(SettleError::Integration {
            kappa: params.kappa,
            time: orbit.time,
            cause: format!("locating the settled cycle by the return map: {e}"),
        })),
    }
}
