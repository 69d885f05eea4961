//! Repeated timed runs and their medians.
//!
//! Every timing in the report is the median of several samples taken in the same process
//! run, so that ratios between two timings compare runs made under the same conditions
//! (other load on the machine, clock frequency) as closely as a sequential run can.

use glam::DVec3;
use serde::{Deserialize, Serialize};
use std::hint::black_box;
use std::time::{Duration, Instant};

/// How long evaluations take: the median over samples of the time per evaluation, and the
/// samples themselves.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct EvalTiming {
    /// Median over samples of nanoseconds per evaluation, on one thread.
    pub ns_per_eval: f64,
    /// Nanoseconds per evaluation of each sample, in the order taken.
    pub samples_ns: Vec<f64>,
    /// Evaluations in each sample (whole passes over the fixed pair set).
    pub evals_per_sample: usize,
}

/// How long a bake takes: the median of repeated bakes and the repetitions.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct BakeTiming {
    /// Median wall-clock seconds of one bake.
    pub seconds: f64,
    /// Seconds of each repetition, in the order taken.
    pub samples_seconds: Vec<f64>,
    /// Worker threads of the pool the bakes ran in.
    pub threads: usize,
}

/// Median of `values` (mean of the two middle values for an even count); NaN if empty, a
/// figure the report shows as missing.
pub fn median(values: &[f64]) -> f64 {
    crate::render::median(values).unwrap_or(f64::NAN)
}

/// An evaluation to time: F(wi, wo) by some estimator over every pair of a slice, summed
/// (so that nothing can be optimised away). A pass over the whole slice, rather than one
/// call per pair, lets an estimator use its batch entry point (the table lookups'
/// `Table::lookup_batch`).
pub type Eval<'a> = &'a dyn Fn(&[(DVec3, DVec3)]) -> DVec3;

/// An owned [`Eval`].
pub type BoxedEval<'a> = Box<dyn Fn(&[(DVec3, DVec3)]) -> DVec3 + 'a>;

/// An [`Eval`] calling `eval` pair by pair.
pub fn pair_by_pair(eval: impl Fn(DVec3, DVec3) -> DVec3) -> impl Fn(&[(DVec3, DVec3)]) -> DVec3 {
    move |pairs| {
        pairs
            .iter()
            .map(|&(wi, wo)| eval(black_box(wi), black_box(wo)))
            .sum()
    }
}

/// Times each of `evals` over `pairs` on the calling thread, interleaved: one untimed
/// warm-up pass of each, then `samples` rounds in which every evaluation takes one sample.
/// A sample is as many whole passes as it takes to last at least `min_sample` (estimated
/// from the warm-up), so that short evaluations are not timed below the clock's and the
/// scheduler's resolution. Interleaving spreads any change of machine load over all the
/// evaluations alike, so the ratios between them hold better than their absolute values.
pub fn time_interleaved(
    pairs: &[(DVec3, DVec3)],
    samples: usize,
    min_sample: Duration,
    evals: &[Eval],
) -> Vec<EvalTiming> {
    let pass = |eval: Eval| eval(black_box(pairs));
    let passes: Vec<usize> = evals
        .iter()
        .map(|&eval| {
            let started = Instant::now();
            black_box(pass(eval));
            let warm_up = started.elapsed().max(Duration::from_nanos(1));
            (min_sample.as_secs_f64() / warm_up.as_secs_f64())
                .ceil()
                .clamp(1.0, 1e6) as usize
        })
        .collect();
    let mut samples_ns = vec![Vec::with_capacity(samples.max(1)); evals.len()];
    for _ in 0..samples.max(1) {
        for (k, &eval) in evals.iter().enumerate() {
            let started = Instant::now();
            for _ in 0..passes[k] {
                black_box(pass(eval));
            }
            let evals_done = (passes[k] * pairs.len()).max(1);
            samples_ns[k].push(started.elapsed().as_nanos() as f64 / evals_done as f64);
        }
    }
    samples_ns
        .into_iter()
        .zip(passes)
        .map(|(samples_ns, passes)| EvalTiming {
            ns_per_eval: median(&samples_ns),
            samples_ns,
            evals_per_sample: passes * pairs.len(),
        })
        .collect()
}

/// Runs `job` `repetitions` times (at least once) in `pool`, timing each, but only once
/// when the first run takes longer than `repeat_below_seconds`; returns the first run's
/// value and the timings.
pub fn time_repeated<T: Send>(
    pool: &rayon::ThreadPool,
    repetitions: usize,
    repeat_below_seconds: f64,
    job: impl Fn() -> T + Sync + Send,
) -> (T, BakeTiming) {
    let mut first = None;
    let mut samples_seconds = Vec::with_capacity(repetitions.max(1));
    for _ in 0..repetitions.max(1) {
        let started = Instant::now();
        let value = pool.install(&job);
        let seconds = started.elapsed().as_secs_f64();
        samples_seconds.push(seconds);
        first.get_or_insert(value);
        if seconds > repeat_below_seconds {
            break;
        }
    }
    let seconds = median(&samples_seconds);
    (
        first.expect("at least one repetition"),
        BakeTiming {
            seconds,
            samples_seconds,
            threads: pool.current_num_threads(),
        },
    )
}

#[cfg(test)]
mod tests {
    use super::median;

    #[test]
    fn median_of_odd_and_even_counts() {
        assert_eq!(median(&[3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median(&[4.0, 1.0, 3.0, 2.0]), 2.5);
        assert!(median(&[]).is_nan());
    }
}
