//! The `rhonn` command: glue between the command line and the `rhonn` and
//! `rhonn-report` libraries. No physics or numerics here: every command is a library
//! call that a test can make.

mod args;
mod identify;
mod progress;

use anyhow::{Context, Result};
use args::{Cli, Command};
use clap::Parser;
use rhonn::data::Record;
use rhonn::experiment::{preset, run_full, Trace};
use rhonn::sysid::{parse_spec_file, FittedModel, ModelSpec, RecordFigures};
use rhonn_report::campaign;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

fn main() -> ExitCode {
    let cli = Cli::parse();
    match dispatch(cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            for cause in e.chain().skip(1) {
                eprintln!("  caused by: {cause}");
            }
            ExitCode::from(2)
        }
    }
}

fn dispatch(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Run { scenario, out } => cmd_run(&scenario, out),
        Command::Scenarios => {
            for (name, description) in preset::list() {
                println!("{name:<16} {description}");
            }
            Ok(())
        }
        Command::Fit {
            data,
            inputs,
            outputs,
            resample,
            units,
            model,
            out,
        } => {
            let opts = FitOptions {
                resample_s: resample,
                units: parse_units(&units, &inputs, &outputs)?,
            };
            cmd_fit(&data, &inputs, &outputs, model.as_deref(), &out, opts)
        }
        Command::Identify {
            data,
            inputs,
            outputs,
            model,
            epochs,
            validate,
            steps_ahead,
            out,
        } => identify::cmd_identify(identify::IdentifyArgs {
            data: &data,
            inputs: &inputs,
            outputs: &outputs,
            model: model.as_deref(),
            epochs,
            validate: &validate,
            steps_ahead,
            out: &out,
        }),
        Command::Predict {
            model,
            data,
            out,
            steps_ahead,
        } => cmd_predict(&model, &data, &out, steps_ahead),
        Command::Bench {
            scenarios,
            json,
            seconds,
        } => cmd_bench(&scenarios, json, seconds),
        Command::Campaign {
            scenario,
            runs,
            seed,
            shard,
            corners,
            envelope_runs,
            threads,
            out,
        } => {
            let shard = campaign::parse_shard(&shard)?;
            let opts = campaign::CampaignOptions {
                runs,
                seed,
                shard,
                corners,
                envelope_runs,
            };
            let go = || cmd_campaign(&scenario, &opts, out);
            match threads {
                Some(0) => anyhow::bail!("--threads 0 is not allowed: give 1 or more"),
                Some(n) => rayon::ThreadPoolBuilder::new()
                    .num_threads(n)
                    .build()
                    .context("cannot start the worker threads")?
                    .install(go),
                None => go(),
            }
        }
        Command::Merge { dirs, out } => report_campaign(campaign::merge_campaigns(&dirs, &out)?),
        Command::Reproduce { out } => {
            let root = out.unwrap_or_else(|| PathBuf::from("out"));
            for name in ["thesis-ch3", "thesis-ch5", "regulated-pi", "control-adaptive"] {
                cmd_run(name, Some(root.join(name)))?;
            }
            Ok(())
        }
        Command::Show { scenario } => {
            let spec = preset::load_any(&scenario)?;
            match (preset::SHIPPED.iter().find(|(n, _)| *n == scenario), spec) {
                (Some((_, text)), _) => print!("{text}"),
                (None, preset::AnyScenario::Pump(spec)) => print!("{}", spec.to_toml()),
                (None, preset::AnyScenario::Plant(_)) => print!("{}", std::fs::read_to_string(&scenario)?),
            }
            Ok(())
        }
    }
}

/// What `rhonn fit` takes besides the data and the structure.
struct FitOptions {
    /// `--resample`: the uniform grid's interval \[s\] (None: each record's median).
    resample_s: Option<f64>,
    /// `--units`: unit by column.
    units: std::collections::BTreeMap<String, String>,
}

/// `--units COL=UNIT,...`: every column named must be an input or an output.
fn parse_units(
    pairs: &[String],
    inputs: &[String],
    outputs: &[String],
) -> Result<std::collections::BTreeMap<String, String>> {
    let mut map = std::collections::BTreeMap::new();
    for p in pairs {
        let (col, unit) = p.split_once('=').filter(|(c, u)| !c.trim().is_empty() && !u.trim().is_empty()).ok_or_else(|| {
            anyhow::anyhow!("--units `{p}` is not allowed: give COLUMN=UNIT pairs separated by commas, e.g. --units u=V,y=mm")
        })?;
        let col = col.trim();
        if !inputs.iter().chain(outputs).any(|c| c == col) {
            anyhow::bail!(
                "--units names column `{col}`, which is not among the inputs and outputs ({})",
                inputs
                    .iter()
                    .chain(outputs)
                    .cloned()
                    .collect::<Vec<_>>()
                    .join(", ")
            );
        }
        map.insert(col.to_string(), unit.trim().to_string());
    }
    Ok(map)
}

fn read_data(
    paths: &[PathBuf],
    inputs: &[String],
    outputs: &[String],
    min_rows: usize,
    resample_s: Option<f64>,
) -> Result<Vec<Record>> {
    if let Some(dt) = resample_s {
        if !(dt.is_finite() && dt > 0.0) {
            anyhow::bail!("--resample {dt} is not allowed: give a sample time in seconds, finite and > 0");
        }
    }
    let mut recs = Vec::new();
    for p in paths {
        let r = rhonn_report::read_record(p, inputs, outputs, min_rows)?;
        let dt = resample_s.unwrap_or_else(|| r.median_interval());
        let u = r.uniform(dt);
        if u.len() < min_rows {
            anyhow::bail!(
                "{}: {} samples on the grid of {dt} s, the model needs at least {min_rows}: give a shorter --resample",
                p.display(),
                u.len()
            );
        }
        recs.push(u);
    }
    Ok(recs)
}

fn cmd_fit(
    data: &[PathBuf],
    inputs: &[String],
    outputs: &[String],
    model: Option<&Path>,
    out: &Path,
    opts: FitOptions,
) -> Result<()> {
    let specs: Vec<ModelSpec> = match model {
        None => vec![ModelSpec::default()],
        Some(p) => {
            let text = std::fs::read_to_string(p).map_err(|e| {
                anyhow::anyhow!(
                    "cannot read {}: {}",
                    p.display(),
                    rhonn::error::path_problem(p, &e)
                )
            })?;
            parse_spec_file(&text)
                .map_err(|e| anyhow::anyhow!("cannot read model spec {}: {e}", p.display()))?
        }
    };
    for (k, spec) in specs.iter().enumerate() {
        spec.check().with_context(|| {
            if specs.len() > 1 {
                format!("in members[{k}]")
            } else {
                "in the model spec".to_string()
            }
        })?;
    }
    let max_lag = specs.iter().map(|s| s.max_lag()).max().unwrap_or(0);
    let recs = read_data(data, inputs, outputs, max_lag + 2, opts.resample_s)?;
    let sample_s = recs.first().map_or(0.0, |r| r.median_interval());
    for w in rhonn::sysid::data_warnings(&recs, inputs, outputs, max_lag, sample_s, "--resample") {
        eprintln!("warning: {w}");
    }
    let busy = progress::Busy::start(format!("fitting on {} record(s)", recs.len()));
    let (mut fitted, summary) = rhonn::sysid::train(&specs, &recs, inputs, outputs)?;
    drop(busy);
    fitted.units = opts.units;
    let files = rhonn_report::write_fit(out, &fitted, &summary)?;
    if fitted.members.is_empty() {
        println!(
            "fitted a {:?} model with {} features per output on {} record(s)",
            specs[0].kind,
            fitted.model.n_features(),
            recs.len()
        );
    } else {
        println!(
            "fitted an ensemble of {} models ({} features per output in all) on {} record(s)",
            1 + fitted.members.len(),
            fitted.all_members().map(|m| m.n_features()).sum::<usize>(),
            recs.len()
        );
    }
    print_training(
        &summary.training.free_run,
        "free run (training data)",
        &fitted.units,
    );
    if let Some(b) = &summary.baseline_arx {
        print_training(&b.free_run, "ARX baseline, free run", &fitted.units);
    }
    for f in files {
        println!("  wrote {}", f.display());
    }
    Ok(())
}

/// " V" for a column with a unit, else "".
fn unit_of(units: &std::collections::BTreeMap<String, String>, col: &str) -> String {
    units.get(col).map_or(String::new(), |u| format!(" {u}"))
}

fn print_training(
    figures: &[RecordFigures],
    label: &str,
    units: &std::collections::BTreeMap<String, String>,
) {
    for rec in figures {
        for o in &rec.outputs {
            println!(
                "  {label}: {} {}: rms error {:.4}{}, fit {:.1} %",
                rec.data,
                o.output,
                o.rms_error,
                unit_of(units, &o.output),
                o.fit_percent
            );
        }
    }
}

fn cmd_predict(model: &Path, data: &Path, out: &Path, steps: Option<usize>) -> Result<()> {
    let text = std::fs::read_to_string(model).map_err(|e| {
        anyhow::anyhow!(
            "cannot read {}: {}",
            model.display(),
            rhonn::error::path_problem(model, &e)
        )
    })?;
    if steps == Some(0) {
        anyhow::bail!("--steps-ahead 0 is not allowed: give K >= 1, or leave it out for a free run");
    }
    let kind = serde_json::from_str::<serde_json::Value>(&text)
        .ok()
        .and_then(|v| v.get("kind").and_then(|k| k.as_str()).map(str::to_string));
    if kind.as_deref() == Some(rhonn::ident::OnlineModel::KIND) {
        return identify::cmd_predict_online(model, &text, data, out, steps);
    }
    let fitted: FittedModel = serde_json::from_str(&text)
        .map_err(|e| anyhow::anyhow!("{} is not a model written by `rhonn fit`: {e}", model.display()))?;
    fitted
        .validate()
        .with_context(|| format!("{} is not a valid model", model.display()))?;
    let m = &fitted.model;
    let recs = read_data(
        &[data.to_path_buf()],
        &m.inputs,
        &m.outputs,
        rhonn::sysid::samples_needed(&fitted, steps),
        None,
    )?;
    let busy = progress::Busy::start(format!("predicting {}", data.display()));
    let p = rhonn::sysid::predict(&fitted, &recs[0], steps)?;
    drop(busy);
    if let Some(dt) = p.resampled_from_s {
        // Intervals read off decimal times carry float noise: shown to the nanosecond.
        let ns = |v: f64| (v * 1e9).round() / 1e9;
        eprintln!(
            "note: {} is sampled every {} s; predicting on the model's grid of {} s ({} samples)",
            data.display(),
            ns(dt),
            ns(m.sample_time_s),
            p.record.len()
        );
    }
    let files = rhonn_report::write_prediction(out, &fitted, &p, &model.display().to_string())?;
    let mode = p.mode();
    for (j, f) in p.figures.iter().enumerate() {
        let unit = unit_of(&fitted.units, &f.output);
        print!(
            "{} ({mode}): rms error {:.4}{unit}, fit {:.1} %, nrmse {:.4}",
            f.output, f.rms_error, f.fit_percent, f.nrmse
        );
        if let Some((_, fb)) = &p.baseline {
            print!(
                "; ARX baseline: rms error {:.4}{unit}, fit {:.1} %",
                fb[j].rms_error, fb[j].fit_percent
            );
        }
        println!();
    }
    for f in files {
        println!("  wrote {}", f.display());
    }
    Ok(())
}

fn cmd_campaign(scenario: &str, opts: &campaign::CampaignOptions, out: Option<PathBuf>) -> Result<()> {
    let spec = match preset::load_any(scenario)? {
        preset::AnyScenario::Pump(spec) => spec,
        preset::AnyScenario::Plant(spec) => {
            let dir = out.unwrap_or_else(|| PathBuf::from("out").join(format!("campaign-{}", spec.name)));
            let reporter = progress::Reporter::new(&spec.name);
            let outcome =
                rhonn_report::plant_campaign::run_plant_campaign(&spec, opts, &dir, &|p| reporter.update(p));
            reporter.finish();
            return report_campaign(outcome?);
        }
    };
    let dir = out.unwrap_or_else(|| PathBuf::from("out").join(format!("campaign-{}", spec.name)));
    let reporter = progress::Reporter::new(&spec.name);
    let outcome = campaign::run_campaign(&spec, opts, &dir, &|p| reporter.update(p));
    reporter.finish();
    report_campaign(outcome?)
}

fn report_campaign(o: campaign::CampaignOutcome) -> Result<()> {
    for n in &o.notes {
        eprintln!("{n}");
    }
    if o.already_complete {
        println!("campaign already complete in {}", o.dir.display());
    } else {
        println!(
            "campaign {}: {} runs, {} failed; wrote {}",
            o.scenario,
            o.runs,
            o.failed,
            o.dir.join("runs.csv").display()
        );
    }
    Ok(())
}

fn cmd_bench(names: &[String], json: bool, seconds: f64) -> Result<()> {
    if !(seconds.is_finite() && seconds > 0.0 && seconds <= 3600.0) {
        anyhow::bail!("--seconds {seconds} is not allowed: give a time in (0, 3600] s");
    }
    let default = ["thesis-ch3", "thesis-ch5", "regulated-pi", "control-adaptive"].map(String::from);
    let names: &[String] = if names.is_empty() { &default } else { names };
    let mut all = Vec::new();
    for name in names {
        let budget = std::time::Duration::from_secs_f64(seconds);
        let b = match preset::load_any(name)? {
            preset::AnyScenario::Pump(spec) => rhonn::experiment::bench(&spec.check()?, budget)?,
            preset::AnyScenario::Plant(spec) => rhonn::experiment::bench_plant(&spec, budget)?,
        };
        if !json {
            if all.is_empty() {
                println!(
                    "{:<16} {:>14} {:>16} {:>22}",
                    "scenario", "median [ms]", "rhs evaluations", "runs/s on all cores"
                );
            }
            println!(
                "{:<16} {:>14.4} {:>16} {:>15.0} ({} threads)",
                b.scenario,
                b.median_s * 1e3,
                b.rhs_evaluations.map_or("-".to_string(), |n| n.to_string()),
                b.runs_per_s_all_cores,
                b.threads
            );
        }
        all.push(b);
    }
    if json {
        println!("{}", serde_json::to_string_pretty(&all)?);
    }
    Ok(())
}

/// `rhonn run` for a scenario of a plant other than the pump.
fn cmd_run_plant(spec: &rhonn::experiment::PlantScenarioSpec, out: Option<PathBuf>) -> Result<()> {
    let dir = out.unwrap_or_else(|| PathBuf::from("out").join(&spec.name));
    let output = rhonn::experiment::run_plant_scenario(spec, None)?;
    let files = rhonn_report::write_plant_run(&dir, &output).with_context(|| {
        format!(
            "scenario `{}` ran, but its outputs could not be written",
            spec.name
        )
    })?;
    let s = &output.summary;
    println!(
        "{}: {} s simulated, plant {}",
        spec.name, spec.duration_s, s.plant
    );
    if let Some(figs) = &s.identification {
        for f in figs {
            print!(
                "  {}: online (second half) rms error {:.3} {}, fit {:.1} %",
                f.state, f.training_rms_error, f.unit, f.training_fit_percent
            );
            if let (Some(r), Some(p)) = (f.validation_rms_error, f.validation_fit_percent) {
                print!(
                    "; frozen, free run on the validation inputs: rms error {r:.3} {}, fit {p:.1} %",
                    f.unit
                );
            }
            println!();
        }
    }
    if let (Some(c), Some((state, unit))) = (&s.control, s.regulated) {
        for f in c {
            println!(
                "  {:<14} {state}: IAE {:.1} {unit} s, ISE {:.0} {unit}^2 s, final error {:.3} {unit}, input saturated {:.0} s",
                f.controller, f.iae, f.ise, f.final_error, f.time_input_saturated_s
            );
        }
    }
    for f in &s.findings {
        println!("  finding: {f}");
    }
    for f in files {
        println!("  wrote {}", f.display());
    }
    Ok(())
}

fn cmd_run(scenario: &str, out: Option<PathBuf>) -> Result<()> {
    let spec = match preset::load_any(scenario)? {
        preset::AnyScenario::Pump(spec) => spec,
        preset::AnyScenario::Plant(spec) => return cmd_run_plant(&spec, out),
    };
    let sc = spec.check()?;
    for w in &sc.warnings {
        eprintln!("warning: {w}");
    }
    let dir = out.unwrap_or_else(|| PathBuf::from("out").join(&spec.name));
    let mut trace = Trace::default();
    let output = run_full(&sc, &mut trace)?;
    let summary = &output.summary;
    let files = rhonn_report::write_run(&dir, &trace, &output).with_context(|| {
        format!(
            "scenario `{}` ran, but its outputs could not be written",
            spec.name
        )
    })?;
    let f = &summary.figures;
    println!(
        "{}: {} s simulated, {} samples",
        spec.name, f.duration_s, f.samples
    );
    println!(
        "  line pressure: final {:.3} MPa, min {:.3} MPa, max {:.3} MPa; below P_min for {:.3} s ({:.3} s after the first second)",
        f.final_p_line_mpa, f.p_line_min_mpa, f.p_line_max_mpa, f.time_below_p_min_s, f.time_below_p_min_after_1s_s
    );
    println!(
        "  stroke: final {:.4} mm, max {:.4} mm",
        f.final_stroke_mm, f.stroke_max_mm
    );
    if let Some(r) = &f.regulation {
        println!(
            "  regulation: max |p - p_ref| {:.3} MPa ({:.3} MPa from 1 s after each set-point change), ISE {:.3} MPa^2 s, current saturated {:.3} s",
            r.max_abs_deviation_mpa, r.max_abs_deviation_settled_mpa, r.ise_mpa2_s, r.time_current_saturated_s
        );
    }
    if let Some(id) = &summary.identification {
        for line in id.to_string().lines() {
            println!("  {line}");
        }
    }
    if let Some(c) = &summary.control {
        println!(
            "  RHONN adaptive vs PI baseline (kp {} A/MPa, ti {} s) on an identical plant:",
            c.baseline.kp_a_per_mpa, c.baseline.ti_s
        );
        for line in &c.findings {
            println!("    {line}");
        }
        println!(
            "    weights: |W| max {:.1}, |W_1 - centre| max {:.2} within the ball's radius {:.2}, {} projections",
            c.adaptive.w_norm_max, c.adaptive.w1_distance_max, c.adaptive.w1_ball_radius, c.adaptive.projections
        );
    }
    let s = &summary.solver;
    println!(
        "  solver: {} rhs evaluations, {} accepted and {} rejected steps, {} events",
        s.rhs_evaluations, s.accepted_steps, s.rejected_steps, s.events
    );
    for file in files {
        println!("  wrote {}", file.display());
    }
    Ok(())
}
