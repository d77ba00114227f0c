//! stickslip: bifurcation analysis of a rate-and-state driven block.
pub mod error;
pub mod friction;
pub mod params;
