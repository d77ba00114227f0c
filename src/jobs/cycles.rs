//! The `cycles` job: the stick-slip cycles born at the Hopf point (or
//! reached through a simulated orbit, [`super::cycle_start`]), continued in
//! the stiffness, with the bifurcations of cycles located on the branch,
//! the cycles at requested stiffnesses, and optionally the curves of folds
//! of cycles through its folds. A request in ([`CyclesRequest`]), one record
//! out ([`Cycles`], the command's JSON), each cycle handed to an
//! [`Observer`] as it is computed.

use super::cycle_start::Start;
use super::restart::{Labels, Restart};
use super::{onset_with_degeneracy_resolved, SceneSpec, Setup, TextUnits};
use crate::analysis::control::Control;
use crate::analysis::cycle_at::cycle_at;
use crate::analysis::cycles::{
    along_branch, collocation_for, requested_points, trace_cycles_from, BranchEnds,
    CycleBifurcation, CycleRecord, CycleRequest, Leg,
};
use crate::analysis::hopf::{Criticality, HopfPoint};
use crate::analysis::lpc_curve::{lpc_curve_through, LpcCurves, LpcStop};
use crate::analysis::operating_point::{
    judge, without_onset_after_search, FoldAt, Regime, StabilityAt,
};
use crate::analysis::orbit_inertia::InertiaWatch;
use crate::analysis::return_map;
use crate::error::{Error, InputError};
use crate::model::ModelKind;
use crate::params::Param;
use crate::records::cycle::{
    Asked, Cycle, CycleSpecialPoint, LegStop, OperatingCycle, Requested, SimulatedOrbit,
};
use crate::records::diagram::FoldPoint;
use crate::records::hopf::OperatingPoint;
use crate::records::orbit::{points_name, Source, StoredOrbit};
use crate::records::{params_json, UnitsRecord};
use crate::scene::Units;
use continuation::periodic::CollocationPoints;
use serde::Serialize;
use serde_json::Value;

/// What `cycles` is asked, in the stiffness (the command's options, less
/// those of its output).
#[derive(Clone, Debug)]
pub struct CyclesRequest {
    /// Stop when the stiffness falls below this fraction of `kappa_c` (of
    /// the simulated orbit's stiffness without a Hopf point); in `(0, 1)`.
    pub kappa_fraction: f64,
    /// Start from a simulated orbit even where there is a Hopf point.
    pub from_simulation: bool,
    /// Most continuation steps per leg.
    pub max_steps: usize,
    /// Initial and largest number of mesh intervals.
    pub ntst: usize,
    pub ntst_max: usize,
    /// Collocation points instead of the model's choice.
    pub collocation: Option<CollocationPoints>,
    /// Continue every fold of cycles on the branch in (kappa, nu).
    pub lpc_curve: bool,
    /// Stiffnesses at which cycles are located exactly, as asked.
    pub at: Vec<Asked>,
    /// Where the branch ends, in the unit of a stiffness control
    /// (`--param K --to 1e5`), in place of `kappa_fraction`.
    pub to: Option<(Control, f64)>,
    /// Restart from a cycle an earlier run wrote (`--from FILE.json
    /// --index N`) instead of the Hopf point or a simulated orbit: the
    /// scene is the file's, the branch goes both ways from the cycle.
    pub from: Option<Restart>,
}

impl Default for CyclesRequest {
    /// The command's defaults.
    fn default() -> Self {
        CyclesRequest {
            kappa_fraction: 0.5,
            from_simulation: false,
            max_steps: 500,
            ntst: 40,
            ntst_max: 12800,
            collocation: None,
            lpc_curve: false,
            at: Vec::new(),
            to: None,
            from: None,
        }
    }
}

impl CyclesRequest {
    /// The request checked, each error naming its option.
    fn check(&self) -> Result<(), InputError> {
        if !(self.kappa_fraction > 0.0 && self.kappa_fraction < 1.0) {
            return Err(InputError::out_of_range(
                "--kappa-fraction",
                self.kappa_fraction,
                "in (0, 1)",
            ));
        }
        if self.ntst < 4 {
            return Err(InputError::out_of_range("--ntst", self.ntst as f64, ">= 4"));
        }
        if self.ntst_max < self.ntst {
            return Err(InputError::out_of_range(
                "--ntst-max",
                self.ntst_max as f64,
                &format!(">= --ntst ({})", self.ntst),
            ));
        }
        if let Some((_, t)) = self.to.filter(|(_, t)| !(t.is_finite() && *t > 0.0)) {
            return Err(InputError::out_of_range("--to", t, "> 0 (unit of --param)"));
        }
        if self.from.is_some() && self.from_simulation {
            return Err(InputError::Conflict(
                "--from restarts from a written cycle, --from-simulation from a simulated orbit; \
                 give one"
                    .into(),
            ));
        }
        Ok(())
    }
}

/// What the job says as it goes, besides the cycles.
pub enum Note {
    /// The quasi-static branch handed over to the inertial model.
    Switch(String),
    /// A warning: a forced model outside its validity, negative friction.
    Warning(String),
    /// The regime at the scene's K, decided once the branch located the
    /// fold of cycles ([`decided_by_fold`]).
    Regime(String),
}

/// Receives what the job computes as it computes it: progress,
/// cancellation, each cycle (for incremental output), notes.
pub trait Observer {
    /// `Some(error)` to stop the branch here (`at` says where it stands):
    /// a signal's [`Error::Interrupted`].
    fn stop(&mut self, _at: &dyn Fn() -> String) -> Option<Error> {
        None
    }
    /// Progress in words.
    fn progress(&mut self, _what: &str) {}
    /// A cycle, with the bifurcations located since the previous one; an
    /// error (a file that cannot be written) stops the branch.
    fn cycle(&mut self, _cycle: &Cycle, _found: &[CycleSpecialPoint]) -> Result<(), Error> {
        Ok(())
    }
    /// A note.
    fn note(&mut self, _note: Note) {}
    /// The cycle at the scene's own stiffness (or why there is none),
    /// before the branch.
    fn operating_point(&mut self, _op: &OperatingCycle) {}
    /// The orbit of a cycle just labelled, before the cycle itself is
    /// handed over: what a restart reads ([`Restart`]); an error (a file
    /// that cannot be written) stops the branch.
    fn orbit(&mut self, _orbit: &StoredOrbit) -> Result<(), Error> {
        Ok(())
    }
}

/// An observer that keeps nothing but the result.
pub struct Quiet;

impl Observer for Quiet {}

/// A planned `cycles` run: the scene set up, the onset located and the start
/// of the branch chosen (which may take simulations), before any cycle.
pub struct Plan {
    pub setup: Setup,
    pub start: Start,
    /// The collocation points of the first cycles.
    pub points: CollocationPoints,
    /// The request; it may be amended before the run (requested points
    /// placed relative to the start).
    pub request: CyclesRequest,
    /// The scene's own stiffness against the onset, where it gives one.
    pub operating: Option<OperatingPoint>,
    /// The onset's model and the inertia watch of the branch.
    watch: InertiaWatch,
    /// The model was forced (`--model`).
    forced: bool,
    threshold: f64,
    /// Where the run comes from (the JSON's `source`).
    source: Source,
}

impl Plan {
    /// Sets up `spec`, locates the onset (with the model decision shared by
    /// every command) and chooses where the branch starts.
    pub fn new(spec: &SceneSpec, mut request: CyclesRequest) -> Result<Plan, Error> {
        request.check()?;
        if let Some(from) = &request.from {
            let restarted = from.load()?;
            let setup = restarted.setup(spec)?;
            let source = restarted.source.clone();
            let stored = restarted.cycle.mesh.points;
            // Points other than the model's were forced in the run: again.
            if stored != collocation_for(restarted.orbit.model) {
                request.collocation = request.collocation.or(Some(stored));
            }
            return Ok(Plan {
                watch: InertiaWatch::new(
                    &setup.scene_params,
                    source.inertia_threshold,
                    source.model.is_none(),
                ),
                points: request.collocation.unwrap_or(stored),
                start: Start::Stored(Box::new(restarted)),
                operating: None,
                forced: source.model.is_some(),
                threshold: source.inertia_threshold,
                source,
                setup,
                request,
            });
        }
        let mut setup = spec.setup(|p| *p)?;
        let onset = onset_with_degeneracy_resolved(&mut setup, spec.model.is_some())?;
        let watch = InertiaWatch::new(
            &setup.scene_params,
            spec.inertia_threshold,
            spec.model.is_none(),
        );
        let mut operating = setup
            .stiffness_given()
            .then(|| OperatingPoint::new(&setup, &onset, setup.scene_params.kappa));
        let start = Start::choose(&setup, onset, request.from_simulation, &watch)?;
        // Without an onset the simulations from a stick have looked for a
        // coexisting cycle: the verdict says what they found.
        if let (Some(op), Some(why)) = (operating.as_mut(), start.reason()) {
            if op.regime == Regime::Undecided && op.margin.is_none() && op.kappa > 0.0 {
                op.reason = without_onset_after_search(why);
            }
        }
        let points = request
            .collocation
            .unwrap_or(collocation_for(start.first_model(setup.choice.kind)));
        Ok(Plan {
            source: Source::new(spec, &setup),
            setup,
            start,
            points,
            operating,
            watch,
            forced: spec.model.is_some(),
            threshold: spec.inertia_threshold,
            request,
        })
    }

    /// What is computed, as `hopf` and `diagram` open: the scene, the
    /// model, where the branch starts and the numerics.
    pub fn describe(&self, units: TextUnits) -> Vec<String> {
        let s = &self.setup;
        vec![
            format!("scene: {} — {}", s.scene.name, s.scene.description),
            format!("model: {}", s.choice.reason),
            self.start.describe(s, units),
            numerics(
                self.points,
                self.request.collocation.is_some(),
                self.start.first_model(s.choice.kind),
            ),
        ]
    }

    /// The name of the run (`run_name` of its scene, overrides and model):
    /// the one restarted from, for a restart.
    pub fn source_name(&self) -> String {
        self.source.run_name(&self.setup.scene.name)
    }

    /// `gauss` or `radau`.
    pub fn points_name(&self) -> &'static str {
        points_name(self.points)
    }

    /// Traces the branch, handing each cycle to `observer`, then the
    /// fold-of-cycles curves when asked; what was computed is kept also
    /// when a leg fails or is stopped ([`Cycles::failure`]).
    pub fn run(self, observer: &mut dyn Observer) -> Cycles {
        let Plan {
            setup,
            start,
            points,
            request,
            operating,
            watch,
            forced,
            threshold,
            source,
        } = self;
        let units = setup.scene.units;
        let (at_kappa, asked) = requested_once(&request.at, &units);
        let kappa_ref = start.reference_kappa();
        let to = request
            .to
            .map(|(c, t)| c.to_dimensionless(&units, &setup.scene_params, t));
        let mut req = CycleRequest {
            kappa_min: to.map_or(request.kappa_fraction * kappa_ref, |t| t.min(kappa_ref)),
            kappa_max: to.map_or(10.0 * kappa_ref, |t| t.max(10.0 * kappa_ref)),
            max_steps: request.max_steps,
            ntst: request.ntst,
            at_kappa,
            ntst_max: request.ntst_max,
            // Each model's own points unless forced (the branch may change model).
            collocation: request.collocation,
        };
        // Requested stiffnesses outside the default range extend the branch
        // to them, as the stiffness of a cycle restarted from.
        if let Start::Stored(r) = &start {
            req.at_kappa.push(r.orbit.param(Param::Kappa));
            req.cover_requested();
            req.at_kappa.pop();
        }
        req.cover_requested();
        let mut labels = Labels::default();
        let mut operating = operating.map(OperatingCycle::new);
        // The cycle at the scene's K first: directly, or as the start of
        // a branch from a simulated orbit there.
        let mut at_start = false;
        if let Some(op) = operating.as_mut().filter(|op| op.wanted) {
            match &start {
                Start::Hopf(h) => {
                    observer.progress("the cycle at the scene's K");
                    let rec = operating_cycle(op, &setup, h, &req, &watch);
                    if let (Some(rec), Some(c)) = (rec, op.cycle.as_mut()) {
                        // A write error shows again, and stops the run, at the next orbit.
                        let _ = labels.label(c, &rec, observer);
                    }
                    observer.operating_point(op);
                }
                Start::Simulation { orbit, .. } if orbit.params.kappa == op.point.kappa => {
                    at_start = true;
                }
                _ => {
                    op.not_delivered = Some(
                        start
                            .reason()
                            .unwrap_or(
                                "the simulation settled on a cycle only at another stiffness",
                            )
                            .to_string(),
                    );
                    observer.operating_point(op);
                }
            }
        } else if let Some(op) = &operating {
            observer.operating_point(op);
        }
        let mut switch: Option<ModelSwitch> = None;
        let mut method_switch: Option<MethodSwitch> = None;
        let mut records: Vec<CycleRecord> = Vec::new();
        let mut cycles: Vec<Cycle> = Vec::new();
        let mut specials: Vec<CycleSpecialPoint> = Vec::new();
        let outcomes = start.trace(&setup, &req, &watch, |c| {
            // Counted in the leg the signal came in (the one `c` belongs
            // to): a leg that has handed out no cycle yet was interrupted
            // before its first.
            let at = || {
                let leg: Vec<&CycleRecord> = records.iter().filter(|r| r.leg == c.leg).collect();
                match leg.last() {
                    Some(r) => format!(
                        "after {} cycle{} of this leg, the last at kappa = {:.10e}",
                        leg.len(),
                        if leg.len() == 1 { "" } else { "s" },
                        r.kappa
                    ),
                    None => "before the leg's first cycle".to_string(),
                }
            };
            if let Some(e) = observer.stop(&at) {
                return Err(e);
            }
            observer.progress(&format!(
                "{} cycles, kappa = {:.6e}, {}",
                records.len() + 1,
                c.kappa,
                c.ntst()
                    .map_or_else(|| "return map".to_string(), |n| format!("NTST {n}"))
            ));
            if let Some(sw) = ModelSwitch::between(records.last(), c, threshold, || {
                let u = &setup.scene.units;
                format!(
                    "K/W = {:.8e} 1/m (kappa = {:.8e})",
                    u.k_over_w(c.kappa),
                    c.kappa
                )
            }) {
                observer.note(Note::Switch(sw.reason.clone()));
                switch = Some(sw);
            }
            if let Some(sw) = MethodSwitch::between(records.last(), c) {
                observer.note(Note::Switch(sw.reason.clone()));
                method_switch = Some(sw);
            }
            if let Some(op) = operating
                .as_mut()
                .filter(|_| at_start && records.is_empty())
            {
                op.deliver(c, "branch_start", &units);
                // The same cycle as the branch's first, labelled next.
                if let Some(cycle) = op.cycle.as_mut() {
                    cycle.label = labels.next();
                }
                observer.operating_point(op);
            }
            // The cycles at requested stiffnesses passed since the last one, then it.
            for rec in c.user.iter().chain([c]) {
                let mut cycle = Cycle::new(rec, &units);
                labels.label(&mut cycle, rec, observer)?;
                let mut found = Vec::new();
                for (kind, l) in rec.special_points() {
                    let mut cycle = Cycle::new(l, &units);
                    labels.label(&mut cycle, l, observer)?;
                    found.push(CycleSpecialPoint { kind, cycle });
                }
                observer.cycle(&cycle, &found)?;
                specials.extend(found);
                cycles.push(cycle);
                // The orbits are written: a fold's kept for its curve.
                records.push(rec.without_orbit());
            }
            Ok(())
        });
        if let (Some(op), Start::Hopf(h)) = (operating.as_mut(), &start) {
            if let Some(line) = decided_by_fold(op, &setup, h, &specials, &units) {
                observer.note(Note::Regime(line));
            }
        }
        if let Some(w) = validity_warning(&records, &setup, &watch, forced) {
            observer.note(Note::Warning(w));
        }
        let negative_friction = NegativeFriction::of(&records);
        if let Some(n) = &negative_friction {
            observer.note(Note::Warning(n.reason.clone()));
        }
        let outside_domain = OutsideDomain::of(&records);
        if let Some(o) = &outside_domain {
            observer.note(Note::Warning(o.reason.clone()));
        }
        let leg_stops: Vec<LegStop> = outcomes
            .iter()
            .map(|(leg, outcome)| LegStop::new(*leg, outcome, request.max_steps))
            .collect();
        let legs_complete = leg_stops.iter().all(LegStop::complete);
        let mut stop = match start.reason() {
            Some(_) => {
                "no branch: no Hopf point and no cycle found by simulation (see reason)".to_string()
            }
            None => leg_stops
                .iter()
                .map(ToString::to_string)
                .collect::<Vec<_>>()
                .join("; "),
        };
        let folds = if request.lpc_curve {
            fold_curves(&setup, &records)
        } else {
            FoldCurves::default()
        };
        let requested: Vec<Requested> = requested_points(
            &req.at_kappa,
            &records,
            &BranchEnds {
                hopf_start: match &start {
                    Start::Hopf(h) => Some(h.kappa_c),
                    _ => None,
                },
                stop: &stop,
                no_branch: start.reason(),
            },
            &|c| c.kappa,
        )
        .iter()
        .zip(&asked)
        .map(|(r, a)| Requested::new(r, *a, &units))
        .collect();
        // Partial: a leg ended short of its range, or the search for a start
        // was inconclusive. A requested value the branch did not reach is
        // then among what is missing; one where no cycle exists (above
        // kappa_c, beyond a fold, no branch at all) is answered by its reason.
        let undelivered = requested.iter().filter(|r| r.reason.is_some()).count();
        let operating_missing = operating.as_ref().filter(|op| op.missing()).map(|op| {
            op.not_delivered.clone().unwrap_or_else(|| {
                "the branch from the simulated orbit at the scene's K gave no cycle".into()
            })
        });
        let complete = start.conclusive()
            && legs_complete
            && !folds.incomplete
            && undelivered == 0
            && operating_missing.is_none();
        if let Some(why) = &operating_missing {
            stop = format!("{stop}; the cycle at the scene's K not delivered: {why}");
        }
        if folds.incomplete {
            let why: Vec<String> = folds.stops.iter().map(ToString::to_string).collect();
            stop = format!(
                "{stop}; the fold-of-cycles curve is incomplete: {}",
                why.join("; ")
            );
        }
        if undelivered > 0 {
            stop = format!(
                "{stop}; {undelivered} of the {} requested stiffnesses not delivered (see requested_points)",
                requested.len()
            );
        }
        let failure = leg_failure(outcomes);
        Cycles {
            scene: setup.scene.name.clone(),
            model: setup.choice.kind,
            // The parameters of the last model used (the scene's inertia
            // after a switch to the inertial model).
            params: params_json(&match switch {
                Some(_) => setup.scene_params,
                None => setup.params,
            }),
            kappa_c: start.kappa_c(),
            start: start.json(),
            collocation: points_name(points),
            units: UnitsRecord::of(&units),
            cycles,
            special_points: specials,
            complete,
            stop,
            leg_stops,
            model_switch: switch,
            method_switch,
            requested_points: requested,
            lpc_curve: folds.points,
            lpc_stops: folds.stops,
            operating_point: operating,
            files: Vec::new(),
            source,
            orbits_file: None,
            reason: start.reason().map(str::to_string),
            negative_friction,
            outside_domain,
            records,
            failure,
            setup,
        }
    }
}

/// The cycle at the scene's stiffness `op.point.kappa` below the Hopf point
/// `h`: directly ([`cycle_at`]: simulated in the onset's model, the model
/// judged on the whole orbit, corrected by collocation with `req`'s mesh
/// settings); where that fails, along the branch from `h` to it (the
/// `--at K` path), saying why the first failed.
fn operating_cycle(
    op: &mut OperatingCycle,
    setup: &Setup,
    h: &HopfPoint,
    req: &CycleRequest,
    watch: &InertiaWatch,
) -> Option<CycleRecord> {
    let (units, kappa) = (setup.scene.units, op.point.kappa);
    let direct = match cycle_at(&setup.scene_params, setup.choice.kind, kappa, watch, req) {
        Ok(c) => {
            op.deliver(&c.record, "simulation", &units);
            op.simulation = Some(SimulatedOrbit::new(
                c.simulated.kind,
                &c.simulated.orbit,
                &units,
            ));
            return Some(c.record);
        }
        Err(e) => e.to_string(),
    };
    let mut along = CycleRequest {
        kappa_min: kappa.min(h.kappa_c),
        kappa_max: 10.0 * h.kappa_c,
        at_kappa: vec![kappa],
        ..req.clone()
    };
    along.cover_requested();
    let mut found: Option<CycleRecord> = None;
    // Where the branch passes the scene's K more than once (bistable: an
    // unstable cycle bounding the basin of steady sliding, and a stable
    // one), the stable cycle is the one the rig runs on.
    let end = trace_cycles_from(setup.choice.kind, &setup.params, h, &along, watch, |c| {
        let here = c.user.iter().find(|u| u.kappa == kappa);
        found = match (found.take(), here) {
            (Some(f), Some(u)) if !f.stability.is_stable() && u.stability.is_stable() => {
                Some(u.clone())
            }
            (Some(f), _) => Some(f),
            (None, u) => u.cloned(),
        };
        Ok(())
    });
    match found {
        Some(c) => {
            op.deliver(&c, "continuation", &units);
            op.fallback_reason = Some(direct);
            Some(c)
        }
        None => {
            let end = match end {
                Ok(stop) => {
                    LegStop::new(Some(Leg::FromHopf), &Ok(stop), along.max_steps).to_string()
                }
                Err(e) => e.to_string(),
            };
            op.not_delivered = Some(format!(
                "{direct}; the branch from the Hopf point did not reach it either ({end})"
            ));
            None
        }
    }
}

/// The regime at the scene's K decided by the fold of cycles the branch
/// from a subcritical Hopf point `h` located (the largest fold stiffness
/// among `specials`): `hopf` leaves it undecided above `K_c`, for want of
/// the fold ([`judge`]). Above the fold only steady sliding remains (no
/// cycle is wanted there); between `K_c` and the fold the rig is bistable.
/// Returns the line that says so, when it decided.
fn decided_by_fold(
    op: &mut OperatingCycle,
    setup: &Setup,
    h: &HopfPoint,
    specials: &[CycleSpecialPoint],
    units: &Units,
) -> Option<String> {
    let fold = specials
        .iter()
        .filter(|p| p.kind == CycleBifurcation::Lpc)
        .map(|p| p.cycle.kappa)
        .reduce(f64::max)?;
    if op.point.regime != Regime::Undecided || h.onset.criticality != Criticality::Subcritical {
        return None;
    }
    let onset = StabilityAt::located(
        setup.choice.kind,
        &setup.scene_params,
        &setup.params,
        (h.kappa_c, h.onset.criticality),
        // The fold is located on the branch to the corrector's tolerance.
        Some(Some(FoldAt {
            kappa: fold,
            error: FOLD_LOCATED * fold,
        })),
    );
    let (regime, margin, reason) = judge(op.point.kappa, &onset);
    if regime == Regime::Undecided {
        return None;
    }
    op.point.regime = regime;
    op.point.margin = Some(margin);
    op.point.reason = format!("{reason} (located on the branch)");
    if regime == Regime::Steady {
        op.wanted = false;
        op.not_delivered = None;
    }
    Some(format!(
        "the scene's K = {:.6e} N/m, with the fold of cycles located at K = {:.6e} N/m: {} — {}",
        units.stiffness(op.point.kappa),
        units.stiffness(fold),
        regime.name(),
        op.point.reason
    ))
}

/// Relative accuracy of a fold of cycles located on a branch (the
/// corrector's tolerance on the parameter and the orbit's discretization
/// error, both far below it).
const FOLD_LOCATED: f64 = 1e-9;

/// The result of `cycles`: its JSON, with the records behind it for the
/// figures.
#[derive(Serialize)]
pub struct Cycles {
    pub scene: String,
    /// The model at the start.
    pub model: ModelKind,
    pub params: Value,
    pub kappa_c: Option<f64>,
    pub start: Value,
    pub collocation: &'static str,
    pub units: UnitsRecord,
    pub cycles: Vec<Cycle>,
    pub special_points: Vec<CycleSpecialPoint>,
    /// Everything requested was delivered.
    pub complete: bool,
    /// How the branch ended, in words.
    pub stop: String,
    pub leg_stops: Vec<LegStop>,
    pub model_switch: Option<ModelSwitch>,
    /// Where the branch went on by the return map.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub method_switch: Option<MethodSwitch>,
    pub requested_points: Vec<Requested>,
    pub lpc_curve: Vec<FoldPoint>,
    pub lpc_stops: Vec<LpcStop>,
    /// The cycle at the scene's own stiffness, where the scene or `--set`
    /// gives K.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub operating_point: Option<OperatingCycle>,
    /// The files written (by the command line).
    pub files: Vec<String>,
    /// Where the run came from: the scene as given, the overrides, the
    /// model forced, and the parameters they gave (for a restart).
    pub source: Source,
    /// The file holding every cycle's orbit, one line per `label`
    /// (`<run>-cycles-orbits.jsonl`, by the command line); `null` when
    /// none was written.
    pub orbits_file: Option<String>,
    /// Why there is no branch at all.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub negative_friction: Option<NegativeFriction>,
    /// Cycles whose orbit leaves the friction law's domain (a direct
    /// effect that is not positive), if any.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub outside_domain: Option<OutsideDomain>,
    /// The cycles as computed (orbits for the figures).
    #[serde(skip)]
    pub records: Vec<CycleRecord>,
    /// The first error that ended a leg, if any.
    #[serde(skip)]
    pub failure: Option<Error>,
    /// The scene and model the cycles were computed for.
    #[serde(skip)]
    pub setup: Setup,
}

impl Cycles {
    /// The run's answer as an exit status: a signal or a file that could
    /// not be written is the answer; a failure with nothing kept is the
    /// failure; anything short of the request is partial.
    pub fn status(&mut self) -> Result<(), Error> {
        branch_status(
            self.failure.take(),
            self.records.len(),
            self.complete,
            &self.stop,
        )
    }

    /// Whether a leg was stopped by a signal.
    pub fn interrupted(&self) -> bool {
        matches!(self.failure, Some(Error::Interrupted(_)))
    }

    /// The cycles in order along the branch (each leg from its start).
    pub fn along_branch(&self) -> Vec<&CycleRecord> {
        along_branch(&self.records)
    }
}

/// What ended the legs `outcomes` short, for the exit status: a signal
/// first (in whichever leg it came), else the first failure.
pub fn leg_failure<L, T>(
    outcomes: impl IntoIterator<Item = (L, Result<T, Error>)>,
) -> Option<Error> {
    let (interrupted, failed): (Vec<_>, Vec<_>) = outcomes
        .into_iter()
        .filter_map(|(_, o)| o.err())
        .partition(|e| matches!(e, Error::Interrupted(_)));
    interrupted.into_iter().chain(failed).next()
}

/// The answer of a cycle branch as an exit status: a signal or a file that
/// could not be written (`failure`) is the answer; a failure with no cycle
/// `kept` is the failure; a branch short of its request is partial.
pub fn branch_status(
    failure: Option<Error>,
    kept: usize,
    complete: bool,
    stop: &str,
) -> Result<(), Error> {
    match failure {
        Some(e @ (Error::Interrupted(_) | Error::Output(_))) => Err(e),
        Some(e) if kept == 0 => Err(e),
        _ if !complete => Err(Error::Partial(format!(
            "{kept} cycles written; stopped: {stop}"
        ))),
        _ => Ok(()),
    }
}

/// The cycles of a branch a check picks out (a warning's subject), with
/// their stiffness range.
struct Flagged<'a> {
    cycles: Vec<&'a CycleRecord>,
    kappa_range: [f64; 2],
}

impl<'a> Flagged<'a> {
    /// The cycles of `records` for which `bad` holds; `None` for none.
    fn among(records: &'a [CycleRecord], bad: impl Fn(&CycleRecord) -> bool) -> Option<Self> {
        let cycles: Vec<&CycleRecord> = records.iter().filter(|c| bad(c)).collect();
        if cycles.is_empty() {
            return None;
        }
        let mut flagged = Flagged {
            cycles,
            kappa_range: [0.0; 2],
        };
        flagged.kappa_range = [flagged.least(|c| c.kappa), -flagged.least(|c| -c.kappa)];
        Some(flagged)
    }

    /// The least of `g` over the cycles.
    fn least(&self, g: fn(&CycleRecord) -> f64) -> f64 {
        self.cycles
            .iter()
            .map(|c| g(c))
            .fold(f64::INFINITY, f64::min)
    }
}

/// Cycles on which the friction coefficient, or the spring force that
/// balances it, falls below zero: the friction law outside its physical
/// range (a block pulled forward by friction), reported, not hidden.
#[derive(Clone, Debug, Serialize)]
pub struct NegativeFriction {
    pub cycles: usize,
    pub of: usize,
    pub kappa_range: [f64; 2],
    pub friction_min: f64,
    pub s_min: f64,
    pub reason: String,
}

impl NegativeFriction {
    /// `None` when friction stays non-negative on every cycle. A negative
    /// spring force alone is not flagged: with inertia the block overshoots
    /// and the spring is compressed while friction stays positive, which a
    /// real spring does.
    fn of(records: &[CycleRecord]) -> Option<Self> {
        let bad = Flagged::among(records, |c| c.friction_min < 0.0)?;
        let [kappa_lo, kappa_hi] = bad.kappa_range;
        let (friction_min, s_min) = (bad.least(|c| c.friction_min), bad.least(|c| c.s_min));
        Some(NegativeFriction {
            cycles: bad.cycles.len(),
            of: records.len(),
            kappa_range: bad.kappa_range,
            friction_min,
            s_min,
            reason: format!(
                "negative friction on {} cycles (kappa = {kappa_lo:.6e} .. {kappa_hi:.6e}): the \
                 friction coefficient falls to {friction_min:.4e} and the spring force s to \
                 {s_min:.4e}; the friction law is outside its physical range there (e.g. mu2 < 0 \
                 makes mu fall without bound at long ages), so these cycles are the model's, not \
                 a real interface's",
                bad.cycles.len()
            ),
        })
    }
}

/// Cycles on whose orbit the direct effect `d mu / d ln v = A + 2 mu_vv ln
/// v + mu_vphi ln theta` is not positive: the `(ln v)^2` and
/// `(ln v)(ln theta)` corrections have taken the law out of the domain
/// docs/model.md requires of it (friction rising with the slip velocity at
/// fixed state), which the scene's own velocity satisfies but an orbit over
/// decades of `v` need not; reported, not hidden.
#[derive(Clone, Debug, Serialize)]
pub struct OutsideDomain {
    pub cycles: usize,
    pub of: usize,
    pub kappa_range: [f64; 2],
    pub direct_effect_min: f64,
    pub reason: String,
}

impl OutsideDomain {
    /// `None` when the direct effect stays positive on every cycle.
    fn of(records: &[CycleRecord]) -> Option<Self> {
        let bad = Flagged::among(records, |c| c.direct_effect_min <= 0.0)?;
        let [kappa_lo, kappa_hi] = bad.kappa_range;
        let direct_effect_min = bad.least(|c| c.direct_effect_min);
        Some(OutsideDomain {
            cycles: bad.cycles.len(),
            of: records.len(),
            kappa_range: bad.kappa_range,
            direct_effect_min,
            reason: format!(
                "the friction law leaves its domain on {} of {} cycles (kappa = {kappa_lo:.6e} .. \
                 {kappa_hi:.6e}): the direct effect d mu / d ln v = A + 2 mu_vv ln v + mu_vphi \
                 ln theta falls to {direct_effect_min:.4e} on their orbits, where friction no \
                 longer rises with the slip velocity; these cycles are those of the \
                 extrapolated law, not of the corrections' range of validity (docs/model.md)",
                bad.cycles.len(),
                records.len()
            ),
        })
    }
}

/// The stiffnesses asked for by `--at-kappa` (first) and `--at NAME=...`
/// (in the order given), as asked: each name one of [`Asked::NAMES`], each
/// value a finite number `> 0`; errors name the option and the name.
pub fn asked_stiffnesses(at_kappa: &[f64], at: &[String]) -> Result<Vec<Asked>, InputError> {
    if let Some(k) = at_kappa.iter().find(|k| !(k.is_finite() && **k > 0.0)) {
        return Err(InputError::out_of_range("--at-kappa", *k, "> 0"));
    }
    let mut asked: Vec<Asked> = at_kappa
        .iter()
        .map(|&value| Asked {
            name: "kappa",
            value,
            unit: "1",
        })
        .collect();
    let allowed = || {
        Asked::NAMES
            .iter()
            .map(|(n, u)| format!("{n} [{u}]"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    for item in at {
        let (name, values) = item.split_once('=').ok_or_else(|| InputError::Malformed {
            field: "--at".into(),
            value: item.clone(),
            expected: format!("NAME=V1,V2,... with NAME one of {}", allowed()),
        })?;
        let name = name.trim();
        let Some(&(name, unit)) = Asked::NAMES.iter().find(|(n, _)| *n == name) else {
            return Err(InputError::UnknownName {
                what: "--at stiffness",
                name: name.to_string(),
                suggestion: crate::error::closest(name, Asked::NAMES.iter().map(|(n, _)| *n)),
                allowed: allowed(),
            });
        };
        let field = format!("--at {name}");
        for text in values.split(',') {
            let value: f64 = text.trim().parse().map_err(|_| InputError::Malformed {
                field: field.clone(),
                value: text.to_string(),
                expected: format!("a number ({unit})"),
            })?;
            if !(value.is_finite() && value > 0.0) {
                return Err(InputError::out_of_range(
                    &field,
                    value,
                    &format!("> 0 ({unit})"),
                ));
            }
            asked.push(Asked { name, value, unit });
        }
    }
    Ok(asked)
}

/// The stiffnesses asked for, each once (the first of values whose `kappa`
/// lie within `1e-12` relative of each other, in whatever unit each was
/// asked), in the order given: their `kappa` in the units `u`, and how
/// each was asked.
fn requested_once(asked: &[Asked], u: &Units) -> (Vec<f64>, Vec<Asked>) {
    let mut once: (Vec<f64>, Vec<Asked>) = (Vec::new(), Vec::new());
    for a in asked {
        let k = a.kappa(u);
        if !once.0.iter().any(|&q| (q - k).abs() <= 1e-12 * k.abs()) {
            once.0.push(k);
            once.1.push(*a);
        }
    }
    once
}

/// Where a quasi-static branch handed over to the inertial model (JSON
/// `model_switch`).
#[derive(Clone, Debug, Serialize)]
pub struct ModelSwitch {
    /// The stiffness of the last quasi-static and the first inertial cycle.
    pub kappa: f64,
    /// `chi` on the last quasi-static cycle.
    pub inertial_imbalance: f64,
    pub threshold: f64,
    pub from: &'static str,
    pub to: &'static str,
    /// In words.
    pub reason: String,
}

/// Where a branch went on from collocation to the return map (JSON
/// `method_switch`).
#[derive(Clone, Debug, Serialize)]
pub struct MethodSwitch {
    /// The stiffness of the first cycle of the return map.
    pub kappa: f64,
    pub from: &'static str,
    pub to: &'static str,
    /// In words.
    pub reason: String,
}

impl MethodSwitch {
    /// The switch between `prev`, the cycle before `c` on its leg, and
    /// `c`, where the method changed; `None` where it did not.
    pub fn between(prev: Option<&CycleRecord>, c: &CycleRecord) -> Option<Self> {
        let prev = prev.filter(|p| p.method.name() != c.method.name() && p.leg == c.leg)?;
        Some(MethodSwitch {
            kappa: c.kappa,
            from: prev.method.name(),
            to: c.method.name(),
            reason: return_map::handover_reason(&c.log, prev, c),
        })
    }
}

impl ModelSwitch {
    /// The switch between `prev`, the cycle before `c`, and `c`, where the
    /// model changed along one leg (a quasi-static branch handing over to
    /// the inertial model where the inertia watch said so, with
    /// `threshold`, `--inertia-threshold`), with its reason in words, `at`
    /// saying where (`kappa = ...`); `None` where it did not.
    pub fn between(
        prev: Option<&CycleRecord>,
        c: &CycleRecord,
        threshold: f64,
        at: impl FnOnce() -> String,
    ) -> Option<Self> {
        let prev = prev.filter(|p| p.model != c.model && p.leg == c.leg)?;
        Some(ModelSwitch {
            kappa: c.kappa,
            inertial_imbalance: prev.inertial_imbalance,
            threshold,
            from: "quasi-static",
            to: "inertial",
            reason: format!(
                "switching to the inertial model at {}: on the last quasi-static cycle inertia \
                 would shift ln v by chi = max m |dv/dt| / A = {:.3e} > {threshold:.0e} \
                 (--inertia-threshold); the same orbit, corrected with the scene's inertia, \
                 continues the branch",
                at(),
                prev.inertial_imbalance
            ),
        })
    }
}

/// Under `--model`, where the forced model is outside its validity: a
/// quasi-static model on cycles whose `chi` exceeds the threshold, or an
/// inertial one where inertia is negligible on every cycle.
fn validity_warning(
    records: &[CycleRecord],
    setup: &Setup,
    watch: &InertiaWatch,
    forced: bool,
) -> Option<String> {
    if !forced || records.is_empty() || setup.scene_params.m <= 0.0 {
        return None;
    }
    let outside: Vec<&CycleRecord> = records
        .iter()
        .filter(|c| c.model == ModelKind::QuasiStatic && c.inertial_imbalance > watch.threshold)
        .collect();
    if let (Some(first), Some(last)) = (outside.first(), outside.last()) {
        return Some(format!(
            "--model quasi-static is outside its validity on {} of {} cycles (kappa = {:.6e} .. {:.6e}): \
             there the scene's inertia would shift ln v by chi = max m |dv/dt| / A up to {:.3e} > {:.0e}; \
             without --model the branch switches to the inertial model",
            outside.len(),
            records.len(),
            first.kappa,
            last.kappa,
            outside.iter().map(|c| c.inertial_imbalance).fold(0.0, f64::max),
            watch.threshold
        ));
    }
    let largest = records
        .iter()
        .map(|c| c.inertial_imbalance)
        .fold(0.0, f64::max);
    (setup.choice.kind == ModelKind::Inertial
        && largest < watch.threshold
        && setup.choice.inertia_ratio < watch.threshold)
        .then(|| {
            format!(
                "inertia is negligible on every cycle (chi = max m |dv/dt| / A <= {largest:.3e} < {:.0e}, \
                 inertia ratio at onset {:.3e}): the quasi-static model would give the same cycles",
                watch.threshold, setup.choice.inertia_ratio
            )
        })
}

/// The curves of folds of cycles through the folds of a branch.
#[derive(Default)]
struct FoldCurves {
    points: Vec<FoldPoint>,
    /// Why their ends stopped.
    stops: Vec<LpcStop>,
    /// Whether a curve did not start, or stopped short of its range other
    /// than at a Bautin point: the request (`--lpc-curve`) is incomplete.
    incomplete: bool,
}

/// The curves of folds of cycles through every fold on the branch, each
/// across the scene's velocity range widened to a factor 2 around its fold.
fn fold_curves(setup: &Setup, records: &[CycleRecord]) -> FoldCurves {
    let mut curves = LpcCurves::default();
    let folds = records
        .iter()
        .flat_map(CycleRecord::special_points)
        .filter_map(|(kind, r)| {
            (kind == CycleBifurcation::Lpc)
                .then_some(r.orbit.as_ref())
                .flatten()
        });
    for fold in folds {
        let nu = fold.p[Param::Nu as usize];
        let (lo, hi) = setup.scene.nu_range;
        let range = (lo.min(0.5 * nu), hi.max(2.0 * nu));
        let c = lpc_curve_through(setup.choice.kind, &setup.params, fold, range);
        curves.points.extend(c.points);
        curves.stops.extend(c.stops);
        curves.incomplete |= c.incomplete;
    }
    FoldCurves {
        points: FoldPoint::all(&curves, &setup.scene.units),
        stops: curves.stops,
        incomplete: curves.incomplete,
    }
}

/// What the numerics are and why: the collocation points, and how stability
/// is decided.
fn numerics(points: CollocationPoints, forced: bool, kind: ModelKind) -> String {
    let why = match (forced, points) {
        (true, _) => "as asked (--collocation)",
        (false, CollocationPoints::Radau) => {
            "L-stable, for the stiff relaxation of the velocity while the block sticks"
        }
        (false, CollocationPoints::Gauss) => "no stiff component in the quasi-static model",
    };
    let stability = match kind {
        ModelKind::QuasiStatic => {
            "stability from the nontrivial multiplier exp(int_0^T tr J dt) (Liouville's formula \
             in the plane, as accurate as the collocation quadrature); |mu_1 - 1| checks the \
             Floquet pencil only"
        }
        ModelKind::Inertial => {
            "stability from the Floquet pencil; |mu_1 - 1| is its error at the trivial multiplier"
        }
    };
    format!(
        "collocation: {} points, degree {} ({why}); {stability}",
        match points {
            CollocationPoints::Gauss => "Gauss-Legendre",
            CollocationPoints::Radau => "Radau IIA",
        },
        continuation::periodic::CycleSettings::default().mesh.degree
    )
}
