//! Which stiffness to simulate at when a cycle branch starts from a
//! simulated orbit, and the search over those stiffnesses.
//!
//! A stick-slip cycle that coexists with stable steady sliding (no Hopf
//! point, or above a subcritical one) is reached only from far away, and
//! only where it exists: at small stiffness the stick phases are long, the
//! interface ages well past the cutoff and the ageing gained in a stick,
//! `B ln(theta/theta_c)`, outgrows the rate strengthening of the slip,
//! `A ln v`. The stiffnesses tried, in order:
//!
//! 1. the scene's own `kappa`, when it gives one;
//! 2. `0.9 kappa_c` below a Hopf point, where steady sliding is unstable;
//! 3. `b 10^-k`, `k = 1..=5`, with `b = max(A, B)` — the scale of
//!    `kappa_c = (mu_phi - mu_v)(1 + m nu^2/mu_v)` without inertia.
//!
//! Each is simulated from [`stuck_start`]; the first whose return map
//! settles is used, in the model the whole orbit needs
//! ([`settled_with_inertia_judged`]: a quasi-static orbit on which inertia
//! matters is settled again with the scene's inertia).

use super::joined_flow::State;
use super::model_choice::params_for;
use super::orbit_inertia::InertiaWatch;
use super::return_map;
use super::settle::{settle, stuck_start, SettleError, SettleSettings, SettledOrbit};
use super::simulate::{settled_with_inertia_judged, JudgedOrbit};
use crate::model::ModelKind;
use crate::params::Params;
use thiserror::Error;

/// Decades of stiffness below `max(A, B)` tried when nothing else is given.
const DECADES: i32 = 5;

/// The stiffnesses to try for `params`, with the Hopf point `kappa_c` if any.
pub fn candidate_stiffnesses(params: &Params, kappa_c: Option<f64>) -> Vec<f64> {
    let b = params.a.max(params.b);
    let mut out: Vec<f64> = [params.kappa, kappa_c.map_or(0.0, |k| 0.9 * k)]
        .into_iter()
        .filter(|k| *k > 0.0)
        .collect();
    out.extend((1..=DECADES).map(|k| b * 10f64.powi(-k)));
    out
}

/// An orbit settled by simulation and the parameters it belongs to.
#[derive(Clone, Debug)]
pub struct OrbitStart {
    /// The model of the orbit (the inertial one where the quasi-static
    /// orbit needs it).
    pub kind: ModelKind,
    /// The model's parameters, `kappa` the stiffness simulated.
    pub params: Params,
    pub orbit: SettledOrbit,
    /// The stiffnesses tried before, and why they gave no cycle.
    pub rejected: Vec<SettleError>,
}

/// No stiffness tried gave a cycle.
#[derive(Clone, Debug, Error, PartialEq)]
#[error(
    "no stick-slip cycle found by simulation from a stuck state: {}. Stick-slip coexists with \
     stable sliding only at small enough stiffness and, above the friction minimum V_min, only in \
     a band of velocities close to it: try a smaller --set kappa=..., or --set nu=... closer to V_min",
    .tries.iter().map(SettleError::summary).collect::<Vec<_>>().join("; ")
)]
pub struct NoCycleFound {
    pub tries: Vec<SettleError>,
}

/// The orbit a simulation from a stuck start settles on at the stiffness
/// `kappa`: in the model `kind` on the scene's parameters `scene` (inertia
/// kept), the model then judged on the settled orbit under `watch`
/// ([`settled_with_inertia_judged`]).
pub fn settled_at(
    kind: ModelKind,
    scene: &Params,
    kappa: f64,
    watch: &InertiaWatch,
) -> Result<JudgedOrbit, SettleError> {
    let params_of = |k: ModelKind| Params {
        kappa,
        ..params_for(k, scene)
    };
    let p = params_of(kind);
    let settings = SettleSettings::for_params(&p);
    let start = stuck_start(&p);
    settle(kind, &p, start, &settings)
        .or_else(|e| match e {
            // An inertial stop the integration cannot follow: the joined
            // flow, its sticks below v_b quasi-static.
            SettleError::Integration { .. } if kind == ModelKind::Inertial && p.m > 0.0 => {
                let state = State::Slipping([start[0], start[1].ln(), start[2].ln()]);
                return_map::settle(&p, state, &settings).map_err(|_| e)
            }
            e => Err(e),
        })
        .and_then(|orbit| {
            settled_with_inertia_judged(
                kind,
                params_of,
                orbit,
                watch,
                settings.rtol,
                SettleSettings::for_params,
            )
        })
}

/// Simulates at each of [`candidate_stiffnesses`] until one settles on a
/// cycle ([`settled_at`]).
pub fn simulated_start(
    kind: ModelKind,
    scene: &Params,
    kappa_c: Option<f64>,
    watch: &InertiaWatch,
) -> Result<OrbitStart, NoCycleFound> {
    let mut rejected = Vec::new();
    for kappa in candidate_stiffnesses(&params_for(kind, scene), kappa_c) {
        match settled_at(kind, scene, kappa, watch) {
            Ok(judged) => {
                return Ok(OrbitStart {
                    kind: judged.kind,
                    params: judged.params,
                    orbit: judged.orbit,
                    rejected,
                })
            }
            Err(e) => rejected.push(e),
        }
    }
    Err(NoCycleFound { tries: rejected })
}
