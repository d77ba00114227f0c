//! The stability diagram: the Hopf curve `kappa_c(nu)` of a scene over a
//! velocity range, with the onset type along it and its special points.
//!
//! The curve is continued in `(ln kappa, ln nu)` (steps uniform on the log
//! axes of the plot) by the engine's minimally augmented Hopf system; `l1` is
//! evaluated at every point and Bautin points (`l1 = 0`) are located where it
//! changes sign. Where the curve runs into `kappa_c -> 0` — the minimum of
//! steady friction, `V_min` for the cutoff law — the end point is located on
//! the friction law itself: `mu_phi(1/nu) = mu_v`.

use crate::analysis::hopf::{
    find_hopf_with, location_error, resolved_normal_form, Criticality, HopfOutcome, EXTENDED_DIGITS,
};
use crate::analysis::lpc_curve::{lpc_curves, BautinStart, LpcCurves};
use crate::analysis::model_choice::{inertia_decides, params_for, ModelChoice};
use crate::error::NumericalError;
use crate::model::{full_state, DrivenBlock, ModelKind};
use crate::params::{Param, Params};
use continuation::codim2::{CurveSettings, HopfCurve, HopfCurvePoint};
use continuation::normal_form::hopf_series;
use continuation::CurveControl;
use continuation::StepControl;
use continuation::Stop;
use continuation::{AsIs, ContinuationSettings, LogParameters, NewtonSettings, VectorField, Wrap};

/// One point of the Hopf curve, in docs/model.md's variables.
#[derive(Clone, Debug)]
pub struct CurvePoint {
    pub nu: f64,
    pub kappa: f64,
    /// Inertia (varies along a `(kappa, m)` curve).
    pub m: f64,
    pub omega: f64,
    pub l1: f64,
    /// Bound on the rounding error of `l1`.
    pub l1_error_bound: f64,
    pub criticality: Criticality,
    /// Steady state `(s, v, theta)`.
    pub state: [f64; 3],
}

/// What a special point of the diagram is (JSON `kind`: `bautin`, `endpoint`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum SpecialKind {
    /// `l1 = 0`: the onset changes type.
    Bautin,
    /// `kappa_c -> 0`: the Hopf curve ends at the friction minimum.
    Endpoint,
}

impl SpecialKind {
    /// `bautin` or `endpoint`, as in the JSON.
    pub fn name(self) -> &'static str {
        match self {
            SpecialKind::Bautin => "bautin",
            SpecialKind::Endpoint => "endpoint",
        }
    }
}

/// Its [`name`](SpecialKind::name), padded as the format asks.
impl std::fmt::Display for SpecialKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.pad(self.name())
    }
}

/// Why a run of the Hopf curve stopped (JSON `stop_reason`, snake case).
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum CurveEnd {
    /// The curve reached the end of the requested range.
    EndOfRange,
    /// The critical stiffness vanishes (`kappa_c -> 0`, the friction minimum).
    KappaCVanishes,
    /// The most continuation steps were taken first.
    StepLimit,
    /// The continuation ended without a reason.
    Stopped,
    /// No Hopf point was found to start from.
    NoHopfPoint,
}

impl CurveEnd {
    /// In words: `end of the range`, `kappa_c -> 0`, `step limit`, ...
    pub fn words(self) -> &'static str {
        match self {
            CurveEnd::EndOfRange => "end of the range",
            CurveEnd::KappaCVanishes => "kappa_c -> 0",
            CurveEnd::StepLimit => "step limit",
            CurveEnd::Stopped => "stopped",
            CurveEnd::NoHopfPoint => "no Hopf point in the range",
        }
    }

    /// Whether the curve ended where it should: at the end of the range, or
    /// where the curve itself ends (`kappa_c -> 0`).
    pub fn ends_curve(self) -> bool {
        matches!(self, CurveEnd::EndOfRange | CurveEnd::KappaCVanishes)
    }
}

/// A codimension-2 or end point of the diagram.
#[derive(Clone, Debug)]
pub struct SpecialPoint {
    pub kind: SpecialKind,
    pub nu: f64,
    pub kappa: f64,
    pub omega: f64,
    /// Inertia at the point (varies along an `(kappa, m)` curve).
    pub m: f64,
    /// Second Lyapunov coefficient at a Bautin point: `l2 < 0` means the
    /// subcritical side is bounded by a fold of cycles (hysteresis loop).
    pub l2: Option<f64>,
    /// Bound on the rounding error of `l2`.
    pub l2_error_bound: Option<f64>,
}

/// The Hopf curve of a scene and its special points.
#[derive(Clone, Debug)]
pub struct StabilityDiagram {
    pub points: Vec<CurvePoint>,
    pub special: Vec<SpecialPoint>,
    /// Why the continuation stopped; with a run below the starting point,
    /// the first that did not end the curve.
    pub stop: CurveEnd,
    /// Whether the curve covers the requested range (each run reached the
    /// end of the range or the end of the curve, `kappa_c -> 0`).
    pub complete: bool,
    /// Curves of folds of cycles (empty without a subcritical onset).
    pub lpc: LpcCurves,
    /// Stretches `(nu_from, nu_to)` of the range where steady friction is
    /// velocity strengthening (`mu_phi <= mu_v`): steady sliding is stable
    /// for every stiffness there and the Hopf curve does not enter them.
    pub strengthening: Vec<(f64, f64)>,
    /// Why the curve is empty or partial, in words (e.g. velocity
    /// strengthening over the whole range); `None` when it covers the range.
    pub reason: Option<String>,
}

/// `mu_phi - mu_v` of steady sliding at `nu` (the friction law's slopes;
/// `mu_v + eta_d nu` with radiation damping).
fn weakening_at(params: &Params, nu: f64) -> f64 {
    let mut p = *params;
    p.nu = nu;
    p.mu_phi() - p.mu_v_damped()
}

/// The stretches of `[lo, hi]` in `nu` where steady friction is velocity
/// strengthening or neutral, `mu_phi(1/nu) <= mu_v`, by the friction law's
/// own slopes: sign changes of `mu_phi - mu_v` on a log grid of 400 points,
/// each boundary bisected in `ln nu` to rounding.
pub fn strengthening_intervals(params: &Params, (lo, hi): (f64, f64)) -> Vec<(f64, f64)> {
    const GRID: usize = 400;
    let strong = |nu: f64| weakening_at(params, nu) <= 0.0;
    let nu_at = |i: usize| {
        if i == GRID - 1 {
            hi
        } else {
            lo * (hi / lo).powf(i as f64 / (GRID - 1) as f64)
        }
    };
    // The boundary between a and b (strong(a) != strong(b)), bisected in ln nu.
    let boundary = |mut a: f64, mut b: f64| {
        let sa = strong(a);
        for _ in 0..200 {
            let mid = (a.ln() + 0.5 * (b / a).ln()).exp();
            if mid <= a.min(b) || mid >= a.max(b) {
                break;
            }
            if strong(mid) == sa {
                a = mid;
            } else {
                b = mid;
            }
        }
        if sa {
            a
        } else {
            b
        }
    };
    let mut out = Vec::new();
    let mut open = strong(lo).then_some(lo);
    for i in 1..GRID {
        let (a, b) = (nu_at(i - 1), nu_at(i));
        match (open, strong(b)) {
            (None, true) => open = Some(boundary(a, b)),
            (Some(from), false) => {
                out.push((from, boundary(a, b)));
                open = None;
            }
            _ => {}
        }
    }
    if let Some(from) = open {
        out.push((from, hi));
    }
    out
}

/// The words for the velocity-strengthening stretches of the range `(lo, hi)`:
/// `None` when there are none.
fn strengthening_reason(
    params: &Params,
    (lo, hi): (f64, f64),
    strong: &[(f64, f64)],
) -> Option<String> {
    let whole = matches!(strong, [(a, b)] if *a == lo && *b == hi);
    if whole {
        let (w_lo, w_hi) = (weakening_at(params, lo), weakening_at(params, hi));
        return Some(format!(
            "velocity strengthening: mu_phi <= mu_v over the whole range nu = {lo:.6e} .. {hi:.6e} \
             (mu_phi - mu_v = {w_lo:.4e} at nu = {lo:.4e}, {w_hi:.4e} at nu = {hi:.4e}; slopes of the \
             friction law at steady sliding): steady sliding is linearly stable for every stiffness, \
             no Hopf point, no stability boundary to draw"
        ));
    }
    if strong.is_empty() {
        return None;
    }
    let parts: Vec<String> = strong
        .iter()
        .map(|(a, b)| format!("nu = {a:.6e} .. {b:.6e}"))
        .collect();
    Some(format!(
        "velocity strengthening (mu_phi <= mu_v, slopes of the friction law at steady sliding) for {}: \
         steady sliding is linearly stable for every stiffness there, no Hopf point; the Hopf curve \
         covers the velocity-weakening part of the range",
        parts.join(", ")
    ))
}

/// Values of the second parameter tried for a first Hopf point.
const FIRST_HOPF_GRID: usize = 41;

/// The first value of `second` on a log grid over `[lo, hi]` at which steady
/// sliding has a Hopf point, with that point (models built through `fields`).
fn first_hopf<F: Wrap>(
    fields: &F,
    kind: ModelKind,
    params: &Params,
    second: Param,
    (lo, hi): (f64, f64),
) -> Result<Option<(Params, crate::analysis::hopf::HopfPoint)>, NumericalError> {
    const GRID: usize = FIRST_HOPF_GRID;
    for i in 0..GRID {
        let mut p = *params;
        p.set(second, lo * (hi / lo).powf(i as f64 / (GRID - 1) as f64));
        let locator = ContinuationSettings::default().locator;
        if let HopfOutcome::Found(h) = find_hopf_with(fields, kind, &p, &locator)? {
            return Ok(Some((p, h)));
        }
    }
    Ok(None)
}

/// Velocity where `mu_phi(1/nu) = mu_v + eta_d nu` (steady force minimal, `kappa_c = 0`),
/// by Newton's method in `ln nu` from `nu0`, derivative by dual numbers.
fn friction_minimum(params: &Params, nu0: f64) -> Option<f64> {
    use num_dual::{Dual64, DualNum};
    let law = crate::params::friction_from(
        params.theta_c.is_some(),
        &params
            .to_vec()
            .iter()
            .map(|&v| Dual64::from(v))
            .collect::<Vec<_>>(),
    );
    let mut ln_nu = nu0.ln();
    for _ in 0..50 {
        let nu = Dual64::new(ln_nu, 1.0).exp();
        let slope = law.steady_slope(nu) + law.damping(nu);
        if slope.eps == 0.0 {
            return None;
        }
        let step = slope.re / slope.eps;
        ln_nu -= step;
        if step.abs() < 1e-15 * ln_nu.abs().max(1.0) {
            return Some(ln_nu.exp());
        }
    }
    None
}

/// For every Bautin point of `d`, the subcritical Hopf point of the curve
/// nearest to it but at least 2 % away in `nu` (at the Bautin point itself
/// the folded cycles are vanishingly small), where its curve of folds of
/// cycles starts.
fn bautin_starts(d: &StabilityDiagram) -> Vec<BautinStart> {
    d.special
        .iter()
        .filter(|s| s.kind == SpecialKind::Bautin)
        .filter_map(|b| {
            let away = |p: &&CurvePoint| (p.nu / b.nu).ln().abs();
            d.points
                .iter()
                .filter(|p| p.criticality == Criticality::Subcritical)
                .filter(|p| away(p) > 0.02)
                .min_by(|x, y| away(x).total_cmp(&away(y)))
                .map(|p| BautinStart {
                    bautin_nu: b.nu,
                    hopf_nu: p.nu,
                })
        })
        .collect()
}

/// Traces the Hopf curve of `params` for `nu` in `[nu_lo, nu_hi]` and,
/// from its Bautin points, the curves of folds of cycles that bound the
/// hysteretic region.
pub fn stability_diagram(
    kind: ModelKind,
    params: &Params,
    range: (f64, f64),
) -> Result<StabilityDiagram, NumericalError> {
    stability_diagram_with(&AsIs, kind, params, range, DEFAULT_CURVE_STEPS)
}

/// Steps of each run of the Hopf curve by default (`diagram --max-steps`).
pub const DEFAULT_CURVE_STEPS: usize = 50_000;

/// [`stability_diagram`] with the models built through `fields` (e.g.
/// counted) and at most `max_steps` continuation steps in each direction
/// along the Hopf curve.
pub fn stability_diagram_with<F: Wrap>(
    fields: &F,
    kind: ModelKind,
    params: &Params,
    range: (f64, f64),
    max_steps: usize,
) -> Result<StabilityDiagram, NumericalError> {
    let d = hopf_curve_with(fields, kind, params, Param::Nu, range, max_steps)?;
    Ok(with_fold_curves(fields, kind, params, range, d))
}

/// The stability diagram of the scene `scene` (its own inertia) over
/// `range` in the model `choice` made, or in the inertial one where
/// [`inertia_decides`] says so: the quasi-static Hopf curve is compared
/// point by point with the inertial one ([`onset_types_changed`]), and only
/// the curve kept gets its fold-of-cycles curves. Returns the diagram and
/// the new choice, when the inertia decided.
pub fn stability_diagram_deciding<F: Wrap>(
    fields: &F,
    choice: &ModelChoice,
    forced: bool,
    scene: &Params,
    range: (f64, f64),
    max_steps: usize,
) -> Result<(StabilityDiagram, Option<ModelChoice>), NumericalError> {
    let params = params_for(choice.kind, scene);
    let curve = hopf_curve_with(fields, choice.kind, &params, Param::Nu, range, max_steps)?;
    let mut inertial = None;
    let decided = inertia_decides(choice, forced, scene.m, || {
        let other = hopf_curve_with(
            fields,
            ModelKind::Inertial,
            scene,
            Param::Nu,
            range,
            max_steps,
        )
        .ok()?;
        let changed = onset_types_changed(&curve, &other);
        inertial = Some(other);
        Some((changed, curve.points.len()))
    });
    Ok(match (decided, inertial) {
        (Some(decided), Some(other)) => (
            with_fold_curves(fields, ModelKind::Inertial, scene, range, other),
            Some(decided),
        ),
        _ => (
            with_fold_curves(fields, choice.kind, &params, range, curve),
            None,
        ),
    })
}

/// The points of the quasi-static curve `qs` whose onset type is degenerate
/// or differs from that of the inertial curve `inertial` at the nearest
/// velocity (every point, when the inertial curve has none).
fn onset_types_changed(qs: &StabilityDiagram, inertial: &StabilityDiagram) -> usize {
    qs.points
        .iter()
        .filter(|p| {
            let nearest = inertial.points.iter().min_by(|a, b| {
                (a.nu / p.nu)
                    .ln()
                    .abs()
                    .total_cmp(&(b.nu / p.nu).ln().abs())
            });
            p.criticality == Criticality::Degenerate
                || nearest.is_none_or(|q| q.criticality != p.criticality)
        })
        .count()
}

/// The Hopf curve `d` completed into the stability diagram: the curves of
/// folds of cycles from its Bautin points and the velocity-strengthening
/// stretches of `range`.
fn with_fold_curves<F: Wrap>(
    fields: &F,
    kind: ModelKind,
    params: &Params,
    range: (f64, f64),
    mut d: StabilityDiagram,
) -> StabilityDiagram {
    d.lpc = lpc_curves(fields, kind, params, &bautin_starts(&d), range);
    d.strengthening = strengthening_intervals(params, range);
    if let Some(why) = strengthening_reason(params, range, &d.strengthening) {
        d.reason = Some(why);
    }
    d
}

/// `l1` of the Hopf-curve point `pt` (parameters `p`) with its error bound,
/// in the arithmetic `hopf` would use there: the curve's `f64` value where
/// its bound leaves [`EXTENDED_DIGITS`] digits, else the normal form
/// recomputed by [`resolved_normal_form`] (double-double where that
/// resolves it), so that a curve point is never called degenerate where
/// `hopf` at the same parameters resolves the sign.
pub(crate) fn curve_l1<S: VectorField>(
    block: &S,
    kind: ModelKind,
    p: &Params,
    pt: &HopfCurvePoint,
) -> (f64, f64) {
    if pt.l1_error_bound <= 10f64.powi(-EXTENDED_DIGITS) * pt.l1.abs() {
        return (pt.l1, pt.l1_error_bound);
    }
    let kappa_error = location_error(kind, p, p.kappa);
    match resolved_normal_form(block, &pt.x, &p.to_vec(), pt.omega, kappa_error) {
        Ok((nf, _)) if nf.l1_error_bound < pt.l1_error_bound => (nf.l1, nf.l1_error_bound),
        _ => (pt.l1, pt.l1_error_bound),
    }
}

/// Traces the Hopf curve `kappa_c(second)` for `second` (`nu` or `m`) in
/// `range`, continued in `(ln kappa, ln second)`.
pub fn hopf_curve(
    kind: ModelKind,
    params: &Params,
    second: Param,
    range: (f64, f64),
) -> Result<StabilityDiagram, NumericalError> {
    hopf_curve_with(&AsIs, kind, params, second, range, DEFAULT_CURVE_STEPS)
}

/// [`hopf_curve`] with the models built through `fields` (e.g. counted)
/// and at most `max_steps` steps in each direction.
pub fn hopf_curve_with<F: Wrap>(
    fields: &F,
    kind: ModelKind,
    params: &Params,
    second: Param,
    range: (f64, f64),
    max_steps: usize,
) -> Result<StabilityDiagram, NumericalError> {
    let Some((p0, h0)) = first_hopf(fields, kind, params, second, range)? else {
        return Ok(StabilityDiagram {
            points: Vec::new(),
            special: Vec::new(),
            stop: CurveEnd::NoHopfPoint,
            complete: true,
            lpc: LpcCurves::default(),
            strengthening: Vec::new(),
            reason: Some(format!(
                "no Hopf point found at any of the {FIRST_HOPF_GRID} values of {} tried in {:.6e} .. {:.6e}",
                second.name(),
                range.0,
                range.1
            )),
        });
    };
    let block = fields.field(DrivenBlock::new(kind, params));
    let pair = [Param::Kappa as usize, second as usize];
    let logs = LogParameters {
        inner: &block,
        indices: pair.to_vec(),
    };
    let mut p0 = p0;
    p0.kappa = h0.kappa_c;
    let x0: Vec<f64> = match kind {
        ModelKind::Inertial => h0.state.to_vec(),
        ModelKind::QuasiStatic => vec![h0.state[0], h0.state[2]],
    };
    let q0 = logs.to_log(&p0.to_vec());
    let convert = |pt: &HopfCurvePoint| {
        let p = params.with_vec(&logs.from_log(&pt.p));
        let (l1, bound) = curve_l1(&block, kind, &p, pt);
        CurvePoint {
            nu: p.nu,
            kappa: p.kappa,
            m: p.m,
            omega: pt.omega,
            l1,
            // Never below a few units in the last place of l1 itself.
            l1_error_bound: bound.max(4.0 * f64::EPSILON * l1.abs()),
            criticality: Criticality::of(l1, bound),
            state: full_state(kind, &p, &pt.x),
        }
    };
    // One run of the curve from the starting Hopf point, up or down in `second`.
    let run =
        |upward: bool| -> Result<(Vec<CurvePoint>, Vec<SpecialPoint>, CurveEnd), NumericalError> {
            let settings = CurveSettings {
                control: CurveControl {
                    step: StepControl {
                        ds: 0.02,
                        ds_min: 1e-10,
                        ds_max: 0.1,
                        growth: 1.5,
                        easy_iterations: 3,
                        min_tangent_cos: 0.97,
                    },
                    corrector: NewtonSettings {
                        max_iter: 8,
                        ..NewtonSettings::default()
                    },
                    // Arclength measured in (ln kappa, ln second): the state and
                    // omega get small weights, relative to their size, so that a
                    // state or frequency spanning decades (phi = 1/nu is 1e12 at
                    // nu = 1e-12) does not take over the step (with a fixed 1e-16
                    // the decade above nu = 1e-12 took 50 000 points).
                    weights: [vec![1e-16; x0.len() + 1], vec![1.0, 1.0]].concat(),
                    relative: (0..=x0.len()).collect(),
                },
                max_steps,
                // Stop a factor 1e6 below the starting stiffness: closer to kappa_c = 0
                // the Hopf system degenerates (omega -> 0); the end point is then
                // located on the friction law.
                bounds: [
                    (q0[0] + 1e-6f64.ln(), f64::INFINITY),
                    (range.0.ln(), range.1.ln()),
                ],
                increase_second: upward,
                omega_min: 1e-4 * h0.omega_c,
                ..Default::default()
            };
            let mut curve = HopfCurve::new(&logs, &x0, h0.omega_c, &q0, pair, settings)
                .map_err(NumericalError::from)?;
            let (mut points, mut special) = (Vec::new(), Vec::new());
            for pt in curve.by_ref() {
                let pt = pt.map_err(NumericalError::from)?;
                if let Some(b) = pt.events.first().map(|e| &e.point) {
                    let c = convert(b);
                    let series =
                        hopf_series(&logs, &b.x, &b.p, b.omega).map_err(NumericalError::from)?;
                    special.push(SpecialPoint {
                        kind: SpecialKind::Bautin,
                        nu: c.nu,
                        kappa: c.kappa,
                        omega: c.omega,
                        m: c.m,
                        l2: Some(series.l2),
                        l2_error_bound: Some(series.l2_error_bound),
                    });
                }
                points.push(convert(&pt));
            }
            let last = points
                .last()
                .map(|p| if second == Param::Nu { p.nu } else { p.m });
            let end = if upward { range.1 } else { range.0 };
            let at_end = last.is_some_and(|v| (v / end - 1.0).abs() < 1e-10);
            let stop = match curve.stop() {
                Some(Stop::Bound { .. }) if at_end => CurveEnd::EndOfRange,
                Some(Stop::Bound { .. } | Stop::FrequencyVanishing { .. }) => {
                    CurveEnd::KappaCVanishes
                }
                Some(Stop::MaxSteps { .. }) => CurveEnd::StepLimit,
                Some(_) | None => CurveEnd::Stopped,
            };
            if stop == CurveEnd::KappaCVanishes && second == Param::Nu {
                if let Some(nu_end) = points.last().and_then(|p| friction_minimum(params, p.nu)) {
                    special.push(SpecialPoint {
                        kind: SpecialKind::Endpoint,
                        nu: nu_end,
                        kappa: 0.0,
                        omega: 0.0,
                        m: params.m,
                        l2: None,
                        l2_error_bound: None,
                    });
                }
            }
            Ok((points, special, stop))
        };
    let (mut points, mut special, mut stop) = run(true)?;
    // The grid search may have started above the bottom of the range: trace
    // the stretch below as well, and put it in front.
    let start = if second == Param::Nu { p0.nu } else { p0.m };
    if start > range.0 * (1.0 + 1e-12) {
        let (mut below, below_special, below_stop) = run(false)?;
        if stop.ends_curve() && !below_stop.ends_curve() {
            stop = below_stop;
        }
        below.reverse();
        below.pop();
        below.extend(points);
        points = below;
        special.splice(0..0, below_special);
    }
    Ok(StabilityDiagram {
        points,
        special,
        stop,
        complete: stop.ends_curve(),
        lpc: LpcCurves::default(),
        strengthening: Vec::new(),
        reason: None,
    })
}
