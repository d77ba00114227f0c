//! Dimensionless parameters of docs/model.md and their validation.
//!
//! | name | definition | meaning |
//! |---|---|---|
//! | `kappa` | `K D0 / W` | spring stiffness |
//! | `nu` | `V / V0` | driving velocity |
//! | `m` | `M V0^2 / (W D0)` | inertia |
//! | `A`, `B`, `mu0`, `mu2` | | friction law coefficients |
//! | `mu_vv`, `mu_vphi` | | coefficients of `(ln v)^2` and `(ln theta)(ln v)` (seed §II.D.2) |
//! | `theta_c` | `tau V0 / D0` | ageing cutoff (selects the cutoff form) |
//! | `eta_d` | `eta V0` | radiation damping (`eta` in s/m, `V0` in m/s): the force `W eta x'` over `W` is `eta_d v` |

use crate::error::InputError;
use crate::friction::{Ageing, FrictionLaw};
use continuation::Scalar;

/// Index of each parameter in the vector handed to the continuation engine.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Param {
    Kappa = 0,
    Nu = 1,
    M = 2,
    A = 3,
    B = 4,
    Mu0 = 5,
    Mu2 = 6,
    ThetaC = 7,
    MuVv = 8,
    MuVphi = 9,
    EtaD = 10,
}

/// Magnitudes a nonzero dimensionless parameter may have
/// ([`Params::validate`]).
pub const MAGNITUDE_RANGE: (f64, f64) = (1e-100, 1e100);

/// Number of entries in the engine's parameter vector.
pub const N_PARAMS: usize = 11;

impl Param {
    /// Every parameter, in vector order.
    pub const ALL: [Param; N_PARAMS] = [
        Param::Kappa,
        Param::Nu,
        Param::M,
        Param::A,
        Param::B,
        Param::Mu0,
        Param::Mu2,
        Param::ThetaC,
        Param::MuVv,
        Param::MuVphi,
        Param::EtaD,
    ];

    /// The parameters of the logarithmic ageing form, which the cutoff
    /// form excludes: `mu2`, `mu_vv`, `mu_vphi`.
    pub const LOG_FORM: [Param; 3] = [Param::Mu2, Param::MuVv, Param::MuVphi];

    /// The name used on the command line (`--set NAME=VALUE`) and in JSON.
    pub fn name(self) -> &'static str {
        match self {
            Param::Kappa => "kappa",
            Param::Nu => "nu",
            Param::M => "m",
            Param::A => "A",
            Param::B => "B",
            Param::Mu0 => "mu0",
            Param::Mu2 => "mu2",
            Param::ThetaC => "theta_c",
            Param::MuVv => "mu_vv",
            Param::MuVphi => "mu_vphi",
            Param::EtaD => "eta_d",
        }
    }

    /// The ageing form this parameter belongs to: `Some(true)` the cutoff
    /// (`theta_c`), `Some(false)` the logarithmic form ([`Param::LOG_FORM`]),
    /// `None` both.
    pub fn cutoff_form(self) -> Option<bool> {
        match self {
            Param::ThetaC => Some(true),
            p if Param::LOG_FORM.contains(&p) => Some(false),
            _ => None,
        }
    }

    /// Parses a parameter name; the error suggests the closest valid name.
    pub fn parse(name: &str) -> Result<Param, InputError> {
        Param::ALL
            .into_iter()
            .find(|p| p.name() == name)
            .ok_or_else(|| InputError::UnknownName {
                what: "parameter",
                name: name.to_string(),
                suggestion: crate::error::closest(name, Param::ALL.iter().map(|p| p.name())),
                allowed: Param::ALL
                    .iter()
                    .map(|p| p.name())
                    .collect::<Vec<_>>()
                    .join(", "),
            })
    }
}

/// The dimensionless parameter set of docs/model.md.
///
/// `theta_c = Some(..)` selects the cutoff ageing form `B ln(1 + theta/theta_c)`;
/// `None` selects `B ln theta + mu2 (ln theta)^2 + mu_vv (ln v)^2 +
/// mu_vphi (ln theta)(ln v)` (the last three 0 with the cutoff). `state_law`
/// is the evolution law of `theta`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Params {
    pub kappa: f64,
    pub nu: f64,
    pub m: f64,
    pub a: f64,
    pub b: f64,
    pub mu0: f64,
    pub mu2: f64,
    pub theta_c: Option<f64>,
    pub state_law: StateLaw,
    /// Coefficient of `(ln v)^2` (seed §II.D.2).
    pub mu_vv: f64,
    /// Coefficient of `(ln theta)(ln v)` (seed §II.D.2).
    pub mu_vphi: f64,
    /// Radiation damping `eta_d = eta V0` (docs/model.md, "Radiation
    /// damping"): the force balance `m v' = s - mu(v, theta) - eta_d v`.
    pub eta_d: f64,
}

/// How the state variable `theta` evolves (docs/model.md, "State laws"),
/// in units of `D0 / V0`:
///
/// - the ageing law `theta' = 1 - v theta` (seed eq. RR2; Dieterich): `theta`
///   is the contacts' geometric age, which grows at rest;
/// - Ruina's slip law `theta' = -v theta ln(v theta)` (Ruina 1983): the state
///   evolves only with slip, not at rest.
///
/// Both have the steady state `v theta = 1` and the same linearization there
/// (the partial derivatives in `v` and `theta` are `-theta` and `-v` at
/// `v theta = 1` for both), hence the same `kappa_c` and `Omega_c`
/// (Appendix C); their nonlinear terms, hence `l1`, `l2` and the cycles,
/// differ.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum StateLaw {
    #[default]
    Ageing,
    Slip,
}

impl StateLaw {
    /// Both laws, in the order of their scene names.
    pub const ALL: [StateLaw; 2] = [StateLaw::Ageing, StateLaw::Slip];

    /// The scene key's value: `ageing` or `slip`.
    pub fn name(self) -> &'static str {
        match self {
            StateLaw::Ageing => "ageing",
            StateLaw::Slip => "slip",
        }
    }

    /// The law named `name` ([`StateLaw::name`]), if any.
    pub fn parse(name: &str) -> Option<StateLaw> {
        StateLaw::ALL.into_iter().find(|law| law.name() == name)
    }

    /// `d theta / dt` at `(v, theta)`.
    pub fn rate<D: Scalar>(self, v: D, theta: D) -> D {
        match self {
            StateLaw::Ageing => -(v * theta) + 1.0,
            StateLaw::Slip => {
                let vt = v * theta;
                -(vt * vt.ln())
            }
        }
    }

    /// `d phi / dt` for `phi = ln theta`, from the origin `(w_o, phi_o)` of
    /// the log variables (`w = ln v`) and the state's offsets `(x_w, x_phi)`
    /// from it, `v = e^w_o + dv` (`(ew_o, ephi_o) = (e^w_o, e^-phi_o)`,
    /// computed once per block): without cancelling large terms at a
    /// steady origin (`e^-phi_o = e^w_o`, `w_o + phi_o = 0`):
    ///
    /// - ageing: `e^-phi - e^w = (e^-phi_o - e^w_o) + e^-phi_o expm1(-x_phi) - dv`;
    /// - slip: `-v ln(v theta) = -(e^w_o + dv) ((w_o + phi_o) + x_w + x_phi)`.
    pub fn log_rate<D: Scalar>(
        self,
        (w_o, phi_o): (f64, f64),
        (ew_o, ephi_o): (f64, f64),
        x_w: D,
        x_phi: D,
        dv: D,
    ) -> D {
        match self {
            StateLaw::Ageing => (-x_phi).exp_m1() * ephi_o - dv + (ephi_o - ew_o),
            StateLaw::Slip => -((dv + ew_o) * (x_w + x_phi + (w_o + phi_o))),
        }
    }
}

impl Params {
    /// Value of one parameter (`theta_c` reads 0 when the cutoff is off).
    pub fn get(&self, p: Param) -> f64 {
        match p {
            Param::Kappa => self.kappa,
            Param::Nu => self.nu,
            Param::M => self.m,
            Param::A => self.a,
            Param::B => self.b,
            Param::Mu0 => self.mu0,
            Param::Mu2 => self.mu2,
            Param::ThetaC => self.theta_c.unwrap_or(0.0),
            Param::MuVv => self.mu_vv,
            Param::MuVphi => self.mu_vphi,
            Param::EtaD => self.eta_d,
        }
    }

    /// Sets one parameter. Setting `theta_c` selects the cutoff form (and
    /// clears `mu2`, `mu_vv`, `mu_vphi`); setting one of these selects the
    /// logarithmic form.
    pub fn set(&mut self, p: Param, value: f64) {
        match p {
            Param::Kappa => self.kappa = value,
            Param::Nu => self.nu = value,
            Param::M => self.m = value,
            Param::A => self.a = value,
            Param::B => self.b = value,
            Param::Mu0 => self.mu0 = value,
            Param::EtaD => self.eta_d = value,
            Param::ThetaC => {
                self.theta_c = Some(value);
                self.mu2 = 0.0;
                self.mu_vv = 0.0;
                self.mu_vphi = 0.0;
            }
            Param::Mu2 | Param::MuVv | Param::MuVphi => {
                self.set_value_keep_form(p, value);
                self.theta_c = None;
            }
        }
    }

    /// Applies `NAME=VALUE` overrides in order. Setting `theta_c` with one
    /// of `mu2`, `mu_vv`, `mu_vphi` is refused: the two ageing forms
    /// exclude each other.
    pub fn apply_overrides(&mut self, overrides: &[String]) -> Result<(), InputError> {
        let mut form_set_by: Option<Param> = None;
        for item in overrides {
            let (name, value) = item.split_once('=').ok_or_else(|| InputError::Malformed {
                field: "--set".into(),
                value: item.clone(),
                expected: "NAME=VALUE, e.g. --set kappa=0.01".into(),
            })?;
            let p = Param::parse(name.trim())?;
            let v: f64 = value.trim().parse().map_err(|_| InputError::Malformed {
                field: format!("--set {}", p.name()),
                value: value.to_string(),
                expected: "a number".into(),
            })?;
            if let Some(form) = p.cutoff_form() {
                if let Some(prev) = form_set_by.filter(|prev| prev.cutoff_form() != Some(form)) {
                    return Err(InputError::Conflict(format!(
                        "--set {} and --set {} select different ageing forms \
                         (the logarithmic form's mu2, mu_vv, mu_vphi vs the short-age cutoff \
                         theta_c); use one",
                        prev.name(),
                        p.name()
                    )));
                }
                form_set_by = Some(p);
            }
            self.set(p, v);
        }
        self.validate()
    }

    /// Checks every parameter: finite, and within its physical range.
    pub fn validate(&self) -> Result<(), InputError> {
        for p in Param::ALL {
            let v = self.get(p);
            if !v.is_finite() {
                return Err(InputError::out_of_range(p.name(), v, "a finite number"));
            }
        }
        let positive = [(Param::A, self.a), (Param::Nu, self.nu)];
        for (p, v) in positive {
            if v <= 0.0 {
                return Err(InputError::out_of_range(p.name(), v, "> 0"));
            }
        }
        for (p, v) in [
            (Param::M, self.m),
            (Param::Kappa, self.kappa),
            (Param::EtaD, self.eta_d),
        ] {
            if v < 0.0 {
                return Err(InputError::out_of_range(p.name(), v, ">= 0"));
            }
        }
        if let Some(tc) = self.theta_c {
            if !(tc > 0.0 && tc.is_finite()) {
                return Err(InputError::out_of_range("theta_c", tc, "> 0"));
            }
        }
        if self.b < 0.0 {
            return Err(InputError::out_of_range(
                "B",
                self.b,
                ">= 0 (ageing strengthens the interface)",
            ));
        }
        // Products such as m nu^2 / A, and the stiffness scale built from
        // them, must stay within the floating-point range.
        let sizes = Param::ALL
            .iter()
            .map(|&p| (p.name(), self.get(p)))
            .chain(self.theta_c.map(|tc| ("theta_c", tc)));
        for (name, v) in sizes {
            if v != 0.0 && !(MAGNITUDE_RANGE.0..=MAGNITUDE_RANGE.1).contains(&v.abs()) {
                return Err(InputError::out_of_range(
                    name,
                    v,
                    "0 or of magnitude 1e-100 to 1e100 (dimensionless: rate-and-state values are of order 1e-3 to 1)",
                ));
            }
        }
        // With mu_vv and mu_vphi the direct effect at steady sliding depends
        // on nu; the law defines the slip velocity (and Appendix C its
        // stability) only where it is positive.
        let mu_v = self.mu_v();
        if mu_v.is_nan() || mu_v <= 0.0 {
            return Err(InputError::out_of_range(
                "mu_v = A + (2 mu_vv - mu_vphi) ln nu",
                mu_v,
                &format!(
                    "> 0: the direct effect d mu/d ln v at steady sliding (A = {:e}, mu_vv = {:e}, \
                     mu_vphi = {:e}, nu = {:e}); friction must rise with the slip velocity there",
                    self.a, self.mu_vv, self.mu_vphi, self.nu
                ),
            ));
        }
        Ok(())
    }

    /// The parameter vector in [`Param`] order, as the engine takes it.
    pub fn to_vec(&self) -> Vec<f64> {
        Param::ALL.iter().map(|&p| self.get(p)).collect()
    }

    /// Reads a parameter vector back (the ageing form is kept from `self`).
    pub fn with_vec(&self, p: &[f64]) -> Params {
        let mut out = *self;
        for q in Param::ALL {
            let v = p[q as usize];
            match q {
                Param::ThetaC if self.theta_c.is_none() => {}
                q if q.cutoff_form() == Some(false) && self.theta_c.is_some() => {}
                _ => out.set_value_keep_form(q, v),
            }
        }
        out
    }

    fn set_value_keep_form(&mut self, p: Param, v: f64) {
        match p {
            Param::ThetaC => self.theta_c = Some(v),
            Param::Mu2 => self.mu2 = v,
            Param::MuVv => self.mu_vv = v,
            Param::MuVphi => self.mu_vphi = v,
            _ => self.set(p, v),
        }
    }

    /// The friction law with these coefficients.
    pub fn friction(&self) -> FrictionLaw<f64> {
        friction_from(self.theta_c.is_some(), &self.to_vec())
    }

    /// `mu_v = d mu / d ln v` at steady sliding, `v = nu`, `theta = 1/nu`
    /// (Appendix C): `A + (2 mu_vv - mu_vphi) ln nu`.
    pub fn mu_v(&self) -> f64 {
        self.friction().mu_v(self.nu, 1.0 / self.nu)
    }

    /// `mu_phi = d mu / d ln theta` at steady sliding, `v = nu`, `theta =
    /// 1/nu` (Appendix C): `B + (mu_vphi - 2 mu2) ln nu`, or `B / (1 + nu
    /// theta_c)` with the cutoff.
    pub fn mu_phi(&self) -> f64 {
        self.friction().mu_phi(self.nu, 1.0 / self.nu)
    }

    /// Where the direct effect `d mu / d ln v = A + 2 mu_vv ln v + mu_vphi
    /// ln theta` (seed §II.D.2) vanishes at the steady age `theta = 1/nu`:
    /// the velocity (units of `V0`) below which (`mu_vv > 0`) or above
    /// which (`mu_vv < 0`) the law gives no slip velocity for a friction
    /// level, with `true` for a floor. `None` without `mu_vv`.
    pub fn direct_effect_bound(&self) -> Option<(f64, bool)> {
        (self.mu_vv != 0.0 && self.theta_c.is_none()).then(|| {
            let ln_v = (self.mu_vphi * self.nu.ln() - self.a) / (2.0 * self.mu_vv);
            (ln_v.exp(), self.mu_vv > 0.0)
        })
    }

    /// Refuses a range of driving velocities `(lo, hi)` (units of `V0`,
    /// given by `field`) over which the direct effect at steady sliding,
    /// `mu_v = A + (2 mu_vv - mu_vphi) ln nu`, does not stay positive
    /// (linear in `ln nu`, it is checked at both ends): steady sliding needs
    /// friction rising with the slip velocity (the quasi-static law has no
    /// velocity otherwise, and Appendix C no onset).
    pub fn check_velocity_range(
        &self,
        (lo, hi): (f64, f64),
        field: &str,
    ) -> Result<(), InputError> {
        for nu in [lo, hi] {
            let at = Params { nu, ..*self };
            let mu_v = at.mu_v();
            if mu_v.is_nan() || mu_v <= 0.0 {
                let vanishes = (-self.a / (2.0 * self.mu_vv - self.mu_vphi)).exp();
                return Err(InputError::Conflict(format!(
                    "{field} {lo:e} .. {hi:e}: the direct effect at steady sliding mu_v = A + \
                     (2 mu_vv - mu_vphi) ln nu is {mu_v:e} at nu = {nu:e} (A = {:e}, mu_vv = \
                     {:e}, mu_vphi = {:e}); it vanishes at nu = {vanishes:e}, and steady sliding \
                     needs mu_v > 0: keep the range on the side of it where mu_v > 0",
                    self.a, self.mu_vv, self.mu_vphi
                )));
            }
        }
        Ok(())
    }

    /// The slope in `ln v` of the force the block meets at steady sliding,
    /// `d (mu + eta_d v) / d ln v = mu_v + eta_d nu` (docs/model.md, "Linear
    /// stability"): the linearized force balance's `mu_v`, which eqs.
    /// C11–C13 take with radiation damping (`mu_v` itself without it).
    pub fn mu_v_damped(&self) -> f64 {
        self.mu_v() + self.eta_d * self.nu
    }

    /// Size of the inertia term in eq. C11, `m nu^2 / (mu_v + eta_d nu)`.
    pub fn inertia_ratio(&self) -> f64 {
        self.m * self.nu * self.nu / self.mu_v_damped()
    }

    /// Named values, for JSON output: the parameters of the ageing form in
    /// use (`theta_c` with the cutoff, `mu2`, `mu_vv`, `mu_vphi` without).
    pub fn named(&self) -> Vec<(&'static str, f64)> {
        Param::ALL
            .iter()
            .filter(|p| p.cutoff_form().is_none_or(|c| c == self.theta_c.is_some()))
            .map(|&p| (p.name(), self.get(p)))
            .collect()
    }
}

/// Builds the friction law from an engine parameter vector (any scalar type).
pub fn friction_from<D: Scalar>(cutoff: bool, p: &[D]) -> FrictionLaw<D> {
    let b = p[Param::B as usize];
    FrictionLaw {
        mu0: p[Param::Mu0 as usize],
        a: p[Param::A as usize],
        eta: p[Param::EtaD as usize],
        ageing: if cutoff {
            Ageing::Cutoff {
                b,
                theta_c: p[Param::ThetaC as usize],
            }
        } else {
            Ageing::Log {
                b,
                mu2: p[Param::Mu2 as usize],
                mu_vv: p[Param::MuVv as usize],
                mu_vphi: p[Param::MuVphi as usize],
            }
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn corrected() -> Params {
        Params {
            kappa: 0.01,
            nu: 3.0,
            m: 0.0,
            a: 0.012,
            b: 0.023,
            mu0: 0.6,
            mu2: 2.4e-4,
            theta_c: None,
            state_law: StateLaw::Ageing,
            mu_vv: 1e-3,
            mu_vphi: -5e-4,
            eta_d: 0.0,
        }
    }

    #[test]
    fn the_corrections_belong_to_the_logarithmic_form() {
        let p = corrected();
        let names: Vec<&str> = p.named().iter().map(|(n, _)| *n).collect();
        assert_eq!(
            names,
            ["kappa", "nu", "m", "A", "B", "mu0", "mu2", "mu_vv", "mu_vphi", "eta_d"]
        );
        // The cutoff clears them; setting one selects the logarithmic form.
        let mut c = p;
        c.set(Param::ThetaC, 0.3);
        assert_eq!((c.mu2, c.mu_vv, c.mu_vphi), (0.0, 0.0, 0.0));
        let names: Vec<&str> = c.named().iter().map(|(n, _)| *n).collect();
        assert_eq!(
            names,
            ["kappa", "nu", "m", "A", "B", "mu0", "theta_c", "eta_d"]
        );
        // A vector read back keeps the form: the cutoff ignores the entries.
        let back = c.with_vec(&p.to_vec());
        assert_eq!((back.mu_vv, back.theta_c), (0.0, Some(0.0)));
        c.set(Param::MuVphi, 2e-4);
        assert_eq!((c.theta_c, c.mu_vphi), (None, 2e-4));
        assert_eq!(p.with_vec(&p.to_vec()), p);
        let mut q = p;
        let e = q
            .apply_overrides(&["mu_vv=1e-4".into(), "theta_c=0.3".into()])
            .unwrap_err();
        assert!(
            e.to_string().contains("--set mu_vv and --set theta_c"),
            "{e}"
        );
    }

    #[test]
    fn the_steady_slopes_move_with_nu() {
        let p = corrected();
        let ln3 = 3f64.ln();
        assert!((p.mu_v() - (0.012 + 2.5e-3 * ln3)).abs() < 1e-17);
        assert!((p.mu_phi() - (0.023 - 9.8e-4 * ln3)).abs() < 1e-17);
        // The direct effect vanishes at nu = exp(-A / (2 mu_vv - mu_vphi)) = e^-4.8.
        assert!(p.check_velocity_range((0.01, 100.0), "range").is_ok());
        let e = p.check_velocity_range((1e-3, 1.0), "range").unwrap_err();
        assert!(
            e.to_string().contains("vanishes at nu = 8.2297470490200"),
            "{e}"
        );
        assert!(Params { nu: 1e-3, ..p }.validate().is_err());
    }
}
