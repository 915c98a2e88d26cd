//! `rhonn identify`: read the recordings, one library call, write, print.

use anyhow::{Context, Result};
use rhonn::ident::{identify_records, predict_records, OnlineModel, OnlineSpec};
use rhonn_report::identify::{validation_figures, write_identify, IdentifySummary, Validation};
use std::path::{Path, PathBuf};

/// The arguments of `rhonn identify`.
pub struct IdentifyArgs<'a> {
    pub data: &'a [PathBuf],
    pub inputs: &'a [String],
    pub outputs: &'a [String],
    pub model: Option<&'a Path>,
    pub epochs: Option<usize>,
    pub validate: &'a [PathBuf],
    pub steps_ahead: Option<usize>,
    pub out: &'a Path,
}

fn read_spec(p: &Path) -> Result<OnlineSpec> {
    let text = std::fs::read_to_string(p).map_err(|e| {
        anyhow::anyhow!(
            "cannot read {}: {}",
            p.display(),
            rhonn::error::path_problem(p, &e)
        )
    })?;
    toml::from_str(&text).map_err(|e| anyhow::anyhow!("cannot read model spec {}: {e}", p.display()))
}

pub fn cmd_identify(a: IdentifyArgs) -> Result<()> {
    let mut spec = match a.model {
        Some(p) => read_spec(p)?,
        None => OnlineSpec::default(),
    };
    if let Some(e) = a.epochs {
        spec.epochs = e;
    }
    if a.steps_ahead == Some(0) {
        anyhow::bail!("--steps-ahead 0 is not allowed: give K >= 1 samples");
    }
    let read = |paths: &[PathBuf]| -> Result<Vec<rhonn::data::Record>> {
        paths
            .iter()
            .map(|p| rhonn_report::read_record(p, a.inputs, a.outputs, 2).map_err(anyhow::Error::from))
            .collect()
    };
    let records = read(a.data)?;
    let busy = crate::progress::Busy::start(format!("identifying online on {} record(s)", records.len()));
    let run = identify_records(&spec, &records, a.outputs).context("online identification")?;
    let validation = if a.validate.is_empty() {
        None
    } else {
        let vrec = read(a.validate)?;
        rhonn::ident::sample_time(&vrec)?;
        let mut id = run.identifier.clone();
        let free_run = predict_records(&mut id, &vrec, None)?;
        let ahead = match a.steps_ahead {
            Some(k) => Some((k, predict_records(&mut id, &vrec, Some(k))?)),
            None => None,
        };
        Some(Validation {
            records: vrec,
            free_run,
            ahead,
        })
    };
    drop(busy);
    let dt = rhonn::ident::sample_time(&records)?;
    let weights = run.identifier.weights();
    let final_norms: Vec<f64> = weights
        .iter()
        .map(|w| w.iter().map(|x| x * x).sum::<f64>().sqrt())
        .collect();
    let vfig = validation
        .as_ref()
        .map(|v| validation_figures(v, a.outputs))
        .unwrap_or_default();
    let summary = IdentifySummary {
        model: spec.clone(),
        records: records.iter().map(|r| r.source.clone()).collect(),
        sample_time_s: dt,
        terms_per_neuron: run.identifier.n_terms(),
        terms: run.identifier.term_names(a.outputs, a.inputs),
        online: run.figures.clone(),
        final_weight_norms: final_norms,
        max_weight_norm_per_pass: run.max_norm_per_pass.clone(),
        findings: findings(&run, &vfig),
        validation: vfig,
    };
    let model = OnlineModel {
        kind: OnlineModel::KIND.into(),
        inputs: a.inputs.to_vec(),
        outputs: a.outputs.to_vec(),
        sample_time_s: dt,
        model: spec,
        scaling: run.identifier.scaling().clone(),
        weights,
    };
    let files = write_identify(
        a.out,
        &run,
        &records,
        a.outputs,
        &model,
        &summary,
        validation.as_ref(),
    )?;
    for f in &summary.online {
        println!(
            "{}: online (last half of the final pass) RMS error {:.4}, fit {:.1} %",
            f.output, f.rms_error_last_half, f.fit_percent_last_half
        );
    }
    for v in &summary.validation {
        print!(
            "{}: frozen, free run on the validation data: RMS error {:.4}, fit {:.1} %",
            v.output, v.free_run_rms_error, v.free_run_fit_percent
        );
        if let (Some(k), Some(r), Some(f)) = (v.horizon, v.ahead_rms_error, v.ahead_fit_percent) {
            print!("; {k} samples ahead: RMS error {r:.4}, fit {f:.1} %");
        }
        println!();
    }
    for f in files {
        println!("  wrote {}", f.display());
    }
    Ok(())
}

/// What the numbers mean, in words.
fn findings(run: &rhonn::ident::OnlineRun, v: &[rhonn_report::identify::ValidationFigures]) -> Vec<String> {
    let mut out = Vec::new();
    for f in &run.figures {
        out.push(match f.converged_s {
            Some(t) => format!("{}: the online error stays within +-{:.4} (twice its final RMS) from {t} s of the final pass on", f.output, f.band),
            None => format!("{}: the online error leaves the band +-{:.4} until the end of the final pass", f.output, f.band),
        });
    }
    let passes = &run.max_norm_per_pass;
    if passes.len() > 1 {
        let (first, last) = (&passes[0], &passes[passes.len() - 1]);
        for (i, (a, b)) in first.iter().zip(last).enumerate() {
            out.push(format!(
                "neuron {i}: largest weight norm {a:.3} in the first pass, {b:.3} in the last"
            ));
        }
    }
    for f in v {
        if f.free_run_fit_percent < 0.0 {
            out.push(format!("{}: the frozen model's free run is worse than the validation mean (fit {:.1} %): use K-step prediction or more passes", f.output, f.free_run_fit_percent));
        }
    }
    out
}

/// `rhonn predict` with a `model.json` written by `rhonn identify`.
pub fn cmd_predict_online(
    model_path: &Path,
    text: &str,
    data: &Path,
    out: &Path,
    steps: Option<usize>,
) -> Result<()> {
    let m: OnlineModel = serde_json::from_str(text)
        .map_err(|e| anyhow::anyhow!("{} is not a valid online model: {e}", model_path.display()))?;
    let mut id = m
        .identifier()
        .with_context(|| format!("{} is not a valid model", model_path.display()))?;
    let rec = rhonn_report::read_record(data, &m.inputs, &m.outputs, 2)?;
    let recs = std::slice::from_ref(&rec);
    rhonn::ident::sample_time(recs)?;
    let pred = predict_records(&mut id, recs, steps)?.remove(0);
    let figures =
        rhonn_report::identify::online_prediction_figures(&rec, &pred, &m.outputs, steps.unwrap_or(0));
    let files = rhonn_report::identify::write_online_prediction(
        out,
        &m,
        &model_path.display().to_string(),
        &rec,
        &pred,
        steps,
        &figures,
    )?;
    let mode = steps.map_or("free run".to_string(), |k| format!("{k} steps ahead"));
    for f in &figures {
        println!(
            "{} ({mode}): rms error {:.4}, fit {:.1} %, nrmse {:.4}",
            f.output, f.rms_error, f.fit_percent, f.nrmse
        );
    }
    for f in files {
        println!("  wrote {}", f.display());
    }
    Ok(())
}
