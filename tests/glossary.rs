//! "The README's glossary defines every figure name the outputs print" (now
//! docs/reference/glossary.md): every figure a
//! command writes (summary.json of each shipped scenario, of `rhonn fit` and `rhonn
//! identify`, the columns and statistics of campaigns) is named in the README's
//! "Glossary of the figures". Settings echoed back (scenario, solver, model,
//! parameters) are documented with the scenarios, not here.

use crate::util;

// The same matching as the report's "what it is" column.
use rhonn_report::glossary::matches;
use std::collections::BTreeSet;
use std::path::Path;
use util::{rhonn, stderr};

/// Subtrees of a summary.json that echo settings or hold data, not figures (`members`: an
/// ensemble's structures, each a `model`; the fit's own figures of them are named at the
/// summary's top level too).
const NOT_FIGURES: [&str; 13] = [
    "plan",
    "spec",
    "scenario",
    "solver",
    "model",
    "members",
    "parameters",
    "campaign",
    "rhonn_version",
    "final_weights",
    "terms",
    "records",
    "regulated",
];

/// The names of a JSON tree's figures: keys whose value is a number, null, a boolean or
/// a list of them (or of lists of them); objects are walked (lists of objects too).
fn figure_keys(v: &serde_json::Value, out: &mut BTreeSet<String>) {
    use serde_json::Value;
    let Value::Object(map) = v else {
        if let Value::Array(items) = v {
            items.iter().for_each(|i| figure_keys(i, out));
        }
        return;
    };
    for (k, v) in map {
        if NOT_FIGURES.contains(&k.as_str()) {
            continue;
        }
        let scalar = |x: &Value| x.is_number() || x.is_null() || x.is_boolean();
        match v {
            Value::Object(_) => figure_keys(v, out),
            Value::Array(a) if a.iter().any(Value::is_object) => figure_keys(v, out),
            // Numbers, or lists of numbers (one per neuron, pass or step).
            Value::Array(a)
                if !a.is_empty()
                    && a.iter()
                        .all(|x| scalar(x) || x.as_array().is_some_and(|i| i.iter().all(scalar))) =>
            {
                out.insert(k.clone());
            }
            x if scalar(x) => {
                out.insert(k.clone());
            }
            _ => {}
        }
    }
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
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let d = tempfile::tempdir().unwrap();
    let mut keys = BTreeSet::new();
    let mut read_summary = |dir: &Path| {
        let text = std::fs::read_to_string(dir.join("summary.json")).unwrap();
        figure_keys(&serde_json::from_str(&text).unwrap(), &mut keys);
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
        figure_keys(&summary, &mut keys);
    }
    let glossary = std::fs::read_to_string(root.join("docs/reference/glossary.md")).unwrap();
    let names = glossary_names(&glossary);
    let missing: Vec<&String> = keys
        .iter()
        .filter(|k| !names.iter().any(|n| matches(n, k)))
        .collect();
    assert!(
        missing.is_empty(),
        "figures the outputs write but the glossary does not name: {missing:?}"
    );
}
