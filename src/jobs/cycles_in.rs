//! The `cycles --param P` job: the cycle branch in a control parameter other
//! than the stiffness ([`cycles_in`]), from the Hopf point in that
//! parameter or from a simulated orbit at the scene's value; each cycle
//! handed to an [`Observer`] ([`super::cycles::Observer`]) with the control
//! in its unit; the result ([`CyclesInControl`]) is the command's JSON.

use super::cycles::{branch_status, ModelSwitch, Note, Observer};
use super::restart::{CycleRestartRecord, Labels, Restart};
use super::{SceneSpec, Setup};
use crate::analysis::control::{
    choose_along, cycles_in, upward_range, Control, CyclesInRequest, CyclesStart,
};
use crate::analysis::cycles::collocation_for;
use crate::analysis::cycles::{
    along_branch_order, extremes, requested_points, BranchEnds, CycleRecord, CycleRequest, Leg,
    Quantity,
};
use crate::analysis::model_choice::params_for;
use crate::analysis::orbit_inertia::InertiaWatch;
use crate::error::{Error, InputError};
use crate::params::Param;
use crate::records::branch::ParamValue;
use crate::records::cycle::{Cycle, CycleSpecialPoint, LegStop};
use crate::records::hopf::Critical;
use crate::records::orbit::Source;
use crate::records::params_json;
use crate::records::UnitsRecord;
use crate::scene::Units;
use continuation::periodic::CollocationPoints;
use serde::Serialize;
use serde_json::Value;

/// What `cycles --param P --to VALUE` is asked.
#[derive(Clone, Debug)]
pub struct CyclesInControlRequest {
    /// The control parameter (not the stiffness).
    pub control: Control,
    /// Where the branch ends, in the control's unit.
    pub to: f64,
    /// Where the Hopf point in the control is searched, in its unit.
    pub search: Option<(f64, f64)>,
    /// Values of the control at which cycles are located exactly.
    pub at: Vec<f64>,
    pub from_simulation: bool,
    pub max_steps: usize,
    pub ntst: usize,
    pub ntst_max: usize,
    pub collocation: Option<CollocationPoints>,
    /// Restart from a written cycle (`--from FILE.json --index N`), as
    /// [`super::cycles::CyclesRequest::from`].
    pub from: Option<Restart>,
}

/// The `--at` values of a branch in `control`: every item `NAME=V1,V2,...`
/// names it (as `stickslip cycles --param P --at P=...`).
pub fn asked_values(
    at_kappa: &[f64],
    at: &[String],
    control: Control,
) -> Result<Vec<f64>, InputError> {
    if !at_kappa.is_empty() {
        return Err(InputError::Conflict(format!(
            "--at-kappa asks for stiffnesses, and --param {} continues the cycles in {}: give \
             --at {}=V1,V2,... (in {})",
            control.name(),
            control.name(),
            control.name(),
            control.unit_in_words()
        )));
    }
    let mut out = Vec::new();
    for item in at {
        let (name, values) = item.split_once('=').unwrap_or(("", item));
        if name.trim() != control.name() {
            return Err(InputError::Conflict(format!(
                "--at {item}: the branch is in {} (--param); give --at {}=V1,V2,... (in {})",
                control.name(),
                control.name(),
                control.unit_in_words()
            )));
        }
        for v in values.split(',') {
            out.push(v.trim().parse::<f64>().map_err(|_| InputError::Malformed {
                field: format!("--at {}", control.name()),
                value: v.to_string(),
                expected: format!("a number in {}", control.unit_in_words()),
            })?);
        }
    }
    Ok(out)
}

/// A planned branch: the scene set up with the model judged over the
/// range, the request in the continued parameter.
pub struct Plan {
    pub setup: Setup,
    pub control: Control,
    /// The dimensionless parameter continued.
    pub param: Param,
    request: CyclesInRequest,
    watch: InertiaWatch,
    /// Where the run comes from (the JSON's `source`).
    source: Source,
    /// For a restart, the cycle restarted from, in words.
    restart_text: Option<String>,
    /// For a restart, the cycle restarted from (the JSON's `restarted_from`).
    restarted_from: Option<CycleRestartRecord>,
}

impl Plan {
    /// Sets up `spec`, judges the model over the search range and `to`
    /// (where the inertia ratio is largest; the Hopf point lies in the
    /// search range).
    pub fn new(spec: &SceneSpec, r: &CyclesInControlRequest) -> Result<Plan, Error> {
        let control = r.control;
        let restarted = r.from.as_ref().map(Restart::load).transpose()?;
        let mut setup = match &restarted {
            Some(x) => x.setup(spec)?,
            None => spec.setup(|p| *p)?,
        };
        let source = match &restarted {
            Some(x) => x.source.clone(),
            None => Source::new(spec, &setup),
        };
        let (units, scene_params) = (setup.scene.units, setup.scene_params);
        let param = control.continued(&units)?;
        if let Some(search) = r.search {
            upward_range(search, "--search")?;
        }
        let judged = r
            .search
            .or_else(|| control.default_range(&units, &scene_params, setup.scene.nu_range))
            .map_or((r.to, r.to), |(lo, hi)| (lo.min(r.to), hi.max(r.to)));
        // A restart keeps the model of its cycle (set up from the file).
        if restarted.is_none() {
            setup.choice = choose_along(
                control,
                &units,
                &scene_params,
                Some(judged).filter(|(lo, _)| *lo > 0.0),
                spec.model,
                spec.inertia_threshold,
            );
            setup.params = params_for(setup.choice.kind, &scene_params);
        }
        let restarted_from = restarted.as_ref().map(|x| x.record(&scene_params));
        let restart_text = restarted.as_ref().map(|x| {
            let value = control.from_dimensionless(&units, &scene_params, x.orbit.param(param));
            let (fold, corrected) = x.correction_words();
            format!(
                "restarting from cycle #{} of {}{fold} ({} model, {} = {value:.10e} {}, period \
                 {:.10e} s, NTST {}), corrected on its own mesh {corrected}, continued both ways \
                 in {}",
                x.from.index,
                x.from.file.display(),
                x.orbit.model.name(),
                control.name(),
                control.text_unit(),
                x.orbit.period * units.d0 / units.v0,
                x.orbit.mesh.len() - 1,
                control.name(),
            )
        });
        let collocation = match &restarted {
            // Points other than the model's were forced in the run: again.
            Some(x) if x.cycle.mesh.points != collocation_for(x.orbit.model) => {
                r.collocation.or(Some(x.cycle.mesh.points))
            }
            _ => r.collocation,
        };
        let request = CyclesInRequest {
            control,
            to: r.to,
            search: r.search,
            nu_range: setup.scene.nu_range,
            at: r.at.clone(),
            from_simulation: r.from_simulation,
            stored: restarted.map(|x| (x.log, x.cycle, x.fold_in)),
            cycles: CycleRequest {
                kappa_min: 0.0,
                kappa_max: 0.0,
                max_steps: r.max_steps,
                ntst: r.ntst,
                at_kappa: Vec::new(),
                ntst_max: r.ntst_max,
                collocation,
            },
        };
        let watch = InertiaWatch::new(
            &scene_params,
            source.inertia_threshold,
            source.model.is_none(),
        );
        Ok(Plan {
            setup,
            control,
            param,
            request,
            watch,
            source,
            restart_text,
            restarted_from,
        })
    }

    /// What the text says of the start before the cycles: the cycle
    /// restarted from, for a restart.
    pub fn describe_start(&self) -> Option<&str> {
        self.restart_text.as_deref()
    }

    /// The name of the run (`run_name` of its scene, overrides and model):
    /// the one restarted from, for a restart.
    pub fn source_name(&self) -> String {
        self.source.run_name(&self.setup.scene.name)
    }

    /// The record of the CSV header: the columns of the continued parameter
    /// and of the control in its unit.
    pub fn header_record(&self) -> Cycle {
        Cycle {
            continued: (!matches!(self.param, Param::Kappa | Param::M)).then_some(ParamValue {
                name: self.param.name(),
                value: 0.0,
            }),
            control: control_column(self.control).map(|name| ParamValue { name, value: 0.0 }),
            ..Cycle::default()
        }
    }

    /// The control's axis: its value on a cycle.
    pub fn axis(&self) -> Axis {
        Axis {
            control: self.control,
            param: self.param,
            units: self.setup.scene.units,
            params: self.setup.scene_params,
        }
    }

    /// Traces the branch, handing each cycle to `observer`. `Err` when no
    /// branch started (nothing computed).
    pub fn run(self, observer: &mut dyn Observer) -> Result<CyclesInControl, Error> {
        let axis = self.axis();
        let Plan {
            setup,
            control,
            param,
            request,
            watch,
            source,
            restarted_from,
            ..
        } = self;
        let mut labels = Labels::default();
        let (units, scene_params) = (setup.scene.units, setup.scene_params);
        let kind = setup.choice.kind;
        let mut switch: Option<ControlSwitch> = None;
        let mut cycles: Vec<Cycle> = Vec::new();
        let mut records: Vec<CycleRecord> = Vec::new();
        let mut specials: Vec<CycleSpecialPoint> = Vec::new();
        let traced = cycles_in(kind, &scene_params, &units, &request, &watch, |c| {
            let at = || format!("after {} cycles", records.len());
            if let Some(e) = observer.stop(&at) {
                return Err(e);
            }
            let value = axis.value_of_record(c);
            if let Some(sw) = ModelSwitch::between(records.last(), c, watch.threshold, || {
                format!("{} = {}", control.name(), axis.in_unit(value, 8))
            }) {
                observer.note(Note::Switch(sw.reason.clone()));
                switch = Some(ControlSwitch {
                    switch: sw,
                    param: control.name(),
                    value,
                    unit: control.unit(),
                });
            }
            for rec in c.user.iter().chain([c]) {
                let mut d = record_of(rec, control, param, &setup);
                labels.label(&mut d, rec, observer)?;
                let mut found = Vec::new();
                for (kind, l) in rec.special_points() {
                    let mut cycle = record_of(l, control, param, &setup);
                    labels.label(&mut cycle, l, observer)?;
                    found.push(CycleSpecialPoint { kind, cycle });
                }
                observer.cycle(&d, &found)?;
                specials.extend(found);
                cycles.push(d);
                records.push(rec.without_orbit());
            }
            Ok(())
        })?;
        let leg_stops: Vec<LegStop> = traced
            .legs
            .iter()
            .map(|(leg, o)| LegStop::new(Some(*leg), o, request.cycles.max_steps))
            .collect();
        let mut stop: Vec<String> = leg_stops
            .iter()
            .map(|l| match l.leg {
                Some(Leg::Up) => format!("toward larger {}: {}", control.name(), l.message),
                Some(Leg::Down) => format!("toward smaller {}: {}", control.name(), l.message),
                Some(Leg::LongerPeriod | Leg::ShorterPeriod) => l.to_string(),
                _ => l.message.clone(),
            })
            .collect();
        let (start, critical) = match &traced.start {
            CyclesStart::Hopf(o) => {
                let scene_value = control.value(&units, &scene_params);
                ("hopf", Some(Critical::new(o, scene_value)))
            }
            CyclesStart::Simulation => ("simulation", None),
            CyclesStart::Stored => ("restart", None),
        };
        let (requested, missing) = axis.requested(
            &request.at,
            &records,
            &BranchEnds {
                hopf_start: critical.as_ref().map(|c| c.value),
                stop: &stop.join("; "),
                no_branch: None,
            },
        );
        let mut complete = leg_stops.iter().all(LegStop::complete) && missing.is_none();
        stop.extend(missing);
        // From the Hopf point the cycles go where they are born, which may
        // be away from --to: then none lies between the onset and --to.
        if let Some(c) = critical.as_ref().filter(|_| !cycles.is_empty()) {
            let side = |v: f64| (v - c.value).signum();
            if !cycles
                .iter()
                .any(|cy| side(axis.value_of(cy)) == side(request.to))
            {
                complete = false;
                stop.push(format!(
                    "no cycle between the onset at {name} = {:.6e} {unit} and --to {:.6e} {unit}: \
                     the cycles are born on the other side of this ({}) onset, where the branch \
                     went",
                    c.value,
                    request.to,
                    c.criticality.name(),
                    name = control.name(),
                    unit = control.text_unit(),
                ));
            }
        }
        Ok(CyclesInControl {
            scene: setup.scene.name.clone(),
            model: kind,
            model_reason: setup.choice.reason.clone(),
            // The parameters of the last model used (the scene's inertia
            // after a switch to the inertial model), as `cycles`' `params`.
            params: params_json(match switch {
                Some(_) => &setup.scene_params,
                None => &setup.params,
            }),
            control: ControlEnd {
                param: control.name(),
                unit: control.unit(),
                to: request.to,
                continued: param.name(),
            },
            start,
            restarted_from,
            critical,
            units: UnitsRecord::of(&units),
            along_branch: along_branch_order(&records),
            cycles,
            special_points: specials,
            requested_points: requested,
            complete,
            stop: stop.join("; "),
            leg_stops,
            model_switch: switch,
            files: Vec::new(),
            source,
            orbits_file: None,
            failure: super::cycles::leg_failure(traced.legs),
            setup,
        })
    }
}

/// The control of a branch and the scene it moves.
#[derive(Clone, Copy, Debug)]
pub struct Axis {
    pub control: Control,
    /// The dimensionless parameter continued.
    pub param: Param,
    units: Units,
    params: crate::params::Params,
}

impl Axis {
    /// The control's value (its unit) where the continued parameter is `x`.
    fn at(&self, x: f64) -> f64 {
        self.control
            .from_dimensionless(&self.units, &self.params, x)
    }

    /// The control's value (its unit) on the cycle `c`.
    pub fn value_of(&self, c: &Cycle) -> f64 {
        self.at(match (self.param, &c.continued) {
            (Param::Kappa, _) => c.kappa,
            (Param::M, _) => c.m,
            (_, Some(v)) => v.value,
            (_, None) => f64::NAN,
        })
    }

    /// The control's value (its unit) on the computed cycle `c`.
    pub fn value_of_record(&self, c: &CycleRecord) -> f64 {
        self.at(c.params[self.param as usize])
    }

    /// The control as messages word it (`V`, `value of V`, `µm/s`; no
    /// unit when dimensionless).
    pub fn quantity(&self) -> Quantity<'static> {
        Quantity {
            name: self.control.name(),
            noun: format!("value of {}", self.control.name()).into(),
            unit: self.control.text_unit(),
        }
    }

    /// What became of the values `at` of the control (its unit) asked of
    /// the branch `records`, which started and ended as `ends` says
    /// ([`requested_points`]), and, where some were not delivered, the
    /// stop's words for them: how many, and the span of the control over
    /// the cycles computed.
    fn requested(
        &self,
        at: &[f64],
        records: &[CycleRecord],
        ends: &BranchEnds,
    ) -> (Vec<RequestedValue>, Option<String>) {
        let value_of = |c: &CycleRecord| self.value_of_record(c);
        let quantity = self.quantity();
        let requested: Vec<RequestedValue> = requested_points(at, records, ends, &value_of)
            .into_iter()
            .map(|r| RequestedValue {
                value: r.value,
                unit: self.control.unit(),
                delivered: r.delivered > 0,
                cycles: r.delivered,
                reason: r
                    .reason
                    .map(|why| why.describe(&quantity, &|x, decimals| format!("{x:.decimals$e}"))),
            })
            .collect();
        let missing = requested.iter().filter(|r| r.reason.is_some()).count();
        let words = (missing > 0).then(|| {
            let span = extremes(records, &value_of).map_or_else(String::new, |(lo, hi)| {
                format!(
                    ": the cycles computed span {} = {:.6e} .. {}",
                    quantity.name,
                    lo.0,
                    self.in_unit(hi.0, 6)
                )
            });
            format!(
                "{missing} of the {} requested values not delivered (see requested_points){span}",
                at.len()
            )
        });
        (requested, words)
    }

    /// `value` of the control with `decimals`, and its unit
    /// ([`quantity`](Self::quantity)): `1.5e2 µm/s`.
    pub fn in_unit(&self, value: f64, decimals: usize) -> String {
        self.quantity().with_unit(format!("{value:.decimals$e}"))
    }
}

/// The control of the branch (JSON `control`).
#[derive(Clone, Debug, Serialize)]
pub struct ControlEnd {
    pub param: &'static str,
    pub unit: &'static str,
    /// Where the branch ends, in `unit`.
    pub to: f64,
    /// The dimensionless parameter continued.
    pub continued: &'static str,
}

/// A value of the control asked for (JSON `requested_points`).
#[derive(Clone, Debug, Serialize)]
pub struct RequestedValue {
    pub value: f64,
    pub unit: &'static str,
    pub delivered: bool,
    /// How many cycles were delivered at it (a branch that turns at folds
    /// passes some values twice).
    pub cycles: usize,
    /// Why none was delivered, in words (absent when one was), as the
    /// stiffness branch's `requested_points`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
}

/// Where the branch handed over from the quasi-static to the inertial model
/// (JSON `model_switch`): `cycles`' record, with the control's value there.
#[derive(Clone, Debug, Serialize)]
pub struct ControlSwitch {
    #[serde(flatten)]
    pub switch: ModelSwitch,
    /// The control, and its value (in `unit`) on the last quasi-static and
    /// the first inertial cycle.
    pub param: &'static str,
    pub value: f64,
    pub unit: &'static str,
}

/// The branch in a control parameter: its JSON and the setup.
#[derive(Serialize)]
pub struct CyclesInControl {
    pub scene: String,
    /// The model at the start (`model_switch` says where it changed).
    pub model: crate::model::ModelKind,
    pub model_reason: String,
    pub params: Value,
    pub control: ControlEnd,
    /// `hopf`, `simulation` or `restart`.
    pub start: &'static str,
    /// For a restart, the cycle restarted from; `null` otherwise.
    pub restarted_from: Option<CycleRestartRecord>,
    /// The Hopf point in the control, where the branch started there.
    pub critical: Option<Critical>,
    pub units: UnitsRecord,
    pub cycles: Vec<Cycle>,
    pub special_points: Vec<CycleSpecialPoint>,
    pub requested_points: Vec<RequestedValue>,
    pub complete: bool,
    pub stop: String,
    pub leg_stops: Vec<LegStop>,
    /// Where the branch handed over to the inertial model; `null` where it
    /// did not.
    pub model_switch: Option<ControlSwitch>,
    /// The files written (by the command line).
    pub files: Vec<String>,
    /// Where the run came from, as `cycles`' `source`.
    pub source: Source,
    /// The orbits file, as `cycles`' `orbits_file`.
    pub orbits_file: Option<String>,
    #[serde(skip)]
    pub failure: Option<Error>,
    #[serde(skip)]
    pub setup: Setup,
    /// The indices of `cycles` in their order along the branch: the leg
    /// toward smaller values reversed, then the others (for figures, whose
    /// lines join consecutive cycles).
    #[serde(skip)]
    pub along_branch: Vec<usize>,
}

impl CyclesInControl {
    /// The requested values not delivered, with why.
    pub fn undelivered(&self) -> impl Iterator<Item = (f64, &str)> {
        self.requested_points
            .iter()
            .filter_map(|r| Some((r.value, r.reason.as_deref()?)))
    }

    /// The run's answer as an exit status ([`branch_status`]).
    pub fn status(&mut self) -> Result<(), Error> {
        branch_status(
            self.failure.take(),
            self.cycles.len(),
            self.complete,
            &self.stop,
        )
    }
}

/// The CSV column of the control in its unit, where no other column gives it.
fn control_column(control: Control) -> Option<&'static str> {
    match control {
        Control::V => Some("V_um_per_s"),
        Control::M => Some("M_kg"),
        Control::W => Some("W_N"),
        Control::Tau => Some("tau_s"),
        Control::Eta => Some("eta_s_per_m"),
        Control::K | Control::Dimensionless(_) => None,
    }
}

/// The cycle `c` as a record, in the units at its value of the control.
fn record_of(c: &CycleRecord, control: Control, param: Param, setup: &Setup) -> Cycle {
    let (units, params) = (&setup.scene.units, &setup.scene_params);
    let x = c.params[param as usize];
    let value = control.from_dimensionless(units, params, x);
    let at: Units = control.at(units, params, value).1;
    let mut d = Cycle::new(c, &at);
    d.continued = (!matches!(param, Param::Kappa | Param::M)).then_some(ParamValue {
        name: param.name(),
        value: x,
    });
    d.control = control_column(control).map(|name| ParamValue { name, value });
    d
}
