//! Adhesive scenes (`law = "adhesive"`): a soft slider (gel, elastomer) on
//! glass in laboratory units, read from TOML and made dimensionless
//! ([`super::params`]):
//!
//! ```text
//! nu = V / V_s,   kappa = K V_s tau_out / F_a,   r = tau_on / tau_out,
//! f_v = F_v / F_a,   m = M V_s / (F_a tau_out)
//! ```
//!
//! `F_a` \[N\] is the pinning force scale `N0 k_B T / b` (seed eq. D1),
//! `V_s` [µm/s] Schallamach's velocity `k_B T / (kappa b tau_out)` (eq. D7),
//! `tau_out` and `tau_on` \[s\] the desorption and readsorption times, `F_v`
//! \[N\] and `alpha` the junction's viscous force `F_v (v / V_s)^(1 - alpha)`
//! (seed §III.D.2), `M` \[kg\], `K` [N/m], `V` [µm/s] as for the other laws.

use super::params::AdhesiveParams;
use crate::error::{closest, InputError};
use crate::scene::{file_error, other_law_key, read, require, string, v_range, Law};
use toml::Table;

/// The value of the scene key `law` that selects this family.
pub const LAW: &str = "adhesive";

/// Every key an adhesive scene may hold.
const KEYS: &str = "law name description F_a V_s tau_out tau_on F_v alpha M K V V_range";

/// The built-in adhesive scenes (`examples/scenes/NAME.toml`).
const BUILTINS: [(&str, &str); 1] = [("gel", include_str!("../../examples/scenes/gel.toml"))];

/// Physical units of an adhesive scene, to report in the experimenter's units.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct AdhesiveUnits {
    /// Pinning force scale `F_a` \[N\].
    #[serde(rename = "F_a_N")]
    pub f_a: f64,
    /// Schallamach's velocity `V_s` [m/s] (JSON: in µm/s).
    #[serde(rename = "V_s_um_per_s", serialize_with = "micrometres")]
    pub v_s: f64,
    /// Desorption time `tau_out` \[s\], the unit of time.
    #[serde(rename = "tau_out_s")]
    pub tau_out: f64,
    /// Block mass `M` \[kg\].
    #[serde(rename = "M_kg")]
    pub mass: f64,
}

/// A velocity in m/s written in µm/s (divided by the factor it was
/// multiplied with, which gives the scene's own value back).
fn micrometres<S: serde::Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_f64(v / 1e-6)
}

impl AdhesiveUnits {
    /// A force in N of a dimensionless one (`F / F_a`).
    pub fn force_n(&self, f: f64) -> f64 {
        f * self.f_a
    }
    /// A velocity in µm/s of a dimensionless one (`v / V_s`).
    pub fn velocity_um_s(&self, u: f64) -> f64 {
        u * self.v_s * 1e6
    }
    /// The dimensionless velocity of one in µm/s.
    pub fn nu_of_velocity_um_s(&self, v: f64) -> f64 {
        v / (self.v_s * 1e6)
    }
    /// A time in s of a dimensionless one (`t / tau_out`).
    pub fn time_s(&self, t: f64) -> f64 {
        t * self.tau_out
    }
    /// A stiffness in N/m of `kappa`: `K = kappa F_a / (V_s tau_out)`.
    pub fn stiffness_n_m(&self, kappa: f64) -> f64 {
        kappa * self.f_a / (self.v_s * self.tau_out)
    }
}

/// An adhesive experiment and its dimensionless parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct AdhesiveScene {
    pub name: String,
    pub description: String,
    pub params: AdhesiveParams,
    pub units: AdhesiveUnits,
    /// Whether the scene gives the stiffness `K` (else `kappa = 0`).
    pub stiffness_given: bool,
    /// Driving velocities to explore, `V_range / V_s`.
    pub nu_range: (f64, f64),
    /// What is unusual in the scene but valid (`tau_on > tau_out`), for
    /// stderr and the JSON.
    pub warnings: Vec<String>,
}

/// The warning of a scene whose readsorption is slower than desorption,
/// `r = tau_on / tau_out > 1`. Valid: the bond kinetics and the friction
/// law (eqs. D2, D3) hold for every `r > 0`, and steady friction keeps its
/// bell (rising as `F_a v / V_s / (1 + r)`). Unusual: Schallamach's
/// picture assumes chains readsorb faster than they desorb (`tau_on <
/// tau_out`, docs/model.md), and with `r > 1` fewer than half the chains
/// are bonded at rest (`n = 1 / (1 + r)`).
fn slow_readsorption(tau_on: f64, tau_out: f64) -> Option<String> {
    (tau_on > tau_out).then(|| {
        format!(
            "tau_on = {tau_on:e} s > tau_out = {tau_out:e} s (r = tau_on / tau_out = {:.4e} > \
             1): chains readsorb slower than they desorb, so fewer than half are bonded at \
             rest (n = 1/(1 + r) = {:.4}); Schallamach's picture assumes tau_on < tau_out. \
             The model holds for any r > 0; check that the two times are not swapped",
            tau_on / tau_out,
            1.0 / (1.0 + tau_on / tau_out)
        )
    })
}

/// Names of the built-in adhesive scenes.
pub fn builtin_names() -> impl Iterator<Item = &'static str> {
    BUILTINS.iter().map(|(n, _)| *n)
}

/// The text of a built-in adhesive scene.
pub fn builtin_text(name: &str) -> Option<&'static str> {
    BUILTINS.iter().find(|(n, _)| *n == name).map(|(_, t)| *t)
}

/// A built-in adhesive scene by name, or else a path to a TOML file.
pub fn load(name_or_path: &str) -> Result<AdhesiveScene, InputError> {
    load_with(name_or_path, &[])
}

/// The keys `--set` may give on an adhesive scene: its numbers, in the
/// scene file's units, and `V_range` as `LO:HI` in µm/s (every key of its
/// scene files but `law`, `name` and `description`).
const SETTABLE: &str = "F_a V_s tau_out tau_on F_v alpha M K V V_range";

/// The adhesive block's dimensionless parameters and the scene key each
/// is made from (`nu = V / V_s`, `kappa = K V_s tau_out / F_a`, `r = tau_on
/// / tau_out`, `f_v = F_v / F_a`, `m = M V_s / (F_a tau_out)`).
const DIMENSIONLESS: [(&str, &str); 5] = [
    ("nu", "V"),
    ("kappa", "K"),
    ("r", "tau_on"),
    ("f_v", "F_v"),
    ("m", "M"),
];

/// [`load`] with the overrides `set` (`KEY=VALUE`, a key of [`SETTABLE`]
/// in the scene file's unit, `V_range=LO:HI`) put in place of the file's
/// values before the scene is read: checked as the file's own values are,
/// a refused value named as given (`--set K`).
pub fn load_with(name_or_path: &str, set: &[String]) -> Result<AdhesiveScene, InputError> {
    let (text, in_file) = match builtin_text(name_or_path) {
        Some(text) => (text.to_string(), false),
        None => (
            std::fs::read_to_string(name_or_path).map_err(|e| file_error(name_or_path, e))?,
            true,
        ),
    };
    let mut t: Table = text.parse().map_err(|e| file_error(name_or_path, e))?;
    let given = insert_overrides(&mut t, set)?;
    from_table(&t, name_or_path).map_err(|e| match as_set(e, &given) {
        Ok(e) => e,
        Err(e) if in_file => e.in_file(name_or_path),
        Err(e) => e,
    })
}

/// Puts the overrides `set` (`KEY=VALUE`, [`load_with`]) in the scene
/// table `t` as the scene file would hold them; returns the keys set.
pub fn insert_overrides<'a>(t: &mut Table, set: &'a [String]) -> Result<Vec<&'a str>, InputError> {
    let mut given = Vec::new();
    for item in set {
        let (key, value) = parse_override(item)?;
        t.insert(key.to_string(), value);
        given.push(key);
    }
    Ok(given)
}

/// The error `e` of a value given by `--set` (a key of `given`) named as
/// given (`--set K`, `--set V_range`); `Err(e)` unchanged for any other.
fn as_set(e: InputError, given: &[&str]) -> Result<InputError, InputError> {
    let set_key = |field: &str| {
        given
            .iter()
            .find(|k| field == **k || field.starts_with(&format!("{k}[")))
            .map(|k| format!("--set {k}"))
    };
    match e {
        InputError::OutOfRange {
            field,
            value,
            expected,
        } => match set_key(&field) {
            Some(field) => Ok(InputError::OutOfRange {
                field,
                value,
                expected,
            }),
            None => Err(InputError::OutOfRange {
                field,
                value,
                expected,
            }),
        },
        other => Err(other),
    }
}

/// The unit of a number of an adhesive scene ("" for `alpha`).
fn unit_of(key: &str) -> &'static str {
    match key {
        "F_a" | "F_v" => "N",
        "V_s" | "V" | "V_range" => "µm/s",
        "tau_out" | "tau_on" => "s",
        "M" => "kg",
        "K" => "N/m",
        _ => "",
    }
}

/// One `--set KEY=VALUE` of an adhesive scene: its key and the value as the
/// scene file holds it.
fn parse_override(item: &str) -> Result<(&str, toml::Value), InputError> {
    let allowed = SETTABLE.replace(' ', ", ");
    let malformed = || InputError::Malformed {
        field: "--set".into(),
        value: item.to_string(),
        expected: format!("KEY=VALUE with KEY one of the adhesive scene's keys ({allowed})"),
    };
    let (key, value) = item.split_once('=').ok_or_else(malformed)?;
    let (key, value) = (key.trim(), value.trim());
    if key == "V_range" {
        let (lo, hi) = crate::overrides::v_range(value)?;
        let range = vec![toml::Value::Float(lo), toml::Value::Float(hi)];
        return Ok((key, toml::Value::Array(range)));
    }
    if !SETTABLE.split(' ').any(|k| k == key) {
        if let Some(e) = crate::overrides::not_a_quantity(key) {
            return Err(e);
        }
        // A key of the rate-and-state law says so, with this law's keys.
        let field = format!("--set {key}");
        if let Some(e) = other_law_key(key, &field, Law::Adhesive, ("--set keys", &allowed)) {
            return Err(e);
        }
        // A dimensionless parameter (docs/model.md) names the scene key it
        // comes from; anything else the closest key, if one is close.
        let from = DIMENSIONLESS
            .iter()
            .find(|(d, _)| *d == key)
            .map(|(_, k)| k.to_string());
        return Err(InputError::UnknownName {
            what: "--set key of an adhesive scene (its numbers in the scene file's units; the \
                   dimensionless nu, kappa, r, f_v, m follow from them)",
            name: key.to_string(),
            suggestion: from.or_else(|| closest(key, SETTABLE.split(' '))),
            allowed,
        });
    }
    let number: f64 = value.parse().map_err(|_| InputError::Malformed {
        field: format!("--set {key}"),
        value: value.to_string(),
        expected: match unit_of(key) {
            "" => "a number (dimensionless)".to_string(),
            unit => format!("a number in {unit}"),
        },
    })?;
    Ok((key, toml::Value::Float(number)))
}

/// Parses an adhesive scene; `origin` names it in errors and gives the
/// default name (its stem).
pub fn from_toml_str(text: &str, origin: &str) -> Result<AdhesiveScene, InputError> {
    let t: Table = text.parse().map_err(|e| file_error(origin, e))?;
    from_table(&t, origin)
}

/// An adhesive scene from its TOML table.
fn from_table(t: &Table, origin: &str) -> Result<AdhesiveScene, InputError> {
    if let Some(key) = t.keys().find(|k| !KEYS.split(' ').any(|known| known == *k)) {
        let allowed = KEYS.replace(' ', ", ");
        let field = format!("key {key}");
        if let Some(e) = other_law_key(key, &field, Law::Adhesive, ("keys", &allowed)) {
            return Err(e);
        }
        return Err(InputError::UnknownName {
            what: "key of an adhesive scene",
            name: key.clone(),
            suggestion: closest(key, KEYS.split(' ')),
            allowed: KEYS.replace(' ', ", "),
        });
    }
    let stem = std::path::Path::new(origin)
        .file_stem()
        .and_then(|s| s.to_str());
    let name = string(t, "name")?.unwrap_or_else(|| stem.unwrap_or(origin).to_string());
    let description = string(t, "description")?.unwrap_or_default();
    let required = |key: &str, unit: &str, meaning: &str| -> Result<f64, InputError> {
        read(t, key, "> 0", unit)?.ok_or_else(|| {
            file_error(
                origin,
                format!(
                    "the key {key} ({meaning}, > 0, in {unit}) is required with law = \"adhesive\""
                ),
            )
        })
    };
    let f_a = required("F_a", "N", "pinning force scale N0 kB T / b")?;
    let v_s = required(
        "V_s",
        "µm/s",
        "Schallamach's velocity kB T / (kappa b tau_out)",
    )?;
    let tau_out = required("tau_out", "s", "desorption time")?;
    let tau_on = required("tau_on", "s", "readsorption time")?;
    let f_v = read(t, "F_v", ">= 0", "N")?.unwrap_or(0.0);
    let alpha = read(t, "alpha", ">= 0", "dimensionless")?.unwrap_or(0.0);
    require(
        alpha < 1.0,
        "alpha",
        alpha,
        "in [0, 1) (0: Newtonian junction; about 0.6 for gelatin)",
    )?;
    let mass = read(t, "M", ">= 0", "kg")?.unwrap_or(0.0);
    let k = read(t, "K", ">= 0", "N/m")?;
    let v = read(t, "V", "> 0", "µm/s")?.ok_or_else(|| {
        file_error(
            origin,
            "the key V (driving velocity, > 0, in µm/s) is required",
        )
    })?;
    let (lo, hi) = t
        .get("V_range")
        .map_or(Ok((0.01 * v, 100.0 * v)), v_range)?;
    let units = AdhesiveUnits {
        f_a,
        v_s: v_s * 1e-6,
        tau_out,
        mass,
    };
    let params = AdhesiveParams {
        kappa: k.map_or(0.0, |k| k * units.v_s * tau_out / f_a),
        nu: v / v_s,
        r: tau_on / tau_out,
        f_v: f_v / f_a,
        alpha,
        m: mass * units.v_s / (f_a * tau_out),
    };
    params.validate().map_err(|e| e.in_file(origin))?;
    Ok(AdhesiveScene {
        name,
        description,
        params,
        units,
        stiffness_given: k.is_some(),
        nu_range: (lo / v_s, hi / v_s),
        warnings: slow_readsorption(tau_on, tau_out).into_iter().collect(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gel_converts_to_hand_computed_numbers() {
        let s = load("gel").unwrap();
        let p = s.params;
        let rel = |a: f64, b: f64| ((a - b) / b).abs();
        // kappa = K V_s tau_out / F_a = 200 * 0.025e-6 * 1 / 0.05.
        assert!(rel(p.kappa, 1e-4) < 1e-14, "{}", p.kappa);
        assert!(rel(p.nu, 800.0) < 1e-14 && rel(p.r, 0.1) < 1e-15);
        assert!(rel(p.f_v, 0.01) < 1e-15 && p.alpha == 0.6);
        // m = M V_s / (F_a tau_out) = 1e-3 * 0.025e-6 / 0.05.
        assert!(rel(p.m, 5e-10) < 1e-14, "{}", p.m);
        assert!(rel(s.units.stiffness_n_m(p.kappa), 200.0) < 1e-14);
        assert!(rel(s.units.velocity_um_s(p.nu), 20.0) < 1e-14);
        assert!(s.stiffness_given && s.nu_range.0 < p.nu && p.nu < s.nu_range.1);
        assert!(!s.description.is_empty());
    }

    #[test]
    fn required_keys_are_named() {
        let e = from_toml_str("law = \"adhesive\"\nV_s = 1", "t.toml").unwrap_err();
        assert!(e.to_string().contains("the key F_a"), "{e}");
    }
}
