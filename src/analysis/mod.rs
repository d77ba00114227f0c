//! Analyses a user runs: model choice, the Hopf (stick-slip onset) point,
//! branches of steady sliding.

pub mod axes;
pub mod branch;
pub mod control;
pub mod cycle_at;
pub mod cycles;
pub mod decimate;
pub mod diagram;
pub mod hopf;
pub mod joined_flow;
pub mod lpc_curve;
pub mod model_choice;
pub mod operating_point;
pub mod orbit_inertia;
pub mod orbit_start;
pub mod return_map;
pub mod sampled_cycle;
pub mod settle;
pub mod simulate;
