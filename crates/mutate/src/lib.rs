//! The mutation harness of the `rhonn` command.
//!
//! Every file a user gives the command (recordings for `fit`, `predict` and `identify`,
//! model specs, a model.json of every kind, every shipped scenario) is mutated once per
//! case with a seeded hostile change (extreme or non-finite numbers, wrong types, keys
//! lost or unknown, rows lost, doubled or swapped, times rounded or in milliseconds, another
//! delimiter, the text truncated) and the command run on it with a timeout. A case passes
//! when the command exits 0 having written no NaN, infinity or JSON null, or exits 2
//! leaving no output folder; no case may panic, hang, or leave a temporary file. Refusals
//! are counted by whether the message names the file and the field, column or line.
//!
//! `cargo run --release -p rhonn-mutate -- --bin target/release/rhonn --cases 20000` runs a
//! long campaign; `tests/mutation.rs` runs the default, short one; `--sweep` the systematic
//! one ([`mutation::sweep`]: every numeric value set to each extreme in turn, run by CI).

pub mod corpus;
pub mod csv_mutation;
pub mod mutant;
pub mod mutation;
mod outcome;

pub use outcome::{Failure, Report, SurfaceStats};

use corpus::Surface;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::path::PathBuf;
use std::process::{Command, Stdio};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Duration;
use wait_timeout::ChildExt;

/// A harness run.
#[derive(Debug, Clone)]
pub struct Config {
    /// The `rhonn` binary.
    pub bin: PathBuf,
    /// A folder for the bases and the cases (created; each passing case's folder removed).
    pub work: PathBuf,
    /// How many mutants.
    pub cases: usize,
    /// The seed of every mutation (case `i` depends only on `(seed, i)`).
    pub seed: u64,
    /// A case still running after this is a hang.
    pub timeout: Duration,
    /// Cases run at once.
    pub jobs: usize,
    /// Instead of `cases` random mutants, every numeric value of every TOML and JSON
    /// surface set to each extreme in turn ([`mutation::sweep`]).
    pub sweep: bool,
}

/// What one case did.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Verdict {
    /// Exit 0, every written number finite.
    Accepted,
    /// Exit 2; `named`: the message names the file and the field, column or line.
    Refused { named: bool },
    /// A failure of the harness's rules.
    Failed(String),
}

/// Run the harness: prepare the bases, then every case.
pub fn run(cfg: &Config) -> anyhow::Result<Report> {
    let base = cfg.work.join("base");
    let surfaces = corpus::prepare(&cfg.bin, &base)?;
    // The sweep's cases, made up front: (surface, mutant).
    let swept: Vec<(usize, mutation::Mutant)> = match cfg.sweep {
        true => (surfaces.iter().enumerate())
            .flat_map(|(k, s)| {
                mutation::sweep(&s.base, s.format)
                    .into_iter()
                    .map(move |m| (k, m))
            })
            .collect(),
        false => Vec::new(),
    };
    let total = if cfg.sweep { swept.len() } else { cfg.cases };
    let next = AtomicUsize::new(0);
    let report = Mutex::new(Report::new(&surfaces));
    std::thread::scope(|scope| {
        for _ in 0..cfg.jobs.max(1) {
            scope.spawn(|| loop {
                let i = next.fetch_add(1, Ordering::SeqCst);
                if i >= total {
                    break;
                }
                let (s, m) = match cfg.sweep {
                    true => (&surfaces[swept[i].0], swept[i].1.clone()),
                    false => {
                        let s = &surfaces[i % surfaces.len()];
                        let mut rng = ChaCha8Rng::seed_from_u64(
                            cfg.seed ^ (i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15),
                        );
                        (s, mutation::mutate(&s.base, s.format, &mut rng))
                    }
                };
                let (what, stderr, verdict) = run_mutant(cfg, s, i, m);
                report.lock().unwrap().add(i, s, what, &stderr, verdict);
            });
        }
    });
    Ok(report.into_inner().unwrap())
}

/// Run case `i` on surface `s`: its seeded random mutant; its folder is removed when it
/// passes.
pub fn run_case(cfg: &Config, s: &Surface, i: usize) -> (String, String, Verdict) {
    let mut rng = ChaCha8Rng::seed_from_u64(cfg.seed ^ (i as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15));
    run_mutant(cfg, s, i, mutation::mutate(&s.base, s.format, &mut rng))
}

/// Run mutant `m` of surface `s` as case `i`; its folder is removed when it passes.
pub fn run_mutant(cfg: &Config, s: &Surface, i: usize, m: mutation::Mutant) -> (String, String, Verdict) {
    let dir = cfg.work.join(format!("case-{i:06}"));
    let _ = std::fs::remove_dir_all(&dir);
    if let Err(e) = std::fs::create_dir_all(&dir) {
        return (m.what, String::new(), Verdict::Failed(format!("harness: {e}")));
    }
    let file = corpus::mutant_path(&dir, s);
    // One case in four writes its output into the folder that holds its input (an input
    // inside `--out`): the input must come out unchanged, and a refusal must add nothing.
    let out = if i % 4 == 3 { dir.clone() } else { dir.join("out") };
    if let Err(e) = std::fs::write(&file, &m.text) {
        return (m.what, String::new(), Verdict::Failed(format!("harness: {e}")));
    }
    let args = corpus::case_args(s, &file, &out);
    let (code, stderr) = match spawn(cfg, &args, &dir) {
        Ok(x) => x,
        Err(e) => return (m.what, String::new(), Verdict::Failed(e)),
    };
    let verdict = match outcome::judge(code, &stderr, &dir, &out, s, &m.names) {
        Verdict::Failed(f) => Verdict::Failed(f),
        v => match std::fs::read_to_string(&file) {
            Ok(t) if t == m.text => v,
            _ => Verdict::Failed(format!("its input {} was changed or removed", file.display())),
        },
    };
    if !matches!(verdict, Verdict::Failed(_)) {
        let _ = std::fs::remove_dir_all(&dir);
    }
    (m.what, stderr, verdict)
}

/// Run the command with a timeout; `Ok((exit code or None if killed by a signal, stderr))`.
fn spawn(cfg: &Config, args: &[String], dir: &std::path::Path) -> Result<(Option<i32>, String), String> {
    let err_path = dir.join("stderr.txt");
    let err_file = std::fs::File::create(&err_path).map_err(|e| format!("harness: {e}"))?;
    let mut child = Command::new(&cfg.bin)
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(err_file)
        .spawn()
        .map_err(|e| format!("harness: {e}"))?;
    let status = match child.wait_timeout(cfg.timeout).map_err(|e| e.to_string())? {
        Some(st) => st,
        None => {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!("hang: still running after {} s", cfg.timeout.as_secs()));
        }
    };
    let stderr = std::fs::read_to_string(&err_path).unwrap_or_default();
    let _ = std::fs::remove_file(&err_path);
    Ok((status.code(), stderr))
}
