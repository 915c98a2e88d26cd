//! The selection's work queue: every (candidate, fold) pair is one job, taken in order
//! (candidate by candidate, cheapest first) by one worker per thread of the rayon pool.
//!
//! Running a candidate's folds in parallel and the candidates one after another left a
//! thread idle for a third of every candidate on a 2-core machine (3 folds on 2 threads);
//! a flat queue keeps every thread busy, and taking the jobs in order keeps the time
//! budget's meaning: when it is spent, no candidate whose first fold has not started yet
//! starts (the folds of one already started still run). rayon's own `par_iter` splits its
//! range in halves, so it would start the slowest candidate, the last, first: hence this
//! small queue (a counter under a lock, the jobs taken in order) rather than a `par_iter`
//! over the pairs.

use std::sync::Mutex;
use std::time::Instant;

/// What became of one candidate.
pub(super) enum Outcome<R> {
    /// Its results, fold by fold.
    Ran(Vec<R>),
    /// `may_start` refused it when its first fold came up.
    Skipped,
}

struct State<R> {
    started: Vec<Option<Instant>>,
    skipped: Vec<bool>,
    results: Vec<Vec<Option<R>>>,
    done: Vec<usize>,
    next: usize,
}

/// Run `job(c, f)` for every candidate `c` in `0..candidates` and fold `f` in `0..folds`.
/// When candidate c's first job comes up, `may_start(c)` decides whether it runs at all
/// (and `on_start(c)` hears that it does); when its last fold ends, `on_done(c, results,
/// seconds)` hears its results in fold order and the wall time from its first fold's start
/// to its last fold's end.
pub(super) fn run<R: Send>(
    candidates: usize,
    folds: usize,
    may_start: &(dyn Fn(usize) -> bool + Sync),
    on_start: &(dyn Fn(usize) + Sync),
    job: &(dyn Fn(usize, usize) -> R + Sync),
    on_done: &(dyn Fn(usize, &[R], f64) + Sync),
) -> Vec<Outcome<R>> {
    let state = Mutex::new(State {
        started: vec![None; candidates],
        skipped: vec![false; candidates],
        results: (0..candidates)
            .map(|_| (0..folds).map(|_| None).collect())
            .collect(),
        done: vec![0; candidates],
        next: 0,
    });
    let jobs = candidates * folds;
    let worker = || loop {
        let (c, f) = {
            let mut st = state.lock().unwrap_or_else(|e| e.into_inner());
            let j = st.next;
            // A stop asked for (`crate::cancel`): no job more; the caller says so.
            if j >= jobs || crate::cancel::requested() {
                break;
            }
            st.next += 1;
            let (c, f) = (j / folds, j % folds);
            if st.skipped[c] {
                continue;
            }
            if st.started[c].is_none() {
                if !may_start(c) {
                    st.skipped[c] = true;
                    continue;
                }
                st.started[c] = Some(Instant::now());
                on_start(c);
            }
            (c, f)
        };
        let r = job(c, f);
        let mut st = state.lock().unwrap_or_else(|e| e.into_inner());
        st.results[c][f] = Some(r);
        st.done[c] += 1;
        if st.done[c] == folds {
            let seconds = st.started[c].map_or(0.0, |t| t.elapsed().as_secs_f64());
            let rs: Vec<R> = st.results[c].iter_mut().filter_map(Option::take).collect();
            on_done(c, &rs, seconds);
            st.results[c] = rs.into_iter().map(Some).collect();
        }
    };
    rayon::scope(|s| {
        for _ in 0..rayon::current_num_threads().max(1) {
            s.spawn(|_| worker());
        }
    });
    let st = state.into_inner().unwrap_or_else(|e| e.into_inner());
    st.results
        .into_iter()
        .zip(st.started)
        .map(|(rs, started)| match started {
            None => Outcome::Skipped,
            Some(_) => Outcome::Ran(rs.into_iter().flatten().collect()),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_job_runs_once_in_fold_order_and_a_refused_candidate_runs_none() {
        let calls = Mutex::new(Vec::new());
        let starts = Mutex::new(Vec::new());
        let out = run(
            5,
            3,
            &|c| c != 3,
            &|c| starts.lock().unwrap().push(c),
            &|c, f| {
                calls.lock().unwrap().push((c, f));
                10 * c + f
            },
            &|c, rs, _| assert_eq!(rs, [10 * c, 10 * c + 1, 10 * c + 2]),
        );
        let mut calls = calls.into_inner().unwrap();
        calls.sort();
        let want: Vec<(usize, usize)> = (0..5)
            .filter(|&c| c != 3)
            .flat_map(|c| (0..3).map(move |f| (c, f)))
            .collect();
        assert_eq!(calls, want);
        let mut starts = starts.into_inner().unwrap();
        starts.sort();
        assert_eq!(starts, [0, 1, 2, 4]);
        for (c, o) in out.iter().enumerate() {
            match o {
                Outcome::Ran(rs) => assert_eq!(rs, &[10 * c, 10 * c + 1, 10 * c + 2]),
                Outcome::Skipped => assert_eq!(c, 3),
            }
        }
    }

    #[test]
    fn candidates_start_in_order() {
        // With any number of threads, candidate c's first fold is taken before c + 1's.
        let order = Mutex::new(Vec::new());
        run(
            8,
            2,
            &|_| true,
            &|c| order.lock().unwrap().push(c),
            &|_, _| (),
            &|_, _, _| (),
        );
        assert_eq!(order.into_inner().unwrap(), (0..8).collect::<Vec<_>>());
    }
}
