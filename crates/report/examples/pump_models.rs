//! The pump models of the README, reproduced from the records `rhonn run` writes:
//!
//! ```sh
//! rhonn run pump-identify && rhonn run pump-validate
//! for s in scenarios/stress/*.toml; do rhonn run "$s"; done
//! cargo run --release -p rhonn-report --example pump_models -- select   # how models/pump.toml was chosen
//! cargo run --release -p rhonn-report --example pump_models -- table    # the README's table
//! ```
//!
//! `select` reads pump-identify only: 3-fold cross-validation over contiguous 20 s thirds
//! (train on two, judge the third 10 and 200 samples ahead) of the grey-box settings in
//! its grid. `table` trains `models/pump.toml` (grey box), `models/pump-direct.toml` (the
//! direct 10-step RHONN predictor, with its ARX baseline) and the ceiling (the grey box
//! with the thesis's true parameters and the same state estimator) on pump-identify, and
//! prints their fits 1, 10 and 200 samples ahead on pump-validate and each stress record
//! beside persistence, every figure over the same samples (from sample 250 on).

use rhonn::data::Record;
use rhonn::metrics::fit_percent;
use rhonn::sysid::{fit_with_baseline, parse_spec_file, predict, FittedModel, ModelSpec};
use rhonn_report::read_record;
use std::path::Path;

type Error = Box<dyn std::error::Error>;

/// The first sample every figure starts at (after the longest horizon and lags).
const FROM: usize = 250;

/// The sample from which the filter's own error is measured (12 s: after its transient).
const FILTER_FROM: usize = 2400;

/// The records the table reports (none of them used in training or selection).
const RECORDS: [&str; 4] = [
    "pump-validate",
    "stress-multisine",
    "stress-noise",
    "stress-nodither",
];

fn names() -> (Vec<String>, Vec<String>) {
    (
        vec!["current".into(), "demand".into()],
        vec!["p_line_measured".into()],
    )
}

fn record(name: &str) -> Result<Record, Error> {
    let (u, y) = names();
    let path = format!("out/{name}/trajectory.csv");
    if !Path::new(&path).exists() {
        return Err(format!("{path} is missing: run `rhonn run {name}` first (see this file's docs)").into());
    }
    Ok(read_record(Path::new(&path), &u, &y, 100)?)
}

fn spec(path: &str) -> Result<ModelSpec, Error> {
    Ok(parse_spec_file(&std::fs::read_to_string(path)?)?.remove(0))
}

fn train(s: &ModelSpec, recs: &[Record]) -> Result<FittedModel, Error> {
    let (u, y) = names();
    Ok(fit_with_baseline(s, recs, &u, &y)?)
}

/// The model's (or, with `baseline`, its ARX baseline's) fit K samples ahead on `r`.
fn fit_k(m: &FittedModel, r: &Record, k: usize, baseline: bool) -> Result<f64, Error> {
    let p = predict(m, r, Some(k))?;
    let out = if baseline {
        &p.baseline.as_ref().ok_or("no baseline")?.0[0]
    } else {
        &p.outputs[0]
    };
    Ok(fit_percent(&r.outputs[0][FROM..], &out[FROM..]))
}

fn persistence(r: &Record, k: usize) -> f64 {
    let y = &r.outputs[0];
    fit_percent(&y[FROM..], &y[FROM - k..y.len() - k])
}

fn select() -> Result<(), Error> {
    let id = record("pump-identify")?;
    let n = id.len();
    let cuts = [0, n / 3, 2 * n / 3, n];
    let base = spec("models/pump.toml")?;
    println!("| estimate | horizon | process noise MPa / mm | fold fits 10 ahead | fold fits 200 ahead | mean of both |");
    println!("|---|---|---|---|---|---|");
    let mut best: Option<(f64, String)> = None;
    for estimate in [vec!["beta", "q_0", "mu_1"]] {
        for horizon in [10, 50, 200] {
            for (pn_mpa, pn_mm) in [
                (0.001, 1e-5),
                (0.001, 1e-4),
                (0.01, 1e-5),
                (0.01, 1e-4),
                (0.1, 1e-5),
                (0.1, 1e-4),
            ] {
                let mut s = base.clone();
                s.pump.estimate = estimate.iter().map(|e| e.to_string()).collect();
                s.horizon = horizon;
                s.pump.process_noise_mpa = pn_mpa;
                s.pump.process_noise_mm = pn_mm;
                let (mut f10, mut f200) = (vec![], vec![]);
                for fold in 0..3 {
                    let train_recs: Vec<Record> = (0..3)
                        .filter(|&f| f != fold)
                        .map(|f| id.slice(cuts[f], cuts[f + 1]))
                        .collect();
                    let test = id.slice(cuts[fold], cuts[fold + 1]);
                    let m = train(&s, &train_recs)?;
                    f10.push(fit_k(&m, &test, 10, false)?);
                    f200.push(fit_k(&m, &test, 200, false)?);
                }
                let mean = (f10.iter().sum::<f64>() + f200.iter().sum::<f64>()) / 6.0;
                let row = format!(
                    "| {} | {horizon} | {pn_mpa} / {pn_mm} | {:.1} / {:.1} / {:.1} | {:.1} / {:.1} / {:.1} | {mean:.2} |",
                    estimate.join(", "),
                    f10[0],
                    f10[1],
                    f10[2],
                    f200[0],
                    f200[1],
                    f200[2]
                );
                println!("{row}");
                if best.as_ref().is_none_or(|b| mean > b.0) {
                    best = Some((mean, row));
                }
            }
        }
    }
    println!("\nbest: {}", best.map(|b| b.1).unwrap_or_default());
    Ok(())
}

fn table() -> Result<(), Error> {
    let id = record("pump-identify")?;
    let grey_spec = spec("models/pump.toml")?;
    let grey = train(&grey_spec, std::slice::from_ref(&id))?;
    let direct = train(&spec("models/pump-direct.toml")?, std::slice::from_ref(&id))?;
    let mut ceiling_spec = grey_spec.clone();
    ceiling_spec.pump.estimate.clear();
    let ceiling = train(&ceiling_spec, std::slice::from_ref(&id))?;
    println!(
        "estimated: {}",
        rhonn::sysid::pump_grey::describe_estimates(&grey.model)
    );
    true_state(&ceiling)?;
    println!("| record | K (time ahead) | grey box (models/pump.toml) | direct RHONN (models/pump-direct.toml) | ARX, same lags | persistence | ceiling |");
    println!("|---|---|---|---|---|---|---|");
    for name in RECORDS {
        let r = record(name)?;
        for k in [1, 10, 200] {
            println!(
                "| {name} | {k} ({} ms) | {:.1} % | {:.1} % | {:.1} % | {:.1} % | {:.1} % |",
                k * 5,
                fit_k(&grey, &r, k, false)?,
                fit_k(&direct, &r, k, false)?,
                fit_k(&direct, &r, k, true)?,
                persistence(&r, k),
                fit_k(&ceiling, &r, k, false)?,
            );
        }
    }
    Ok(())
}

/// What the state estimate costs: the ceiling's equations started from the true state
/// of each record (its `p_line` and `stroke` columns) and from that state slightly off
/// (the sensor noise is 0.02-0.1 MPa).
fn true_state(ceiling: &FittedModel) -> Result<(), Error> {
    for name in RECORDS {
        let r = record(name)?;
        let truth = read_record(
            Path::new(&format!("out/{name}/trajectory.csv")),
            &names().0,
            &["p_line".to_string(), "stroke".to_string()],
            100,
        )?;
        let y = &r.outputs[0];
        let mut line = format!("{name}, 10 / 200 ahead, from");
        for (dp_pa, dx_m, label) in [
            (0.0, 0.0, "the true state"),
            (2e3, 0.0, "pressure +0.002 MPa"),
            (2e4, 0.0, "pressure +0.02 MPa"),
            (0.0, 1e-7, "stroke +0.1 um"),
        ] {
            let mut fits = Vec::new();
            for k in [10, 200] {
                let pred = (FROM..y.len())
                    .map(|end| {
                        let s = [
                            truth.outputs[0][end - k] + dp_pa,
                            truth.outputs[1][end - k] + dx_m,
                            0.0,
                        ];
                        let p =
                            rhonn::sysid::pump_grey::predict_from_state(&ceiling.model, &r, end - k, s, k)?;
                        Ok(p[k - 1])
                    })
                    .collect::<Result<Vec<f64>, Error>>()?;
                fits.push(format!("{:.1} %", fit_percent(&y[FROM..], &pred)));
            }
            line += &format!(" {label}: {};", fits.join(" / "));
        }
        println!("{}", line.trim_end_matches(';'));
        // The filter's own error against the true state, after its first 12 s.
        let est = rhonn::sysid::pump_grey::estimate_states(&ceiling.model, &r)?;
        let rms = |c: usize, scale: f64| {
            let e: Vec<f64> = (FILTER_FROM..est.len())
                .map(|k| (est[k][c] - truth.outputs[c][k]) * scale)
                .collect();
            (e.iter().map(|v| v * v).sum::<f64>() / e.len() as f64).sqrt()
        };
        println!(
            "{name}, the filter's RMS error from 12 s on: pressure {:.4} MPa, stroke {:.2} um",
            rms(0, 1e-6),
            rms(1, 1e6)
        );
    }
    Ok(())
}

fn main() -> Result<(), Error> {
    match std::env::args().nth(1).as_deref() {
        Some("select") => select(),
        Some("table") => table(),
        _ => Err("usage: pump_models select|table (see the file's docs)".into()),
    }
}
