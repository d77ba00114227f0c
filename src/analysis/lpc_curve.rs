//! The boundary of the hysteretic (bistable) region: the curve of folds of
//! cycles (LPC) in `(nu, kappa)`. It is born at a Bautin point of the Hopf
//! curve, where the onset turns subcritical: there the unstable cycles born
//! at the Hopf point fold back at `kappa_LPC > kappa_c` into large stable
//! stick-slip cycles, which coexist with stable steady sliding for
//! `kappa_c < kappa < kappa_LPC` (Brockley's hysteresis; seed, end of
//! Appendix C). Past the friction minimum steady sliding is stable for every
//! stiffness, and stick-slip below `kappa_LPC` is hysteretic alone.

use crate::analysis::cycles::hopf_with_normal_form;
use crate::analysis::hopf::{find_hopf_with, HopfOutcome};
use crate::error::NumericalError;
use crate::log_model::LogBlock;
use crate::model::ModelKind;
use crate::params::{Param, Params};
use continuation::periodic::Cycle;
use continuation::periodic::{fold_beside_bautin, CycleSettings, Discretization, FloquetPolicy};
use continuation::periodic::{LpcCurve, LpcCurveSettings};
use continuation::ContinuationError;
use continuation::StepControl;
use continuation::{ContinuationSettings, VectorField, Wrap};

/// Mesh intervals of the cycles a curve of folds starts on.
const LPC_NTST: usize = 30;

/// Largest estimated discretization error of a fold along a curve of folds
/// (relative, of `kappa` and the period): the mesh follows it, from 4 up to
/// 8 times the start's intervals.
const LPC_MESH_TOL: f64 = 1e-8;

/// A fold of cycles in docs/model.md's variables.
#[derive(Clone, Debug)]
pub struct LpcCurvePoint {
    pub nu: f64,
    pub kappa: f64,
    /// Period at the fold (units of `D0/V0`).
    pub period: f64,
    /// Peak-to-peak spring force of the cycle at the fold.
    pub delta_s: f64,
}

/// Why a curve of folds of cycles, or one end of it, stopped short.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum LpcStopReason {
    /// No fold of cycles was found near a Hopf point to start a curve from.
    NoFold,
    /// The curve did not start in one direction from its first fold.
    NoStart,
    /// The folded cycles shrink toward the end: the curve ends at a Bautin
    /// point of the Hopf curve nearby, where the fold system degenerates.
    BautinPoint,
    /// The next fold could not be computed on the mesh the curve may use:
    /// its cycles have (most likely) become too stiff for it.
    TooStiff,
    /// The curve reached the end of the velocity range (its last fold lies
    /// on it): complete there.
    EndOfRange,
    /// The curve took its most steps before reaching the range's end.
    StepLimit,
}

/// One stop of a curve of folds of cycles: why, where (`nu`, `kappa` of its
/// last fold, when there is one) and in words.
#[derive(Clone, Debug, serde::Serialize)]
pub struct LpcStop {
    pub reason: LpcStopReason,
    pub nu: Option<f64>,
    pub kappa: Option<f64>,
    pub message: String,
}

impl std::fmt::Display for LpcStop {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

/// The curves of folds of cycles of a diagram (one per Bautin point), in
/// increasing `nu`, and why each end stopped.
#[derive(Clone, Debug, Default)]
pub struct LpcCurves {
    pub points: Vec<Vec<LpcCurvePoint>>,
    pub stops: Vec<LpcStop>,
    /// Whether a curve stopped short of the range for a reason other than
    /// its expected end at a Bautin point (a failed start, stiff cycles):
    /// the request is then incomplete.
    pub incomplete: bool,
    /// The velocity spans `(lo, hi)` in `nu` where a curve was not computed
    /// though it may exist: beyond each end that stopped short, to the edge
    /// of the range or the next Bautin point. The hysteretic region there
    /// is unknown, not absent.
    pub gaps: Vec<(f64, f64)>,
}

/// The span from `from` toward `edge`, cut at the first Bautin point of
/// `bautin` on the way (one at `from` itself, within 1 %, does not cut),
/// as `(lo, hi)`.
fn gap_toward(from: f64, edge: f64, bautin: &[f64]) -> (f64, f64) {
    let beyond = |b: f64| (b / from).ln().abs() >= 0.01 && (b - from) * (edge - from) > 0.0;
    let to = bautin
        .iter()
        .copied()
        .filter(|&b| beyond(b))
        .min_by(|a, b| (a - from).abs().total_cmp(&(b - from).abs()))
        .map_or(edge, |b| {
            if (b - from).abs() < (edge - from).abs() {
                b
            } else {
                edge
            }
        });
    (from.min(to), from.max(to))
}

fn record<S: VectorField>(log: &S, c: &Cycle) -> LpcCurvePoint {
    let (lo, hi) = c.range(log, 0);
    LpcCurvePoint {
        nu: c.p[Param::Nu as usize],
        kappa: c.p[Param::Kappa as usize],
        period: c.period,
        delta_s: hi - lo,
    }
}

/// The fold of the cycles born at the subcritical Hopf point of `params`
/// beside the Bautin point at `bautin_nu` (continued up in `kappa` until
/// they turn back: the engine's [`fold_beside_bautin`]), the models built
/// through `fields`; the normal form in the arithmetic `hopf` uses.
fn first_fold<F: Wrap>(
    fields: &F,
    log: &LogBlock,
    params: &Params,
    bautin_nu: f64,
) -> Result<Cycle, NumericalError> {
    let locator = ContinuationSettings::default().locator;
    let HopfOutcome::Found(h) = find_hopf_with(fields, log.kind, params, &locator)? else {
        return Err(NumericalError::Analysis(
            "no Hopf point next to the Bautin point".into(),
        ));
    };
    // A seed for the curve, on its own mesh: no refinement (the fold is
    // corrected on the curve's mesh when the curve starts).
    let settings = CycleSettings {
        mesh: Discretization {
            ntst: LPC_NTST,
            mesh_tol: None,
            ntst_max: LPC_NTST,
            ..Default::default()
        },
        floquet: FloquetPolicy {
            trivial_tol: None,
            trivial_limit: None,
            ..Default::default()
        },
        p_min: 0.5 * h.kappa_c,
        p_max: 50.0 * h.kappa_c,
        max_steps: 300,
        step: StepControl {
            ds: 0.05,
            ds_max: 0.2,
            ..CycleSettings::default().step
        },
        param_floor: 1e-3 * h.kappa_c,
        ..Default::default()
    };
    let field = fields.field(*log);
    let (x0, p, nf) = hopf_with_normal_form(&field, log, params, &h)?;
    Ok(fold_beside_bautin(
        &field,
        (Param::Nu as usize, bautin_nu),
        (&x0, &p),
        &nf,
        Param::Kappa as usize,
        settings,
    )?)
}

/// Where a curve of folds of cycles starts: a Bautin point of the Hopf
/// curve and the subcritical Hopf point beside it whose folded cycles are
/// continued (velocities `nu`).
#[derive(Clone, Copy, Debug)]
pub struct BautinStart {
    pub bautin_nu: f64,
    pub hopf_nu: f64,
}

/// The curves of folds of cycles from the Bautin points `starts`, within the
/// velocity range; a Bautin point already reached by a curve from another is
/// skipped.
pub fn lpc_curves<F: Wrap>(
    fields: &F,
    kind: ModelKind,
    params: &Params,
    starts: &[BautinStart],
    (lo, hi): (f64, f64),
) -> LpcCurves {
    let log = LogBlock::new(kind, params);
    let mut out = LpcCurves::default();
    let bautin: Vec<f64> = starts.iter().map(|b| b.bautin_nu).collect();
    let near = |nu: f64, b: f64| (nu / b).ln().abs() < 0.01;
    for start in starts {
        // A curve already traced from another Bautin point may end here.
        if out
            .points
            .iter()
            .flatten()
            .any(|p| near(p.nu, start.bautin_nu))
        {
            continue;
        }
        let mut at = *params;
        at.nu = start.hopf_nu;
        let fold = match first_fold(fields, &log, &at, start.bautin_nu) {
            Ok(f) => f,
            Err(e) => {
                out.stops.push(LpcStop {
                    reason: LpcStopReason::NoFold,
                    nu: None,
                    kappa: None,
                    message: format!("no fold of cycles near nu = {:.6e}: {e}", start.hopf_nu),
                });
                out.incomplete = true;
                // Unknown on the subcritical side of the Bautin point.
                let edge = if start.hopf_nu < start.bautin_nu {
                    lo
                } else {
                    hi
                };
                out.gaps.push(gap_toward(start.bautin_nu, edge, &bautin));
                continue;
            }
        };
        let points: Vec<f64> = starts.iter().map(|b| b.bautin_nu).collect();
        let (curve, stops, ends) = trace_through(&fields.field(log), &fold, (lo, hi), &points);
        out.stops.extend(stops);
        out.incomplete |= !ends.is_empty();
        out.gaps.extend(
            ends.into_iter()
                .map(|(from, edge)| gap_toward(from, edge, &bautin)),
        );
        out.points.push(curve);
    }
    drop_covered(&mut out, &bautin);
    out
}

/// Drops the gaps another curve covers (the curve from the next Bautin
/// point can pass where the one from the first stopped short, the Bautin
/// point at a gap's end reached within 1 %, as [`trace_through`] counts
/// it) with the stops at their start: that end is then no failure of the
/// request. The request is incomplete where a gap is left.
fn drop_covered(out: &mut LpcCurves, bautin: &[f64]) {
    let spans: Vec<(f64, f64)> = out
        .points
        .iter()
        .filter(|c| !c.is_empty())
        .map(|c| {
            c.iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                    (lo.min(p.nu), hi.max(p.nu))
                })
        })
        .collect();
    let at_bautin = |nu: f64| bautin.iter().any(|&b| (nu / b).ln().abs() < 1e-12);
    let reach = 0.01f64.exp();
    let covered = |&(lo, hi): &(f64, f64)| {
        let lo = if at_bautin(lo) { lo * reach } else { lo };
        let hi = if at_bautin(hi) { hi / reach } else { hi };
        spans.iter().any(|&(a, b)| a <= lo && b >= hi)
    };
    let (covered_gaps, left): (Vec<_>, Vec<_>) = out.gaps.iter().partition(|g| covered(g));
    out.stops.retain(|s| {
        !s.nu
            .is_some_and(|nu| covered_gaps.iter().any(|&(lo, hi)| nu == lo || nu == hi))
    });
    out.gaps = left;
    out.incomplete = !out.gaps.is_empty();
}

/// The curve of folds of cycles through the fold `fold` (an orbit at a fold
/// in `kappa` in the variables of [`LogBlock::centered`] for `kind` and
/// `params`, as the cycle branches give it), continued in `(kappa, nu)`
/// both ways within `nu` in `(lo, hi)` on the fold's own mesh.
pub fn lpc_curve_through(
    kind: ModelKind,
    params: &Params,
    fold: &Cycle,
    (lo, hi): (f64, f64),
) -> LpcCurves {
    let log = LogBlock::centered(kind, params);
    let (curve, stops, ends) = trace_through(&log, fold, (lo, hi), &[]);
    LpcCurves {
        points: vec![curve],
        stops,
        incomplete: !ends.is_empty(),
        gaps: ends
            .into_iter()
            .map(|(from, edge)| gap_toward(from, edge, &[]))
            .collect(),
    }
}

/// Steps of each half of a curve of folds of cycles.
const LPC_MAX_STEPS: usize = 300;

/// The curve of folds through `fold`, both ways at once, in increasing `nu`,
/// with a message for each end that stopped on a failure away from a Bautin
/// point (`bautin`: where the folded cycles shrink to nothing and the fold
/// system degenerates, the expected end), and the ends that stopped short of
/// the range, as `(nu at the end, edge of the range beyond it)`. A half that
/// failed at or past a Bautin point on its way (within 1 % of it, or beyond:
/// near the point the fold system is too ill-conditioned to see it passed)
/// ended there; its folds beyond it are dropped.
fn trace_through<S: VectorField>(
    log: &S,
    fold: &Cycle,
    (lo, hi): (f64, f64),
    bautin: &[f64],
) -> (Vec<LpcCurvePoint>, Vec<LpcStop>, Vec<(f64, f64)>) {
    let start = fold.p[Param::Nu as usize];
    // The Bautin point at or before `nu` on the way from the start.
    let reached = |nu: f64| {
        bautin.iter().copied().find(|&b| {
            let past = (b - start) * (nu - b) >= 0.0 && (b / start).ln().abs() >= 0.01;
            (nu / b).ln().abs() < 0.01 || past
        })
    };
    let ntst = fold.mesh.ntst();
    let trace = |direction: f64| {
        let settings = LpcCurveSettings {
            p2_min: lo,
            p2_max: hi,
            param_floor: [1e-9, lo],
            min_amplitude: 1e-3,
            max_steps: LPC_MAX_STEPS,
            step: StepControl {
                ds: 0.05,
                ds_max: 0.2,
                ds_min: 1e-5,
                ..LpcCurveSettings::default().step
            },
            mesh_tol: Some(LPC_MESH_TOL),
            ntst_min: 4,
            ntst_max: 8 * ntst,
            ..Default::default()
        };
        let mut half = Vec::new();
        let mut failure = None;
        let mut last_ntst = ntst;
        match LpcCurve::new(
            log,
            fold,
            (Param::Kappa as usize, Param::Nu as usize),
            direction,
            settings,
        ) {
            Ok(points) => {
                for pt in points {
                    match pt {
                        Ok(pt) => {
                            last_ntst = pt.cycle.mesh.ntst();
                            half.push(record(log, &pt.cycle));
                        }
                        Err(e) => {
                            failure = Some(e);
                            break;
                        }
                    }
                }
            }
            Err(e) => failure = Some(e),
        }
        (half, failure, last_ntst)
    };
    let (down, up) = rayon::join(|| trace(-1.0), || trace(1.0));
    let (mut curve, mut stops, mut short) = (Vec::new(), Vec::new(), Vec::new());
    for (direction, (mut half, failure, last_ntst)) in [(-1.0, down), (1.0, up)] {
        let largest = half.iter().fold(0.0f64, |a, p| a.max(p.delta_s));
        let edge = if direction < 0.0 { lo } else { hi };
        let passed = half.last().and_then(|end| reached(end.nu));
        match (failure, half.last(), passed) {
            (Some(cause), None, _) => {
                short.push((fold.p[Param::Nu as usize], edge));
                stops.push(LpcStop {
                    reason: LpcStopReason::NoStart,
                    nu: None,
                    kappa: None,
                    message: format!(
                        "the fold-of-cycles curve did not start toward {} nu: {}",
                        if direction < 0.0 { "smaller" } else { "larger" },
                        // The engine's advice (where to start) is not the
                        // user's to take: the start is the located fold.
                        cause.without_hint()
                    ),
                })
            }
            (Some(_), Some(_), Some(b)) => half.retain(|p| (p.nu - b) * (start - b) >= 0.0),
            (Some(cause), Some(end), None) => {
                // Folded cycles shrinking toward the end: a Bautin point,
                // where the fold system degenerates; else, most likely,
                // cycles too stiff for the mesh.
                let shrinking = end.delta_s < 0.2 * largest;
                if !shrinking {
                    short.push((end.nu, edge));
                }
                let (cause, why, reason) = match cause {
                    ContinuationError::Unresolved {
                        ntst, error, tol, ..
                    } => (
                        if error.is_finite() {
                            format!(
                                "the next fold is no longer resolved: its estimated \
                                 discretization error is {error:.3e} (tolerance {tol:.0e}) with \
                                 {ntst} mesh intervals, the limit"
                            )
                        } else {
                            format!(
                                "the next fold is no longer resolved with {ntst} mesh \
                                 intervals, the limit: half of them cannot carry its cycle, so \
                                 its error cannot even be estimated (tolerance {tol:.0e})"
                            )
                        },
                        "its cycles have become too stiff for the mesh".to_string(),
                        LpcStopReason::TooStiff,
                    ),
                    // In the engine's words: the field names nu.
                    cause => (
                        cause.without_hint().to_string(),
                        if shrinking {
                            format!(
                                "the folded cycles shrink there (Delta_s = {:.3e}, down from \
                                 {largest:.3e}): the curve ends at a Bautin point of the Hopf \
                                 curve nearby, where the fold system degenerates",
                                end.delta_s
                            )
                        } else {
                            format!(
                                "the curve is traced on {last_ntst} mesh intervals there; its \
                                 cycles may have become too stiff for them"
                            )
                        },
                        if shrinking {
                            LpcStopReason::BautinPoint
                        } else {
                            LpcStopReason::TooStiff
                        },
                    ),
                };
                stops.push(LpcStop {
                    reason,
                    nu: Some(end.nu),
                    kappa: Some(end.kappa),
                    message: format!(
                        "the fold-of-cycles curve ends at nu = {:.6e}, kappa = {:.6e}: {cause} ({why})",
                        end.nu, end.kappa,
                    ),
                });
            }
            (None, Some(end), _) => {
                let towards = if direction < 0.0 { "smaller" } else { "larger" };
                if (end.nu / edge).ln().abs() <= 1e-9 {
                    stops.push(LpcStop {
                        reason: LpcStopReason::EndOfRange,
                        nu: Some(end.nu),
                        kappa: Some(end.kappa),
                        message: format!(
                            "the fold-of-cycles curve reaches the end of the range toward {towards} \
                             nu at nu = {:.6e}, kappa = {:.6e}",
                            end.nu, end.kappa
                        ),
                    });
                } else if half.len() > LPC_MAX_STEPS {
                    short.push((end.nu, edge));
                    stops.push(LpcStop {
                        reason: LpcStopReason::StepLimit,
                        nu: Some(end.nu),
                        kappa: Some(end.kappa),
                        message: format!(
                            "the fold-of-cycles curve took its {LPC_MAX_STEPS} steps toward \
                             {towards} nu and ends at nu = {:.6e}, kappa = {:.6e}, short of \
                             the range's end",
                            end.nu, end.kappa
                        ),
                    });
                }
            }
            _ => {}
        }
        if direction < 0.0 {
            half.reverse();
            half.pop();
        }
        curve.extend(half);
    }
    (curve, stops, short)
}

#[cfg(test)]
mod tests {
    use super::gap_toward;

    /// A curve that stopped short leaves unknown the span to the edge of
    /// the range, or to the next Bautin point on the way (where the band
    /// closes); a Bautin point at the end itself does not cut it.
    #[test]
    fn a_short_end_leaves_unknown_the_span_beyond_it() {
        assert_eq!(gap_toward(0.39, 0.1, &[79.0]), (0.1, 0.39));
        assert_eq!(gap_toward(5.9e4, 1e5, &[1.6e3]), (5.9e4, 1e5));
        assert_eq!(gap_toward(3.0, 100.0, &[3.01, 20.0, 50.0]), (3.0, 20.0));
        assert_eq!(gap_toward(3.0, 0.1, &[0.5, 2.0, 20.0]), (2.0, 3.0));
    }
}
