//! The mutation harness (crates/mutate) in its default, short run: seeded hostile variants
//! of every file a user gives the command (recordings, specs, a model.json of every kind,
//! every shipped scenario), each run with a timeout. No panic, no hang, no NaN written with
//! exit 0, nothing left behind; at least 95 % of refusals name the file and the field,
//! column or line. Cases also run with their input inside `--out`, their recording grown to
//! 100,000 rows, as two writers into one folder at once, and killed part-way then run again
//! (`rhonn_mutate::flavor`). A longer run: `cargo run --release -p rhonn-mutate -- --cases 20000`.

use std::time::Duration;

#[test]
fn hostile_files_get_clear_errors_and_never_a_panic_a_hang_or_a_nan() {
    let work = tempfile::tempdir().unwrap();
    let cfg = rhonn_mutate::Config {
        bin: env!("CARGO_BIN_EXE_rhonn").into(),
        work: work.path().to_path_buf(),
        cases: 600,
        seed: 1,
        // Generous: a case takes well under a second; only a hang reaches this.
        timeout: Duration::from_secs(120),
        jobs: 2,
        sweep: false,
    };
    let report = rhonn_mutate::run(&cfg).unwrap();
    let table = report.table();
    println!("{table}");
    assert!(report.failures.is_empty(), "{table}");
    let t = report.totals();
    assert_eq!(t.cases, 600);
    // The harness reaches every surface and both outcomes.
    assert!(report.surfaces.len() >= 20, "{table}");
    assert!(t.accepted > 50 && t.refused > 300, "{table}");
    assert!(report.named_share() >= 0.95, "{table}");
    // And every way of running a case: an input inside `--out`, a recording grown long,
    // two writers into one folder at once, a run killed part-way and run again.
    for f in [
        "input inside --out",
        "recording grown long",
        "two writers at once",
        "killed, then run again",
    ] {
        assert!(report.flavors.get(f).is_some_and(|n| *n >= 5), "{f}: {table}");
    }
}
