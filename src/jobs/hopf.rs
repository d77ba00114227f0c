//! The `hopf` job: the stick-slip onset of a scene in the stiffness or in
//! any control parameter ([`Control`]), its type from the normal form, the
//! rig's operating point, next to Appendix C ([`HopfReport`], the
//! command's JSON).

use super::restart::Restart;
use super::{onset_with_degeneracy_resolved, SceneSpec, Setup};
use crate::analysis::control::{choose_along, onset_in, upward_range, Control, OnsetIn};
use crate::analysis::hopf::HopfOutcome;
use crate::analysis::model_choice::{choose_model, params_for};
use crate::error::{Error, InputError, NumericalError};
use crate::params::Params;
use crate::records::hopf::{Critical, HopfReport};

/// What `hopf` is asked.
#[derive(Clone, Debug, Default)]
pub struct HopfRequest {
    /// The control parameter of the onset (`None`: the stiffness).
    pub param: Option<Control>,
    /// The range searched, in the unit of `param` (not for the stiffness).
    pub from: Option<f64>,
    pub to: Option<f64>,
}

/// The onset found: the report (the JSON) and the setup it is for.
pub struct Hopf {
    pub report: HopfReport,
    /// The scene and model at the onset (in a control other than the
    /// stiffness: the scene's parameters moved to the critical value).
    pub setup: Setup,
    /// A note for the reader: the scene's own stiffness is not used to find
    /// the onset but compared with it.
    pub note: Option<String>,
}

/// Locates the onset asked for.
pub fn run(spec: &SceneSpec, request: &HopfRequest) -> Result<Hopf, Error> {
    run_at(spec, request, None)
}

/// `hopf --from FILE.json --index N`: the onset asked for at the
/// parameters of a written cycle or branch point ([`Restart::load_point`]),
/// with the scene, overrides and forced model of the run that wrote it
/// (`given`, the command line's scene options, must leave them out:
/// [`Restart::scene_spec`]); the model is chosen as for `hopf --set` of
/// those parameters. The report's `restarted_from` names the point.
pub fn run_from(given: &SceneSpec, from: &Restart, request: &HopfRequest) -> Result<Hopf, Error> {
    let point = from.load_point()?;
    let (spec, _) = from.scene_spec(&point.source, given)?;
    let mut hopf = run_at(&spec, request, Some(point.params))?;
    hopf.report.restarted_from = Some(point.record());
    Ok(hopf)
}

/// The scene of `spec` set up, at the parameters `at` if given (the model
/// chosen for them, their stiffness given as the scene's).
fn setup_at(spec: &SceneSpec, at: Option<Params>) -> Result<Setup, Error> {
    let mut setup = spec.setup(|p| *p)?;
    if let Some(at) = at {
        setup.scene_params = at;
        setup.scene.stiffness_given = at.kappa > 0.0;
        setup.choice = choose_model(&at, spec.model, spec.inertia_threshold);
        setup.params = params_for(setup.choice.kind, &at);
    }
    Ok(setup)
}

/// [`run`] at the parameters `at` instead of the scene's (`None`: the scene's).
fn run_at(spec: &SceneSpec, request: &HopfRequest, at: Option<Params>) -> Result<Hopf, Error> {
    if let Some(c) = request.param.filter(|c| !c.is_stiffness()) {
        return run_in_control(spec, request, c, at);
    }
    if let Some(field) = [("--from", request.from), ("--to", request.to)]
        .into_iter()
        .find_map(|(f, v)| v.map(|_| f))
    {
        return Err(InputError::Conflict(format!(
            "{field} bounds the range of --param V, M, W, tau or a dimensionless parameter other \
             than kappa; the onset in the stiffness is searched from a stable stiffness downward"
        ))
        .into());
    }
    let mut setup = setup_at(spec, at)?;
    let kappa_set = setup.overrides.sets_stiffness();
    let note = (kappa_set || setup.scene.stiffness_given).then(|| {
        let source = if at.is_some() {
            "the point's"
        } else if setup.overrides.sets("K") {
            "--set K"
        } else if kappa_set {
            "--set"
        } else {
            "the scene's K"
        };
        format!(
            "hopf finds the stiffness at onset itself; the given kappa = {:e} ({source}) is not used \
             to find it: it is the operating point, compared with K_c",
            setup.scene_params.kappa,
        )
    });
    let outcome = onset_with_degeneracy_resolved(&mut setup, spec.model.is_some())?;
    if let HopfOutcome::Found(h) = &outcome {
        let values = [h.kappa_c, h.omega_c].into_iter().chain(h.state);
        if values.clone().any(|v| !v.is_finite()) {
            return Err(NumericalError::Analysis(format!(
                "the located Hopf point has non-finite values (kappa_c = {}, omega_c = {})",
                h.kappa_c, h.omega_c
            ))
            .into());
        }
    }
    let mut report = HopfReport::new(&setup, &outcome);
    if let (Some(control), HopfOutcome::Found(h)) = (request.param, &outcome) {
        let mut at = setup.scene_params;
        at.kappa = h.kappa_c;
        let units = setup.scene.units;
        let onset = OnsetIn {
            control,
            value: control.value(&units, &at),
            params: at,
            units,
            hopf: h.clone(),
            range: None,
            method: "the Hopf point in kappa (continuation from a stable stiffness downward)"
                .to_string(),
        };
        let scene_value = control.value(&units, &setup.scene_params);
        report.critical = Some(Critical::new(&onset, scene_value));
    }
    Ok(Hopf {
        report,
        setup,
        note,
    })
}

/// The onset in `--param` (not the stiffness): located by
/// [`onset_in`], reported at the critical value with `critical`.
fn run_in_control(
    spec: &SceneSpec,
    request: &HopfRequest,
    control: Control,
    at: Option<Params>,
) -> Result<Hopf, Error> {
    let mut setup = setup_at(spec, at)?;
    let (units, scene_params) = (setup.scene.units, setup.scene_params);
    let default = control.default_range(&units, &scene_params, setup.scene.nu_range);
    let range = match (request.from, request.to, default) {
        (Some(lo), Some(hi), _) => Some((lo, hi)),
        (from, to, Some((lo, hi))) => Some((from.unwrap_or(lo), to.unwrap_or(hi))),
        (None, None, None) => None,
        (from, _, None) => {
            let missing = if from.is_none() { "--from" } else { "--to" };
            return Err(InputError::Conflict(format!(
                "the scene's {} is 0, so the range to search has no default: give {missing} too \
                 (in {})",
                control.name(),
                control.unit_in_words()
            ))
            .into());
        }
    };
    let fields = match (request.from, request.to) {
        (Some(_), None) => "--from (with the default --to)",
        (None, Some(_)) => "--to (with the default --from)",
        _ => "--from/--to",
    };
    let range = range.map(|r| upward_range(r, fields)).transpose()?;
    setup.choice = choose_along(
        control,
        &units,
        &scene_params,
        range,
        spec.model,
        spec.inertia_threshold,
    );
    let kind = setup.choice.kind;
    let onset = onset_in(kind, &scene_params, &units, control, range)?;
    let scene_value = control.value(&units, &scene_params);
    setup.scene.units = onset.units;
    setup.scene_params = onset.params;
    setup.params = params_for(kind, &onset.params);
    let mut report = HopfReport::new(&setup, &HopfOutcome::Found(onset.hopf.clone()));
    report.operating_point = None;
    report.critical = Some(Critical::new(&onset, scene_value));
    Ok(Hopf {
        report,
        setup,
        note: None,
    })
}
