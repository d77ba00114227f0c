//! The `branch` job: steady sliding continued in a parameter (kappa, nu, or
//! a control parameter in its unit), the eigenvalues at every point and the
//! bifurcations located on it; each point a [`BranchRow`], handed to an
//! [`Observer`] as it is computed; the result ([`Branch`]) is the command's
//! JSON.

use super::restart::{Restart, RestartRecord};
use super::{SceneSpec, Setup};
use crate::analysis::branch::{trace, BranchRequest as Range};
use crate::analysis::control::{choose_along, Control};
use crate::analysis::hopf::{find_hopf, stable_stiffness, HopfOutcome};
use crate::analysis::model_choice::params_for;
use crate::error::{Error, InputError};
use crate::model::{DrivenBlock, ModelKind};
use crate::overrides::Overrides;
use crate::params::{Param, Params};
use crate::records::branch::BranchRow;
use crate::records::orbit::Source;
use crate::records::params_json;
use crate::records::UnitsRecord;
use serde::Serialize;
use serde_json::Value;

/// What `branch` is asked.
#[derive(Clone, Copy, Debug)]
pub struct BranchRequest {
    /// The continuation parameter.
    pub param: Control,
    /// Start value in the unit of `param` (default: kappa, K — a stable
    /// stiffness; nu, V — the bottom of the scene's velocity range; others
    /// — the scene's value).
    pub from: Option<f64>,
    /// End value (default: kappa, K — 1e-3 of the start; nu, V — the top of
    /// the scene's velocity range; others — 1e3 times the start).
    pub to: Option<f64>,
    /// Most continuation steps.
    pub max_steps: usize,
}

/// Receives each point as it is computed.
pub trait Observer {
    /// A point (a located bifurcation first, then the step's point); an
    /// error (a closed output) stops the branch.
    fn point(&mut self, row: &BranchRow) -> Result<(), Error>;
}

/// A planned branch: the scene set up with the model for the whole range,
/// the range in the continued dimensionless parameter.
pub struct Plan {
    pub setup: Setup,
    pub control: Control,
    /// The dimensionless parameter continued, its range and the step limit.
    pub range: Range,
    /// Where the run came from, for a restart from its points.
    pub source: Source,
    /// The point restarted from (`branch --from`), if any.
    pub restarted_from: Option<RestartRecord>,
}

/// `branch --from FILE.json --index N`: continue steady sliding from a
/// point of an earlier `branch --json`.
#[derive(Clone, Debug)]
pub struct BranchRestart {
    /// The file and the point's label.
    pub from: Restart,
    /// The parameter to continue in (`None`: the file's `--param`).
    pub param: Option<Control>,
    /// End value in the unit of `param` (`None`: in the file's parameter,
    /// the file's `to`; in another, the default of a fresh run).
    pub to: Option<f64>,
    /// Most continuation steps.
    pub max_steps: usize,
}

impl Plan {
    /// Sets up `spec`, chooses the model along the branch and its range
    /// (defaults as documented on [`BranchRequest`]), each error naming its option.
    pub fn new(spec: &SceneSpec, request: &BranchRequest) -> Result<Plan, Error> {
        Self::at_params(spec, request, None)
    }

    /// The plan of a restart: the scene, its overrides and the model of
    /// the file (checked to give the same parameters), the parameters of
    /// the point labelled `index`, continued from the point's value exactly
    /// in the file's parameter or in `--param`, to `--to` or the file's
    /// end. `given` is the command line's scene options, which must be
    /// left out ([`Restart::scene_setup`]). Errors are
    /// [`InputError::Restart`] naming the file and the field.
    pub fn restart(given: &SceneSpec, r: &BranchRestart) -> Result<Plan, Error> {
        let point = r.from.load_branch_point()?;
        let (spec, base) = r.from.scene_spec(&point.source, given)?;
        let refuse = |field: &str, why: String| -> Error {
            InputError::Restart {
                path: r.from.file.display().to_string(),
                field: field.to_string(),
                reason: why,
            }
            .into()
        };
        let control = match r.param {
            Some(c) => c,
            None => Control::parse(&point.control, "control")
                .map_err(|e| refuse("control", e.to_string()))?,
        };
        let units = base.scene.units;
        // In the file's parameter the point keeps its run's model; in
        // another one the model is chosen along the new range, as a fresh
        // run at the point's parameters chooses it (the file's forced
        // model, if any, stays forced; a control that moves the inertia
        // then gets the inertial model, as `branch --param M` does).
        let same_param = control.continued(&units)? == point.param;
        let mut spec = spec;
        if same_param {
            spec.model = Some(point.model);
        }
        let request = BranchRequest {
            param: control,
            from: Some(control.value(&units, &point.params)),
            to: r.to,
            max_steps: r.max_steps,
        };
        let mut plan = Self::at_params(&spec, &request, Some(point.params))?;
        // From the point exactly (not through the control's unit), and in
        // the file's parameter (K or kappa alike) to the file's end unless
        // --to says otherwise.
        plan.range.from = point.params.get(plan.range.param);
        if r.to.is_none() && plan.range.param == point.param {
            plan.range.to = point.to;
        }
        if plan.range.from == plan.range.to {
            return Err(refuse(
                "--to",
                format!(
                    "point #{} is the end of the file's branch ({} = {:e}): give --to",
                    r.from.index,
                    point.param.name(),
                    point.to
                ),
            ));
        }
        if same_param {
            plan.setup.choice.reason = format!(
                "{}: the model of point #{} of {}",
                plan.setup.choice.kind.name(),
                r.from.index,
                r.from.file.display()
            );
        }
        let mut source = point.source.clone();
        source
            .at
            .insert(point.param.name().to_string(), point.value);
        plan.source = source;
        plan.restarted_from = Some(RestartRecord::new(
            &r.from,
            "branch point",
            point.model,
            &point.params,
        ));
        Ok(plan)
    }

    /// [`Plan::new`], at the scene's parameters `at` instead of the scene's
    /// own (a restart's point).
    fn at_params(
        spec: &SceneSpec,
        request: &BranchRequest,
        at: Option<Params>,
    ) -> Result<Plan, Error> {
        let control = request.param;
        let overrides = Overrides::parse(&spec.set)?;
        let scene = crate::scene::load_with(&spec.scene, &overrides.physical())?;
        let mut scene_params = scene.params;
        overrides.apply_dimensionless(&mut scene_params)?;
        let scene_params = at.unwrap_or(scene_params);
        let param = control.continued(&scene.units)?;
        control.check_form(&scene_params, "--param")?;
        let (nu_lo, nu_hi) = scene.nu_range;
        // kappa and nu as always (the scene's velocity range as given in the
        // scene); other controls in their unit, converted.
        let (arg_from, arg_to) = match control {
            Control::Dimensionless(Param::Kappa | Param::Nu) => (request.from, request.to),
            _ => control.branch_range(
                &scene.units,
                &scene_params,
                scene.nu_range,
                (request.from, request.to),
            )?,
        };
        // For a velocity branch, inertia is judged at the fastest velocity of the range.
        let top = arg_to.unwrap_or(nu_hi).max(arg_from.unwrap_or(nu_lo));
        let mut setup = spec.setup(|p| {
            let mut q = *p;
            if param == Param::Nu {
                q.nu = top;
            }
            if param == Param::M {
                q.m = arg_to.unwrap_or(q.m).max(arg_from.unwrap_or(q.m));
            }
            q
        })?;
        let source = Source::new(spec, &setup);
        if let Some(at) = at {
            setup.scene_params = at;
            setup.params = params_for(setup.choice.kind, &at);
        }
        if control.moves_inertia(&setup.scene.units) && setup.choice.kind == ModelKind::QuasiStatic
        {
            if spec.model.is_some() {
                return Err(InputError::Conflict(format!(
                    "branch --param {} moves the inertia m, which the quasi-static model drops; \
                 leave out --model quasi-static",
                    control.name()
                ))
                .into());
            }
            setup.choice = choose_along(
                control,
                &setup.scene.units,
                &setup.scene_params,
                None,
                None,
                spec.inertia_threshold,
            );
            setup.params = params_for(setup.choice.kind, &setup.scene_params);
        }
        let kind = setup.choice.kind;
        let from = match (arg_from, param) {
            (Some(v), _) => v,
            (None, Param::Kappa) => {
                stable_stiffness(&DrivenBlock::new(kind, &setup.params), kind, &setup.params)?
            }
            (None, _) => nu_lo,
        };
        let to = match (arg_to, param) {
            (Some(v), _) => v,
            (None, Param::Kappa) => 1e-3 * from,
            (None, _) => nu_hi,
        };
        for (name, v) in [("--from", from), ("--to", to)] {
            // kappa = 0 is no end point: without a spring steady sliding has a
            // zero eigenvalue (a0 = kappa nu in the characteristic polynomial).
            if !(v.is_finite() && v > 0.0) {
                return Err(InputError::out_of_range(
                    name,
                    v,
                    "a finite value > 0 (kappa = 0 has no isolated steady state: the spring holds \
                 nothing; for kappa use e.g. 1e-3 of the start, as the default --to does)",
                )
                .into());
            }
        }
        if param == Param::Nu {
            setup
                .scene_params
                .check_velocity_range((from.min(to), from.max(to)), "--from/--to in nu")?;
        }
        if param != Param::Kappa && setup.params.kappa <= 0.0 {
            return Err(no_stiffness(&setup, control).into());
        }
        if from == to {
            return Err(InputError::Conflict(format!(
                "--from and --to are equal ({from}); give a range"
            ))
            .into());
        }
        Ok(Plan {
            setup,
            control,
            range: Range {
                param,
                from,
                to,
                max_steps: request.max_steps,
            },
            source,
            restarted_from: None,
        })
    }

    /// `--from`, `--to` in the unit of the control: `(from, to)`.
    pub fn control_range(&self) -> (f64, f64) {
        let u = &self.setup.scene.units;
        let in_unit = |x: f64| {
            self.control
                .from_dimensionless(u, &self.setup.scene_params, x)
        };
        (in_unit(self.range.from), in_unit(self.range.to))
    }

    /// Continues the branch, handing every point to `observer`.
    pub fn run(self, observer: &mut dyn Observer) -> Branch {
        let Plan {
            setup,
            control,
            range,
            source,
            restarted_from,
        } = self;
        let (kind, param) = (setup.choice.kind, range.param);
        let (params, scene_params, scene_units) =
            (setup.params, setup.scene_params, setup.scene.units);
        // The units at a point: M and the load follow a branch in M.
        let units = |x: f64| {
            let value = control.from_dimensionless(&scene_units, &scene_params, x);
            control.at(&scene_units, &scene_params, value).1
        };
        let mut points = Vec::new();
        let traced = trace(kind, &params, &range, |point| {
            let events = point
                .events
                .iter()
                .map(|e| (&e.point.p, &e.point.x, &e.point.eigenvalues, Some(&e.kind)));
            for (p, x, eigenvalues, event) in
                events.chain([(&point.p, &point.x, &point.eigenvalues, None)])
            {
                let at = params.with_vec(p);
                let mut row = BranchRow::new(
                    kind,
                    &at,
                    param,
                    x,
                    eigenvalues,
                    event,
                    &units(at.get(param)),
                );
                row.label = points.len();
                observer.point(&row)?;
                points.push(row);
            }
            Ok(())
        });
        let stop = match &traced {
            Ok(None) => None,
            Ok(Some(last)) => Some(format!(
                "the branch ended at {} = {last:.10e}, before --to {:.6e}: the step limit \
                 (--max-steps {}) or a turn of the branch; raise --max-steps or check the range",
                param.name(),
                range.to,
                range.max_steps
            )),
            Err(e) => Some(e.to_string()),
        };
        let in_unit = |x: f64| control.from_dimensionless(&scene_units, &scene_params, x);
        Branch {
            scene: setup.scene.name.clone(),
            model: setup.choice.kind,
            model_reason: setup.choice.reason.clone(),
            params: params_json(&setup.params),
            param: param.name(),
            from: range.from,
            to: range.to,
            units: UnitsRecord::of(&scene_units),
            points,
            complete: stop.is_none(),
            stop,
            // The control of --param when it is not the continued parameter itself.
            control: (control.name() != param.name()).then(|| ControlRange {
                param: control.name(),
                unit: control.unit(),
                from: in_unit(range.from),
                to: in_unit(range.to),
            }),
            source,
            restarted_from,
            failure: traced.err(),
            setup,
        }
    }
}

/// The control of `--param` in its unit, where it is not the continued
/// parameter itself (JSON `control`).
#[derive(Clone, Debug, Serialize)]
pub struct ControlRange {
    pub param: &'static str,
    pub unit: &'static str,
    pub from: f64,
    pub to: f64,
}

/// The branch: its JSON, and the setup it was computed for.
#[derive(Serialize)]
pub struct Branch {
    pub scene: String,
    pub model: ModelKind,
    pub model_reason: String,
    pub params: Value,
    /// The dimensionless parameter continued and its range.
    pub param: &'static str,
    pub from: f64,
    pub to: f64,
    pub units: UnitsRecord,
    pub points: Vec<BranchRow>,
    /// The branch reached `to`.
    pub complete: bool,
    /// Why not.
    pub stop: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub control: Option<ControlRange>,
    /// Where the run came from: the scene as given, the overrides, the
    /// model forced, and the parameters they gave (with `at`, those of the
    /// point a restart started from), for `branch --from` and `hopf --from`.
    pub source: Source,
    /// The point a restart started from (`branch --from`), if any.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub restarted_from: Option<RestartRecord>,
    /// The error that ended the branch, if any.
    #[serde(skip)]
    pub failure: Option<Error>,
    #[serde(skip)]
    pub setup: Setup,
}

impl Branch {
    /// The run's answer as an exit status: a failure as it is, a branch
    /// short of `to` as partial (its rows are kept).
    pub fn status(&mut self) -> Result<(), Error> {
        match (self.failure.take(), &self.stop) {
            (Some(e), _) => Err(e),
            (None, Some(why)) => Err(Error::Partial(why.clone())),
            (None, None) => Ok(()),
        }
    }
}

/// The refusal of a velocity branch without a stiffness, with `kappa_c` at
/// the scene's velocity (located as by `stickslip hopf`) as a hint.
fn no_stiffness(setup: &Setup, control: Control) -> InputError {
    let p = &setup.params;
    let hint = match find_hopf(setup.choice.kind, p) {
        Ok(HopfOutcome::Found(h)) => format!(
            "; at the scene's velocity nu = {:.6e} steady sliding is stable above kappa_c = {:.6e} \
             ({} model, as for this branch), e.g. --set kappa={:.4e} crosses the onset on the branch",
            p.nu,
            h.kappa_c,
            setup.choice.kind.name(),
            h.kappa_c
        ),
        Ok(HopfOutcome::StableForAllStiffness { .. }) => format!(
            "; at the scene's velocity nu = {:.6e} steady sliding is stable for every stiffness",
            p.nu
        ),
        Err(_) => String::new(),
    };
    InputError::Conflict(format!(
        "branch --param {} needs a stiffness: kappa = 0 here (the scene gives no K), and without a \
         spring steady sliding has a zero eigenvalue at every velocity (no isolated equilibrium to \
         continue); give --set kappa=... (kappa = K D0/W){hint}",
        control.name()
    ))
}
