//! The `fit` job: the friction law's parameters (`mu0`, `A`, `B`, `D0`,
//! and `mu2` or `tau` by the scene's form, under its state law, with the
//! scene's `mu_vv`, `mu_vphi` and radiation damping `eta` held at their
//! values) from laboratory data, by joint
//! weighted least squares over every dataset, with standard errors, the
//! correlation matrix, the parameters the data do not determine (named,
//! with the data that would determine them, never given a made-up value),
//! the seed's closed-form route beside the fit, and the fitted scene.
//!
//! Time series (`velocity_step`, `relaxation`) are modelled by integrating
//! the spring-block equations on the scene's rig with their forward
//! sensitivities ([`crate::fit::series`]), in the model `simulate` would
//! use for the protocol ([`super::simulate::model_of_run`]), and enter the
//! same least squares.
//!
//! Positive parameters are fitted as their logarithms (`mu2` linearly: its
//! sign is free, and a true 0 gets a symmetric error); a dataset without
//! a `sigma` column gets the error its residuals give, `s^2 = RSS /
//! (n (1 - p/N))` (its share of the degrees of freedom), re-estimated
//! until the fit settles.

use super::{SceneSpec, Setup};
use crate::analysis::hopf::{Criticality, HopfOutcome};
use crate::analysis::model_choice::{choose_model, params_for};
use crate::error::{Error, InputError, NumericalError};
use crate::fit::data::{Dataset, Kind, Measured};
use crate::fit::least_squares::{
    covariance, minimize, scaled_svd, seeded, LeastSquaresError, Minimum, Problem,
};
use crate::fit::model::{AgeingValue, Fixed, Name, Rig, Values};
use crate::fit::series::{law_vector, real_values, SeriesModel, Solved, N_LAW};
use crate::records::{params_json, UnitsRecord};
use crate::scene::Units;
use continuation::Scalar;
use nalgebra::{DMatrix, DVector};
use serde::Serialize;
use std::cell::RefCell;
use std::collections::BTreeMap;
use std::path::PathBuf;

/// What `fit` is asked.
#[derive(Clone, Debug, Default)]
pub struct FitRequest {
    /// The datasets, `(kind, file)`.
    pub data: Vec<(Kind, PathBuf)>,
    /// The parameters to fit (`None`: every parameter of the scene's law).
    pub free: Option<Vec<String>>,
    /// Also the fitted scene's stability boundary with its 95 % band and
    /// its onset type with the share of drawn parameter sets that agree
    /// (about 0.1 s: 700 Hopf points located).
    pub stability: bool,
}

/// A singular value of the column-scaled Jacobian below this fraction of
/// the largest marks a direction the data do not determine (rounding
/// level of `J^T J`).
const UNDETERMINED: f64 = 1e-8;

/// Re-estimations of the residual errors at most.
const SIGMA_ROUNDS: usize = 20;

/// One parameter of the result.
#[derive(Clone, Debug, Serialize)]
pub struct Estimate {
    /// The value (fitted, or the scene's where not fitted).
    pub value: f64,
    /// Its standard error; `null` where it was not fitted.
    pub std_error: Option<f64>,
    pub unit: &'static str,
    /// `fitted`, `fixed` (not in `--free`) or `not_determined`.
    pub status: &'static str,
    /// The scene's value, where the fit started.
    pub start: f64,
    /// Parameters not determined by the data that this value depends on
    /// (it is fitted with them kept at the scene's values: only a
    /// combination is determined).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub given: Vec<&'static str>,
}

/// A parameter the data did not determine.
#[derive(Clone, Debug, Serialize)]
pub struct NotDetermined {
    pub name: &'static str,
    /// The parameters of the undetermined direction (only a combination of
    /// them is determined).
    pub with: Vec<&'static str>,
    /// What to do: which data would determine it.
    pub remedy: String,
    /// Where it was kept.
    pub kept_at: f64,
}

/// One measured quantity of a dataset in the result.
#[derive(Clone, Debug, Serialize)]
pub struct DatasetFit {
    pub kind: Kind,
    pub file: String,
    pub rows: usize,
    /// The quantity (column) measured.
    pub quantity: &'static str,
    /// Root-mean-square residual, in the quantity's unit.
    pub rms: f64,
    /// `given` (a sigma column) or `estimated` (from the residuals).
    pub sigma: &'static str,
    /// The error per row estimated from the residuals, where not given.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub sigma_estimated: Option<f64>,
    /// The model integrated for a time series (`quasi-static` or
    /// `inertial`) and why.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub model: Option<&'static str>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub model_reason: Option<String>,
    /// Where the rig's spring is softer than the fitted scene's critical
    /// stiffness at a velocity of the series' protocol: the model slides by
    /// stick-slip there, and a fit of a transient to it is not what the
    /// data kind assumes.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub warning: Option<String>,
}

/// Why the time series `d` is taken on a rig (spring `k_over_w`, 1/m) that
/// slides by stick-slip at a velocity of its protocol with the fitted
/// `values`: `(K/W)_c` there (Appendix C) above the rig's.
fn below_onset(rig: &Rig, values: &Values<f64>, d: &Dataset, k_over_w: f64) -> Option<String> {
    let (v, critical) = d
        .v_um_s
        .iter()
        .filter(|v| **v > 0.0)
        .map(|&v| (v, predict(rig, values, "K_over_W_per_m", v)))
        .filter(|(_, c)| c.is_finite())
        .max_by(|a, b| a.1.total_cmp(&b.1))?;
    (k_over_w < critical).then(|| {
        format!(
            "the rig's K/W = {k_over_w:.4e} 1/m lies below the fitted (K/W)_c = {critical:.4e} 1/m \
             at V = {v:.4e} µm/s of this series' protocol: the model slides by stick-slip there, \
             and its transient fits noise and stick-slip alike (the rms says how well); a stiffer \
             rig, or onset data, determine the parameters"
        )
    })
}

/// The seed's route to the parameters (§II.D.2), printed beside the fit:
/// the slope of steady friction against `ln V` gives `B - A`, the
/// critical stiffness `(K/W)_c = (B - A)/D0` (eq. KcRR, quasi-static)
/// gives `D0`, the onset frequency (eq. omegacRR) gives `A`.
#[derive(Clone, Debug, Serialize)]
pub struct ClosedForm {
    pub b_minus_a: f64,
    pub mu0: f64,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub d0_um: Option<f64>,
    #[serde(rename = "A", skip_serializing_if = "Option::is_none")]
    pub a: Option<f64>,
    pub from: &'static str,
}

/// The critical stiffness of the fitted scene at one velocity with its
/// 95 % band: `±1.96` standard errors by the delta method (the exact
/// gradient of `(K/W)_c` in the fitted parameters, from dual numbers,
/// against their covariance), and the 2.5 % and 97.5 % quantiles over
/// parameter sets drawn from the fit's normal distribution, as a check.
#[derive(Clone, Debug, Serialize)]
pub struct BandPoint {
    #[serde(rename = "V_um_s")]
    pub v_um_s: f64,
    #[serde(rename = "K_over_W_per_m")]
    pub k_over_w: f64,
    pub std_error: f64,
    pub lo_95: f64,
    pub hi_95: f64,
    pub sampled_lo_95: f64,
    pub sampled_hi_95: f64,
}

/// The onset type of the fitted scene at one velocity, and how sure it is:
/// the share of the parameter sets drawn from the fit's distribution whose
/// onset is supercritical (the same onset and model decision as `hopf`).
#[derive(Clone, Debug, Serialize)]
pub struct OnsetTypeAt {
    #[serde(rename = "V_um_s")]
    pub v_um_s: f64,
    pub criticality: Criticality,
    pub l1: f64,
    pub share_supercritical: f64,
    pub samples: usize,
}

/// The correlation matrix of the fitted parameters.
#[derive(Clone, Debug, Serialize)]
pub struct Correlation {
    pub names: Vec<&'static str>,
    pub matrix: Vec<Vec<f64>>,
}

/// What every fit reports of its estimate, either family of laws: the
/// parameters with their errors, the correlations, chi2, the residuals per
/// dataset, what the data do not determine, and why it is partial.
#[derive(Serialize)]
pub struct Summary {
    pub parameters: BTreeMap<&'static str, Estimate>,
    pub correlation: Correlation,
    pub chi2: f64,
    pub dof: usize,
    pub chi2_per_dof: f64,
    pub datasets: Vec<DatasetFit>,
    pub not_determined: Vec<NotDetermined>,
    /// Why the fit is partial (`None`: complete); the JSON's `stop`.
    #[serde(skip)]
    pub stop: Option<String>,
}

/// The undetermined parameters with what would determine each.
fn listed(not_determined: &[NotDetermined]) -> String {
    not_determined
        .iter()
        .map(|n| format!("{} ({})", n.name, n.remedy))
        .collect::<Vec<_>>()
        .join("; ")
}

/// One parameter of the law for [`summarize`]: its name, unit, value,
/// scene value, and whether it was fitted as its logarithm.
pub(crate) struct Entry {
    pub key: &'static str,
    pub unit: &'static str,
    pub value: f64,
    pub start: f64,
    pub logarithmic: bool,
}

/// The summary of the minimum of `problem` (the unknowns still free after
/// holding `not_determined`): each entry's estimate, its standard error
/// from the covariance `c` by the delta method (`d value = value d ln
/// value` for a logarithmic one), the correlations, chi2 and the
/// residuals.
pub(crate) fn summarize<P: DataFit>(
    problem: &P,
    minimum: &Minimum,
    c: &DMatrix<f64>,
    entries: &[Entry],
    not_determined: Vec<NotDetermined>,
) -> Summary {
    let free = problem.free_keys();
    let mut parameters = BTreeMap::new();
    for e in entries {
        let fitted = free.iter().position(|n| *n == e.key);
        let status = match fitted {
            Some(_) => "fitted",
            None if not_determined.iter().any(|n| n.name == e.key) => "not_determined",
            None => "fixed",
        };
        let std_error = fitted.map(|k| {
            let sd = c[(k, k)].sqrt();
            if e.logarithmic {
                e.value * sd
            } else {
                sd
            }
        });
        parameters.insert(
            e.key,
            Estimate {
                value: e.value,
                std_error,
                unit: e.unit,
                status,
                start: e.start,
                given: not_determined
                    .iter()
                    .filter(|n| fitted.is_some() && n.with.contains(&e.key))
                    .map(|n| n.name)
                    .collect(),
            },
        );
    }
    let rows: usize = problem
        .data()
        .iter()
        .map(|d| d.rows() * d.measured.len())
        .sum();
    let chi2 = minimum.residuals.norm_squared();
    let dof = rows.saturating_sub(free.len());
    let stop = (!not_determined.is_empty())
        .then(|| format!("not determined by the data: {}", listed(&not_determined)));
    Summary {
        parameters,
        correlation: correlation(free, c),
        chi2,
        dof,
        chi2_per_dof: if dof > 0 { chi2 / dof as f64 } else { f64::NAN },
        datasets: dataset_fits(problem, &minimum.x),
        not_determined,
        stop,
    }
}

/// What every fit's result ends with, either family of laws: the fitted
/// scene's dimensionless parameters and units (`U`), how the fit ended,
/// the files written, and (not in the JSON) the fitted scene as TOML, the
/// datasets and the fitted and starting values (`V`), for the figures.
#[derive(Serialize)]
pub struct Outcome<V, U> {
    pub params: serde_json::Value,
    pub units: U,
    pub iterations: usize,
    pub complete: bool,
    pub stop: Option<String>,
    /// The files written (by the command line).
    pub files: Vec<String>,
    /// The fitted scene as a TOML file.
    #[serde(skip)]
    pub fitted_toml: String,
    #[serde(skip)]
    pub data: Vec<Dataset>,
    #[serde(skip)]
    pub values: V,
    /// The scene's values the fit started from.
    #[serde(skip)]
    pub start: V,
}

/// The result of `fit`: its serde form is the command's JSON.
#[derive(Serialize)]
pub struct Fit {
    pub scene: String,
    /// `rice-ruina`, `ln2` or `cutoff`.
    pub law: &'static str,
    #[serde(flatten)]
    pub summary: Summary,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub closed_form: Option<ClosedForm>,
    /// The fitted scene's stability boundary over its velocity range with
    /// the 95 % band.
    pub band: Vec<BandPoint>,
    /// Its onset type along the range, with the share of sampled
    /// parameter sets that agree.
    pub onset_type: Vec<OnsetTypeAt>,
    #[serde(flatten)]
    pub outcome: Outcome<Values<f64>, UnitsRecord>,
    #[serde(skip)]
    pub rig: Rig,
    /// Per dataset: the model of a time series (`None` for the others).
    #[serde(skip)]
    pub series: Vec<Option<SeriesModel>>,
}

impl Fit {
    /// The model of the quantity `column` (`mu`, `K_over_W_per_m`,
    /// `frequency_hz`) at `v_um_s` on the fit's rig with the values `p`.
    pub fn predict(&self, p: &Values<f64>, column: &str, v_um_s: f64) -> f64 {
        predict(&self.rig, p, column, v_um_s)
    }

    /// The fitted values (`fitted`) or the scene's the fit started from.
    pub fn values_of(&self, fitted: bool) -> &Values<f64> {
        if fitted {
            &self.outcome.values
        } else {
            &self.outcome.start
        }
    }

    /// The model of the time series `i` at its rows' times with the values
    /// `p`; `None` for a dataset that is not a time series or where the
    /// integration fails (e.g. the scene's values before the fit on a rig
    /// that stick-slips with them).
    pub fn series_model(&self, i: usize, p: &Values<f64>) -> Option<Vec<f64>> {
        let model = self.series.get(i)?.as_ref()?;
        model.solve(p).ok().map(|s| s.values)
    }
}

/// A time series' model with its last solution (the least squares ask for
/// the residuals and their derivatives at the same values `n + 1` times).
struct Cached {
    model: SeriesModel,
    last: RefCell<Option<([f64; N_LAW], Option<Solved>)>>,
}

impl Cached {
    /// `f` of the solution at `v` (solved once per values), `None` where
    /// the integration fails.
    fn with<R>(&self, v: &Values<f64>, f: impl FnOnce(&Solved) -> R) -> Option<R> {
        let q = law_vector(v);
        let mut last = self.last.borrow_mut();
        if last.as_ref().is_none_or(|(at, _)| *at != q) {
            *last = Some((q, self.model.solve(v).ok()));
        }
        last.as_ref().and_then(|(_, s)| s.as_ref()).map(f)
    }
}

/// The least-squares problem: weighted residuals of every measured value.
struct Joint<'a> {
    rows: Rows<'a>,
    rig: Rig,
    base: Values<f64>,
    free: Vec<Name>,
    /// Per dataset: the model of a time series.
    series: Vec<Option<Cached>>,
}

impl Joint<'_> {
    /// The law's values at the unknowns `x` (logarithms of positive parameters).
    fn values<T: Scalar>(&self, x: &[T]) -> Values<T> {
        let b = &self.base;
        let mut v = Values {
            mu0: T::from(b.mu0),
            a: T::from(b.a),
            b: T::from(b.b),
            d0_um: T::from(b.d0_um),
            ageing: match b.ageing {
                AgeingValue::Mu2(x) => AgeingValue::Mu2(T::from(x)),
                AgeingValue::Tau(x) => AgeingValue::Tau(T::from(x)),
            },
            fixed: b.fixed,
        };
        for (name, xi) in self.free.iter().zip(x) {
            v.set(*name, if name.positive() { xi.exp() } else { *xi });
        }
        v
    }

    /// The model of the quantity `q` of dataset `i` at every row with the
    /// values `p`. A time series from its integration with sensitivities
    /// `J = d model / d q` at the real parts `q0` of the law's values,
    /// `model(q0) + J (q - q0)`: its value, and for dual numbers its exact
    /// first derivative.
    fn model<T: Scalar>(&self, i: usize, q: &Measured, p: &Values<T>) -> Option<Vec<T>> {
        let d = &self.rows.data[i];
        let Some(series) = &self.series[i] else {
            return Some(
                d.v_um_s
                    .iter()
                    .map(|&v| predict(&self.rig, p, q.column, v))
                    .collect(),
            );
        };
        let law = law_vector(p);
        let at = real_values(p);
        let q0 = law_vector(&at);
        series.with(&at, |solved| {
            solved
                .values
                .iter()
                .enumerate()
                .map(|(r, &y)| {
                    (0..N_LAW).fold(T::from(y), |out, k| {
                        out + (law[k] - q0[k]) * solved.jacobian[(r, k)]
                    })
                })
                .collect()
        })
    }

    /// The unknowns of `values`.
    fn unknowns_of(&self, values: &Values<f64>) -> Vec<f64> {
        self.free
            .iter()
            .map(|n| {
                let x = values.get(*n).unwrap_or(0.0);
                if n.positive() {
                    x.ln()
                } else {
                    x
                }
            })
            .collect()
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
        self.model(i, q, &self.values(x))
    }
    fn free_keys(&self) -> Vec<&'static str> {
        self.free.iter().map(|n| n.key()).collect()
    }
    fn start(&self) -> Vec<f64> {
        self.unknowns_of(&self.base)
    }
    fn hold(&mut self, k: usize) -> Vec<&'static str> {
        self.free.remove(k);
        Vec::new()
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

/// A joint weighted least-squares problem over datasets, in the unknowns
/// `x` (logarithms of positive parameters): what the estimation of the
/// errors, the search for undetermined parameters and the residuals'
/// summary need, for either family of laws (the rate-and-state fit here,
/// the adhesive one in [`crate::adhesive::fit`]).
pub(crate) trait DataFit {
    /// The datasets with their errors.
    fn rows(&self) -> &Rows<'_>;
    fn rows_mut(&mut self) -> &mut Vec<Vec<f64>>;
    /// The datasets.
    fn data(&self) -> &[Dataset] {
        self.rows().data
    }
    /// Per dataset and quantity: the error per row where none is given.
    fn scale(&self) -> &[Vec<f64>] {
        &self.rows().scale
    }
    fn set_scale(&mut self, scale: Vec<Vec<f64>>) {
        *self.rows_mut() = scale;
    }
    /// The model of the quantity `q` of dataset `i` at every row, at `x`.
    fn model_at<T: Scalar>(&self, i: usize, q: &Measured, x: &[T]) -> Option<Vec<T>>;
    /// The names of the unknowns.
    fn free_keys(&self) -> Vec<&'static str>;
    /// The unknowns at the scene's values, where the fit starts.
    fn start(&self) -> Vec<f64>;
    /// Holds the `k`-th unknown at the scene's value; the names of the
    /// unknowns held with it (whose value means nothing without it).
    fn hold(&mut self, k: usize) -> Vec<&'static str>;
    /// The standard error of the `k`-th unknown above which its value
    /// means nothing (default: none; the adhesive fit: 1, a factor `e` in
    /// a positive parameter fitted as its logarithm).
    fn error_limit(&self, _k: usize) -> f64 {
        f64::INFINITY
    }
}

/// The datasets of a fit and, per dataset and quantity, the error per row
/// where the file gives none (estimated from the residuals; 1 until the
/// fit sets its first estimate, `fit_with_estimated_errors`).
pub(crate) struct Rows<'a> {
    pub data: &'a [Dataset],
    pub scale: Vec<Vec<f64>>,
}

impl<'a> Rows<'a> {
    pub fn new(data: &'a [Dataset]) -> Rows<'a> {
        Rows {
            data,
            scale: data
                .iter()
                .map(|d| d.measured.iter().map(|_| 1.0).collect())
                .collect(),
        }
    }
}

/// The weighted residuals `(model - data) / sigma` of every measured value
/// of `problem` at `x`; `None` where the model is undefined.
pub(crate) fn weighted_residuals<P: DataFit, T: Scalar>(problem: &P, x: &[T]) -> Option<Vec<T>> {
    let mut out = Vec::new();
    for (k, (d, scales)) in problem.data().iter().zip(problem.scale()).enumerate() {
        for (q, scale) in d.measured.iter().zip(scales) {
            let model = problem.model_at(k, q, x)?;
            for (i, (m, &y)) in model.into_iter().zip(&q.values).enumerate() {
                let sigma = q.sigma.as_ref().map_or(*scale, |s| s[i]);
                let r = (m - y) / sigma;
                if !r.re().is_finite() {
                    return None;
                }
                out.push(r);
            }
        }
    }
    Some(out)
}

/// Fits `problem`, holding at the scene's values the parameters the data
/// do not determine, each described by `describe(name, with, error)`
/// (`with`: the parameters only a combination of which is determined;
/// `error`: the standard error that was too large, if that was why). The
/// minimum, the undetermined ones. Undetermined is
///
/// - a direction of the unknowns the data do not see at all: a singular
///   value of the column-scaled Jacobian below [`UNDETERMINED`] of the
///   largest (the parameter with the largest share of that direction is
///   held; `with`: those with a share above 0.1);
/// - a parameter whose standard error from `(J^T J)^-1` exceeds its
///   [`DataFit::error_limit`] (the one with the largest error over its
///   limit is held; `with`: those correlated with it by more than 0.9).
pub(crate) fn fit_determined<P: DataFit + Problem>(
    problem: &mut P,
    mut describe: impl FnMut(&'static str, &[&'static str], Option<f64>) -> NotDetermined,
) -> Result<(Minimum, Vec<NotDetermined>), Error> {
    let mut not_determined: Vec<NotDetermined> = Vec::new();
    loop {
        if problem.unknowns() == 0 {
            return Err(NumericalError::Analysis(format!(
                "the data determine none of the parameters asked for: {}",
                listed(&not_determined)
            ))
            .into());
        }
        // Where the iterations creep along a valley to their limit, the
        // last iterate tells which parameters the data leave free: they are
        // held as at a minimum, and the fit tried again without them.
        let (minimum, converged) = fit_with_estimated_errors(problem)?;
        let Some((s, v)) = scaled_svd(&minimum.jacobian) else {
            let keys = problem.free_keys();
            let undefined: Vec<&str> = (0..keys.len())
                .filter(|&k| !minimum.jacobian.column(k).iter().all(|d| d.is_finite()))
                .map(|k| keys[k])
                .collect();
            let why = if undefined.is_empty() {
                "the singular value decomposition of the model's derivatives did not converge"
                    .to_string()
            } else {
                format!(
                    "the model's derivatives along {} are not finite",
                    undefined.join(", ")
                )
            };
            return Err(NumericalError::Analysis(format!(
                "{why} at the fit's last iterate (after {} iterations), so which parameters the \
                 data determine cannot be told",
                minimum.iterations
            ))
            .into());
        };
        let weakest = s.len() - 1;
        let keys = problem.free_keys();
        let (k, with, error) = if s[weakest] > UNDETERMINED * s[0] && s[0] > 0.0 {
            // Each error against its limit.
            let c = covariance(&minimum.jacobian)
                .unwrap_or_else(|| DMatrix::from_element(keys.len(), keys.len(), f64::INFINITY));
            let over = |k: usize| c[(k, k)].sqrt() / problem.error_limit(k);
            let k = (0..keys.len())
                .max_by(|&a, &b| over(a).total_cmp(&over(b)))
                .unwrap_or(0);
            // (A NaN error, from a singular covariance, is over.)
            if over(k) <= 1.0 {
                return match converged {
                    true => Ok((minimum, not_determined)),
                    false => Err(failed(LeastSquaresError::NoConvergence(minimum.iterations))),
                };
            }
            let with: Vec<&'static str> = (0..keys.len())
                .filter(|&j| (c[(k, j)] / (c[(k, k)] * c[(j, j)]).sqrt()).abs() > 0.9)
                .map(|j| keys[j])
                .collect();
            (k, with, Some(c[(k, k)].sqrt()))
        } else {
            // The direction the data leave free: its parameters; the one
            // with the largest share is kept at the scene's value.
            let direction = v.column(weakest);
            let share = |k: usize| direction[k].abs();
            let with: Vec<&'static str> = (0..keys.len())
                .filter(|&k| share(k) > 0.1)
                .map(|k| keys[k])
                .collect();
            let k = (0..keys.len())
                .max_by(|&a, &b| share(a).total_cmp(&share(b)))
                .unwrap_or(0);
            (k, with, None)
        };
        let along = problem.hold(k);
        not_determined.push(describe(keys[k], &with, error));
        for name in along {
            not_determined.push(describe(name, &[keys[k], name], None));
        }
    }
}

/// The correlation matrix of the unknowns `names` from their covariance `c`.
pub(crate) fn correlation(names: Vec<&'static str>, c: &DMatrix<f64>) -> Correlation {
    let n = names.len();
    Correlation {
        names,
        matrix: (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| c[(i, j)] / (c[(i, i)] * c[(j, j)]).sqrt())
                    .collect()
            })
            .collect(),
    }
}

/// The law's parameters of a scene, in their physical units.
fn scene_values(setup: &Setup) -> Values<f64> {
    let (p, u) = (&setup.scene_params, &setup.scene.units);
    let d0_um = u.d0 * 1e6;
    Values {
        mu0: p.mu0,
        a: p.a,
        b: p.b,
        d0_um,
        ageing: match p.theta_c {
            // theta_c = tau V0 / D0.
            Some(theta_c) => AgeingValue::Tau(theta_c * u.d0 / u.v0),
            None => AgeingValue::Mu2(p.mu2),
        },
        fixed: Fixed {
            mu_vv: p.mu_vv,
            mu_vphi: p.mu_vphi,
            eta_d: p.eta_d,
        },
    }
}

/// The parameter of the scene key `key`.
fn by_key(key: &str) -> Name {
    Name::ALL
        .into_iter()
        .find(|n| n.key() == key)
        .unwrap_or(Name::Mu0)
}

/// Which data determine a parameter, given the kinds of data the fit had
/// (`given`): never one of those alone where it did not suffice.
fn remedy(name: Name, with: &[Name], given: &[Kind]) -> String {
    let only_combination = with.len() > 1;
    let has = |k: Kind| given.contains(&k);
    let what = match name {
        // Onset data give (K/W)_c = (B - A)/D0 (eq. KcRR): D0 needs B - A
        // from elsewhere; steady friction gives B - A, not D0.
        Name::D0 if has(Kind::Onset) && !has(Kind::Steady) => {
            "steady-friction or velocity-step data: the critical stiffness gives (B - A) / D0 \
             (eq. KcRR), and B - A from the steady slope separates D0"
        }
        Name::D0 if has(Kind::Onset) => {
            "velocity-step data, or onset data over a wider range of V: these determine \
             (B - A) / D0 and B - A too loosely to separate D0"
        }
        Name::A | Name::B if !only_combination && has(Kind::Steady) && has(Kind::Onset) => {
            "velocity-step data, or steady and onset data over a wider range of V"
        }
        Name::A | Name::B if !only_combination && has(Kind::Steady) => "onset data",
        Name::A | Name::B if !only_combination && has(Kind::Onset) => "steady-friction data",
        Name::Mu0 => {
            "steady-friction or velocity-step data (relaxation data see only changes of friction)"
        }
        Name::A | Name::B
            if only_combination && with.contains(&Name::A) && with.contains(&Name::B) =>
        {
            "onset frequencies (a frequency_hz column in the onset data) or velocity-step data: \
             steady friction and the critical stiffness give only B - A"
        }
        Name::A | Name::B => "steady-friction or onset data",
        Name::D0 => "onset data ((K/W)_c against V) or velocity-step data",
        Name::Mu2 => {
            "steady or onset data over several decades of V, or relaxation data at several V"
        }
        Name::Tau => "steady or onset data around and above the friction minimum V_min",
    };
    format!("add {what}")
}

/// Refuses a fit without data or with a file given twice.
pub(crate) fn check_request(data: &[(Kind, PathBuf)]) -> Result<(), Error> {
    if data.is_empty() {
        return Err(InputError::Conflict(
            "fit needs data: give --data KIND=FILE (KIND steady, onset, velocity_step or \
             relaxation; steady and onset on an adhesive scene), repeatable"
                .into(),
        )
        .into());
    }
    if let Some((i, (_, file))) = data
        .iter()
        .enumerate()
        .find(|(i, d)| data[..*i].contains(d))
    {
        return Err(InputError::Conflict(format!(
            "--data gives {} twice (data #{}): each measurement counts once",
            file.display(),
            i + 1
        ))
        .into());
    }
    Ok(())
}

/// Fits the scene `spec` to the data of `request`.
pub fn run(spec: &SceneSpec, request: &FitRequest) -> Result<Fit, Error> {
    check_request(&request.data)?;
    let setup = spec.setup(|p| *p)?;
    let data = request
        .data
        .iter()
        .map(|(kind, file)| Dataset::read(*kind, file))
        .collect::<Result<Vec<_>, _>>()?;
    let start = scene_values(&setup);
    let law_names = start.names();
    let requested: Vec<Name> = match &request.free {
        None => law_names.clone(),
        Some(names) => names
            .iter()
            .map(|n| {
                law_names
                    .iter()
                    .find(|l| l.key() == n.trim())
                    .copied()
                    .ok_or_else(|| InputError::UnknownName {
                        what: "parameter in --free (of this scene's friction law)",
                        name: n.clone(),
                        suggestion: crate::error::closest(n, law_names.iter().map(|l| l.key())),
                        allowed: law_names
                            .iter()
                            .map(|l| l.key())
                            .collect::<Vec<_>>()
                            .join(", "),
                    })
            })
            .collect::<Result<_, _>>()?,
    };
    if let Some(twice) = requested
        .iter()
        .enumerate()
        .find(|(i, n)| requested[..*i].contains(n))
    {
        return Err(InputError::Conflict(format!("--free names {} twice", twice.1.key())).into());
    }
    let rig = Rig::of(&setup.scene.units);
    let series = series_models(spec, &setup, &data, &start, rig)?;
    let mut problem = Joint {
        rows: Rows::new(&data),
        rig,
        base: start,
        free: requested.clone(),
        series: series
            .iter()
            .map(|s| {
                s.as_ref().map(|(model, _)| Cached {
                    model: model.clone(),
                    last: RefCell::new(None),
                })
            })
            .collect(),
    };
    let given: Vec<Kind> = request.data.iter().map(|(kind, _)| *kind).collect();
    let (minimum, not_determined) = fit_determined(&mut problem, |key, with, _| {
        let name = by_key(key);
        let with: Vec<Name> = with.iter().map(|k| by_key(k)).collect();
        NotDetermined {
            name: key,
            with: with.iter().map(|n| n.key()).collect(),
            remedy: remedy(name, &with, &given),
            kept_at: start.get(name).unwrap_or(f64::NAN),
        }
    })?;
    let values = problem.values(&minimum.x);
    let c = covariance(&minimum.jacobian).ok_or_else(|| {
        NumericalError::Analysis("the fit's normal matrix J^T J is singular".into())
    })?;
    let entries: Vec<Entry> = law_names
        .iter()
        .map(|name| Entry {
            key: name.key(),
            unit: name.unit(),
            value: values.get(*name).unwrap_or(f64::NAN),
            start: start.get(*name).unwrap_or(f64::NAN),
            logarithmic: name.positive(),
        })
        .collect();
    let not_determined_names: Vec<&'static str> = not_determined.iter().map(|n| n.name).collect();
    let mut summary = summarize(&problem, &minimum, &c, &entries, not_determined);
    let datasets = &mut summary.datasets;
    let mut at = 0;
    for (d, s) in data.iter().zip(&series) {
        if let Some((model, reason)) = s {
            let warning = below_onset(
                &rig,
                &values,
                d,
                setup.scene.units.k_over_w(setup.scene_params.kappa),
            );
            for fit in &mut datasets[at..at + d.measured.len()] {
                fit.model = Some(model.kind.name());
                fit.model_reason = Some(reason.clone());
                fit.warning.clone_from(&warning);
            }
        }
        at += d.measured.len();
    }
    let fitted_params = fitted_params(&setup, &values);
    let mut fitted_toml = fitted_toml(spec, &setup, &values, &data)?;
    if !not_determined_names.is_empty() {
        let names = &not_determined_names;
        fitted_toml = format!(
            "# not determined by the data, kept at the scene's values: {}\n{fitted_toml}",
            names.join(", ")
        );
    }
    let closed_form = closed_form(&data, &rig);
    // With a parameter left at the scene's value for want of data, a band
    // would claim a precision the data do not give.
    let (band, onset_type) = if request.stability && not_determined_names.is_empty() {
        let draws = Draws::new(&minimum.x, &c);
        (
            band(&setup, &problem, &minimum.x, &c, &draws),
            onset_types(spec, &setup, &problem, &minimum.x, &draws)?,
        )
    } else {
        (Vec::new(), Vec::new())
    };
    let stop = summary.stop.clone();
    Ok(Fit {
        scene: setup.scene.name.clone(),
        law: match start.ageing {
            AgeingValue::Tau(_) => "cutoff",
            AgeingValue::Mu2(m) if m != 0.0 || requested.contains(&Name::Mu2) => "ln2",
            AgeingValue::Mu2(_) => "rice-ruina",
        },
        summary,
        closed_form,
        band,
        onset_type,
        outcome: Outcome {
            params: params_json(&fitted_params),
            units: UnitsRecord::of(&Units {
                d0: values.d0_um * 1e-6,
                ..setup.scene.units
            }),
            iterations: minimum.iterations,
            complete: stop.is_none(),
            stop,
            files: Vec::new(),
            fitted_toml,
            data: data.clone(),
            values,
            start,
        },
        rig,
        series: series.into_iter().map(|s| s.map(|(m, _)| m)).collect(),
    })
}

/// Per dataset, the model of a time series on the scene's rig (`None` for
/// the other kinds) with why that model (quasi-static or inertial): the
/// one `simulate` would use for the protocol at the scene's values
/// ([`super::simulate::model_of_run`], steady sliding at the first
/// velocity for a unit of time before it). Checked to integrate at the
/// scene's values, where the fit starts.
fn series_models(
    spec: &SceneSpec,
    setup: &Setup,
    data: &[Dataset],
    start: &Values<f64>,
    rig: Rig,
) -> Result<Vec<Option<(SeriesModel, String)>>, Error> {
    let u = &setup.scene.units;
    let k_over_w = u.k_over_w(setup.scene_params.kappa);
    let cutoff = matches!(start.ageing, AgeingValue::Tau(_));
    let mut out = Vec::with_capacity(data.len());
    for d in data {
        if !d.kind.is_series() {
            out.push(None);
            continue;
        }
        let file = d.file.display();
        if !(setup.stiffness_given() && k_over_w > 0.0 && k_over_w.is_finite()) {
            return Err(InputError::Conflict(format!(
                "{file}: {} data are modelled on the scene's rig, whose spring the scene does \
                 not give: give K (N/m) in the scene or --set K=...",
                d.kind.name()
            ))
            .into());
        }
        let protocol = crate::fit::series::Protocol::of(d);
        let steady = crate::analysis::simulate::Segment {
            nu: protocol.steady_um_s / rig.v0_um_s,
            duration: 1.0,
        };
        let segments: Vec<_> = std::iter::once(steady)
            .chain(protocol.segments(u.d0 / u.v0, rig.v0_um_s))
            .collect();
        let choice = super::simulate::model_of_run(spec, setup, &segments);
        let model = SeriesModel::new(
            d,
            choice.kind,
            (cutoff, setup.scene_params.state_law),
            rig,
            k_over_w,
        );
        if let Err(e) = model.solve(start) {
            return Err(NumericalError::Analysis(format!(
                "{file}: the {} model ({}) at the scene's values, where the fit starts: {e}; \
                 start from values closer to the data's (--set), and check the rig's K (below \
                 the critical stiffness the block stick-slips)",
                d.kind.name(),
                choice.kind.name()
            ))
            .into());
        }
        out.push(Some((model, choice.reason)));
    }
    Ok(out)
}

/// Minimises with the errors of datasets without a sigma column estimated
/// from their residuals, until the estimates settle.
fn fit_with_estimated_errors<P: DataFit + Problem>(
    problem: &mut P,
) -> Result<(Minimum, bool), Error> {
    let mut x = problem.start();
    let total: usize = problem
        .data()
        .iter()
        .map(|d| d.rows() * d.measured.len())
        .sum();
    let p = problem.unknowns();
    let estimated = problem
        .data()
        .iter()
        .any(|d| d.measured.iter().any(|q| q.sigma.is_none()));
    if estimated && total <= p {
        return Err(InputError::Conflict(format!(
            "{total} measured values for {p} parameters leave no residual to estimate the \
             errors from: give a sigma column, more rows, or fewer --free parameters"
        ))
        .into());
    }
    // The first errors: each estimated quantity's RMS residual at the
    // start (its own magnitude where the start fits it exactly or not at
    // all), not 1 in its unit. Datasets in different units (a force in N
    // against a stiffness in N/m) then start on an equal footing, and the
    // first minimisation is not one dataset's alone (an onset in N/m
    // weighted 1e7 times a friction in N left five parameters to eight
    // stiffnesses, and that minimisation did not converge even from the
    // true values).
    let mut scales = problem.scale().to_vec();
    for (k, (d, scales)) in problem.data().iter().zip(scales.iter_mut()).enumerate() {
        for (q, scale) in d.measured.iter().zip(scales.iter_mut()) {
            if q.sigma.is_none() {
                let n = q.values.len() as f64;
                let at_start = (residual_sum_of_squares(problem, k, &x, q) / n).sqrt();
                let magnitude = (q.values.iter().map(|y| y * y).sum::<f64>() / n).sqrt();
                *scale = [at_start, magnitude, 1.0]
                    .into_iter()
                    .find(|s| s.is_finite() && *s > 0.0)
                    .unwrap_or(1.0);
            }
        }
    }
    problem.set_scale(scales);
    for _ in 0..SIGMA_ROUNDS {
        let (minimum, converged) = minimize(problem, &x).map_err(failed)?;
        if !converged {
            return Ok((minimum, false));
        }
        x = minimum.x.clone();
        let mut moved = 0.0f64;
        let mut scales = problem.scale().to_vec();
        for (k, (d, scales)) in problem.data().iter().zip(scales.iter_mut()).enumerate() {
            for (q, scale) in d.measured.iter().zip(scales.iter_mut()) {
                if q.sigma.is_some() {
                    continue;
                }
                let rss = residual_sum_of_squares(problem, k, &x, q);
                let n = q.values.len() as f64;
                // Data the model reproduces to rounding (exact synthetic
                // values) estimate no error below the rounding of their own
                // magnitude: weights of 1/MIN_POSITIVE sent the next
                // minimisation off to non-finite parameters.
                let magnitude = (q.values.iter().map(|y| y * y).sum::<f64>() / n).sqrt();
                let new = (rss / (n * (1.0 - p as f64 / total as f64)))
                    .sqrt()
                    .max(ROUNDING_ERRORS * f64::EPSILON * magnitude)
                    .max(f64::MIN_POSITIVE);
                moved = moved.max((new / *scale - 1.0).abs());
                *scale = new;
            }
        }
        problem.set_scale(scales);
        if moved < 1e-9 {
            return Ok((minimum, true));
        }
    }
    minimize(problem, &x).map_err(failed)
}

/// The least error per row estimated from residuals, in units of the
/// rounding of the values' magnitude.
const ROUNDING_ERRORS: f64 = 16.0;

/// A failed minimisation as the job's error, with what to try.
fn failed(e: LeastSquaresError) -> Error {
    NumericalError::Analysis(match e {
        LeastSquaresError::UndefinedStart => format!(
            "fit: {e}; start from a scene whose law has an onset at the data's velocities \
             (mu_phi > A: the rig's own scene, or --set B=... above A)"
        ),
        other => format!("fit: {other}; give the scene values closer to the data's (--set) or fewer --free parameters"),
    })
    .into()
}

/// The model of the quantity `column` at `v_um_s`.
fn predict<T: Scalar>(rig: &Rig, p: &Values<T>, column: &str, v_um_s: f64) -> T {
    match column {
        "mu" => rig.steady(p, v_um_s),
        "K_over_W_per_m" => rig.k_over_w_c(p, v_um_s),
        _ => rig.frequency_hz(p, v_um_s),
    }
}

/// `sum (model - data)^2` of the quantity `q` of dataset `i` at the
/// unknowns `x`, unweighted (infinite where the model is undefined).
fn residual_sum_of_squares<P: DataFit>(problem: &P, i: usize, x: &[f64], q: &Measured) -> f64 {
    problem.model_at(i, q, x).map_or(f64::INFINITY, |model| {
        model
            .iter()
            .zip(&q.values)
            .map(|(m, y)| (m - y).powi(2))
            .sum()
    })
}

/// Per dataset and quantity at the unknowns `x`: the RMS residual and how
/// its error was had.
pub(crate) fn dataset_fits<P: DataFit>(problem: &P, x: &[f64]) -> Vec<DatasetFit> {
    let mut out = Vec::new();
    for (k, (d, scales)) in problem.data().iter().zip(problem.scale()).enumerate() {
        for (q, scale) in d.measured.iter().zip(scales) {
            let rss = residual_sum_of_squares(problem, k, x, q);
            out.push(DatasetFit {
                kind: d.kind,
                file: d.file.display().to_string(),
                rows: d.rows(),
                quantity: q.column,
                rms: (rss / q.values.len() as f64).sqrt(),
                sigma: if q.sigma.is_some() {
                    "given"
                } else {
                    "estimated"
                },
                sigma_estimated: q.sigma.is_none().then_some(*scale),
                model: None,
                model_reason: None,
                warning: None,
            });
        }
    }
    out
}

/// The scene's dimensionless parameters with the fitted values.
fn fitted_params(setup: &Setup, v: &Values<f64>) -> crate::params::Params {
    let (mut p, u) = (setup.scene_params, &setup.scene.units);
    let d0 = v.d0_um * 1e-6;
    p.mu0 = v.mu0;
    p.a = v.a;
    p.b = v.b;
    p.kappa *= d0 / u.d0;
    p.m *= u.d0 / d0;
    match v.ageing {
        AgeingValue::Mu2(mu2) => p.mu2 = mu2,
        AgeingValue::Tau(tau) => p.theta_c = Some(tau * u.v0 / d0),
    }
    p
}

/// The fitted scene as TOML (every command reads it), checked by reading it back.
fn fitted_toml(
    spec: &SceneSpec,
    setup: &Setup,
    v: &Values<f64>,
    data: &[Dataset],
) -> Result<String, Error> {
    let overrides = crate::overrides::Overrides::parse(&spec.set)?;
    let (mut table, _) =
        crate::scene::table_with(&spec.scene, &setup.scene, &overrides.physical())?;
    for name in v.names() {
        if let Some(x) = v.get(name) {
            table.insert(name.key().into(), toml::Value::Float(x));
        }
    }
    let files: Vec<String> = data.iter().map(|d| d.file.display().to_string()).collect();
    table.insert(
        "name".into(),
        toml::Value::String(format!("{}-fitted", setup.scene.name)),
    );
    table.insert(
        "description".into(),
        toml::Value::String(format!(
            "{} fitted by stickslip fit to {}",
            setup.scene.name,
            files.join(", ")
        )),
    );
    let text = toml::to_string(&table).map_err(|e| std::io::Error::other(e.to_string()))?;
    crate::scene::from_toml_str(&text, "fitted.toml")?;
    Ok(text)
}

/// The seed's route (§II.D.2) where steady data are given: a straight
/// line of `mu` against `ln(V/V0)` (slope `A - B`, intercept `mu0`), then
/// with onset data `D0 = (B - A) / (K/W)_c` (eq. KcRR without inertia,
/// averaged over the rows) and with onset frequencies `B/A - 1 = (2 pi f
/// D0 / V)^2` (eq. omegacRR).
fn closed_form(data: &[Dataset], rig: &Rig) -> Option<ClosedForm> {
    let steady = data.iter().find(|d| d.kind == Kind::Steady)?;
    let x: Vec<f64> = steady
        .v_um_s
        .iter()
        .map(|v| (v / rig.v0_um_s).ln())
        .collect();
    let y = &steady.measured[0].values;
    let n = x.len() as f64;
    let (mx, my) = (x.iter().sum::<f64>() / n, y.iter().sum::<f64>() / n);
    let sxx: f64 = x.iter().map(|x| (x - mx).powi(2)).sum();
    let sxy: f64 = x.iter().zip(y).map(|(x, y)| (x - mx) * (y - my)).sum();
    let slope = sxy / sxx;
    let b_minus_a = -slope;
    let onset = data.iter().find(|d| d.kind == Kind::Onset);
    let d0_m = onset.map(|d| {
        let kw = &d.measured[0].values;
        kw.iter().map(|k| b_minus_a / k).sum::<f64>() / kw.len() as f64
    });
    let a = onset.zip(d0_m).and_then(|(d, d0)| {
        let f = d.measured.iter().find(|q| q.column == "frequency_hz")?;
        let per_row: Vec<f64> = d
            .v_um_s
            .iter()
            .zip(&f.values)
            .map(|(v, f)| b_minus_a / (2.0 * std::f64::consts::PI * f * d0 / (v * 1e-6)).powi(2))
            .collect();
        Some(per_row.iter().sum::<f64>() / per_row.len() as f64)
    });
    Some(ClosedForm {
        b_minus_a,
        mu0: my - slope * mx,
        d0_um: d0_m.map(|d| d * 1e6),
        a,
        from: "seed §II.D.2: slope of steady friction against ln V (B - A), eq. KcRR without \
               inertia (D0), eq. omegacRR (A)",
    })
}

/// Velocities of the band, log-spaced over the scene's range.
const BAND_POINTS: usize = 41;

/// Velocities at which the onset type is decided (the band's: a stretch of
/// the other type between two Bautin points is not stepped over).
const ONSET_TYPE_POINTS: usize = BAND_POINTS;

/// Parameter sets drawn for the sampled band.
const BAND_SAMPLES: usize = 1000;

/// Parameter sets drawn for the onset type at each velocity (each a Hopf
/// location with `l1`).
const ONSET_TYPE_SAMPLES: usize = 40;

/// Parameter sets drawn from the fit's normal distribution `N(x, C)` of
/// the unknowns, `x + L z` with `C = L L^T` and `z` standard normal from a
/// fixed seed (SplitMix64, Box–Muller): the same draws every run.
struct Draws(Vec<Vec<f64>>);

impl Draws {
    fn new(x: &[f64], c: &DMatrix<f64>) -> Draws {
        let Some(l) = c.clone().cholesky().map(|ch| ch.l()) else {
            return Draws(Vec::new());
        };
        let mut state = 0x05EE_DF17_u64;
        let mut uniform = || {
            state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            (((z ^ (z >> 31)) >> 11) as f64 + 0.5) / (1u64 << 53) as f64
        };
        let draws = (0..BAND_SAMPLES)
            .map(|_| {
                let z = DVector::from_fn(x.len(), |_, _| {
                    let (u, v) = (uniform(), uniform());
                    (-2.0 * u.ln()).sqrt() * (2.0 * std::f64::consts::PI * v).cos()
                });
                let u = &l * z;
                x.iter().zip(u.iter()).map(|(a, b)| a + b).collect()
            })
            .collect();
        Draws(draws)
    }
}

/// The velocities of the scene's range, `n` log-spaced, in µm/s.
fn range_velocities(setup: &Setup, n: usize) -> Vec<f64> {
    let (lo, hi) = setup.scene.nu_range;
    let v0 = setup.scene.units.v0 * 1e6;
    (0..n)
        .map(|i| v0 * lo * (hi / lo).powf(i as f64 / (n - 1) as f64))
        .collect()
}

/// The 95 % band of `(K/W)_c` over the scene's range (points where the
/// fitted law has no onset are left out).
fn band(
    setup: &Setup,
    problem: &Joint,
    x: &[f64],
    c: &DMatrix<f64>,
    draws: &Draws,
) -> Vec<BandPoint> {
    // `v` sorted.
    let quantile = |v: &[f64], q: f64| v[((v.len() - 1) as f64 * q).round() as usize];
    range_velocities(setup, BAND_POINTS)
        .into_iter()
        .filter_map(|v| {
            let k_over_w = predict(&problem.rig, &problem.values(x), "K_over_W_per_m", v);
            if !(k_over_w.is_finite() && k_over_w > 0.0) {
                return None;
            }
            let gradient = DVector::from_fn(x.len(), |k, _| {
                let xd = seeded(x, k);
                predict(&problem.rig, &problem.values(&xd), "K_over_W_per_m", v).eps
            });
            let std_error = (gradient.transpose() * c * &gradient)[(0, 0)].sqrt();
            let mut sampled: Vec<f64> = draws
                .0
                .iter()
                .map(|u| predict(&problem.rig, &problem.values(u), "K_over_W_per_m", v))
                .filter(|k| k.is_finite())
                .collect();
            let (sampled_lo_95, sampled_hi_95) = if sampled.len() > 1 {
                sampled.sort_by(f64::total_cmp);
                (quantile(&sampled, 0.025), quantile(&sampled, 0.975))
            } else {
                (f64::NAN, f64::NAN)
            };
            Some(BandPoint {
                v_um_s: v,
                k_over_w,
                std_error,
                lo_95: k_over_w - 1.96 * std_error,
                hi_95: k_over_w + 1.96 * std_error,
                sampled_lo_95,
                sampled_hi_95,
            })
        })
        .collect()
}

/// The onset type of the fitted scene at velocities of its range, and the
/// share of drawn parameter sets that agree, each decided as `hopf`
/// decides it ([`super::onset_with_degeneracy_resolved`]).
fn onset_types(
    spec: &SceneSpec,
    setup: &Setup,
    problem: &Joint,
    x: &[f64],
    draws: &Draws,
) -> Result<Vec<OnsetTypeAt>, Error> {
    let onset = |u: &[f64], v: f64| -> Result<Option<(Criticality, f64)>, Error> {
        let mut at = setup.clone();
        at.scene_params = fitted_params(setup, &problem.values(u));
        at.scene_params.nu = v / (setup.scene.units.v0 * 1e6);
        at.choice = choose_model(&at.scene_params, spec.model, spec.inertia_threshold);
        at.params = params_for(at.choice.kind, &at.scene_params);
        Ok(
            match super::onset_with_degeneracy_resolved(&mut at, spec.model.is_some())? {
                HopfOutcome::Found(h) => Some((h.onset.criticality, h.onset.l1)),
                HopfOutcome::StableForAllStiffness { .. } => None,
            },
        )
    };
    let mut out = Vec::new();
    for v in range_velocities(setup, ONSET_TYPE_POINTS) {
        let Some((criticality, l1)) = onset(x, v)? else {
            continue;
        };
        let mut supercritical = 0;
        let mut samples = 0;
        for u in draws.0.iter().take(ONSET_TYPE_SAMPLES) {
            // A drawn set without an onset there, or whose location fails,
            // is not counted.
            if let Ok(Some((c, _))) = onset(u, v) {
                samples += 1;
                supercritical += usize::from(c == Criticality::Supercritical);
            }
        }
        out.push(OnsetTypeAt {
            v_um_s: v,
            criticality,
            l1,
            share_supercritical: if samples > 0 {
                supercritical as f64 / samples as f64
            } else {
                f64::NAN
            },
            samples,
        });
    }
    Ok(out)
}
