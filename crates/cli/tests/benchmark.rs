//! `rhonn benchmark`: the shipped benchmarks under their protocol. On two small ones (the
//! DaISy hair dryer and the coupled electric drives, two test records): the table, the
//! files, every figure a number, the models trained on train that `rhonn predict` runs to
//! the very figures of the table, the published figures beside them; and clear errors. On
//! parts of Silverbox and Wiener-Hammerstein: the polynomial RHONN and the block structure
//! run free below the published GRU figures.

use crate::util;

use std::path::{Path, PathBuf};
use util::{files_in, rhonn, stderr};

fn repo() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

fn json(p: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(p).unwrap()).unwrap()
}

/// RMS error of column `hat` against `y` in a CSV, from row `from` on.
fn rms_in_csv(p: &Path, y: &str, hat: &str, from: usize) -> f64 {
    let mut rd = csv::Reader::from_path(p).unwrap();
    let h = rd.headers().unwrap().clone();
    let (iy, ih) = (
        h.iter().position(|c| c == y).unwrap(),
        h.iter().position(|c| c == hat).unwrap(),
    );
    let e: Vec<f64> = rd
        .records()
        .skip(from)
        .map(|r| {
            let r = r.unwrap();
            r[iy].parse::<f64>().unwrap() - r[ih].parse::<f64>().unwrap()
        })
        .collect();
    (e.iter().map(|v| v * v).sum::<f64>() / e.len() as f64).sqrt()
}

/// `rhonn predict` in `dir` of the model.json of the benchmark folder `ced` on its file
/// `csv`, seeing the drives' window of 4 outputs, into `dir/p`: its summary.json.
fn predict_in_window(dir: &Path, ced: &Path, csv: &str) -> serde_json::Value {
    let p = rhonn(
        dir,
        &[
            "predict",
            "--model",
            ced.join("model.json").to_str().unwrap(),
            "--data",
            ced.join(csv).to_str().unwrap(),
            "--out",
            "p",
            "--init-window",
            "4",
        ],
    );
    assert!(p.status.success(), "{}", stderr(&p));
    json(&dir.join("p/summary.json"))
}

#[test]
fn two_benchmarks_give_the_table_the_files_and_models_that_predict_their_figures() {
    let d = tempfile::tempdir().unwrap();
    // `rhonn benchmark daisy-hair-dryer coupled-electric-drives`, run once for the tests
    // that read it (`util::two_benchmarks`).
    let (b, out) = util::two_benchmarks();
    assert!(out.contains("coupled-electric-drives | test 2 | y |"), "{out}");
    // The best on the protocol's split, the neural baseline beside it, and a figure of
    // another split marked as such (below the best, so shown).
    assert!(
        out.contains(
            "0.089 (GP-NARX, Champneys et al., IFAC-PapersOnLine 58(15), 2024); \
             neural baseline 0.095 (FIR-MLP, Champneys et al., IFAC-PapersOnLine 58(15), 2024); \
             on another split 0.074 (CT-SUBNET, Beintema et al., ICLR, 2023; trained and tested \
             on another split of the records)"
        ),
        "{out}"
    );
    // Test 1's figure of another split (0.115) is above the best on the protocol's: not
    // shown; its best is the neural baseline itself, not shown twice.
    let test1 = out
        .lines()
        .find(|l| l.starts_with("coupled-electric-drives | test 1"))
        .unwrap();
    assert!(
        test1.contains("| 0.096 (RNN, Champneys et al., IFAC-PapersOnLine 58(15), 2024) |"),
        "{test1}"
    );
    assert!(
        !test1.contains("another split") && !test1.contains("neural baseline"),
        "{test1}"
    );
    assert_eq!(
        files_in(b),
        [
            "benchmark.csv",
            "coupled-electric-drives",
            "daisy-hair-dryer",
            "report.html",
            "rhonn-manifest.json",
            "summary.json"
        ]
    );
    assert_eq!(
        files_in(&b.join("coupled-electric-drives")),
        [
            "free_run_0.csv",
            "free_run_0.svg",
            "free_run_1.csv",
            "free_run_1.svg",
            "model.json",
            "online",
            "report.html",
            "residuals_0.svg",
            "residuals_1.svg",
            "summary.json"
        ]
    );
    let s = json(&b.join("summary.json"));
    let rows = s["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 3, "{s}");
    for r in rows {
        for k in ["fit_rmse", "online_rmse", "arx_rmse", "fit_time_s"] {
            let v = r[k].as_f64().unwrap_or(f64::NAN);
            assert!(v.is_finite() && v > 0.0, "{k}: {r}");
        }
        // The coupled drives' protocol: every model sees the first 4 outputs only and is
        // scored from sample 4, whatever its lags (the selection's ARX has 8, the cascade
        // settles on 5).
        if r["benchmark"] == "coupled-electric-drives" {
            assert_eq!(r["scored_from"].as_u64(), Some(4), "{r}");
        }
    }
    // The table's figure of rhonn fit's model is what `rhonn predict` gives with the
    // model.json it wrote, on the test record it wrote (free_run_1.csv: test 2), seeing
    // the same 4 outputs.
    let ced = b.join("coupled-electric-drives");
    let summary = predict_in_window(d.path(), &ced, "free_run_1.csv");
    assert_eq!(summary["init_window"], 4);
    let row = &rows[2];
    assert_eq!(row["test"], "test 2");
    let from = row["scored_from"].as_u64().unwrap() as usize;
    let predicted = rms_in_csv(&d.path().join("p/prediction.csv"), "y", "y_hat", from);
    let table = row["fit_rmse"].as_f64().unwrap();
    assert!((predicted - table).abs() <= 1e-9 * table, "{predicted} {table}");
    // The same figure from the free-run file's own column.
    let in_file = rms_in_csv(&ced.join("free_run_1.csv"), "y", "y_fit", from);
    assert!((in_file - table).abs() <= 1e-9 * table);
    // The drives' selection chose an ensemble: model.json holds its members, the test
    // figures above are the mean's, and both are below the cascade's alone (0.186 / 0.195,
    // the figures before ensembles).
    let m = json(&ced.join("model.json"));
    assert!(!m["members"].as_array().unwrap().is_empty(), "{m}");
    assert!(
        rows[1]["fit_structure"]
            .as_str()
            .unwrap()
            .starts_with("mean of the best"),
        "{}",
        rows[1]
    );
    let fit: Vec<f64> = rows[1..]
        .iter()
        .map(|r| r["fit_rmse"].as_f64().unwrap())
        .collect();
    assert!(fit[0] < 0.186 && fit[1] < 0.195, "{fit:?}");
    // The online model is a frozen online model `rhonn predict` reads too.
    let m = json(&ced.join("online/model.json"));
    assert_eq!(m["kind"], "online-rhonn");
}

/// `--model`: the spec trained in place of the default selection's choice, named in the
/// table and in summary.json; the coupled drives' FROLS spec runs free below the cascade's
/// figures alone (0.186 / 0.195) on both test records, and `rhonn predict` with the
/// model.json it wrote gives the table's figure. A spec that cannot be read is refused
/// before anything runs, naming the file, and nothing is written.
#[test]
fn a_given_model_takes_the_fit_column_and_the_drives_frols_spec_beats_the_cascade_alone() {
    let d = tempfile::tempdir().unwrap();
    let data = repo().join("data/benchmarks");
    let spec = repo().join("models/coupled-drives-frols.toml");
    let args = |spec: &str| {
        [
            "benchmark",
            "coupled-electric-drives",
            "--model",
            spec,
            "--data-dir",
            data.to_str().unwrap(),
            "--out",
            "b",
        ]
        .map(String::from)
    };
    let o = rhonn(
        d.path(),
        &args(spec.to_str().unwrap()).each_ref().map(String::as_str),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    assert!(out.contains("| rhonn fit (--model) |"), "{out}");
    let s = json(&d.path().join("b/summary.json"));
    let rows = s["rows"].as_array().unwrap();
    let fit: Vec<f64> = rows.iter().map(|r| r["fit_rmse"].as_f64().unwrap()).collect();
    assert!(fit[0] < 0.186 && fit[1] < 0.195, "{fit:?}");
    for r in rows {
        assert_eq!(r["fit_method"], "rhonn fit (--model)", "{r}");
        assert_eq!(r["fit_structure"], "coupled-drives-frols.toml", "{r}");
    }
    let ced = d.path().join("b/coupled-electric-drives");
    let m = json(&ced.join("model.json"));
    assert_eq!(m["model"]["spec"]["term_selection"], "error-reduction");
    assert_eq!(m["model"]["terms"].as_array().unwrap().len(), 2);
    predict_in_window(d.path(), &ced, "free_run_0.csv");
    let predicted = rms_in_csv(&d.path().join("p/prediction.csv"), "y", "y_hat", 4);
    assert!(
        (predicted - fit[0]).abs() <= 1e-9 * fit[0],
        "{predicted} {}",
        fit[0]
    );
    // A spec with an unknown key: refused, the file named, nothing written.
    std::fs::write(d.path().join("bad.toml"), "kind = \"rhonn\"\nmax_term = 2\n").unwrap();
    std::fs::remove_dir_all(d.path().join("b")).unwrap();
    let o = rhonn(d.path(), &args("bad.toml").each_ref().map(String::as_str));
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(e.contains("bad.toml") && e.contains("max_term"), "{e}");
    assert!(!d.path().join("b").exists());
}

/// The ball and beam (an unstable plant): the online selection's final check rules out
/// the candidates that, frozen as they ended on train, drift or diverge in a long free run
/// (the high-order recursive ARX won the short windows and ran free on test at 2.3 x the
/// output's deviation). The frozen winner then runs free on test below the ARX of lags by
/// cross-validation, below the test's own mean and within 1.5 x rhonn fit's default.
#[test]
fn ball_and_beam_online_model_runs_free_below_the_arx_and_the_mean() {
    let d = tempfile::tempdir().unwrap();
    let data = repo().join("data/benchmarks");
    let o = rhonn(
        d.path(),
        &[
            "benchmark",
            "daisy-ball-and-beam",
            "--data-dir",
            data.to_str().unwrap(),
            "--out",
            "b",
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let s = json(&d.path().join("b/summary.json"));
    let r = &s["rows"][0];
    let (online, arx, fit) = (
        r["online_rmse"].as_f64().unwrap(),
        r["arx_rmse"].as_f64().unwrap(),
        r["fit_rmse"].as_f64().unwrap(),
    );
    let test = d.path().join("b/daisy-ball-and-beam/free_run_0.csv");
    let mut rd = csv::Reader::from_path(&test).unwrap();
    let iy = rd
        .headers()
        .unwrap()
        .iter()
        .position(|c| c == "y_ball_position")
        .unwrap();
    let ys: Vec<f64> = rd
        .records()
        .map(|x| x.unwrap()[iy].parse::<f64>().unwrap())
        .collect();
    let mean = ys.iter().sum::<f64>() / ys.len() as f64;
    let sd = (ys.iter().map(|y| (y - mean) * (y - mean)).sum::<f64>() / ys.len() as f64).sqrt();
    assert!(online < arx, "online {online} ARX {arx}");
    assert!(online < sd, "online {online} test mean {sd}");
    assert!(online <= 1.5 * fit, "online {online} fit {fit}");
    let b = json(&d.path().join("b/daisy-ball-and-beam/summary.json"));
    let sel = &b["online_selection"];
    let cands = sel["candidates"].as_array().unwrap();
    let chosen = &cands[sel["chosen"].as_u64().unwrap() as usize];
    assert!(chosen.get("ruled_out").is_none(), "{chosen}");
    assert!(chosen["final_free_run_nrmse"].as_f64().unwrap() < 1.0, "{chosen}");
    let out: Vec<&serde_json::Value> = cands.iter().filter(|c| c.get("ruled_out").is_some()).collect();
    assert!(!out.is_empty(), "{sel}");
    for c in out {
        let f = c["final_free_run_nrmse"].as_f64().unwrap_or(f64::INFINITY);
        assert!(f >= 1.0, "{c}");
    }
    assert_eq!(sel["checked"], 375, "{sel}");
}

#[test]
fn an_unknown_benchmark_or_a_bad_file_is_a_clear_error_and_writes_nothing() {
    let d = tempfile::tempdir().unwrap();
    let data = repo().join("data/benchmarks");
    let o = rhonn(
        d.path(),
        &[
            "benchmark",
            "silverbux",
            "--data-dir",
            data.to_str().unwrap(),
            "--out",
            "b",
        ],
    );
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(
        e.contains("no benchmark `silverbux`") && e.contains("silverbox"),
        "{e}"
    );
    assert!(!d.path().join("b").exists());
    // Run from another folder without --data-dir: the default folder is not there, and
    // the error says so and how to give it (it once listed the benchmarks of a missing
    // folder: none).
    let o = rhonn(d.path(), &["benchmark", "silverbox", "--out", "b"]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(
        e.contains("cannot read the benchmarks' folder data/benchmarks") && e.contains("--data-dir"),
        "{e}"
    );
    assert!(!d.path().join("b").exists());
    // A copy of a benchmark with a cell that is not a number: file, line and column named.
    let mine = d.path().join("mine/dryer");
    std::fs::create_dir_all(&mine).unwrap();
    let src = data.join("daisy-hair-dryer");
    std::fs::copy(src.join("benchmark.toml"), mine.join("benchmark.toml")).unwrap();
    std::fs::copy(src.join("train.csv.gz"), mine.join("train.csv.gz")).unwrap();
    std::fs::write(
        mine.join("test.csv.gz"),
        b"", // not gzip: an unreadable file
    )
    .unwrap();
    let o = rhonn(d.path(), &["benchmark", "--data-dir", "mine", "--out", "b"]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(e.contains("test.csv.gz"), "{e}");
    std::fs::write(
        mine.join("test.csv.gz"),
        gz("k,t_s,u_heater_V,y_outlet_temp_V\n0,0,1,2\n1,0.08,1,nan\n"),
    )
    .unwrap();
    let o = rhonn(d.path(), &["benchmark", "--data-dir", "mine", "--out", "b"]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(
        e.contains("test.csv.gz, line 3, column `y_outlet_temp_V`: `nan` is not a finite number"),
        "{e}"
    );
    std::fs::write(mine.join("benchmark.toml"), "title = 3\n").unwrap();
    let o = rhonn(d.path(), &["benchmark", "--data-dir", "mine", "--out", "b"]);
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(e.contains("benchmark.toml") && e.contains("title"), "{e}");
    assert!(!d.path().join("b").exists());
}

fn gz(text: &str) -> Vec<u8> {
    use std::io::Write;
    let mut e = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::default());
    e.write_all(text.as_bytes()).unwrap();
    e.finish().unwrap()
}

/// The first `n` rows of a shipped benchmark's gzip CSV, its time column named `t`.
fn head_of(gz_path: &Path, n: usize) -> String {
    use std::io::Read;
    let mut text = String::new();
    flate2::read::GzDecoder::new(std::fs::File::open(gz_path).unwrap())
        .read_to_string(&mut text)
        .unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().replace("t_s", "t");
    std::iter::once(header)
        .chain(lines.take(n).map(str::to_string))
        .collect::<Vec<_>>()
        .join("\n")
}

/// A folder with the first `n_train` rows of benchmark `name`'s `train_file` as
/// `train.csv` and the first `n_test` of its `test_file` as `test.csv`, so that a check
/// runs in seconds.
fn benchmark_head(
    name: &str,
    train_file: &str,
    n_train: usize,
    test_file: &str,
    n_test: usize,
) -> tempfile::TempDir {
    let d = tempfile::tempdir().unwrap();
    let b = repo().join("data/benchmarks").join(name);
    std::fs::write(d.path().join("train.csv"), head_of(&b.join(train_file), n_train)).unwrap();
    std::fs::write(d.path().join("test.csv"), head_of(&b.join(test_file), n_test)).unwrap();
    d
}

/// A third of Silverbox's training file and half of its multisine test file.
fn silverbox_third() -> tempfile::TempDir {
    benchmark_head(
        "silverbox",
        "train.csv.gz",
        20_000,
        "test_multisine.csv.gz",
        10_000,
    )
}

/// `rhonn fit --model SPEC` on `train.csv` (input u_V, output y_V) in `dir`, then `rhonn
/// predict` on `test.csv`: the model's and the ARX baseline's free-run RMS errors, and the
/// summary as text.
fn fit_then_predict(dir: &Path, spec: &str) -> (f64, f64, String) {
    let fit = [
        "fit",
        "--data",
        "train.csv",
        "--inputs",
        "u_V",
        "--outputs",
        "y_V",
        "--model",
        spec,
        "--out",
        "m",
    ];
    let o = rhonn(dir, &fit);
    assert!(o.status.success(), "{}", stderr(&o));
    let predict = [
        "predict",
        "--model",
        "m/model.json",
        "--data",
        "test.csv",
        "--out",
        "p",
    ];
    let o = rhonn(dir, &predict);
    assert!(o.status.success(), "{}", stderr(&o));
    let s = json(&dir.join("p/summary.json"));
    let text = s.to_string();
    let model = s["outputs"][0]["rms_error"].as_f64().expect(&text);
    let arx = s["baseline_arx"][0]["rms_error"].as_f64().expect(&text);
    (model, arx, text)
}

#[test]
fn the_wiener_hammerstein_block_structure_runs_free_on_the_benchmarks_test_below_the_gru() {
    // A fifth of the Wiener-Hammerstein 2009 records (train and test), so that it runs in
    // seconds; `rhonn benchmark wiener-hammerstein-2009` on the whole gives 1.36 mV.
    let d = benchmark_head(
        "wiener-hammerstein-2009",
        "train.csv.gz",
        20_000,
        "test.csv.gz",
        20_000,
    );
    std::fs::write(
        d.path().join("wh.toml"),
        "kind = \"wiener-hammerstein\"\nna = 6\nnb = 7\nnk = 0\ndegree = 12\nepochs = 30\n",
    )
    .unwrap();
    let (model, arx, text) = fit_then_predict(d.path(), "wh.toml");
    // The GRU's published 3.97 mV (arXiv 2405.10779) on the whole test record; the ARX of
    // the same orders is ten times further.
    assert!(model < 3.97e-3, "{model} V; {text}");
    assert!(model < 0.1 * arx, "{model} V against the ARX's {arx} V");
}

/// Issue 34: the online bank's polynomial NARX (recursive least squares on monomials of
/// the lags) is what default `rhonn identify` chooses on Silverbox, and its frozen free
/// run is below the best published neural baseline and a tenth of the offline ARX's.
#[test]
fn default_identify_chooses_the_recursive_polynomial_narx_on_silverbox() {
    // A third of Silverbox's training file and half of its multisine test file; `rhonn
    // benchmark silverbox` on the whole gives 0.259 mV there.
    let d = silverbox_third();
    let args = [
        "identify",
        "--data",
        "train.csv",
        "--inputs",
        "u_V",
        "--outputs",
        "y_V",
        "--validate",
        "test.csv",
        "--out",
        "o",
    ];
    let o = rhonn(d.path(), &args);
    assert!(o.status.success(), "{}", stderr(&o));
    let s = json(&d.path().join("o/summary.json"));
    let sel = &s["selection"];
    let chosen = &sel["candidates"][sel["chosen"].as_u64().unwrap() as usize];
    assert!(
        chosen["name"]
            .as_str()
            .unwrap()
            .starts_with("recursive polynomial NARX"),
        "{chosen}"
    );
    // Of its two priors, the one with a ridge (P(0) = 10 I) ran free better in the windows.
    assert!(chosen["name"].as_str().unwrap().ends_with("p0 10"), "{chosen}");
    let poly: Vec<f64> = sel["candidates"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|c| {
            c["name"]
                .as_str()
                .unwrap()
                .starts_with("recursive polynomial NARX")
        })
        .map(|c| c["free_run_nrmse"].as_f64().unwrap())
        .collect();
    assert_eq!(poly.len(), 2, "{sel}");
    let r = &s["baseline_arx"]["records"][0];
    let (online, arx) = (
        r["online_rms_error"].as_f64().unwrap(),
        r["arx_rms_error"].as_f64().unwrap(),
    );
    // The GRU's published 1.49 mV on the whole multisine record (arXiv 2405.10779).
    assert!(online < 1.49e-3, "{online} V; {r}");
    assert!(online < 0.1 * arx, "{online} V against the offline ARX's {arx} V");
}

#[test]
fn a_polynomial_rhonn_runs_free_on_silverbox_below_the_neural_baseline() {
    // A third of Silverbox's training file and half of its multisine test file, so that it
    // runs in seconds; `rhonn benchmark silverbox` on the whole gives 0.229 mV there.
    let d = silverbox_third();
    std::fs::write(
        d.path().join("poly.toml"),
        "kind = \"rhonn\"\nactivation = \"identity\"\nna = 4\nnb = 4\nnk = 0\ndegree = 3\nmax_factors = 3\n\
         nonlinear_lags = 2\nlaw = \"simulation-error\"\nepochs = 15\n",
    )
    .unwrap();
    let (model, arx, text) = fit_then_predict(d.path(), "poly.toml");
    // The GRU's published 1.49 mV on the whole multisine record (arXiv 2405.10779); the ARX
    // of the same lags is ten times further.
    assert!(model < 1.49e-3, "{model} V; {text}");
    assert!(model < 0.1 * arx, "{model} V against the ARX's {arx} V");
}

/// Every shipped benchmark's published figures are cited with their year; each test set
/// that has any has a best on the protocol's own split (figures on another split are
/// marked and never taken for it), and the neural baseline is never below that best.
#[test]
fn every_published_figure_is_cited_with_its_year_and_its_split() {
    let dir = repo().join("data/benchmarks");
    let mut names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.join("benchmark.toml").exists())
        .collect();
    names.sort();
    assert!(names.len() >= 9, "{names:?}");
    let mut cited = 0;
    for b in names {
        let text = std::fs::read_to_string(b.join("benchmark.toml")).unwrap();
        let spec: rhonn::benchmark::BenchmarkSpec = toml::from_str(&text).unwrap();
        for t in &spec.test {
            for p in &t.published {
                assert!(p.year.is_some(), "{b:?} `{}`: {p:?}", t.label);
                cited += 1;
            }
            if t.published.is_empty() {
                continue;
            }
            for j in 0..spec.outputs.len() {
                let best = rhonn::benchmark::published_best(&t.published, j);
                let b0 = best.best.expect("a best on the protocol's split");
                assert!(b0.other_split.is_none());
                if let Some(n) = best.neural_baseline {
                    assert!(n.rmse[j] >= b0.rmse[j], "{b:?} `{}`", t.label);
                }
            }
        }
    }
    assert!(cited >= 20, "{cited}");
}
