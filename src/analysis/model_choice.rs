//! Choosing the quasi-static or the inertial model.
//!
//! Inertia enters the critical stiffness only through the factor
//! `1 + m nu^2 / mu_v` (seed eq. C11). When that ratio is below a threshold
//! the quasi-static model changes `kappa_c` by less than the threshold
//! (relative), and it is the one used; otherwise the inertial model is.
//! One exception, decided by [`inertia_decides`] for every command alike:
//! where dropping the scene's inertia changes the onset type (the
//! quasi-static onset degenerate, `l1 = 0` within its bound as for the plain
//! Rice–Ruina law, or of the other sign), that inertia, however small,
//! decides it, and the inertial model is used.

use crate::model::ModelKind;
use crate::params::Params;

/// Default threshold on `m nu^2 / mu_v` below which inertia is dropped.
pub const DEFAULT_INERTIA_THRESHOLD: f64 = 1e-3;

/// The model an analysis uses and why.
#[derive(Clone, Debug)]
pub struct ModelChoice {
    /// The model.
    pub kind: ModelKind,
    /// The inertia ratio `m nu^2 / mu_v` of the scene.
    pub inertia_ratio: f64,
    /// A sentence saying why.
    pub reason: String,
}

/// Picks the model for `params`; `forced` (from `--model`) wins.
pub fn choose_model(params: &Params, forced: Option<ModelKind>, threshold: f64) -> ModelChoice {
    let ratio = params.inertia_ratio();
    let (kind, reason) = match forced {
        Some(ModelKind::QuasiStatic) if params.m > 0.0 => (
            ModelKind::QuasiStatic,
            format!("quasi-static as requested (--model); inertia m = {:.3e} dropped, which shifts kappa_c by {ratio:.3e} relative (eq. C11)", params.m),
        ),
        Some(k) => (k, format!("{} as requested (--model); inertia ratio m nu^2/mu_v = {ratio:.3e}", k.name())),
        None if params.m == 0.0 => {
            (ModelKind::QuasiStatic, "quasi-static: the scene has no inertia (m = 0)".to_string())
        }
        None if ratio < threshold => (
            ModelKind::QuasiStatic,
            format!(
                "quasi-static: inertia ratio m nu^2/mu_v = {ratio:.3e} < {threshold:.0e}, so inertia \
                 shifts kappa_c by only {ratio:.3e} relative (eq. C11); m = {:.3e} dropped",
                params.m
            ),
        ),
        None => (
            ModelKind::Inertial,
            format!(
                "inertial: inertia ratio m nu^2/mu_v = {ratio:.3e} >= {threshold:.0e} shifts kappa_c \
                 by that much relative (eq. C11)"
            ),
        ),
    };
    ModelChoice {
        kind,
        inertia_ratio: ratio,
        reason,
    }
}

/// The parameters the chosen model actually uses (`m = 0` when quasi-static).
pub fn params_for(kind: ModelKind, params: &Params) -> Params {
    let mut p = *params;
    if kind == ModelKind::QuasiStatic {
        p.m = 0.0;
    }
    p
}

/// The inertial model in place of an automatic quasi-static `choice` where
/// dropping the inertia changes the onset type: `compare` (called only when
/// the choice could change: not forced, the scene has inertia `m > 0`, the
/// choice is quasi-static) gives `(changed, of)`, the count of the `of` Hopf
/// points compared (one for `hopf` and `cycles`, every point of a `diagram`
/// curve) where the quasi-static onset is degenerate (`l1 = 0` within its
/// bound) or of another type than the inertial one, or `None` when the
/// inertial onset could not be computed. The inertia ratio bounds the shift
/// of `kappa_c`, not of `l1`: a small `l1` can change sign with an inertia
/// that moves `kappa_c` by 1e-4 only. `None` (keep `choice`) when no onset
/// type changes.
pub fn inertia_decides(
    choice: &ModelChoice,
    forced: bool,
    m: f64,
    compare: impl FnOnce() -> Option<(usize, usize)>,
) -> Option<ModelChoice> {
    if forced || m <= 0.0 || choice.kind != ModelKind::QuasiStatic {
        return None;
    }
    let (changed, of) = compare().filter(|&(changed, _)| changed > 0)?;
    let where_ = if of == 1 {
        "the quasi-static onset type is not the inertial one".to_string()
    } else {
        format!(
            "the quasi-static onset type is not the inertial one at {changed} of the {of} \
             points of the quasi-static curve"
        )
    };
    Some(ModelChoice {
        kind: ModelKind::Inertial,
        inertia_ratio: choice.inertia_ratio,
        reason: format!(
            "inertial: {where_} (degenerate, l1 = 0 to rounding, or of the other sign), so the \
             scene's small inertia (m nu^2/mu_v = {:.3e}) decides the onset type",
            choice.inertia_ratio
        ),
    })
}
