//! The mutation harness of the `rhonn` command.
//!
//! Every file a user gives the command (recordings for `fit`, `predict` and `identify`,
//! model specs, a model.json of every kind, every shipped scenario) is mutated once per
//! case with a seeded hostile change (extreme or non-finite numbers, wrong types, keys
//! lost or unknown, rows lost, doubled or swapped, times rounded or in milliseconds, another
//! delimiter, the text truncated) and the command run on it with a timeout, in one of the
//! ways of [`flavor`] (into the folder holding the input, a recording grown long, two
//! writers at once, killed and run again). A case passes when the command exits 0 having
//! written no NaN, infinity or JSON null, or exits 2 leaving no output folder; no case may
//! panic, hang, or leave a temporary file. Refusals
//! are counted by whether the message names the file and the field, column or line.
//!
//! `cargo run --release -p rhonn-mutate -- --bin target/release/rhonn --cases 20000` runs a
//! long campaign; `crates/cli/tests/mutation.rs` runs the default, short one; `--sweep` the systematic
//! one ([`mutation::sweep`]: every numeric value set to each extreme in turn, run by CI).

pub mod corpus;
pub mod csv_mutation;
pub mod flavor;
pub mod mutant;
pub mod mutation;
mod outcome;

pub use outcome::{Failure, Report, SurfaceStats};

use corpus::Surface;
use flavor::Flavor;
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
                let flavor = flavor::of(i, s).name();
                report.lock().unwrap().add(i, s, (what, flavor), &stderr, verdict);
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

/// Run mutant `m` of surface `s` as case `i` (in its [`flavor::of`]); its folder is
/// removed when it passes.
pub fn run_mutant(cfg: &Config, s: &Surface, i: usize, mut m: mutation::Mutant) -> (String, String, Verdict) {
    let dir = cfg.work.join(format!("case-{i:06}"));
    let _ = std::fs::remove_dir_all(&dir);
    if let Err(e) = std::fs::create_dir_all(&dir) {
        return (m.what, String::new(), Verdict::Failed(format!("harness: {e}")));
    }
    let file = corpus::mutant_path(&dir, s);
    let flavor = flavor::of(i, s);
    // An input inside `--out`: the input must come out unchanged, and a refusal must add
    // nothing.
    let out = match flavor {
        Flavor::InputInOut => dir.clone(),
        _ => dir.join("out"),
    };
    if flavor == Flavor::LongRecord {
        m.text = flavor::grown(&m.text, flavor::LONG_ROWS);
        m.what = format!("{}; grown to {} rows", m.what, flavor::LONG_ROWS);
    }
    if let Err(e) = std::fs::write(&file, &m.text) {
        return (m.what, String::new(), Verdict::Failed(format!("harness: {e}")));
    }
    let args = corpus::case_args(s, &file, &out);
    let run = match flavor {
        Flavor::TwoWriters => two_writers(cfg, s, &args, &dir, &out, &m.names),
        Flavor::Killed(after) => killed(cfg, s, &args, after, (&dir, &out), &m.names),
        _ => spawn(cfg, &args, &dir, "stderr.txt")
            .map(|(code, stderr)| (outcome::judge(code, &stderr, &dir, &out, s, &m.names), stderr)),
    };
    let (verdict, stderr) = match run {
        Ok(x) => x,
        Err(e) => return (m.what, String::new(), Verdict::Failed(e)),
    };
    let verdict = match verdict {
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

/// Whether `out` holds a folder `rhonn report` renders (exit 0): one run's whole folder.
fn reported(cfg: &Config, out: &std::path::Path, dir: &std::path::Path) -> Result<bool, String> {
    let args = ["report".to_string(), out.display().to_string()];
    spawn(cfg, &args, dir, "stderr-report.txt").map(|(code, _)| code == Some(0))
}

/// Whether `out` shows anything but hidden entries (a run's stage is hidden).
fn shows_files(out: &std::path::Path) -> bool {
    std::fs::read_dir(out).is_ok_and(|d| {
        d.flatten()
            .any(|e| !e.file_name().to_string_lossy().starts_with('.'))
    })
}

/// Two writers into one folder at once: each exits 0 or refuses (2); when one succeeded,
/// the folder is one run's, whole (`rhonn report` renders it) and holds no NaN; when both
/// refused, neither wrote it. Nothing temporary is left.
fn two_writers(
    cfg: &Config,
    s: &Surface,
    args: &[String],
    dir: &std::path::Path,
    out: &std::path::Path,
    names: &[String],
) -> Result<(Verdict, String), String> {
    let (a, b) = std::thread::scope(|scope| {
        let a = scope.spawn(|| spawn(cfg, args, dir, "stderr-a.txt"));
        let b = scope.spawn(|| spawn(cfg, args, dir, "stderr-b.txt"));
        (a.join(), b.join())
    });
    let ((ca, ea), (cb, eb)) = (
        a.map_err(|_| "harness: a writer's thread panicked".to_string())??,
        b.map_err(|_| "harness: a writer's thread panicked".to_string())??,
    );
    let stderr = format!("{ea}{eb}");
    for (code, e) in [(ca, &ea), (cb, &eb)] {
        if e.contains("panicked") || code == Some(101) {
            return Ok((Verdict::Failed("panic".into()), stderr));
        }
        if !matches!(code, Some(0 | 2)) {
            return Ok((Verdict::Failed(format!("a writer's exit code {code:?}")), stderr));
        }
    }
    if ca != Some(0) && cb != Some(0) {
        // Judge the refusal of the input, not the other writer's hold on the folder: which
        // writer held it is a race, and its message rightly names the folder only.
        let (code, e) = outcome::input_refusal((ca, &ea), (cb, &eb));
        return Ok((outcome::judge(code, e, dir, out, s, names), stderr));
    }
    let v = outcome::judge(Some(0), &stderr, dir, out, s, names);
    if matches!(v, Verdict::Failed(_)) {
        return Ok((v, stderr));
    }
    if !reported(cfg, out, dir)? {
        return Ok((
            Verdict::Failed(
                "two writers: `rhonn report` refused the folder (not one run's whole folder)".into(),
            ),
            stderr,
        ));
    }
    Ok((v, stderr))
}

/// A run killed `after` its start (if still running), then run again: after the kill the
/// folder shows nothing or one run's whole folder; the rerun is judged as any case (it
/// also removes what the killed run left hidden).
fn killed(
    cfg: &Config,
    s: &Surface,
    args: &[String],
    after: Duration,
    (dir, out): (&std::path::Path, &std::path::Path),
    names: &[String],
) -> Result<(Verdict, String), String> {
    let mut child = Command::new(&cfg.bin)
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .map_err(|e| format!("harness: {e}"))?;
    if child.wait_timeout(after).map_err(|e| e.to_string())?.is_none() {
        let _ = child.kill();
    }
    let _ = child.wait();
    if shows_files(out) && !reported(cfg, out, dir)? {
        return Ok((
            Verdict::Failed("killed: the folder shows files that are not one run's whole folder".into()),
            String::new(),
        ));
    }
    let (code, stderr) = spawn(cfg, &flavor::rerun_args(args), dir, "stderr.txt")?;
    Ok((outcome::judge(code, &stderr, dir, out, s, names), stderr))
}

/// Run the command with a timeout; `Ok((exit code or None if killed by a signal, stderr))`.
fn spawn(
    cfg: &Config,
    args: &[String],
    dir: &std::path::Path,
    err_name: &str,
) -> Result<(Option<i32>, String), String> {
    let err_path = dir.join(err_name);
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
