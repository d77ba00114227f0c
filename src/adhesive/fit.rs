//! `fit` on an adhesive scene: the adhesive law's parameters (`F_a`, `V_s`,
//! `tau_on`, `tau_out`, `F_v`, `alpha`; docs/model.md, "Soft adhesive
//! contacts") from steady friction against the driving velocity and,
//! where given, the onset of stick-slip (the critical stiffness `K_c`
//! against `V`), by the joint weighted least squares of the rate-and-state
//! fit ([`crate::jobs::fit`]: the same estimation of the errors, the same
//! search for what the data do not determine, the same output).
//!
//! With `nu = V / V_s`, `r = tau_on / tau_out`, `f_v = F_v / F_a` and `m
//! = M V_s / (F_a tau_out)` (the scene's mass, held):
//!
//! ```text
//! F_ss(V) = F_a [n_ss g(1/nu) + f_v nu^(1 - alpha)]              (eqs. D2, D3)
//! K_c(V)  = kappa_c(nu) F_a / (V_s tau_out),
//! kappa_c = -lambda_n dF_ss/du (1 + chi)                         (docs/model.md, "Linear stability")
//! ```
//!
//! steady friction by [`block::steady_force`] and the critical stiffness
//! by [`block::critical_stiffness_at`] (the closed form `hopf` prints
//! beside the onset it locates, equal to it to 1e-10, tests/adhesive.rs),
//! on dual numbers: the Jacobian is exact.
//!
//! Steady friction depends on `tau_on` and `tau_out` only through their
//! ratio `r` (time enters the steady state only as `t(v) / tau_on`): with
//! steady data alone `tau_out` is held at the scene's value and `tau_on`
//! fitted, which fits `r`; the critical stiffness sees `tau_out` itself
//! (`lambda_n / tau_out = 1/tau_on + 1/t(v)`), and onset data fit both.

use super::block::{self, SteadyLaw};
use super::scene::{self as adhesive_scene, AdhesiveScene, AdhesiveUnits};
use crate::error::{Error, InputError};
use crate::fit::data::{Dataset, Kind, Measured};
use crate::fit::least_squares::{covariance, Problem};
use crate::jobs::fit::{
    fit_determined, summarize, weighted_residuals, DataFit, Entry, Estimate, NotDetermined,
    Outcome, Rows, Summary,
};
use crate::model::ModelKind;
use crate::scene::Law;
use continuation::Scalar;
use serde::Serialize;
use std::path::PathBuf;

/// A parameter of the adhesive law, in its scene unit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Name {
    /// Pinning force scale, N.
    Fa,
    /// Schallamach's velocity, µm/s.
    Vs,
    /// Readsorption time, s.
    TauOn,
    /// Desorption time, s.
    TauOut,
    /// Junction viscous force at `V_s`, N.
    Fv,
    /// Shear thinning of the junction.
    Alpha,
}

impl Name {
    pub const ALL: [Name; 6] = [
        Name::Fa,
        Name::Vs,
        Name::TauOn,
        Name::TauOut,
        Name::Fv,
        Name::Alpha,
    ];

    /// The scene key.
    pub fn key(self) -> &'static str {
        match self {
            Name::Fa => "F_a",
            Name::Vs => "V_s",
            Name::TauOn => "tau_on",
            Name::TauOut => "tau_out",
            Name::Fv => "F_v",
            Name::Alpha => "alpha",
        }
    }

    /// The unit of the value (`1`: dimensionless).
    pub fn unit(self) -> &'static str {
        match self {
            Name::Fa | Name::Fv => "N",
            Name::Vs => "um/s",
            Name::TauOn | Name::TauOut => "s",
            Name::Alpha => "1",
        }
    }

    fn by_key(key: &str) -> Name {
        Name::ALL
            .into_iter()
            .find(|n| n.key() == key)
            .unwrap_or(Name::Fa)
    }

    /// Which data determine the parameter.
    fn remedy(self) -> &'static str {
        match self {
            Name::Fa | Name::Vs | Name::TauOn => {
                "add steady friction on both sides of its maximum V_max (the rise and the fall \
                 of the pinning force)"
            }
            Name::TauOut => {
                "add onset data (K_c against V): steady friction sees only tau_on / tau_out"
            }
            Name::Fv | Name::Alpha => {
                "add steady friction in the viscous regime (around and above the friction \
                 minimum V_c, where the junction's viscous force F_v (V/V_s)^(1 - alpha) \
                 takes over)"
            }
        }
    }
}

/// The law's values in their scene units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Values<T> {
    pub f_a: T,
    pub v_s_um_s: T,
    pub tau_on: T,
    pub tau_out: T,
    pub f_v: T,
    pub alpha: T,
}

impl<T: Scalar> Values<T> {
    pub fn get(&self, name: Name) -> T {
        match name {
            Name::Fa => self.f_a,
            Name::Vs => self.v_s_um_s,
            Name::TauOn => self.tau_on,
            Name::TauOut => self.tau_out,
            Name::Fv => self.f_v,
            Name::Alpha => self.alpha,
        }
    }

    /// The values `f(name)` of every parameter.
    fn from_fn(f: impl Fn(Name) -> T) -> Values<T> {
        Values {
            f_a: f(Name::Fa),
            v_s_um_s: f(Name::Vs),
            tau_on: f(Name::TauOn),
            tau_out: f(Name::TauOut),
            f_v: f(Name::Fv),
            alpha: f(Name::Alpha),
        }
    }

    /// The dimensionless law with the block's mass `mass_kg`.
    fn law(&self, mass_kg: f64) -> SteadyLaw<T> {
        SteadyLaw {
            r: self.tau_on / self.tau_out,
            f_v: self.f_v / self.f_a,
            alpha: self.alpha,
            m: self.v_s_um_s * (mass_kg * 1e-6) / (self.f_a * self.tau_out),
        }
    }

    /// Steady friction \[N\] at `V` µm/s.
    pub fn steady_force_n(&self, mass_kg: f64, v_um_s: f64) -> T {
        block::steady_force(self.v_s_um_s.recip() * v_um_s, &self.law(mass_kg)) * self.f_a
    }

    /// The critical stiffness `K_c` [N/m] at `V` µm/s (with the block's
    /// inertia, `1 + chi`, where the scene has a mass).
    pub fn critical_stiffness_n_m(&self, mass_kg: f64, v_um_s: f64) -> T {
        let kind = if mass_kg > 0.0 {
            ModelKind::Inertial
        } else {
            ModelKind::QuasiStatic
        };
        let (kappa_c, _) =
            block::critical_stiffness_at(self.v_s_um_s.recip() * v_um_s, &self.law(mass_kg), kind);
        kappa_c * self.f_a / (self.v_s_um_s * 1e-6 * self.tau_out)
    }

    /// The model of the measured quantity `column` at `V` µm/s.
    pub fn predict(&self, mass_kg: f64, column: &str, v_um_s: f64) -> T {
        match column {
            "K_N_per_m" => self.critical_stiffness_n_m(mass_kg, v_um_s),
            _ => self.steady_force_n(mass_kg, v_um_s),
        }
    }
}

impl Values<f64> {
    /// The values of a scene.
    pub fn of(scene: &AdhesiveScene) -> Values<f64> {
        let (p, u) = (&scene.params, &scene.units);
        Values {
            f_a: u.f_a,
            // (Divided by the factor it was multiplied with: the scene's own value.)
            v_s_um_s: u.v_s / 1e-6,
            tau_on: p.r * u.tau_out,
            tau_out: u.tau_out,
            f_v: p.f_v * u.f_a,
            alpha: p.alpha,
        }
    }
}

/// Whether `name` is fitted as its logarithm at the start `start`: every
/// positive parameter (`alpha` lies in `[0, 1)`, and `F_v` may start at 0).
fn logarithmic(name: Name, start: f64) -> bool {
    name != Name::Alpha && start > 0.0
}

/// The least-squares problem.
struct Joint<'a> {
    rows: Rows<'a>,
    mass_kg: f64,
    base: Values<f64>,
    free: Vec<Name>,
}

impl Joint<'_> {
    fn values<T: Scalar>(&self, x: &[T]) -> Values<T> {
        // Each parameter: its unknown where free (the logarithm's
        // exponential where fitted as one), else the scene's value.
        Values::from_fn(|name| match self.free.iter().position(|n| *n == name) {
            Some(k) if logarithmic(name, self.base.get(name)) => x[k].exp(),
            Some(k) => x[k],
            None => T::from(self.base.get(name)),
        })
    }
}

impl DataFit for Joint<'_> {
    fn rows(&self) -> &Rows<'_> {
        &self.rows
    }
    fn rows_mut(&mut self) -> &mut Vec<Vec<f64>> {
        &mut self.rows.scale
    }
    fn model_at<T: Scalar>(&self, i: usize, q: &Measured, x: &[T]) -> Option<Vec<T>> {
        let v = self.values(x);
        // The law is defined for 0 <= alpha < 1 and F_v >= 0 (a trial step
        // outside is rejected).
        if !((0.0..1.0).contains(&v.alpha.re()) && v.f_v.re() >= 0.0) {
            return None;
        }
        Some(
            self.rows.data[i]
                .v_um_s
                .iter()
                .map(|&speed| v.predict(self.mass_kg, q.column, speed))
                .collect(),
        )
    }
    fn free_keys(&self) -> Vec<&'static str> {
        self.free.iter().map(|n| n.key()).collect()
    }
    fn start(&self) -> Vec<f64> {
        self.free
            .iter()
            .map(|n| {
                let x = self.base.get(*n);
                if logarithmic(*n, x) {
                    x.ln()
                } else {
                    x
                }
            })
            .collect()
    }
    /// `alpha` goes with `F_v`: it shapes the viscous force `F_v (V /
    /// V_s)^(1 - alpha)` alone, and its value would describe the shape of a
    /// term whose size the data do not give.
    fn hold(&mut self, k: usize) -> Vec<&'static str> {
        let name = self.free.remove(k);
        match self.free.iter().position(|n| *n == Name::Alpha) {
            Some(a) if name == Name::Fv => {
                self.free.remove(a);
                vec![Name::Alpha.key()]
            }
            _ => Vec::new(),
        }
    }
    /// A factor `e` in a parameter fitted as its logarithm, the whole range
    /// of `alpha`; none for `F_v` fitted from 0.
    fn error_limit(&self, k: usize) -> f64 {
        let name = self.free[k];
        if name == Name::Alpha || logarithmic(name, self.base.get(name)) {
            MEANINGLESS_ERROR
        } else {
            f64::INFINITY
        }
    }
}

impl Problem for Joint<'_> {
    fn unknowns(&self) -> usize {
        self.free.len()
    }
    fn residuals<T: Scalar>(&self, x: &[T]) -> Option<Vec<T>> {
        weighted_residuals(self, x)
    }
}

/// A parameter held at the scene's value by design, not for want of data,
/// and why.
#[derive(Clone, Debug, Serialize)]
pub struct Held {
    pub name: &'static str,
    pub value: f64,
    pub reason: String,
}

/// The result of `fit` on an adhesive scene: its serde form is the JSON,
/// in the field conventions of the rate-and-state fit.
#[derive(Serialize)]
pub struct AdhesiveFit {
    pub scene: String,
    /// `adhesive`.
    pub law: &'static str,
    #[serde(flatten)]
    pub summary: Summary,
    /// Parameters held because the data kinds given cannot see them
    /// (`tau_out` without onset data).
    pub held: Vec<Held>,
    /// `tau_on / tau_out` of the fitted values, with its standard error
    /// (`null` where `tau_on` is not fitted), the combination steady
    /// friction determines.
    pub ratio_tau_on_over_tau_out: Estimate,
    /// What is unusual in the scene or the fitted scene but valid
    /// (`tau_on > tau_out`), also on stderr.
    pub warnings: Vec<String>,
    #[serde(flatten)]
    pub outcome: Outcome<Values<f64>, AdhesiveUnits>,
    /// The scene's block mass, kg.
    #[serde(skip)]
    pub mass_kg: f64,
}

/// A parameter whose standard error (of its logarithm, for a positive one;
/// of `alpha` itself, whose whole range is 1) exceeds this is not
/// determined: the data leave it uncertain by more than a factor `e`.
const MEANINGLESS_ERROR: f64 = 1.0;

/// Fits the adhesive scene `scene_name` (with `--set` overrides `set`) to
/// the datasets `data`, the parameters `free` (default all).
pub fn run(
    scene_name: &str,
    set: &[String],
    data: &[(Kind, PathBuf)],
    free: Option<&[String]>,
) -> Result<AdhesiveFit, Error> {
    crate::jobs::fit::check_request(data)?;
    let scene = adhesive_scene::load_with(scene_name, set)?;
    let data = data
        .iter()
        .map(|(kind, file)| Dataset::read_for(Law::Adhesive, *kind, file))
        .collect::<Result<Vec<_>, _>>()?;
    let start = Values::of(&scene);
    let onset = data.iter().any(|d| d.kind == Kind::Onset);
    let mut held = Vec::new();
    let requested: Vec<Name> = match free {
        Some(names) => names
            .iter()
            .map(|n| {
                Name::ALL
                    .into_iter()
                    .find(|l| l.key() == n.trim())
                    .ok_or_else(|| InputError::UnknownName {
                        what: "parameter in --free (of the adhesive law)",
                        name: n.clone(),
                        suggestion: crate::error::closest(n, Name::ALL.iter().map(|l| l.key())),
                        allowed: Name::ALL.map(|l| l.key()).join(", "),
                    })
            })
            .collect::<Result<_, _>>()?,
        None => Name::ALL
            .into_iter()
            .filter(|n| onset || *n != Name::TauOut)
            .collect(),
    };
    if let Some(twice) = requested
        .iter()
        .enumerate()
        .find(|(i, n)| requested[..*i].contains(n))
    {
        return Err(InputError::Conflict(format!("--free names {} twice", twice.1.key())).into());
    }
    if !onset && requested.contains(&Name::TauOn) && requested.contains(&Name::TauOut) {
        return Err(InputError::Conflict(
            "--free names tau_on and tau_out, but steady friction depends on them only through \
             tau_on / tau_out: free one of them, or add onset data (K_c against V)"
                .into(),
        )
        .into());
    }
    if !onset && !requested.contains(&Name::TauOut) {
        held.push(Held {
            name: Name::TauOut.key(),
            value: start.tau_out,
            reason: "steady friction depends on tau_on and tau_out only through their ratio \
                     r = tau_on / tau_out: tau_out is held at the scene's value and tau_on \
                     fitted, which fits r (onset data, K_c against V, determine tau_out)"
                .into(),
        });
    }
    let mass_kg = scene.units.mass;
    let mut problem = Joint {
        rows: Rows::new(&data),
        mass_kg,
        base: start,
        free: requested.clone(),
    };
    let (minimum, not_determined) = fit_determined(&mut problem, |key, with, error| {
        let name = Name::by_key(key);
        let why = match error {
            Some(e) if name == Name::Alpha => {
                format!("its standard error from these data, {e:.2}, spans its whole range; ")
            }
            Some(e) if e.exp().is_finite() => format!(
                "these data give it only within a factor {:.3e} (standard error {e:.2} in its \
                 logarithm); ",
                e.exp()
            ),
            Some(e) => {
                format!("these data do not bound it (standard error {e:.3e} in its logarithm); ")
            }
            None if name == Name::Alpha && with.contains(&Name::Fv.key()) => {
                "alpha shapes the viscous force F_v (V/V_s)^(1 - alpha) alone, whose size these \
                 data do not give; "
                    .into()
            }
            None => String::new(),
        };
        NotDetermined {
            name: key,
            with: with.to_vec(),
            remedy: format!("{why}{}", name.remedy()),
            kept_at: start.get(name),
        }
    })?;
    let values = problem.values(&minimum.x);
    let c = covariance(&minimum.jacobian).ok_or_else(|| {
        crate::error::NumericalError::Analysis("the fit's normal matrix J^T J is singular".into())
    })?;
    let entries: Vec<Entry> = Name::ALL
        .into_iter()
        .map(|name| Entry {
            key: name.key(),
            unit: name.unit(),
            value: values.get(name),
            start: start.get(name),
            logarithmic: logarithmic(name, start.get(name)),
        })
        .collect();
    let not_determined_names: Vec<&'static str> = not_determined.iter().map(|n| n.name).collect();
    let summary = summarize(&problem, &minimum, &c, &entries, not_determined);
    let ratio = values.tau_on / values.tau_out;
    let ratio_error = {
        // ln r = ln tau_on - ln tau_out: the variance of the difference.
        let k_on = problem.free.iter().position(|n| *n == Name::TauOn);
        let k_out = problem.free.iter().position(|n| *n == Name::TauOut);
        let var = |k: Option<usize>| k.map_or(0.0, |k| c[(k, k)]);
        let cov = match (k_on, k_out) {
            (Some(a), Some(b)) => c[(a, b)],
            _ => 0.0,
        };
        (k_on.is_some() || k_out.is_some())
            .then(|| ratio * (var(k_on) + var(k_out) - 2.0 * cov).sqrt())
    };
    let ratio_tau_on_over_tau_out = Estimate {
        value: ratio,
        std_error: ratio_error,
        unit: "1",
        status: if ratio_error.is_some() {
            "fitted"
        } else {
            "fixed"
        },
        start: start.tau_on / start.tau_out,
        given: Vec::new(),
    };
    let fitted = fitted_scene(
        &scene,
        &values,
        &data,
        scene_name,
        set,
        &not_determined_names,
    )?;
    let stop = summary.stop.clone();
    let mut warnings: Vec<String> = scene
        .warnings
        .iter()
        .map(|w| format!("the scene: {w}"))
        .collect();
    warnings.extend(
        fitted
            .1
            .warnings
            .iter()
            .map(|w| format!("the fitted scene: {w}")),
    );
    Ok(AdhesiveFit {
        warnings,
        scene: scene.name.clone(),
        law: adhesive_scene::LAW,
        summary,
        held,
        ratio_tau_on_over_tau_out,
        outcome: Outcome {
            params: serde_json::to_value(fitted.1.params).map_err(std::io::Error::other)?,
            units: fitted.1.units,
            iterations: minimum.iterations,
            complete: stop.is_none(),
            stop,
            files: Vec::new(),
            fitted_toml: fitted.0,
            data,
            values,
            start,
        },
        mass_kg,
    })
}

/// The fitted scene as TOML (every command reads it), checked by reading it
/// back: the scene's file (or built-in text) with `--set` and the fitted
/// values in place, named `<scene>-fitted`.
fn fitted_scene(
    scene: &AdhesiveScene,
    v: &Values<f64>,
    data: &[Dataset],
    scene_name: &str,
    set: &[String],
    not_determined: &[&str],
) -> Result<(String, AdhesiveScene), Error> {
    let text = match adhesive_scene::builtin_text(scene_name) {
        Some(t) => t.to_string(),
        None => std::fs::read_to_string(scene_name)
            .map_err(|e| crate::scene::file_error(scene_name, e))?,
    };
    let mut table: toml::Table = text
        .parse()
        .map_err(|e| crate::scene::file_error(scene_name, e))?;
    // The overrides first (checked by loading the scene), then the fit.
    for item in set {
        if let Some((key, value)) = item.split_once('=') {
            if let Ok(x) = value.trim().parse::<f64>() {
                table.insert(key.trim().into(), toml::Value::Float(x));
            }
        }
    }
    for name in Name::ALL {
        table.insert(name.key().into(), toml::Value::Float(v.get(name)));
    }
    let files: Vec<String> = data.iter().map(|d| d.file.display().to_string()).collect();
    table.insert(
        "name".into(),
        toml::Value::String(format!("{}-fitted", scene.name)),
    );
    table.insert(
        "description".into(),
        toml::Value::String(format!(
            "{} fitted by stickslip fit to {}",
            scene.name,
            files.join(", ")
        )),
    );
    let mut text = toml::to_string(&table).map_err(|e| std::io::Error::other(e.to_string()))?;
    let back = adhesive_scene::from_toml_str(&text, "fitted.toml")?;
    if !not_determined.is_empty() {
        text = format!(
            "# not determined by the data, kept at the scene's values: {}\n{text}",
            not_determined.join(", ")
        );
    }
    Ok((text, back))
}
