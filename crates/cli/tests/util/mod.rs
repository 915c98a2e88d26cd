//! Shared by the integration tests: run the real `rhonn` binary in a folder and read what it left.

#![allow(dead_code)]

use std::path::Path;
use std::process::{Command, Output};

pub fn rhonn(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rhonn"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("runs rhonn")
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

pub fn stdout(o: &Output) -> String {
    String::from_utf8_lossy(&o.stdout).into_owned()
}

pub fn files_in(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .map(|rd| {
            rd.map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

/// What users read: README.md, CHANGELOG.md and every Markdown file under docs/ (path
/// relative to `root`, text), in a stable order.
pub fn user_docs(root: &Path) -> Vec<(String, String)> {
    fn walk(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
        let mut entries: Vec<_> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .collect();
        entries.sort();
        for p in entries {
            if p.is_dir() {
                walk(&p, out);
            } else if p.extension().is_some_and(|e| e == "md") {
                out.push(p);
            }
        }
    }
    let mut files = vec![root.join("README.md"), root.join("CHANGELOG.md")];
    walk(&root.join("docs"), &mut files);
    files
        .into_iter()
        .map(|p| {
            let text = std::fs::read_to_string(&p).unwrap();
            (p.strip_prefix(root).unwrap().display().to_string(), text)
        })
        .collect()
}

/// A folder for files several tests share, made once per test process: in Cargo's folder for
/// integration tests' files, named `PREFIX-PID`; the folders of earlier processes that have
/// ended are removed first.
fn shared_dir(prefix: &str) -> std::path::PathBuf {
    let base = Path::new(env!("CARGO_TARGET_TMPDIR"));
    for e in std::fs::read_dir(base).into_iter().flatten().flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let ended = name
            .strip_prefix(prefix)
            .and_then(|rest| rest.strip_prefix('-'))
            .and_then(|pid| pid.parse::<u32>().ok())
            .is_some_and(|pid| Path::new("/proc").is_dir() && !Path::new(&format!("/proc/{pid}")).exists());
        if ended {
            let _ = std::fs::remove_dir_all(e.path());
        }
    }
    let dir = base.join(format!("{prefix}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The folder of `rhonn fit` with the default selection on the cascaded tanks' estimation
/// record, made once per test process and shared by the tests that read a default fit's
/// files (the fit costs about 20 CPU-seconds; the test command's time on 2 cores). No
/// test writes into it: one that needs the folder as its own copies it ([`copy_dir`]).
pub fn tanks_default_fit() -> &'static Path {
    static FIT: std::sync::OnceLock<std::path::PathBuf> = std::sync::OnceLock::new();
    FIT.get_or_init(|| {
        let dir = shared_dir("tanks-default-fit");
        let data = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
            .join("data/cascaded-tanks/estimation.csv");
        let o = rhonn(
            &dir,
            &[
                "fit",
                "--data",
                data.to_str().unwrap(),
                "--inputs",
                "u",
                "--outputs",
                "y",
                "--out",
                "fit",
            ],
        );
        assert!(o.status.success(), "the shared tanks fit: {}", stderr(&o));
        dir.join("fit")
    })
}

/// `rhonn benchmark daisy-hair-dryer coupled-electric-drives` on the shipped data, made once
/// per test process and shared (tests/benchmark.rs checks it, tests/glossary.rs reads its
/// figures' names; about 30 CPU-seconds): its output folder and what it printed. No test
/// writes into the folder.
pub fn two_benchmarks() -> &'static (std::path::PathBuf, String) {
    static RUN: std::sync::OnceLock<(std::path::PathBuf, String)> = std::sync::OnceLock::new();
    RUN.get_or_init(|| {
        let dir = shared_dir("two-benchmarks");
        let data = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join("data/benchmarks");
        let o = rhonn(
            &dir,
            &[
                "benchmark",
                "daisy-hair-dryer",
                "coupled-electric-drives",
                "--data-dir",
                data.to_str().unwrap(),
                "--out",
                "b",
            ],
        );
        assert!(o.status.success(), "the shared benchmarks: {}", stderr(&o));
        (dir.join("b"), String::from_utf8_lossy(&o.stdout).into_owned())
    })
}

/// Copy the files of folder `from` (and its folders) into `to`, made if missing.
pub fn copy_dir(from: &Path, to: &Path) {
    std::fs::create_dir_all(to).unwrap();
    for e in std::fs::read_dir(from).unwrap() {
        let p = e.unwrap().path();
        let target = to.join(p.file_name().unwrap());
        if p.is_dir() {
            copy_dir(&p, &target);
        } else {
            std::fs::copy(&p, target).unwrap();
        }
    }
}
