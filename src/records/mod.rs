//! The records the commands present, one definition each: the points of
//! `branch`, the onset of `hopf`, the points of the stability diagram and of its fold curves, the
//! stick-slip cycles, the rows of a simulation. Each is built once from an
//! analysis result and the scene's units, in docs/model.md's variables and
//! in physical units. Serde gives the JSON (the record itself) and the CSV
//! (header: its field names; rows: the same serialization, [`csv`]);
//! the text lines select and format its fields.

pub mod branch;
pub mod csv;
pub mod cycle;
pub mod diagram;
pub mod hopf;
pub mod orbit;
pub mod simulation;

use crate::scene::Units;
use serde::Serialize;

/// A point of a diagram (a Hopf point, a fold of cycles) in physical units:
/// the driving velocity, the stiffness over the load and over the mass, and
/// the frequency of the oscillation there.
#[derive(Clone, Debug, Default, Serialize)]
pub struct PhysicalPoint {
    /// Driving velocity `V = nu V0` [µm/s].
    #[serde(rename = "V_um_per_s")]
    pub v_um_per_s: f64,
    /// `K/W = kappa / D0` [1/m].
    #[serde(rename = "K_over_W_per_m")]
    pub k_over_w_per_m: f64,
    /// `K/M` [1/s²]; `None` for a massless block.
    #[serde(rename = "K_over_M_per_s2")]
    pub k_over_m_per_s2: Option<f64>,
    /// Frequency `omega V0 / (2 pi D0)` \[Hz\].
    pub frequency_hz: f64,
}

impl PhysicalPoint {
    /// The point `(nu, kappa)` with the angular frequency `omega` in the units `u`.
    pub fn new(u: &Units, nu: f64, kappa: f64, omega: f64) -> Self {
        PhysicalPoint {
            v_um_per_s: u.velocity_um_s(nu),
            k_over_w_per_m: u.k_over_w(kappa),
            k_over_m_per_s2: u.k_over_m(kappa),
            frequency_hz: u.frequency_hz(omega),
        }
    }
}

/// `v` with five significant digits: fixed notation between `1e-3` and
/// `1e6`, scientific outside (a small velocity is never printed as `0.0000`).
pub fn significant(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 || !a.is_finite() {
        return format!("{v}");
    }
    if (1e-3..1e6).contains(&a) {
        let decimals = (4 - a.log10().floor() as i32).max(0) as usize;
        format!("{v:.decimals$}")
    } else {
        format!("{v:.4e}")
    }
}

/// Formats parameters as `name = value` pairs on one line.
pub fn describe_params(p: &crate::params::Params) -> String {
    describe_params_except(p, None)
}

/// [`describe_params`] without the parameter `left_out`.
pub fn describe_params_except(
    p: &crate::params::Params,
    left_out: Option<crate::params::Param>,
) -> String {
    let left_out = left_out.map(crate::params::Param::name);
    let listed = p
        .named()
        .iter()
        .filter(|(n, _)| Some(*n) != left_out)
        .map(|(n, v)| format!("{n} = {v:.6e}"))
        .collect::<Vec<_>>()
        .join(", ");
    format!("{listed}; {} state law", p.state_law.name())
}

/// The units of a result: the scene's length and velocity scales.
#[derive(Clone, Debug, Serialize)]
pub struct UnitsRecord {
    #[serde(rename = "D0_um")]
    pub d0_um: f64,
    #[serde(rename = "V0_um_per_s")]
    pub v0_um_per_s: f64,
}

impl UnitsRecord {
    /// The units `u`.
    pub fn of(u: &Units) -> Self {
        UnitsRecord {
            d0_um: u.d0 * 1e6,
            v0_um_per_s: u.velocity_um_s(1.0),
        }
    }
}

/// Parameters as a JSON object (names of docs/model.md), with the state
/// law by name (`state_law`: `ageing` or `slip`).
pub fn params_json(p: &crate::params::Params) -> serde_json::Value {
    serde_json::Value::Object(
        p.named()
            .into_iter()
            .map(|(n, v)| (n.to_string(), serde_json::json!(v)))
            .chain([("state_law".into(), p.state_law.name().into())])
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::branch::BranchEvent;
    use crate::analysis::diagram::SpecialKind;
    use crate::analysis::hopf::{Arithmetic, Criticality};
    use crate::model::ModelKind;

    /// A value's JSON string.
    fn json(v: impl serde::Serialize) -> String {
        serde_json::to_value(v)
            .unwrap()
            .as_str()
            .unwrap()
            .to_string()
    }

    /// The kinds are written in JSON and CSV by serde and in the text by
    /// their names: the same words.
    #[test]
    fn kinds_have_one_name_in_json_csv_and_text() {
        for (kind, name) in [
            (json(ModelKind::Inertial), ModelKind::Inertial.name()),
            (json(ModelKind::QuasiStatic), ModelKind::QuasiStatic.name()),
            (
                json(Criticality::Supercritical),
                Criticality::Supercritical.name(),
            ),
            (
                json(Criticality::Subcritical),
                Criticality::Subcritical.name(),
            ),
            (
                json(Criticality::Degenerate),
                Criticality::Degenerate.name(),
            ),
            (json(Arithmetic::Double), Arithmetic::Double.name()),
            (
                json(Arithmetic::DoubleDouble),
                Arithmetic::DoubleDouble.name(),
            ),
            (json(SpecialKind::Bautin), SpecialKind::Bautin.name()),
            (json(SpecialKind::Endpoint), SpecialKind::Endpoint.name()),
            (json(BranchEvent::Hopf), BranchEvent::Hopf.name()),
            (json(BranchEvent::Fold), BranchEvent::Fold.name()),
        ] {
            assert_eq!(kind, name);
        }
    }
}
