//! Learn the cascaded tanks from estimation.csv with the shipped structure and run it
//! free on validation.csv, as `rhonn fit` + `rhonn predict` do:
//! `cargo run --release -p rhonn-report --example fit_tanks [DATA_DIR]`
//! (default `data/cascaded-tanks`).

use rhonn::sysid::{parse_spec_file, predict, train};
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
    let specs = parse_spec_file(&std::fs::read_to_string("models/cascaded-tanks.toml")?)?;
    let (model, summary) = train(&specs, &[estimation], &u, &y)?;
    let fit_rms = summary.training.free_run[0].outputs[0].rms_error;
    println!("free-run RMS error on estimation: {fit_rms:.4} V");
    let p = predict(&model, &validation, None)?; // free run; Some(K): K steps ahead
    println!(
        "free-run RMS error on validation: {:.4} V",
        p.figures[0].rms_error
    );
    Ok(())
}
