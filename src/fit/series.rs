//! The time series of `stickslip fit` (`velocity_step`, `relaxation`): the
//! spring-block equations of docs/model.md integrated with their forward
//! sensitivities to the law's parameters.
//!
//! In the log variables of [`LogBlock`] (state `X = (s, ln v, ln theta)`,
//! quasi-statically `(s, ln theta)`) and in physical time `t` \[s\], with the
//! rate `c = V0 / D0`:
//!
//! ```text
//! dX/dt   = c f(X, P(q))                                         (docs/model.md)
//! dS_k/dt = c (D_X f S_k + d f / d q_k) + (d c / d q_k) f         (variational equations)
//! S_k(t0) = d X(t0) / d q_k,  X(t0) = (mu_ss(nu0), ln nu0, -ln nu0)   (steady sliding, eq. RR5)
//! ```
//!
//! where `q = (mu0, A, B, D0 [µm], mu2 | tau [s])` are the law's values and
//! `P(q)` the dimensionless parameters on the scene's rig: `kappa = (K/W)
//! D0`, `m = (M/W) V0^2 / D0` (inertial model), `theta_c = tau V0 / D0`,
//! `nu = V / V0`. `S = dX/dq` is integrated alongside `X` by the same Radau
//! IIA integrator as `simulate` (one augmented system, the error control
//! on both); the right-hand side of each `S_k` is one forward dual-number
//! pass (`Dual<D>`) through the same `f`, so `D_X f S_k + d f / d q_k` is
//! exact. The measured quantities are `mu = s` (the spring force over the
//! load) and the slip `x(t) - x(0) = (s(0) - s(t)) / (K/W)` after the drive
//! stops (`nu = 0`: `ds/dt = -kappa v`).

use super::data::{Dataset, Kind};
use super::model::{AgeingValue, Fixed, Rig, Values};
use crate::analysis::simulate::{integration_stop, Segment};
use crate::log_model::LogBlock;
use crate::model::ModelKind;
use crate::params::{Param, StateLaw, N_PARAMS};
use continuation::integrate::{Outcome, Output, Radau5, Settings};
use continuation::{Scalar, VectorField};
use nalgebra::DMatrix;
use num_dual::{Dual, Dual64};

/// The law's values `q`: `mu0, A, B, D0, mu2 | tau`.
pub const N_LAW: usize = 5;

/// Relative tolerance of the integration (the absolute one is `1e-3`
/// times it): the model's error is then about 1e-8 of `mu` and of the
/// slip, four orders below the data's (tests/fit_series.rs checks it).
pub const RTOL: f64 = 1e-8;

/// The law's values as `q` (module docs).
pub fn law_vector<T: Scalar>(v: &Values<T>) -> [T; N_LAW] {
    let ageing = match v.ageing {
        AgeingValue::Mu2(x) | AgeingValue::Tau(x) => x,
    };
    [v.mu0, v.a, v.b, v.d0_um, ageing]
}

/// The real parts of `v`.
pub fn real_values<T: Scalar>(v: &Values<T>) -> Values<f64> {
    let q = law_vector(v).map(|x| x.re());
    let ageing = match v.ageing {
        AgeingValue::Mu2(_) => AgeingValue::Mu2(q[4]),
        AgeingValue::Tau(_) => AgeingValue::Tau(q[4]),
    };
    with_law(
        &Values {
            mu0: 0.0,
            a: 0.0,
            b: 0.0,
            d0_um: 0.0,
            ageing,
            fixed: v.fixed,
        },
        &q,
    )
}

/// `values`' ageing form and fixed terms with the law's values `q`.
pub fn with_law<T: Scalar>(values: &Values<f64>, q: &[T]) -> Values<T> {
    Values {
        mu0: q[0],
        a: q[1],
        b: q[2],
        d0_um: q[3],
        ageing: match values.ageing {
            AgeingValue::Mu2(_) => AgeingValue::Mu2(q[4]),
            AgeingValue::Tau(_) => AgeingValue::Tau(q[4]),
        },
        fixed: values.fixed,
    }
}

/// A protocol of load-point velocities: steady sliding at `steady_um_s`
/// before the first stretch, then stretches of constant velocity, the last
/// one up to the last output time.
#[derive(Clone, Debug, PartialEq)]
pub struct Protocol {
    pub steady_um_s: f64,
    /// `(start [s], V [µm/s])`, starts increasing.
    pub stretches: Vec<(f64, f64)>,
    /// The output times \[s\], increasing, none before the first stretch.
    pub times: Vec<f64>,
}

impl Protocol {
    /// The protocol of a time series: a velocity step's rows (each row's
    /// velocity until the next row's time; equal velocities of successive
    /// rows one stretch), or a relaxation (the drive stopped at `t = 0`).
    pub fn of(d: &Dataset) -> Protocol {
        let steady_um_s = d.v_um_s.first().copied().unwrap_or(f64::NAN);
        let stretches = match d.kind {
            Kind::Relaxation => vec![(0.0, 0.0)],
            _ => {
                let mut s: Vec<(f64, f64)> = Vec::new();
                for (&t, &v) in d.t_s.iter().zip(&d.v_um_s) {
                    if s.last().is_none_or(|l| l.1 != v) {
                        s.push((t, v));
                    }
                }
                s
            }
        };
        Protocol {
            steady_um_s,
            stretches,
            times: d.t_s.clone(),
        }
    }

    /// The fastest load-point velocity [µm/s], steady sliding included.
    pub fn top_um_s(&self) -> f64 {
        self.stretches
            .iter()
            .map(|s| s.1)
            .fold(self.steady_um_s, f64::max)
    }

    /// The stretches as `simulate`'s segments: `nu = V / V0` for durations
    /// in `time_unit_s = D0 / V0` \[s\].
    pub fn segments(&self, time_unit_s: f64, v0_um_s: f64) -> Vec<Segment> {
        self.spans()
            .map(|(t0, t1, v)| Segment {
                nu: v / v0_um_s,
                duration: (t1 - t0) / time_unit_s,
            })
            .collect()
    }

    /// The stretches as `(start, end, V)`, the last ending at the last
    /// output time; empty ones left out.
    fn spans(&self) -> impl Iterator<Item = (f64, f64, f64)> + '_ {
        let end = self.times.last().copied().unwrap_or(0.0);
        self.stretches
            .iter()
            .enumerate()
            .map(move |(j, &(t0, v))| {
                let t1 = self.stretches.get(j + 1).map_or(end, |n| n.0.min(end));
                (t0, t1, v)
            })
            .filter(|(t0, t1, _)| t1 > t0)
    }
}

/// What a time series measures.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Observable {
    /// `mu = s`, the spring force over the load.
    Friction,
    /// The slip since `t = 0` \[µm\].
    Slip,
}

/// One time series' model: the rig, the model (quasi-static or inertial,
/// decided as `simulate` decides it), the law's forms, the protocol.
#[derive(Clone, Debug)]
pub struct SeriesModel {
    pub kind: ModelKind,
    /// The cutoff ageing form (else the logarithmic one).
    pub cutoff: bool,
    /// The scene's evolution law of `theta` (ageing or slip, docs/model.md):
    /// a velocity step and a relaxation tell them apart, unlike steady
    /// sliding and the onset.
    pub state_law: StateLaw,
    pub rig: Rig,
    /// The rig's stiffness over load `K/W` [1/m].
    pub k_over_w: f64,
    pub protocol: Protocol,
    pub observable: Observable,
}

/// The model's values at the output times and their derivatives in the
/// law's values `q` (rows by [`N_LAW`]).
#[derive(Clone, Debug)]
pub struct Solved {
    pub values: Vec<f64>,
    pub jacobian: DMatrix<f64>,
}

impl SeriesModel {
    /// The model of dataset `d` (a time series) of `kind` on the rig.
    pub fn new(
        d: &Dataset,
        kind: ModelKind,
        (cutoff, state_law): (bool, StateLaw),
        rig: Rig,
        k_over_w: f64,
    ) -> Self {
        SeriesModel {
            kind,
            cutoff,
            state_law,
            rig,
            k_over_w,
            protocol: Protocol::of(d),
            observable: match d.kind {
                Kind::Relaxation => Observable::Slip,
                _ => Observable::Friction,
            },
        }
    }

    /// Integrates the protocol with the sensitivities at the values `v`
    /// (module docs) at the tolerance [`RTOL`]; the error names the time
    /// \[s\] where the integration failed.
    pub fn solve(&self, v: &Values<f64>) -> Result<Solved, String> {
        self.solve_at(v, RTOL)
    }

    /// [`SeriesModel::solve`] at the relative tolerance `rtol` (absolute:
    /// `1e-3 rtol`).
    pub fn solve_at(&self, v: &Values<f64>, rtol: f64) -> Result<Solved, String> {
        let q = law_vector(v);
        let block = LogBlock::at(self.kind, self.cutoff, self.state_law, [0.0; 3]);
        let n = block.dim();
        let nu0 = self.protocol.steady_um_s / self.rig.v0_um_s;
        // X(t0) and S(t0): steady sliding, s0 = mu_ss(nu0) by dual numbers.
        let mut y = vec![0.0; n * (1 + N_LAW)];
        let x0 = block.from_model(0.0, nu0, nu0.recip());
        y[..n].copy_from_slice(&x0);
        let mut ds0 = [0.0; N_LAW];
        for (k, d) in ds0.iter_mut().enumerate() {
            let qd: Vec<Dual64> = (0..N_LAW)
                .map(|j| Dual64::new(q[j], if j == k { 1.0 } else { 0.0 }))
                .collect();
            let s0 = self
                .rig
                .steady(&with_law(v, &qd), self.protocol.steady_um_s);
            y[0] = s0.re;
            *d = s0.eps;
            y[n * (1 + k)] = s0.eps;
        }
        let s0 = y[0];
        let times = &self.protocol.times;
        let rows = times.len();
        let mut values = Vec::with_capacity(rows);
        let mut jacobian = DMatrix::zeros(rows, N_LAW);
        // mu = s; the slip (s(0) - s) / (K/W) in µm.
        let (scale, shift, d_shift) = match self.observable {
            Observable::Friction => (1.0, 0.0, [0.0; N_LAW]),
            Observable::Slip => (-1e6 / self.k_over_w, s0, ds0),
        };
        let record = |y: &[f64], values: &mut Vec<f64>, jacobian: &mut DMatrix<f64>| {
            let i = values.len();
            values.push(scale * (y[0] - shift));
            for k in 0..N_LAW {
                jacobian[(i, k)] = scale * (y[n * (1 + k)] - d_shift[k]);
            }
        };
        let first = self.protocol.stretches.first().map_or(0.0, |s| s.0);
        while values.len() < rows && times[values.len()] <= first {
            record(&y, &mut values, &mut jacobian);
        }
        let settings = Settings {
            rtol,
            atol: rtol * 1e-3,
            ..Settings::default()
        };
        for (t0, t1, v_um_s) in self.protocol.spans() {
            let next = values.len();
            let mut grid: Vec<f64> = times[next..]
                .iter()
                .take_while(|&&t| t <= t1)
                .map(|t| t - t0)
                .collect();
            let outputs = grid.len();
            if grid.last() != Some(&(t1 - t0)) {
                grid.push(t1 - t0);
            }
            let system = Variational {
                block,
                fixed: v.fixed,
                rig: self.rig,
                k_over_w: self.k_over_w,
                nu: v_um_s / self.rig.v0_um_s,
            };
            let sol = Radau5::new(&system, &q, settings.clone()).solve(
                0.0,
                &y,
                t1 - t0,
                Output::Grid(grid),
            );
            if let Outcome::Failed(e) = &sol.outcome {
                return Err(format!(
                    "the integration at V = {v_um_s} µm/s from t = {t0} s failed ({}, in the \
                     integrator's time from there, in s)",
                    integration_stop(e)
                ));
            }
            for x in sol.x.iter().take(outputs) {
                record(x, &mut values, &mut jacobian);
            }
            y = sol.x_final;
        }
        if values.iter().chain(jacobian.iter()).any(|x| !x.is_finite()) {
            return Err("the integrated model is not finite".into());
        }
        Ok(Solved { values, jacobian })
    }
}

/// The spring block with its variational equations, in physical time, for
/// the law's values `q` as parameters (module docs).
struct Variational {
    block: LogBlock,
    /// The scene's terms held at their values.
    fixed: Fixed,
    rig: Rig,
    k_over_w: f64,
    nu: f64,
}

impl Variational {
    /// `P(q)` in the engine's parameter vector, and the rate `c = V0/D0` [1/s].
    fn dimensionless<T: Scalar>(&self, q: &[T]) -> ([T; N_PARAMS], T) {
        let zero = T::from(0.0);
        let d0_m = q[3] * 1e-6;
        let v0_m_s = self.rig.v0_um_s * 1e-6;
        let mut p = [zero; N_PARAMS];
        p[Param::Kappa as usize] = d0_m * self.k_over_w;
        p[Param::Nu as usize] = T::from(self.nu);
        p[Param::M as usize] = match self.block.kind {
            ModelKind::Inertial => d0_m.recip() * (self.rig.mass_over_load * v0_m_s * v0_m_s),
            ModelKind::QuasiStatic => zero,
        };
        p[Param::A as usize] = q[1];
        p[Param::B as usize] = q[2];
        p[Param::Mu0 as usize] = q[0];
        p[Param::MuVv as usize] = T::from(self.fixed.mu_vv);
        p[Param::MuVphi as usize] = T::from(self.fixed.mu_vphi);
        p[Param::EtaD as usize] = T::from(self.fixed.eta_d);
        let rate = q[3].recip() * self.rig.v0_um_s;
        if self.block.cutoff {
            p[Param::ThetaC as usize] = q[4] * rate;
        } else {
            p[Param::Mu2 as usize] = q[4];
        }
        (p, rate)
    }
}

impl VectorField for Variational {
    fn dim(&self) -> usize {
        self.block.dim() * (1 + N_LAW)
    }

    fn n_params(&self) -> usize {
        N_LAW
    }

    fn rhs<D: Scalar>(&self, y: &[D], q: &[D], out: &mut [D]) {
        let n = self.block.dim();
        let zero = Dual::<D>::from_re(D::from(0.0));
        for k in 0..N_LAW {
            let mut x = [zero; 3];
            for (i, xi) in x.iter_mut().enumerate().take(n) {
                *xi = Dual::new(y[i], y[n * (1 + k) + i]);
            }
            let mut qd = [zero; N_LAW];
            for (j, qj) in qd.iter_mut().enumerate() {
                *qj = Dual::new(q[j], D::from(if j == k { 1.0 } else { 0.0 }));
            }
            let (p, rate) = self.dimensionless(&qd);
            let mut f = [zero; 3];
            self.block.rhs(&x[..n], &p, &mut f[..n]);
            for i in 0..n {
                let fi = f[i] * rate;
                if k == 0 {
                    out[i] = fi.re;
                }
                out[n * (1 + k) + i] = fi.eps;
            }
        }
    }
}
