//! The same data, options and seed give the same model on any machine: `rhonn fit`'s
//! default selection is bounded by a work budget computed from the data, never by the
//! clock, so one thread, every core and every core busy give the same model.json.

use crate::util::{rhonn, stderr, tanks_default_fit};
use std::path::Path;
use std::process::Command;

fn fit(dir: &Path, out: &str, threads: Option<&str>) -> Vec<u8> {
    let data =
        Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join("data/cascaded-tanks/estimation.csv");
    let mut c = Command::new(env!("CARGO_BIN_EXE_rhonn"));
    c.args([
        "fit",
        "--data",
        data.to_str().unwrap(),
        "--inputs",
        "u",
        "--outputs",
        "y",
        "--out",
        out,
    ])
    .current_dir(dir);
    if let Some(t) = threads {
        c.env("RAYON_NUM_THREADS", t);
    }
    let o = c.output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    std::fs::read(dir.join(out).join("model.json")).unwrap()
}

#[test]
fn the_default_fit_is_the_same_on_one_thread_every_core_and_a_loaded_machine() {
    let d = tempfile::tempdir().unwrap();
    let one = fit(d.path(), "one", Some("1"));
    // Every core: the fit the tests share is this very command (the same data, columns and
    // defaults, no thread setting), run beside the other tests.
    let all = std::fs::read(tanks_default_fit().join("model.json")).unwrap();
    // Every core busy with a spinning thread while the fit runs.
    let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let spinners: Vec<_> = (0..std::thread::available_parallelism().map_or(2, |n| n.get()))
        .map(|_| {
            let stop = stop.clone();
            std::thread::spawn(move || {
                let mut x = 0u64;
                while !stop.load(std::sync::atomic::Ordering::Relaxed) {
                    x = std::hint::black_box(x.wrapping_mul(6364136223846793005).wrapping_add(1));
                }
            })
        })
        .collect();
    let loaded = fit(d.path(), "loaded", Some("3"));
    stop.store(true, std::sync::atomic::Ordering::Relaxed);
    for s in spinners {
        s.join().unwrap();
    }
    assert!(one == all, "model.json differs between 1 thread and every core");
    assert!(one == loaded, "model.json differs on a loaded machine");
    let summary = std::fs::read_to_string(d.path().join("one/summary.json")).unwrap();
    assert!(summary.contains("\"work_budget\""), "the budget is recorded");
    let o = rhonn(d.path(), &["report", "one"]);
    assert!(o.status.success(), "{}", stderr(&o));
}
