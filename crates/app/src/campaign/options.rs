//! What a campaign call is asked for, how far it has come, and what it did.

use std::path::PathBuf;

/// What `rhonn campaign` was asked for.
#[derive(Debug, Clone)]
pub struct CampaignOptions {
    /// Runs (random draws).
    pub runs: u64,
    /// Seed.
    pub seed: u64,
    /// `[k, m]`.
    pub shard: [u64; 2],
    /// Full-factorial corners instead of random draws.
    pub corners: bool,
    /// Keep the traces of runs with index below this.
    pub envelope_runs: u64,
}

/// The most runs a campaign may have.
pub const MAX_RUNS: u64 = 10_000_000;

impl CampaignOptions {
    /// A whole campaign (shard 1/1): `runs` random draws from `seed` (or every corner).
    pub fn whole(runs: u64, seed: u64, corners: bool, envelope_runs: u64) -> Self {
        CampaignOptions {
            runs,
            seed,
            shard: [1, 1],
            corners,
            envelope_runs,
        }
    }

    /// The run indices `[first, end)` this call's shard runs of a campaign of `runs` runs
    /// (every run for shard 1/1); a shard that would hold no run is refused.
    pub fn shard_indices(&self, runs: u64) -> Result<[u64; 2], rhonn_report::Error> {
        if runs == 0 || runs > MAX_RUNS {
            return Err(rhonn_report::Error::Input(format!(
                "--runs {runs} is not allowed: give a number in [1, {MAX_RUNS}]"
            )));
        }
        let [k, m] = self.shard;
        if m > runs {
            return Err(rhonn_report::Error::Input(format!(
                "--shard {k}/{m} is not allowed: the campaign has {runs} runs, so give M at most {runs} (each shard runs at least one)"
            )));
        }
        Ok([runs * (k - 1) / m, runs * k / m])
    }
}

/// How far a campaign has come, given to the progress callback after each run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Progress<'a> {
    /// The scenario's name.
    pub scenario: &'a str,
    /// Runs finished in this call.
    pub done: usize,
    /// Runs this call has to do.
    pub total: usize,
    /// Runs of this call that failed.
    pub failed: usize,
    /// Since the call started \[s\].
    pub elapsed_s: f64,
}

/// What a campaign call did.
#[derive(Debug, Clone, PartialEq)]
pub struct CampaignOutcome {
    /// The scenario's name.
    pub scenario: String,
    /// The folder.
    pub dir: PathBuf,
    /// Runs in `runs.csv`.
    pub runs: usize,
    /// Of which failed.
    pub failed: usize,
    /// The folder held the finished campaign already: nothing was run.
    pub already_complete: bool,
    /// What the user should know (a resumed campaign, a row cut by an interruption).
    pub notes: Vec<String>,
}

/// The most worker threads a campaign may ask for.
pub const MAX_WORKER_THREADS: usize = 1024;

/// Run `f` on `threads` worker threads (None: every core, rayon's global pool), as
/// `rhonn campaign --threads` and Python's `rhonn.campaign(threads=...)` do; `Some(0)` is
/// refused with `zero`, the door's message naming its argument.
pub fn on_threads<T: Send, E: From<rhonn_report::Error> + Send>(
    threads: Option<usize>,
    zero: &str,
    f: impl FnOnce() -> Result<T, E> + Send,
) -> Result<T, E> {
    match threads {
        Some(0) => Err(rhonn_report::Error::Input(zero.to_string()).into()),
        // 100,000 threads took longer to start than the campaign to run (found by hand).
        Some(n) if n > MAX_WORKER_THREADS => Err(rhonn_report::Error::Input(format!(
            "threads = {n} is not allowed: give at most {MAX_WORKER_THREADS} worker threads (this machine has {} cores)",
            std::thread::available_parallelism().map_or(1, |c| c.get())
        ))
        .into()),
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .map_err(|e| rhonn_report::Error::Campaign(format!("cannot start {n} worker threads: {e}")))?
            .install(f),
        None => f(),
    }
}
