//! Where a rig's own stiffness lies against the onset at its own driving
//! velocity: steady sliding, stick-slip, or both (bistable), and when a
//! label would be decided by rounding or by an interpolation, undecided.
//!
//! Below the critical stiffness `kappa_c` steady sliding is unstable
//! (docs/model.md; the seed's eq. C11/C12 in closed form). Above it steady
//! sliding is linearly stable; with a subcritical onset (`l1 > 0`) an
//! unstable cycle surrounds it, and stick-slip coexists with it up to the
//! stiffness of the fold of cycles (the seed's section III.D: Brockley's
//! hysteretic onset). Above the fold, and above `kappa_c` with a
//! supercritical onset, only steady sliding remains near the onset.

use crate::analysis::hopf::Criticality;
use crate::analysis::lpc_curve::LpcCurvePoint;
use crate::appendix_c;
use crate::model::ModelKind;
use crate::params::Params;
use serde::Serialize;

/// Relative distances `|K - K_c| / K_c` within which the regime is not
/// decided: the located `kappa_c` agrees with Appendix C to about `1e-15`,
/// and `kappa = K D0 / W` is rounded to a few `1e-16`.
pub const TOLERANCE: f64 = 1e-12;

/// The regime of the rig at its own stiffness and velocity.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Regime {
    /// Steady sliding is stable and no stick-slip cycle coexists with it
    /// near the onset.
    Steady,
    /// Below `K_c`: steady sliding is unstable.
    StickSlip,
    /// Between `K_c` and the fold of cycles of a subcritical onset: stable
    /// steady sliding and stable stick-slip coexist (hysteresis).
    Bistable,
    /// Not decided (the reason says why).
    Undecided,
}

impl Regime {
    /// `steady`, `stick-slip`, `bistable` or `undecided`, as in the JSON.
    pub fn name(self) -> &'static str {
        match self {
            Regime::Steady => "steady",
            Regime::StickSlip => "stick-slip",
            Regime::Bistable => "bistable",
            Regime::Undecided => "undecided",
        }
    }
}

/// The stiffness of the fold of cycles at one velocity, read off a traced
/// curve of folds, with a bound on the error of that reading.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FoldAt {
    pub kappa: f64,
    /// Bound on `|kappa - kappa_fold|` from the interpolation: twice the
    /// difference between the linear and the quadratic interpolant in
    /// `(ln nu, ln kappa)` through the nearest curve points.
    pub error: f64,
}

/// The fold of cycles at `nu` on the traced curves `curves` (each in
/// increasing `nu`): the largest fold stiffness among the curves that span
/// `nu` (the upper edge of the hysteretic band), `None` where no curve
/// spans it or a curve has fewer than three points there.
pub fn fold_at(curves: &[Vec<LpcCurvePoint>], nu: f64) -> Option<FoldAt> {
    curves
        .iter()
        .filter_map(|c| fold_on(c, nu))
        .max_by(|a, b| a.kappa.total_cmp(&b.kappa))
}

fn fold_on(curve: &[LpcCurvePoint], nu: f64) -> Option<FoldAt> {
    let xy: Vec<(f64, f64)> = curve
        .iter()
        .filter(|p| p.nu > 0.0 && p.kappa > 0.0)
        .map(|p| (p.nu.ln(), p.kappa.ln()))
        .collect();
    let x = nu.ln();
    let i = xy.windows(2).position(|w| {
        let (a, b) = (w[0].0.min(w[1].0), w[0].0.max(w[1].0));
        a <= x && x <= b
    })?;
    let ((x0, y0), (x1, y1)) = (xy[i], xy[i + 1]);
    let linear = if x1 == x0 {
        y0
    } else {
        y0 + (y1 - y0) * (x - x0) / (x1 - x0)
    };
    // The third point: the nearer neighbour of the bracket.
    let third = match (i.checked_sub(1), xy.get(i + 2)) {
        (Some(j), Some(&after)) => {
            if (xy[j].0 - x).abs() <= (after.0 - x).abs() {
                xy[j]
            } else {
                after
            }
        }
        (Some(j), None) => xy[j],
        (None, Some(&after)) => after,
        (None, None) => return None,
    };
    let quadratic = lagrange3([(x0, y0), (x1, y1), third], x)?;
    let kappa = linear.exp();
    Some(FoldAt {
        kappa,
        error: 2.0 * (quadratic.exp() - kappa).abs() + TOLERANCE * kappa,
    })
}

/// The quadratic through three points with distinct abscissae, at `x`.
fn lagrange3(p: [(f64, f64); 3], x: f64) -> Option<f64> {
    let mut sum = 0.0;
    for (i, &(xi, yi)) in p.iter().enumerate() {
        let mut w = 1.0;
        for (j, &(xj, _)) in p.iter().enumerate() {
            if i != j {
                if xi == xj {
                    return None;
                }
                w *= (x - xj) / (xi - xj);
            }
        }
        sum += w * yi;
    }
    sum.is_finite().then_some(sum)
}

/// What decides the regime: the onset at the rig's velocity and, with a
/// subcritical onset, the fold of cycles there.
#[derive(Clone, Copy, Debug)]
pub struct StabilityAt {
    pub kappa_c: f64,
    pub criticality: Criticality,
    /// `|K - K_c| / K_c` below which the side is not decided (at least
    /// [`TOLERANCE`]).
    pub tolerance: f64,
    /// With the quasi-static model, the inertia ratio `m nu^2 / mu_v` of the
    /// rig: the relative rise of `kappa_c` the dropped inertia makes (eq. C11).
    pub dropped_inertia: Option<f64>,
    /// The fold of cycles: `None` where it was not looked for, `Some(None)`
    /// where it was and no traced curve spans the velocity.
    pub fold: Option<Option<FoldAt>>,
}

impl StabilityAt {
    /// The onset `kappa_c` (of type `criticality`) located with the model
    /// `kind` on `params` (that model's parameters; `scene` keeps the
    /// scene's inertia): the side of `K_c` is undecided within the larger of
    /// [`TOLERANCE`] and its difference from Appendix C (eq. C11/C12), and,
    /// with the quasi-static model, within the rise of `kappa_c` the dropped
    /// inertia makes.
    pub fn located(
        kind: ModelKind,
        scene: &Params,
        params: &Params,
        (kappa_c, criticality): (f64, Criticality),
        fold: Option<Option<FoldAt>>,
    ) -> StabilityAt {
        let reference = appendix_c::critical_stiffness(params);
        StabilityAt {
            kappa_c,
            criticality,
            tolerance: ((kappa_c - reference) / reference).abs(),
            dropped_inertia: (kind == ModelKind::QuasiStatic && scene.m > 0.0)
                .then(|| scene.inertia_ratio()),
            fold,
        }
    }
}

/// The regime at stiffness `kappa`, its margin `(K - K_c)/K_c` and the
/// reason in words.
pub fn judge(kappa: f64, onset: &StabilityAt) -> (Regime, f64, String) {
    let margin = (kappa - onset.kappa_c) / onset.kappa_c;
    let tolerance = onset.tolerance.max(TOLERANCE);
    let (regime, reason) = if margin.abs() <= tolerance {
        (
            Regime::Undecided,
            format!(
                "K is within {tolerance:.0e} relative of K_c, the accuracy of K_c and of K D0/W: \
                 rounding cannot tell which side it is on"
            ),
        )
    } else if margin < 0.0 {
        (
            Regime::StickSlip,
            "K < K_c: steady sliding is unstable, the block slides by stick-slip".to_string(),
        )
    } else if let Some(ratio) = onset.dropped_inertia.filter(|&r| margin <= r + tolerance) {
        (
            Regime::Undecided,
            format!(
                "K exceeds the quasi-static K_c by less than the shift the dropped inertia makes \
                 (m nu^2/mu_v = {ratio:.3e}, eq. C11): rerun with --model inertial"
            ),
        )
    } else {
        match (onset.criticality, onset.fold) {
            (Criticality::Supercritical, _) => (
                Regime::Steady,
                "K > K_c with a supercritical onset: steady sliding is stable and no small \
                 stick-slip cycle surrounds it"
                    .to_string(),
            ),
            (Criticality::Degenerate, _) => (
                Regime::Undecided,
                "K > K_c, but the onset type is degenerate within rounding: whether stick-slip \
                 cycles coexist with stable steady sliding is not decided"
                    .to_string(),
            ),
            (Criticality::Subcritical, None) => (
                Regime::Undecided,
                "K > K_c with a subcritical onset: steady sliding is stable, but stick-slip \
                 cycles coexist with it (bistable) up to the stiffness of the fold of cycles, \
                 which this judgement does not know (the cycle branch of `stickslip cycles` \
                 locates it)"
                    .to_string(),
            ),
            (Criticality::Subcritical, Some(None)) => (
                Regime::Undecided,
                "K > K_c with a subcritical onset, but no traced curve of folds of cycles spans \
                 this velocity: whether stick-slip coexists with steady sliding here is not \
                 decided; `stickslip cycles --lpc-curve` traces the fold at this velocity"
                    .to_string(),
            ),
            (Criticality::Subcritical, Some(Some(fold))) => {
                if (kappa - fold.kappa).abs() <= fold.error {
                    (
                        Regime::Undecided,
                        format!(
                            "K > K_c with a subcritical onset, within {:.1e} relative (the \
                             reading's error) of the fold of cycles at kappa = {:.6e}: which side \
                             of the fold is not decided",
                            fold.error / fold.kappa,
                            fold.kappa
                        ),
                    )
                } else if kappa < fold.kappa {
                    (
                        Regime::Bistable,
                        format!(
                            "K_c < K < K_fold (kappa_fold = {:.6e}): stable steady sliding and \
                             stable stick-slip coexist; which one the rig shows depends on its \
                             history (hysteretic onset)",
                            fold.kappa
                        ),
                    )
                } else {
                    (
                        Regime::Steady,
                        format!(
                            "K above the fold of cycles (kappa_fold = {:.6e}) of a subcritical \
                             onset: only steady sliding remains near the onset",
                            fold.kappa
                        ),
                    )
                }
            }
        }
    };
    (regime, margin, reason)
}

/// Steady sliding without a Hopf point, in words.
const STABLE: &str = "no Hopf point at this velocity: steady sliding is linearly stable at every \
                      stiffness";

/// [`judge_without_onset`]'s words (no fold known) once `cycles` has
/// simulated the scene from a stick and found no cycle (`why`): still
/// undecided, since a simulation that settles on steady sliding proves no
/// cycle absent.
pub fn without_onset_after_search(why: &str) -> String {
    format!(
        "{STABLE}, but finite-amplitude stick-slip may coexist with it: no fold of cycles is \
         known at this velocity, and the simulations from a stick found no cycle ({why})"
    )
}

/// The regime at stiffness `kappa` where steady sliding has no Hopf point
/// at the rig's velocity (linearly stable at every stiffness): stick-slip
/// may still coexist with it below a fold of cycles that a traced curve of
/// folds reaches at this velocity (past the friction minimum of the cutoff
/// law, Brockley's hysteresis without an onset).
pub fn judge_without_onset(kappa: f64, fold: Option<FoldAt>) -> (Regime, String) {
    match fold {
        None => (
            Regime::Undecided,
            format!(
                "{STABLE}, but finite-amplitude stick-slip may coexist with it (no fold of \
                 cycles is known at this velocity; the simulations from a stick of \
                 `stickslip cycles` look for it)"
            ),
        ),
        Some(fold) if (kappa - fold.kappa).abs() <= fold.error => (
            Regime::Undecided,
            format!(
                "{STABLE}; K is within {:.1e} relative (the reading's error) of the fold of \
                 cycles at kappa = {:.6e}: whether stick-slip coexists is not decided",
                fold.error / fold.kappa,
                fold.kappa
            ),
        ),
        Some(fold) if kappa < fold.kappa => (
            Regime::Bistable,
            format!(
                "{STABLE}, and stick-slip coexists with it below the fold of cycles \
                 (kappa_fold = {:.6e}): which one the rig shows depends on its history",
                fold.kappa
            ),
        ),
        Some(fold) => (
            Regime::Steady,
            format!(
                "{STABLE}, and K lies above the fold of cycles (kappa_fold = {:.6e}): no \
                 stick-slip cycle coexists with it there",
                fold.kappa
            ),
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn curve(f: impl Fn(f64) -> f64, nus: &[f64]) -> Vec<LpcCurvePoint> {
        nus.iter()
            .map(|&nu| LpcCurvePoint {
                nu,
                kappa: f(nu),
                period: 1.0,
                delta_s: 0.1,
            })
            .collect()
    }

    #[test]
    fn a_power_law_fold_curve_is_read_exactly_and_a_curved_one_with_its_error() {
        // kappa = 0.01 nu^0.3 is a line in (ln nu, ln kappa): read exactly.
        let line = curve(|nu| 0.01 * nu.powf(0.3), &[1.0, 2.0, 4.0, 8.0]);
        let at = fold_at(&[line], 3.0).unwrap();
        let exact = 0.01 * 3f64.powf(0.3);
        assert!((at.kappa - exact).abs() <= 1e-15 * exact, "{at:?}");
        assert!(at.error <= 1e-11 * exact);
        // A curved one: the bound covers the true error.
        let bent = |nu: f64| 0.01 * (1.0 + 0.5 * nu.ln().powi(2));
        let at = fold_at(&[curve(bent, &[1.0, 1.5, 2.25, 3.4])], 1.8).unwrap();
        assert!(
            (at.kappa - bent(1.8)).abs() <= at.error,
            "{at:?} vs {}",
            bent(1.8)
        );
        assert!(at.error < 0.05 * at.kappa);
        // Outside every curve, or on a two-point curve: no reading.
        assert!(fold_at(&[curve(bent, &[1.0, 1.5, 2.25])], 5.0).is_none());
        assert!(fold_at(&[curve(bent, &[1.0, 1.5])], 1.2).is_none());
    }

    #[test]
    fn regimes_on_both_sides_of_the_onset_and_of_the_fold() {
        let fold = FoldAt {
            kappa: 1.1,
            error: 1e-3,
        };
        let onset = |criticality, fold| StabilityAt {
            kappa_c: 1.0,
            criticality,
            tolerance: 0.0,
            dropped_inertia: None,
            fold,
        };
        let sub = onset(Criticality::Subcritical, Some(Some(fold)));
        let sup = onset(Criticality::Supercritical, None);
        let cases = [
            (0.9, sub, Regime::StickSlip),
            (1.05, sub, Regime::Bistable),
            (1.2, sub, Regime::Steady),
            (1.1005, sub, Regime::Undecided),
            (1.0 + 1e-13, sub, Regime::Undecided),
            (1.05, sup, Regime::Steady),
            (0.95, sup, Regime::StickSlip),
            (
                1.05,
                onset(Criticality::Subcritical, Some(None)),
                Regime::Undecided,
            ),
            (
                1.05,
                onset(Criticality::Subcritical, None),
                Regime::Undecided,
            ),
            (
                1.05,
                onset(Criticality::Degenerate, None),
                Regime::Undecided,
            ),
            (
                1.05,
                StabilityAt {
                    dropped_inertia: Some(0.1),
                    ..sup
                },
                Regime::Undecided,
            ),
            (
                1.2,
                StabilityAt {
                    dropped_inertia: Some(0.1),
                    ..sup
                },
                Regime::Steady,
            ),
        ];
        for (kappa, o, expected) in cases {
            let (regime, margin, reason) = judge(kappa, &o);
            assert_eq!(regime, expected, "kappa = {kappa}: {reason}");
            assert!((margin - (kappa - 1.0)).abs() < 1e-15);
        }
        let fold = Some(FoldAt {
            kappa: 1.0,
            error: 1e-3,
        });
        for (kappa, fold, expected) in [
            (0.5, fold, Regime::Bistable),
            (1.5, fold, Regime::Steady),
            (1.0005, fold, Regime::Undecided),
            (0.5, None, Regime::Undecided),
        ] {
            let (regime, reason) = judge_without_onset(kappa, fold);
            assert_eq!(regime, expected, "kappa = {kappa}: {reason}");
        }
    }
}
