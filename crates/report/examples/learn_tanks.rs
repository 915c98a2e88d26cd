//! The cascaded tanks learned four ways through the library, as the commands do: `rhonn
//! fit`'s default (the structure selected by cross-validation on the estimation record),
//! `rhonn fit --model` (the shipped `models/cascaded-tanks.toml`), `rhonn identify`'s
//! default (the online bank), and a model learned one sample at a time in a loop of one's
//! own (Python's `OnlineIdentifier`); each run free on validation.csv.
//! `cargo run --release -p rhonn-report --example learn_tanks [DATA_DIR]`
//! (default `data/cascaded-tanks`).

use rhonn::ident::{OnlineSession, SessionOptions};
use rhonn::identification::{identify, IdentifyPlan};
use rhonn::metrics::sig;
use rhonn::sysid::{fit_records, parse_spec_file, predict, select::SelectOptions, FitStructure};
use rhonn_report::read_record;
use std::path::PathBuf;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let dir = PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "data/cascaded-tanks".into()),
    );
    let (u, y) = (vec!["u".to_string()], vec!["y".to_string()]);
    let estimation = read_record(&dir.join("estimation.csv"), &u, &y, 20)?;
    let validation = read_record(&dir.join("validation.csv"), &u, &y, 20)?;

    // `rhonn fit`: the selection, then the chosen structure trained on every record.
    let options = SelectOptions::default();
    let fit = fit_records(
        FitStructure::Select(&options),
        std::slice::from_ref(&estimation),
        &u,
        &y,
        &|line| eprintln!("{line}"),
    )?;
    let p = predict(&fit.fitted, &validation, None)?; // free run; Some(K): K steps ahead
    println!(
        "rhonn fit: {} V free-run RMS error on validation",
        sig(p.figures[0].rms_error, 4)
    );

    // `rhonn fit --model`: a structure of one's own.
    let specs = parse_spec_file(&std::fs::read_to_string("models/cascaded-tanks.toml")?)?;
    let given = fit_records(
        FitStructure::Given(specs),
        std::slice::from_ref(&estimation),
        &u,
        &y,
        &|_| {},
    )?;
    let p = predict(&given.fitted, &validation, None)?;
    println!(
        "rhonn fit --model: {} V free-run RMS error on validation",
        sig(p.figures[0].rms_error, 4)
    );

    // `rhonn identify`: the online bank over the records, the winner frozen, validated.
    let plan = IdentifyPlan {
        inputs: u.clone(),
        outputs: y.clone(),
        given: None,
        epochs: None,
        steps_ahead: None,
        units: Default::default(),
    };
    let id =
        identify(std::slice::from_ref(&estimation), &[validation], &plan).map_err(|e| format!("{e:?}"))?;
    println!(
        "rhonn identify: {} V free-run RMS error on validation",
        sig(id.summary.validation[0].free_run_rms_error, 4)
    );

    // One sample at a time: each estimate made before the sample is learned.
    let options = SessionOptions {
        samples: Some(estimation.len()),
        ..SessionOptions::default()
    };
    let dt = estimation.t[1] - estimation.t[0];
    let mut session = OnlineSession::new(u, y, dt, None, options)?;
    let mut squared = 0.0;
    for k in 0..estimation.len() {
        let (uk, yk) = (estimation.inputs[0][k], estimation.outputs[0][k]);
        let estimate = session.update(estimation.t[k], &[uk], &[yk])?[0];
        squared += (estimate - yk).powi(2);
    }
    let model = session.freeze()?; // an OnlineModel: model.json's, `rhonn predict` runs it
    println!(
        "in a loop: {} V RMS one-step error while learning; frozen: {:?}",
        sig((squared / estimation.len() as f64).sqrt(), 4),
        model.model.structure
    );
    Ok(())
}
