//! The `rhonn` command: glue between the command line and the `rhonn` and
//! `rhonn-report` libraries. No physics or numerics here: every command is a library
//! call that a test can make.

mod args;
mod live;
mod progress;

use anyhow::Result;
use args::{Cli, Command};
use clap::Parser;
use rhonn::experiment::preset;
use rhonn_app as commands;
use rhonn_app::campaign;
use std::path::PathBuf;
use std::process::ExitCode;

fn main() -> ExitCode {
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        Err(e) => {
            let hint = columns_hint(&e);
            let _ = e.print();
            if let Some(h) = hint {
                eprintln!("{h}");
            }
            return ExitCode::from(u8::try_from(e.exit_code()).unwrap_or(2));
        }
    };
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

/// For `--inputs` or `--outputs` missing where `--data FILE` is given: the file's columns,
/// so the first command on one's own data needs no second look at the file.
fn columns_hint(e: &clap::Error) -> Option<String> {
    let text = e.to_string();
    if e.kind() != clap::error::ErrorKind::MissingRequiredArgument
        || !(text.contains("--inputs") || text.contains("--outputs"))
    {
        return None;
    }
    // `args_os`: an argument that is not UTF-8 (a file name) must not panic here.
    let args: Vec<String> = std::env::args_os()
        .map(|a| a.to_string_lossy().into_owned())
        .collect();
    let file = args
        .iter()
        .enumerate()
        .find_map(|(i, a)| match a.strip_prefix("--data=") {
            Some(v) => Some(v.to_string()),
            None => (a == "--data").then(|| args.get(i + 1).cloned()).flatten(),
        })?;
    let columns = rhonn_report::csv_header(std::path::Path::new(&file)).ok()?;
    Some(format!(
        "the columns of {file}: {}; give --inputs and --outputs from them, comma-separated",
        columns.join(", ")
    ))
}

fn dispatch(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Run { scenario, out } => commands::run(&scenario, out)?.print(),
        Command::Scenarios => {
            for (name, description) in preset::list() {
                println!("{name:<16} {description}");
            }
        }
        c @ Command::Fit { .. } => cmd_fit_command(c)?,
        c @ Command::Identify { .. } => cmd_identify(c)?,
        Command::Predict {
            model,
            data,
            out,
            steps_ahead,
            init_window,
            time_column,
        } => {
            let busy = progress::Busy::start(format!("predicting {}", data.display()));
            let o = commands::predict(
                &model,
                (&data, time_column.as_deref().unwrap_or("t")),
                &out,
                steps_ahead,
                init_window,
            );
            drop(busy);
            o?.print();
        }
        Command::Benchmark {
            names,
            data_dir,
            out,
            json,
            model,
        } => cmd_benchmark(commands::BenchmarkRequest {
            names,
            data_dir,
            out,
            json,
            model,
        })?,
        Command::Corpus {
            seed,
            systems,
            only,
            out,
            json,
        } => {
            let busy = progress::Busy::start("corpus".into());
            let req = commands::CorpusRequest {
                seed,
                systems,
                only,
                out,
                json,
            };
            let o = commands::corpus(&req, &|line| busy.set_message(line.to_string()));
            drop(busy);
            o?.print();
        }
        Command::Bench {
            scenarios,
            json,
            seconds,
            out,
            compare,
        } => bench(&scenarios, json, seconds, out, compare)?,
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
            cmd_campaign(&scenario, &opts, out, threads)?
        }
        Command::Merge { dirs, out } => {
            commands::campaign_report(&campaign::merge_campaigns(&dirs, &out)?)?.print()
        }
        Command::Reproduce { out } => {
            let root = out.unwrap_or_else(|| PathBuf::from("out"));
            for o in commands::reproduce(&root)? {
                o.print();
            }
        }
        Command::Show { scenario } => print!("{}", commands::show(&scenario)?),
        Command::Report { dir } => commands::report(&dir)?.print(),
    }
    Ok(())
}

/// `rhonn bench`, with one progress line per scenario on a terminal (nothing runs beside
/// the timings).
fn bench(
    scenarios: &[String],
    json: bool,
    seconds: f64,
    out: Option<PathBuf>,
    compare: Option<PathBuf>,
) -> Result<()> {
    let terminal = std::io::IsTerminal::is_terminal(&std::io::stderr());
    let progress = |k: usize, n: usize, name: &str| {
        if terminal {
            eprintln!("timing {name} ({k}/{n}), about {:.0} s", 2.0 * seconds);
        }
    };
    commands::bench(
        scenarios,
        json,
        seconds,
        out.as_deref(),
        compare.as_deref(),
        &progress,
    )?
    .print();
    Ok(())
}

/// `rhonn campaign`: the pump's campaigns (envelopes, merge) or another plant's.
fn cmd_campaign(
    scenario: &str,
    opts: &campaign::CampaignOptions,
    out: Option<PathBuf>,
    threads: Option<usize>,
) -> Result<()> {
    let sc = preset::load_any(scenario)?;
    let name = sc.name.clone();
    let dir = out.unwrap_or_else(|| PathBuf::from("out").join(format!("campaign-{name}")));
    let reporter = progress::Reporter::new(&name);
    let zero = "--threads 0 is not allowed: give 1 or more";
    let outcome = commands::campaign(&sc, opts, &dir, (threads, zero), &|p| reporter.update(p));
    reporter.finish();
    outcome?.print();
    Ok(())
}

/// `rhonn fit`'s selection options, by the rules both doors share (`fit_args`).
fn fit_selection(
    has_model: bool,
    select: Option<args::SelectMode>,
    steps_ahead: Option<usize>,
    budget: Option<f64>,
) -> Result<Option<rhonn::sysid::select::SelectOptions>> {
    let args = commands::fit_args::FitArgs {
        model_given: has_model,
        select: select.map(|m| match m {
            args::SelectMode::Auto => "auto",
            args::SelectMode::None => "none",
        }),
        select_steps_ahead: steps_ahead.map(|k| k as i128),
        budget,
    };
    Ok(args.selection(&commands::fit_args::COMMAND_LINE)?)
}

/// `rhonn identify`: the identification with a spinner.
/// `rhonn fit`: its arguments checked by the one set of rules (`fit_selection`), then fitted.
fn cmd_fit_command(c: Command) -> Result<()> {
    let Command::Fit {
        data,
        inputs,
        outputs,
        resample,
        time_column,
        units,
        model,
        select,
        select_steps_ahead,
        budget,
        out,
        force,
    } = c
    else {
        return Ok(());
    };
    let select = fit_selection(model.is_some(), select, select_steps_ahead, budget)?;
    cmd_fit(commands::FitRequest {
        data,
        inputs,
        outputs,
        model,
        resample_s: resample,
        time_column,
        units,
        select,
        out,
        force,
    })
}

fn cmd_identify(c: Command) -> Result<()> {
    let Command::Identify {
        data,
        stream,
        follow,
        samples,
        every,
        on_error,
        inputs,
        outputs,
        model,
        epochs,
        validate,
        steps_ahead,
        units,
        time_column,
        out,
        force,
    } = c
    else {
        return Ok(());
    };
    if stream || follow.is_some() {
        let req = commands::StreamRequest {
            source: follow
                .as_ref()
                .map_or("standard input".into(), |p| p.display().to_string()),
            inputs,
            outputs,
            time_column,
            model,
            samples,
            every,
            on_error: if on_error == "skip" {
                commands::OnError::Skip
            } else {
                commands::OnError::Stop
            },
            out,
            force,
        };
        return live::identify(&req, follow.as_deref());
    }
    if samples.is_some() || every != 1 || on_error != "stop" {
        anyhow::bail!("--samples, --every and --on-error are for a stream: add --stream or --follow FILE");
    }
    let req = commands::IdentifyRequest {
        data,
        inputs,
        outputs,
        model,
        epochs,
        validate,
        steps_ahead,
        units,
        time_column,
        out,
        force,
    };
    let busy = progress::Busy::start(format!(
        "identifying online on {}",
        rhonn::metrics::count(req.data.len(), "record")
    ));
    let o = commands::identify(&req);
    drop(busy);
    o?.print();
    Ok(())
}

/// `rhonn benchmark`: the benchmark and model being trained on the spinner.
fn cmd_benchmark(req: commands::BenchmarkRequest) -> Result<()> {
    let busy = progress::Busy::start("benchmarks".into());
    let o = commands::benchmark(&req, &|line| busy.set_message(line.to_string()));
    drop(busy);
    o?.print();
    Ok(())
}

/// `rhonn fit`: the fit with the candidate structure being tried on the spinner.
fn cmd_fit(req: commands::FitRequest) -> Result<()> {
    let what = format!("fitting on {}", rhonn::metrics::count(req.data.len(), "record"));
    let busy = progress::Busy::start(what.clone());
    let o = commands::fit_with_progress(&req, &|line| busy.set_message(format!("{what}: {line}")));
    drop(busy);
    o?.print();
    Ok(())
}
