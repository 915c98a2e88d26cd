//! The unseen-systems corpus (`rhonn corpus`): a small fixed sample of it judged from the
//! command line, its files, and its verdict on rhonn fit's default against the ARX.

use crate::util::{rhonn, stderr};

#[test]
fn a_small_fixed_sample_of_the_corpus_is_judged_and_written() {
    let d = tempfile::tempdir().unwrap();
    // A short record and a dead zone of seed 5 (seconds each): the families' default must
    // hold its own against the ARX of lags by cross-validation on both.
    let o = rhonn(
        d.path(),
        &[
            "corpus",
            "--seed",
            "5",
            "--systems",
            "13",
            "--only",
            "11,3",
            "--out",
            "c",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        text.contains("s11-short-record") && text.contains("s03-dead-zone"),
        "{text}"
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.path().join("c/summary.json")).unwrap()).unwrap();
    assert_eq!(summary["seed"], 5);
    assert_eq!(summary["summary"]["scored"], 2, "{summary}");
    assert_eq!(summary["summary"]["failed"], 0, "{summary}");
    let csv = std::fs::read_to_string(d.path().join("c/corpus.csv")).unwrap();
    let mut rows = csv::Reader::from_reader(csv.as_bytes());
    let head = rows.headers().unwrap().clone();
    let col = |n: &str| head.iter().position(|h| h == n).unwrap();
    let mut n = 0;
    for r in rows.records() {
        let r = r.unwrap();
        let ratio: f64 = r[col("ratio")].parse().unwrap();
        let (fit, arx): (f64, f64) = (
            r[col("fit_rmse")].parse().unwrap(),
            r[col("arx_rmse")].parse().unwrap(),
        );
        assert!(
            (ratio - fit / arx).abs() < 1e-12 * ratio.max(1.0),
            "{ratio} {fit} {arx}"
        );
        assert!(
            ratio <= 1.01,
            "{}: rhonn {fit} against the ARX's {arx}",
            &r[col("system")]
        );
        n += 1;
    }
    assert_eq!(n, 2);
    assert!(d.path().join("c/report.html").is_file());
}

#[test]
fn a_system_index_beyond_the_corpus_is_refused_naming_the_flag() {
    let d = tempfile::tempdir().unwrap();
    let o = rhonn(d.path(), &["corpus", "--systems", "5", "--only", "7"]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("--only 7"), "{}", stderr(&o));
}
