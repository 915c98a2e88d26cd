//! Command-line arguments. Each command's help says what it writes and in which units.

use clap::{Parser, Subcommand};
use std::path::PathBuf;

/// rhonn: simulate, identify and control a solenoid-controlled variable-displacement
/// pump with Recurrent High-Order Neural Networks.
#[derive(Debug, Parser)]
#[command(name = "rhonn", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Run a scenario and write its trajectory, summary and plots.
    ///
    /// Writes into DIR (default out/<scenario name>), whatever the plant:
    ///   trajectory.csv  header, then one row per output sample, SI units: t [s], the
    ///                   inputs, each state (the pump: p_line [Pa], stroke [m]); a loop
    ///                   adds <output>_ref, <output>_measured (what the controller saw),
    ///                   a cascade's inner set-point and each baseline's columns
    ///                   (_baseline, _second_baseline)
    ///   summary.json    the solver's settings and work, and the figures in display
    ///                   units (the pump: p_line [MPa], stroke [mm]): ranges and the time
    ///                   below the plant's floor (the pump's P_min), each loop's IAE, ISE,
    ///                   deviations, share within 1 % and the input's activity, findings
    ///   states.svg      each state against time (the set-point, each controller, the
    ///                   plant's floor)
    ///   inputs.svg      the inputs against time
    /// With an [identifier] (e.g. thesis-ch5) also:
    ///   trajectory.csv  + <state>_hat (last training epoch)
    ///   weights.json    the trained model: states, inputs, sigmoid, scales, terms,
    ///                   poles, law, weights (SI)
    ///   validation.csv  the frozen model: t [s], <state>, and its estimates (SI)
    ///   summary.json    + per state: RMS error and fit, and over each whole run RMS
    ///                   error, fit, NRMSE, convergence band and time
    ///   errors.svg, validation.svg
    /// Files appear only when all of them are complete. Exit code 2 on any error.
    #[command(verbatim_doc_comment)]
    Run {
        /// A shipped scenario's name (see `rhonn scenarios`) or a path to a TOML file.
        scenario: String,
        /// Output folder.
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
    },
    /// Reproduce the thesis: run thesis-ch3 (the pump, chapter 3), thesis-ch5 (the RHONN
    /// identification, chapter 5), regulated-pi (the PI baseline) and control-adaptive
    /// (RHONN adaptive control against the PI) into DIR/<name>
    /// (default out/), each writing what `rhonn run` writes.
    Reproduce {
        /// Output root.
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
    },
    /// Train a model on measured data (CSV) and write it.
    ///
    /// Each CSV has a header, a time column `t` [s] (uniform or not: a non-uniform file
    /// is put on a uniform grid of its median interval, inputs held, outputs
    /// interpolated) and numeric columns. Several --data files are separate recordings.
    /// Writes into DIR:
    ///   model.json    the model (structure, normalisation, weights: all that
    ///                 `rhonn predict` needs) and its ARX baseline, trained on the same
    ///                 data: the best ARX of the cross-validation folds (with --select
    ///                 none, the ARX of the model's lags)
    ///   summary.json  per output and model: RMS error, fit [%] and NRMSE on the
    ///                 training data, one step ahead and free run; `selection`: the
    ///                 candidate structures' cross-validation errors (--select auto);
    ///                 `parameters`: a `pump` model's parameters by name, SI
    /// Without --model the structure is selected on the training records (--select).
    /// Errors are in the data's units: a column named with its unit (`y_V`, `p_line_pa`)
    /// has it, --units names others. Warnings (on stderr) for a constant input, an input
    /// that is also an output, `t` used as a signal, and data sampled far faster than it
    /// changes (with the --resample value to try).
    /// Exit code 2 on any error, naming file, line, column.
    #[command(verbatim_doc_comment)]
    Fit {
        /// A CSV file (repeat for several recordings).
        #[arg(long = "data", value_name = "FILE.csv", required = true)]
        data: Vec<PathBuf>,
        /// Input columns, comma-separated.
        #[arg(long, value_delimiter = ',', required = true)]
        inputs: Vec<String>,
        /// Output columns, comma-separated.
        #[arg(long, value_delimiter = ',', required = true)]
        outputs: Vec<String>,
        /// Put every record on a uniform grid of this sample time [s] instead of its own
        /// median interval (inputs held, outputs interpolated; no anti-alias filter):
        /// for data sampled much faster than the system moves, as a warning then says.
        #[arg(long, value_name = "SECONDS", allow_negative_numbers = true)]
        resample: Option<f64>,
        /// The column holding the time in seconds (default `t`), e.g. `--time-column time`.
        #[arg(long, value_name = "NAME")]
        time_column: Option<String>,
        /// Units of the columns, as COLUMN=UNIT pairs (e.g. `--units u=V,y=V`): printed
        /// with the errors and kept in model.json for `rhonn predict`. A column whose name
        /// ends in a unit (`_V`, `_mm`, `_pa`, `_mpa`, ...) has it without this.
        #[arg(long, value_delimiter = ',', value_name = "COLUMN=UNIT")]
        units: Vec<String>,
        /// Model structure (TOML: kind = rhonn, arx, cascade, wiener-hammerstein or pump; na, nb, nk, degree,
        /// max_factors, law, ridge, epochs, gain, output_margin, ...; models/ has examples). An ensemble: [[members]] tables, each a
        /// structure; it predicts the mean of its members' predictions. Without it the
        /// structure is selected (--select auto).
        #[arg(long, value_name = "SPEC.toml")]
        model: Option<PathBuf>,
        /// How to choose the structure when no --model is given: `auto` (default):
        /// 3-fold cross-validation over contiguous thirds of the training records, over
        /// ARX, lagged RHONN (least squares and free-run trained, sigmoid or polynomial
        /// terms), for one input and one output Wiener-Hammerstein block structures and,
        /// for one output, continuous-time cascade structures, then the means of the best 2
        /// and of the best 3 (ensembles, judged from the folds' own free runs); the choice is never worse
        /// than the best ARX on the folds (another structure replaces it only when it is
        /// better on every fold), and summary.json's `selection` says by how much. `none`:
        /// a RHONN with na = nb = 2, nk = 1, degree 2, batch least squares.
        #[arg(long, value_name = "auto|none")]
        select: Option<SelectMode>,
        /// Judge the selection K samples ahead instead of in free run.
        #[arg(long, value_name = "K")]
        select_steps_ahead: Option<usize>,
        /// The selection's work budget per candidate, as a multiple of the default: a
        /// candidate whose estimated work on the folds (from the data's size, never the
        /// clock) exceeds it is skipped and said; ARX structures always run [default: 1].
        #[arg(long, value_name = "FACTOR")]
        budget: Option<f64>,
        /// Output folder.
        #[arg(long, value_name = "DIR", required = true)]
        out: PathBuf,
        /// Replace a different model already in --out (without it, that is refused and
        /// nothing is written; the same model again is always fine).
        #[arg(long)]
        force: bool,
    },
    /// Identify a RHONN online from recordings, sample by sample, with the thesis's
    /// stability-proven laws; then freeze it and validate it.
    ///
    /// Without --model the model is picked online: a bank of candidates (recursive ARX,
    /// lagged RHONNs by recursive least squares, the continuous-time neurons and, for
    /// one output and at most 5,000 samples, the cascade) runs over the records in one
    /// pass and the one with the lowest prequential free-run error wins (each sample
    /// predicted before it is learned; summary.json's `selection`). With --validate, an
    /// offline ARX (lags by cross-validation on the records) runs free beside it.
    ///
    /// The identifier runs over the --data records in time order (inputs held between
    /// samples, or linear with `inputs = "linear"` in the model spec), series-parallel on
    /// the measured outputs; unmeasured states are stood in for by filtered inputs
    /// (`filters_s`). Model spec (TOML, every key optional): law (a [law] table),
    /// gain, degree, max_factors, a_per_s, filters_s, inputs, epochs,
    /// freeze_after_s, dead_zone, output_margin, output_terms. Or
    /// `structure = "lagged"` with `lags = { na, nb, nk, output_lag_start,
    /// nonlinear_lags }`: a discrete-time RHONN of lagged measurements (rhonn fit's
    /// lagged model) learned sample by sample by recursive least squares
    /// (models/tanks-online-lagged.toml). Or `structure = "cascade"` with `cascade = {
    /// neurons, starts, measurement_var, pass_var, ... }`: rhonn fit's continuous-time
    /// cascade with hidden neurons (one output), its parameters and hidden levels
    /// learned by extended Kalman filters from several starts; use epochs = 4 or more
    /// (models/tanks-online-cascade.toml). Writes into DIR:
    ///   estimate.csv    record, t, per output <name> and <name>_hat (final pass)
    ///   weights.csv     record, t, the weight norm of each neuron, error_energy,
    ///                   every weight w_<output>_<k> when there are at most 50
    ///   validation.csv  with --validate: <name>, <name>_free_run, <name>_<K>_ahead
    ///   summary.json    online RMS error and fit over the last half, convergence
    ///                   time into a band, weight norms per pass, validation, findings
    ///   model.json      the frozen model (settings, scaling, weights)
    ///   estimate.svg, weights.svg, validation.svg
    #[command(verbatim_doc_comment)]
    Identify {
        /// A CSV file (repeat for several recordings, identified in this order).
        #[arg(long = "data", value_name = "FILE.csv", required_unless_present_any = ["stream", "follow"])]
        data: Vec<PathBuf>,
        /// Learn a live stream from standard input instead (a header line, then one sample
        /// a line): prints `t`, each output's estimate and its running prequential RMS error;
        /// at the end of the input or on Ctrl-C, freezes and writes model.json and summary.json.
        #[arg(long, conflicts_with_all = ["data", "validate", "epochs", "steps_ahead"])]
        stream: bool,
        /// As --stream, from a CSV file that grows (a logger's): waits for new lines until
        /// Ctrl-C.
        #[arg(long, value_name = "FILE.csv", conflicts_with_all = ["data", "stream", "validate", "epochs", "steps_ahead"])]
        follow: Option<PathBuf>,
        /// With --stream or --follow and no --model: the stream's length, when known; the
        /// bank then judges it as --data judges a file of that length (the same model).
        #[arg(long, value_name = "N")]
        samples: Option<usize>,
        /// With --stream or --follow: print a line every N samples (default 1).
        #[arg(long, value_name = "N", default_value_t = 1, value_parser = at_least_one)]
        every: usize,
        /// With --stream or --follow: what a malformed line does; `stop` saves the model
        /// learned so far and exits with an error naming the line, `skip` says so and goes on.
        #[arg(long, value_name = "stop|skip", default_value = "stop", value_parser = ["stop", "skip"])]
        on_error: String,
        /// Input columns, comma-separated.
        #[arg(long, value_delimiter = ',', required = true)]
        inputs: Vec<String>,
        /// Output columns, comma-separated.
        #[arg(long, value_delimiter = ',', required = true)]
        outputs: Vec<String>,
        /// Model spec (TOML); without it the bank picks the model online.
        #[arg(long, value_name = "SPEC.toml")]
        model: Option<PathBuf>,
        /// Passes over the records (overrides the spec's `epochs`).
        #[arg(long)]
        epochs: Option<usize>,
        /// A CSV file to validate the frozen model on (repeat): free run, and K samples
        /// ahead with --steps-ahead.
        #[arg(long, value_name = "FILE.csv")]
        validate: Vec<PathBuf>,
        /// Also predict K samples ahead on the validation records.
        #[arg(long, value_name = "K")]
        steps_ahead: Option<usize>,
        /// The column holding the time in seconds (default `t`), e.g. `--time-column time`.
        #[arg(long, value_name = "NAME")]
        time_column: Option<String>,
        /// Units of the columns, as COLUMN=UNIT pairs (e.g. `--units u=V,y=V`), as for
        /// `rhonn fit`: printed with the figures and kept in summary.json.
        #[arg(long, value_delimiter = ',', value_name = "COLUMN=UNIT")]
        units: Vec<String>,
        /// Output folder.
        #[arg(long, value_name = "DIR", required = true)]
        out: PathBuf,
        /// Replace a different model.json already in --out (without it, that is refused
        /// and nothing is written).
        #[arg(long)]
        force: bool,
    },
    /// Run a trained model on data and compare.
    ///
    /// Free run by default (the model sees the inputs and the first few measured
    /// outputs only); --steps-ahead K predicts sample k + K from the measurements up to
    /// k (1: one-step tracking). Writes into DIR:
    ///   prediction.csv  t, then per output <name>, <name>_hat and (with a baseline)
    ///                   <name>_hat_arx; the first samples, which no model can
    ///                   predict, repeat the measurement
    ///   summary.json    per output: rms_error, fit_percent, nrmse, for the model and
    ///                   the baseline
    ///   prediction.svg  measured and predicted against time
    #[command(verbatim_doc_comment)]
    Predict {
        /// model.json written by `rhonn fit` or `rhonn identify`.
        #[arg(long, value_name = "FILE")]
        model: PathBuf,
        /// A CSV file with the model's input and output columns.
        #[arg(long, value_name = "FILE.csv")]
        data: PathBuf,
        /// Output folder.
        #[arg(long, value_name = "DIR")]
        out: PathBuf,
        /// Predict K samples ahead instead of a free run.
        #[arg(long, value_name = "K")]
        steps_ahead: Option<usize>,
        /// Free run seeing only the first N measured outputs (a benchmark's
        /// state-initialisation window, e.g. 4 for the coupled drives): a model that needs
        /// more past outputs gets the first sample held before the data; the model and its
        /// baseline are scored from sample N on.
        #[arg(long, value_name = "N")]
        init_window: Option<usize>,
        /// The column holding the time in seconds (default `t`), e.g. `--time-column time`.
        #[arg(long, value_name = "NAME")]
        time_column: Option<String>,
    },
    /// The field's standard benchmarks under their published protocol, beside the
    /// published figures.
    ///
    /// For each benchmark of data/benchmarks/ (Silverbox, Wiener-Hammerstein 2009,
    /// Bouc-Wen, coupled electric drives, cascaded tanks, four DaISy sets): rhonn fit's
    /// default model, rhonn identify's default online model and an ARX of lags by
    /// cross-validation, each trained on train only, run free on every test set from its
    /// start-up window; RMS error in the data's units. Writes into DIR:
    ///   summary.json, benchmark.csv   the table (one row per test set and output)
    ///   NAME/model.json               rhonn fit's model (runs with `rhonn predict`)
    ///   NAME/online/model.json        the online model, frozen
    ///   NAME/free_run_K.csv, .svg     test set K: measured and the three free runs
    ///   NAME/residuals_K.svg          the fit model's residuals on test set K
    ///   report.html, NAME/report.html
    #[command(verbatim_doc_comment)]
    Benchmark {
        /// Benchmark names (folders of --data-dir; default: every one).
        names: Vec<String>,
        /// The benchmarks' folder.
        #[arg(long, value_name = "DIR", default_value = "data/benchmarks")]
        data_dir: PathBuf,
        /// Output folder.
        #[arg(long, value_name = "DIR", default_value = "out/benchmark")]
        out: PathBuf,
        /// Print the table as JSON (summary.json's text) instead of text.
        #[arg(long)]
        json: bool,
        /// Train this model spec (as `rhonn fit --model`) in place of the default
        /// selection's choice; the table's fit column is then `rhonn fit (--model)`.
        #[arg(long, value_name = "SPEC.toml")]
        model: Option<PathBuf>,
    },
    /// Judge rhonn fit's default on simulated systems nobody tuned it on.
    ///
    /// The unseen-systems corpus: systems of 13 families (a closed-loop integrator with
    /// friction, fast sampling, saturation, dead zone, backlash, hysteresis, Wiener,
    /// Hammerstein, bilinear, input delay, two outputs of different nature, short
    /// records, slow drifts) drawn from --seed, each trained on a multisine or filtered
    /// noise and tested on a new record (every other draw of a family on steps or
    /// pulses). Per system and output: rhonn fit's default free-run RMS error on test over
    /// an ARX's (lags by cross-validation on train), then the median and the worst. With
    /// --out DIR: DIR/corpus.csv (a row per system and output), DIR/summary.json,
    /// DIR/report.html, and per system DIR/SYSTEM/: train_0.csv, test_0.csv (its
    /// records), model.json and online/model.json (the models scored: `rhonn predict`
    /// runs them), summary.json (why each was chosen: every candidate's scores).
    #[command(verbatim_doc_comment)]
    Corpus {
        /// The corpus's seed: judge a change to a default on a seed it was not designed with.
        #[arg(long, default_value_t = 1)]
        seed: u64,
        /// Systems drawn (cycling through the 13 families).
        #[arg(long, default_value_t = 40)]
        systems: usize,
        /// Only these systems (indices below --systems, comma-separated).
        #[arg(long, value_delimiter = ',', value_name = "I,J,...")]
        only: Vec<usize>,
        /// Output folder (default: print only).
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
        /// Print summary.json's text instead of the table.
        #[arg(long)]
        json: bool,
    },
    /// Time whole runs without I/O and print a table (or JSON).
    ///
    /// Per scenario: the median wall time of one run on one core, the right-hand-side
    /// evaluations of one run, and the runs per second with every core busy. Each
    /// scenario is timed for about --seconds on one core, then as long on all cores.
    #[command(verbatim_doc_comment)]
    Bench {
        /// Shipped scenario names or TOML paths (default: thesis-ch3, thesis-ch5, regulated-pi, control-adaptive).
        scenarios: Vec<String>,
        /// Print a JSON list of objects with scenario, median_s, rhs_evaluations,
        /// runs_per_s_all_cores, threads, samples.
        #[arg(long)]
        json: bool,
        /// Time budget per scenario and phase [s].
        #[arg(long, default_value_t = 1.0)]
        seconds: f64,
        /// Also write DIR/summary.json, DIR/bench.svg (bars) and DIR/report.html.
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
        /// A JSON list of another tool's timings measured beside rhonn ({run, tool,
        /// median_s, rhs_evaluations}, as `python3 bench/scipy_ch5.py --json FILE` writes),
        /// drawn beside rhonn's in DIR/bench.svg (needs --out).
        #[arg(long, value_name = "FILE.json")]
        compare: Option<PathBuf>,
    },
    /// Monte Carlo campaign over the thesis's tolerances (beta, mu_1, mu_2 +-20 %, Q_0 +-10 %,
    /// demand slew +-10 %, uniform draws), every core busy. Writes DIR/runs.csv (one row per
    /// run: drawn parameters, status, figures), DIR/summary.json (per figure min, quantiles,
    /// max, failures) and DIR/campaign.json. Finished runs are appended to
    /// DIR/runs.partial.csv as they end: rerunning the same command resumes an interrupted
    /// campaign. Each run's draw depends only on (seed, run index).
    #[command(verbatim_doc_comment)]
    Campaign {
        /// A shipped scenario's name or a path to a TOML file.
        scenario: String,
        /// Number of runs.
        #[arg(long, default_value_t = 100)]
        runs: u64,
        /// Seed of the draws.
        #[arg(long, default_value_t = 0)]
        seed: u64,
        /// Run only the K-th of M contiguous slices of the runs (merge them with `rhonn merge`).
        #[arg(long, value_name = "K/M", default_value = "1/1")]
        shard: String,
        /// Every corner of the parameters' ranges instead of random draws (2^k runs for k
        /// varying parameters, 32 by default; --runs ignored).
        #[arg(long)]
        corners: bool,
        /// Keep the pressure traces of the runs with index below N for the envelope plot
        /// (traces.csv, envelope.csv, envelope.svg); 0 for none.
        #[arg(long, value_name = "N", default_value_t = 1000)]
        envelope_runs: u64,
        /// Worker threads (default: every core).
        #[arg(long)]
        threads: Option<usize>,
        /// Output folder (default out/campaign-<scenario>).
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
    },
    /// Merge finished campaign shards into one campaign (identical to the unsharded run).
    Merge {
        /// Shard folders.
        dirs: Vec<PathBuf>,
        /// Output folder.
        #[arg(long, value_name = "DIR")]
        out: PathBuf,
    },
    /// List the shipped scenarios with a one-line description each.
    Scenarios,
    /// Print a scenario's TOML (a shipped one as it ships: copy it to start your own).
    Show {
        /// A shipped scenario's name or a path to a TOML file.
        scenario: String,
    },
    /// Rebuild DIR/report.html (one self-contained page: settings, figures, findings,
    /// every plot) from the folder's files, e.g. for a run of an older version or a merged
    /// campaign. Every command that writes a folder writes it too.
    Report {
        /// A folder written by run, reproduce, fit, predict, identify or campaign.
        dir: PathBuf,
    },
}

/// `rhonn fit --select`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum SelectMode {
    /// Cross-validate the candidate structures.
    Auto,
    /// The default structure.
    None,
}

/// A count of at least 1 (`--every`): 0 would print no line at all.
fn at_least_one(s: &str) -> Result<usize, String> {
    match s.parse::<usize>() {
        Ok(0) => Err("0 prints no line: give a whole number of at least 1".into()),
        Ok(n) => Ok(n),
        Err(_) => Err(format!("`{s}` is not a whole number of at least 1")),
    }
}
