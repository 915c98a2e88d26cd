//! The `rhonn` command: glue between the command line and the `rhonn` and
//! `rhonn-report` libraries. No physics or numerics here: every command is a library
//! call that a test can make.

mod args;
mod campaign;

use anyhow::{Context, Result};
use args::{Cli, Command};
use clap::Parser;
use rhonn::data::Record;
use rhonn::experiment::{preset, run_full, Trace};
use rhonn::sysid::{fit_ensemble, parse_spec_file, FittedModel, Model, ModelSpec};
use rhonn_report::{Series, TimePlot};
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
            model,
            out,
        } => cmd_fit(&data, &inputs, &outputs, model.as_deref(), &out),
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
            let go = || campaign::cmd_campaign(&scenario, &opts, out);
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
        Command::Merge { dirs, out } => campaign::cmd_merge(&dirs, &out),
        Command::Reproduce { out } => {
            let root = out.unwrap_or_else(|| PathBuf::from("out"));
            for name in ["thesis-ch3", "thesis-ch5", "regulated-pi", "control-adaptive"] {
                cmd_run(name, Some(root.join(name)))?;
            }
            Ok(())
        }
        Command::Show { scenario } => {
            let spec = preset::load(&scenario)?;
            match preset::SHIPPED.iter().find(|(n, _)| *n == scenario) {
                Some((_, text)) => print!("{text}"),
                None => print!("{}", spec.to_toml()),
            }
            Ok(())
        }
    }
}

fn read_data(
    paths: &[PathBuf],
    inputs: &[String],
    outputs: &[String],
    min_rows: usize,
) -> Result<Vec<Record>> {
    let mut recs = Vec::new();
    for p in paths {
        let r = rhonn_report::read_record(p, inputs, outputs, min_rows)?;
        let dt = r.median_interval();
        recs.push(r.uniform(dt));
    }
    Ok(recs)
}

fn figures_json(
    m: &Model,
    predict: impl Fn(&Record) -> rhonn::Result<(Vec<Vec<f64>>, usize)>,
    recs: &[Record],
) -> Result<serde_json::Value> {
    let per = recs
        .iter()
        .map(|r| {
            let (p, first) = predict(r)?;
            let figures = m.figures(r, &p, first);
            rhonn::sysid::ensure_finite_figures(&figures, &r.source)?;
            Ok(serde_json::json!({ "data": r.source, "outputs": figures }))
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(serde_json::Value::Array(per))
}

fn cmd_fit(
    data: &[PathBuf],
    inputs: &[String],
    outputs: &[String],
    model: Option<&Path>,
    out: &Path,
) -> Result<()> {
    let specs: Vec<ModelSpec> = match model {
        None => vec![ModelSpec::default()],
        Some(p) => {
            let text = std::fs::read_to_string(p).with_context(|| format!("cannot read {}", p.display()))?;
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
    let recs = read_data(data, inputs, outputs, max_lag + 2)?;
    let fitted = fit_ensemble(&specs, &recs, inputs, outputs)?;
    let spec = &specs[0];
    let m = &fitted.model;
    let mut summary = serde_json::json!({
        "rhonn_version": env!("CARGO_PKG_VERSION"),
        "model": m.spec,
        "features": m.n_features(),
        "high_order_terms": m.terms.len(),
        "sample_time_s": m.sample_time_s,
        "training": {
            "one_step": figures_json(m, |r| fitted.predict(r, Some(1)), &recs)?,
            "free_run": figures_json(m, |r| fitted.predict(r, None), &recs)?,
        },
    });
    if !fitted.members.is_empty() {
        // An ensemble: every member's structure and size; the figures are the mean's.
        summary["members"] = fitted
            .all_members()
            .map(|m| {
                serde_json::json!({
                    "model": m.spec,
                    "features": m.n_features(),
                    "high_order_terms": m.terms.len(),
                })
            })
            .collect();
    }
    if let Some(b) = &fitted.baseline {
        summary["baseline_arx"] = serde_json::json!({
            "features": b.n_features(),
            "one_step": figures_json(b, |r| b.predict(r, Some(1)), &recs)?,
            "free_run": figures_json(b, |r| b.predict(r, None), &recs)?,
        });
    }
    let mut set = rhonn_report::OutputSet::new(out)?;
    set.write("model.json", |w| {
        serde_json::to_writer_pretty(&mut *w, &fitted).map_err(std::io::Error::other)?;
        writeln!(w)
    })?;
    set.write("summary.json", |w| {
        serde_json::to_writer_pretty(&mut *w, &summary).map_err(std::io::Error::other)?;
        writeln!(w)
    })?;
    let files = set.commit()?;
    if fitted.members.is_empty() {
        println!(
            "fitted a {:?} model with {} features per output on {} record(s)",
            spec.kind,
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
    print_training(&summary["training"]["free_run"], "free run (training data)");
    if fitted.baseline.is_some() {
        print_training(&summary["baseline_arx"]["free_run"], "ARX baseline, free run");
    }
    for f in files {
        println!("  wrote {}", f.display());
    }
    Ok(())
}

fn print_training(v: &serde_json::Value, label: &str) {
    for rec in v.as_array().into_iter().flatten() {
        for o in rec["outputs"].as_array().into_iter().flatten() {
            println!(
                "  {label}: {} {}: rms error {:.4}, fit {:.1} %",
                rec["data"].as_str().unwrap_or(""),
                o["output"].as_str().unwrap_or(""),
                o["rms_error"].as_f64().unwrap_or(f64::NAN),
                o["fit_percent"].as_f64().unwrap_or(f64::NAN)
            );
        }
    }
}

fn cmd_predict(model: &Path, data: &Path, out: &Path, steps: Option<usize>) -> Result<()> {
    let text = std::fs::read_to_string(model).with_context(|| format!("cannot read {}", model.display()))?;
    let fitted: FittedModel = serde_json::from_str(&text)
        .map_err(|e| anyhow::anyhow!("{} is not a model written by `rhonn fit`: {e}", model.display()))?;
    if steps == Some(0) {
        anyhow::bail!("--steps-ahead 0 is not allowed: give K >= 1, or leave it out for a free run");
    }
    fitted
        .validate()
        .with_context(|| format!("{} is not a valid model", model.display()))?;
    let m = &fitted.model;
    let recs = read_data(
        &[data.to_path_buf()],
        &m.inputs,
        &m.outputs,
        fitted.max_lag() + steps.unwrap_or(1) + 1,
    )?;
    // The model's lags are in its own samples: data sampled otherwise is put on the
    // model's grid (inputs held, outputs interpolated) and said so.
    let dt = recs[0].median_interval();
    let resampled;
    let r = if (dt - m.sample_time_s).abs() > 1e-6 * m.sample_time_s {
        resampled = recs[0].uniform(m.sample_time_s);
        let need = fitted.max_lag() + steps.unwrap_or(1) + 1;
        if resampled.len() < need {
            anyhow::bail!(
                "{}: {} samples on the model's {} s grid, the model needs at least {need}",
                data.display(),
                resampled.len(),
                m.sample_time_s
            );
        }
        // Intervals read off decimal times carry float noise: shown to the nanosecond.
        let ns = |v: f64| (v * 1e9).round() / 1e9;
        eprintln!(
            "note: {} is sampled every {} s; predicting on the model's grid of {} s ({} samples)",
            data.display(),
            ns(dt),
            ns(m.sample_time_s),
            resampled.len()
        );
        &resampled
    } else {
        &recs[0]
    };
    let (p, first) = fitted.predict(r, steps)?;
    let figs = m.figures(r, &p, first);
    rhonn::sysid::ensure_finite_figures(&figs, &r.source)?;
    let base = match &fitted.baseline {
        Some(b) => {
            let (pb, fb) = b.predict(r, steps)?;
            let f = b.figures(r, &pb, fb);
            rhonn::sysid::ensure_finite_figures(&f, &format!("{} (ARX baseline)", r.source))?;
            Some((pb, f))
        }
        None => None,
    };
    let mut trace = rhonn::experiment::Trace::default();
    let col = |name: String, values: Vec<f64>| rhonn::experiment::Column {
        name,
        unit: "",
        values,
    };
    trace.columns.push(col("t".into(), r.t.clone()));
    for (j, name) in m.outputs.iter().enumerate() {
        trace.columns.push(col(name.clone(), r.outputs[j].clone()));
        trace.columns.push(col(format!("{name}_hat"), p[j].clone()));
        if let Some((pb, _)) = &base {
            trace.columns.push(col(format!("{name}_hat_arx"), pb[j].clone()));
        }
    }
    let mode = match steps {
        None => "free run".to_string(),
        Some(k) => format!("{k} step(s) ahead"),
    };
    let summary = serde_json::json!({
        "rhonn_version": env!("CARGO_PKG_VERSION"),
        "model": model.display().to_string(),
        "data": r.source,
        "mode": mode,
        "steps_ahead": steps,
        "outputs": figs,
        "baseline_arx": base.as_ref().map(|(_, f)| f),
    });
    let plots: Vec<TimePlot> = m
        .outputs
        .iter()
        .enumerate()
        .map(|(j, name)| {
            // Columns rhonn writes in SI are plotted in display units; others as they are.
            let (to_display, y_label): (ToDisplay, String) = match display_unit(name) {
                Some((f, unit)) => (f, format!("{name} [{unit}]")),
                None => (|v| v, name.clone()),
            };
            let scaled = |v: &[f64]| v.iter().map(|&x| to_display(x)).collect::<Vec<f64>>();
            let mut series = vec![
                Series {
                    label: name.clone(),
                    y: scaled(&r.outputs[j]),
                    dashed: false,
                },
                Series {
                    label: format!("{name}_hat ({mode})"),
                    y: scaled(&p[j]),
                    dashed: true,
                },
            ];
            if let Some((pb, _)) = &base {
                series.push(Series {
                    label: "ARX baseline".into(),
                    y: scaled(&pb[j]),
                    dashed: true,
                });
            }
            TimePlot {
                title: format!("{name}: measured and predicted, {mode}"),
                y_label,
                t: r.t.clone(),
                series,
            }
        })
        .collect();
    let svg = TimePlot::render(&plots, 900, 380);
    let mut set = rhonn_report::OutputSet::new(out)?;
    set.write("prediction.csv", |w| rhonn_report::write_trace_csv(w, &trace))?;
    set.write("summary.json", |w| {
        serde_json::to_writer_pretty(&mut *w, &summary).map_err(std::io::Error::other)?;
        writeln!(w)
    })?;
    set.write("prediction.svg", |w| w.write_all(svg.as_bytes()))?;
    let files = set.commit()?;
    for (j, f) in figs.iter().enumerate() {
        print!(
            "{} ({mode}): rms error {:.4}, fit {:.1} %, nrmse {:.4}",
            f.output, f.rms_error, f.fit_percent, f.nrmse
        );
        if let Some((_, fb)) = &base {
            print!(
                "; ARX baseline: rms error {:.4}, fit {:.1} %",
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

fn cmd_bench(names: &[String], json: bool, seconds: f64) -> Result<()> {
    if !(seconds.is_finite() && seconds > 0.0 && seconds <= 3600.0) {
        anyhow::bail!("--seconds {seconds} is not allowed: give a time in (0, 3600] s");
    }
    let default = ["thesis-ch3", "thesis-ch5", "regulated-pi", "control-adaptive"].map(String::from);
    let names: &[String] = if names.is_empty() { &default } else { names };
    let mut all = Vec::new();
    for name in names {
        let sc = preset::load(name)?.check()?;
        let b = rhonn::experiment::bench(&sc, std::time::Duration::from_secs_f64(seconds))?;
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
                b.rhs_evaluations,
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

fn cmd_run(scenario: &str, out: Option<PathBuf>) -> Result<()> {
    let spec = preset::load(scenario)?;
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

/// A conversion from SI to a display unit.
type ToDisplay = fn(f64) -> f64;

/// The display unit of a column `rhonn run` writes in SI (`trajectory.csv`): pressures in
/// Pa are shown in MPa, strokes in m in mm, flows in m^3/s in dm^3/s. None for any other
/// column (measured data keeps its own units).
fn display_unit(column: &str) -> Option<(ToDisplay, &'static str)> {
    use rhonn::units::{dm3_s, mm, mpa};
    let base = column.strip_suffix("_pi").unwrap_or(column);
    match base {
        "p_line" | "p_meas" | "p_ref" | "p_line_model" => Some((mpa, "MPa")),
        "stroke" | "stroke_ref" => Some((mm, "mm")),
        "demand" => Some((dm3_s, "dm^3/s")),
        _ => None,
    }
}
