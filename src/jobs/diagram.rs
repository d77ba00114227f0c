//! The `diagram` job: the stability diagram of a scene — the Hopf curve
//! in (velocity, stiffness) with the onset type along it, Bautin points,
//! the curves of folds of cycles bounding the hysteretic region — and the
//! rig's operating point against it ([`Diagram`], whose JSON is the
//! command's).

use super::{SceneSpec, Setup};
use crate::analysis::axes::{
    axes_diagram, choose_axes_model, x_range_of, Axes, AxesDiagram, AxesRequest,
};
use crate::analysis::diagram::{stability_diagram_deciding, CurveEnd, StabilityDiagram};
use crate::analysis::hopf::{find_hopf, Criticality, HopfOutcome};
use crate::analysis::operating_point::{fold_at, judge, judge_without_onset, Regime, StabilityAt};
use crate::error::{Error, NumericalError};
use crate::records::diagram::DiagramRecords;
use crate::records::{params_json, significant, UnitsRecord};
use continuation::Wrap;
use serde::Serialize;
use serde_json::{json, Value};

/// What `diagram` is asked for one scene.
#[derive(Clone, Copy, Debug)]
pub struct DiagramRequest {
    /// The velocity range (units of `V0`); `None`: the scene's `V_range`.
    pub nu_range: Option<(f64, f64)>,
    /// Most continuation steps along the Hopf curve in each direction.
    pub max_steps: usize,
}

/// The stability diagram of one scene.
pub struct Diagram {
    /// The scene's own stiffness against the diagram, when it gives one.
    pub operating: Option<OperatingPoint>,
    pub setup: Setup,
    pub range: (f64, f64),
    pub diagram: StabilityDiagram,
    /// The diagram's records, for its CSV, JSON and text.
    pub records: DiagramRecords,
    /// The files written (by the command line) and the time it took.
    pub files: Vec<std::path::PathBuf>,
    pub seconds: f64,
    /// `max_steps`, to name it in the stop reason.
    pub max_steps: usize,
}

/// The diagram of the scene `spec` with the models built through `fields`
/// (the benchmark counts their evaluations; [`continuation::AsIs`] else).
/// Where dropping the scene's inertia changes the onset type anywhere on
/// the curve, the inertia decides, as `hopf` and `cycles` decide at one point.
pub fn run_with<F: Wrap>(
    fields: &F,
    spec: &SceneSpec,
    request: &DiagramRequest,
) -> Result<Diagram, Error> {
    let name = &spec.scene;
    let scene = crate::scene::load(name)?;
    let (lo, hi) = request.nu_range.unwrap_or(scene.nu_range);
    // Inertia grows with nu^2: the model is chosen at the top of the range.
    let mut setup = spec.setup(|p| {
        let mut q = *p;
        q.nu = hi;
        q
    })?;
    setup
        .scene_params
        .check_velocity_range((lo, hi), "--nu-range (default: the scene's V_range / V0)")?;
    let (diagram, decided) = stability_diagram_deciding(
        fields,
        &setup.choice,
        spec.model.is_some(),
        &setup.scene_params,
        (lo, hi),
        request.max_steps,
    )?;
    if let Some(choice) = decided {
        setup.choice = choice;
        setup.params = setup.scene_params;
    }
    if diagram.points.iter().any(|p| {
        !(p.kappa.is_finite() && p.nu.is_finite() && p.omega.is_finite() && p.l1.is_finite())
    }) {
        return Err(NumericalError::Analysis(format!(
            "the Hopf curve of scene '{name}' has non-finite values"
        ))
        .into());
    }
    let records = DiagramRecords::new(&diagram, &setup.params, &setup.scene.units);
    let operating = setup
        .stiffness_given()
        .then(|| OperatingPoint::new(&setup, &diagram, (lo, hi)))
        .transpose()?;
    Ok(Diagram {
        operating,
        setup,
        range: (lo, hi),
        diagram,
        records,
        files: Vec::new(),
        seconds: 0.0,
        max_steps: request.max_steps,
    })
}

impl Diagram {
    /// The command's JSON of the diagram.
    pub fn to_json(&self) -> Value {
        let r = self;
        let records = &r.records;
        let mut out = json!({
            "scene": r.setup.scene.name,
            "model": r.setup.choice.kind,
            "model_reason": r.setup.choice.reason,
            "params": params_json(&r.setup.params),
            "units": UnitsRecord::of(&r.setup.scene.units),
            "nu_range": [r.range.0, r.range.1],
            "hopf_curve": records.curve,
            "special_points": records.special,
            // Partial (status 4) also where the fold-of-cycles curve is.
            "complete": r.diagram.complete && !r.diagram.lpc.incomplete,
            "stop": r.stop_text(),
            "stop_reason": r.diagram.stop,
            "lpc_curve": records.folds,
            "lpc_stops": r.diagram.lpc.stops,
            "lpc_complete": !r.diagram.lpc.incomplete,
            "lpc_gaps": records.fold_gaps,
            "files": r.files.iter().map(|f| f.display().to_string()).collect::<Vec<_>>(),
            "elapsed_s": r.seconds,
            "velocity_strengthening": records.strengthening,
            "onset_type": onset_type(records).map(Criticality::name).unwrap_or("mixed"),
        });
        // Only where the scene gives a stiffness (the diagram's JSON writes no null).
        if let Some(op) = &r.operating {
            out["operating_point"] = json!(op);
        }
        if let Some(why) = &r.diagram.reason {
            out["reason"] = json!(why);
        }
        out
    }

    /// The stop reason in words; a step limit names the option that raises it.
    pub fn stop_text(&self) -> String {
        match self.diagram.stop {
            CurveEnd::StepLimit => format!(
                "step limit ({} steps, --max-steps) before the end of the range",
                self.max_steps
            ),
            stop => stop.words().to_string(),
        }
    }
}

/// The scene's own stiffness and velocity against the diagram (JSON
/// `operating_point`): the onset at the scene's velocity located exactly
/// (as `hopf` does, with the model the diagram decided) and, where it is
/// subcritical, the fold of cycles read off the diagram's traced curves
/// ([`operating_point::judge`]).
#[derive(Clone, Debug, Serialize)]
pub struct OperatingPoint {
    #[serde(rename = "K_N_per_m")]
    pub k_n_per_m: f64,
    pub kappa: f64,
    #[serde(rename = "V_um_per_s")]
    pub v_um_per_s: f64,
    pub nu: f64,
    pub regime: Regime,
    /// `(K - K_c) / K_c` at the scene's velocity; absent without an onset.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub margin: Option<f64>,
    /// `kappa_c` at the scene's velocity (and `K_c`); absent without an onset.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub kappa_c: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    #[serde(rename = "K_c_N_per_m")]
    pub k_c_n_per_m: Option<f64>,
    /// The model `K_c` is located in (adhesive scenes, whose commands
    /// name it beside every `K_c`); absent for rate-and-state scenes.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub model: Option<&'static str>,
    /// The fold of cycles at the scene's velocity, where a traced curve spans
    /// it, and the bound on the error of reading it off that curve.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub kappa_fold: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub kappa_fold_error: Option<f64>,
    /// Whether the scene's velocity lies in the diagram's range (the point is drawn).
    pub in_range: bool,
    pub reason: String,
}

impl OperatingPoint {
    pub fn new(setup: &Setup, d: &StabilityDiagram, (lo, hi): (f64, f64)) -> Result<Self, Error> {
        let p = setup.params;
        let u = &setup.scene.units;
        let kappa = setup.scene_params.kappa;
        let mut op = OperatingPoint::unjudged(
            (u.stiffness(kappa), kappa),
            (u.velocity_um_s(p.nu), p.nu),
            lo <= p.nu && p.nu <= hi,
        );
        if kappa == 0.0 {
            return Ok(op);
        }
        let fold = fold_at(&d.lpc.points, p.nu);
        op.kappa_fold = fold.map(|f| f.kappa);
        op.kappa_fold_error = fold.map(|f| f.error);
        let HopfOutcome::Found(h) = find_hopf(setup.choice.kind, &p)? else {
            (op.regime, op.reason) = judge_without_onset(kappa, fold);
            op.reason = op.with_range_note(op.reason.clone());
            return Ok(op);
        };
        let onset = StabilityAt::located(
            setup.choice.kind,
            &setup.scene_params,
            &p,
            (h.kappa_c, h.onset.criticality),
            Some(fold),
        );
        let (regime, margin, reason) = judge(kappa, &onset);
        op.regime = regime;
        op.margin = Some(margin);
        op.kappa_c = Some(h.kappa_c);
        op.k_c_n_per_m = Some(u.stiffness(h.kappa_c));
        op.reason = op.with_range_note(reason);
        Ok(op)
    }

    /// The point `(K [N/m], kappa)` at `(V [µm/s], nu)`, not judged yet
    /// (undecided, no onset), `in_range` of the diagram; judged at once
    /// where `K = 0`.
    pub(crate) fn unjudged(
        (k_n_per_m, kappa): (f64, f64),
        (v_um_per_s, nu): (f64, f64),
        in_range: bool,
    ) -> OperatingPoint {
        OperatingPoint {
            k_n_per_m,
            kappa,
            v_um_per_s,
            nu,
            regime: Regime::Undecided,
            margin: None,
            kappa_c: None,
            k_c_n_per_m: None,
            model: None,
            kappa_fold: None,
            kappa_fold_error: None,
            in_range,
            reason: if kappa == 0.0 {
                "K = 0: no spring, hence no steady sliding driven through it".into()
            } else {
                String::new()
            },
        }
    }

    /// `reason`, noting when the scene's velocity lies outside the range.
    pub(crate) fn with_range_note(&self, reason: String) -> String {
        if self.in_range {
            reason
        } else {
            format!("{reason} (the scene's velocity lies outside the diagram's range: not drawn)")
        }
    }

    /// The text line: where the rig is, and why.
    pub fn line(&self) -> String {
        let at = match (self.kappa_c, self.k_c_n_per_m) {
            (Some(kc), Some(k)) => {
                let model = self.model.map_or(String::new(), |m| format!(", {m} model"));
                format!(
                    ", where K_c = {} N/m (kappa_c = {kc:.6e}{model})",
                    significant(k)
                )
            }
            _ => String::new(),
        };
        format!(
            "operating point: K = {} N/m (kappa = {:.6e}) at V = {} µm/s{at}: {} — {}",
            significant(self.k_n_per_m),
            self.kappa,
            significant(self.v_um_per_s),
            self.regime.name(),
            self.reason
        )
    }
}

/// The onset type shared by every point of the Hopf curve, `None` where it
/// differs between points (or the curve is empty).
pub fn onset_type(records: &DiagramRecords) -> Option<Criticality> {
    let first = records.curve.first()?.criticality;
    records
        .curve
        .iter()
        .all(|p| p.criticality == first)
        .then_some(first)
}

/// The stability diagram of a scene in a pair of control parameters
/// (`diagram --x P --y Q`).
pub struct PairDiagram {
    pub setup: Setup,
    pub diagram: AxesDiagram,
    /// The regime at the scene's own operating point (its K against the
    /// onset at its parameters, as `hopf` judges it), when the scene gives
    /// both coordinates of the pair and its K.
    pub regime: Option<crate::records::hopf::OperatingPoint>,
}

/// The Hopf curve of the scene `spec` in the pair `axes`: `x_range` of `P`
/// and bounds `y_range` of `Q` in their units (defaults in
/// [`AxesRequest`]), the model judged along `P` ([`choose_axes_model`]).
pub fn run_pair(
    spec: &SceneSpec,
    axes: Axes,
    x_range: Option<(f64, f64)>,
    y_range: Option<(f64, f64)>,
    request: &DiagramRequest,
) -> Result<PairDiagram, Error> {
    let setup = spec.setup(|p| *p)?;
    let (units, params) = (setup.scene.units, setup.scene_params);
    let req = AxesRequest {
        axes,
        x_range,
        y_range,
        nu_range: request.nu_range.unwrap_or(setup.scene.nu_range),
        max_steps: request.max_steps,
    };
    let range = x_range_of(axes, &units, &params, &req)?;
    let choice = choose_axes_model(
        axes,
        &units,
        &params,
        range,
        spec.model,
        spec.inertia_threshold,
    );
    let diagram = axes_diagram(&choice, &params, &units, &req)?;
    // The same judgement as `hopf`'s; where the onset cannot be located the
    // point stays without a regime (the curve is the answer asked for).
    let regime = match diagram.operating {
        Some(_) if setup.stiffness_given() => {
            super::hopf::run(spec, &super::hopf::HopfRequest::default())
                .ok()
                .and_then(|h| h.report.operating_point)
        }
        _ => None,
    };
    Ok(PairDiagram {
        setup,
        diagram,
        regime,
    })
}

impl PairDiagram {
    /// The command's JSON of the diagram (without `files`, `elapsed_s`).
    pub fn to_json(&self) -> Value {
        let mut v = json!({
            "scene": self.setup.scene.name,
            "params": params_json(&self.setup.scene_params),
            "units": UnitsRecord::of(&self.setup.scene.units),
        });
        if let (Value::Object(a), Value::Object(b)) = (&mut v, self.diagram.to_json()) {
            a.extend(b);
        }
        if let (Some(op), Some(Value::Object(point))) = (&self.regime, v.get_mut("operating_point"))
        {
            point.insert("regime".into(), json!(op.regime));
            point.insert("reason".into(), json!(op.reason));
        }
        v
    }
}
