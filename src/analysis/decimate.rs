//! Decimation of a simulated time series that keeps its extremes: the steps
//! are grouped in buckets of consecutive steps, and from each bucket the
//! first and last steps and those holding the least and greatest spring
//! force `s` and slip velocity (`log10 v`) are kept, in time order. A slip lasting a few
//! steps keeps its tip (every k-th step would cut it, and the figures of a
//! long run would alias).

use super::simulate::{Sample, Trajectory};

/// The samples of `bucket` a decimated series keeps: the first, the last,
/// and those holding the least and greatest `s` and `log10 v` (first
/// occurrence), in time order without repeats; at most six.
pub fn extremes(bucket: &[Sample]) -> Vec<Sample> {
    extreme_indices(bucket, |p| p)
        .iter()
        .map(|&i| bucket[i])
        .collect()
}

/// The indices of [`extremes`] in `items`, whose samples `sample` reads.
fn extreme_indices<T>(items: &[T], sample: impl Fn(&T) -> &Sample) -> Vec<usize> {
    if items.is_empty() {
        return Vec::new();
    }
    let arg = |key: fn(&Sample) -> f64, better: fn(f64, f64) -> bool| {
        (0..items.len())
            .reduce(|i, j| {
                if better(key(sample(&items[j])), key(sample(&items[i]))) {
                    j
                } else {
                    i
                }
            })
            .unwrap_or(0)
    };
    let lower = |a: f64, b: f64| a < b;
    let higher = |a: f64, b: f64| a > b;
    let mut keep = vec![
        0,
        items.len() - 1,
        arg(|p| p.s, lower),
        arg(|p| p.s, higher),
        arg(|p| p.log10_v, lower),
        arg(|p| p.log10_v, higher),
    ];
    keep.sort_unstable();
    keep.dedup();
    keep
}

/// A stream of samples grouped in buckets of `size` consecutive samples,
/// each handed on as its [`extremes`] when full (or at [`Buckets::finish`]).
#[derive(Clone, Debug)]
pub struct Buckets {
    size: usize,
    bucket: Vec<Sample>,
}

impl Buckets {
    /// Buckets of `size` samples (at least 1; size 1 keeps every sample).
    pub fn new(size: usize) -> Self {
        Buckets {
            size: size.max(1),
            bucket: Vec::new(),
        }
    }

    /// Adds `p`; when that fills the bucket its extremes go to `emit`.
    pub fn push<E>(
        &mut self,
        p: &Sample,
        mut emit: impl FnMut(&Sample) -> Result<(), E>,
    ) -> Result<(), E> {
        if self.size == 1 {
            return emit(p);
        }
        self.bucket.push(*p);
        if self.bucket.len() >= self.size {
            return self.finish(&mut emit);
        }
        Ok(())
    }

    /// Hands on the extremes of the samples added since the last full bucket.
    pub fn finish<E>(&mut self, emit: impl FnMut(&Sample) -> Result<(), E>) -> Result<(), E> {
        let kept = extremes(&self.bucket);
        self.bucket.clear();
        kept.iter().try_for_each(emit)
    }
}

/// A record of a run for its figures of at most `cap` samples, whatever the
/// run's length: the [`extremes`] of every bucket of `stride` consecutive
/// steps (buckets aligned on step 0), the stride doubling each time `cap` is
/// reached (the samples kept so far are then regrouped by buckets of twice
/// the steps: the extremes of a union are among those of its parts, so the
/// record is the same as if the run had been decimated with the new stride
/// from the start).
#[derive(Clone, Debug)]
pub struct Envelope {
    cap: usize,
    stride: usize,
    steps: usize,
    bucket: Vec<Sample>,
    /// Kept samples with their step number.
    kept: Vec<(usize, Sample)>,
}

/// The least `cap` of an [`Envelope`]: twice the most a bucket keeps.
pub const ENVELOPE_MIN_CAP: usize = 12;

impl Envelope {
    /// A record of at most `cap` samples (at least [`ENVELOPE_MIN_CAP`]).
    pub fn new(cap: usize) -> Self {
        Envelope {
            cap: cap.max(ENVELOPE_MIN_CAP),
            stride: 1,
            steps: 0,
            bucket: Vec::new(),
            kept: Vec::new(),
        }
    }

    /// Adds the run's next sample.
    pub fn push(&mut self, p: &Sample) {
        self.steps += 1;
        if self.stride == 1 {
            self.kept.push((self.steps - 1, *p));
        } else {
            // Buckets end on multiples of the stride (after a doubling the
            // first one is shorter), so that each lies in one window of a
            // later regrouping.
            self.bucket.push(*p);
            if !self.steps.is_multiple_of(self.stride) {
                return;
            }
            self.close_bucket();
        }
        while self.kept.len() >= self.cap {
            self.stride *= 2;
            let stride = self.stride;
            let mut regrouped = Vec::with_capacity(self.kept.len() / 2);
            for group in self.kept.chunk_by(|a, b| a.0 / stride == b.0 / stride) {
                regrouped.extend(extreme_indices(group, |k| &k.1).iter().map(|&i| group[i]));
            }
            self.kept = regrouped;
        }
    }

    /// Moves the extremes of the current bucket to the record.
    fn close_bucket(&mut self) {
        let first = self.steps - self.bucket.len();
        let keep = extreme_indices(&self.bucket, |p| p);
        self.kept
            .extend(keep.iter().map(|&i| (first + i, self.bucket[i])));
        self.bucket.clear();
    }

    /// Steps per bucket now in force (1: every step kept).
    pub fn stride(&self) -> usize {
        self.stride
    }

    /// The samples kept, with the run's last one.
    pub fn into_trajectory(mut self) -> Trajectory {
        self.close_bucket();
        let mut traj = Trajectory::default();
        for (_, p) in &self.kept {
            traj.push(p);
        }
        traj
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::ModelKind;

    /// A spike train: one step in 1000 slips (v up to 1e6 + i, s drops).
    fn sample(i: usize) -> Sample {
        let spike = i % 1000 == 500;
        Sample {
            t: i as f64,
            s: if spike {
                -1.0
            } else {
                (i % 1000) as f64 * 1e-3
            },
            v: 0.0,
            theta: 1.0,
            slip: 0.0,
            log10_v: if spike { 6.0 + i as f64 * 1e-9 } else { -3.0 },
            model: ModelKind::Inertial,
        }
    }

    #[test]
    fn envelope_keeps_every_spike_tip_within_its_cap() {
        let n = 1_000_000;
        let mut env = Envelope::new(5000);
        for i in 0..n {
            env.push(&sample(i));
        }
        assert!(env.stride() > 1);
        let traj = env.into_trajectory();
        assert!(traj.t.len() <= 5000, "{}", traj.t.len());
        let tips: Vec<f64> = traj
            .t
            .iter()
            .zip(&traj.log10_v)
            .filter(|(_, l)| **l > 5.0)
            .map(|(t, _)| *t)
            .collect();
        assert_eq!(tips.len(), n / 1000);
        assert!(tips.iter().all(|t| *t as usize % 1000 == 500));
        assert!(traj.t.windows(2).all(|w| w[0] < w[1]));
        assert_eq!(traj.t[0], 0.0);
        assert_eq!(*traj.t.last().unwrap(), (n - 1) as f64);
        assert_eq!(traj.s.iter().copied().fold(f64::INFINITY, f64::min), -1.0);
    }

    #[test]
    fn buckets_of_one_keep_every_sample() {
        let mut b = Buckets::new(1);
        let mut out = Vec::new();
        for i in 0..10 {
            b.push(&sample(i), |p| {
                out.push(p.t);
                Ok::<(), ()>(())
            })
            .unwrap();
        }
        b.finish(|p| {
            out.push(p.t);
            Ok::<(), ()>(())
        })
        .unwrap();
        assert_eq!(out, (0..10).map(|i| i as f64).collect::<Vec<_>>());
    }

    #[test]
    fn buckets_keep_at_most_six_in_order_and_the_last_step() {
        let mut b = Buckets::new(100);
        let mut out = Vec::new();
        for i in 0..1050 {
            b.push(&sample(i), |p| {
                out.push(*p);
                Ok::<(), ()>(())
            })
            .unwrap();
        }
        b.finish(|p| {
            out.push(*p);
            Ok::<(), ()>(())
        })
        .unwrap();
        assert!(out.len() <= 6 * 11);
        assert!(out.windows(2).all(|w| w[0].t < w[1].t));
        assert_eq!(out.last().unwrap().t, 1049.0);
        assert!(out.iter().any(|p| p.t == 500.0));
    }
}
