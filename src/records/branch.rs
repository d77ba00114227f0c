//! The record of `branch`: one point of steady sliding continued in `kappa`
//! or `nu` (a row of its CSV, an entry of its JSON `points`), or a
//! bifurcation located between two points.

use crate::model::{full_state, ModelKind};
use crate::params::{Param, Params};
use crate::records::csv::CsvRecord;
use crate::scene::Units;
use continuation::{Complex64, EventKind};
use serde::ser::{SerializeMap, Serializer};
use serde::Serialize;

/// Eigenvalues a row has room for (the inertial block has three).
const EIGENVALUES: usize = 3;

/// A point of the branch: the continuation parameter, steady sliding there,
/// its eigenvalues, the bifurcation located there if any, and the point in
/// physical units. The CSV columns up to `omega` are those `branch --csv`
/// has always written; the physical ones follow.
#[derive(Clone, Debug, Default, Serialize)]
pub struct BranchRow {
    /// The continuation parameter, in a column named after it (`kappa` or `nu`).
    #[serde(flatten)]
    pub param: ParamValue,
    /// Spring force over the load, in units of the friction coefficient.
    pub s: f64,
    /// Slip velocity `v/V0`.
    pub v: f64,
    /// State (age) `theta`, units `D0/V0`.
    pub theta: f64,
    /// Number of eigenvalues with a positive real part; at a located
    /// bifurcation the critical ones are not counted ([`unstable_count`]).
    pub n_unstable: usize,
    #[serde(flatten)]
    pub eigenvalues: Eigenvalues,
    /// The bifurcation this row locates, if any.
    pub event: Option<BranchEvent>,
    /// Angular frequency at a Hopf point (units `V0/D0`).
    pub omega: Option<f64>,
    /// `K/W = kappa / D0` [1/m].
    #[serde(rename = "K_over_W_per_m")]
    pub k_over_w_per_m: f64,
    /// Driving velocity `V = nu V0` [µm/s] (in steady sliding, also the slip velocity).
    #[serde(rename = "V_um_per_s")]
    pub v_um_per_s: f64,
    /// Age `theta D0/V0` \[s\].
    pub theta_s: f64,
    /// `K/M` [1/s²]; `None` for a massless block.
    #[serde(rename = "K_over_M_per_s2")]
    pub k_over_m_per_s2: Option<f64>,
    /// Frequency at a Hopf point, `omega V0 / (2 pi D0)` \[Hz\].
    pub frequency_hz: Option<f64>,
    /// Spring stiffness `K = kappa W / D0` [N/m].
    #[serde(rename = "K_N_per_m")]
    pub k_n_per_m: f64,
    /// Spring force in steady sliding, `s W` \[N\].
    #[serde(rename = "spring_force_N")]
    pub spring_force_n: f64,
    /// The point's number in the run, from 0 in the order written (what
    /// `branch --from FILE.json --index N` and `hopf --from` name).
    pub label: usize,
}

impl CsvRecord for BranchRow {
    const DIGITS: usize = 15;
}

/// A bifurcation located on the branch.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum BranchEvent {
    /// A Hopf point: an oscillation (stick-slip) sets in or dies.
    Hopf,
    /// A fold: the branch turns.
    Fold,
}

impl BranchEvent {
    /// Its name in the CSV, the JSON and the text: `hopf` or `fold`.
    pub fn name(self) -> &'static str {
        match self {
            BranchEvent::Hopf => "hopf",
            BranchEvent::Fold => "fold",
        }
    }
}

/// The continuation parameter's value, serialized as one field named after
/// the parameter.
#[derive(Clone, Copy, Debug, Default)]
pub struct ParamValue {
    /// `kappa` or `nu`.
    pub name: &'static str,
    /// Its value.
    pub value: f64,
}

impl Serialize for ParamValue {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut map = s.serialize_map(Some(1))?;
        map.serialize_entry(self.name, &self.value)?;
        map.end()
    }
}

/// The eigenvalues by decreasing real part, `eig_re_i`, `eig_im_i` for
/// `i = 1..3`; `None` beyond the model's dimension.
#[derive(Clone, Copy, Debug, Default)]
pub struct Eigenvalues(pub [Option<Complex64>; EIGENVALUES]);

impl Serialize for Eigenvalues {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        let mut map = s.serialize_map(Some(2 * EIGENVALUES))?;
        for (i, l) in self.0.iter().enumerate() {
            map.serialize_entry(&format!("eig_re_{}", i + 1), &l.map(|l| l.re))?;
            map.serialize_entry(&format!("eig_im_{}", i + 1), &l.map(|l| l.im))?;
        }
        map.end()
    }
}

impl BranchRow {
    /// The point `x` of the `kind` model at the parameters `at`, continued
    /// in `param`, with its eigenvalues `ev` and the bifurcation `event`
    /// located there, in the units `u`.
    pub fn new(
        kind: ModelKind,
        at: &Params,
        param: Param,
        x: &[f64],
        ev: &[Complex64],
        event: Option<&EventKind>,
        u: &Units,
    ) -> Self {
        let state = full_state(kind, at, x);
        let mut eigenvalues = [None; EIGENVALUES];
        for (slot, l) in eigenvalues.iter_mut().zip(ev) {
            *slot = Some(*l);
        }
        let omega = match event {
            Some(EventKind::Hopf { omega }) => Some(*omega),
            _ => None,
        };
        BranchRow {
            param: ParamValue {
                name: param.name(),
                value: at.get(param),
            },
            s: state[0],
            v: state[1],
            theta: state[2],
            n_unstable: unstable_count(ev, event.is_some()),
            eigenvalues: Eigenvalues(eigenvalues),
            event: event.map(|e| match e {
                EventKind::Hopf { .. } => BranchEvent::Hopf,
                EventKind::Fold { .. } => BranchEvent::Fold,
            }),
            omega,
            k_over_w_per_m: u.k_over_w(at.kappa),
            v_um_per_s: u.velocity_um_s(at.nu),
            theta_s: state[2] * u.d0 / u.v0,
            k_over_m_per_s2: u.k_over_m(at.kappa),
            frequency_hz: omega.map(|w| u.frequency_hz(w)),
            k_n_per_m: u.stiffness(at.kappa),
            spring_force_n: state[0] * u.load,
            label: 0,
        }
    }
}

/// The eigenvalues of `ev` with a positive real part. At a located
/// bifurcation (`at_event`) the critical eigenvalues, those of least `|re|`
/// (a real one at a fold, a complex pair at a Hopf point), have a zero real
/// part by construction and the sign rounding gives them: they are left out.
fn unstable_count(ev: &[Complex64], at_event: bool) -> usize {
    let critical = at_event
        .then(|| ev.iter().map(|l| l.re.abs()).fold(f64::INFINITY, f64::min))
        .filter(|m| m.is_finite());
    ev.iter()
        .filter(|l| l.re > 0.0 && critical.is_none_or(|m| l.re.abs() > m))
        .count()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::records::csv::{header_of, row};

    /// The columns `branch --csv` has always written come first, in their
    /// order, the parameter's named after it; `None` is an empty cell.
    #[test]
    fn columns_keep_their_names_and_order() {
        let r = BranchRow {
            param: ParamValue {
                name: "nu",
                value: 2.0,
            },
            ..BranchRow::default()
        };
        assert_eq!(
            header_of(&r).unwrap(),
            "nu,s,v,theta,n_unstable,eig_re_1,eig_im_1,eig_re_2,eig_im_2,eig_re_3,eig_im_3,\
             event,omega,K_over_W_per_m,V_um_per_s,theta_s,K_over_M_per_s2,frequency_hz,\
             K_N_per_m,spring_force_N,label"
        );
        assert!(row(&r).unwrap().starts_with("2.000000000000000e0,"));
    }

    /// At a located Hopf point the critical pair's real part is rounding
    /// (+5.6e-17 in a run of a steel-on-granite rig): it is not counted;
    /// away from a bifurcation every positive real part is.
    #[test]
    fn the_critical_pair_at_a_hopf_point_is_not_counted_unstable() {
        let ev = [
            Complex64::new(5.55e-17, 0.38),
            Complex64::new(5.55e-17, -0.38),
            Complex64::new(-2.0, 0.0),
        ];
        assert_eq!(unstable_count(&ev, true), 0);
        assert_eq!(unstable_count(&ev, false), 2);
        let past = [
            Complex64::new(1e-3, 0.38),
            Complex64::new(1e-3, -0.38),
            Complex64::new(0.5, 0.0),
            Complex64::new(-1e-16, 0.0),
        ];
        // At a fold the real eigenvalue nearest zero is the critical one.
        assert_eq!(unstable_count(&past, true), 3);
    }
}
