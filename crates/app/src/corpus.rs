//! `rhonn corpus`: rhonn fit's default judged on the unseen-systems corpus
//! (`rhonn::corpus`): per system and output, its free-run RMS error on the test records
//! over the ARX's (lags by cross-validation on train), then the median and the worst.

use super::Outcome;
use rhonn::corpus::{self, Judged, Summary};
use rhonn::metrics::sig;
use rhonn_report::corpus_file::SummaryFile;
use rhonn_report::OutputSet;
use rhonn_report::{Error, Result};
use serde::Serialize;
use std::path::PathBuf;

/// What `rhonn corpus` takes.
#[derive(Debug, Clone)]
pub struct CorpusRequest {
    /// The corpus's seed.
    pub seed: u64,
    /// Systems drawn (cycling through the families).
    pub systems: usize,
    /// Only these systems (indices), when given.
    pub only: Vec<usize>,
    /// The output folder (None: print only).
    pub out: Option<PathBuf>,
    /// Print summary.json's text instead of the table.
    pub json: bool,
}

/// One row of corpus.csv: one output of one system.
#[derive(Debug, Serialize, schemars::JsonSchema)]
struct Row<'a> {
    system: &'a str,
    family: &'static str,
    train_input: &'static str,
    test_input: &'static str,
    train_samples: usize,
    output: &'a str,
    fit_rmse: Option<f64>,
    arx_rmse: Option<f64>,
    test_std: Option<f64>,
    ratio: Option<f64>,
    flagged_no_better_than_mean: bool,
    fit_structure: &'a str,
    arx_structure: &'a str,
    online_rmse: Option<f64>,
    online_ratio: Option<f64>,
    online_structure: &'a str,
    failed: &'a str,
}

const PROTOCOL: &str = "each system's default rhonn fit and ARX (lags by cross-validation) trained on its training records only, run free on its test records; RMS error from the later of the two models' first predictions; ratio = rhonn / ARX per output; online_ratio = rhonn identify's default online model (trained on the same records, frozen) / ARX over the samples from the later of their first predictions";

fn rows(judged: &[Judged]) -> Vec<Row<'_>> {
    let mut v = Vec::new();
    for j in judged {
        let row = |output: &'static str| Row {
            system: &j.system,
            family: j.family.name(),
            train_input: j.train_input.name(),
            test_input: j.test_input.name(),
            train_samples: j.train_samples,
            output,
            fit_rmse: None,
            arx_rmse: None,
            test_std: None,
            ratio: None,
            flagged_no_better_than_mean: false,
            fit_structure: &j.fit_structure,
            arx_structure: &j.arx_structure,
            online_rmse: None,
            online_ratio: None,
            online_structure: &j.online_structure,
            failed: j.failed.as_deref().unwrap_or(""),
        };
        if j.outputs.is_empty() {
            v.push(row(""));
        }
        for o in &j.outputs {
            v.push(Row {
                output: &o.output,
                fit_rmse: Some(o.fit_rmse),
                arx_rmse: Some(o.arx_rmse),
                test_std: Some(o.test_std),
                ratio: Some(o.ratio),
                flagged_no_better_than_mean: o.flagged_no_better_than_mean,
                online_rmse: o.online_rmse,
                online_ratio: o.online_ratio,
                ..row("")
            });
        }
    }
    v
}

fn table(judged: &[Judged], s: &Summary, seed: u64) -> Vec<String> {
    let mut lines = vec![
        format!("unseen-systems corpus, seed {seed}: free-run RMS error on each system's test records, rhonn fit (default) over the ARX (lags by CV), both trained on train only"),
        "system | family | train / test input | output | rhonn / ARX | rhonn | ARX | test std | rhonn's structure | online / ARX".into(),
    ];
    for j in judged {
        if let Some(f) = &j.failed {
            lines.push(format!("{} | {} | failed: {f}", j.system, j.family.name()));
        }
        for o in &j.outputs {
            lines.push(format!(
                "{} | {} | {} / {} | {} | {} | {} | {} | {} | {}{} | {}",
                j.system,
                j.family.name(),
                j.train_input.name(),
                j.test_input.name(),
                o.output,
                sig(o.ratio, 3),
                sig(o.fit_rmse, 3),
                sig(o.arx_rmse, 3),
                sig(o.test_std, 3),
                j.fit_structure,
                if o.flagged_no_better_than_mean {
                    " (the fit said: no better than the mean)"
                } else {
                    ""
                },
                o.online_ratio
                    .map_or_else(|| j.online_structure.clone(), |r| sig(r, 3)),
            ));
        }
    }
    lines.push(format!(
        "median ratio {} over {} outputs of {} systems; worst {} ({}); at most 1.01 x the ARX: {} of {}; above the test's standard deviation where the ARX is below it: {}; failed: {}",
        sig(s.median_ratio, 3),
        s.scored,
        judged.len(),
        sig(s.worst_ratio, 3),
        s.worst,
        s.at_most_arx,
        s.scored,
        s.above_std_where_arx_below,
        s.failed
    ));
    lines.push(format!(
        "online (rhonn identify's default): median ratio {}; worst {} ({}); at most 1.01 x the ARX: {} of {}",
        sig(s.online_median_ratio, 3),
        sig(s.online_worst_ratio, 3),
        s.online_worst,
        s.online_at_most_arx,
        s.scored
    ));
    lines
}

/// `rhonn corpus`.
pub fn corpus(req: &CorpusRequest, progress: &(dyn Fn(&str) + Sync)) -> Result<Outcome> {
    if req.systems == 0 || req.systems > 10_000 {
        return Err(Error::Input(format!(
            "--systems {}: give a number of systems in [1, 10000]",
            req.systems
        )));
    }
    if let Some(i) = req.only.iter().find(|&&i| i >= req.systems) {
        return Err(Error::Input(format!(
            "--only {i}: give system indices below --systems ({})",
            req.systems
        )));
    }
    if let Some(out) = &req.out {
        rhonn_report::folder::check_writable(out)?;
    }
    let picked: Vec<usize> = if req.only.is_empty() {
        (0..req.systems).collect()
    } else {
        req.only.clone()
    };
    let opts = rhonn::sysid::select::SelectOptions::default();
    let (mut systems, mut judged, mut trained) = (Vec::new(), Vec::new(), Vec::new());
    for (n, &i) in picked.iter().enumerate() {
        let sys = corpus::system(req.seed, i);
        let say = |l: &str| progress(&format!("system {}/{} ({}): {l}", n + 1, picked.len(), sys.name));
        let (j, t) = corpus::judge(&sys, &opts, &say);
        judged.push(j);
        trained.push(t);
        systems.push(sys);
        rhonn::cancel::check()?;
    }
    let summary = corpus::summarise(&judged);
    let file = SummaryFile {
        rhonn_version: env!("CARGO_PKG_VERSION"),
        seed: req.seed,
        protocol: PROTOCOL,
        summary: &summary,
        systems: &judged,
    };
    let lines = if req.json {
        vec![serde_json::to_string_pretty(&file).map_err(|e| Error::Input(e.to_string()))?]
    } else {
        table(&judged, &summary, req.seed)
    };
    let Some(out) = &req.out else {
        return Ok(Outcome {
            lines,
            ..Outcome::default()
        });
    };
    super::in_folder(out, (&[], rhonn_report::folder::writes::CORPUS), false, |stage| {
        let mut set = OutputSet::new(stage)?;
        set.write("summary.json", |w| rhonn_report::write_json(w, &file))?;
        // Each system's records, as recordings every command (and any other tool) reads,
        // and what was trained on them (`write_trained`).
        let mut recordings = 0;
        for ((sys, j), t) in systems.iter().zip(&judged).zip(&trained) {
            let mut one = OutputSet::new(&stage.join(&sys.name))?;
            for (what, recs) in [("train", &sys.train), ("test", &sys.tests)] {
                for (k, r) in recs.iter().enumerate() {
                    one.write(&format!("{what}_{k}.csv"), |w| {
                        super::benchmark::free_run_csv(w, r, (&sys.inputs, &sys.outputs), &[])
                    })?;
                    recordings += 1;
                }
            }
            if let Some(t) = t {
                write_trained(&mut one, &stage.join(&sys.name), j, t)?;
            }
            one.commit()?;
        }
        set.write("corpus.csv", |w| {
            let mut c = csv::Writer::from_writer(w);
            for r in rows(&judged) {
                c.serialize(r).map_err(std::io::Error::other)?;
            }
            c.flush()
        })?;
        let mut lines = lines.clone();
        lines.push(format!(
            "  wrote {recordings} recordings: {}/<system>/train_0.csv, test_0.csv (t, inputs, outputs); beside them model.json, online/model.json and summary.json (each model's selection)",
            out.display()
        ));
        Ok(Outcome {
            lines,
            files: set.commit()?,
            ..Outcome::default()
        })
    })
}

/// Into a system's folder `dir` (its files staged in `set`): rhonn fit's default model
/// (`model.json`), the online default frozen (`online/model.json`), both run with `rhonn
/// predict` on the system's test records; and `summary.json`, the system's row with each
/// model's selection (why it was chosen).
fn write_trained(
    set: &mut OutputSet,
    dir: &std::path::Path,
    judged: &Judged,
    t: &corpus::Trained,
) -> Result<()> {
    if let Some((model, _)) = &t.online {
        let mut online = OutputSet::new(&dir.join("online"))?;
        online.write("model.json", |w| rhonn_report::write_json(w, model))?;
        online.commit()?;
    }
    set.write("model.json", |w| rhonn_report::write_json(w, &t.fitted))?;
    let file = rhonn_report::corpus_file::SystemFile {
        system: judged,
        selection: t.selection.as_ref(),
        online_selection: t.online.as_ref().map(|(_, s)| s),
    };
    set.write("summary.json", |w| rhonn_report::write_json(w, &file))?;
    Ok(())
}
