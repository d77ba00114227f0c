//! Accuracy control of every orbit on the branch: its discretization error
//! is estimated by solving it again on half the mesh, and the mesh is
//! doubled (and re-equidistributed) until the estimate meets the tolerance.
//!
//! The multipliers can need a finer mesh than the orbit itself, so the mesh
//! is also refined while the trivial multiplier is off by more than
//! `trivial_tol` (or, when larger, 1e-7 of the distance of the other
//! multipliers from the unit circle, which decides what they are used for)
//! — as long as that helps: on stiff stick-slip orbits
//! perturbations grow by many decades during the slip, and the multiplier 1
//! is then so ill-conditioned that its computed distance from 1 is set by
//! rounding (`eps` times that growth), whatever the mesh. That floor is
//! detected (doubling the mesh no longer divides the error by 4) and
//! accepted, and the orbit stays on the coarser mesh.
//!
//! Where an estimate falls far below the tolerance the next step halves the
//! mesh ([`Cycles::mesh_size`]): the intervals a stretch of the branch
//! needed are not carried along the rest of it.

use super::{
    point_at, CyclePoint, Cycles, Reading, Stability, WhenUndecidable, MULTIPLIER_MEMORY,
    ORBIT_FLOOR_MEMORY,
};
use crate::error::ContinuationError;
use crate::newton::{NewtonReport, NewtonSettings};
use crate::periodic::adapt::equidistribute;
use crate::periodic::collocation::Collocation;
use crate::periodic::cycle::unknowns_on;
use crate::periodic::newton::{
    chord_bordered, correct_bordered, newton_bordered, unit_row, ArcWeights, OrbitJacobian,
};
use crate::periodic::Cycle;
use crate::periodic::Mesh;
use crate::system::VectorField;

/// The share of the distance of the nontrivial multipliers from the unit
/// circle the trivial multiplier's error is refined below
/// ([`Cycles::multiplier_tol`]).
const MARGIN_SHARE: f64 = 1e-7;

/// Largest difference between two approximations `a` (the finer) and `b`
/// of an orbit of `sys`: of the periods, relative, and of the least and
/// greatest value of every observable of `sys` ([`VectorField::observable`],
/// by [`Cycle::observable_range`]), relative to that observable's amplitude
/// on `a` (`max - min`) — what a user reads as the size of the orbit, not the
/// size of the values (near a Hopf point the values sit far from zero and
/// the amplitude is small).
fn difference<S: VectorField>(sys: &S, a: &CyclePoint, b: &Cycle) -> f64 {
    let mut d = ((a.cycle.period - b.period) / a.cycle.period).abs();
    for (k, &(a_lo, a_hi)) in a.extremes(sys).iter().enumerate() {
        let (b_lo, b_hi) = b.observable_range(sys, k);
        let amplitude = (a_hi - a_lo).max(f64::MIN_POSITIVE);
        d = d.max((a_lo - b_lo).abs().max((a_hi - b_hi).abs()) / amplitude);
    }
    d
}

impl<S: VectorField> Cycles<'_, S> {
    /// The current orbit, on a mesh fine enough for `mesh_tol` (and for
    /// `trivial_tol` while refining helps the multipliers): otherwise the mesh
    /// doubles (up to `ntst_max`) and the orbit is corrected on it. A
    /// doubling that does not divide the orbit's error estimate by 4 (a
    /// discretization error falls by `2^(m+1)` or more) shows that the
    /// estimate is the rounding floor of the orbit (near a Hopf point the
    /// amplitude at fixed parameter is ill-conditioned, and rounding in the
    /// collocation equations moves it by more than the tolerance): the orbit
    /// stays on the coarser mesh, and for [`ORBIT_FLOOR_MEMORY`] steps
    /// estimates up to twice that floor are accepted without trying again.
    pub(super) fn refined_point(
        &mut self,
        rep: NewtonReport,
    ) -> Result<CyclePoint, ContinuationError> {
        let mut pt = self.point(rep)?;
        // Far below the tolerance the estimate is renewed every fifth orbit
        // only (it costs a solve on the coarse mesh); in between the last
        // one is reported.
        let fresh = self.last_estimate > 0.1 * self.settings.mesh.tol()
            || self.since_estimate >= 4
            || self.last_ntst != self.coll.mesh.ntst();
        if fresh {
            self.renew_estimate(&pt);
        } else {
            self.since_estimate += 1;
        }
        let (floor, since) = self.orbit_floor;
        let mut orbit_tol = if self.steps < since + ORBIT_FLOOR_MEMORY {
            self.settings.mesh.tol().max(floor)
        } else {
            self.settings.mesh.tol()
        };
        loop {
            pt.error_estimate = self.last_estimate;
            let ntst = self.coll.mesh.ntst();
            let orbit_resolved = pt.error_estimate <= orbit_tol;
            if orbit_resolved && pt.trivial_error <= self.multiplier_tol(&pt) {
                break;
            }
            if ntst >= self.settings.mesh.ntst_max {
                // At the mesh limit an orbit is still accepted within
                // `mesh_accept` (and reported with its estimate).
                if pt.error_estimate <= self.settings.mesh.accept() {
                    break;
                }
                return Err(ContinuationError::Unresolved {
                    param_name: self.sys.param_name(self.k),
                    ntst,
                    error: pt.error_estimate,
                    tol: self.settings.mesh.accept(),
                    param: self.z[self.z.len() - 1],
                });
            }
            // If twice the intervals do not help, the coarser mesh stays.
            let coarser = (self.coll.cycle(&self.z), self.tangent.clone());
            self.adapt((2 * ntst).min(self.settings.mesh.ntst_max));
            let corrector = self.settings.corrector;
            let finer = self
                .correct_on_mesh(&corrector)
                .and_then(|rep| self.point(rep));
            let coarse_estimate = pt.error_estimate;
            if !orbit_resolved {
                // The orbit asked for the intervals.
                let finer = finer?;
                self.renew_estimate(&finer);
                if self.last_estimate <= 0.25 * coarse_estimate {
                    pt = finer;
                    continue;
                }
                // Rounding floor: back to the coarser mesh, where the
                // multipliers are still to be judged.
                self.orbit_floor = (2.0 * coarse_estimate, self.steps);
                orbit_tol = orbit_tol.max(2.0 * coarse_estimate);
                self.restore(coarser);
                self.last_estimate = coarse_estimate;
                self.last_ntst = ntst;
                pt.error_estimate = coarse_estimate;
                continue;
            }
            match finer {
                Ok(finer)
                    if finer.trivial_error.is_finite()
                        && finer.trivial_error <= 0.25 * pt.trivial_error =>
                {
                    // The multipliers needed the intervals: halving stops here
                    // until their error is found to be rounding. (Where half the
                    // new mesh cannot carry the orbit, its estimate stays the
                    // coarser orbit's: more intervals do not resolve it worse.)
                    self.multiplier_ntst = (self.coll.mesh.ntst(), self.steps);
                    self.renew_estimate(&finer);
                    if !self.last_estimate.is_finite() {
                        self.last_estimate = coarse_estimate;
                    }
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
                    self.restore(coarser);
                    self.last_ntst = ntst;
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
            && (self.settings.floquet.trivial_limit).is_some_and(|limit| pt.trivial_error > limit)
            && (near_circle > 1 || pt.trivial_error > 0.1)
        {
            if self.settings.floquet.when_undecidable == WhenUndecidable::KeepFirst
                && self.steps == 0
            {
                pt.stability = Stability::IllConditioned {
                    trivial_error: Some(pt.trivial_error).filter(|e| e.is_finite()),
                };
                return Ok(pt);
            }
            return Err(ContinuationError::FloquetIllConditioned {
                param_name: self.sys.param_name(self.k),
                param: self.z[self.z.len() - 1],
                trivial_error: pt.trivial_error,
            });
        }
        Ok(pt)
    }

    /// The error of the trivial multiplier the mesh is refined for:
    /// `trivial_tol` (as raised to a rounding floor), or [`MARGIN_SHARE`] of
    /// the distance of the nearest nontrivial multiplier from the unit
    /// circle if that is larger — the multipliers decide stability, period
    /// doublings and tori by that distance, and a finer mesh would not change
    /// the decision.
    fn multiplier_tol(&self, pt: &CyclePoint) -> f64 {
        let margin = pt
            .multipliers
            .iter()
            .enumerate()
            .filter(|(i, _)| Some(*i) != pt.trivial)
            .map(|(_, z)| (z.norm() - 1.0).abs())
            .fold(f64::INFINITY, f64::min);
        self.trivial_tol.max(MARGIN_SHARE * margin)
    }

    /// Corrects the current orbit, just moved onto a new mesh, on the
    /// hyperplane through it normal to the branch: well posed also near a
    /// Hopf point or a fold, where the orbit at fixed parameter is
    /// ill-determined. An orbit held at its parameter (`held`: a first
    /// orbit corrected there, an orbit landed on a range bound) stays
    /// there. The corrected orbit becomes the phase reference; the system
    /// linearized there is kept for its multipliers
    /// ([`Cycles::point`]: they come from the collocation rows, which the
    /// new phase reference does not change).
    pub(super) fn correct_on_mesh(
        &mut self,
        settings: &NewtonSettings,
    ) -> Result<NewtonReport, ContinuationError> {
        let row = if self.held {
            unit_row(self.z.len(), self.z.len() - 1)
        } else {
            ArcWeights::at(&self.z, self.settings.param_floor).row(&self.tangent)
        };
        let anchor = self.z.clone();
        let (rep, at) = correct_bordered(&self.coll, &mut self.z, settings, &row, &anchor)?;
        self.jacobian = Some((self.z.clone(), at.jacobian));
        self.coll = Collocation::new(self.sys, &self.coll.cycle(&self.z), self.k);
        Ok(rep)
    }

    /// Error estimate of `point`'s orbit (the branch's current orbit, or one
    /// located near it, with the branch's unit tangent `tangent` there on the
    /// orbit's mesh): its difference ([`difference`]) from the same orbit
    /// solved on an equidistributed mesh of half as many intervals, divided
    /// by `2^(m+1) - 1` (Richardson: the collocation error between mesh
    /// points is `O(h^(m+1))`; the period and the extremes, read at the mesh
    /// points' accuracy, converge faster, so this overestimates their error).
    /// Infinite when the coarse mesh cannot carry the orbit.
    ///
    /// The coarse orbit is solved on the hyperplane through `orbit` normal to
    /// the branch (well posed also near a Hopf point or a fold, where the
    /// orbit at fixed parameter is ill-determined), so it lies at a slightly
    /// different parameter `p_c`. Read [`Reading::AtParameter`], the
    /// comparison is at the orbit's own parameter `p`: the coarse orbit is
    /// moved along the branch to first order, `z_c + (p - p_c) t / t_p`. Near
    /// a Hopf point that is most of the error: the period and extremes of
    /// the orbits hardly differ on the hyperplane, but the parameter does
    /// (the discretization shifts the Hopf point by `O(h^(2m))`), and the
    /// amplitude at a given parameter, `~ sqrt(p_c - p)`, changes by
    /// `delta p / (2 (p_c - p))` relative: at `(p_c - p) / p_c = 1e-5` a
    /// relative shift of the Hopf point of `1e-9` is an error of `5e-5` in
    /// the amplitude. Read [`Reading::Point`], the parameter is compared as
    /// one more coordinate, relative.
    pub(super) fn error_estimate(
        &self,
        point: &CyclePoint,
        tangent: &[f64],
        reading: Reading,
    ) -> f64 {
        let orbit = &point.cycle;
        let ntst = orbit.mesh.ntst();
        if ntst < 4 {
            return f64::INFINITY;
        }
        let coarse = equidistribute(orbit, ntst / 2);
        let coll = Collocation::new(self.sys, &coarse, self.k);
        let mut z = coll.unknowns(&coarse);
        let anchor = z.clone();
        let tangent = self.tangent_on(&orbit.mesh, tangent, &coarse.mesh, &z);
        let w = ArcWeights::at(&z, self.settings.param_floor);
        let row = w.row(&tangent);
        // The coarse orbit is the fine one to the discretization error:
        // chord iterations, and Newton's method from the start again where
        // they do not converge.
        let corrector = &self.settings.corrector;
        if chord_bordered(&coll, &mut z, corrector, &row, &anchor).is_err() {
            z.copy_from_slice(&anchor);
            if newton_bordered(&coll, &mut z, corrector, &row, &anchor).is_err() {
                return f64::INFINITY;
            }
        }
        let order = orbit.mesh.degree as i32 + 1;
        let nz = z.len();
        let p = orbit.p[self.k];
        let d = match reading {
            Reading::AtParameter => {
                let shift = (p - z[nz - 1]) / tangent[nz - 1];
                for (zi, ti) in z.iter_mut().zip(&tangent) {
                    *zi += shift * ti;
                }
                difference(self.sys, point, &coll.cycle(&z))
            }
            Reading::Point => difference(self.sys, point, &coll.cycle(&z))
                .max(((p - z[nz - 1]) / p.abs().max(self.settings.param_floor)).abs()),
        };
        if d.is_finite() {
            d / (2f64.powi(order) - 1.0)
        } else {
            f64::INFINITY
        }
    }

    /// Renews the error estimate of the branch's current orbit `orbit` (on
    /// the current mesh, read at its parameter).
    fn renew_estimate(&mut self, point: &CyclePoint) {
        let tangent = self.tangent.clone();
        let reading = if self.steps == 0 && self.start_at_fold {
            Reading::Point
        } else {
            Reading::AtParameter
        };
        self.last_estimate = self.error_estimate(point, &tangent, reading);
        self.last_ntst = self.coll.mesh.ntst();
        self.since_estimate = 0;
    }

    /// Puts the branch back on an orbit and tangent kept before a refinement.
    pub(super) fn restore(&mut self, (orbit, tangent): (Cycle, Vec<f64>)) {
        self.coll = Collocation::new(self.sys, &orbit, self.k);
        self.z = self.coll.unknowns(&orbit);
        self.tangent = tangent;
    }

    /// Intervals for the next orbit: half the current mesh when its last
    /// (fresh) estimate is below `mesh_tol / (8 * 2^(m+1))` — halving raises
    /// the error by about `2^(m+1)`, which leaves a margin of 8 — and never
    /// fewer than the initial `ntst` or than the multipliers were found to
    /// need in the last [`MULTIPLIER_MEMORY`] steps; else the current mesh.
    pub(super) fn mesh_size(&self) -> usize {
        let ntst = self.coll.mesh.ntst();
        let order = self.coll.mesh.degree as i32 + 1;
        let far_below = self.settings.mesh.tol() / (8.0 * 2f64.powi(order));
        let fresh = self.since_estimate == 0 && self.last_ntst == ntst;
        let (needed, since) = self.multiplier_ntst;
        let remembered = self.steps < since + MULTIPLIER_MEMORY;
        let least = self
            .settings
            .mesh
            .ntst
            .max(if remembered { needed } else { 0 });
        if fresh && self.last_estimate < far_below && ntst / 2 >= least {
            ntst / 2
        } else {
            ntst
        }
    }

    /// The tangent `tangent`, given on `from`, moved onto `mesh` (unit
    /// length there, in the arclength weights at the unknowns `z`).
    pub(super) fn tangent_on(
        &self,
        from: &Mesh,
        tangent: &[f64],
        mesh: &Mesh,
        z: &[f64],
    ) -> Vec<f64> {
        let t = unknowns_on(tangent, from, self.sys.dim(), mesh);
        let norm = ArcWeights::at(z, self.settings.param_floor)
            .dot(&t, &t)
            .sqrt();
        t.iter().map(|v| v / norm).collect()
    }

    /// The current orbit with its multipliers, from the Jacobian the last
    /// step kept when it ended on this orbit.
    pub(super) fn point(&mut self, newton: NewtonReport) -> Result<CyclePoint, ContinuationError> {
        let jacobian = match self.jacobian.take() {
            Some((z, jacobian)) if z == self.z => jacobian,
            _ => OrbitJacobian::new(self.coll.linearize(&self.z), self.sys.dim()),
        };
        point_at(&self.coll, &self.z, &jacobian, &self.tangent, newton)
    }

    /// Moves the orbit and tangent onto an equidistributing mesh of `ntst` intervals.
    pub(super) fn adapt(&mut self, ntst: usize) {
        let new = equidistribute(&self.coll.cycle(&self.z), ntst);
        let coll = Collocation::new(self.sys, &new, self.k);
        let z = coll.unknowns(&new);
        self.tangent = self.tangent_on(&self.coll.mesh, &self.tangent, &new.mesh, &z);
        self.coll = coll;
        self.z = z;
    }
}
