//! Accuracy control of every orbit on the branch: its discretization error
//! is estimated by solving it again on half the mesh, and the mesh is
//! doubled (and re-equidistributed) until the estimate meets the tolerance.
//!
//! The multipliers can need a finer mesh than the orbit itself, so the mesh
//! is also refined while the trivial multiplier is off by more than
//! `trivial_tol` — as long as that helps: on stiff stick-slip orbits
//! perturbations grow by many decades during the slip, and the multiplier 1
//! is then so ill-conditioned that its computed distance from 1 is set by
//! rounding (`eps` times that growth), whatever the mesh. That floor is
//! detected (doubling the mesh no longer divides the error by 4) and
//! accepted, and the orbit stays on the coarser mesh.
//!
//! Where an estimate falls far below the tolerance the next step halves the
//! mesh ([`CycleBranch::mesh_size`]): the intervals a stretch of the branch
//! needed are not carried along the rest of it.

use super::{point_at, CycleBranch, CyclePoint, MULTIPLIER_MEMORY};
use crate::error::ContinuationError;
use crate::newton::NewtonReport;
use crate::periodic::adapt::equidistribute;
use crate::periodic::collocation::Collocation;
use crate::periodic::cycle::Cycle;
use crate::periodic::mesh::Mesh;
use crate::periodic::newton::{newton_bordered, unit_row, ArcWeights};
use crate::system::VectorField;

/// Largest difference between two approximations of an orbit: of the
/// periods (relative) and of the least and greatest value of every
/// component (relative to `1 + |value|`).
fn difference(a: &Cycle, b: &Cycle) -> f64 {
    let mut d = ((a.period - b.period) / a.period).abs();
    for j in 0..a.n {
        let ((a_lo, a_hi), (b_lo, b_hi)) = (a.range(j), b.range(j));
        d = d
            .max((a_lo - b_lo).abs() / (1.0 + a_lo.abs()))
            .max((a_hi - b_hi).abs() / (1.0 + a_hi.abs()));
    }
    d
}

impl<S: VectorField> CycleBranch<'_, S> {
    /// The current orbit, on a mesh fine enough for `mesh_tol` (and for
    /// `trivial_tol` while refining helps the multipliers): otherwise the mesh
    /// doubles (up to `ntst_max`) and the orbit is corrected on it.
    pub(super) fn refined_point(
        &mut self,
        rep: NewtonReport,
    ) -> Result<CyclePoint, ContinuationError> {
        let mut pt = self.point(rep)?;
        loop {
            // Far below the tolerance the estimate is renewed every fifth orbit
            // only (it costs a solve on the coarse mesh); in between the last
            // one is reported.
            let fresh = self.last_estimate > 0.1 * self.settings.mesh_tol
                || self.since_estimate >= 4
                || self.last_ntst != self.coll.mesh.ntst();
            if fresh {
                self.last_estimate = self.error_estimate(&pt.cycle);
                self.last_ntst = self.coll.mesh.ntst();
                self.since_estimate = 0;
            } else {
                self.since_estimate += 1;
            }
            pt.error_estimate = self.last_estimate;
            let ntst = self.coll.mesh.ntst();
            let orbit_resolved = pt.error_estimate <= self.settings.mesh_tol;
            if orbit_resolved && pt.trivial_error <= self.trivial_tol {
                break;
            }
            if ntst >= self.settings.ntst_max {
                // At the mesh limit an orbit is still accepted within
                // `mesh_accept` (and reported with its estimate).
                if pt.error_estimate <= self.settings.mesh_accept {
                    break;
                }
                return Err(ContinuationError::Unresolved {
                    ntst,
                    error: pt.error_estimate,
                    tol: self.settings.mesh_accept,
                    param: self.z[self.z.len() - 1],
                });
            }
            // Kept while the orbit is resolved and only the multipliers ask
            // for more intervals: if they do not improve, the coarser mesh stays.
            let coarser = orbit_resolved.then(|| (self.coll.cycle(&self.z), self.tangent.clone()));
            self.adapt((2 * ntst).min(self.settings.ntst_max));
            // Corrected on the hyperplane through the orbit normal to the
            // branch: well posed also near a Hopf point or a fold, where the
            // orbit at fixed parameter is ill-determined. A first orbit that
            // was corrected at its parameter stays there.
            let row = if self.steps == 0 && self.start_at_fixed_parameter {
                unit_row(self.z.len(), self.z.len() - 1)
            } else {
                ArcWeights::at(&self.z, self.settings.param_floor).row(&self.tangent)
            };
            let anchor = self.z.clone();
            let finer = newton_bordered(
                &self.coll,
                &mut self.z,
                &self.settings.corrector,
                &row,
                &anchor,
            )
            .and_then(|rep| {
                self.coll = Collocation::new(self.sys, &self.coll.cycle(&self.z), self.k);
                self.point(rep)
            });
            let Some((orbit, tangent)) = coarser else {
                pt = finer?;
                continue;
            };
            match finer {
                Ok(finer)
                    if finer.trivial_error.is_finite()
                        && finer.trivial_error <= 0.25 * pt.trivial_error =>
                {
                    // The multipliers needed the intervals: halving stops here
                    // until their error is found to be rounding.
                    self.multiplier_ntst = (self.coll.mesh.ntst(), self.steps);
                    pt = finer;
                }
                _ => {
                    // Twice the intervals did not help the multipliers (a
                    // discretization error would fall by 2^(m+1) or more), or
                    // the orbit could not be solved on them: their error is
                    // the rounding floor of this orbit; accept it from now on,
                    // on the mesh the orbit needs.
                    // (Not when the pencil left the trivial multiplier
                    // undetermined: the tolerance would become infinite.)
                    if pt.trivial_error.is_finite() {
                        self.trivial_tol = self.trivial_tol.max(2.0 * pt.trivial_error);
                    }
                    self.multiplier_ntst = (0, 0);
                    self.coll = Collocation::new(self.sys, &orbit, self.k);
                    self.z = self.coll.unknowns(&orbit);
                    self.tangent = tangent;
                    break;
                }
            }
        }
        // Past `trivial_limit`, stability is still decided while no other
        // multiplier lies within the trivial one's error of the unit circle
        // (always in the plane, where the other multiplier is exact).
        let error = super::multiplier_error(self.sys.dim(), pt.trivial_error);
        let near_circle = pt
            .multipliers
            .iter()
            .filter(|z| (z.norm() - 1.0).abs() <= error)
            .count();
        if self.sys.dim() > 2
            && pt.trivial_error > self.settings.trivial_limit
            && (near_circle > 1 || pt.trivial_error > 0.1)
        {
            return Err(ContinuationError::FloquetIllConditioned {
                param: self.z[self.z.len() - 1],
                trivial_error: pt.trivial_error,
            });
        }
        Ok(pt)
    }

    /// Error estimate of `orbit` (the branch's current orbit, or one located
    /// near it): its difference from the same orbit solved on an
    /// equidistributed mesh of half as many intervals (on the hyperplane
    /// normal to the branch), divided by `2^(m+1) - 1` (Richardson: the
    /// collocation error between mesh points is `O(h^(m+1))`). Infinite when
    /// the coarse mesh cannot carry the orbit.
    pub(super) fn error_estimate(&self, orbit: &Cycle) -> f64 {
        let ntst = orbit.mesh.ntst();
        if ntst < 4 {
            return f64::INFINITY;
        }
        let coarse = equidistribute(orbit, ntst / 2);
        let coll = Collocation::new(self.sys, &coarse, self.k);
        let mut z = coll.unknowns(&coarse);
        let anchor = z.clone();
        let tangent = self.tangent_on(&coarse.mesh);
        let w = ArcWeights::at(&z, self.settings.param_floor);
        match newton_bordered(
            &coll,
            &mut z,
            &self.settings.corrector,
            &w.row(&tangent),
            &anchor,
        ) {
            Ok(_) => {
                let order = orbit.mesh.degree as i32 + 1;
                difference(orbit, &coll.cycle(&z)) / (2f64.powi(order) - 1.0)
            }
            Err(_) => f64::INFINITY,
        }
    }

    /// Intervals for the next orbit: half the current mesh when its last
    /// (fresh) estimate is below `mesh_tol / (8 * 2^(m+1))` — halving raises
    /// the error by about `2^(m+1)`, which leaves a margin of 8 — and never
    /// fewer than the initial `ntst` or than the multipliers were found to
    /// need in the last [`MULTIPLIER_MEMORY`] steps; else the current mesh.
    pub(super) fn mesh_size(&self) -> usize {
        let ntst = self.coll.mesh.ntst();
        let order = self.coll.mesh.degree as i32 + 1;
        let far_below = self.settings.mesh_tol / (8.0 * 2f64.powi(order));
        let fresh = self.since_estimate == 0 && self.last_ntst == ntst;
        let (needed, since) = self.multiplier_ntst;
        let remembered = self.steps < since + MULTIPLIER_MEMORY;
        let least = self.settings.ntst.max(if remembered { needed } else { 0 });
        if fresh && self.last_estimate < far_below && ntst / 2 >= least {
            ntst / 2
        } else {
            ntst
        }
    }

    /// The branch's tangent moved onto `mesh` (unit length there).
    fn tangent_on(&self, mesh: &Mesh) -> Vec<f64> {
        let orbit = self.coll.cycle(&self.z);
        let nn = orbit.u.len();
        let mut t = Cycle {
            u: self.tangent[..nn].to_vec(),
            period: 0.0,
            ..orbit
        }
        .remesh(mesh.clone())
        .u;
        t.extend_from_slice(&self.tangent[nn..]);
        let norm = ArcWeights::at(&self.z, self.settings.param_floor)
            .dot(&t, &t)
            .sqrt();
        t.iter().map(|v| v / norm).collect()
    }

    pub(super) fn point(&self, newton: NewtonReport) -> Result<CyclePoint, ContinuationError> {
        point_at(&self.coll, &self.z, &self.tangent, newton)
    }

    /// Moves the orbit and tangent onto an equidistributing mesh of `ntst` intervals.
    pub(super) fn adapt(&mut self, ntst: usize) {
        let new = equidistribute(&self.coll.cycle(&self.z), ntst);
        self.tangent = self.tangent_on(&new.mesh);
        self.coll = Collocation::new(self.sys, &new, self.k);
        self.z = self.coll.unknowns(&new);
    }
}
