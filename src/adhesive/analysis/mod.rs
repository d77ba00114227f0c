//! The analyses of the adhesive block, one question each: the onset
//! ([`onset`]), the steady branch and the stability diagram in the
//! driving velocity ([`steady`]), the cycles ([`cycles`]), simulations
//! ([`simulate`]).

pub mod cycles;
pub mod onset;
pub mod simulate;
pub mod steady;
