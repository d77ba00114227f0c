//! stickslip: bifurcation analysis of a rate-and-state driven block.
pub mod adhesive;
pub mod analysis;
pub mod appendix_c;
pub mod cli;
pub mod error;
pub mod exp_integral;
pub mod file_names;
pub mod fit;
pub mod friction;
pub mod jobs;
pub mod log_model;
pub mod model;
pub mod overrides;
pub mod params;
pub mod plot;
pub mod records;
pub mod scene;
