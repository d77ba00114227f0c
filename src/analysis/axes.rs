//! The stability diagram in any pair of control parameters (`diagram --x P
//! --y Q`): the Hopf curve `Q_c(P)` with the onset type along it and its
//! Bautin points, each axis in its physical unit.
//!
//! Every control moves the dimensionless parameters as a monomial
//! ([`Control::powers`]: `kappa ∝ K`, `kappa ∝ 1/M` with `W = M g`,
//! `kappa, m ∝ 1/W`, `nu ∝ V`, ...), so a pair `(P, Q)` is a linear map
//! in logarithms: `ln q_i = ln q_i(start) + e_i^P ln(P/P0) + e_i^Q ln(Q/Q0)`.
//! [`PairField`] is the driven block with `ln(Q/Q0)` and `ln(P/P0)` as two
//! extra parameters through that map, and the engine's two-parameter Hopf
//! continuation (minimally augmented system, `continuation::codim2`)
//! traces the curve in exactly that pair: no approximation of a parameter
//! moving several dimensionless ones at once (`W`, `M`).
//!
//! The curve starts at the first value of `P` on a log grid over its range
//! where [`onset_in`] (`hopf --param Q`) finds an onset in `Q`; it is then
//! continued up and down in `P` to the ends of the range (or until `Q`
//! leaves its bounds, or the Hopf frequency vanishes).

use crate::analysis::control::{choose_along, onset_in, Control, CONTROL_NAMES};
use crate::analysis::diagram::curve_l1;
use crate::analysis::hopf::Criticality;
use crate::analysis::model_choice::{params_for, ModelChoice};
use crate::error::{Error, InputError, NumericalError};
use crate::model::{steady_state, DrivenBlock, ModelKind};
use crate::params::{Param, Params, N_PARAMS};
use crate::scene::Units;
use continuation::codim2::{CurveSettings, HopfCurve, HopfCurvePoint};
use continuation::normal_form::hopf_series;
use continuation::CurveControl;
use continuation::StepControl;
use continuation::Stop;
use continuation::{NewtonSettings, Scalar, VectorField};
use serde::Serialize;
use serde_json::{json, Map, Value};

/// The two axes of a diagram: `x` the parameter `P` varied along the
/// curve, `y` the critical value `Q_c` plotted against it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Axes {
    pub x: Control,
    pub y: Control,
}

/// The error of `Control::parse` for the option `field` (`--x`, `--y`).
fn parse_one(name: &str, field: &'static str) -> Result<Control, InputError> {
    Control::parse(name, field).map_err(|e| match e {
        InputError::UnknownName {
            name,
            suggestion,
            allowed,
            ..
        } => InputError::UnknownName {
            what: if field == "--x" {
                "--x value"
            } else {
                "--y value"
            },
            name,
            suggestion,
            allowed,
        },
        e => e,
    })
}

impl Axes {
    /// The axes `--x` and `--y` name; `None` when neither is given (the
    /// default diagram, `(V, K/M)` or `(V, K/W)`). One given alone is paired
    /// with `V` (x) or `K` (y).
    pub fn parse(x: Option<&str>, y: Option<&str>) -> Result<Option<Axes>, InputError> {
        if x.is_none() && y.is_none() {
            return Ok(None);
        }
        let x = x.map(|n| parse_one(n, "--x")).transpose()?;
        let y = y.map(|n| parse_one(n, "--y")).transpose()?;
        let axes = Axes {
            x: x.unwrap_or(Control::V),
            y: y.unwrap_or(Control::K),
        };
        if axes.x == axes.y {
            return Err(InputError::Conflict(format!(
                "--x and --y both name {}: a diagram needs two different parameters ({CONTROL_NAMES})",
                axes.x.name()
            )));
        }
        Ok(Some(axes))
    }

    /// The units the pair is read in: with `W` on an axis the load is
    /// given by it (no longer the block's weight), so `M` moves `m`.
    pub fn units(&self, units: &Units) -> Units {
        let mut u = *units;
        if self.x == Control::W || self.y == Control::W {
            u.load_is_weight = false;
        }
        u
    }

    /// Refuses a parameter of the ageing form the scene does not use
    /// (`tau` with the ln² form, `mu2` with the cutoff), naming its option.
    pub fn check_forms(&self, params: &Params) -> Result<(), InputError> {
        for (field, c) in [("--x", self.x), ("--y", self.y)] {
            c.check_form(params, field)?;
        }
        Ok(())
    }

    /// Refuses a pair the scene cannot vary: a parameter of the other
    /// ageing form, or two that move the model's dimensionless parameters
    /// along one line (`K` and `kappa`; `K` and `M` with `W = M g`, both
    /// `kappa` alone; `K` and `W` without inertia), naming `--x` and `--y`.
    pub fn check(&self, kind: ModelKind, units: &Units, params: &Params) -> Result<(), InputError> {
        self.check_forms(params)?;
        let u = self.units(units);
        // The inertia counts only where the model has it.
        let counts = |q: Param| q != Param::M || (kind == ModelKind::Inertial && params.m > 0.0);
        let vector = |c: Control| {
            let mut v = [0.0; N_PARAMS];
            for (q, e) in c.powers(&u) {
                if counts(q) {
                    v[q as usize] = e;
                }
            }
            v
        };
        let (a, b) = (vector(self.x), vector(self.y));
        let independent =
            (0..N_PARAMS).any(|i| (0..N_PARAMS).any(|j| (a[i] * b[j] - a[j] * b[i]).abs() > 1e-12));
        if !independent {
            let moved = |c: Control| {
                let names: Vec<&str> = c
                    .powers(&u)
                    .into_iter()
                    .filter(|(q, _)| counts(*q))
                    .map(|(q, _)| q.name())
                    .collect();
                if names.is_empty() {
                    "nothing in this model".to_string()
                } else {
                    names.join(" and ")
                }
            };
            return Err(InputError::Conflict(format!(
                "--x {} and --y {} cannot vary independently: {} moves {}, {} moves {}{}, so one \
                 fixes the other's effect and the pair has no two-parameter curve; choose two \
                 parameters that move different dimensionless ones ({CONTROL_NAMES})",
                self.x.name(),
                self.y.name(),
                self.x.name(),
                moved(self.x),
                self.y.name(),
                moved(self.y),
                if u.load_is_weight {
                    " (the load is the block's weight, W = M g)"
                } else {
                    ""
                }
            )));
        }
        Ok(())
    }
}

/// The column name of a control with its unit: `V_um_per_s`, `K_N_per_m`,
/// `M_kg`, `W_N`, `tau_s`, or its name (dimensionless).
pub fn column(c: Control) -> String {
    match c.unit() {
        "1" => c.name().to_string(),
        unit => format!("{}_{}", c.name(), unit.replace('/', "_per_")),
    }
}

/// The driven block with two extra parameters, `ln(Q/Q0)` (index
/// `N_PARAMS`) and `ln(P/P0)` (`N_PARAMS + 1`), each moving the
/// dimensionless parameters by its powers: `q_i = p_i exp(e_i^Q ln(Q/Q0)
/// + e_i^P ln(P/P0))`, exact (every control is a monomial).
pub struct PairField<'a, S: VectorField> {
    pub inner: &'a S,
    /// Powers of `Q` and of `P` on each dimensionless parameter.
    pub powers: [[f64; N_PARAMS]; 2],
}

impl<S: VectorField> PairField<'_, S> {
    /// The dimensionless parameters at the extended vector `p`.
    pub fn dimensionless(&self, p: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; N_PARAMS];
        self.map(p, &mut out);
        out
    }

    fn map<D: Scalar>(&self, p: &[D], out: &mut [D]) {
        let (w, u) = (p[N_PARAMS], p[N_PARAMS + 1]);
        for i in 0..N_PARAMS {
            let (eq, ep) = (self.powers[0][i], self.powers[1][i]);
            out[i] = if eq == 0.0 && ep == 0.0 {
                p[i]
            } else {
                p[i] * (w * eq + u * ep).exp()
            };
        }
    }
}

impl<S: VectorField> VectorField for PairField<'_, S> {
    fn dim(&self) -> usize {
        self.inner.dim()
    }
    fn n_params(&self) -> usize {
        N_PARAMS + 2
    }
    fn param_name(&self, k: usize) -> String {
        match k {
            k if k < N_PARAMS => self.inner.param_name(k),
            k if k == N_PARAMS => "ln(Q/Q0)".to_string(),
            _ => "ln(P/P0)".to_string(),
        }
    }
    fn rhs<D: Scalar>(&self, x: &[D], p: &[D], out: &mut [D]) {
        let mut q = [p[0]; N_PARAMS];
        self.map(p, &mut q);
        self.inner.rhs(x, &q, out);
    }
}

/// A request for a diagram in a pair of controls.
#[derive(Clone, Debug)]
pub struct AxesRequest {
    pub axes: Axes,
    /// The range of `P` [its unit]; default: the scene's velocity range
    /// for `V` and `nu`, a decade either side of the scene's value otherwise.
    pub x_range: Option<(f64, f64)>,
    /// Bounds of `Q` [its unit]; default: six decades either side of
    /// where the curve starts.
    pub y_range: Option<(f64, f64)>,
    /// The scene's velocity range (dimensionless).
    pub nu_range: (f64, f64),
    /// Most steps in each direction along the curve.
    pub max_steps: usize,
}

/// A point of the curve: `P` and `Q` in their units, the dimensionless
/// parameters there and the onset (a row of `-hopf-curve.csv`).
#[derive(Clone, Debug, Serialize)]
pub struct AxesPoint {
    /// `P` [its unit].
    pub x: f64,
    /// `Q_c` [its unit].
    pub y: f64,
    pub nu: f64,
    pub kappa: f64,
    pub m: f64,
    pub omega: f64,
    pub l1: f64,
    pub l1_error_bound: f64,
    pub criticality: Criticality,
    #[serde(rename = "V_um_per_s")]
    pub v_um_per_s: f64,
    #[serde(rename = "K_N_per_m")]
    pub k_n_per_m: f64,
    #[serde(rename = "M_kg")]
    pub m_kg: f64,
    #[serde(rename = "W_N")]
    pub w_n: f64,
    pub frequency_hz: f64,
}

/// A Bautin point of the curve (`l1 = 0`).
#[derive(Clone, Debug, Serialize)]
pub struct AxesBautin {
    pub x: f64,
    pub y: f64,
    pub nu: f64,
    pub kappa: f64,
    pub m: f64,
    pub omega: f64,
    pub l2: f64,
    pub l2_error_bound: f64,
}

/// Why a run of the curve stopped (JSON `stop_reason`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum AxesStop {
    /// At the end of the range of `P`.
    EndOfRange,
    /// `Q_c` left its bounds (`--y-range`).
    YBound,
    /// The Hopf frequency vanished (the curve ends, e.g. `kappa_c -> 0`).
    FrequencyVanishing,
    /// `--max-steps` steps first.
    StepLimit,
    /// The continuation ended without a reason.
    Stopped,
    /// No onset in `Q` at any `P` tried.
    NoHopfPoint,
}

impl AxesStop {
    /// In words.
    pub fn words(self) -> &'static str {
        match self {
            AxesStop::EndOfRange => "end of the x range",
            AxesStop::YBound => "the critical value left the y range",
            AxesStop::FrequencyVanishing => "the Hopf frequency vanishes (the curve ends)",
            AxesStop::StepLimit => "step limit (--max-steps)",
            AxesStop::Stopped => "stopped",
            AxesStop::NoHopfPoint => "no onset found in the x range",
        }
    }

    /// Whether the run ended where it should.
    pub fn ends_curve(self) -> bool {
        matches!(
            self,
            AxesStop::EndOfRange | AxesStop::YBound | AxesStop::FrequencyVanishing
        )
    }
}

/// The Hopf curve in a pair of controls.
#[derive(Clone, Debug)]
pub struct AxesDiagram {
    pub axes: Axes,
    /// The scene's units as the pair reads them ([`Axes::units`]).
    pub units: Units,
    /// The model it was computed in, and why.
    pub choice: ModelChoice,
    /// The range of `P` and the bounds of `Q` [their units].
    pub x_range: (f64, f64),
    pub y_bounds: (f64, f64),
    pub points: Vec<AxesPoint>,
    pub bautin: Vec<AxesBautin>,
    pub stop: AxesStop,
    pub complete: bool,
    /// The scene's own `(P, Q)`, where both are positive.
    pub operating: Option<(f64, f64)>,
    /// Whether steady sliding is stable above the curve (larger `Q`),
    /// judged at its first point; `None` without a curve.
    pub stable_above: Option<bool>,
    /// Why the curve is empty, in words.
    pub reason: Option<String>,
    /// Largest relative difference between the dimensionless parameters
    /// of the continued map and those of [`Control::at`] applied at each
    /// point's `(P, Q)` (a check of the map; rounding).
    pub map_check: f64,
}

/// The model for a diagram in `axes`: the choice along `P` over its range
/// ([`choose_along`]), inertial where `Q` moves the inertia.
pub fn choose_axes_model(
    axes: Axes,
    units: &Units,
    params: &Params,
    x_range: (f64, f64),
    forced: Option<ModelKind>,
    threshold: f64,
) -> ModelChoice {
    let u = axes.units(units);
    let mut choice = choose_along(axes.x, &u, params, Some(x_range), forced, threshold);
    if forced.is_none() && choice.kind == ModelKind::QuasiStatic && axes.y.moves_inertia(&u) {
        choice.kind = ModelKind::Inertial;
        choice.reason = format!(
            "inertial: the control {} moves the inertia m, which the quasi-static model drops",
            axes.y.name()
        );
    }
    choice
}

/// The range of `P` asked for or its default.
pub fn x_range_of(
    axes: Axes,
    units: &Units,
    params: &Params,
    req: &AxesRequest,
) -> Result<(f64, f64), InputError> {
    axes.check_forms(params)?;
    let u = axes.units(units);
    let range = match (req.x_range, axes.x) {
        (Some(r), _) => r,
        (None, Control::V) | (None, Control::Dimensionless(Param::Nu)) => axes
            .x
            .default_range(&u, params, req.nu_range)
            .unwrap_or((0.0, 0.0)),
        (None, c) => {
            let v = c.value(&u, params);
            if !(v.is_finite() && v > 0.0) {
                return Err(InputError::Conflict(format!(
                    "--x {}: the scene's {} is 0, so the x range has no default: give --x-range \
                     LO:HI (in {})",
                    c.name(),
                    c.name(),
                    c.unit_in_words()
                )));
            }
            (v / 10.0, v * 10.0)
        }
    };
    check_range("--x-range", range, axes.x)?;
    Ok(range)
}

fn check_range(field: &str, (lo, hi): (f64, f64), c: Control) -> Result<(), InputError> {
    for v in [lo, hi] {
        if !(v.is_finite() && v > 0.0) {
            return Err(InputError::out_of_range(
                field,
                v,
                &format!("a finite value > 0 ({})", c.unit_in_words()),
            ));
        }
    }
    if hi <= lo {
        return Err(InputError::Conflict(format!(
            "{field} {lo}:{hi}: give LO:HI with LO < HI (in {})",
            c.unit_in_words()
        )));
    }
    Ok(())
}

/// Values of `P` tried for a first onset.
const FIRST_ONSET_GRID: usize = 41;

/// Traces the Hopf curve of the scene (`params` with inertia kept, `units`)
/// in `req.axes`, in the model `choice`.
pub fn axes_diagram(
    choice: &ModelChoice,
    params: &Params,
    units: &Units,
    req: &AxesRequest,
) -> Result<AxesDiagram, Error> {
    let axes = req.axes;
    let kind = choice.kind;
    axes.check(kind, units, params)?;
    let u = axes.units(units);
    let (x_lo, x_hi) = x_range_of(axes, units, params, req)?;
    if let Some(r) = req.y_range {
        check_range("--y-range", r, axes.y)?;
    }
    let scene_value = |c: Control| {
        let v = c.value(&u, params);
        (v.is_finite() && v > 0.0).then_some(v)
    };
    let operating = scene_value(axes.x).zip(scene_value(axes.y));
    let mut out = AxesDiagram {
        axes,
        units: u,
        choice: choice.clone(),
        x_range: (x_lo, x_hi),
        y_bounds: req.y_range.unwrap_or((0.0, f64::INFINITY)),
        points: Vec::new(),
        bautin: Vec::new(),
        stop: AxesStop::NoHopfPoint,
        complete: true,
        operating,
        stable_above: None,
        reason: None,
        map_check: 0.0,
    };
    // The first onset in Q on a log grid over the range of P.
    let mut start = None;
    let mut last_why = String::new();
    for i in 0..FIRST_ONSET_GRID {
        let p = x_lo * (x_hi / x_lo).powf(i as f64 / (FIRST_ONSET_GRID - 1) as f64);
        let (pp, pu) = axes.x.at(&u, params, p);
        let range = req
            .y_range
            .or_else(|| axes.y.default_range(&pu, &pp, req.nu_range));
        match onset_in(kind, &pp, &pu, axes.y, range) {
            Ok(onset) => {
                start = Some((p, onset));
                break;
            }
            Err(Error::Input(e)) => return Err(e.into()),
            // In a pair the range of Q searched is --y-range.
            Err(Error::Numerical(NumericalError::NoOnsetInRange {
                param,
                unit,
                lo,
                hi,
                why,
                ..
            })) => {
                last_why = NumericalError::NoOnsetInRange {
                    param,
                    unit,
                    lo,
                    hi,
                    why,
                    remedy: "--y-range",
                }
                .to_string()
            }
            Err(e) => last_why = e.to_string(),
        }
    }
    let Some((p0, onset)) = start else {
        // Not found is not absent: the curve may lie where the search did
        // not reach (partial, status 4).
        out.complete = false;
        out.reason = Some(format!(
            "no onset in {} at any of the {FIRST_ONSET_GRID} values of {} tried in {x_lo:.6e} .. \
             {x_hi:.6e} {} (the last: {last_why})",
            axes.y.name(),
            axes.x.name(),
            axes.x.unit_in_words()
        ));
        return Ok(out);
    };
    let q0 = onset.value;
    out.y_bounds = req.y_range.unwrap_or((q0 * 1e-6, q0 * 1e6));
    let start_params = params_for(kind, &onset.params);
    let block = DrivenBlock::new(kind, &start_params);
    let mut powers = [[0.0; N_PARAMS]; 2];
    for (row, c) in [axes.y, axes.x].into_iter().enumerate() {
        for (q, e) in c.powers(&u) {
            powers[row][q as usize] = e;
        }
    }
    let field = PairField {
        inner: &block,
        powers,
    };
    let mut z0 = start_params.to_vec();
    z0.extend([0.0, 0.0]);
    let x0: Vec<f64> = match kind {
        ModelKind::Inertial => onset.hopf.state.to_vec(),
        ModelKind::QuasiStatic => vec![onset.hopf.state[0], onset.hopf.state[2]],
    };
    out.stable_above = Some(stable_above(kind, &field, &z0, &start_params));
    let at_point = |pt: &HopfCurvePoint| -> (AxesPoint, f64) {
        let dimensionless = field.dimensionless(&pt.p);
        let p = start_params.with_vec(&dimensionless);
        let (x, y) = (p0 * pt.p[N_PARAMS + 1].exp(), q0 * pt.p[N_PARAMS].exp());
        // The same point through Control::at (P, then Q): the map's check.
        let (p1, u1) = axes.x.at(&u, params, x);
        let (p2, u2) = axes.y.at(&u1, &p1, y);
        let check = Param::ALL
            .iter()
            .filter(|&&q| q != Param::M || kind == ModelKind::Inertial)
            .map(|&q| {
                let (a, b) = (p.get(q), p2.get(q));
                if a == b {
                    0.0
                } else {
                    (a - b).abs() / a.abs().max(b.abs())
                }
            })
            .fold(0.0, f64::max);
        let (l1, bound) = curve_l1(&block, kind, &p, pt);
        let bound = bound.max(4.0 * f64::EPSILON * l1.abs());
        let point = AxesPoint {
            x,
            y,
            nu: p.nu,
            kappa: p.kappa,
            m: p2.m,
            omega: pt.omega,
            l1,
            l1_error_bound: bound,
            criticality: Criticality::of(l1, bound),
            v_um_per_s: u2.velocity_um_s(p.nu),
            k_n_per_m: u2.stiffness(p.kappa),
            m_kg: u2.mass,
            w_n: u2.load,
            frequency_hz: u2.frequency_hz(pt.omega),
        };
        (point, check)
    };
    let bounds = [
        ((out.y_bounds.0 / q0).ln(), (out.y_bounds.1 / q0).ln()),
        ((x_lo / p0).ln(), (x_hi / p0).ln()),
    ];
    let run = |upward: bool| -> Result<(Vec<AxesPoint>, Vec<AxesBautin>, AxesStop, f64), Error> {
        let settings = CurveSettings {
            control: CurveControl {
                step: StepControl {
                    ds: 0.02,
                    ds_min: 1e-10,
                    ds_max: 0.05,
                    growth: 1.5,
                    easy_iterations: 3,
                    min_tangent_cos: 0.97,
                },
                corrector: NewtonSettings {
                    max_iter: 8,
                    ..NewtonSettings::default()
                },
                // Arclength in (ln Q, ln P), the state and omega weighted
                // lightly relative to their size (as the (kappa, nu) curve).
                weights: [vec![1e-16; x0.len() + 1], vec![1.0, 1.0]].concat(),
                relative: (0..=x0.len()).collect(),
            },
            max_steps: req.max_steps,
            bounds,
            increase_second: upward,
            omega_min: 1e-4 * onset.hopf.omega_c,
            ..Default::default()
        };
        let mut curve = HopfCurve::new(
            &field,
            &x0,
            onset.hopf.omega_c,
            &z0,
            [N_PARAMS, N_PARAMS + 1],
            settings,
        )
        .map_err(NumericalError::from)?;
        let (mut points, mut special, mut check) = (Vec::new(), Vec::new(), 0.0f64);
        for pt in curve.by_ref() {
            let pt = pt.map_err(NumericalError::from)?;
            if let Some(b) = pt.events.first().map(|e| &e.point) {
                let (c, _) = at_point(b);
                let series =
                    hopf_series(&field, &b.x, &b.p, b.omega).map_err(NumericalError::from)?;
                special.push(AxesBautin {
                    x: c.x,
                    y: c.y,
                    nu: c.nu,
                    kappa: c.kappa,
                    m: c.m,
                    omega: c.omega,
                    l2: series.l2,
                    l2_error_bound: series.l2_error_bound,
                });
            }
            let (point, c) = at_point(&pt);
            check = check.max(c);
            points.push(point);
        }
        let end = if upward { x_hi } else { x_lo };
        let at_end = points
            .last()
            .is_some_and(|p| (p.x / end - 1.0).abs() < 1e-10);
        let stop = match curve.stop() {
            Some(Stop::Bound { .. }) if at_end => AxesStop::EndOfRange,
            Some(Stop::Bound { .. }) => AxesStop::YBound,
            Some(Stop::FrequencyVanishing { .. }) => AxesStop::FrequencyVanishing,
            Some(Stop::MaxSteps { .. }) => AxesStop::StepLimit,
            Some(_) | None => AxesStop::Stopped,
        };
        Ok((points, special, stop, check))
    };
    let (mut points, mut special, mut stop, mut check) = run(true)?;
    if p0 > x_lo * (1.0 + 1e-12) {
        let (mut below, below_special, below_stop, below_check) = run(false)?;
        if stop.ends_curve() && !below_stop.ends_curve() {
            stop = below_stop;
        }
        below.reverse();
        below.pop();
        below.extend(points);
        points = below;
        special.splice(0..0, below_special);
        check = check.max(below_check);
    }
    if points
        .iter()
        .any(|p| !(p.x.is_finite() && p.y.is_finite() && p.omega.is_finite() && p.l1.is_finite()))
    {
        return Err(NumericalError::Analysis(format!(
            "the Hopf curve in ({}, {}) has non-finite values",
            axes.x.name(),
            axes.y.name()
        ))
        .into());
    }
    out.points = points;
    out.bautin = special;
    out.stop = stop;
    out.complete = stop.ends_curve();
    out.map_check = check;
    Ok(out)
}

/// Whether steady sliding is stable just above the onset in `Q` (at
/// `Q = Q0 (1 + 1e-3)`, `P = P0`): no eigenvalue of its Jacobian with a
/// positive real part.
fn stable_above<S: VectorField>(
    kind: ModelKind,
    field: &PairField<S>,
    z0: &[f64],
    start: &Params,
) -> bool {
    let mut z = z0.to_vec();
    z[N_PARAMS] = 1e-3f64.ln_1p();
    let p = start.with_vec(&field.dimensionless(&z));
    let x = steady_state(kind, &p);
    let jac = continuation::system::jacobian(field, &x, &z);
    jac.complex_eigenvalues().iter().all(|l| l.re < 0.0)
}

impl AxesDiagram {
    /// The x and y columns of a point, named with their units
    /// (`x_V_um_per_s`, `y_M_kg`).
    pub fn columns(&self) -> (String, String) {
        (
            format!("x_{}", column(self.axes.x)),
            format!("y_{}", column(self.axes.y)),
        )
    }

    /// A point as a JSON object: its fields with `x` and `y` also under
    /// their named columns.
    fn point_json<T: Serialize>(&self, p: &T, x: f64, y: f64) -> Value {
        let (cx, cy) = self.columns();
        let mut v = serde_json::to_value(p).unwrap_or(Value::Null);
        if let Value::Object(map) = &mut v {
            let mut named = Map::new();
            named.insert(cx, json!(x));
            named.insert(cy, json!(y));
            named.append(map);
            *map = named;
        }
        v
    }

    /// The onset type shared by every point, `None` where it changes.
    pub fn onset_type(&self) -> Option<Criticality> {
        let first = self.points.first()?.criticality;
        self.points
            .iter()
            .all(|p| p.criticality == first)
            .then_some(first)
    }

    /// The diagram's JSON fields (the CLI adds the scene, its parameters
    /// and the files).
    pub fn to_json(&self) -> Value {
        let axis = |c: Control, col: String, range: (f64, f64)| {
            json!({
                "param": c.name(),
                "unit": c.unit(),
                "column": col,
                "range": [range.0, range.1],
                "moves": c.moves(&self.units).iter().map(|q| q.name()).collect::<Vec<_>>(),
            })
        };
        let (cx, cy) = self.columns();
        let mut out = json!({
            "model": self.choice.kind,
            "model_reason": self.choice.reason,
            "x": axis(self.axes.x, cx, self.x_range),
            "y": axis(self.axes.y, cy, self.y_bounds),
            "hopf_curve": self.points.iter().map(|p| self.point_json(p, p.x, p.y)).collect::<Vec<_>>(),
            "special_points": self.bautin.iter().map(|b| {
                let mut v = self.point_json(b, b.x, b.y);
                v["kind"] = json!("bautin");
                v
            }).collect::<Vec<_>>(),
            "complete": self.complete,
            "stop": self.stop.words(),
            "stop_reason": self.stop,
            "onset_type": self.onset_type().map(Criticality::name).unwrap_or("mixed"),
        });
        if let Some(side) = self.stable_above {
            out["stable_side"] = json!(if side { "above" } else { "below" });
        }
        if let Some((x, y)) = self.operating {
            out["operating_point"] = json!({
                self.columns().0: x,
                self.columns().1: y,
            });
        }
        if let Some(why) = &self.reason {
            out["reason"] = json!(why);
        }
        out
    }

    /// `-hopf-curve.csv`: the named x and y columns first, then every field
    /// of [`AxesPoint`] but `x` and `y`.
    pub fn csv(&self, head: &str) -> String {
        let (cx, cy) = self.columns();
        let mut w = String::from(head);
        w.push_str(&format!(
            "{cx},{cy},nu,kappa,m,omega,l1,l1_error_bound,criticality,V_um_per_s,K_N_per_m,M_kg,W_N,frequency_hz\n"
        ));
        for p in &self.points {
            w.push_str(&format!(
                "{:.15e},{:.15e},{:.15e},{:.15e},{:.15e},{:.15e},{:.15e},{:.15e},{},{:.15e},{:.15e},{:.15e},{:.15e},{:.15e}\n",
                p.x,
                p.y,
                p.nu,
                p.kappa,
                p.m,
                p.omega,
                p.l1,
                p.l1_error_bound,
                p.criticality.name(),
                p.v_um_per_s,
                p.k_n_per_m,
                p.m_kg,
                p.w_n,
                p.frequency_hz
            ));
        }
        w
    }
}
