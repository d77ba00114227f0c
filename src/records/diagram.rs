//! The records of the stability diagram: the points of the Hopf curve, its
//! special points, the velocity-strengthening stretches, the points of the
//! curves of folds of cycles (also those of `cycles --lpc-curve`) and the
//! stretches where those curves were not computed.

use super::PhysicalPoint;
use crate::analysis::diagram::{self, SpecialKind, StabilityDiagram};
use crate::analysis::hopf::Criticality;
use crate::analysis::lpc_curve::LpcCurves;
use crate::appendix_c;
use crate::params::Params;
use crate::records::csv::CsvRecord;
use crate::scene::Units;
use serde::Serialize;
use std::f64::consts::TAU;

/// The records of a stability diagram, built once for its CSV, JSON and text.
#[derive(Clone, Debug)]
pub struct DiagramRecords {
    pub curve: Vec<HopfCurvePoint>,
    pub special: Vec<SpecialPoint>,
    pub folds: Vec<FoldPoint>,
    pub strengthening: Vec<VelocitySpan>,
    /// Where a fold-of-cycles curve stopped short: the hysteretic region
    /// there is unknown, not absent.
    pub fold_gaps: Vec<VelocitySpan>,
}

impl DiagramRecords {
    /// The records of `d`, the diagram of `params`, in the units `u`.
    pub fn new(d: &StabilityDiagram, params: &Params, u: &Units) -> Self {
        DiagramRecords {
            curve: d
                .points
                .iter()
                .map(|p| HopfCurvePoint::new(p, params, u))
                .collect(),
            special: d.special.iter().map(|s| SpecialPoint::new(s, u)).collect(),
            folds: FoldPoint::all(&d.lpc, u),
            strengthening: d
                .strengthening
                .iter()
                .map(|&stretch| VelocitySpan::new(stretch, u))
                .collect(),
            fold_gaps: d
                .lpc
                .gaps
                .iter()
                .map(|&gap| VelocitySpan::new(gap, u))
                .collect(),
        }
    }
}

/// A point of the Hopf curve (the stability boundary) at one driving
/// velocity: a row of `-hopf-curve.csv`, an entry of `hopf_curve`.
#[derive(Clone, Debug, Default, Serialize)]
pub struct HopfCurvePoint {
    pub nu: f64,
    /// Critical stiffness `kappa_c` at `nu`.
    pub kappa: f64,
    /// Angular frequency at onset (units `V0/D0`).
    pub omega: f64,
    /// First Lyapunov coefficient.
    pub l1: f64,
    pub criticality: Criticality,
    /// `kappa_c` of Appendix C (eq. C11/C12) at `nu`.
    pub kappa_appendix_c: f64,
    #[serde(flatten)]
    pub physical: PhysicalPoint,
    /// Bound on the rounding error of `l1`.
    pub l1_error_bound: f64,
    /// `omega_c` of Appendix C (eq. C13) at `nu`.
    pub omega_appendix_c: Option<f64>,
    /// Critical spring stiffness `K_c = kappa W / D0` [N/m].
    #[serde(rename = "K_N_per_m")]
    pub k_n_per_m: f64,
}

impl CsvRecord for HopfCurvePoint {
    const DIGITS: usize = 15;
}

impl HopfCurvePoint {
    /// The point `p` of the curve of `params` (its velocity varying).
    pub fn new(p: &diagram::CurvePoint, params: &Params, u: &Units) -> Self {
        let mut at = *params;
        at.nu = p.nu;
        HopfCurvePoint {
            nu: p.nu,
            kappa: p.kappa,
            omega: p.omega,
            l1: p.l1,
            criticality: p.criticality,
            kappa_appendix_c: appendix_c::critical_stiffness(&at),
            physical: PhysicalPoint::new(u, p.nu, p.kappa, p.omega),
            l1_error_bound: p.l1_error_bound,
            omega_appendix_c: appendix_c::critical_frequency(&at),
            k_n_per_m: u.stiffness(p.kappa),
        }
    }
}

/// A special point of the Hopf curve: a Bautin point (the onset changes
/// type) or its end at the friction minimum (an entry of `special_points`).
#[derive(Clone, Debug, Serialize)]
pub struct SpecialPoint {
    pub kind: SpecialKind,
    pub nu: f64,
    pub kappa: f64,
    pub omega: f64,
    #[serde(flatten)]
    pub physical: PhysicalPoint,
    /// Second Lyapunov coefficient (Bautin points).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub l2: Option<f64>,
    /// Bound on the rounding error of `l2`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub l2_error_bound: Option<f64>,
    /// Spring stiffness `K = kappa W / D0` [N/m].
    #[serde(rename = "K_N_per_m")]
    pub k_n_per_m: f64,
}

impl SpecialPoint {
    /// The special point `s` in the units `u`.
    pub fn new(s: &diagram::SpecialPoint, u: &Units) -> Self {
        SpecialPoint {
            kind: s.kind,
            nu: s.nu,
            kappa: s.kappa,
            omega: s.omega,
            physical: PhysicalPoint::new(u, s.nu, s.kappa, s.omega),
            l2: s.l2,
            l2_error_bound: s.l2_error_bound,
            k_n_per_m: u.stiffness(s.kappa),
        }
    }
}

/// A stretch of driving velocities: an entry of `velocity_strengthening`
/// (steady friction velocity strengthening there, stable for every
/// stiffness) or of `lpc_gaps` (a fold-of-cycles curve not computed there).
#[derive(Clone, Debug, Serialize)]
pub struct VelocitySpan {
    pub nu_from: f64,
    pub nu_to: f64,
    #[serde(rename = "V_from_um_per_s")]
    pub v_from_um_per_s: f64,
    #[serde(rename = "V_to_um_per_s")]
    pub v_to_um_per_s: f64,
}

impl VelocitySpan {
    /// The stretch `nu_from .. nu_to` in the units `u`.
    pub fn new((nu_from, nu_to): (f64, f64), u: &Units) -> Self {
        VelocitySpan {
            nu_from,
            nu_to,
            v_from_um_per_s: u.velocity_um_s(nu_from),
            v_to_um_per_s: u.velocity_um_s(nu_to),
        }
    }
}

/// A fold of cycles on a curve of folds (the hysteresis boundary): a row of
/// `-lpc-curve.csv`, an entry of `lpc_curve`.
#[derive(Clone, Debug, Default, Serialize)]
pub struct FoldPoint {
    /// Which curve (numbered from 0).
    pub curve: usize,
    pub nu: f64,
    pub kappa: f64,
    /// Period of the cycle at the fold (units `D0/V0`).
    pub period: f64,
    /// Peak-to-peak spring force of the cycle at the fold.
    pub delta_s: f64,
    /// The fold in physical units, with the frequency of its cycle.
    #[serde(flatten)]
    pub physical: PhysicalPoint,
    /// Period of the cycle at the fold \[s\].
    pub period_s: f64,
    /// Its peak-to-peak spring force, `Delta_s W` \[N\].
    #[serde(rename = "delta_s_N")]
    pub delta_s_n: f64,
    /// Spring stiffness `K = kappa W / D0` [N/m].
    #[serde(rename = "K_N_per_m")]
    pub k_n_per_m: f64,
}

impl CsvRecord for FoldPoint {
    const DIGITS: usize = 15;
}

impl FoldPoint {
    /// Every point of every curve of `curves`, curve after curve.
    pub fn all(curves: &LpcCurves, u: &Units) -> Vec<FoldPoint> {
        curves
            .points
            .iter()
            .enumerate()
            .flat_map(|(curve, points)| points.iter().map(move |p| (curve, p)))
            .map(|(curve, p)| FoldPoint {
                curve,
                nu: p.nu,
                kappa: p.kappa,
                period: p.period,
                delta_s: p.delta_s,
                physical: PhysicalPoint::new(u, p.nu, p.kappa, TAU / p.period),
                period_s: p.period * u.d0 / u.v0,
                delta_s_n: p.delta_s * u.load,
                k_n_per_m: u.stiffness(p.kappa),
            })
            .collect()
    }
}
