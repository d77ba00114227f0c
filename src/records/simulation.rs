//! The record of `simulate`: one row of the time series (`-simulation.csv`).

use crate::analysis::simulate::Sample;
use crate::model::ModelKind;
use crate::records::csv::CsvRecord;
use crate::scene::Units;
use serde::{Serialize, Serializer};

/// One integrator step: time in seconds and in `D0/V0`, the state, the slip
/// since the start (units `D0`), `log10 v`, and the model that computed it;
/// then the state in physical units (the columns before them are those
/// `simulate` has always written, in their order).
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct SimulationRow {
    pub t_s: f64,
    pub t: f64,
    pub s: f64,
    pub v: SlipVelocity,
    pub theta: f64,
    pub slip: f64,
    pub log10_v: f64,
    pub model: ModelKind,
    /// Spring force `K (V t - x) = s W` \[N\].
    #[serde(rename = "spring_force_N")]
    pub spring_force_n: f64,
    /// Slip velocity `v V0` [µm/s] (written from its logarithm below the
    /// floating-point range, as `v`).
    pub v_um_per_s: SlipVelocity,
    /// Age `theta D0/V0` \[s\].
    pub theta_s: f64,
    /// Slip since the start, `slip D0` \[µm\].
    pub slip_um: f64,
}

impl CsvRecord for SimulationRow {
    const DIGITS: usize = 12;
}

impl SimulationRow {
    /// The sample `p` with its time in the units `u`.
    pub fn new(p: &Sample, u: &Units) -> Self {
        SimulationRow {
            t_s: p.t * (u.d0 / u.v0),
            t: p.t,
            s: p.s,
            v: SlipVelocity {
                v: p.v,
                log10_v: p.log10_v,
            },
            theta: p.theta,
            slip: p.slip,
            log10_v: p.log10_v,
            model: p.model,
            spring_force_n: p.s * u.load,
            v_um_per_s: SlipVelocity {
                v: u.velocity_um_s(p.v),
                log10_v: p.log10_v + (u.v0 * 1e6).log10(),
            },
            theta_s: p.theta * u.d0 / u.v0,
            slip_um: p.slip * u.d0 * 1e6,
        }
    }
}

/// The slip velocity `v` (units `V0`) with its `log10`: a number in the
/// normal floating-point range; below it (where `v` underflows or loses
/// digits) the decimal text from `log10 v`, e.g. `3.162277660168e-400`,
/// never 0.
#[derive(Clone, Copy, Debug, Default)]
pub struct SlipVelocity {
    pub v: f64,
    pub log10_v: f64,
}

impl Serialize for SlipVelocity {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        if self.v >= f64::MIN_POSITIVE {
            return s.serialize_f64(self.v);
        }
        let e = self.log10_v.floor();
        let digits = SimulationRow::DIGITS;
        s.collect_str(&format_args!(
            "{:.digits$}e{}",
            10f64.powf(self.log10_v - e),
            e as i64
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::records::csv::row;

    /// A velocity below the range of f64 is written from its logarithm,
    /// one in range as the number.
    #[test]
    fn a_velocity_below_the_range_is_written_from_its_logarithm() {
        let cell = |v: f64, log10_v: f64| {
            let r = SimulationRow {
                v: SlipVelocity { v, log10_v },
                ..SimulationRow::default()
            };
            row(&r).unwrap().split(',').nth(3).unwrap().to_string()
        };
        assert_eq!(cell(0.0, -400.5), "3.162277660168e-401");
        assert_eq!(cell(2.5e-3, 2.5e-3f64.log10()), "2.500000000000e-3");
    }
}
