//! Branches of steady sliding in `kappa` or `nu`, with eigenvalues and events.

use crate::error::NumericalError;
use crate::model::{steady_state, DrivenBlock, ModelKind};
use crate::params::{Param, Params};
use continuation::StepControl;
use continuation::{Branch, BranchPoint, ContinuationSettings, Direction};

/// The branch to trace: the parameter and its range.
#[derive(Clone, Copy, Debug)]
pub struct BranchRequest {
    /// `kappa` or `nu`.
    pub param: Param,
    /// Start value (steady sliding is corrected there).
    pub from: f64,
    /// End value: the branch stops on it.
    pub to: f64,
    /// Step limit.
    pub max_steps: usize,
}

/// Traces steady sliding from `from` to `to`, handing each point to `sink`
/// as soon as it is computed (so a failure keeps what was already written).
/// Returns the parameter of the last point when it falls short of `to`
/// (the step limit, or the branch turned), `None` when it reached `to`.
pub fn trace(
    kind: ModelKind,
    params: &Params,
    req: &BranchRequest,
    mut sink: impl FnMut(&BranchPoint) -> Result<(), crate::error::Error>,
) -> Result<Option<f64>, crate::error::Error> {
    let block = DrivenBlock::new(kind, params);
    let mut p = *params;
    p.set(req.param, req.from);
    let span = (req.to - req.from).abs();
    // Arclength mixes the state and the parameter; the state changes on the
    // scale of the parameter for nu (theta = 1/nu), so steps are a fraction of the span.
    let settings = ContinuationSettings {
        step: StepControl {
            ds: 1e-3 * span,
            ds_max: 0.02 * span,
            ds_min: 1e-13 * span.max(1e-300),
            ..ContinuationSettings::default().step
        },
        p_min: req.from.min(req.to),
        p_max: req.from.max(req.to),
        direction: if req.to < req.from {
            Direction::Decreasing
        } else {
            Direction::Increasing
        },
        max_steps: req.max_steps,
        ..Default::default()
    };
    let x0 = steady_state(kind, &p);
    let branch = Branch::new(&block, &x0, &p.to_vec(), req.param as usize, settings)
        .map_err(NumericalError::from)?;
    let mut last = req.from;
    for point in branch {
        let point = point.map_err(NumericalError::from)?;
        last = point.p[req.param as usize];
        sink(&point)?;
    }
    // Signed distance still to go, relative to the span.
    let to_go = (req.to - last) * (req.to - req.from).signum();
    Ok((to_go > 1e-9 * span).then_some(last))
}
