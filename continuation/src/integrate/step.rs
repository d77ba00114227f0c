//! One Radau IIA step: starting values, the simplified Newton iteration in
//! transformed variables, the embedded error estimate and the dense output.
//!
//! With `Z_i = Y_i - y0` the stage increments at `t0 + c_i h`, the collocation
//! equations are `Z = h (A ⊗ I) F(Z)`. Simplified Newton with the Jacobian
//! `J` frozen at the start of the step solves
//! `(h^-1 A^-1 ⊗ I - I ⊗ J) dZ = -h^-1 (A^-1 ⊗ I) Z + F(Z)`. In the variables
//! `W = (T^-1 ⊗ I) Z` the matrix `A^-1` becomes block diagonal, so each
//! iteration needs one real solve with `E1 = (gamma/h) I - J` and one complex
//! solve with `E2 = ((alpha + i beta)/h) I - J`, `n x n` each, instead of a
//! `3n x 3n` real solve (Hairer & Wanner II, §IV.8, "Implementation").

use super::error::NewtonTrouble;
use super::lu::{Lu, Singular};
use super::tableau::{ALPHA, BETA, C1, C1M1, C1MC2, C2, C2M1, DD, GAMMA, T, TI};
use crate::system::VectorField;
use nalgebra::DMatrix;
use num_complex::Complex64;

/// Preallocated state of the integrator: nothing in the step loop allocates
/// except the Jacobian evaluation of the [`VectorField`] itself.
pub(crate) struct Work {
    pub(crate) n: usize,
    /// State at the current time `t` (the end of the last accepted step).
    pub(crate) y: Vec<f64>,
    /// `f(y)`.
    pub(crate) f0: Vec<f64>,
    /// Error weights `atol_i + rtol |y_i|` (internal tolerances).
    pub(crate) scal: Vec<f64>,
    /// Stage increments `Z_1..Z_3` (also scratch for `F(Z)` in the iteration).
    z: [Vec<f64>; 3],
    /// Transformed increments `W = T^-1 Z`.
    w: [Vec<f64>; 3],
    /// Newton coefficients of the collocation polynomial of the last accepted step.
    cont: [Vec<f64>; 3],
    tmp: Vec<f64>,
    ftmp: Vec<f64>,
    comb: Vec<f64>,
    cbuf: Vec<Complex64>,
    pub(crate) jac: DMatrix<f64>,
    e1: Lu<f64>,
    e2: Lu<Complex64>,
}

/// Result of the Newton iteration of one step attempt.
pub(crate) enum Newton {
    /// Converged after this many iterations.
    Converged(usize),
    /// Converging too slowly for this `h`: retry with `h * factor`.
    Shrink(f64),
    /// Failed; the driver halves `h`.
    Failed(NewtonTrouble),
}

/// Convergence control carried from step to step (RADAU5's `FACCON`, `THETA`).
pub(crate) struct NewtonControl {
    /// Stopping tolerance of the iteration (scaled norm of the increment).
    pub(crate) fnewt: f64,
    /// Iteration limit.
    pub(crate) max_iter: usize,
    /// Contraction factor below which the Jacobian is kept.
    pub(crate) theta_keep: f64,
    /// Estimate `theta/(1 - theta)` of the error-to-increment ratio.
    pub(crate) faccon: f64,
    /// Last observed contraction factor.
    pub(crate) theta: f64,
}

fn rms(v: &[f64], scal: &[f64]) -> f64 {
    let s: f64 = v.iter().zip(scal).map(|(a, s)| (a / s) * (a / s)).sum();
    (s / v.len() as f64).sqrt()
}

impl Work {
    pub(crate) fn new(n: usize) -> Self {
        let v = || vec![0.0; n];
        Work {
            n,
            y: v(),
            f0: v(),
            scal: v(),
            z: [v(), v(), v()],
            w: [v(), v(), v()],
            cont: [v(), v(), v()],
            tmp: v(),
            ftmp: v(),
            comb: v(),
            cbuf: vec![Complex64::new(0.0, 0.0); n],
            jac: DMatrix::zeros(n, n),
            e1: Lu::new(n, 0.0),
            e2: Lu::new(n, Complex64::new(0.0, 0.0)),
        }
    }

    /// Factors `E1 = (gamma/h) I - J` and `E2 = ((alpha + i beta)/h) I - J`.
    pub(crate) fn decompose(&mut self, h: f64) -> Result<(), Singular> {
        let jac = &self.jac;
        let fac1 = GAMMA / h;
        self.e1
            .factor(|i, j| if i == j { fac1 } else { 0.0 } - jac[(i, j)])?;
        let s = Complex64::new(ALPHA / h, BETA / h);
        let zero = Complex64::new(0.0, 0.0);
        self.e2
            .factor(|i, j| if i == j { s } else { zero } - jac[(i, j)])
    }

    /// Starting values for the stage increments: zero on the first step,
    /// otherwise the collocation polynomial of the previous step extrapolated
    /// to `t + c_i h` (`h_old` is the length of that step).
    pub(crate) fn start_values(&mut self, first: bool, h: f64, h_old: f64) {
        if first {
            for k in 0..3 {
                self.z[k].fill(0.0);
                self.w[k].fill(0.0);
            }
            return;
        }
        let c3q = h / h_old;
        let cq = [C1 * c3q, C2 * c3q, c3q];
        for i in 0..self.n {
            let (a1, a2, a3) = (self.cont[0][i], self.cont[1][i], self.cont[2][i]);
            let zi = cq.map(|q| q * (a1 + (q - C2M1) * (a2 + (q - C1M1) * a3)));
            for (k, ti) in TI.iter().enumerate() {
                self.z[k][i] = zi[k];
                self.w[k][i] = ti[0] * zi[0] + ti[1] * zi[1] + ti[2] * zi[2];
            }
        }
    }

    /// The simplified Newton iteration for the stage equations of a step of
    /// length `h` from `y` (RADAU5's loop, including its stopping rule
    /// `faccon |dW| <= fnewt` and its early step-size reduction when the
    /// predicted error after `max_iter` iterations is too large).
    pub(crate) fn newton<S: VectorField>(
        &mut self,
        sys: &S,
        p: &[f64],
        h: f64,
        ctl: &mut NewtonControl,
        n_rhs: &mut usize,
    ) -> Newton {
        let n = self.n;
        let nit = ctl.max_iter;
        let (fac1, alphn, betan) = (GAMMA / h, ALPHA / h, BETA / h);
        ctl.faccon = ctl.faccon.max(f64::EPSILON).powf(0.8);
        ctl.theta = ctl.theta_keep.abs();
        let (mut dynold, mut thqold) = (0.0f64, 0.0f64);
        let mut newt = 0usize;
        loop {
            if newt >= nit {
                return Newton::Failed(NewtonTrouble::MaxIterations);
            }
            // F at the three stages, written over Z (Z is recomputed from W below).
            for k in 0..3 {
                for i in 0..n {
                    self.tmp[i] = self.y[i] + self.z[k][i];
                }
                sys.rhs(&self.tmp, p, &mut self.z[k]);
            }
            *n_rhs += 3;
            if self.z.iter().any(|v| v.iter().any(|x| !x.is_finite())) {
                return Newton::Failed(NewtonTrouble::NonFinite);
            }
            // Right-hand sides in transformed variables.
            for i in 0..n {
                let f = [self.z[0][i], self.z[1][i], self.z[2][i]];
                let g: [f64; 3] =
                    std::array::from_fn(|k| TI[k][0] * f[0] + TI[k][1] * f[1] + TI[k][2] * f[2]);
                let (w1, w2, w3) = (self.w[0][i], self.w[1][i], self.w[2][i]);
                self.z[0][i] = g[0] - fac1 * w1;
                self.z[1][i] = g[1] - alphn * w2 + betan * w3;
                self.z[2][i] = g[2] - alphn * w3 - betan * w2;
            }
            self.e1.solve(&mut self.z[0]);
            for i in 0..n {
                self.cbuf[i] = Complex64::new(self.z[1][i], self.z[2][i]);
            }
            self.e2.solve(&mut self.cbuf);
            for i in 0..n {
                self.z[1][i] = self.cbuf[i].re;
                self.z[2][i] = self.cbuf[i].im;
            }
            newt += 1;
            let dyno = {
                let s: f64 = (0..n)
                    .map(|i| {
                        let d = self.scal[i];
                        (0..3).map(|k| (self.z[k][i] / d).powi(2)).sum::<f64>()
                    })
                    .sum();
                (s / (3 * n) as f64).sqrt()
            };
            if !dyno.is_finite() {
                return Newton::Failed(NewtonTrouble::NonFinite);
            }
            if newt > 1 && newt < nit {
                let thq = dyno / dynold;
                ctl.theta = if newt == 2 {
                    thq
                } else {
                    (thq * thqold).sqrt()
                };
                thqold = thq;
                if ctl.theta < 0.99 {
                    ctl.faccon = ctl.theta / (1.0 - ctl.theta);
                    let left = (nit - 1 - newt) as i32;
                    let dyth = ctl.faccon * dyno * ctl.theta.powi(left) / ctl.fnewt;
                    if dyth >= 1.0 {
                        let qnewt = dyth.clamp(1e-4, 20.0);
                        return Newton::Shrink(0.8 * qnewt.powf(-1.0 / (4.0 + left as f64)));
                    }
                } else {
                    return Newton::Failed(NewtonTrouble::Diverging { theta: ctl.theta });
                }
            }
            dynold = dyno.max(f64::EPSILON);
            for i in 0..n {
                let wi: [f64; 3] = std::array::from_fn(|k| self.w[k][i] + self.z[k][i]);
                for k in 0..3 {
                    self.w[k][i] = wi[k];
                    self.z[k][i] = T[k][0] * wi[0] + T[k][1] * wi[1] + T[k][2] * wi[2];
                }
            }
            if ctl.faccon * dyno <= ctl.fnewt {
                return Newton::Converged(newt);
            }
        }
    }

    /// The RADAU5 error estimate: `err = E1^-1 (f(y0) + (DD . Z)/h)`, i.e. the
    /// difference to an embedded order-3 solution filtered by
    /// `(I - h gamma0 J)^-1` so that it stays bounded for stiff components
    /// (Hairer & Wanner II, §IV.8, eq. (8.19)–(8.20)). On the first step or
    /// after a rejection a large estimate is recomputed once with `f`
    /// evaluated at `y0 + err` (their eq. (8.21)). Returns the scaled RMS norm,
    /// at least `1e-10`.
    pub(crate) fn error_estimate<S: VectorField>(
        &mut self,
        sys: &S,
        p: &[f64],
        h: f64,
        refine: bool,
        n_rhs: &mut usize,
    ) -> f64 {
        let n = self.n;
        let hee = [DD[0] / h, DD[1] / h, DD[2] / h];
        for i in 0..n {
            self.comb[i] = hee[0] * self.z[0][i] + hee[1] * self.z[1][i] + hee[2] * self.z[2][i];
            self.tmp[i] = self.comb[i] + self.f0[i];
        }
        self.e1.solve(&mut self.tmp);
        let mut err = rms(&self.tmp, &self.scal).max(1e-10);
        if err >= 1.0 && refine {
            for i in 0..n {
                self.tmp[i] += self.y[i];
            }
            sys.rhs(&self.tmp, p, &mut self.ftmp);
            *n_rhs += 1;
            for i in 0..n {
                self.tmp[i] = self.ftmp[i] + self.comb[i];
            }
            self.e1.solve(&mut self.tmp);
            err = rms(&self.tmp, &self.scal).max(1e-10);
        }
        if err.is_nan() {
            f64::INFINITY
        } else {
            err
        }
    }

    /// Accepts the step: `y <- y + Z_3` and stores the collocation polynomial
    /// in Newton form on the nodes `1, c2, c1, 0` of the scaled time
    /// `s = (t - t_new)/h` (so `s` runs over `[-1, 0]`).
    pub(crate) fn accept(&mut self) {
        for i in 0..self.n {
            let (z1, z2, z3) = (self.z[0][i], self.z[1][i], self.z[2][i]);
            self.y[i] += z3;
            let c1 = (z2 - z3) / C2M1;
            let ak = (z1 - z2) / C1MC2;
            let acont3 = (ak - z1 / C1) / C2;
            let c2 = (ak - c1) / C1M1;
            self.cont[0][i] = c1;
            self.cont[1][i] = c2;
            self.cont[2][i] = c2 - acont3;
        }
    }

    /// Recomputes the error weights from the current `y`.
    pub(crate) fn update_scale(&mut self, rtol: f64, atol: &[f64]) {
        for ((s, a), y) in self.scal.iter_mut().zip(atol).zip(&self.y) {
            *s = a + rtol * y.abs();
        }
    }

    /// The dense output of the last accepted step, which ends at the
    /// compensated time `t_new + t_new_lo`.
    pub(crate) fn dense(&self, t_new: f64, t_new_lo: f64, h: f64) -> Dense<'_> {
        Dense {
            t_new,
            t_new_lo,
            h,
            y: &self.y,
            cont: [&self.cont[0], &self.cont[1], &self.cont[2]],
        }
    }
}

/// The collocation polynomial of one accepted step (a borrowed view).
#[derive(Clone, Copy)]
pub(crate) struct Dense<'w> {
    /// The step end, rounded.
    t_new: f64,
    /// The rounding error of `t_new` (the step ends at `t_new + t_new_lo`).
    t_new_lo: f64,
    h: f64,
    y: &'w [f64],
    cont: [&'w [f64]; 3],
}

impl Dense<'_> {
    /// Writes `u(t)` into `out`; exact at the step end (`t == t_new`, the
    /// rounded end), order-3 accurate (uniformly) inside the step,
    /// extrapolation outside it. The offset from the end is taken from the
    /// compensated end time, so a step only a few units in the last place of
    /// `t` long is still resolved.
    pub(crate) fn eval(&self, t: f64, out: &mut [f64]) {
        if t == self.t_new {
            out.copy_from_slice(self.y);
            return;
        }
        let s = ((t - self.t_new) - self.t_new_lo) / self.h;
        let [a1, a2, a3] = self.cont;
        for i in 0..self.y.len() {
            out[i] = self.y[i] + s * (a1[i] + (s - C2M1) * (a2[i] + (s - C1M1) * a3[i]));
        }
    }
}
