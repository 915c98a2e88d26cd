//! Timing whole runs without I/O: the median wall time of one run on one core, and the
//! throughput of runs on every core (rayon). Used by `rhonn bench`; the criterion
//! benches in `benches/` are the finer instrument.

use super::plant_run::run_plant_summary;
use super::scenario::ScenarioSpec;
use crate::error::Result;
use rayon::prelude::*;
use serde::Serialize;
use std::time::{Duration, Instant};

/// What `rhonn bench` reports for one scenario.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct BenchFigures {
    /// Scenario name.
    pub scenario: String,
    /// Median wall time of one run without I/O \[s\].
    pub median_s: f64,
    /// Right-hand-side evaluations of one run.
    pub rhs_evaluations: Option<u64>,
    /// Runs per second with one run per core at a time, on every core.
    pub runs_per_s_all_cores: f64,
    /// Threads used for the throughput.
    pub threads: usize,
    /// Runs timed one by one.
    pub samples: usize,
}

/// Time a scenario's run for about `budget` on one core, then as long on every core: the
/// run of [`ScenarioSpec::run_summary`], without recording its samples.
pub fn bench_plant(spec: &ScenarioSpec, budget: Duration) -> Result<BenchFigures> {
    let rhs = Some(run_plant_summary(spec, None)?.solver.rhs_evaluations);
    timed(&spec.name, rhs, budget, || {
        run_plant_summary(spec, None).map(|_| ())
    })
}

fn timed(
    name: &str,
    rhs: Option<u64>,
    budget: Duration,
    one: impl Fn() -> Result<()> + Sync,
) -> Result<BenchFigures> {
    let mut times = Vec::new();
    let start = Instant::now();
    while times.len() < 5 || start.elapsed() < budget {
        let t0 = Instant::now();
        one()?;
        times.push(t0.elapsed().as_secs_f64());
        if times.len() >= 100_000 {
            break;
        }
    }
    times.sort_by(f64::total_cmp);
    let median_s = times[times.len() / 2];
    let threads = rayon::current_num_threads();
    // Enough runs to keep every core busy for about the budget.
    let n = ((budget.as_secs_f64() / median_s.max(1e-9)) as usize * threads).clamp(threads, 1_000_000);
    let t0 = Instant::now();
    (0..n).into_par_iter().try_for_each(|_| one())?;
    let runs_per_s_all_cores = n as f64 / t0.elapsed().as_secs_f64();
    Ok(BenchFigures {
        scenario: name.to_string(),
        median_s,
        rhs_evaluations: rhs,
        runs_per_s_all_cores,
        threads,
        samples: times.len(),
    })
}

/// The median wall time \[s\] of `repeats` runs of `sc` (at least one), each made as
/// `ScenarioSpec::run` makes it: Python's bench (`python/bench.py`) compares it with the
/// same run called from Python.
pub fn median_run_seconds(sc: &ScenarioSpec, repeats: usize) -> Result<f64> {
    let mut times = (0..repeats.max(1))
        .map(|_| {
            let start = Instant::now();
            sc.run().map(|r| {
                std::hint::black_box(r);
                start.elapsed().as_secs_f64()
            })
        })
        .collect::<Result<Vec<f64>>>()?;
    times.sort_by(f64::total_cmp);
    Ok(times[times.len() / 2])
}
