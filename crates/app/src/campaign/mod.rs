//! The files of a Monte Carlo campaign (`rhonn campaign`, `rhonn merge`): one campaign
//! kind for every plant, the pump's included (`plant.rs`), run by one runner
//! (`runner.rs`); the rows' files and the finished folder's writers are `rhonn-report`'s
//! (`campaign_rows`, `campaign_file`, `worst_runs`, `plant_envelope`).
//!
//! `DIR/campaign.json` says what the campaign is (scenario, seed, runs, sampling, shard);
//! finished runs are appended to `DIR/runs.partial.csv` and flushed one by one, so an
//! interrupted campaign loses nothing and `rhonn campaign` with the same arguments
//! resumes it; at the end `DIR/runs.csv` holds every row sorted by run index (the same
//! bytes whatever the thread count or sharding) and `DIR/summary.json` the statistics.

mod options;
mod plant;
mod runner;

pub use options::{on_threads, CampaignOptions, CampaignOutcome, Progress, MAX_RUNS, MAX_WORKER_THREADS};
pub use plant::run_scenario_campaign;
use rhonn_report::Error;
use std::path::{Path, PathBuf};

type Result<T, E = Error> = std::result::Result<T, E>;

/// Parse a shard `K/M` (1 <= K <= M).
pub fn parse_shard(s: &str) -> Result<[u64; 2]> {
    let bad = || {
        Error::Campaign(format!(
            "--shard {s:?} is not allowed: give K/M with 1 <= K <= M, e.g. 2/4"
        ))
    };
    let (k, m) = s.split_once('/').ok_or_else(bad)?;
    let (k, m): (u64, u64) = (
        k.trim().parse().map_err(|_| bad())?,
        m.trim().parse().map_err(|_| bad())?,
    );
    if k == 0 || m == 0 || k > m {
        return Err(bad());
    }
    Ok([k, m])
}

/// Combine finished shard folders of one campaign into the folder `out` (`rhonn merge`).
pub fn merge_campaigns(dirs: &[PathBuf], out: &Path) -> Result<CampaignOutcome> {
    plant::merge_plant_campaigns(dirs, out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::atomic::{AtomicUsize, Ordering};

    #[test]
    fn a_campaign_is_a_library_call_that_reports_progress_and_resumes() {
        let d = tempfile::tempdir().unwrap();
        let mut sc = rhonn::experiment::preset::load_any("thesis-ch3").unwrap();
        sc.duration_s = 0.5;
        let o = CampaignOptions {
            runs: 6,
            seed: 2,
            shard: [1, 1],
            corners: false,
            envelope_runs: 0,
        };
        let run = run_scenario_campaign;
        let calls = AtomicUsize::new(0);
        let out = run(&sc, &o, d.path(), &|p| {
            calls.fetch_add(1, Ordering::Relaxed);
            assert!(p.done <= p.total && p.total == 6);
        })
        .unwrap();
        assert_eq!((out.runs, out.failed, out.already_complete), (6, 0, false));
        assert_eq!(calls.load(Ordering::Relaxed), 6);
        let rows = std::fs::read_to_string(d.path().join("runs.csv")).unwrap();
        assert_eq!(rows.lines().count(), 7);
        let again = run(&sc, &o, d.path(), &|_| panic!("nothing to run")).unwrap();
        assert!(again.already_complete);
        // Another campaign in the same folder is refused, naming the folder.
        let other = CampaignOptions { seed: 3, ..o };
        let e = run(&sc, &other, d.path(), &|_| {}).unwrap_err().to_string();
        assert!(
            e.contains("holds another campaign") && e.contains(&d.path().display().to_string()),
            "{e}"
        );
    }
}
