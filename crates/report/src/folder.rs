//! One rule for output folders: checked writable before any work; after a command has
//! written its complete set, the files of rhonn's own kind that it did not write this
//! time (an earlier run's `validation.csv`, say) are removed; temporary files that a
//! killed run left are removed by the next run in the folder.

use crate::{Error, Result};
use std::path::{Path, PathBuf};

/// The files `run`, `fit`, `predict` and `identify` write (and `training_<k>.svg`): the
/// ones a later such command removes when it does not write them again. A campaign's
/// files and anything else in the folder are never touched.
const RUN_FILES: &[&str] = &[
    "estimate.csv",
    "estimate.svg",
    "ident_errors.svg",
    "ident_states.svg",
    "ident_zoom.svg",
    "inputs.svg",
    "model.json",
    "prediction.csv",
    "prediction.svg",
    "prediction_zoom.svg",
    "pressure.svg",
    "report.html",
    "residual_histogram.svg",
    "residuals.svg",
    "states.svg",
    "stroke.svg",
    "summary.json",
    "training.svg",
    "trajectory.csv",
    "validation.csv",
    "validation.svg",
    "validation_residuals.svg",
    "weights.csv",
    "weights.json",
    "weights.svg",
];

fn is_run_file(name: &str) -> bool {
    RUN_FILES.contains(&name)
        || name
            .strip_prefix("training_")
            .and_then(|r| r.strip_suffix(".svg"))
            .is_some_and(|k| !k.is_empty() && k.bytes().all(|b| b.is_ascii_digit()))
}

/// Check, before any work, that `dir` can be the output folder: a folder that exists and
/// can be written, or a path whose nearest existing ancestor is a writable folder. Nothing
/// is created.
pub fn check_writable(dir: &Path) -> Result<()> {
    let err = |message: String| Error::Folder {
        path: dir.to_path_buf(),
        message,
    };
    let mut probe_in = dir.to_path_buf();
    loop {
        if probe_in.exists() {
            break;
        }
        match probe_in.parent() {
            Some(p) if !p.as_os_str().is_empty() => probe_in = p.to_path_buf(),
            _ => {
                probe_in = PathBuf::from(".");
                break;
            }
        }
    }
    if !probe_in.is_dir() {
        return Err(err(if probe_in == dir {
            "it exists and is not a folder".into()
        } else {
            format!("{} is a file, not a folder", probe_in.display())
        }));
    }
    let probe = probe_in.join(format!(".rhonn-probe-{}", std::process::id()));
    match std::fs::File::create(&probe) {
        Ok(_) => {
            let _ = std::fs::remove_file(&probe);
            Ok(())
        }
        Err(e) => Err(err(format!(
            "cannot write in {}: {}",
            probe_in.display(),
            rhonn::error::path_problem(&probe, &e)
        ))),
    }
}

/// After a command wrote `written` into `dir`: remove the run files (see `RUN_FILES`)
/// that it did not write, so that nothing of an earlier run stays beside it. Returns the
/// files removed.
pub fn remove_stale(dir: &Path, written: &[PathBuf]) -> Vec<PathBuf> {
    let keep: Vec<std::ffi::OsString> = written
        .iter()
        .filter_map(|p| p.file_name().map(|n| n.to_os_string()))
        .collect();
    let mut removed = Vec::new();
    let Ok(rd) = std::fs::read_dir(dir) else {
        return removed;
    };
    for e in rd.flatten() {
        let name = e.file_name();
        let is_file = e.file_type().is_ok_and(|t| t.is_file());
        if is_file
            && is_run_file(&name.to_string_lossy())
            && !keep.contains(&name)
            && std::fs::remove_file(e.path()).is_ok()
        {
            removed.push(e.path());
        }
    }
    removed.sort();
    removed
}

/// Whether process `pid` runs on this machine (Linux's /proc; elsewhere assumed running).
fn alive(pid: u32) -> bool {
    let proc_dir = Path::new("/proc");
    !proc_dir.is_dir() || proc_dir.join(pid.to_string()).exists()
}

/// Remove the temporary files (`.NAME.tmp-PID`, `.campaign.json.tmp`) that a killed run
/// left in `dir`: those of a process no longer running that are over a minute old, and
/// any over an hour old (a folder shared between machines: a PID may be another's).
pub fn clean_temporary(dir: &Path) {
    let Ok(rd) = std::fs::read_dir(dir) else { return };
    let now = std::time::SystemTime::now();
    for e in rd.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        if !name.starts_with('.') {
            continue;
        }
        let pid = match name.rsplit_once(".tmp-") {
            Some((_, p)) => match p.parse::<u32>() {
                Ok(p) => Some(p),
                Err(_) => continue,
            },
            None if name.ends_with(".tmp") => None,
            None => continue,
        };
        let age = e
            .metadata()
            .and_then(|m| m.modified())
            .ok()
            .and_then(|m| now.duration_since(m).ok());
        let Some(age) = age else { continue };
        let dead = pid.is_some_and(|p| p != std::process::id() && !alive(p));
        if (dead && age.as_secs() >= 60) || age.as_secs() >= 3600 {
            let _ = std::fs::remove_file(e.path());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_unwritable_or_file_path_is_refused_before_work_and_nothing_is_created() {
        let d = tempfile::tempdir().unwrap();
        let f = d.path().join("file");
        std::fs::write(&f, "x").unwrap();
        let e = check_writable(&f).unwrap_err().to_string();
        assert!(e.contains("not a folder"), "{e}");
        let e = check_writable(&f.join("sub")).unwrap_err().to_string();
        assert!(e.contains("is a file, not a folder"), "{e}");
        let new = d.path().join("a").join("b");
        check_writable(&new).unwrap();
        assert!(!d.path().join("a").exists(), "nothing is created");
        assert_eq!(
            std::fs::read_dir(d.path()).unwrap().count(),
            1,
            "the probe is removed"
        );
    }

    #[test]
    fn stale_run_files_go_and_everything_else_stays() {
        let d = tempfile::tempdir().unwrap();
        for n in [
            "validation.csv",
            "validation.svg",
            "summary.json",
            "training_3.svg",
            "notes.txt",
            "runs.csv",
            "training_x.svg",
        ] {
            std::fs::write(d.path().join(n), "x").unwrap();
        }
        let removed = remove_stale(d.path(), &[d.path().join("summary.json")]);
        let names: Vec<String> = removed
            .iter()
            .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
            .collect();
        assert_eq!(names, ["training_3.svg", "validation.csv", "validation.svg"]);
        let mut left: Vec<String> = std::fs::read_dir(d.path())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        left.sort();
        assert_eq!(left, ["notes.txt", "runs.csv", "summary.json", "training_x.svg"]);
    }

    #[test]
    fn a_dead_process_s_old_temporary_file_is_cleaned_and_a_fresh_one_kept() {
        let d = tempfile::tempdir().unwrap();
        // PID 4294967295 runs nowhere.
        let old = d.path().join(".summary.json.tmp-4294967295");
        let own = d.path().join(format!(".summary.json.tmp-{}", std::process::id()));
        std::fs::write(&old, "x").unwrap();
        std::fs::write(&own, "x").unwrap();
        let f = std::fs::File::options().write(true).open(&old).unwrap();
        f.set_modified(std::time::SystemTime::now() - std::time::Duration::from_secs(120))
            .unwrap();
        clean_temporary(d.path());
        assert!(!old.exists());
        assert!(own.exists());
    }
}
