//! Pseudo-arclength continuation of the solution curve of a
//! [`DefiningSystem`] with one more unknown than equations (Keller 1977;
//! Kuznetsov 1998, §10.2.1).
//!
//! With unit tangent `t`, a step predicts `z + ds t` and corrects by Newton on
//! `G(z) = 0, t . (z - z_pred) = 0`, by the shared step of
//! [`crate::predictor_corrector`] (the step grows after easy corrections,
//! halves after failures or sharp turns of the tangent); a step that would
//! cross a bound is shortened to land on it.

use crate::defining::DefiningSystem;
use crate::error::ContinuationError;
use crate::linalg::solve;
use crate::newton::{self, DensePoint, NewtonReport, NewtonSettings};
use crate::predictor_corrector::{self, Corrected, CurveProblem, Review, StepControl};
use nalgebra::{DMatrix, DVector};

/// Settings of a curve: its step-size control, corrector and arclength norm.
#[derive(Clone, Debug)]
pub struct CurveControl {
    /// Step-size control.
    pub step: StepControl,
    /// Corrector settings.
    pub corrector: NewtonSettings,
    /// Weights of the unknowns in the arclength norm `|dz|^2 = sum w_i dz_i^2`
    /// (empty: all 1). Small weights on the state let the step follow the
    /// parameters, as AUTO's THL/THU do.
    pub weights: Vec<f64>,
    /// The unknowns whose weights are relative to the current point, `w_i /
    /// max(1, z_i^2)`: such an unknown spanning decades along the curve
    /// counts by its relative change, not by its size (with a fixed weight a
    /// state growing like `1/p` takes over the step as `p` goes to zero).
    pub relative: Vec<usize>,
}

impl CurveControl {
    /// The control in force at `z`: the weights of the unknowns
    /// [`CurveControl::relative`] made relative there.
    fn at(&self, z: &DVector<f64>) -> CurveControl {
        let mut control = self.clone();
        if !self.relative.is_empty() {
            control.weights = (0..z.len()).map(|i| self.weight(i)).collect();
            for &i in &self.relative {
                control.weights[i] /= z[i].abs().max(1.0).powi(2);
            }
        }
        control
    }

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
    control: CurveControl,
    bounds: Vec<Bound>,
}

impl<G: DefiningSystem> Stepper<G> {
    /// Starts at `z0` (already on the curve) with the tangent oriented along `seed`.
    pub fn new(
        mut system: G,
        z0: DVector<f64>,
        seed: &DVector<f64>,
        control: CurveControl,
        bounds: Vec<Bound>,
    ) -> Result<Self, ContinuationError> {
        system.accept(&z0)?;
        let tangent = tangent_at(&system, &z0, seed, &control.at(&z0))?;
        let ds = control.step.ds.abs();
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
        let control = self.control.at(&self.z);
        correct(&self.system, &control, z, tangent, fixed, settings).map(|(report, _)| report)
    }

    /// Takes one step that the corrector accepts ([`predictor_corrector::step`]).
    /// A step whose prediction crosses a bound, or whose corrected point lies
    /// beyond one (the corrector moves across the tangent), is retaken to
    /// land on the bound.
    pub fn step(&mut self) -> Result<Step, ContinuationError> {
        let control = self.control.at(&self.z);
        let mut curve = Arclength {
            system: &mut self.system,
            z: &mut self.z,
            tangent: &mut self.tangent,
            control: &control,
            bounds: &self.bounds,
            overshot: None,
            landed: None,
        };
        let stepped = predictor_corrector::step(&mut curve, &self.control.step, &mut self.ds)?;
        Ok(Step {
            report: stepped.report,
            bound: curve.landed,
            ds: stepped.ds,
        })
    }
}

/// Newton on `G(z) = 0` plus `t . (z - z_pred) = 0`, or plus `z_i = value`
/// when `fixed = Some((i, value))`; returns the report and the system
/// linearized at the solution (`DG` on its first `n_equations` rows).
fn correct<G: DefiningSystem>(
    system: &G,
    control: &CurveControl,
    z: &mut DVector<f64>,
    tangent: &DVector<f64>,
    fixed: Option<(usize, f64)>,
    settings: &NewtonSettings,
) -> Result<(NewtonReport, DensePoint), ContinuationError> {
    let m = system.n_equations();
    let z_pred = z.clone();
    let mut gs = DVector::zeros(m);
    let mut dgs = DMatrix::zeros(m, z.len());
    let wt = control.weighted(tangent);
    let mut diff = DVector::zeros(z.len());
    newton::solve_dense(z, settings, "", |z, g, dg| {
        system.eval(z, &mut gs, &mut dgs);
        g.rows_mut(0, m).copy_from(&gs);
        dg.view_mut((0, 0), (m, z.len())).copy_from(&dgs);
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

/// A point corrected by [`Arclength`]: the point, the system linearized
/// there and the bound it landed on.
struct ArcPoint {
    z: DVector<f64>,
    linearized: DensePoint,
    bound: Option<Bound>,
}

/// One step of a [`Stepper`], as a [`CurveProblem`] with bounds to land on.
struct Arclength<'s, G: DefiningSystem> {
    system: &'s mut G,
    z: &'s mut DVector<f64>,
    tangent: &'s mut DVector<f64>,
    control: &'s CurveControl,
    bounds: &'s [Bound],
    /// A bound the last corrected point overshot: the step is retaken onto it.
    overshot: Option<(Bound, f64)>,
    /// The bound the accepted step landed on.
    landed: Option<Bound>,
}

impl<G: DefiningSystem> Arclength<'_, G> {
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
}

impl<G: DefiningSystem> CurveProblem for Arclength<'_, G> {
    type Point = ArcPoint;
    type Tangent = DVector<f64>;

    /// The prediction `z + ds t`, or, when it crosses a bound (or the last
    /// corrected point overshot one), the point of the tangent on the bound,
    /// corrected there with the bounded unknown fixed.
    fn correct(&mut self, ds: f64) -> Result<Corrected<ArcPoint>, ContinuationError> {
        let mut ds = ds;
        let mut z_new = &*self.z + &*self.tangent * ds;
        let crossed = self.overshot.take().or_else(|| self.beyond(&z_new));
        if let Some((b, target)) = crossed {
            ds = (target - self.z[b.index]) / self.tangent[b.index];
            z_new = &*self.z + &*self.tangent * ds;
            z_new[b.index] = target;
        }
        let fixed = crossed.map(|(b, target)| (b.index, target));
        let (report, linearized) = correct(
            self.system,
            self.control,
            &mut z_new,
            self.tangent,
            fixed,
            &self.control.corrector,
        )?;
        Ok(Corrected {
            point: ArcPoint {
                z: z_new,
                linearized,
                bound: crossed.map(|(b, _)| b),
            },
            report,
            ds,
            constrained: crossed.is_some(),
        })
    }

    /// From the corrector's last evaluation, at the point: its `DG` is reused.
    fn tangent(&mut self, point: &mut ArcPoint) -> Result<DVector<f64>, ContinuationError> {
        let a = std::mem::replace(&mut point.linearized.dg, DMatrix::zeros(0, 0));
        tangent_from(a, self.tangent, self.control)
    }

    fn turn(&self, tangent: &DVector<f64>) -> f64 {
        self.control.dot(tangent, self.tangent)
    }

    /// A point corrected along the tangent but beyond a bound is retaken onto
    /// the bound when the tangent leads there, else rejected.
    fn review(&mut self, corrected: &Corrected<ArcPoint>) -> Review {
        if corrected.constrained {
            return Review::Keep;
        }
        let Some((b, target)) = self.beyond(&corrected.point.z) else {
            return Review::Keep;
        };
        let landing = (target - self.z[b.index]) / self.tangent[b.index];
        if landing.is_finite() && landing * corrected.ds > 0.0 {
            self.overshot = Some((b, target));
            Review::Retake
        } else {
            Review::Reject("the corrected point lies beyond a bound the tangent leads away from")
        }
    }

    fn accept(&mut self, point: ArcPoint, tangent: DVector<f64>) -> Result<(), ContinuationError> {
        self.system.accept(&point.z)?;
        *self.z = point.z;
        *self.tangent = tangent;
        self.landed = point.bound;
        Ok(())
    }

    fn location(&self) -> (String, f64) {
        ("z".into(), self.z[self.z.len() - 1])
    }
}

/// Unit tangent of the curve at `z` (in the weighted norm of `control`),
/// oriented along `reference`: solves `[[DG(z)], [(W reference)^T]] t = (0, 1)`.
pub fn tangent_at<G: DefiningSystem>(
    system: &G,
    z: &DVector<f64>,
    reference: &DVector<f64>,
    control: &CurveControl,
) -> Result<DVector<f64>, ContinuationError> {
    let m = system.n_equations();
    let mut g = DVector::zeros(m);
    let mut dg = DMatrix::zeros(m, z.len());
    system.eval(z, &mut g, &mut dg);
    let mut a = DMatrix::zeros(m + 1, z.len());
    a.view_mut((0, 0), (m, z.len())).copy_from(&dg);
    tangent_from(a, reference, control)
}

/// The tangent of [`tangent_at`] from `a`, whose first rows hold `DG(z)`;
/// its last row is overwritten with `(W reference)^T`.
fn tangent_from(
    mut a: DMatrix<f64>,
    reference: &DVector<f64>,
    control: &CurveControl,
) -> Result<DVector<f64>, ContinuationError> {
    let m = a.nrows() - 1;
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
        let control = CurveControl {
            step: StepControl {
                ds,
                ds_min: 1e-8,
                ds_max: ds,
                growth: 1.0,
                easy_iterations: 3,
                min_tangent_cos: 0.5,
            },
            corrector: NewtonSettings::default(),
            weights: Vec::new(),
            relative: Vec::new(),
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
