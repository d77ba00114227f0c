//! Periodic orbits: orthogonal collocation, Floquet multipliers, and
//! continuation of cycles from a Hopf point.

mod adapt;
mod bordered;
mod branch;
mod collocation;
mod cycle;
mod floquet;
mod lpc;
mod mesh;
mod newton;

pub use adapt::equidistribute;
pub use branch::{
    CycleBranch, CycleEvent, CyclePoint, CycleSettings, Discretization, FloquetPolicy, Stability,
    WhenUndecidable,
};
pub use cycle::Cycle;
pub use lpc::{fold_beside_bautin, locate_lpc, FoldsOfCycles, LpcCurve, LpcCurveSettings};
pub use mesh::{CollocationPoints, Mesh, Tableau};

#[cfg(test)]
mod tests;
