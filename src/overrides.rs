//! `--set NAME=VALUE` overrides, in either kind of unit:
//!
//! * a **dimensionless** parameter of docs/model.md ([`Param`]: `kappa, nu,
//!   m, A, B, mu0, mu2, theta_c, mu_vv, mu_vphi, eta_d`), applied to the parameters
//!   after the scene is made dimensionless, as always;
//! * a **scene key in its physical unit** ([`PHYSICAL`]: `K` in N/m, `M` in
//!   kg, `W` in N, `V` and `V0` in µm/s, `D0` in µm, `tau` in s, `g` in
//!   m/s², `eta` in s/m, `V_range` as `LO:HI` in µm/s), applied to the scene before it is
//!   made dimensionless, so that `--set K=2e5` gives `kappa = K D0 / W` with
//!   the scene's `D0` and `W`, and `--set W=600` changes `kappa` and `m`
//!   together. The friction coefficients `A, B, mu0, mu2, mu_vv, mu_vphi`
//!   are the same numbers in both (the scene keys are dimensionless) and
//!   are applied as parameters.
//!
//! One quantity given both ways (`K` and `kappa`, `V` and `nu`, `M` and
//! `m`, `tau` and `theta_c`, `eta` and `eta_d`) is refused, naming both; so are the two ageing
//! forms together (`mu2`, `mu_vv` or `mu_vphi` with `theta_c` or `tau`). The same name given
//! twice keeps the last value (as the run names do).

use crate::error::{closest, InputError};
use crate::params::{Param, Params, StateLaw};
use crate::scene::SceneOverride;

/// A scene key `--set` takes in its physical unit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct PhysicalKey {
    /// The key, spelt as in a scene file.
    pub name: &'static str,
    /// Its unit, as written in messages (`N/m`).
    pub unit: &'static str,
    /// Its unit as written in file names and JSON field names (`N_per_m`).
    pub slug: &'static str,
    /// `"> 0"` or `">= 0"`: the values a scene file accepts.
    pub bound: &'static str,
    /// The dimensionless parameter this key alone determines (`K` gives
    /// `kappa`): giving both is a conflict.
    pub sets: Option<Param>,
    /// What it is, for messages.
    pub meaning: &'static str,
}

/// Every scene key `--set` takes in its physical unit (the numeric scene
/// keys other than the friction coefficients, docs/index.md §2).
pub const PHYSICAL: [PhysicalKey; 10] = [
    key(
        "K",
        "N/m",
        "N_per_m",
        ">= 0",
        Some(Param::Kappa),
        "spring stiffness",
    ),
    key("M", "kg", "kg", ">= 0", Some(Param::M), "block mass"),
    key("W", "N", "N", "> 0", None, "normal load"),
    key(
        "V",
        "µm/s",
        "um_per_s",
        "> 0",
        Some(Param::Nu),
        "driving velocity",
    ),
    key("V0", "µm/s", "um_per_s", "> 0", None, "reference velocity"),
    key("D0", "µm", "um", "> 0", None, "memory length"),
    key("tau", "s", "s", "> 0", Some(Param::ThetaC), "ageing cutoff"),
    key("g", "m/s^2", "m_per_s2", "> 0", None, "gravity"),
    key(
        "eta",
        "s/m",
        "s_per_m",
        ">= 0",
        Some(Param::EtaD),
        "radiation damping",
    ),
    key(
        "V_range",
        "µm/s",
        "um_per_s",
        "> 0",
        None,
        "velocities explored, LO:HI",
    ),
];

const fn key(
    name: &'static str,
    unit: &'static str,
    slug: &'static str,
    bound: &'static str,
    sets: Option<Param>,
    meaning: &'static str,
) -> PhysicalKey {
    PhysicalKey {
        name,
        unit,
        slug,
        bound,
        sets,
        meaning,
    }
}

impl PhysicalKey {
    /// The physical key named `name`, if any (case-sensitive: `M` is the
    /// mass in kg, `m` the dimensionless inertia).
    pub fn find(name: &str) -> Option<&'static PhysicalKey> {
        PHYSICAL.iter().find(|k| k.name == name)
    }

    /// The name of an override of this key in run names (file names), with
    /// its unit: `K_N_per_m`. Distinct from every dimensionless name, also
    /// where file names ignore case (`M_kg` beside `m`).
    pub fn file_key(&self) -> String {
        format!("{}_{}", self.name, self.slug)
    }
}

/// The name of the override `name` in run names: a physical key with its
/// unit ([`PhysicalKey::file_key`]), any other name as given.
pub fn file_key(name: &str) -> String {
    PhysicalKey::find(name).map_or_else(|| name.to_string(), PhysicalKey::file_key)
}

/// The value of one physical override.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PhysicalValue {
    /// A number in the key's unit.
    Number(f64),
    /// `V_range`: `LO:HI`.
    Range(f64, f64),
}

/// One `--set` item, parsed and checked.
#[derive(Clone, Debug, PartialEq)]
pub enum Override {
    /// A dimensionless parameter.
    Dimensionless(Param, f64),
    /// A scene key in its physical unit.
    Physical(&'static PhysicalKey, PhysicalValue),
    /// The evolution law of `theta` (`state_law=ageing|slip`, the scene key).
    StateLaw(StateLaw),
}

impl Override {
    /// The name as given on the command line.
    pub fn name(&self) -> &'static str {
        match self {
            Override::Dimensionless(p, _) => p.name(),
            Override::Physical(k, _) => k.name,
            Override::StateLaw(_) => "state_law",
        }
    }

    /// The dimensionless quantity it determines, if one alone.
    fn quantity(&self) -> Option<Param> {
        match self {
            Override::Dimensionless(p, _) => Some(*p),
            Override::Physical(k, _) => k.sets,
            Override::StateLaw(_) => None,
        }
    }

    /// The ageing form it selects: `Some(true)` the cutoff (`theta_c`,
    /// `tau`), `Some(false)` the logarithmic form (`mu2`, `mu_vv`,
    /// `mu_vphi`; [`Param::cutoff_form`]).
    fn ageing_form(&self) -> Option<bool> {
        self.quantity().and_then(Param::cutoff_form)
    }
}

/// The overrides of one command line, in the order given, each name once
/// (the last of a repeated one).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Overrides {
    items: Vec<(String, Override)>,
}

/// Every name `--set` takes, both kinds, with units (for messages and help).
pub fn accepted_names() -> String {
    let dimensionless: Vec<&str> = Param::ALL.iter().map(|p| p.name()).collect();
    let physical: Vec<String> = PHYSICAL
        .iter()
        .map(|k| match k.name {
            "V_range" => format!("V_range [LO:HI {}]", k.unit),
            _ => format!("{} [{}]", k.name, k.unit),
        })
        .collect();
    format!(
        "dimensionless {}; physical (scene keys) {}; the state law state_law [ageing|slip]",
        dimensionless.join(", "),
        physical.join(", ")
    )
}

impl Overrides {
    /// Parses `NAME=VALUE` items: every name checked (an unknown one gets
    /// the accepted names of both kinds and a suggestion), every value a
    /// finite number (`LO:HI` for `V_range`) in its range, and no quantity
    /// given both ways nor both ageing forms.
    pub fn parse(set: &[String]) -> Result<Overrides, InputError> {
        let mut items: Vec<(String, Override)> = Vec::new();
        for item in set {
            let (name, value) = item.split_once('=').ok_or_else(|| InputError::Malformed {
                field: "--set".into(),
                value: item.clone(),
                expected: "NAME=VALUE, e.g. --set kappa=0.01 or --set K=2e5 (N/m)".into(),
            })?;
            let (name, value) = (name.trim(), value.trim());
            let parsed = parse_one(name, value)?;
            items.retain(|(_, o)| o.name() != parsed.name());
            for (_, earlier) in &items {
                if earlier.quantity().is_some() && earlier.quantity() == parsed.quantity() {
                    let p = parsed.quantity().map_or("", Param::name);
                    return Err(InputError::Conflict(format!(
                        "--set {} and --set {} both set {p} ({}); give one",
                        earlier.name(),
                        parsed.name(),
                        quantity_definition(p)
                    )));
                }
                if let (Some(a), Some(b)) = (earlier.ageing_form(), parsed.ageing_form()) {
                    if a != b {
                        return Err(InputError::Conflict(format!(
                            "--set {} and --set {} select different ageing forms \
                             (the logarithmic form's mu2, mu_vv, mu_vphi vs the short-age \
                             cutoff tau, theta_c); use one",
                            earlier.name(),
                            parsed.name()
                        )));
                    }
                }
            }
            items.push((value.to_string(), parsed));
        }
        Ok(Overrides { items })
    }

    /// Whether no override was given.
    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }

    /// Whether `name` (either kind) was given.
    pub fn sets(&self, name: &str) -> bool {
        self.items.iter().any(|(_, o)| o.name() == name)
    }

    /// Whether the stiffness was given, as `kappa` or `K`.
    pub fn sets_stiffness(&self) -> bool {
        self.sets("kappa") || self.sets("K")
    }

    /// The physical overrides, for [`crate::scene::load_with`].
    pub fn physical(&self) -> Vec<SceneOverride> {
        self.items
            .iter()
            .filter_map(|(shown, o)| match o {
                Override::Physical(k, v) => Some(SceneOverride {
                    key: k.name,
                    value: match *v {
                        PhysicalValue::Number(x) => toml::Value::Float(x),
                        PhysicalValue::Range(lo, hi) => {
                            toml::Value::Array(vec![toml::Value::Float(lo), toml::Value::Float(hi)])
                        }
                    },
                    shown: format!("{}={shown}", k.name),
                }),
                // A scene key too: a scene written out with the overrides keeps it.
                Override::StateLaw(law) => Some(SceneOverride {
                    key: "state_law",
                    value: toml::Value::String(law.name().into()),
                    shown: format!("state_law={}", law.name()),
                }),
                Override::Dimensionless(..) => None,
            })
            .collect()
    }

    /// Applies the dimensionless overrides to `params` (after the scene's
    /// physical ones) and validates the result.
    pub fn apply_dimensionless(&self, params: &mut Params) -> Result<(), InputError> {
        for (_, o) in &self.items {
            match o {
                Override::Dimensionless(p, v) => params.set(*p, *v),
                Override::StateLaw(law) => params.state_law = *law,
                Override::Physical(..) => {}
            }
        }
        params.validate()
    }
}

/// How the dimensionless `p` follows from the scene's keys.
fn quantity_definition(p: &str) -> &'static str {
    match p {
        "kappa" => "kappa = K D0 / W, K in N/m",
        "m" => "m = M V0^2 / (W D0), M in kg",
        "nu" => "nu = V / V0, V in µm/s",
        "theta_c" => "theta_c = tau V0 / D0, tau in s",
        "eta_d" => "eta_d = eta V0, eta in s/m, V0 in m/s",
        _ => "",
    }
}

/// The refusal of `--set NAME` for the scene keys that are no quantity
/// (`name`, `description`, `law`), on a scene of either law.
pub fn not_a_quantity(name: &str) -> Option<InputError> {
    match name {
        "name" | "description" => Some(InputError::Conflict(format!(
            "--set {name}: the scene's {name} is not a quantity; --name NAME names the output \
             files"
        ))),
        "law" => Some(InputError::Conflict(
            "--set law: the friction law is the scene's own (its key law), not a quantity; \
             --scene names a scene of the other law (the built-in gel is adhesive, pmma \
             rate-and-state)"
                .into(),
        )),
        _ => None,
    }
}

/// `--set V_range=LO:HI`, the velocities explored in µm/s: both numbers
/// finite, `0 < LO < HI`, the messages naming `--set V_range` (the same
/// for the scenes of either law).
pub fn v_range(value: &str) -> Result<(f64, f64), InputError> {
    let k = &PHYSICAL[PHYSICAL.len() - 1];
    debug_assert_eq!(k.name, "V_range");
    let Some((lo, hi)) = value.split_once(':') else {
        return Err(InputError::Malformed {
            field: "--set V_range".into(),
            value: value.to_string(),
            expected: format!("LO:HI in {} with 0 < LO < HI", k.unit),
        });
    };
    let lo = physical_number(k, lo, "--set V_range (LO)")?;
    let hi = physical_number(k, hi, "--set V_range (HI)")?;
    if hi <= lo {
        return Err(InputError::out_of_range(
            "--set V_range (HI)",
            hi,
            &format!("> LO = {lo} ({})", k.unit),
        ));
    }
    Ok((lo, hi))
}

/// One override `name=value`.
fn parse_one(name: &str, value: &str) -> Result<Override, InputError> {
    if let Ok(p) = Param::parse(name) {
        let v: f64 = value.parse().map_err(|_| InputError::Malformed {
            field: format!("--set {}", p.name()),
            value: value.to_string(),
            expected: "a number".into(),
        })?;
        return Ok(Override::Dimensionless(p, v));
    }
    if name == "state_law" {
        return StateLaw::parse(value)
            .map(Override::StateLaw)
            .ok_or_else(|| InputError::Malformed {
                field: "--set state_law".into(),
                value: value.to_string(),
                expected: "ageing or slip".into(),
            });
    }
    let Some(k) = PhysicalKey::find(name) else {
        if let Some(e) = not_a_quantity(name) {
            return Err(e);
        }
        if let Some(e) = crate::scene::other_law_key(
            name,
            &format!("--set {name}"),
            crate::scene::Law::RateAndState,
            ("--set keys", &accepted_names()),
        ) {
            return Err(e);
        }
        let all = Param::ALL
            .iter()
            .map(|p| p.name())
            .chain(PHYSICAL.iter().map(|k| k.name))
            .chain(["state_law"]);
        return Err(InputError::UnknownName {
            what: "parameter",
            name: name.to_string(),
            suggestion: closest(name, all),
            allowed: accepted_names(),
        });
    };
    if k.name == "V_range" {
        let (lo, hi) = v_range(value)?;
        return Ok(Override::Physical(k, PhysicalValue::Range(lo, hi)));
    }
    let field = format!("--set {}", k.name);
    Ok(Override::Physical(
        k,
        PhysicalValue::Number(physical_number(k, value, &field)?),
    ))
}

/// A number of the physical key `k` given as `field`: finite and within
/// the key's bound.
fn physical_number(k: &PhysicalKey, text: &str, field: &str) -> Result<f64, InputError> {
    let unit = k.unit;
    let x: f64 = text.trim().parse().map_err(|_| InputError::Malformed {
        field: field.to_string(),
        value: text.to_string(),
        expected: format!("a number in {unit}"),
    })?;
    let ok = x.is_finite()
        && match k.bound {
            "> 0" => x > 0.0,
            _ => x >= 0.0,
        };
    ok.then_some(x).ok_or_else(|| {
        InputError::out_of_range(
            field,
            x,
            &format!("a finite number {} ({unit}, {})", k.bound, k.meaning),
        )
    })
}

/// The overrides `NAME=VALUE` of `set` sorted by name, the last of a
/// repeated one kept, numbers in one spelling ([`canonical_number`]); a
/// scene key in its physical unit named with that unit
/// ([`file_key`]: `K_N_per_m=2e5`, `M_kg=2`), so that it
/// never names the same file as a dimensionless parameter (`m`), also where
/// file names ignore case; `V_range=LO:HI` with both numbers so spelt.
pub fn canonical_overrides(set: &[String]) -> Vec<(String, String)> {
    let mut overrides: Vec<(String, String)> = Vec::new();
    for part in set {
        let (key, value) = part.split_once('=').unwrap_or((part.as_str(), ""));
        let (key, value) = (file_key(key.trim()), value.trim());
        let number = |v: &str| {
            v.trim()
                .parse::<f64>()
                .map_or_else(|_| v.to_string(), canonical_number)
        };
        let value = match value.split_once(':') {
            Some((lo, hi)) => format!("{}:{}", number(lo), number(hi)),
            None => number(value),
        };
        overrides.retain(|(k, _)| *k != key);
        overrides.push((key, value));
    }
    overrides.sort_by(|a, b| a.0.cmp(&b.0));
    overrides
}

/// `v` in one spelling: plain digits within `[1e-3, 1e5)`, else the
/// shortest mantissa and exponent (`1e-12`).
fn canonical_number(v: f64) -> String {
    if v == 0.0 || (1e-3..1e5).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn set(items: &[&str]) -> Result<Overrides, InputError> {
        Overrides::parse(&items.iter().map(|s| s.to_string()).collect::<Vec<_>>())
    }

    fn err(items: &[&str]) -> String {
        set(items).expect_err("refused").to_string()
    }

    #[test]
    fn both_kinds_parse_and_the_last_of_a_name_is_kept() {
        let o = set(&["K=2e5", "kappa=1", "kappa=0.5", "mu2=1e-4", "V_range=1:10"]);
        // kappa with K is a conflict; without it both kinds parse.
        assert!(o.is_err());
        let o = set(&["K=2e5", "K=3e5", "m=0.1", "V_range=1:10"]).unwrap();
        let physical = o.physical();
        assert_eq!(physical.len(), 2);
        assert_eq!(physical[0].key, "K");
        assert_eq!(physical[0].value, toml::Value::Float(3e5));
        assert_eq!(physical[0].shown, "K=3e5");
        assert!(o.sets_stiffness() && o.sets("m") && !o.sets("M"));
        let mut p = crate::scene::builtin("pmma").unwrap().params;
        o.apply_dimensionless(&mut p).unwrap();
        assert_eq!(p.m, 0.1);
    }

    #[test]
    fn one_quantity_twice_is_refused_naming_both() {
        for (a, b, q) in [
            ("K=2e5", "kappa=0.01", "kappa"),
            ("m=0.1", "M=2", "m"),
            ("V=3", "nu=2", "nu"),
            ("tau=0.1", "theta_c=2", "theta_c"),
        ] {
            let e = err(&[a, b]);
            let (na, nb) = (a.split('=').next().unwrap(), b.split('=').next().unwrap());
            assert!(
                e.contains(&format!("--set {na} and --set {nb} both set {q}")),
                "{e}"
            );
        }
        let e = err(&["tau=0.1", "mu2=1e-4"]);
        assert!(e.contains("--set tau and --set mu2 select different ageing forms"));
        let e = err(&["mu_vphi=1e-4", "theta_c=0.3"]);
        assert!(e.contains("--set mu_vphi and --set theta_c select different ageing forms"));
        // The logarithmic form's three parameters go together.
        let o = set(&["mu2=1e-4", "mu_vv=2e-4", "mu_vphi=-3e-4"]).unwrap();
        let mut p = crate::scene::builtin("brockley").unwrap().params;
        o.apply_dimensionless(&mut p).unwrap();
        assert_eq!(
            (p.mu2, p.mu_vv, p.mu_vphi, p.theta_c),
            (1e-4, 2e-4, -3e-4, None)
        );
    }

    #[test]
    fn bad_names_and_values_name_the_field() {
        let e = err(&["Kappa=1"]);
        assert!(e.contains("unknown parameter 'Kappa'") && e.contains("did you mean"));
        assert!(e.contains("kappa, nu, m") && e.contains("K [N/m]") && e.contains("tau [s]"));
        for (item, field) in [
            (
                "M=-1",
                "--set M = -1 is out of range: expected a finite number >= 0 (kg",
            ),
            (
                "W=0",
                "--set W = 0 is out of range: expected a finite number > 0 (N",
            ),
            ("D0=nan", "--set D0 = NaN is out of range"),
            ("V=inf", "--set V = inf"),
            (
                "K=stiff",
                "--set K: cannot read 'stiff': expected a number in N/m",
            ),
            ("V_range=10:1", "--set V_range (HI) = 1"),
            ("V_range=10", "--set V_range: cannot read '10'"),
            ("kappa=x", "--set kappa: cannot read 'x'"),
            ("name=x", "--set name: the scene's name is not a quantity"),
            ("K", "--set: cannot read 'K'"),
        ] {
            let e = err(&[item]);
            assert!(e.contains(field), "{item}: {e}");
        }
    }

    #[test]
    fn physical_names_in_file_names_carry_their_unit() {
        assert_eq!(file_key("K"), "K_N_per_m");
        assert_eq!(file_key("M"), "M_kg");
        assert_eq!(file_key("m"), "m");
        assert_eq!(file_key("V_range"), "V_range_um_per_s");
        // Unique also where file names ignore case.
        let mut names: Vec<String> = PHYSICAL
            .iter()
            .map(PhysicalKey::file_key)
            .chain(Param::ALL.iter().map(|p| p.name().to_string()))
            .map(|n| n.to_lowercase())
            .collect();
        names.sort();
        let n = names.len();
        names.dedup();
        assert_eq!(names.len(), n);
    }
}
