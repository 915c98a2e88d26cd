//! Every field every command writes is explained from the same source as the field: its
//! doc comment, walked into `docs/reference/fields.md` (`rhonn_report::fields`). This test
//! runs the commands (summary.json of each shipped scenario, of `rhonn fit`, `predict`,
//! `identify`, `benchmark`, `corpus`, `bench` and `campaign`) and checks that each key path
//! they write is a row of that reference; the figures a campaign names (runs.csv's columns,
//! made from the runs' figures) are named by the glossary's patterns
//! (docs/reference/glossary.md).

use crate::util;

// The same matching as the report's "what it is" column.
use rhonn_report::fields::key_paths;
use rhonn_report::glossary::matches;
use std::collections::BTreeSet;
use std::path::Path;
use util::{rhonn, stderr};

/// Whether a row of the reference names `path` (`rhonn_report::fields::names`) or holds
/// it: a row with no rows below it (an echoed setting, a map of settings) covers what is
/// inside it.
fn covered(rows: &[String], path: &str) -> bool {
    use rhonn_report::fields::names;
    if rows.iter().any(|r| names(r, path)) {
        return true;
    }
    // A prefix that is a leaf row.
    let mut p = path.to_string();
    while let Some(cut) = p.rfind(['.', '[']) {
        p.truncate(cut);
        let leaf = |r: &&String| names(r, &p) && !rows.iter().any(|x| x.starts_with(&format!("{r}.")));
        if rows.iter().any(|r| leaf(&r)) {
            return true;
        }
    }
    false
}

/// The names the glossary's first column gives in backticks (`*` and `...` stand for
/// any text).
fn glossary_names(glossary: &str) -> Vec<String> {
    let (_, rest) = glossary
        .split_once("# Glossary of the figures")
        .expect("docs/reference/glossary.md has a glossary");
    let table = rest.split("\n# ").next().unwrap();
    let mut names = Vec::new();
    for row in table.lines().filter(|l| l.starts_with("| ")) {
        let first = row[2..].split(" | ").next().unwrap();
        names.extend(first.split('`').skip(1).step_by(2).map(str::to_string));
    }
    names
}

#[test]
fn the_glossary_patterns_match_as_documented() {
    assert!(matches("iae_mpa_s", "iae_mpa_s"));
    assert!(!matches("iae_mpa_s", "iae"));
    assert!(matches("*_rms_*", "training_rms_error"));
    assert!(!matches("*_rms_*", "rms_error"));
    assert!(matches("..._settled_mpa", "max_abs_deviation_settled_mpa"));
    assert!(matches("baseline_*", "baseline_iae_mpa_s"));
}

#[test]
fn the_glossary_names_every_figure_the_outputs_write() {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let d = tempfile::tempdir().unwrap();
    let mut keys = BTreeSet::new();
    let mut paths = BTreeSet::new();
    let mut read_summary = |dir: &Path| {
        let text = std::fs::read_to_string(dir.join("summary.json")).unwrap();
        paths.extend(key_paths(&serde_json::from_str(&text).unwrap()));
    };
    let list = rhonn(d.path(), &["scenarios"]);
    let scenarios: Vec<String> = String::from_utf8_lossy(&list.stdout)
        .lines()
        .filter_map(|l| l.split_whitespace().next().map(str::to_string))
        .collect();
    assert!(scenarios.len() >= 8, "{scenarios:?}");
    for s in &scenarios {
        let o = rhonn(d.path(), &["run", s, "--out", &format!("runs/{s}")]);
        assert!(o.status.success(), "{s}: {}", stderr(&o));
        read_summary(&d.path().join("runs").join(s));
    }
    let tanks = root.join("data/cascaded-tanks/estimation.csv");
    let tanks = tanks.to_str().unwrap();
    let val = root.join("data/cascaded-tanks/validation.csv");
    // The default fit of the tanks: the one the tests share.
    let fit = util::tanks_default_fit();
    read_summary(fit);
    let model = fit.join("model.json");
    let calls: [Vec<&str>; 3] = [
        vec![
            "predict",
            "--model",
            model.to_str().unwrap(),
            "--data",
            val.to_str().unwrap(),
            "--out",
            "predict",
        ],
        vec![
            "identify",
            "--data",
            tanks,
            "--inputs",
            "u",
            "--outputs",
            "y",
            // The frozen model's validation figures and the ARX baseline's too.
            "--validate",
            val.to_str().unwrap(),
            "--steps-ahead",
            "5",
            "--out",
            "identify",
        ],
        // One short record of the unseen-systems corpus (seconds).
        vec![
            "corpus",
            "--seed",
            "5",
            "--systems",
            "13",
            "--only",
            "11",
            "--out",
            "corpus",
        ],
    ];
    // The benchmark run the tests share (`util::two_benchmarks`): the hair dryer and the
    // coupled drives.
    let (benchmark, _) = util::two_benchmarks();
    read_summary(benchmark);
    read_summary(&benchmark.join("daisy-hair-dryer"));
    read_summary(&benchmark.join("coupled-electric-drives"));
    let o = rhonn(
        d.path(),
        &["bench", "thesis-ch3", "--seconds", "0.05", "--out", "bench"],
    );
    assert!(o.status.success(), "bench: {}", stderr(&o));
    read_summary(&d.path().join("bench"));
    for args in calls {
        let o = rhonn(d.path(), &args);
        assert!(o.status.success(), "{args:?}: {}", stderr(&o));
        read_summary(&d.path().join(args[0]));
    }
    // The online selection on two outputs (each output's own bank).
    crate::identify::two_outputs_csv(&d.path().join("two.csv"), 3000, 3);
    crate::identify::two_outputs_csv(&d.path().join("two_val.csv"), 1500, 4);
    let o = rhonn(
        d.path(),
        &[
            "identify",
            "--data",
            "two.csv",
            "--validate",
            "two_val.csv",
            "--inputs",
            "u1,u2",
            "--outputs",
            "y1,y2",
            "--out",
            "two",
        ],
    );
    assert!(o.status.success(), "two outputs: {}", stderr(&o));
    read_summary(&d.path().join("two"));
    for (s, runs) in [("control-adaptive", "4"), ("tanks-control", "3")] {
        let out = format!("campaign-{s}");
        let o = rhonn(
            d.path(),
            &[
                "campaign",
                s,
                "--runs",
                runs,
                "--envelope-runs",
                "0",
                "--out",
                &out,
            ],
        );
        assert!(o.status.success(), "{s}: {}", stderr(&o));
        let summary: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(d.path().join(&out).join("summary.json")).unwrap())
                .unwrap();
        // The statistics name each figure (a column of runs.csv besides the drawn
        // parameters, which are the scenario's settings).
        let figures = summary["figures"].as_array().expect("campaign figures");
        assert!(figures.len() >= 6, "{s}: {figures:?}");
        for f in figures {
            keys.insert(f["figure"].as_str().unwrap().to_string());
        }
        paths.extend(key_paths(&summary));
    }
    // Every key path written is a row of the fields' reference (or lies inside a row that
    // has no rows of its own: an echoed setting, a map).
    let rows: Vec<String> = rhonn_report::fields::outputs()
        .iter()
        .flat_map(|o| rhonn_report::fields::rows(&o.schema))
        .map(|(p, _)| p)
        .collect();
    // (The rule itself: a field, a list's field, an echoed setting's inside; not a stranger.)
    assert!(covered(&rows, "selection.candidates[].score") && covered(&rows, "settings.plant.kind"));
    assert!(!covered(&rows, "selection.no_such_figure") && !covered(&rows, "no_such_key"));
    let unexplained: Vec<&String> = paths.iter().filter(|p| !covered(&rows, p)).collect();
    assert!(
        unexplained.is_empty(),
        "key paths the outputs write but no field's doc comment explains: {unexplained:?}"
    );
    // A campaign's figure is a run's field or a name the glossary's patterns give (a
    // plant's `h1_training_fit_percent`, `controller_iae_mpa_s`).
    let glossary = std::fs::read_to_string(root.join("docs/reference/glossary.md")).unwrap();
    let names = glossary_names(&glossary);
    let field_names: BTreeSet<&str> = rows
        .iter()
        .map(|r| r.rsplit('.').next().unwrap().trim_end_matches("[]"))
        .collect();
    let missing: Vec<&String> = keys
        .iter()
        .filter(|k| !field_names.contains(k.as_str()) && !names.iter().any(|n| matches(n, k)))
        .collect();
    assert!(
        missing.is_empty(),
        "campaign figures neither a field nor named by the glossary: {missing:?}"
    );
}
