//! Branches of steady sliding in `kappa` or `nu`, with eigenvalues and events.
