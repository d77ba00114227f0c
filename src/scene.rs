//! Scenes: physical experiments in laboratory units, read from TOML and
//! converted to the dimensionless [`Params`] of docs/model.md:
//!
//! ```text
//! nu = V / V0,   kappa = K D0 / W,   m = M V0^2 / (W D0),   theta_c = tau V0 / D0,
//! W = M g unless W is given.
//! ```
//!
//! Lengths are read in micrometres, velocities in um/s, `M` in kg, `W` in N,
//! `K` in N/m, `tau` in s, `g` in m/s^2.

use crate::error::{closest, InputError};
use crate::params::{Params, StateLaw};
use std::path::Path;
use toml::{Table, Value};

/// Physical units of a scene: converts dimensionless numbers back to SI for reports.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Units {
    /// Memory length `D0` \[m\].
    pub d0: f64,
    /// Reference velocity `V0` [m/s].
    pub v0: f64,
    /// Block mass `M` \[kg\].
    pub mass: f64,
    /// Normal load `W` \[N\].
    pub load: f64,
    /// Gravity `g` [m/s^2].
    pub g: f64,
    /// Whether the load is the block's weight, `W = M g` (the scene gives no `W`).
    pub load_is_weight: bool,
}

impl Units {
    /// `K/W = kappa / D0` [1/m].
    pub fn k_over_w(&self, kappa: f64) -> f64 {
        kappa / self.d0
    }

    /// `K/M = kappa W / (M D0)` [1/s^2] (with `W = M g`, `kappa g / D0`);
    /// `None` for a massless block.
    pub fn k_over_m(&self, kappa: f64) -> Option<f64> {
        (self.mass > 0.0).then(|| kappa * self.load / (self.mass * self.d0))
    }

    /// Spring stiffness `K = kappa W / D0` [N/m].
    pub fn stiffness(&self, kappa: f64) -> f64 {
        kappa * self.load / self.d0
    }

    /// Frequency in Hz of a dimensionless angular frequency: `omega V0 / D0 / (2 pi)`.
    pub fn frequency_hz(&self, omega: f64) -> f64 {
        omega * self.v0 / self.d0 / (2.0 * std::f64::consts::PI)
    }

    /// Velocity in um/s of a dimensionless velocity: `nu V0`.
    pub fn velocity_um_s(&self, nu: f64) -> f64 {
        nu * self.v0 * 1e6
    }

    /// Dimensionless velocity of a velocity in um/s: `V / V0`.
    pub fn nu_of_velocity_um_s(&self, v_um_s: f64) -> f64 {
        v_um_s / (self.v0 * 1e6)
    }
}

/// A physical experiment and its dimensionless parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct Scene {
    /// Short name (the `name` key, else the file stem).
    pub name: String,
    /// One-line description.
    pub description: String,
    /// Dimensionless parameters (validated).
    pub params: Params,
    /// Units to convert results back to SI.
    pub units: Units,
    /// Whether the scene fixes the stiffness `K`; if not, `kappa = 0`.
    pub stiffness_given: bool,
    /// Range of driving velocities to explore, `V_range / V0` (dimensionless).
    pub nu_range: (f64, f64),
}

/// Memory lengths `D0` a scene may give without a warning, in micrometres:
/// measured values are of order 0.1 to 10 um (the seed review's systems
/// and the built-in scenes), so a value far outside this band is most
/// likely in the wrong unit (metres).
pub const PLAUSIBLE_D0_UM: (f64, f64) = (1e-3, 1e3);

impl Scene {
    /// Warnings about values that are valid but implausible (most likely a
    /// unit mistake), one sentence each, naming the key.
    pub fn implausible(&self) -> Vec<String> {
        let d0_um = self.units.d0 * 1e6;
        let (lo, hi) = PLAUSIBLE_D0_UM;
        let mut out = Vec::new();
        if !(lo..=hi).contains(&d0_um) {
            out.push(format!(
                "D0 = {d0_um:e} µm is outside the usual {lo:e} to {hi:e} µm (D0 is in micrometres, not metres)"
            ));
        }
        out
    }
}

/// The scene used when none is named.
pub const DEFAULT_SCENE: &str = "pmma";

const BUILTINS: [(&str, &str); 3] = [
    ("pmma", include_str!("../examples/scenes/pmma.toml")),
    ("pmma-rr", include_str!("../examples/scenes/pmma-rr.toml")),
    ("brockley", include_str!("../examples/scenes/brockley.toml")),
];

const BUILTIN_NAMES: [&str; 3] = [BUILTINS[0].0, BUILTINS[1].0, BUILTINS[2].0];

/// Every key a scene file may hold.
const KEYS: &str =
    "law name description A B mu0 mu2 mu_vv mu_vphi tau eta state_law D0 V0 M W g K V V_range";

/// The keys of the logarithmic ageing form, which `tau` (the cutoff form)
/// excludes.
pub const LOG_FORM_KEYS: [&str; 3] = ["mu2", "mu_vv", "mu_vphi"];

/// Names of the built-in scenes (`examples/scenes/NAME.toml`).
pub fn builtin_names() -> &'static [&'static str] {
    &BUILTIN_NAMES
}

/// A built-in scene by name.
pub fn builtin(name: &str) -> Option<Scene> {
    BUILTINS
        .iter()
        .find(|(n, _)| *n == name)
        .and_then(|(n, text)| from_toml_str(text, n).ok())
}

/// The family of friction laws a scene belongs to (its key `law`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Law {
    /// `law = "rate-and-state"` or no `law`: the block of docs/model.md.
    RateAndState,
    /// `law = "adhesive"`: Schallamach's soft adhesive contacts
    /// ([`crate::adhesive`]).
    Adhesive,
}

/// The value of `law` for the rate-and-state block.
pub const RATE_AND_STATE: &str = "rate-and-state";

/// The names only rate-and-state scenes have: their scene keys and the
/// dimensionless parameters `--set` takes (docs/model.md).
const RATE_AND_STATE_ONLY: &str =
    "A B mu0 mu2 mu_vv mu_vphi tau eta state_law D0 V0 W g theta_c eta_d";

/// The names only adhesive scenes have: their scene keys and the
/// dimensionless parameters they are made into (docs/model.md, "Soft
/// adhesive contacts").
const ADHESIVE_ONLY: &str = "F_a V_s tau_out tau_on F_v alpha r f_v";

impl Law {
    /// The value of the scene key `law`.
    pub fn name(self) -> &'static str {
        match self {
            Law::RateAndState => RATE_AND_STATE,
            Law::Adhesive => crate::adhesive::scene::LAW,
        }
    }

    /// The other family.
    fn other(self) -> Law {
        match self {
            Law::RateAndState => Law::Adhesive,
            Law::Adhesive => Law::RateAndState,
        }
    }

    /// The names (scene keys, dimensionless parameters) of this family
    /// that the other does not have.
    fn own_names(self) -> &'static str {
        match self {
            Law::RateAndState => RATE_AND_STATE_ONLY,
            Law::Adhesive => ADHESIVE_ONLY,
        }
    }
}

/// The refusal of `name`, given as `field` (`--set A`, `key A`) to a scene
/// of the law `this`, where it is a key of the other family of laws: says
/// so, and lists `allowed`, this scene's `keys` (`keys`, `--set keys`).
/// `None` where `name` is no key of the other family either (then the
/// closest of this family's keys is suggested, as for any unknown name).
pub fn other_law_key(
    name: &str,
    field: &str,
    this: Law,
    (keys, allowed): (&'static str, &str),
) -> Option<InputError> {
    let other = this.other();
    other
        .own_names()
        .split(' ')
        .any(|k| k == name)
        .then(|| InputError::OtherLaw {
            field: field.to_string(),
            name: name.to_string(),
            family: match other {
                Law::RateAndState => "a rate-and-state",
                Law::Adhesive => "an adhesive",
            },
            law: this.name(),
            keys,
            allowed: allowed.to_string(),
        })
}

/// The law of a parsed scene table (`law`, default rate-and-state).
fn law_in(t: &Table) -> Result<Law, InputError> {
    match string(t, "law")?.as_deref() {
        None | Some(RATE_AND_STATE) => Ok(Law::RateAndState),
        Some(crate::adhesive::scene::LAW) => Ok(Law::Adhesive),
        Some(other) => Err(InputError::Malformed {
            field: "law".into(),
            value: other.into(),
            expected: format!(
                "{RATE_AND_STATE} (the default) or {}",
                crate::adhesive::scene::LAW
            ),
        }),
    }
}

/// The law of the scene `name_or_path` (a built-in name or a TOML file);
/// rate-and-state for anything else, whose loading then names the problem.
pub fn law_of(name_or_path: &str) -> Result<Law, InputError> {
    if crate::adhesive::scene::builtin_text(name_or_path).is_some() {
        return Ok(Law::Adhesive);
    }
    if builtin(name_or_path).is_some() {
        return Ok(Law::RateAndState);
    }
    match std::fs::read_to_string(name_or_path) {
        Ok(text) => match text.parse::<Table>() {
            Ok(t) => law_in(&t).map_err(|e| e.in_file(name_or_path)),
            Err(_) => Ok(Law::RateAndState),
        },
        Err(_) => Ok(Law::RateAndState),
    }
}

/// The refusal of an adhesive scene where only the rate-and-state block is
/// analysed.
fn adhesive_here(origin: &str) -> InputError {
    InputError::Conflict(format!(
        "{origin} is an adhesive scene (law = \"adhesive\"): the commands hopf, branch, \
         diagram, cycles, simulate and fit analyse it (and the Python functions of the same \
         names) with its own law, not this rate-and-state analysis"
    ))
}

/// A built-in name, or else a path to a TOML file; unknown names that are not
/// files get a suggestion among built-ins.
pub fn load(name_or_path: &str) -> Result<Scene, InputError> {
    if let Some(scene) = builtin(name_or_path) {
        return Ok(scene);
    }
    if crate::adhesive::scene::builtin_text(name_or_path).is_some() {
        return Err(adhesive_here(name_or_path));
    }
    let path = Path::new(name_or_path);
    let looks_like_path = name_or_path.contains(['/', '\\']) || path.extension().is_some();
    if !path.exists() && !looks_like_path {
        // Every built-in scene, the adhesive ones too (`gel`).
        let names: Vec<&str> = BUILTIN_NAMES
            .iter()
            .copied()
            .chain(crate::adhesive::scene::builtin_names())
            .collect();
        let allowed = format!("{}, or a path to a TOML scene file", names.join(", "));
        return Err(InputError::UnknownName {
            what: "scene",
            name: name_or_path.to_string(),
            suggestion: closest(name_or_path, names.iter().copied()),
            allowed,
        });
    }
    let text = std::fs::read_to_string(path).map_err(|e| file_error(name_or_path, e))?;
    from_toml_str(&text, name_or_path).map_err(|e| e.in_file(name_or_path))
}

/// A scene key set in its physical unit from the command line (`--set
/// K=2e5`, [`crate::overrides`]), applied before the scene is made
/// dimensionless.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneOverride {
    /// The scene key (`K`).
    pub key: &'static str,
    /// Its value, as the scene file would hold it.
    pub value: Value,
    /// As given, `K=2e5`, for messages.
    pub shown: String,
}

/// [`load`], with the scene keys of `overrides` replaced (or added) before
/// the scene is made dimensionless: `K` gives `kappa = K D0 / W` with the
/// scene's `D0` and `W`, `W` changes `kappa` and `m` together, and so on.
/// Setting `tau` selects the cutoff form (the scene's `mu2`, `mu_vv` and
/// `mu_vphi` are dropped, as `--set theta_c` does). An error of the scene so changed names the
/// overrides (`pmma with --set M=0: ...`).
pub fn load_with(name_or_path: &str, overrides: &[SceneOverride]) -> Result<Scene, InputError> {
    let base = load(name_or_path)?;
    if overrides.is_empty() {
        return Ok(base);
    }
    let (t, origin) = table_with(name_or_path, &base, overrides)?;
    from_table(t, &origin).map_err(|e| e.in_file(&origin))
}

/// The TOML table of the scene `base` loaded from `name_or_path` with the
/// keys of `overrides` replaced as [`load_with`] does, and its origin for
/// messages (`pmma with --set K=2e5`): the scene as a file would hold it.
pub fn table_with(
    name_or_path: &str,
    base: &Scene,
    overrides: &[SceneOverride],
) -> Result<(Table, String), InputError> {
    let text = match BUILTINS.iter().find(|(n, _)| *n == name_or_path) {
        Some((_, text)) => text.to_string(),
        None => std::fs::read_to_string(name_or_path).map_err(|e| file_error(name_or_path, e))?,
    };
    let mut t: Table = text.parse().map_err(|e| file_error(name_or_path, e))?;
    t.insert("name".into(), Value::String(base.name.clone()));
    for o in overrides {
        insert_override(&mut t, o);
    }
    if overrides.is_empty() {
        return Ok((t, name_or_path.to_string()));
    }
    let shown: Vec<&str> = overrides.iter().map(|o| o.shown.as_str()).collect();
    Ok((
        t,
        format!("{name_or_path} with --set {}", shown.join(" --set ")),
    ))
}

/// Sets the key of `o` in the scene table `t`; `tau` selects the cutoff
/// form and drops the keys of the logarithmic one ([`LOG_FORM_KEYS`]).
pub fn insert_override(t: &mut Table, o: &SceneOverride) {
    if o.key == "tau" {
        for key in LOG_FORM_KEYS {
            t.remove(key);
        }
    }
    t.insert(o.key.into(), o.value.clone());
}

/// Parses a scene from TOML text; `origin` (a file name) names it in errors
/// and gives the default scene name (its stem).
pub fn from_toml_str(text: &str, origin: &str) -> Result<Scene, InputError> {
    let t: Table = text.parse().map_err(|e| file_error(origin, e))?;
    from_table(t, origin)
}

/// A scene from its parsed TOML table; `origin` as for [`from_toml_str`].
fn from_table(t: Table, origin: &str) -> Result<Scene, InputError> {
    if law_in(&t)? == Law::Adhesive {
        return Err(adhesive_here(origin));
    }
    if let Some(key) = t.keys().find(|k| !KEYS.split(' ').any(|known| known == *k)) {
        let allowed = KEYS.replace(' ', ", ");
        if let Some(e) = other_law_key(
            key,
            &format!("key {key}"),
            Law::RateAndState,
            ("keys", &allowed),
        ) {
            return Err(e);
        }
        return Err(InputError::UnknownName {
            what: "scene key",
            name: key.clone(),
            suggestion: closest(key, KEYS.split(' ')),
            allowed: KEYS.replace(' ', ", "),
        });
    }
    let stem = Path::new(origin).file_stem().and_then(|s| s.to_str());
    let name = string(&t, "name")?.unwrap_or_else(|| stem.unwrap_or(origin).to_string());
    let description = string(&t, "description")?.unwrap_or_default();

    let missing_a = || file_error(origin, "the key A (direct effect, > 0) is required");
    let a = read(&t, "A", "> 0", "dimensionless")?.ok_or_else(missing_a)?;
    let b = read(&t, "B", ">= 0", "dimensionless")?.unwrap_or(0.0);
    let mu0 = read(&t, "mu0", "", "dimensionless")?.unwrap_or(0.6);
    let mut log_form = [0.0; 3];
    for (value, key) in log_form.iter_mut().zip(LOG_FORM_KEYS) {
        *value = read(&t, key, "", "dimensionless")?.unwrap_or(0.0);
    }
    let [mu2, mu_vv, mu_vphi] = log_form;
    let tau = read(&t, "tau", "> 0", "seconds")?;
    if let Some((key, _)) = LOG_FORM_KEYS
        .into_iter()
        .zip(log_form)
        .find(|(_, v)| tau.is_some() && *v != 0.0)
    {
        return Err(InputError::Conflict(format!(
            "{origin}: scene keys tau and {key} select different ageing forms \
             (short-age cutoff vs the logarithmic form of mu2, mu_vv, mu_vphi); give only one"
        )));
    }
    let state_law = match string(&t, "state_law")? {
        None => StateLaw::Ageing,
        Some(name) => StateLaw::parse(&name).ok_or_else(|| InputError::Malformed {
            field: format!("{origin}: state_law"),
            value: name,
            expected:
                "ageing (theta' = 1 - v theta, the default) or slip (theta' = -v theta ln(v theta))"
                    .into(),
        })?,
    };
    let d0 = read(&t, "D0", "> 0", "micrometres")?.unwrap_or(1.0);
    let v0 = read(&t, "V0", "> 0", "µm/s")?.unwrap_or(1.0);
    let mass = read(&t, "M", ">= 0", "kg")?.unwrap_or(1.0);
    let g = read(&t, "g", "> 0", "m/s^2")?.unwrap_or(9.81);
    let given_load = read(&t, "W", "> 0", "newtons")?;
    let load = match given_load {
        Some(w) => w,
        None if mass == 0.0 => {
            return Err(InputError::Conflict(format!(
                "{origin}: M = 0 leaves no weight to load the interface; give the load W [N]"
            )))
        }
        None => mass * g,
    };
    let k = read(&t, "K", ">= 0", "N/m")?;
    // Radiation damping eta = G / (2 c_s sigma), s/m (docs/model.md).
    let eta = read(&t, "eta", ">= 0", "s/m")?.unwrap_or(0.0);
    let v = read(&t, "V", "> 0", "µm/s")?.unwrap_or(v0);
    let (lo, hi) = t.get("V_range").map_or(Ok((0.1 * v, 100.0 * v)), v_range)?;

    let units = Units {
        d0: d0 * 1e-6,
        v0: v0 * 1e-6,
        mass,
        load,
        g,
        load_is_weight: given_load.is_none(),
    };
    let params = Params {
        kappa: k.map_or(0.0, |k| k * units.d0 / load),
        nu: v / v0,
        m: mass * units.v0 * units.v0 / (load * units.d0),
        a,
        b,
        mu0,
        mu2,
        theta_c: tau.map(|tau| tau * v0 / d0),
        state_law,
        mu_vv,
        mu_vphi,
        eta_d: eta * units.v0,
    };
    let nu_range = (lo / v0, hi / v0);
    let derived = [
        (if given_load.is_some() { "W" } else { "W = M g" }, load),
        ("kappa = K D0 / W", params.kappa),
        ("nu = V / V0", params.nu),
        ("m = M V0^2 / (W D0)", params.m),
        ("theta_c = tau V0 / D0", params.theta_c.unwrap_or(1.0)),
        ("eta_d = eta V0", params.eta_d),
        ("V_range[0] / V0", nu_range.0),
        ("V_range[1] / V0", nu_range.1),
    ];
    for (what, x) in derived {
        let (least, most) = crate::params::MAGNITUDE_RANGE;
        let ok = x.is_finite()
            && (x > 0.0 || !what.starts_with('V'))
            && (x == 0.0 || (least..=most).contains(&x.abs()));
        require(
            ok,
            what,
            x,
            "a finite (positive) number of magnitude 1e-100 to 1e100: the scene's units are too extreme",
        )?;
    }
    params.validate()?;
    let stiffness_given = k.is_some();
    Ok(Scene {
        name,
        description,
        params,
        units,
        stiffness_given,
        nu_range,
    })
}

/// A numeric key (integers accepted), `None` when absent; it must be finite
/// and satisfy `bound` ("> 0", ">= 0", or "" for any value).
pub(crate) fn read(
    t: &Table,
    key: &str,
    bound: &str,
    unit: &str,
) -> Result<Option<f64>, InputError> {
    let Some(value) = t.get(key) else {
        return Ok(None);
    };
    let x = number(key, value, unit)?;
    let ok = match bound {
        "> 0" => x > 0.0,
        ">= 0" => x >= 0.0,
        _ => true,
    };
    require(ok, key, x, &format!("{bound} ({unit})")).map(Some)
}

fn number(field: &str, value: &Value, unit: &str) -> Result<f64, InputError> {
    let x = match value {
        Value::Float(x) => *x,
        Value::Integer(i) => *i as f64,
        other => return Err(malformed(field, other, &format!("a number ({unit})"))),
    };
    require(
        x.is_finite(),
        field,
        x,
        &format!("a finite number ({unit})"),
    )
}

/// `V_range = [lo, hi]` in um/s, `0 < lo < hi`.
pub(crate) fn v_range(value: &Value) -> Result<(f64, f64), InputError> {
    let Some([lo, hi]) = value.as_array().map(Vec::as_slice) else {
        return Err(malformed(
            "V_range",
            value,
            "[lo, hi] in µm/s with 0 < lo < hi",
        ));
    };
    let lo = number("V_range[0]", lo, "µm/s")?;
    let hi = number("V_range[1]", hi, "µm/s")?;
    require(lo > 0.0, "V_range[0]", lo, "> 0 (µm/s)")?;
    require(
        hi > lo,
        "V_range[1]",
        hi,
        &format!("> V_range[0] = {lo} (µm/s)"),
    )?;
    Ok((lo, hi))
}

pub(crate) fn string(t: &Table, key: &str) -> Result<Option<String>, InputError> {
    match t.get(key) {
        None => Ok(None),
        Some(Value::String(s)) => Ok(Some(s.clone())),
        Some(other) => Err(malformed(key, other, "a string")),
    }
}

/// `x` if `ok`, else an out-of-range error naming `field`.
pub(crate) fn require(ok: bool, field: &str, x: f64, expected: &str) -> Result<f64, InputError> {
    ok.then_some(x)
        .ok_or_else(|| InputError::out_of_range(field, x, expected))
}

pub(crate) fn file_error(path: &str, reason: impl std::fmt::Display) -> InputError {
    InputError::File {
        path: path.into(),
        reason: reason.to_string().trim_end().into(),
    }
}

fn malformed(field: &str, value: &Value, expected: &str) -> InputError {
    let (field, value, expected) = (field.into(), value.to_string(), expected.into());
    InputError::Malformed {
        field,
        value,
        expected,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rel(a: f64, b: f64) -> f64 {
        ((a - b) / b).abs()
    }

    fn scene(text: &str) -> Scene {
        from_toml_str(text, "dir/test.toml").unwrap()
    }

    fn err(text: &str) -> String {
        from_toml_str(text, "test.toml")
            .expect_err(text)
            .to_string()
    }

    #[test]
    fn pmma_converts_to_hand_computed_numbers() {
        let s = builtin(DEFAULT_SCENE).unwrap();
        let (p, u) = (s.params, s.units);
        assert!(rel(p.m, 1e-12 / (9.81 * 0.4e-6)) < 1e-14, "m = {}", p.m);
        let expected = (1.0, 0.0, 0.012, 0.023, 0.5, 2.4e-4, None);
        assert_eq!((p.nu, p.kappa, p.a, p.b, p.mu0, p.mu2, p.theta_c), expected);
        assert!(!s.stiffness_given && s.name == "pmma");
        assert!(rel(s.nu_range.0, 0.1) < 1e-15 && rel(s.nu_range.1, 100.0) < 1e-15);
        assert!(rel(u.load, 9.81) < 1e-15 && rel(u.d0, 0.4e-6) < 1e-15);
        assert!(u.load_is_weight);
        // With W = M g, K/M = kappa g / D0.
        assert!(rel(u.k_over_m(0.011).unwrap(), 0.011 * 9.81 / 0.4e-6) < 1e-14);
        assert!(rel(u.k_over_w(0.011), 0.011 / 0.4e-6) < 1e-14);
        assert!(rel(u.frequency_hz(2.0 * std::f64::consts::PI), 2.5) < 1e-14);
        assert!(rel(u.nu_of_velocity_um_s(u.velocity_um_s(7.0)), 7.0) < 1e-14);
        assert_eq!(builtin("pmma-rr").unwrap().params, Params { mu2: 0.0, ..p });
    }

    #[test]
    fn the_corrections_in_ln_v_are_dimensionless_keys() {
        let s = scene("A = 0.012\nB = 0.023\nmu_vv = 1e-3\nmu_vphi = -5e-4\nV = 3");
        assert_eq!((s.params.mu_vv, s.params.mu_vphi), (1e-3, -5e-4));
        assert_eq!(
            (
                scene("A = 0.01").params.mu_vv,
                scene("A = 0.01").params.mu_vphi
            ),
            (0.0, 0.0)
        );
        // The direct effect at steady sliding, A + (2 mu_vv - mu_vphi) ln nu,
        // must stay positive: 0.01 + 2e-2 ln(0.1) < 0.
        let e = err("A = 0.01\nmu_vv = 1e-2\nV = 0.1");
        assert!(e.contains("mu_v = A + (2 mu_vv - mu_vphi) ln nu"), "{e}");
        assert!(err("A = 0.01\nmu_vv = 'x'").contains("mu_vv: cannot read"));
    }

    #[test]
    fn given_stiffness_and_load_convert() {
        let s = scene("A = 0.01\nK = 1e5\nM = 2\ng = 10\nD0 = 0.5\nV0 = 2\nV = 8");
        assert!(s.stiffness_given && s.name == "test" && s.params.nu == 4.0);
        // kappa = K D0 / W = 1e5 * 0.5e-6 / 20; back: K, K/M, K/W.
        assert!(rel(s.params.kappa, 2.5e-3) < 1e-14);
        assert!(rel(s.units.stiffness(s.params.kappa), 1e5) < 1e-14);
        assert!(rel(s.units.k_over_m(s.params.kappa).unwrap(), 5e4) < 1e-14);
        assert!(rel(s.units.k_over_w(s.params.kappa), 5e3) < 1e-14);
        assert!(rel(s.nu_range.0, 0.4) < 1e-15 && rel(s.nu_range.1, 400.0) < 1e-15);
        // Explicit W: m = M V0^2 / (W D0) = 2 * 4e-12 / (50 * 0.5e-6).
        let s = scene("A = 0.01\nM = 2\nW = 50\nD0 = 0.5\nV0 = 2\nK = 100");
        assert!(rel(s.params.m, 8e-12 / 2.5e-5) < 1e-14);
        assert!(rel(s.params.kappa, 100.0 * 0.5e-6 / 50.0) < 1e-14);
        assert!(!s.units.load_is_weight);
        // Massless block: W required, no K/M.
        let s = scene("A = 0.01\nM = 0\nW = 3");
        assert_eq!((s.params.m, s.units.k_over_m(1.0)), (0.0, None));
        assert!(err("A = 0.01\nM = 0").contains("load W"));
    }

    #[test]
    fn unknown_names_get_a_suggestion() {
        let e = err("A = 0.01\nV_rnage = [1, 2]");
        assert!(
            e.starts_with("unknown scene key 'V_rnage' (did you mean 'V_range'?)"),
            "{e}"
        );
        let e = load("pmmma").unwrap_err().to_string();
        assert!(e.contains("did you mean 'pmma'"), "{e}");
        let e = load("/nonexistent/scene.toml").unwrap_err();
        assert!(matches!(e, InputError::File { .. }), "{e}");
    }

    #[test]
    fn bad_values_name_the_field() {
        let e = err("A = 0.01\nD0 = -0.4");
        assert_eq!(e, "D0 = -0.4 is out of range: expected > 0 (micrometres)");
        for (text, field) in [
            ("A = 0.01\nM = nan", "M = NaN"),
            ("A = 0.01\nV = inf", "V = inf"),
            ("A = -0.01", "A = -0.01"),
            ("B = 0.1", "A (direct"),
            ("A = 0.01\nB = -1", "B = -1"),
            ("A = 0.01\nK = -3", "K = -3"),
            ("A = 0.01\ng = 0", "g = 0"),
            ("A = 'big'", "A: cannot read"),
            ("A = 0.01\nname = 3", "name: cannot read"),
            ("A = 0.01\nV_range = [10, 1]", "V_range[1] = 1"),
            ("A = 0.01\nV_range = [0, 1]", "V_range[0] = 0"),
            ("A = 0.01\nV_range = [1]", "V_range: cannot read"),
            ("A = 0.01\nV_range = [1, 'x']", "V_range[1]"),
            ("A = 0.01\nV = 1e300\nV0 = 1e-300", "nu = V / V0"),
            ("A = 0.01\nM = 1e308\ng = 100", "W = M g"),
            ("A = 0.01\nA = 0.02", "test.toml"),
        ] {
            let e = err(text);
            assert!(e.contains(field), "{text:?}: {e}");
        }
    }

    #[test]
    fn physical_overrides_apply_before_the_conversion() {
        let set = |key: &'static str, value: Value| SceneOverride {
            key,
            shown: format!("{key}={value}"),
            value,
        };
        // K: kappa = K D0 / W with the scene's D0 and W = M g.
        let s = load_with("pmma", &[set("K", Value::Float(2e5))]).unwrap();
        assert!(rel(s.params.kappa, 2e5 * 0.4e-6 / 9.81) < 1e-15);
        assert!(s.stiffness_given && s.name == "pmma");
        // tau selects the cutoff form, dropping the scene's mu2 (and
        // mu_vv, mu_vphi: a file's keys of the logarithmic form).
        let s = load_with("pmma", &[set("tau", Value::Float(0.4))]).unwrap();
        assert_eq!((s.params.mu2, s.params.theta_c), (0.0, Some(1.0)));
        let mut t: Table = "A = 0.01\nmu2 = 1e-4\nmu_vv = 2e-4\nmu_vphi = 3e-4"
            .parse()
            .unwrap();
        insert_override(&mut t, &set("tau", Value::Float(0.4)));
        let keys: Vec<&str> = t.keys().map(String::as_str).collect();
        assert_eq!(keys, ["A", "tau"]);
        // An error of the changed scene names the overrides.
        let e = load_with("pmma", &[set("M", Value::Float(0.0))]).unwrap_err();
        assert!(e.to_string().starts_with("pmma with --set M=0"), "{e}");
        assert_eq!(load_with("pmma", &[]).unwrap(), builtin("pmma").unwrap());
    }

    #[test]
    fn the_law_key_selects_the_family() {
        let s = scene("law = \"rate-and-state\"\nA = 0.01");
        assert_eq!(s.params, scene("A = 0.01").params);
        let e = err("law = \"adhesive\"\nF_a = 1");
        assert!(e.contains("adhesive scene"), "{e}");
        assert!(err("law = \"glue\"\nA = 0.01").contains("law: cannot read 'glue'"));
        assert_eq!(law_of("pmma").unwrap(), Law::RateAndState);
        assert_eq!(law_of("gel").unwrap(), Law::Adhesive);
        assert!(load("gel")
            .unwrap_err()
            .to_string()
            .contains("adhesive scene"));
    }

    #[test]
    fn tau_and_mu2_conflict() {
        let e = err("A = 0.01\ntau = 0.1\nmu2 = 1e-4");
        assert!(e.contains("tau") && e.contains("mu2"), "{e}");
        for key in ["mu_vv", "mu_vphi"] {
            let e = err(&format!("A = 0.01\ntau = 0.1\n{key} = -1e-4"));
            assert!(e.contains(&format!("scene keys tau and {key}")), "{e}");
        }
        let s = scene("A = 0.01\ntau = 0.1\nmu2 = 0\nD0 = 0.5\nV0 = 2");
        assert!(rel(s.params.theta_c.unwrap(), 0.4) < 1e-15);
    }

    #[test]
    fn brockley_v_min_is_2_mm_s_inside_the_range() {
        let s = builtin("brockley").unwrap();
        let nu_min = s.params.friction().v_min().unwrap();
        assert!(
            rel(s.units.velocity_um_s(nu_min), 2000.0) < 1e-12,
            "nu_min = {nu_min}"
        );
        assert!(s.nu_range.0 < nu_min && nu_min < s.nu_range.1);
        // Above V_min, and inertia dominant (m nu^2 / A = 191 at 3 mm/s).
        assert!(s.params.nu > nu_min);
        assert!(s.params.inertia_ratio() > 100.0 && s.params.inertia_ratio() < 300.0);
    }

    #[test]
    fn every_builtin_parses_validates_and_loads() {
        assert!(builtin_names().contains(&DEFAULT_SCENE));
        for &name in builtin_names() {
            let s = load(name).unwrap();
            assert!(s.name == name && !s.description.is_empty());
            assert!(s.params.validate().is_ok());
            assert!(s.nu_range.0 < s.params.nu && s.params.nu < s.nu_range.1);
            let path = format!("{}/examples/scenes/{name}.toml", env!("CARGO_MANIFEST_DIR"));
            assert_eq!(load(&path).unwrap(), s);
        }
    }
}
