//! The stick-slip onset of the adhesive block: the Hopf point of steady
//! sliding in the stiffness, located by the engine (the steady branch
//! continued in `kappa` downward from twice the closed form's `kappa_c`,
//! the Hopf test function's sign change located by Newton's method on the
//! minimally augmented Hopf system), its normal form, and the closed form
//! of [`block::critical_stiffness`] beside it.

use crate::adhesive::block::{self, AdhesiveModel};
use crate::adhesive::params::{AdhesiveParam, AdhesiveParams};
use crate::analysis::hopf::{onset_at, Criticality};
use crate::error::NumericalError;
use continuation::StepControl;
use continuation::{Branch, ContinuationSettings, Direction, EventKind};

/// A located onset.
#[derive(Clone, Debug, serde::Serialize)]
pub struct AdhesiveOnset {
    /// Critical stiffness `kappa_c` (engine).
    pub kappa_c: f64,
    /// Angular frequency at onset, in `1 / tau_out`.
    pub omega_c: f64,
    /// `kappa_c` of the closed form ([`block::critical_stiffness_of`], the
    /// model's).
    pub kappa_c_closed_form: f64,
    /// The first Lyapunov coefficient in the model's coordinates (`(s, n)`
    /// quasi-static, `(s, ln u, n)` inertial).
    pub l1: f64,
    pub l1_error_bound: f64,
    pub onset: Criticality,
    /// `C` in `Delta_s ~ C sqrt|kappa - kappa_c|` (dimensionless forces).
    pub amplitude_coefficient: Option<f64>,
    /// Steady sliding at onset, the model's state.
    pub state: Vec<f64>,
}

/// What the search found.
#[derive(Clone, Debug)]
pub enum OnsetOutcome {
    Found(AdhesiveOnset),
    /// Steady friction rises with the velocity at `nu` (`dF_ss/du >= 0`):
    /// the trace of the Jacobian, `(kappa_c - kappa) / F_u`, is negative for
    /// every `kappa > 0` (`kappa_c <= 0`), so steady sliding is stable at
    /// every stiffness.
    StableForAllStiffness {
        steady_slope: f64,
    },
}

/// Locates the onset of `model` at the parameters `p` (its `kappa` ignored).
pub fn find_onset<B: AdhesiveModel>(
    model: B,
    p: &AdhesiveParams,
) -> Result<OnsetOutcome, NumericalError> {
    let (closed, _) = block::critical_stiffness_of(p, B::KIND);
    if !closed.is_finite() {
        return Err(NumericalError::Analysis(format!(
            "the slopes of steady friction are not finite at nu = {:e}: the velocity is outside \
             what double precision resolves for this scene",
            p.nu
        )));
    }
    if closed <= 0.0 {
        return Ok(OnsetOutcome::StableForAllStiffness {
            steady_slope: block::steady_slope(p.nu, p),
        });
    }
    let k0 = 2.0 * closed;
    let mut q = *p;
    q.kappa = k0;
    let settings = ContinuationSettings {
        step: StepControl {
            ds: 0.05 * k0,
            ds_max: 0.2 * k0,
            ds_min: 1e-12 * k0,
            ..ContinuationSettings::default().step
        },
        p_min: 1e-6 * k0,
        direction: Direction::Decreasing,
        max_steps: 1000,
        ..Default::default()
    };
    let x0 = model.steady(&q);
    let k = AdhesiveParam::Kappa as usize;
    let branch = Branch::new(&model, &x0, &q.to_vec(), k, settings)?;
    for point in branch {
        let point = point?;
        let hopf = point.events.iter().find_map(|e| match e.kind {
            EventKind::Hopf { omega } => Some((&e.point, omega)),
            EventKind::Fold { .. } => None,
        });
        if let Some((e, omega)) = hopf {
            let kappa_error = (e.param() - closed).abs().max(4.0 * f64::EPSILON * closed);
            let nf = onset_at(&model, &e.x, &e.p, omega, kappa_error)?;
            return Ok(OnsetOutcome::Found(AdhesiveOnset {
                kappa_c: e.param(),
                omega_c: omega,
                kappa_c_closed_form: closed,
                l1: nf.l1,
                l1_error_bound: nf.l1_error_bound,
                onset: nf.criticality,
                amplitude_coefficient: nf.amplitude_coefficient,
                state: e.x.to_vec(),
            }));
        }
        if point.n_unstable > 0 {
            break;
        }
    }
    Err(NumericalError::Analysis(format!(
        "the continuation of steady sliding in kappa from {k0:.6e} found no Hopf point, \
         where the closed form puts kappa_c = {closed:.6e}"
    )))
}
