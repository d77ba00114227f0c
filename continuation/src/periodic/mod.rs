//! Periodic orbits: orthogonal collocation, Floquet multipliers, and
//! continuation of cycles from a Hopf point.

pub mod adapt;
pub mod bordered;
pub mod branch;
pub mod collocation;
pub mod cycle;
pub mod floquet;
pub mod lpc;
pub mod mesh;
pub mod newton;
