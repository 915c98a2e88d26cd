//! Nothing lost, ever (issue 56): an output folder touches only its own files, a folder is
//! whole from one run or absent, two writers never interleave, and a run killed at any
//! point leaves the folder as one run wrote it. Each reproduction of the issue is a test;
//! every file of the user's is checked by its bytes before and after.

use crate::util::{self, rhonn, stderr};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// `rhonn predict` with the fit's model `m/model.json` on `data` into `out`.
fn predict_args<'a>(data: &'a str, out: &'a str) -> [&'a str; 7] {
    ["predict", "--model", "m/model.json", "--data", data, "--out", out]
}

fn data(name: &str) -> PathBuf {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
        .join("data/cascaded-tanks")
        .join(name)
}

/// Every file below `dir` (relative path, bytes), hidden ones included.
fn snapshot(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    fn walk(root: &Path, dir: &Path, out: &mut BTreeMap<String, Vec<u8>>) {
        for e in std::fs::read_dir(dir).unwrap().flatten() {
            let p = e.path();
            if p.is_dir() {
                walk(root, &p, out);
            } else {
                let rel = p.strip_prefix(root).unwrap().to_string_lossy().into_owned();
                out.insert(rel, std::fs::read(&p).unwrap());
            }
        }
    }
    let mut out = BTreeMap::new();
    if dir.is_dir() {
        walk(dir, dir, &mut out);
    }
    out
}

/// The user's files of `before` are all in `after`, byte for byte.
fn kept(before: &BTreeMap<String, Vec<u8>>, after: &BTreeMap<String, Vec<u8>>, names: &[&str]) {
    for n in names {
        assert_eq!(before.get(*n), after.get(*n), "{n} changed or went");
    }
}

/// Refused (exit 2) with a message holding every one of `parts`.
fn refused(o: &std::process::Output, parts: &[&str]) {
    assert_eq!(o.status.code(), Some(2), "{}", stderr(o));
    let e = stderr(o);
    assert!(parts.iter().all(|p| e.contains(p)), "{parts:?}: {e}");
}

fn ok(o: &std::process::Output) -> String {
    assert!(o.status.success(), "{}", stderr(o));
    stderr(o)
}

/// A folder holding the tanks' two recordings, as a user copies them.
fn with_recordings(root: &Path, name: &str) -> PathBuf {
    let t = root.join(name);
    std::fs::create_dir_all(&t).unwrap();
    for f in ["estimation.csv", "validation.csv"] {
        std::fs::copy(data(f), t.join(f)).unwrap();
    }
    t
}

fn fit_args<'a>(data: &'a str, out: &'a str) -> Vec<&'a str> {
    vec![
        "fit",
        "--data",
        data,
        "--inputs",
        "u",
        "--outputs",
        "y",
        "--select",
        "none",
        "--out",
        out,
    ]
}

#[test]
fn fit_predict_identify_and_run_leave_every_file_of_the_user_as_it_was() {
    let d = tempfile::tempdir().unwrap();
    let t = with_recordings(d.path(), "t");
    let before = snapshot(&t);
    ok(&rhonn(d.path(), &fit_args("t/estimation.csv", "t")));
    let after_fit = snapshot(&t);
    kept(&before, &after_fit, &["estimation.csv", "validation.csv"]);
    // predict into the fit's folder, twice: the model it used survives.
    for _ in 0..2 {
        let o = rhonn(
            d.path(),
            &[
                "predict",
                "--model",
                "t/model.json",
                "--data",
                "t/validation.csv",
                "--out",
                "t",
            ],
        );
        let e = ok(&o);
        assert!(!e.contains("removed t/model.json"), "{e}");
    }
    let after = snapshot(&t);
    kept(
        &after_fit,
        &after,
        &["estimation.csv", "validation.csv", "model.json"],
    );
    // identify --validate with the recording in the folder: refused before any work (it
    // would write its own validation.csv over it), nothing changed.
    let o = rhonn(
        d.path(),
        &[
            "identify",
            "--data",
            "t/estimation.csv",
            "--validate",
            "t/validation.csv",
            "--inputs",
            "u",
            "--outputs",
            "y",
            "--out",
            "t",
        ],
    );
    refused(&o, &["t/validation.csv", "an input of this run"]);
    assert_eq!(snapshot(&t), after);
    // identify into a fit's folder without --force: refused, the fitted model kept.
    let f = d.path().join("f");
    ok(&rhonn(
        d.path(),
        &fit_args(data("estimation.csv").to_str().unwrap(), "f"),
    ));
    let fitted = snapshot(&f);
    let o = rhonn(
        d.path(),
        &[
            "identify",
            "--data",
            data("estimation.csv").to_str().unwrap(),
            "--inputs",
            "u",
            "--outputs",
            "y",
            "--out",
            "f",
        ],
    );
    refused(&o, &["f/model.json", "--force"]);
    assert_eq!(snapshot(&f), fitted, "nothing written");
    // run into it: the model stays (a run writes none, and removes one only with --force).
    let e = ok(&rhonn(d.path(), &["run", "thesis-ch3", "--out", "f"]));
    assert!(e.contains("kept f/model.json"), "{e}");
    assert_eq!(snapshot(&f).get("model.json"), fitted.get("model.json"));
}

#[test]
fn a_command_s_own_input_in_its_folder_is_never_removed() {
    let d = tempfile::tempdir().unwrap();
    // The trajectory of a run, fitted into the run's own folder: kept.
    ok(&rhonn(d.path(), &["run", "thesis-ch3", "--out", "p"]));
    let run = snapshot(&d.path().join("p"));
    let e = ok(&rhonn(
        d.path(),
        &[
            "fit",
            "--data",
            "p/trajectory.csv",
            "--inputs",
            "current",
            "--outputs",
            "p_line",
            "--select",
            "none",
            "--out",
            "p",
        ],
    ));
    assert!(e.contains("kept p/trajectory.csv"), "{e}");
    kept(&run, &snapshot(&d.path().join("p")), &["trajectory.csv"]);
    // A file of the user's with the name of one the run writes: refused, not overwritten.
    std::fs::create_dir_all(d.path().join("u")).unwrap();
    std::fs::write(d.path().join("u/trajectory.csv"), "mine").unwrap();
    refused(
        &rhonn(d.path(), &["run", "thesis-ch3", "--out", "u"]),
        &["u/trajectory.csv", "not a file an earlier rhonn run wrote here"],
    );
    assert_eq!(std::fs::read(d.path().join("u/trajectory.csv")).unwrap(), b"mine");
    assert_eq!(util::files_in(&d.path().join("u")), ["trajectory.csv"]);
    // A file the user edited after the run wrote it is theirs now: kept.
    ok(&rhonn(d.path(), &["run", "thesis-ch3", "--out", "q"]));
    std::fs::write(d.path().join("q/states.svg"), "<svg>mine</svg>").unwrap();
    std::fs::write(d.path().join("q/notes.txt"), "mine").unwrap();
    let e = ok(&rhonn(
        d.path(),
        &fit_args(data("estimation.csv").to_str().unwrap(), "q"),
    ));
    assert!(e.contains("kept q/states.svg"), "{e}");
    assert!(
        e.contains("removed q/trajectory.csv"),
        "an unchanged file of the earlier run goes: {e}"
    );
    let q = snapshot(&d.path().join("q"));
    assert_eq!(q["states.svg"], b"<svg>mine</svg>");
    assert_eq!(q["notes.txt"], b"mine");
}

/// The files of one `rhonn predict` of `data` into `out` (no manifest: compared by content).
fn reference(root: &Path, model: &str, data: &Path, name: &str) -> BTreeMap<String, Vec<u8>> {
    ok(&rhonn(
        root,
        &[
            "predict",
            "--model",
            model,
            "--data",
            data.to_str().unwrap(),
            "--out",
            name,
        ],
    ));
    snapshot(&root.join(name))
}

/// Whether `dir` holds exactly the files of one reference run (report.html and the manifest
/// aside, which name nothing of the run's own) and verifies as whole.
fn whole_from_one(root: &Path, dir: &str, refs: &[&BTreeMap<String, Vec<u8>>]) -> bool {
    let got = snapshot(&root.join(dir));
    if got.keys().any(|k| k.starts_with('.')) || !got.contains_key("report.html") {
        return false;
    }
    let strip = |m: &BTreeMap<String, Vec<u8>>| -> BTreeMap<String, Vec<u8>> {
        m.iter()
            .filter(|(k, _)| !matches!(k.as_str(), "rhonn-manifest.json" | "report.html"))
            .map(|(k, v)| (k.clone(), v.clone()))
            .collect()
    };
    let same = refs.iter().any(|r| strip(r) == strip(&got));
    if !same {
        for r in refs {
            let (r, g) = (strip(r), strip(&got));
            let differ: Vec<&String> = r
                .keys()
                .chain(g.keys())
                .filter(|k| r.get(*k) != g.get(*k))
                .collect();
            eprintln!("{dir}: differs from a reference in {differ:?}");
        }
    }
    same
}

fn trials(var: &str, default: usize) -> usize {
    std::env::var(var)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

#[test]
fn two_writers_at_once_never_leave_a_folder_of_both() {
    let d = tempfile::tempdir().unwrap();
    ok(&rhonn(
        d.path(),
        &fit_args(data("estimation.csv").to_str().unwrap(), "m"),
    ));
    let (a, b) = (data("estimation.csv"), data("validation.csv"));
    let ra = reference(d.path(), "m/model.json", &a, "ra");
    let rb = reference(d.path(), "m/model.json", &b, "rb");
    let n = trials("RHONN_FOLDER_TRIALS", 60);
    let mut refused = 0;
    for k in 0..n {
        // One trial in three into a folder that does not exist yet (both create it).
        let out = if k % 3 == 0 {
            format!("n{k}")
        } else {
            "cc".to_string()
        };
        let spawn = |data: &Path| {
            Command::new(env!("CARGO_BIN_EXE_rhonn"))
                .args(predict_args(data.to_str().unwrap(), &out))
                .current_dir(d.path())
                .stdout(Stdio::null())
                .stderr(Stdio::piped())
                .spawn()
                .unwrap()
        };
        let (pa, pb) = if k % 2 == 0 {
            (spawn(&a), spawn(&b))
        } else {
            (spawn(&b), spawn(&a))
        };
        for p in [pa, pb] {
            let o = p.wait_with_output().unwrap();
            if !o.status.success() {
                let e = String::from_utf8_lossy(&o.stderr);
                assert!(e.contains("another rhonn command is writing"), "trial {k}: {e}");
                refused += 1;
            }
        }
        assert!(
            whole_from_one(d.path(), &out, &[&ra, &rb]),
            "trial {k}: a folder of both runs"
        );
        let o = rhonn(d.path(), &["report", &out]);
        assert!(o.status.success(), "trial {k}: {}", stderr(&o));
    }
    eprintln!("{n} trials of two writers: {refused} refused as concurrent, every folder from one run");
}

#[test]
fn a_run_killed_at_any_step_of_its_commit_leaves_one_run_s_folder() {
    let d = tempfile::tempdir().unwrap();
    ok(&rhonn(
        d.path(),
        &fit_args(data("estimation.csv").to_str().unwrap(), "m"),
    ));
    let (a, b) = (data("estimation.csv"), data("validation.csv"));
    let ra = reference(d.path(), "m/model.json", &a, "ra");
    let rb = reference(d.path(), "m/model.json", &b, "rb");
    // Every step: before the commit's rename, after it, after each file moved, before the
    // manifest. The next command (here `rhonn report`) finishes a decided commit.
    for step in 1..=12 {
        let dir = format!("k{step}");
        ok(&rhonn(d.path(), &predict_args(a.to_str().unwrap(), &dir)));
        let o = Command::new(env!("CARGO_BIN_EXE_rhonn"))
            .args(predict_args(b.to_str().unwrap(), &dir))
            .env("RHONN_TEST_ABORT_AT_COMMIT_STEP", step.to_string())
            .current_dir(d.path())
            .output()
            .unwrap();
        let aborted = !o.status.success();
        let rep = rhonn(d.path(), &["report", &dir]);
        assert!(rep.status.success(), "step {step}: {}", stderr(&rep));
        let expect = if aborted && step == 1 { &ra } else { &rb };
        assert!(
            whole_from_one(d.path(), &dir, &[expect]),
            "step {step} (aborted: {aborted})"
        );
    }
    // Killed at random points of whole runs, into a folder that one run has written whole
    // (so that every kill, early or late, on a fast machine or a slow one, is checked).
    let dir = "kr";
    ok(&rhonn(d.path(), &predict_args(a.to_str().unwrap(), dir)));
    let n = trials("RHONN_KILL_TRIALS", 40);
    let mut rng = 0x9e37_79b9_7f4a_7c15u64;
    for k in 0..n {
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        let mut child = Command::new(env!("CARGO_BIN_EXE_rhonn"))
            .args([
                "predict",
                "--model",
                "m/model.json",
                "--data",
                if k % 2 == 0 {
                    b.to_str().unwrap()
                } else {
                    a.to_str().unwrap()
                },
                "--out",
                dir,
            ])
            .current_dir(d.path())
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(std::time::Duration::from_micros(rng % 60_000));
        let _ = child.kill();
        let _ = child.wait();
        let rep = rhonn(d.path(), &["report", dir]);
        assert!(rep.status.success(), "kill {k}: {}", stderr(&rep));
        assert!(
            whole_from_one(d.path(), dir, &[&ra, &rb]),
            "kill {k}: not one run's folder"
        );
    }
}

#[test]
fn a_first_run_killed_before_its_commit_leaves_no_file_in_sight_and_the_next_run_succeeds() {
    let d = tempfile::tempdir().unwrap();
    ok(&rhonn(
        d.path(),
        &fit_args(data("estimation.csv").to_str().unwrap(), "m"),
    ));
    let a = data("estimation.csv");
    let args = predict_args(a.to_str().unwrap(), "new/inner");
    let o = Command::new(env!("CARGO_BIN_EXE_rhonn"))
        .args(args)
        .env("RHONN_TEST_ABORT_AT_COMMIT_STEP", "1")
        .current_dir(d.path())
        .output()
        .unwrap();
    assert!(!o.status.success(), "the fault was not injected");
    let visible: Vec<String> = std::fs::read_dir(d.path().join("new/inner"))
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| !n.starts_with('.'))
        .collect();
    assert!(visible.is_empty(), "a killed first run left {visible:?}");
    let rep = rhonn(d.path(), &["report", "new/inner"]);
    assert!(
        stderr(&rep).contains("not a folder written by rhonn"),
        "{}",
        stderr(&rep)
    );
    ok(&rhonn(d.path(), &args));
    let hidden: Vec<String> = std::fs::read_dir(d.path().join("new/inner"))
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with(".rhonn-"))
        .collect();
    assert!(hidden.is_empty(), "the killed run's stage was left: {hidden:?}");
}

#[test]
fn report_and_predict_refuse_a_folder_of_two_runs_and_an_edited_model_is_said() {
    let d = tempfile::tempdir().unwrap();
    ok(&rhonn(
        d.path(),
        &fit_args(data("estimation.csv").to_str().unwrap(), "a"),
    ));
    ok(&rhonn(
        d.path(),
        &fit_args(data("validation.csv").to_str().unwrap(), "b"),
    ));
    let predict = |model: &str, out: &str| {
        rhonn(
            d.path(),
            &[
                "predict",
                "--model",
                model,
                "--data",
                data("validation.csv").to_str().unwrap(),
                "--out",
                out,
            ],
        )
    };
    // A model edited by hand is the user's to edit: predicted with, and said.
    let path = d.path().join("a/model.json");
    let text = std::fs::read_to_string(&path).unwrap();
    std::fs::write(&path, text.replacen("{", "{\n", 1)).unwrap();
    let e = ok(&predict("a/model.json", "p0"));
    assert!(
        e.contains("a/model.json was edited since the run that wrote it"),
        "{e}"
    );
    ok(&rhonn(d.path(), &["report", "a"]));
    // The summary of one run beside the plots of another, as a kill between renames left
    // them before: refused by both, nothing written.
    std::fs::copy(d.path().join("b/summary.json"), d.path().join("a/summary.json")).unwrap();
    refused(
        &rhonn(d.path(), &["report", "a"]),
        &["a/summary.json is not the file", "mixes files"],
    );
    refused(&predict("a/model.json", "p"), &["mixes files"]);
    assert!(!d.path().join("p").exists(), "nothing written");
}
