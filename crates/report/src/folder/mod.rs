//! One rule for output folders: an output folder holds its own files and the user's,
//! and rhonn touches only its own. A command checks the folder writable before any work,
//! locks it (`lock.rs`: one writer at a time), writes its whole set into a staging folder
//! and commits it in one step (`commit.rs`); `rhonn-manifest.json` (`manifest.rs`) lists
//! what it wrote, so that a later run removes only files an earlier run wrote and left
//! unchanged, never an input, and readers refuse a folder whose files come from different
//! runs. Temporary files that a killed run left are removed by the next run in the folder.

mod commit;
mod lock;
mod manifest;

pub use commit::{check_whole, roll_forward, writes, Committed, Writing, COMMIT};
pub use lock::FolderLock;
pub use manifest::{Entry, Manifest, MANIFEST};

use crate::{Error, Result};
use std::path::{Path, PathBuf};

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
