//! The cycle-branch jobs: stick-slip cycles continued from the Hopf point
//! down in the stiffness on a fixed collocation mesh, with Floquet
//! multipliers at every cycle, and the accuracy of the last cycle against
//! long-time integration (a different method).

use super::reference::reference_cycle;
use continuation::periodic::Cycle;
use continuation::periodic::{CycleBranch, CycleSettings, Discretization};
use continuation::StepControl;
use continuation::{VectorField, Wrap};
use stickslip::analysis::cycles::{collocation_for, start_amplitude};
use stickslip::analysis::hopf::{find_hopf, HopfOutcome};
use stickslip::error::{Error, NumericalError};
use stickslip::log_model::LogBlock;
use stickslip::model::ModelKind;
use stickslip::params::{Param, Params};

/// Mesh intervals of every cycle (fixed: no refinement, no coarsening).
pub const NTST: usize = 50;
/// Collocation degree.
pub const DEGREE: usize = 4;
/// Cycles per run (the Hopf point's first cycle included).
pub const CYCLES: usize = 100;

/// A branch of [`CYCLES`] cycles from the Hopf point of a scene, prepared.
pub(super) struct CycleWork {
    kind: ModelKind,
    params: Params,
    log: LogBlock,
    /// Hopf point: state in log variables, angular frequency, parameters.
    x0: Vec<f64>,
    omega: f64,
    at_hopf: Vec<f64>,
    settings: CycleSettings,
}

/// The last cycle of a run, in docs/model.md's variables.
#[derive(Clone, Debug)]
pub struct LastCycle {
    /// The model of the branch.
    pub kind: ModelKind,
    /// The scene's parameters at the cycle's stiffness.
    pub params: Params,
    /// Period by collocation.
    pub period: f64,
    /// Peak-to-peak spring force.
    pub delta_s: f64,
}

/// The last cycle of a branch against long-time integration.
#[derive(Clone, Debug)]
pub struct Accuracy {
    /// Stiffness of the cycle.
    pub kappa: f64,
    /// Period by collocation.
    pub period: f64,
    /// Period by integration (the reference).
    pub period_reference: f64,
    /// `|T / T_ref - 1|`.
    pub period_error: f64,
    /// `|Delta_s / Delta_s_ref - 1|` of the peak-to-peak spring force.
    pub delta_s_error: f64,
    /// The reference period's own uncertainty
    /// ([`ReferenceCycle::period_spread`](super::ReferenceCycle::period_spread)).
    pub reference_spread: f64,
}

impl CycleWork {
    /// The branch of `params` (model `kind`) from its Hopf point down to at
    /// most `fraction kappa_c`, arclength steps up to `ds_max`.
    pub(super) fn new(
        kind: ModelKind,
        params: &Params,
        fraction: f64,
        ds_max: f64,
    ) -> Result<CycleWork, Error> {
        let HopfOutcome::Found(h) = find_hopf(kind, params)? else {
            return Err(stickslip::analysis::cycles::no_onset().into());
        };
        let log = LogBlock::centered(kind, params);
        let mut at = *params;
        at.kappa = h.kappa_c;
        let kappa_min = fraction * h.kappa_c;
        // As `stickslip cycles` sets up the branch, with the mesh held at NTST.
        let settings = CycleSettings {
            mesh: Discretization {
                ntst: NTST,
                ntst_max: NTST,
                degree: DEGREE,
                points: collocation_for(kind),
                mesh_tol: None,
                mesh_accept: None,
                ..Default::default()
            },
            max_steps: CYCLES - 1,
            p_min: kappa_min,
            step: StepControl {
                ds: 1e-3,
                ds_max,
                ..CycleSettings::default().step
            },
            param_floor: 0.5 * kappa_min,
            start_amplitude: start_amplitude(&log),
            ..Default::default()
        };
        Ok(CycleWork {
            kind,
            params: *params,
            x0: log.from_model(h.state[0], h.state[1], h.state[2]),
            log,
            omega: h.omega_c,
            at_hopf: at.to_vec(),
            settings,
        })
    }

    /// Traces the branch, the model built through `fields`: the number of
    /// cycles and the last one.
    pub(super) fn run<F: Wrap>(&self, fields: &F) -> Result<(usize, LastCycle), Error> {
        let field = fields.field(self.log);
        let branch = CycleBranch::from_hopf(
            &field,
            &self.x0,
            self.omega,
            &self.at_hopf,
            Param::Kappa as usize,
            self.settings.clone(),
        )
        .map_err(NumericalError::from)?;
        let mut count = 0;
        let mut last = None;
        for pt in branch {
            last = Some(pt.map_err(NumericalError::from)?.cycle);
            count += 1;
        }
        let last = last.ok_or_else(|| NumericalError::Analysis("an empty cycle branch".into()))?;
        Ok((count, self.summary(&field, &last)))
    }

    /// The cycle `c` of `field` (the model as the branch evaluated it: its
    /// extremes take collocation steps) in docs/model.md's variables.
    fn summary<S: VectorField>(&self, field: &S, c: &Cycle) -> LastCycle {
        let (lo, hi) = c.range(field, 0);
        let mut params = self.params;
        params.kappa = c.p[Param::Kappa as usize];
        LastCycle {
            kind: self.kind,
            params,
            period: c.period,
            delta_s: hi - lo,
        }
    }
}

impl LastCycle {
    /// Compares the cycle with the attractor reached by long-time
    /// integration ([`reference_cycle`]).
    pub fn accuracy(&self) -> Result<Accuracy, Error> {
        let r = reference_cycle(self.kind, &self.params, self.period)?;
        Ok(Accuracy {
            kappa: self.params.kappa,
            period: self.period,
            period_reference: r.period,
            period_error: (self.period / r.period - 1.0).abs(),
            delta_s_error: (self.delta_s / r.delta_s - 1.0).abs(),
            reference_spread: r.period_spread,
        })
    }
}
