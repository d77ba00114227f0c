//! stickslip: bifurcation analysis of a rate-and-state driven block.
pub mod error;
pub mod friction;
pub mod params;
pub mod model;
pub mod analysis;
pub mod appendix_c;
pub mod scene;
pub mod cli;
