//! Pseudo-arclength continuation of the solution curve of a
//! [`DefiningSystem`] with one more unknown than equations (Keller 1977;
//! Kuznetsov 1998, §10.2.1).
//!
//! With unit tangent `t`, a step predicts `z + ds t` and corrects by Newton on
//! `G(z) = 0, t . (z - z_pred) = 0`. The step grows after easy corrections
//! (at most 3 Newton iterations), halves after failures or sharp turns of the
//! tangent, and a step that would cross a bound is shortened to land on it.

use crate::defining::DefiningSystem;
use crate::error::ContinuationError;
use crate::linalg::solve;
use crate::newton::{self, NewtonReport, NewtonSettings};
use nalgebra::{DMatrix, DVector};

/// Step-size control of a curve.
#[derive(Clone, Debug)]
pub struct StepControl {
    /// Initial step.
    pub ds: f64,
    /// Smallest step before giving up.
    pub ds_min: f64,
    /// Largest step.
    pub ds_max: f64,
    /// Growth factor after an easy correction.
    pub growth: f64,
    /// Smallest cosine between consecutive tangents.
    pub min_tangent_cos: f64,
    /// Corrector settings.
    pub corrector: NewtonSettings,
    /// Weights of the unknowns in the arclength norm `|dz|^2 = sum w_i dz_i^2`
    /// (empty: all 1). Small weights on the state let the step follow the
    /// parameters, as AUTO's THL/THU do.
    pub weights: Vec<f64>,
}

impl StepControl {
    fn weight(&self, i: usize) -> f64 {
        self.weights.get(i).copied().unwrap_or(1.0)
    }

    /// Weighted inner product `sum w_i a_i b_i`.
    pub fn dot(&self, a: &DVector<f64>, b: &DVector<f64>) -> f64 {
        a.iter()
            .zip(b.iter())
            .enumerate()
            .map(|(i, (x, y))| self.weight(i) * x * y)
            .sum()
    }

    /// `W a`: the weights applied to a vector.
    fn weighted(&self, a: &DVector<f64>) -> DVector<f64> {
        DVector::from_fn(a.len(), |i, _| self.weight(i) * a[i])
    }
}

/// Bounds on one unknown of the curve: the curve stops on them.
#[derive(Clone, Copy, Debug)]
pub struct Bound {
    /// Index of the unknown in `z`.
    pub index: usize,
    /// Lower bound.
    pub min: f64,
    /// Upper bound.
    pub max: f64,
}

/// An accepted step.
#[derive(Clone, Copy, Debug)]
pub struct Step {
    /// The corrector's work.
    pub report: NewtonReport,
    /// The bound the step landed on, if any.
    pub bound: Option<Bound>,
    /// The step length taken.
    pub ds: f64,
}

/// A curve being traced: its current point, tangent and step size.
pub struct Stepper<G: DefiningSystem> {
    /// The defining system.
    pub system: G,
    z: DVector<f64>,
    tangent: DVector<f64>,
    ds: f64,
    control: StepControl,
    bounds: Vec<Bound>,
}

impl<G: DefiningSystem> Stepper<G> {
    /// Starts at `z0` (already on the curve) with the tangent oriented along `seed`.
    pub fn new(
        mut system: G,
        z0: DVector<f64>,
        seed: &DVector<f64>,
        control: StepControl,
        bounds: Vec<Bound>,
    ) -> Result<Self, ContinuationError> {
        system.accept(&z0)?;
        let tangent = tangent_at(&system, &z0, seed, &control)?;
        let ds = control.ds.abs();
        Ok(Stepper {
            system,
            z: z0,
            tangent,
            ds,
            control,
            bounds,
        })
    }

    /// Current point.
    pub fn z(&self) -> &DVector<f64> {
        &self.z
    }

    /// Current unit tangent.
    pub fn tangent(&self) -> &DVector<f64> {
        &self.tangent
    }

    /// Current step size.
    pub fn ds(&self) -> f64 {
        self.ds
    }

    /// Moves back to an earlier point with a new step size (for a caller that
    /// rejects a step, e.g. because events need a shorter bracket).
    pub fn restore(
        &mut self,
        z: DVector<f64>,
        tangent: DVector<f64>,
        ds: f64,
    ) -> Result<(), ContinuationError> {
        self.system.accept(&z)?;
        self.z = z;
        self.tangent = tangent;
        self.ds = ds;
        Ok(())
    }

    /// Newton on `G(z) = 0` plus `t . (z - z_pred) = 0`, or plus `z_i = value`
    /// when `fixed = Some((i, value))`.
    pub fn correct(
        &self,
        z: &mut DVector<f64>,
        tangent: &DVector<f64>,
        fixed: Option<(usize, f64)>,
        settings: &NewtonSettings,
    ) -> Result<NewtonReport, ContinuationError> {
        let mut dgs = DMatrix::zeros(self.system.n_equations(), z.len());
        self.correct_into(z, tangent, fixed, settings, &mut dgs)
    }

    /// [`correct`](Self::correct), leaving in `dgs` (`n_equations` rows) the
    /// Jacobian `DG` of the last evaluation: on success, `DG` at the solution.
    fn correct_into(
        &self,
        z: &mut DVector<f64>,
        tangent: &DVector<f64>,
        fixed: Option<(usize, f64)>,
        settings: &NewtonSettings,
        dgs: &mut DMatrix<f64>,
    ) -> Result<NewtonReport, ContinuationError> {
        let m = self.system.n_equations();
        let z_pred = z.clone();
        let mut gs = DVector::zeros(m);
        let wt = self.control.weighted(tangent);
        let mut diff = DVector::zeros(z.len());
        newton::solve(z, settings, "", |z, g, dg| {
            self.system.eval(z, &mut gs, dgs);
            g.rows_mut(0, m).copy_from(&gs);
            dg.view_mut((0, 0), (m, z.len())).copy_from(&*dgs);
            match fixed {
                Some((i, value)) => {
                    g[m] = z[i] - value;
                    dg.row_mut(m).fill(0.0);
                    dg[(m, i)] = 1.0;
                }
                None => {
                    diff.copy_from(z);
                    diff -= &z_pred;
                    g[m] = wt.dot(&diff);
                    dg.row_mut(m).copy_from(&wt.transpose());
                }
            }
        })
    }

    /// The first bound that `z` lies beyond, with the value to land on.
    fn beyond(&self, z: &DVector<f64>) -> Option<(Bound, f64)> {
        self.bounds.iter().copied().find_map(|b| {
            let v = z[b.index];
            let target = if v < b.min {
                b.min
            } else if v > b.max {
                b.max
            } else {
                return None;
            };
            Some((b, target))
        })
    }

    /// Takes one step that the corrector accepts. A step whose prediction
    /// crosses a bound, or whose corrected point lies beyond one (the
    /// corrector moves across the tangent), is retaken to land on the bound.
    pub fn step(&mut self) -> Result<Step, ContinuationError> {
        // A bound the last corrected point overshot: the step is retaken onto it.
        let mut overshot: Option<(Bound, f64)> = None;
        loop {
            let mut ds = self.ds;
            let mut z_new = &self.z + &self.tangent * ds;
            let crossed = overshot.take().or_else(|| self.beyond(&z_new));
            if let Some((b, target)) = crossed {
                ds = (target - self.z[b.index]) / self.tangent[b.index];
                z_new = &self.z + &self.tangent * ds;
                z_new[b.index] = target;
            }
            let fixed = crossed.map(|(b, target)| (b.index, target));
            let mut dgs = DMatrix::zeros(self.system.n_equations(), z_new.len());
            let attempt = self.correct_into(
                &mut z_new,
                &self.tangent,
                fixed,
                &self.control.corrector,
                &mut dgs,
            );
            let mut accepted = match &attempt {
                Ok(report) => {
                    // The corrector's last evaluation was at `z_new`: its `DG` is reused.
                    let t_new = tangent_from(&dgs, &self.tangent, &self.control)?;
                    let turn_ok =
                        self.control.dot(&t_new, &self.tangent) >= self.control.min_tangent_cos;
                    (turn_ok || crossed.is_some()).then_some((*report, t_new))
                }
                Err(_) => None,
            };
            let over = match (&accepted, crossed) {
                (Some(_), None) => self.beyond(&z_new),
                _ => None,
            };
            if let Some((b, target)) = over {
                // Retaken onto the bound when the tangent leads there; else shorter.
                let landing = (target - self.z[b.index]) / self.tangent[b.index];
                if landing.is_finite() && landing * ds > 0.0 {
                    overshot = over;
                    continue;
                }
                accepted = None;
            }
            if let Some((report, t_new)) = accepted {
                self.system.accept(&z_new)?;
                self.z = z_new;
                self.tangent = t_new;
                if crossed.is_none() && report.iterations <= 3 {
                    self.ds = (self.ds * self.control.growth).min(self.control.ds_max);
                }
                return Ok(Step {
                    report,
                    bound: crossed.map(|(b, _)| b),
                    ds,
                });
            }
            self.ds *= 0.5;
            if self.ds < self.control.ds_min {
                return Err(ContinuationError::StepTooSmall {
                    param_name: "z".into(),
                    param: self.z[self.z.len() - 1],
                    ds: self.ds,
                    ds_min: self.control.ds_min,
                    cause: match attempt {
                        Err(e) => e.to_string(),
                        Ok(_) => "the tangent turned too sharply".into(),
                    },
                });
            }
        }
    }
}

/// Unit tangent of the curve at `z` (in the weighted norm of `control`),
/// oriented along `reference`: solves `[[DG(z)], [(W reference)^T]] t = (0, 1)`.
pub fn tangent_at<G: DefiningSystem>(
    system: &G,
    z: &DVector<f64>,
    reference: &DVector<f64>,
    control: &StepControl,
) -> Result<DVector<f64>, ContinuationError> {
    let m = system.n_equations();
    let mut g = DVector::zeros(m);
    let mut dg = DMatrix::zeros(m, z.len());
    system.eval(z, &mut g, &mut dg);
    tangent_from(&dg, reference, control)
}

/// The tangent of [`tangent_at`] from the Jacobian `dg = DG(z)` (`m` rows).
fn tangent_from(
    dg: &DMatrix<f64>,
    reference: &DVector<f64>,
    control: &StepControl,
) -> Result<DVector<f64>, ContinuationError> {
    let (m, nz) = dg.shape();
    let mut a = DMatrix::zeros(m + 1, nz);
    a.view_mut((0, 0), (m, nz)).copy_from(dg);
    let wref = control.weighted(reference);
    a.row_mut(m).copy_from(&wref.transpose());
    let mut rhs = DVector::zeros(m + 1);
    rhs[m] = 1.0;
    let t = solve(a, &rhs)?;
    let t = &t / control.dot(&t, &t).sqrt();
    Ok(if control.dot(&t, reference) < 0.0 {
        -t
    } else {
        t
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The unit circle `x^2 + y^2 = 1` in `z = (x, y)`.
    struct Circle;

    impl DefiningSystem for Circle {
        fn n_equations(&self) -> usize {
            1
        }
        fn n_unknowns(&self) -> usize {
            2
        }
        fn eval(&self, z: &DVector<f64>, g: &mut DVector<f64>, dg: &mut DMatrix<f64>) {
            g[0] = z[0] * z[0] + z[1] * z[1] - 1.0;
            dg[(0, 0)] = 2.0 * z[0];
            dg[(0, 1)] = 2.0 * z[1];
        }
    }

    #[test]
    fn a_corrected_point_beyond_a_bound_is_retaken_onto_it() {
        // Counterclockwise from angle a: the predictor leaves the circle and
        // the corrector pulls it in radially, to x_pred / sqrt(1 + ds^2). A
        // bound on x between the two is crossed by the corrector alone (the
        // diagram's Hopf curve ended 2.6e-4 beyond the top of its range so).
        let (a, ds) = (0.3f64, 0.2);
        let x_pred = a.cos() - ds * a.sin();
        let x_corr = x_pred / (1.0 + ds * ds).sqrt();
        let x_min = 0.5 * (x_pred + x_corr);
        let control = StepControl {
            ds,
            ds_min: 1e-8,
            ds_max: ds,
            growth: 1.0,
            min_tangent_cos: 0.5,
            corrector: NewtonSettings::default(),
            weights: Vec::new(),
        };
        let z0 = DVector::from_vec(vec![a.cos(), a.sin()]);
        let seed = DVector::from_vec(vec![-a.sin(), a.cos()]);
        let bounds = vec![Bound {
            index: 0,
            min: x_min,
            max: f64::INFINITY,
        }];
        let mut stepper = Stepper::new(Circle, z0, &seed, control, bounds).unwrap();
        let step = stepper.step().unwrap();
        let z = stepper.z();
        assert!(
            step.bound.is_some(),
            "landed at x = {} (bound {x_min})",
            z[0]
        );
        assert_eq!(z[0], x_min);
        assert!((z[0].hypot(z[1]) - 1.0).abs() < 1e-12, "{z}");
        assert!(
            step.ds > ds,
            "the landing step {} is longer than the prediction",
            step.ds
        );
    }
}
