//! The rig's control parameters: what an experimenter varies (`K` in N/m,
//! `V` in µm/s, `M` in kg, `W` in N, `tau` in s, or a dimensionless
//! parameter of docs/model.md), each a path through the dimensionless
//! parameters, and the stick-slip onset along it ([`onset_in`]).
//!
//! With `V0` and `D0` fixed (docs/model.md, "Dimensionless variables"):
//!
//! | control | moves | path |
//! |---|---|---|
//! | `K`, `kappa` | `kappa = K D0 / W` | the stiffness: the onset is `hopf`'s |
//! | `V`, `nu` | `nu = V / V0` | one index |
//! | `M` (the scene gives `W`) | `m = M V0^2 / (W D0)` | one index |
//! | `M` (`W = M g`) | `kappa = K D0 / (M g)`; `m = V0^2 / (g D0)` stays | the stiffness, `M_c = K D0 / (g kappa_c)` |
//! | `W` | `kappa = K D0 / W` and `m = M V0^2 / (W D0)` together | a root of `kappa - kappa_c` in `1/W` |
//! | `tau`, `theta_c` | `theta_c = tau V0 / D0` | one index |
//! | `m`, `A`, `B`, `mu2`, `mu_vv`, `mu_vphi` | itself | one index |
//!
//! `mu0` moves no onset (it shifts the friction level only) and is refused.

use crate::analysis::cycles::CycleRecord;
use crate::analysis::hopf::{find_hopf, HopfOutcome, HopfPoint};
use crate::analysis::model_choice::params_for;
use crate::error::{closest, Error, InputError, NumericalError};
use crate::model::{steady_state, DrivenBlock, ModelKind};
use crate::params::{Param, Params};
use crate::scene::Units;
use continuation::StepControl;
use continuation::{Branch, ContinuationSettings, Direction, EventKind};

/// A control parameter of the rig.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Control {
    /// A dimensionless parameter of docs/model.md (not `mu0`).
    Dimensionless(Param),
    /// The spring stiffness `K` [N/m].
    K,
    /// The driving velocity `V` [µm/s].
    V,
    /// The block mass `M` \[kg\].
    M,
    /// The normal load `W` \[N\].
    W,
    /// The ageing cutoff `tau` \[s\].
    Tau,
    /// The radiation damping `eta` [s/m] (`eta_d = eta V0`).
    Eta,
}

/// The names [`Control::parse`] takes, with their units (for messages).
pub const CONTROL_NAMES: &str = "K [N/m], V [µm/s], M [kg], W [N], tau [s], eta [s/m] \
                                 (physical); kappa, nu, m, A, B, mu2, theta_c, mu_vv, mu_vphi, \
                                 eta_d (dimensionless)";

/// How a control moves the dimensionless parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Path {
    /// `kappa` alone, proportional to the control (`K`, `kappa`).
    Stiffness,
    /// `kappa` alone, inversely proportional (`M` when `W = M g`).
    InverseStiffness,
    /// One index, `param = scale * value`.
    Index { param: Param, scale: f64 },
    /// `kappa` and `m` both proportional to `1 / W`.
    Load,
}

impl Control {
    /// The control `--param` names, if it is given.
    pub fn from_param(param: Option<&str>) -> Result<Option<Control>, InputError> {
        param
            .map(|name| Control::parse(name, "--param"))
            .transpose()
    }

    /// The control named `name` (`field` is the option, for the message).
    pub fn parse(name: &str, field: &str) -> Result<Control, InputError> {
        let control = match name {
            "K" => Control::K,
            "V" => Control::V,
            "M" => Control::M,
            "W" => Control::W,
            "tau" => Control::Tau,
            "eta" => Control::Eta,
            "mu0" => {
                return Err(InputError::Conflict(format!(
                    "{field} mu0: mu0 shifts the friction level only and moves no onset \
                     (Appendix C depends on mu_v and mu_phi); choose one of {CONTROL_NAMES}"
                )))
            }
            _ => match Param::parse(name) {
                Ok(p) => Control::Dimensionless(p),
                Err(_) => {
                    let physical = ["K", "V", "M", "W", "tau", "eta"];
                    let dimensionless = Param::ALL.iter().map(|p| p.name());
                    let all = physical
                        .into_iter()
                        .chain(dimensionless.filter(|n| *n != "mu0"));
                    return Err(InputError::UnknownName {
                        what: "--param value",
                        name: name.to_string(),
                        suggestion: closest(name, all),
                        allowed: CONTROL_NAMES.to_string(),
                    });
                }
            },
        };
        Ok(control)
    }

    /// The name, as given on the command line.
    pub fn name(self) -> &'static str {
        match self {
            Control::Dimensionless(p) => p.name(),
            Control::K => "K",
            Control::V => "V",
            Control::M => "M",
            Control::W => "W",
            Control::Tau => "tau",
            Control::Eta => "eta",
        }
    }

    /// Its unit (`1` for a dimensionless parameter).
    pub fn unit(self) -> &'static str {
        match self {
            Control::Dimensionless(_) => "1",
            Control::K => "N/m",
            Control::V => "um/s",
            Control::M => "kg",
            Control::W => "N",
            Control::Tau => "s",
            Control::Eta => "s/m",
        }
    }

    /// Its unit as text shows it: `µm/s` for `um/s`, nothing for a
    /// dimensionless parameter.
    pub fn text_unit(self) -> &'static str {
        match self.unit() {
            "um/s" => "µm/s",
            "1" => "",
            u => u,
        }
    }

    /// Whether it is the stiffness (`K` or `kappa`), today's default.
    pub fn is_stiffness(self) -> bool {
        matches!(self, Control::K | Control::Dimensionless(Param::Kappa))
    }

    /// Whether it moves the inertia `m` (then only the inertial model sees it).
    pub fn moves_inertia(self, units: &Units) -> bool {
        match self {
            Control::Dimensionless(p) => p == Param::M,
            Control::M => !units.load_is_weight,
            // m = M V0^2/(W D0): only a block with mass.
            Control::W => units.mass > 0.0,
            _ => false,
        }
    }

    /// Refuses a parameter of the ageing form the scene does not use
    /// (`mu2`, `mu_vv` or `mu_vphi` with the cutoff, `tau` or `theta_c`
    /// with the logarithmic form): it would move nothing. `option` names
    /// where it was given (`--param`).
    pub fn check_form(self, params: &Params, option: &str) -> Result<(), InputError> {
        let cutoff = params.theta_c.is_some();
        let what = match self {
            Control::Dimensionless(Param::Mu2) if cutoff => "mu2 is the ln² coefficient",
            Control::Dimensionless(p @ (Param::MuVv | Param::MuVphi)) if cutoff => match p {
                Param::MuVv => "mu_vv is the (ln v)² coefficient of the logarithmic form",
                _ => "mu_vphi is the (ln theta)(ln v) coefficient of the logarithmic form",
            },
            Control::Tau | Control::Dimensionless(Param::ThetaC) if !cutoff => {
                "tau (theta_c) is the ageing cutoff"
            }
            _ => return Ok(()),
        };
        Err(InputError::Conflict(format!(
            "{option} {}: {what}, and the scene uses the other ageing form ({}); vary a \
             parameter of its own form",
            self.name(),
            if cutoff {
                "the short-age cutoff, tau"
            } else {
                "the logarithmic form, mu2, mu_vv, mu_vphi"
            }
        )))
    }

    /// The unit in messages: `µm/s`, `kg`, ..., or `dimensionless`.
    pub fn unit_in_words(self) -> &'static str {
        match self.text_unit() {
            "" => "dimensionless",
            u => u,
        }
    }

    /// Whether it needs the scene's stiffness (every control but the stiffness itself).
    pub fn needs_stiffness(self) -> bool {
        !self.is_stiffness()
    }

    /// The dimensionless parameters it moves, for the text (`V` moves `nu`).
    pub fn moves(self, units: &Units) -> Vec<Param> {
        match self {
            Control::Dimensionless(p) => vec![p],
            Control::K => vec![Param::Kappa],
            Control::V => vec![Param::Nu],
            Control::M if units.load_is_weight => vec![Param::Kappa],
            Control::M => vec![Param::M],
            Control::W => vec![Param::Kappa, Param::M],
            Control::Tau => vec![Param::ThetaC],
            Control::Eta => vec![Param::EtaD],
        }
    }

    /// How it moves the dimensionless parameters, as powers: each `(q, e)`
    /// says `q ∝ control^e` with everything else fixed (`W` moves `kappa`
    /// and `m` both as `1/W`; `M` with `W = M g` moves `kappa` as `1/M`).
    /// Every path is a monomial, so a pair of controls is a linear map in
    /// logarithms (`analysis::axes`).
    pub fn powers(self, units: &Units) -> Vec<(Param, f64)> {
        match self.path(units) {
            Path::Stiffness => vec![(Param::Kappa, 1.0)],
            Path::InverseStiffness => vec![(Param::Kappa, -1.0)],
            Path::Index { param, .. } => vec![(param, 1.0)],
            Path::Load => vec![(Param::Kappa, -1.0), (Param::M, -1.0)],
        }
    }

    fn path(self, units: &Units) -> Path {
        let index = |param, scale| Path::Index { param, scale };
        match self {
            Control::K | Control::Dimensionless(Param::Kappa) => Path::Stiffness,
            Control::Dimensionless(p) => index(p, 1.0),
            Control::V => index(Param::Nu, 1.0 / (units.v0 * 1e6)),
            Control::M if units.load_is_weight => Path::InverseStiffness,
            Control::M => index(Param::M, units.v0 * units.v0 / (units.load * units.d0)),
            Control::W => Path::Load,
            Control::Tau => index(Param::ThetaC, units.v0 / units.d0),
            Control::Eta => index(Param::EtaD, units.v0),
        }
    }

    /// Its value in the scene `params` (inertia kept) with `units`, in its unit.
    pub fn value(self, units: &Units, params: &Params) -> f64 {
        match self {
            Control::Dimensionless(p) => params.get(p),
            Control::K => units.stiffness(params.kappa),
            Control::V => units.velocity_um_s(params.nu),
            Control::M => units.mass,
            Control::W => units.load,
            Control::Tau => params.get(Param::ThetaC) * units.d0 / units.v0,
            Control::Eta => params.get(Param::EtaD) / units.v0,
        }
    }

    /// The scene `params` (inertia kept) and `units` with this control at
    /// `value`, everything else as it was: `K`, the spring's stiffness, stays
    /// when `M` or `W` change the load (docs/index.md §2).
    pub fn at(self, units: &Units, params: &Params, value: f64) -> (Params, Units) {
        let (mut p, mut u) = (*params, *units);
        let k = units.stiffness(params.kappa);
        match self {
            Control::Dimensionless(q) => p.set(q, value),
            Control::K => p.kappa = value * u.d0 / u.load,
            Control::V => p.nu = u.nu_of_velocity_um_s(value),
            Control::Tau => p.set(Param::ThetaC, value * u.v0 / u.d0),
            Control::Eta => p.set(Param::EtaD, value * u.v0),
            Control::M if u.load_is_weight => {
                u.mass = value;
                u.load = value * u.g;
                p.kappa = k * u.d0 / u.load;
            }
            Control::M => {
                u.mass = value;
                p.m = value * u.v0 * u.v0 / (u.load * u.d0);
            }
            Control::W => {
                u.load = value;
                u.load_is_weight = false;
                p.kappa = k * u.d0 / value;
                p.m = u.mass * u.v0 * u.v0 / (value * u.d0);
            }
        }
        (p, u)
    }

    /// The range searched when none is given: the scene's velocity range
    /// for `V` and `nu` (`nu_range`, dimensionless), three decades either
    /// side of the scene's value otherwise; `None` for the stiffness paths
    /// (searched from a stable stiffness downward, as `hopf` does) and where
    /// the scene's value is 0.
    pub fn default_range(
        self,
        units: &Units,
        params: &Params,
        nu_range: (f64, f64),
    ) -> Option<(f64, f64)> {
        match self {
            Control::V => Some((
                units.velocity_um_s(nu_range.0),
                units.velocity_um_s(nu_range.1),
            )),
            Control::Dimensionless(Param::Nu) => Some(nu_range),
            _ => {
                let v = self.value(units, params);
                (v > 0.0).then_some((1e-3 * v, 1e3 * v))
            }
        }
    }

    /// The parameters at the end of `range` (its unit) where the inertia
    /// ratio `m nu^2 / mu_v` (C11) is largest: where the model is judged
    /// (the scene's own without a range).
    pub fn inertia_judged_at(
        self,
        units: &Units,
        params: &Params,
        range: Option<(f64, f64)>,
    ) -> Params {
        let Some((lo, hi)) = range else {
            return *params;
        };
        let (a, b) = (self.at(units, params, lo).0, self.at(units, params, hi).0);
        if b.inertia_ratio() >= a.inertia_ratio() {
            b
        } else {
            a
        }
    }

    /// The dimensionless parameter a steady branch in this control
    /// continues (`kappa` for `M` when `W = M g`, where `kappa = K D0/(M g)`);
    /// `W` moves two at once and is refused, naming what is supported.
    pub fn continued(self, units: &Units) -> Result<Param, InputError> {
        match self.path(units) {
            Path::Stiffness | Path::InverseStiffness => Ok(Param::Kappa),
            Path::Index { param, .. } => Ok(param),
            Path::Load => Err(InputError::Conflict(
                "--param W moves kappa = K D0/W and m = M V0^2/(W D0) together, and a branch \
                 continues one parameter: use hopf --param W for the onset in W, or branch \
                 --param K, M, kappa or m"
                    .to_string(),
            )),
        }
    }

    /// The continued dimensionless parameter ([`continued`](Self::continued))
    /// at this control's `value` (its unit), the scene's `params` otherwise.
    pub fn to_dimensionless(self, units: &Units, params: &Params, value: f64) -> f64 {
        let (p, u) = self.at(units, params, value);
        match self.continued(&u) {
            Ok(q) => p.get(q),
            Err(_) => f64::NAN,
        }
    }

    /// This control's value (its unit) where the continued dimensionless
    /// parameter is `x`, the inverse of [`to_dimensionless`](Self::to_dimensionless).
    pub fn from_dimensionless(self, units: &Units, params: &Params, x: f64) -> f64 {
        match self.path(units) {
            Path::Stiffness => match self {
                Control::K => x * units.load / units.d0,
                _ => x,
            },
            // kappa = K D0 / (M g)
            Path::InverseStiffness => units.stiffness(params.kappa) * units.d0 / (units.g * x),
            Path::Index { scale, .. } => x / scale,
            Path::Load => f64::NAN,
        }
    }

    /// The range of a steady branch in this control (`branch --param`), in
    /// the dimensionless parameter it moves ([`continued`](Self::continued)):
    /// `from`, `to` (in its unit) or their defaults: for the stiffness
    /// (`K`, `kappa`, `M` when `W = M g`) none (a stable stiffness and 1e-3
    /// of it, found by the caller); for `V` and `nu` the scene's velocity
    /// range `nu_range`; otherwise the scene's value and 1e3 times it.
    pub fn branch_range(
        self,
        units: &Units,
        params: &Params,
        nu_range: (f64, f64),
        (from, to): (Option<f64>, Option<f64>),
    ) -> Result<(Option<f64>, Option<f64>), InputError> {
        for (name, given) in [("--from", from), ("--to", to)] {
            if let Some(g) = given.filter(|g| !(g.is_finite() && *g > 0.0)) {
                return Err(InputError::out_of_range(
                    name,
                    g,
                    &format!("a finite value > 0 ({})", self.unit_in_words()),
                ));
            }
        }
        let dimensionless = |v: f64| self.to_dimensionless(units, params, v);
        let (lo, hi) = match self {
            Control::V | Control::Dimensionless(Param::Nu) => (
                from.map_or(nu_range.0, dimensionless),
                to.map_or(nu_range.1, dimensionless),
            ),
            _ if !self.searches_range(units) => {
                return Ok((from.map(dimensionless), to.map(dimensionless)))
            }
            _ => {
                let start = from.unwrap_or_else(|| self.value(units, params));
                if start.is_nan() || start <= 0.0 {
                    return Err(InputError::Conflict(format!(
                        "the scene's {} is 0, so the branch has no default start: give --from \
                         (in {})",
                        self.name(),
                        self.unit_in_words()
                    )));
                }
                (
                    dimensionless(start),
                    dimensionless(to.unwrap_or(1e3 * start)),
                )
            }
        };
        Ok((Some(lo), Some(hi)))
    }

    /// Whether the onset is searched over a range of this control (every
    /// path but the stiffness ones, which search from a stable stiffness down).
    pub fn searches_range(self, units: &Units) -> bool {
        !matches!(self.path(units), Path::Stiffness | Path::InverseStiffness)
    }
}

/// The stick-slip onset in a control parameter.
#[derive(Clone, Debug)]
pub struct OnsetIn {
    /// The control.
    pub control: Control,
    /// Its critical value, in its unit.
    pub value: f64,
    /// The scene's parameters there (inertia kept).
    pub params: Params,
    /// The scene's units there (`M`, `W` follow the control).
    pub units: Units,
    /// The Hopf point there, located as `hopf` locates it (in `kappa`, at
    /// `kappa = kappa_c`): the same normal form and onset type.
    pub hopf: HopfPoint,
    /// The range searched, in the control's unit (`None`: the stiffness,
    /// from a stable one downward).
    pub range: Option<(f64, f64)>,
    /// How it was located, in words.
    pub method: String,
}

/// Relative agreement required between the onset located along the
/// control and the Hopf point in `kappa` recomputed there (two methods).
pub const AGREEMENT: f64 = 1e-8;

/// Locates the stick-slip onset in `control` with everything else at the
/// scene's values (`params` with inertia kept, `units`), in the model
/// `kind`, searching `range` (in the control's unit; ignored by the
/// stiffness paths).
///
/// One index (`V`, `nu`, `m`, `M` under a given `W`, `A`, `B`, `mu2`,
/// `mu_vv`, `mu_vphi`, `theta_c`, `tau`): steady sliding is continued in that parameter from
/// the range's low end to its high end at the scene's `kappa`, and the
/// first Hopf point is located exactly by the engine (minimally augmented
/// Hopf system, Newton). The stiffness (`K`, `kappa`, `M` with `W = M g`):
/// `hopf`'s own location, `M_c = K D0 / (g kappa_c)`. The load `W`
/// (moving `kappa` and `m` together, both `∝ 1/W`): the root of `kappa(W)
/// - kappa_c(W)` in `1/W` by the Illinois method, `kappa_c` located at
/// every trial (C11 makes the function affine in `1/W`, so it converges in a
/// few trials). In every case the Hopf point at the critical value is then
/// located in `kappa` as `hopf` does ([`find_hopf`]) for its normal form,
/// and must agree with the scene's `kappa` to [`AGREEMENT`].
pub fn onset_in(
    kind: ModelKind,
    params: &Params,
    units: &Units,
    control: Control,
    range: Option<(f64, f64)>,
) -> Result<OnsetIn, Error> {
    let path = control.path(units);
    if control.needs_stiffness() && params.kappa <= 0.0 {
        return Err(InputError::Conflict(format!(
            "the onset in {} needs the spring: kappa = 0 here (the scene gives no K); give \
             --set K=... (N/m) or --set kappa=...",
            control.name()
        ))
        .into());
    }
    if control.moves_inertia(units) && kind == ModelKind::QuasiStatic {
        return Err(InputError::Conflict(format!(
            "the onset in {} moves the inertia m, which the quasi-static model drops; \
             leave out --model quasi-static",
            control.name()
        ))
        .into());
    }
    control.check_form(params, "--param")?;
    // None in the range searched: none at any value where Appendix C
    // excludes one (and agrees with what the search saw), else another
    // range may hold it.
    let no_onset = |range: (f64, f64), unstable: bool, why: String| -> Error {
        let (param, unit) = (
            control.name().to_string(),
            control.unit_in_words().to_string(),
        );
        match onset_excluded(params, units, control) {
            Some(Excluded { unstable: u, why }) if u == unstable => {
                NumericalError::NoOnsetAtAnyValue {
                    param,
                    unit,
                    lo: range.0,
                    hi: range.1,
                    why,
                }
            }
            _ => NumericalError::NoOnsetInRange {
                param,
                unit,
                lo: range.0,
                hi: range.1,
                why,
                remedy: "--from and --to",
            },
        }
        .into()
    };
    let (value, method) = match path {
        Path::Stiffness | Path::InverseStiffness => {
            let h = match find_hopf(kind, &params_for(kind, params))? {
                HopfOutcome::Found(h) => h,
                HopfOutcome::StableForAllStiffness { kappa_min } => {
                    return Err(NumericalError::Analysis(format!(
                        "no stick-slip onset in {}: steady sliding is linearly stable at every \
                         stiffness down to kappa = {kappa_min:.3e} (`stickslip hopf` says why)",
                        control.name()
                    ))
                    .into())
                }
            };
            let v = match path {
                Path::Stiffness => control.value(units, &{
                    let mut p = *params;
                    p.kappa = h.kappa_c;
                    p
                }),
                // M_c = K D0 / (g kappa_c), W = M g.
                _ => units.stiffness(params.kappa) * units.d0 / (units.g * h.kappa_c),
            };
            (
                v,
                "the Hopf point in kappa (as hopf locates it)".to_string(),
            )
        }
        Path::Index { param, scale } => {
            let r = checked_range(control, range)?;
            if param == Param::Nu {
                let field = format!("the range searched in {}, in nu", control.name());
                params.check_velocity_range((scale * r.0, scale * r.1), &field)?;
            }
            match along_index(kind, params, param, (scale * r.0, scale * r.1))? {
                Ok(x) => (
                    x / scale,
                    format!(
                        "continuation of steady sliding in {} with Hopf location",
                        param.name()
                    ),
                ),
                Err(unstable) => {
                    return Err(no_onset(
                        r,
                        unstable,
                        format!(
                            "steady sliding is {} along the whole range at kappa = {:.6e} \
                             (K = {:.6e} N/m)",
                            if unstable {
                                "unstable (stick-slip)"
                            } else {
                                "linearly stable"
                            },
                            params.kappa,
                            units.stiffness(params.kappa)
                        ),
                    ))
                }
            }
        }
        Path::Load => {
            let r = checked_range(control, range)?;
            match along_load(kind, params, units, r)? {
                Ok(w) => (
                    w,
                    "root of kappa - kappa_c in 1/W (Illinois), kappa_c located at each trial"
                        .to_string(),
                ),
                Err(unstable) => {
                    return Err(no_onset(
                        r,
                        unstable,
                        format!(
                            "kappa - kappa_c keeps its sign at both ends (steady sliding {} at \
                             both)",
                            if unstable { "unstable" } else { "stable" }
                        ),
                    ))
                }
            }
        }
    };
    let (at, at_units) = control.at(units, params, value);
    let h = match find_hopf(kind, &params_for(kind, &at))? {
        HopfOutcome::Found(h) => h,
        HopfOutcome::StableForAllStiffness { .. } => {
            return Err(NumericalError::Analysis(format!(
                "the onset located at {} = {value:.10e} {} has no Hopf point in kappa there; \
                 the two locations disagree",
                control.name(),
                control.unit_in_words()
            ))
            .into())
        }
    };
    let disagreement = (h.kappa_c / at.kappa - 1.0).abs();
    if disagreement.is_nan() || disagreement > AGREEMENT {
        return Err(NumericalError::Analysis(format!(
            "the onset located at {} = {value:.10e} {} has kappa_c = {:.10e} there, {disagreement:.1e} \
             relative from the scene's kappa = {:.10e}: the two locations disagree",
            control.name(),
            control.unit_in_words(),
            h.kappa_c,
            at.kappa
        ))
        .into());
    }
    Ok(OnsetIn {
        control,
        value,
        params: at,
        units: at_units,
        hopf: h,
        range: matches!(path, Path::Index { .. } | Path::Load)
            .then(|| checked_range(control, range).ok())
            .flatten(),
        method,
    })
}

/// Why no value of a control gives an onset ([`onset_excluded`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Excluded {
    /// Steady sliding is unstable (stick-slip) at every value; else stable
    /// at every value.
    pub unstable: bool,
    /// In words, with the numbers.
    pub why: String,
}

/// Where Appendix C decides in closed form that no value of `control`
/// gives an onset, everything else at the scene's parameters `p` and
/// `units` (its inertia kept: a model chosen over a range may drop it, the
/// block beyond that range has it); `None` where it does not decide. With
/// `K` the spring's stiffness, fixed by each control here, eq. C11 in
/// physical units reads
///
/// ```text
/// K_c = (mu_phi - mu_v) (W + M V^2 / (mu_v D0)) / D0        (kappa_c W / D0)
/// ```
///
/// and steady sliding is stable for `K > K_c` (docs/model.md). Along
///
/// - `M` under a given `W` (and `m`), `mu_phi - mu_v` does not move and
///   `K_c` grows with `M` from `(mu_phi - mu_v) W / D0` at `M = 0` (C12);
/// - `W`, likewise with `W`, from `(mu_phi - mu_v) M V^2 / (mu_v D0^2)` as
///   `W -> 0`;
/// - `V` (and `nu`) under the ln² form with `mu2 = 0`, `mu_phi = B` does not
///   move, and `K_c` grows with `V` from `(B - A) W / D0` as `V -> 0`, or
///   stays there for a block without mass; under the cutoff with `B <= A`,
///   `mu_phi = B / (1 + V tau / D0) < A` at every `V`.
///
/// So where `mu_phi <= mu_v` steady sliding is stable at every value, and
/// where `K` is at or below the least `K_c` (below it if `K_c` stays) it is
/// unstable at every value (stable if `K_c` stays below `K`). Other
/// controls, and `V` under the ln² form with `mu2 != 0` (whose `mu_phi`
/// sweeps every value, so that an onset exists at some `V`), are not
/// decided here.
pub fn onset_excluded(p: &Params, units: &Units, control: Control) -> Option<Excluded> {
    let name = control.name();
    let k = units.stiffness(p.kappa);
    // C12, the least K_c along M (in the unit of kappa).
    let weakening = crate::appendix_c::critical_stiffness_quasi_static(p);
    let law = "C11: K_c = (mu_phi - mu_v)(W + M V^2/(mu_v D0))/D0";
    let stable = |why: String| Excluded {
        unstable: false,
        why: format!("steady sliding is linearly stable at every {name}: {why}"),
    };
    // The least K_c along the control, where it is, and whether K_c grows
    // from it (else it stays there).
    let (least, at, grows) = match control.path(units) {
        Path::Index {
            param: Param::Nu, ..
        } if p.theta_c.is_some() && p.b <= p.a => {
            return Some(stable(format!(
                "mu_phi = B/(1 + V tau/D0) < B = {:.6e} <= A = mu_v = {:.6e} at every V (the \
                 cutoff form), so K_c < 0 < K = {k:.6e} N/m ({law})",
                p.b, p.a
            )))
        }
        Path::Index {
            param: Param::Nu, ..
        } if p.theta_c.is_none() && p.mu2 == 0.0 => (
            units.stiffness(weakening),
            format!("as {name} -> 0 (mu_phi = B does not move with V: mu2 = 0)"),
            p.m > 0.0,
        ),
        Path::Index {
            param: Param::M, ..
        } => (
            units.stiffness(weakening),
            format!("at {name} = 0 (C12)"),
            true,
        ),
        Path::Load => (
            units.stiffness(weakening * p.inertia_ratio()),
            "as W -> 0".to_string(),
            true,
        ),
        _ => return None,
    };
    let slopes = format!(
        "mu_phi - mu_v = {weakening:.6e} at V = {:.6e} µm/s",
        units.velocity_um_s(p.nu)
    );
    if weakening <= 0.0 {
        return Some(stable(format!(
            "steady friction is velocity strengthening ({slopes} <= 0), so K_c <= 0 < K = \
             {k:.6e} N/m ({law})"
        )));
    }
    let unstable = |why: String| Excluded {
        unstable: true,
        why: format!("steady sliding is unstable (stick-slip) at every {name}: {why}"),
    };
    match grows {
        true if k <= least => Some(unstable(format!(
            "K = {k:.6e} N/m is at or below K_c = {least:.6e} N/m {at}, and K_c grows with \
             {name} ({law}; {slopes})"
        ))),
        false if k < least => Some(unstable(format!(
            "K = {k:.6e} N/m is below K_c = {least:.6e} N/m, the same at every {name} \
             ({law}, a block without mass; {slopes})"
        ))),
        false if k > least => Some(stable(format!(
            "K = {k:.6e} N/m is above K_c = {least:.6e} N/m, the same at every {name} ({law}, \
             a block without mass; {slopes})"
        ))),
        _ => None,
    }
}

/// The range, present, finite, positive and ordered.
fn checked_range(control: Control, range: Option<(f64, f64)>) -> Result<(f64, f64), InputError> {
    let Some((lo, hi)) = range else {
        return Err(InputError::Conflict(format!(
            "the scene's {} is 0, so the range to search has no default: give --from and --to \
             (in {})",
            control.name(),
            control.unit_in_words()
        )));
    };
    for (field, v) in [("--from", lo), ("--to", hi)] {
        if !(v.is_finite() && v > 0.0) {
            return Err(InputError::out_of_range(
                field,
                v,
                &format!("> 0 ({})", control.unit_in_words()),
            ));
        }
    }
    if lo == hi {
        return Err(InputError::Conflict(format!(
            "--from and --to are equal ({lo}); give a range"
        )));
    }
    Ok((lo.min(hi), lo.max(hi)))
}

/// Continues steady sliding in `param` over `(lo, hi)` (dimensionless) at
/// the scene's other parameters; the value of the first located Hopf point,
/// or (none) whether steady sliding was unstable at the low end.
fn along_index(
    kind: ModelKind,
    params: &Params,
    param: Param,
    (lo, hi): (f64, f64),
) -> Result<Result<f64, bool>, Error> {
    let model_params = params_for(kind, params);
    let block = DrivenBlock::new(kind, &model_params);
    // The ageing form is the scene's (checked by `onset_in`).
    let mut p = model_params;
    p.set(param, lo);
    let span = hi - lo;
    let settings = ContinuationSettings {
        step: StepControl {
            ds: 1e-3 * span,
            ds_max: 0.02 * span,
            ds_min: 1e-13 * span,
            ..ContinuationSettings::default().step
        },
        p_min: lo,
        p_max: hi,
        direction: Direction::Increasing,
        max_steps: 20_000,
        ..Default::default()
    };
    let x0 = steady_state(kind, &p);
    let branch = Branch::new(&block, &x0, &p.to_vec(), param as usize, settings)
        .map_err(NumericalError::from)?;
    let mut unstable_at_start = None;
    for point in branch {
        let point = point.map_err(NumericalError::from)?;
        unstable_at_start.get_or_insert(point.n_unstable > 0);
        let hopf = point
            .events
            .iter()
            .find(|e| matches!(e.kind, EventKind::Hopf { .. }));
        if let Some(e) = hopf {
            return Ok(Ok(e.point.param()));
        }
    }
    Ok(Err(unstable_at_start.unwrap_or(false)))
}

/// The load `W` in `(lo, hi)` [N] where `kappa = kappa_c`, both moving with
/// `1/W` (`kappa = K D0/W`, `m = M V0^2/(W D0)`): the Illinois method on
/// `g(u) = kappa(u) - kappa_c(u)`, `u = 1/W`, with `kappa_c` located by
/// [`find_hopf`] at each trial (`0` where steady sliding is stable at every
/// stiffness). When `g` has one sign at both ends: whether steady sliding
/// is unstable there (`g < 0`).
fn along_load(
    kind: ModelKind,
    params: &Params,
    units: &Units,
    (lo, hi): (f64, f64),
) -> Result<Result<f64, bool>, Error> {
    let g = |u: f64| -> Result<f64, Error> {
        let (p, _) = Control::W.at(units, params, 1.0 / u);
        let kappa_c = match find_hopf(kind, &params_for(kind, &p))? {
            HopfOutcome::Found(h) => h.kappa_c,
            HopfOutcome::StableForAllStiffness { .. } => 0.0,
        };
        Ok((p.kappa - kappa_c) / p.kappa)
    };
    let (mut a, mut b) = (1.0 / hi, 1.0 / lo);
    let (mut ga, mut gb) = (g(a)?, g(b)?);
    if ga == 0.0 {
        return Ok(Ok(1.0 / a));
    }
    if gb == 0.0 {
        return Ok(Ok(1.0 / b));
    }
    if ga.signum() == gb.signum() {
        return Ok(Err(ga < 0.0));
    }
    let mut side = 0;
    for _ in 0..200 {
        let c = (a * gb - b * ga) / (gb - ga);
        let gc = g(c)?;
        if gc == 0.0 || (b - a).abs() <= 4.0 * f64::EPSILON * c.abs() {
            return Ok(Ok(1.0 / c));
        }
        if gc.signum() == gb.signum() {
            b = c;
            gb = gc;
            if side == 1 {
                ga /= 2.0;
            }
            side = 1;
        } else {
            a = c;
            ga = gc;
            if side == -1 {
                gb /= 2.0;
            }
            side = -1;
        }
        if gc.abs() <= 4.0 * f64::EPSILON {
            return Ok(Ok(1.0 / c));
        }
    }
    Ok(Ok(2.0 / (a + b)))
}

/// A range `(lo, hi)` in which an onset is searched, checked: finite and
/// running upward. `fields` names the options that gave it (`--from/--to`,
/// `--search`), so that a range written downward is refused with the range
/// to give instead, not silently turned around.
pub fn upward_range((lo, hi): (f64, f64), fields: &str) -> Result<(f64, f64), InputError> {
    if !(lo.is_finite() && hi.is_finite()) {
        return Err(InputError::Malformed {
            field: fields.into(),
            value: format!("{lo}:{hi}"),
            expected: "finite numbers".into(),
        });
    }
    if lo == hi {
        return Err(InputError::Conflict(format!(
            "{fields} gives the range {lo:e} to {hi:e}, which is empty: the onset is searched \
             between two different values"
        )));
    }
    if lo > hi {
        return Err(InputError::Conflict(format!(
            "{fields} gives the range {lo:e} to {hi:e}, which does not run upward: the onset is \
             searched from the low end to the high end; give {hi:e} to {lo:e}"
        )));
    }
    Ok((lo, hi))
}

/// The model for the onset along `control` over `range` (its unit): the
/// automatic choice judged at the end of the range where the inertia ratio
/// `m nu^2 / mu_v` (C11) is largest, and the inertial model wherever the
/// control moves `m` (the quasi-static model would not see it), unless
/// `forced`.
pub fn choose_along(
    control: Control,
    units: &Units,
    params: &Params,
    range: Option<(f64, f64)>,
    forced: Option<ModelKind>,
    threshold: f64,
) -> crate::analysis::model_choice::ModelChoice {
    use crate::analysis::model_choice::choose_model;
    let judged = control.inertia_judged_at(units, params, range);
    let mut choice = choose_model(&judged, forced, threshold);
    if forced.is_none() && choice.kind == ModelKind::QuasiStatic && control.moves_inertia(units) {
        choice.kind = ModelKind::Inertial;
        choice.reason = format!(
            "inertial: the control {} moves the inertia m, which the quasi-static model drops \
             (inertia ratio m nu^2/mu_v = {:.3e} at the scene's values)",
            control.name(),
            params.inertia_ratio()
        );
    }
    choice
}

/// A branch of stick-slip cycles in a control parameter (`cycles --param`).
#[derive(Clone, Debug)]
pub struct CyclesInRequest {
    /// The control.
    pub control: Control,
    /// Where the branch ends, in the control's unit.
    pub to: f64,
    /// Where the onset is searched ([`onset_in`]), in the control's unit
    /// (default: [`Control::default_range`] widened to include `to`).
    pub search: Option<(f64, f64)>,
    /// The scene's velocity range (dimensionless), for the default search in `V` and `nu`.
    pub nu_range: (f64, f64),
    /// Values of the control at which cycles are located exactly.
    pub at: Vec<f64>,
    /// Start from a simulated orbit at the scene's value instead of the Hopf point.
    pub from_simulation: bool,
    /// Start from this orbit (in the variables of the block given with
    /// it), written by an earlier run: a restart, before `from_simulation`;
    /// with the parameter it is a fold of cycles in, if it is one.
    pub stored: Option<(
        crate::log_model::LogBlock,
        continuation::periodic::Cycle,
        Option<Param>,
    )>,
    /// Step limit, mesh and collocation as for a stiffness branch (its
    /// bounds and requested values are set here, in the continued parameter).
    pub cycles: crate::analysis::cycles::CycleRequest,
}

/// Where a branch in a control parameter started.
#[derive(Clone, Debug)]
pub enum CyclesStart {
    /// The Hopf point in the control.
    Hopf(Box<OnsetIn>),
    /// A simulated orbit at the scene's value of the control.
    Simulation,
    /// A cycle written by an earlier run (a restart).
    Stored,
}

/// A branch of cycles in a control parameter, traced.
#[derive(Debug)]
pub struct CyclesIn {
    /// Where it started.
    pub start: CyclesStart,
    /// The dimensionless parameter continued (`nu` for `V`).
    pub param: Param,
    /// How each leg ended (one from a Hopf point, two from an orbit).
    pub legs: Vec<(
        crate::analysis::cycles::Leg,
        Result<continuation::Stop, Error>,
    )>,
}

/// Traces the cycles in `req.control` from its Hopf point (located by
/// [`onset_in`], normal form as `hopf`'s) or from a simulated orbit at the
/// scene's value, continued in the dimensionless parameter the control
/// moves ([`Control::continued`]) up to `req.to`; from the Hopf point, on
/// the other side to ten times the start (a subcritical branch goes that
/// way first, to its fold of cycles); from an orbit, between the scene's
/// value and `req.to`. Each cycle is handed to `sink` as it is computed; folds,
/// period doublings and the requested values as on a stiffness branch.
pub fn cycles_in(
    kind: ModelKind,
    params: &Params,
    units: &Units,
    req: &CyclesInRequest,
    watch: &crate::analysis::orbit_inertia::InertiaWatch,
    mut sink: impl FnMut(&CycleRecord) -> Result<(), Error>,
) -> Result<CyclesIn, Error> {
    use crate::analysis::cycles::{trace_cycles_from_in, trace_cycles_from_orbit_in, Leg};
    let control = req.control;
    let param = control.continued(units)?;
    control.check_form(params, "--param")?;
    if !(req.to.is_finite() && req.to > 0.0) {
        return Err(InputError::out_of_range(
            "--to",
            req.to,
            &format!("> 0 ({})", control.unit_in_words()),
        )
        .into());
    }
    if let Some(v) = req.at.iter().find(|v| !(v.is_finite() && **v > 0.0)) {
        return Err(InputError::out_of_range(
            "--at",
            *v,
            &format!("> 0 ({})", control.unit_in_words()),
        )
        .into());
    }
    if control.needs_stiffness() && params.kappa <= 0.0 {
        return Err(InputError::Conflict(format!(
            "cycles in {} need the spring: kappa = 0 here (the scene gives no K); give --set K=... (N/m)",
            control.name()
        ))
        .into());
    }
    let to = control.to_dimensionless(units, params, req.to);
    let bounds = |start: f64| {
        if to < start {
            (to, 10.0 * start)
        } else {
            (0.1 * start, to)
        }
    };
    let mut cycles = req.cycles.clone();
    cycles.at_kappa = req
        .at
        .iter()
        .map(|&v| control.to_dimensionless(units, params, v))
        .collect();
    if let Some((log, cycle, fold_in)) = &req.stored {
        // From the cycle's value to --to, as from a simulated orbit below.
        let start = cycle.p[param as usize];
        let (lo, hi) = (start.min(to) * (1.0 - 1e-3), start.max(to) * (1.0 + 1e-3));
        cycles.kappa_min = lo;
        cycles.kappa_max = hi;
        cycles.cover_requested();
        let through = crate::analysis::cycles::Through::Stored {
            log: *log,
            cycle,
            fold: *fold_in == Some(param),
        };
        let legs = crate::analysis::cycles::trace_cycles_through(
            &through, param, &cycles, watch, &mut sink,
        )?;
        return Ok(CyclesIn {
            start: CyclesStart::Stored,
            param,
            legs: legs.into(),
        });
    }
    if req.from_simulation {
        // From the scene's value to --to; the other leg ends after a step
        // (a margin of 1e-3: a start on the bound ends both legs at once).
        let start = params.get(param);
        let (lo, hi) = (start.min(to) * (1.0 - 1e-3), start.max(to) * (1.0 + 1e-3));
        cycles.kappa_min = lo;
        cycles.kappa_max = hi;
        cycles.cover_requested();
        let model = params_for(kind, params);
        let orbit = crate::analysis::orbit_start::simulated_start(kind, params, None, watch)
            .map_err(|e| NumericalError::Analysis(e.to_string()))?;
        if orbit.params.kappa != model.kappa {
            return Err(NumericalError::Analysis(format!(
                "no stick-slip cycle settled at the scene's stiffness kappa = {:.6e} (a simulation \
                 from a stuck state); start from the Hopf point (without --from-simulation)",
                model.kappa
            ))
            .into());
        }
        let legs = trace_cycles_from_orbit_in(
            orbit.kind,
            &orbit.params,
            &orbit.orbit,
            param,
            &cycles,
            watch,
            &mut sink,
        )?;
        return Ok(CyclesIn {
            start: CyclesStart::Simulation,
            param,
            legs: legs.into(),
        });
    }
    let search = req.search.or_else(|| {
        let (lo, hi) = control.default_range(units, params, req.nu_range)?;
        Some((lo.min(req.to), hi.max(req.to)))
    });
    // The range of a cycle branch's onset is set by --search.
    let onset = onset_in(kind, params, units, control, search).map_err(|e| match e {
        Error::Numerical(NumericalError::NoOnsetInRange {
            param,
            unit,
            lo,
            hi,
            why,
            ..
        }) => Error::Numerical(NumericalError::NoOnsetInRange {
            param,
            unit,
            lo,
            hi,
            why,
            remedy: "--search LO:HI",
        }),
        e => e,
    })?;
    let (lo, hi) = bounds(onset.params.get(param));
    cycles.kappa_min = lo;
    cycles.kappa_max = hi;
    cycles.cover_requested();
    let model = params_for(kind, &onset.params);
    let end = trace_cycles_from_in(kind, &model, &onset.hopf, param, &cycles, watch, &mut sink);
    Ok(CyclesIn {
        start: CyclesStart::Hopf(Box::new(onset)),
        param,
        legs: vec![(Leg::FromHopf, end)],
    })
}
