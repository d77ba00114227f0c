//! The dimensionless parameters of the adhesive block (docs/model.md, "Soft
//! adhesive contacts"): velocities in `V_s`, times in `tau_out`, forces in
//! `F_a`.
//!
//! | name | definition | meaning |
//! |---|---|---|
//! | `kappa` | `K V_s tau_out / F_a` | spring stiffness |
//! | `nu` | `V / V_s` | driving velocity |
//! | `r` | `tau_on / tau_out` | readsorption over desorption time (seed's `tau / tau_out`) |
//! | `f_v` | `F_v / F_a` | junction viscosity |
//! | `alpha` | | shear thinning of the junction (0: Newtonian) |
//! | `m` | `M V_s / (F_a tau_out)` | inertia (the inertial block, [`super::block::InertialAdhesiveBlock`]) |

use crate::error::InputError;

/// Index of each parameter in the vector handed to the engine. The
/// stiffness is index 0, as for the rate-and-state block, so the onset's
/// normal form ([`crate::analysis::hopf::onset_at`]) serves both.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum AdhesiveParam {
    Kappa = 0,
    Nu = 1,
    R = 2,
    Fv = 3,
    Alpha = 4,
    /// Inertia `m`, read by the inertial block only.
    M = 5,
}

/// Number of entries in the engine's parameter vector.
pub const N_ADHESIVE_PARAMS: usize = 6;

impl AdhesiveParam {
    /// Every parameter, in vector order.
    pub const ALL: [AdhesiveParam; N_ADHESIVE_PARAMS] = [
        AdhesiveParam::Kappa,
        AdhesiveParam::Nu,
        AdhesiveParam::R,
        AdhesiveParam::Fv,
        AdhesiveParam::Alpha,
        AdhesiveParam::M,
    ];

    /// The name in messages and JSON.
    pub fn name(self) -> &'static str {
        match self {
            AdhesiveParam::Kappa => "kappa",
            AdhesiveParam::Nu => "nu",
            AdhesiveParam::R => "r",
            AdhesiveParam::Fv => "f_v",
            AdhesiveParam::Alpha => "alpha",
            AdhesiveParam::M => "m",
        }
    }
}

/// The dimensionless parameters of the adhesive block.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct AdhesiveParams {
    pub kappa: f64,
    pub nu: f64,
    /// `tau_on / tau_out`.
    pub r: f64,
    /// `F_v / F_a`.
    pub f_v: f64,
    pub alpha: f64,
    /// `M V_s / (F_a tau_out)`.
    pub m: f64,
}

impl AdhesiveParams {
    /// The engine's parameter vector ([`AdhesiveParam`] order).
    pub fn to_vec(&self) -> Vec<f64> {
        vec![self.kappa, self.nu, self.r, self.f_v, self.alpha, self.m]
    }

    /// Checks every value, naming the dimensionless parameter and the scene
    /// key it comes from.
    pub fn validate(&self) -> Result<(), InputError> {
        let checks = [
            (
                "kappa = K V_s tau_out / F_a",
                self.kappa,
                self.kappa >= 0.0,
                ">= 0",
            ),
            ("nu = V / V_s", self.nu, self.nu > 0.0, "> 0"),
            ("r = tau_on / tau_out", self.r, self.r > 0.0, "> 0"),
            ("f_v = F_v / F_a", self.f_v, self.f_v >= 0.0, ">= 0"),
            (
                "alpha",
                self.alpha,
                (0.0..1.0).contains(&self.alpha),
                "in [0, 1) (0: Newtonian junction; about 0.6 for gelatin)",
            ),
            ("m = M V_s / (F_a tau_out)", self.m, self.m >= 0.0, ">= 0"),
        ];
        for (field, value, ok, expected) in checks {
            if !(ok && value.is_finite()) {
                return Err(InputError::out_of_range(field, value, expected));
            }
        }
        Ok(())
    }
}
