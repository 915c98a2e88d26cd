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
        // rhonn identify's default beside them: its ratio to the ARX on its own samples,
        // finite, and its structure named.
        let online: f64 = r[col("online_ratio")].parse().unwrap();
        let online_rmse: f64 = r[col("online_rmse")].parse().unwrap();
        assert!(
            online.is_finite() && online > 0.0 && online_rmse.is_finite(),
            "{online}"
        );
        assert!(!r[col("online_structure")].is_empty() && !r[col("online_structure")].starts_with("failed"));
        // Beside the records, the models that were scored: `rhonn predict` of each on the
        // test record gives the row's figure (the corpus scores from the later of the model's
        // and the ARX's first prediction, predict from the model's: within 1 %).
        let sys = &r[col("system")];
        for (model, figure) in [("model.json", fit), ("online/model.json", online_rmse)] {
            let out = format!("p-{sys}-{}", model.replace('/', "-"));
            let o = rhonn(
                d.path(),
                &[
                    "predict",
                    "--model",
                    &format!("c/{sys}/{model}"),
                    "--data",
                    &format!("c/{sys}/test_0.csv"),
                    "--out",
                    &out,
                ],
            );
            assert!(o.status.success(), "{sys} {model}: {}", stderr(&o));
            let p: serde_json::Value = serde_json::from_str(
                &std::fs::read_to_string(d.path().join(&out).join("summary.json")).unwrap(),
            )
            .unwrap();
            // An offline model's summary holds `outputs`, an online model's `figures`.
            let figures = if model == "model.json" {
                &p["outputs"]
            } else {
                &p["figures"]
            };
            let rms = figures[0]["rms_error"].as_f64().unwrap();
            assert!(
                (rms - figure).abs() <= 0.01 * figure,
                "{sys} {model}: {rms} against the row's {figure}"
            );
        }
        // And why each was chosen: every candidate of both selections.
        let why: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(d.path().join(format!("c/{sys}/summary.json"))).unwrap(),
        )
        .unwrap();
        assert_eq!(why["system"]["system"], sys);
        assert!(
            why["selection"]["candidates"].as_array().unwrap().len() > 5,
            "{why}"
        );
        assert!(
            why["online_selection"]["candidates"].as_array().unwrap().len() > 5,
            "{why}"
        );
        n += 1;
    }
    assert_eq!(n, 2);
    let s = &summary["summary"];
    assert!(s["online_median_ratio"].as_f64().unwrap().is_finite(), "{s}");
    assert!(s["online_at_most_arx"].as_u64().unwrap() <= 2, "{s}");
    assert!(
        text.contains("online (rhonn identify's default): median ratio"),
        "{text}"
    );
    assert!(d.path().join("c/report.html").is_file());
}

#[test]
fn a_system_index_beyond_the_corpus_is_refused_naming_the_flag() {
    let d = tempfile::tempdir().unwrap();
    let o = rhonn(d.path(), &["corpus", "--systems", "5", "--only", "7"]);
    assert!(!o.status.success());
    assert!(stderr(&o).contains("--only 7"), "{}", stderr(&o));
}

#[test]
fn an_output_the_arx_predicts_better_on_every_fold_gets_it_and_the_model_runs_as_one() {
    // The corpus's system of two outputs (seed 2, system 36: a fast linear speed and a slow
    // heated temperature): one structure for both lost to the ARX on the first output
    // (1.03 x); the best ARX beats it there on every fold, so it predicts that output.
    let d = tempfile::tempdir().unwrap();
    let run = |args: &[&str]| {
        let o = rhonn(d.path(), args);
        assert!(o.status.success(), "{args:?}: {}", stderr(&o));
        o
    };
    let o = run(&[
        "corpus",
        "--seed",
        "2",
        "--systems",
        "37",
        "--only",
        "36",
        "--out",
        "c",
    ]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(text.contains("y1: arx") && text.contains("; y2: "), "{text}");
    let sys = "c/s36-two-outputs";
    let fit = run(&[
        "fit",
        "--data",
        &format!("{sys}/train_0.csv"),
        "--inputs",
        "u1,u2",
        "--outputs",
        "y1,y2",
        "--out",
        "f",
    ]);
    let said = format!("{}{}", String::from_utf8_lossy(&fit.stdout), stderr(&fit));
    assert!(
        said.contains("output `y1`: the best ARX is below") && said.contains("`y1` is predicted by that ARX"),
        "{said}"
    );
    assert!(
        said.contains("output `y1` from a structure of its own: an ARX"),
        "{said}"
    );
    let json = |p: &str| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(d.path().join(p)).unwrap()).unwrap()
    };
    let model = json("f/model.json");
    assert_eq!(model["by_output"][0]["output"], "y1", "{model}");
    assert_eq!(model["by_output"][0]["model"]["spec"]["kind"], "arx", "{model}");
    assert_eq!(model["by_output"].as_array().unwrap().len(), 1);
    let summary = json("f/summary.json");
    assert_eq!(summary["selection"]["by_output"].as_array().unwrap().len(), 2);
    assert_eq!(summary["by_output"][0]["output"], "y1");
    // predict runs it as one model: each output no worse than the ARX baseline kept beside it.
    run(&[
        "predict",
        "--model",
        "f/model.json",
        "--data",
        &format!("{sys}/test_0.csv"),
        "--out",
        "p",
    ]);
    let p = json("p/summary.json");
    for j in 0..2 {
        let (m, a) = (
            p["outputs"][j]["rms_error"].as_f64().unwrap(),
            p["baseline_arx"][j]["rms_error"].as_f64().unwrap(),
        );
        assert!(m <= 1.01 * a, "output {j}: {m} against the ARX's {a}: {p}");
    }
    // And the report renders both folders.
    run(&["report", "f"]);
    run(&["report", "p"]);
}

#[test]
fn closed_loop_integrators_get_no_one_step_structure_and_no_ensemble_as_their_reference() {
    // Corpus seed 8: on s00 a lagged RHONN of 8 lags fitted one step ahead (its position
    // decorrelates after 462 samples) beat the ARX on every fold and, with the ARX, ran free
    // 3.17 x worse than the ARX on the test record; on s39 a mean led by an ARX was taken for
    // the reference ARX (1.62 x). Both now hold their own against the ARX.
    let d = tempfile::tempdir().unwrap();
    let o = rhonn(
        d.path(),
        &["corpus", "--seed", "8", "--only", "0,39", "--out", "c", "--json"],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.path().join("c/summary.json")).unwrap()).unwrap();
    for s in summary["systems"].as_array().unwrap() {
        let ratio = s["outputs"][0]["ratio"].as_f64().unwrap();
        assert!(
            ratio <= 1.01,
            "{}: {ratio} x the ARX ({})",
            s["system"],
            s["fit_structure"]
        );
    }
    // The default fit the corpus scored (`c/<system>/model.json`) and its selection's
    // findings, as `rhonn fit` prints them (`c/<system>/summary.json`).
    let why = std::fs::read_to_string(d.path().join("c/s00-closed-loop-integrator/summary.json")).unwrap();
    let why: serde_json::Value = serde_json::from_str(&why).unwrap();
    let said = why["selection"]["findings"].to_string();
    assert!(
        said.contains("rhonn na 8 nb 8 scored")
            && said.contains("fitted one step ahead")
            && said.contains("462 samples"),
        "{said}"
    );
    // Its test record's pulses drive the force far beyond the training's: predict says so.
    let predict = |record: &str, out: &str| {
        let data = format!("c/s00-closed-loop-integrator/{record}");
        let p = rhonn(
            d.path(),
            &[
                "predict",
                "--model",
                "c/s00-closed-loop-integrator/model.json",
                "--data",
                &data,
                "--out",
                out,
            ],
        );
        assert!(p.status.success(), "{}", stderr(&p));
        stderr(&p)
    };
    let warned = predict("test_0.csv", "p");
    assert!(
        warned.contains("warning: input `force` of c/s00-closed-loop-integrator/test_0.csv spans [")
            && warned.contains("the model extrapolates there"),
        "{warned}"
    );
    let summary: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.path().join("p/summary.json")).unwrap()).unwrap();
    assert_eq!(
        summary["inputs_beyond_training"][0]["input"], "force",
        "{summary}"
    );
    // Its own training record is within the range: nothing said.
    let quiet = predict("train_0.csv", "q");
    assert!(!quiet.contains("extrapolates"), "{quiet}");
}
