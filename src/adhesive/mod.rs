//! Soft adhesive contacts (gels, elastomers on glass): Schallamach's model
//! of friction by adsorbed chains (seed §III.D.3, Appendix D) with the
//! junction's viscous force (§III.D.2), on the driven block. The state is
//! the fraction `n` of bonded chains (docs/model.md, "Soft adhesive
//! contacts").
//!
//! - [`params`]: the dimensionless parameters and their validation;
//! - [`scene`]: scenes with `law = "adhesive"` in laboratory units;
//! - [`block`]: the quasi-static and the inertial block (the model, and
//!   why: the inertia ratio `chi`), steady friction, its extrema `V_max`,
//!   `V_c`, and the closed-form critical stiffness of either;
//! - [`analysis`]: the onset, the steady branch, the stability diagram,
//!   the cycles and simulations, in the experimenter's units.

pub mod analysis;
pub mod block;
pub mod fit;
pub mod jobs;
pub mod params;
pub mod scene;
