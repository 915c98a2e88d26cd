//! `rhonn benchmark [NAME...]`: the shipped standard benchmarks under their protocol
//! (`rhonn::benchmark::run`), one table beside the published figures, and per benchmark
//! the models trained on train (`NAME/model.json` runs with `rhonn predict`), the free runs
//! on every test set as CSV and plots, and a report.

use super::Outcome;
use rhonn::benchmark::BenchmarkOutcome;
pub use rhonn_report::benchmark_file::Row;
use rhonn_report::benchmark_file::Summary;
use rhonn_report::OutputSet;
use rhonn_report::{Error, Result};
use rhonn_report::{Series, TimePlot};
use std::path::{Path, PathBuf};

/// What `rhonn benchmark` takes.
#[derive(Debug, Clone)]
pub struct BenchmarkRequest {
    /// The benchmarks to run (empty: every one in `data_dir`).
    pub names: Vec<String>,
    /// The benchmarks' folder (`data/benchmarks`).
    pub data_dir: PathBuf,
    /// The output folder.
    pub out: PathBuf,
    /// Print the table as JSON instead of text.
    pub json: bool,
    /// A model spec (`rhonn fit --model`'s) trained in place of the default selection's
    /// choice (`rhonn fit (--model)` in the table).
    pub model: Option<PathBuf>,
}

const PROTOCOL: &str = "every model trained on the benchmark's training records only (structure and settings chosen by cross-validation inside them), run free on each test set from its start-up window; RMS error from the first sample every model predicts (the window, or a model's largest lag if later), in the data's units";

/// The table's rows of one benchmark.
fn rows_of(b: &BenchmarkOutcome) -> Vec<Row> {
    let mut rows = Vec::new();
    for (k, ts) in b.test_sets.iter().enumerate() {
        for (j, out) in b.outputs.iter().enumerate() {
            let m = |i: usize| &b.methods[i];
            let p = rhonn::benchmark::published_best(&ts.published, j);
            let cited = |q: Option<&rhonn::benchmark::Published>| q.map(|q| q.cited()).unwrap_or_default();
            rows.push(Row {
                benchmark: b.name.clone(),
                test: ts.label.clone(),
                output: out.clone(),
                unit: b.units.get(out).cloned().unwrap_or_default(),
                scored_from: ts.scored_from,
                samples: ts.samples,
                fit_method: (m(0).method != "rhonn fit (default)").then(|| m(0).method.clone()),
                fit_rmse: m(0).tests[k].rmse[j],
                fit_structure: m(0).structure.clone(),
                fit_time_s: m(0).train_time_s,
                online_rmse: m(1).tests[k].rmse[j],
                online_structure: m(1).structure.clone(),
                online_time_s: m(1).train_time_s,
                arx_rmse: m(2).tests[k].rmse[j],
                arx_structure: m(2).structure.clone(),
                arx_time_s: m(2).train_time_s,
                published_rmse: p.best.map(|q| q.rmse[j]),
                published_model: p.best.map(|q| q.model.clone()).unwrap_or_default(),
                published_source: p
                    .best
                    .map(|q| match q.year {
                        Some(y) => format!("{}, {y}", q.source),
                        None => q.source.clone(),
                    })
                    .unwrap_or_default(),
                baseline_rmse: p.neural_baseline.map(|q| q.rmse[j]),
                baseline_cited: cited(p.neural_baseline),
                other_split_rmse: p.other_split.map(|q| q.rmse[j]),
                other_split_cited: p
                    .other_split
                    .map(|q| format!("{}; {}", q.cited(), q.other_split.as_deref().unwrap_or("")))
                    .unwrap_or_default(),
            });
        }
    }
    rows
}

/// A figure with 3 significant digits in a readable unit: V and m below 0.1 in mV / mm
/// or µV / µm.
pub fn figure(v: f64, unit: &str) -> String {
    let (v, unit) = match unit {
        "V" | "m" | "N" if v.abs() < 1e-4 && v != 0.0 => (v * 1e6, format!(" µ{unit}")),
        "V" | "m" | "N" if v.abs() < 0.1 && v != 0.0 => (v * 1e3, format!(" m{unit}")),
        "" => (v, String::new()),
        u => (v, format!(" {u}")),
    };
    format!("{}{unit}", rhonn::metrics::sig(v, 3))
}

/// `rhonn benchmark`.
pub fn benchmark(req: &BenchmarkRequest, progress: &(dyn Fn(&str) + Sync)) -> Result<Outcome> {
    let names = if req.names.is_empty() {
        rhonn_report::benchmark_data::available(&req.data_dir)?
    } else {
        req.names.clone()
    };
    if names.is_empty() {
        return Err(Error::Input(format!(
            "no benchmark in {} (a folder per benchmark with its benchmark.toml)",
            req.data_dir.display()
        )));
    }
    // The spec and every benchmark are read (and their errors found) before any is run.
    let model = match &req.model {
        Some(p) => {
            let source = p.display().to_string();
            let specs = super::fit::model_specs(Some(&super::read_text(p)?), &source)?;
            let name = p
                .file_name()
                .map_or(source.clone(), |f| f.to_string_lossy().into_owned());
            Some((specs, name))
        }
        None => None,
    };
    let loaded = names
        .iter()
        .map(|n| rhonn_report::benchmark_data::load(&req.data_dir, n))
        .collect::<Result<Vec<_>>>()?;
    let inputs: Vec<PathBuf> = req.model.iter().cloned().collect();
    super::in_folder(
        &req.out,
        (&inputs, rhonn_report::folder::writes::BENCHMARK),
        false,
        |stage| {
            let mut o = Outcome::default();
            let mut rows = Vec::new();
            for b in &loaded {
                let given = model
                    .as_ref()
                    .map(|(specs, name)| (specs.as_slice(), name.as_str()));
                let res = rhonn::benchmark::run_with(b, given, progress)
                    .map_err(|e| super::context(format!("benchmark {}", b.name))(e.into()))?;
                o.files.extend(write_one(
                    (&stage.join(&b.name), &req.out.join(&b.name)),
                    b,
                    &res,
                )?);
                o.notes
                    .extend(res.warnings.iter().map(|w| format!("warning: {}: {w}", b.name)));
                rows.extend(rows_of(&res));
            }
            let mut set = OutputSet::new(stage)?;
            let summary = Summary {
                rhonn_version: env!("CARGO_PKG_VERSION"),
                protocol: PROTOCOL,
                rows: &rows,
            };
            set.write("summary.json", |w| rhonn_report::write_json(w, &summary))?;
            set.write("benchmark.csv", |w| write_rows_csv(w, &rows))?;
            o.files.extend(set.commit()?);
            o.lines = if req.json {
                vec![serde_json::to_string_pretty(&summary).map_err(|e| Error::Input(e.to_string()))?]
            } else {
                table_lines(&rows)
            };
            Ok(o)
        },
    )
}

/// The console table: one line per benchmark, test set and output.
fn table_lines(rows: &[Row]) -> Vec<String> {
    let mut lines = vec![
        "free-run RMS error on test (trained on train only; every model sees only the start-up window's outputs \
         and is scored from its end, or without a window from the latest first prediction: scored_from in \
         benchmark.csv); the best of each row in *stars*"
            .to_string(),
        format!(
            "benchmark | test | output | {} | rhonn identify (default) | ARX (lags by CV) | published best | training time fit / online / ARX",
            rows.first()
                .and_then(|r| r.fit_method.as_deref())
                .unwrap_or("rhonn fit (default)")
        ),
    ];
    for r in rows {
        let best = r.fit_rmse.min(r.online_rmse).min(r.arx_rmse);
        let cell = |v: f64, s: &str| {
            let f = figure(v, &r.unit);
            if v == best {
                format!("*{f}* ({s})")
            } else {
                format!("{f} ({s})")
            }
        };
        let mut published = match r.published_rmse {
            Some(v) => format!(
                "{} ({}, {})",
                figure(v, &r.unit),
                r.published_model,
                r.published_source
            ),
            None => "none published".into(),
        };
        if let Some(v) = r.baseline_rmse.filter(|v| Some(*v) != r.published_rmse) {
            published += &format!("; neural baseline {} ({})", figure(v, &r.unit), r.baseline_cited);
        }
        if let Some(v) = r.other_split_rmse {
            published += &format!(
                "; on another split {} ({})",
                figure(v, &r.unit),
                r.other_split_cited
            );
        }
        lines.push(format!(
            "{} | {} | {} | {} | {} | {} | {} | {} / {} / {} s",
            r.benchmark,
            r.test,
            r.output,
            cell(r.fit_rmse, &r.fit_structure),
            cell(r.online_rmse, &r.online_structure),
            cell(r.arx_rmse, &r.arx_structure),
            published,
            rhonn::metrics::sig(r.fit_time_s, 2),
            rhonn::metrics::sig(r.online_time_s, 2),
            rhonn::metrics::sig(r.arx_time_s, 2)
        ));
    }
    lines
}

fn write_rows_csv(w: &mut dyn std::io::Write, rows: &[Row]) -> std::io::Result<()> {
    let mut c = csv::Writer::from_writer(w);
    for r in rows {
        c.serialize(r).map_err(std::io::Error::other)?;
    }
    c.flush()
}

/// `DIR/NAME/`: the models (model.json, online/model.json), summary.json, per test set
/// the free runs (CSV and plot) and the fit model's residuals, report.html.
fn write_one(
    (dir, shown): (&Path, &Path),
    b: &rhonn::benchmark::Benchmark,
    res: &BenchmarkOutcome,
) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    let mut online = OutputSet::new(&dir.join("online"))?;
    online.write("model.json", |w| rhonn_report::write_json(w, &res.online))?;
    files.extend(online.commit()?);
    let mut set = OutputSet::new(dir)?;
    set.write("model.json", |w| rhonn_report::write_json(w, &res.fitted))?;
    set.write("summary.json", |w| rhonn_report::write_json(w, res))?;
    for (k, (ts, r)) in res.test_sets.iter().zip(&b.tests).enumerate() {
        let preds: Vec<&Vec<Vec<f64>>> = res.methods.iter().map(|m| &m.tests[k].prediction).collect();
        set.write(&format!("free_run_{k}.csv"), |w| {
            free_run_csv(w, r, (&b.spec.inputs, &res.outputs), &preds)
        })?;
        let svg = free_run_plot(res, k, r, &preds);
        set.write(&format!("free_run_{k}.svg"), |w| w.write_all(svg.as_bytes()))?;
        let resid = rhonn_report::plot_residuals(r, preds[0], ts.scored_from, &b.spec.inputs, &res.outputs);
        set.write(&format!("residuals_{k}.svg"), |w| w.write_all(resid.as_bytes()))?;
    }
    files.extend(set.commit()?);
    files.push(rhonn_report::write_report_as(dir, shown)?);
    Ok(files)
}

const METHOD_COLUMNS: [&str; 3] = ["fit", "online", "arx"];

/// `free_run_K.csv`: t, the inputs, then per output the measurement and the three free
/// runs (`<name>_fit`, `<name>_online`, `<name>_arx`): a recording `rhonn predict` reads.
/// With no runs: the record alone (`rhonn corpus`'s recordings).
pub(super) fn free_run_csv(
    w: &mut dyn std::io::Write,
    r: &rhonn::data::Record,
    (inputs, outputs): (&[String], &[String]),
    preds: &[&Vec<Vec<f64>>],
) -> std::io::Result<()> {
    let mut head = vec!["t".to_string()];
    head.extend(inputs.iter().cloned());
    for o in outputs {
        head.push(o.clone());
        head.extend(
            METHOD_COLUMNS
                .iter()
                .take(preds.len())
                .map(|m| format!("{o}_{m}")),
        );
    }
    writeln!(w, "{}", head.join(","))?;
    for k in 0..r.len() {
        let mut row = vec![r.t[k].to_string()];
        row.extend(r.inputs.iter().map(|u| u[k].to_string()));
        for (j, y) in r.outputs.iter().enumerate() {
            row.push(y[k].to_string());
            row.extend(preds.iter().map(|p| p[j][k].to_string()));
        }
        writeln!(w, "{}", row.join(","))?;
    }
    Ok(())
}

fn free_run_plot(
    res: &BenchmarkOutcome,
    k: usize,
    r: &rhonn::data::Record,
    preds: &[&Vec<Vec<f64>>],
) -> String {
    let ts = &res.test_sets[k];
    let plots: Vec<TimePlot> = res
        .outputs
        .iter()
        .enumerate()
        .map(|(j, o)| {
            let unit = res.units.get(o).map_or(String::new(), |u| format!(" [{u}]"));
            let mut series = vec![Series::solid(format!("{o} measured"), r.outputs[j].clone())];
            for (m, p) in res.methods.iter().zip(preds) {
                series.push(Series::solid(
                    format!(
                        "{} (RMS error {})",
                        m.method,
                        figure(m.tests[k].rmse[j], res.units.get(o).map_or("", |u| u))
                    ),
                    p[j].clone(),
                ));
            }
            TimePlot {
                title: format!(
                    "{}: {} free run, {o} (scored from sample {})",
                    res.name, ts.label, ts.scored_from
                ),
                y_label: format!("{o}{unit}"),
                t: r.t.clone(),
                series,
            }
        })
        .collect();
    TimePlot::render(&plots, 900, 380)
}
