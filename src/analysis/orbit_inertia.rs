//! How much inertia matters on an orbit, measured along the orbit itself,
//! and the quasi-static cycle handed over to the inertial model.
//!
//! The quasi-static reduction sets `s = mu(v, theta)`: the block's inertia
//! force `m dv/dt` is dropped from `m dv/dt = s - mu`. Restored, it shifts
//! the friction balance by `m dv/dt`, which the rate dependence of `mu`
//! absorbs with a change of `ln v` by
//!
//! ```text
//! chi = max over the orbit of  m |dv/dt| / mu_v  =  m v |d ln v / dt| / mu_v
//! ```
//!
//! with `mu_v = d mu / d ln v = A + 2 mu_vv ln v + mu_vphi ln theta` at the
//! state (`A` without the corrections of docs/model.md; plus `eta_d v` with
//! radiation damping, which resists beside `mu`): the relative error
//! the reduction makes in the slip velocity where it matters most. On the
//! inertial model the same number is `|s - mu| / mu_v`, the imbalance the
//! inertial orbit actually carries; where it passes through `mu_v <= 0`,
//! which no quasi-static state does, `chi` is infinite (the records say
//! `n/a`, with the reason). Together with the
//! linear criterion at onset (`m nu^2 / mu_v`, [`super::model_choice`]),
//! which covers small oscillations, it decides the model along a branch:
//! the quasi-static model holds on an orbit while both are below the same
//! threshold ([`super::model_choice::DEFAULT_INERTIA_THRESHOLD`]). The study
//! behind the threshold is in `docs/cycles.md`.

use crate::log_model::LogBlock;
use crate::model::ModelKind;
use crate::params::{friction_from, Param, Params};
use continuation::periodic::Cycle;
use continuation::system::VectorField;

/// Orbit samples per mesh interval for [`inertial_imbalance`]: the adapted
/// mesh already concentrates intervals on the slip.
const SAMPLES_PER_INTERVAL: usize = 8;

/// `chi = max m v |d ln v/dt| / mu_v` over the orbit `cycle` of `log`
/// (module documentation), for the inertia `m` (the scene's, also when the
/// orbit is quasi-static): [`state_imbalance`] at the orbit's samples.
pub fn inertial_imbalance(log: &LogBlock, cycle: &Cycle, m: f64) -> f64 {
    let mut chi = 0.0f64;
    cycle.each_sample(SAMPLES_PER_INTERVAL, |_, x| {
        chi = chi.max(state_imbalance(log, x, &cycle.p, m));
    });
    chi
}

/// `m v |d ln v/dt| / mu_v` at the state `x` of `log` with parameters `p`,
/// `mu_v = d mu / d ln v` there (infinite where `mu_v <= 0`). The
/// time derivative of `ln v` is the state's own (inertial: it is a
/// variable) or its derivative along the flow by a central difference
/// (quasi-static: `ln v` is a function of the state).
pub fn state_imbalance(log: &LogBlock, x: &[f64], p: &[f64], m: f64) -> f64 {
    // At most 3 states: on the stack (this runs at every sample of every orbit).
    let mut f = [0.0; 3];
    let f = &mut f[..log.dim()];
    log.rhs(x, p, f);
    let rate = match log.kind {
        ModelKind::Inertial => f[1],
        ModelKind::QuasiStatic => {
            let size = x.iter().fold(1.0f64, |s, v| s.max(v.abs()));
            let speed = f.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            if speed == 0.0 {
                0.0
            } else {
                let h = 1e-7 * size / speed;
                let at = |sign: f64| {
                    let y: Vec<f64> = x
                        .iter()
                        .zip(f.iter())
                        .map(|(xi, fi)| xi + sign * h * fi)
                        .collect();
                    log.ln_velocity(&y, p)
                };
                (at(1.0) - at(-1.0)) / (2.0 * h)
            }
        }
    };
    let ln_v = log.ln_velocity(x, p);
    let ln_theta = log.origin()[2] + x[x.len() - 1];
    // The slope in ln v of the force the block meets, mu + eta_d v.
    let law = friction_from(log.cutoff, p);
    let mu_v = law.rate_coefficient(2.0 * ln_v, ln_theta) + law.damping(ln_v.exp());
    if mu_v.is_nan() || mu_v <= 0.0 {
        return f64::INFINITY;
    }
    m * ln_v.exp() * rate.abs() / mu_v
}

/// The quasi-static state `x = (s, ln theta)` as the inertial one
/// `(s, ln v, ln theta)`, both measured from the origin of `quasi_static`,
/// `ln v` from the quasi-static slaving (exact in the log variable, also
/// where `v` itself underflows).
pub fn inertial_state(quasi_static: &LogBlock, x: &[f64], p: &[f64]) -> [f64; 3] {
    let w_o = quasi_static.origin()[1];
    [x[0], quasi_static.ln_velocity(x, p) - w_o, x[1]]
}

/// The quasi-static orbit `cycle` (state `(s, ln theta)`) as a first guess
/// for the inertial model with inertia `m` (state `(s, ln v, ln theta)`):
/// the same mesh and period, `ln v` the quasi-static slaving at every node.
/// Where the reduction still nearly holds (`chi` at the threshold), Newton's
/// method on the inertial collocation system converges from it.
pub fn inertial_guess(quasi_static: &LogBlock, cycle: &Cycle, m: f64) -> Cycle {
    let mut p = cycle.p.clone();
    p[Param::M as usize] = m;
    let u = (0..cycle.mesh.n_nodes())
        .flat_map(|g| inertial_state(quasi_static, cycle.node(g), &cycle.p))
        .collect();
    Cycle {
        mesh: cycle.mesh.clone(),
        u,
        period: cycle.period,
        p,
        n: 3,
    }
}

/// The model a cycle branch starts in and whether it may hand over to the
/// inertial one.
#[derive(Clone, Copy, Debug)]
pub struct InertiaWatch {
    /// The scene's inertia (kept when the branch is quasi-static).
    pub m: f64,
    /// Rate coefficient `A` (the relaxation rate `A / (m v)` of a stuck
    /// inertial block, in a message).
    pub a: f64,
    /// Largest `chi` for which the quasi-static model holds.
    pub threshold: f64,
    /// Whether a quasi-static branch switches to the inertial model when
    /// `chi` exceeds the threshold (not under `--model`, not without inertia).
    pub switch: bool,
}

impl InertiaWatch {
    /// The watch for the scene's parameters `scene`; `switch` as above.
    pub fn new(scene: &Params, threshold: f64, switch: bool) -> Self {
        InertiaWatch {
            m: scene.m,
            a: scene.a,
            threshold,
            switch: switch && scene.m > 0.0,
        }
    }
}
