//! A folder whole or absent: a command writes its complete set of files into a staging
//! folder inside the output folder, under the folder's lock; the commit then writes the
//! set's manifest, renames the staging folder to `.rhonn-commit` in one step (from there
//! on the new set is decided) and rolls it forward: each file renamed into place, the
//! earlier run's files this run replaces removed, the manifest last. A run killed before
//! that rename leaves the folder as it was (its staging folder is cleaned by the next
//! run); one killed after it is finished by the next command that opens the folder
//! ([`roll_forward`], idempotent). Nothing the run did not write is removed unless the
//! earlier run's manifest lists it, unchanged, and it is no input of this run.

use super::lock::FolderLock;
use super::manifest::{files_below, Manifest, MANIFEST};
use crate::{Error, Result};
use std::path::{Path, PathBuf};

/// The name of a decided commit's folder inside the output folder.
pub const COMMIT: &str = ".rhonn-commit";

/// An output folder being written: its lock and its staging folder.
#[derive(Debug)]
pub struct Writing {
    dir: PathBuf,
    stage: PathBuf,
    /// The outermost folder this writing created, removed again (when empty) if it fails.
    created: Option<PathBuf>,
    inputs: Vec<PathBuf>,
    force: bool,
    /// Held until the writing ends: one writer per folder.
    _lock: FolderLock,
    committed: bool,
}

/// What a commit did.
#[derive(Debug, Default)]
pub struct Committed {
    /// The files written, at their final paths.
    pub files: Vec<PathBuf>,
    /// What the user is told: files of the earlier run removed or kept.
    pub notes: Vec<String>,
}

/// The files each command may write into its output folder (its data, not its plots): an
/// input of one of these names inside the folder is refused before any work.
pub mod writes {
    /// `rhonn fit`.
    pub const FIT: &[&str] = &["model.json", "summary.json", "report.html"];
    /// `rhonn predict`.
    pub const PREDICT: &[&str] = &["prediction.csv", "summary.json", "report.html"];
    /// `rhonn identify`.
    pub const IDENTIFY: &[&str] = &[
        "estimate.csv",
        "weights.csv",
        "validation.csv",
        "model.json",
        "summary.json",
        "report.html",
    ];
    /// `rhonn run` (either runner).
    pub const RUN: &[&str] = &[
        "trajectory.csv",
        "validation.csv",
        "weights.json",
        "summary.json",
        "report.html",
    ];
    /// `rhonn benchmark`.
    pub const BENCHMARK: &[&str] = &["benchmark.csv", "summary.json", "report.html"];
    /// `rhonn corpus --out`.
    pub const CORPUS: &[&str] = &["corpus.csv", "summary.json", "report.html"];
    /// `rhonn bench --out`.
    pub const BENCH: &[&str] = &["summary.json", "report.html"];
}

impl Writing {
    /// Start writing `dir` (created if needed): lock it, finish an interrupted commit,
    /// refuse an input of this run that it may overwrite (one of `writes`, the names it
    /// may write), and make the staging folder. `force`: a different `model.json` may be
    /// replaced.
    pub fn begin(dir: &Path, inputs: &[PathBuf], writes: &[&str], force: bool) -> Result<Writing> {
        super::check_writable(dir)?;
        let created = outermost_missing(dir);
        let folder_err = |e: std::io::Error| Error::Folder {
            path: dir.to_path_buf(),
            message: rhonn::error::path_problem(dir, &e),
        };
        let lock = lock_created(dir, &folder_err)?;
        let w = Writing {
            dir: dir.to_path_buf(),
            stage: dir.join(format!(".rhonn-stage-{}", std::process::id())),
            created,
            inputs: inputs.iter().filter_map(|p| p.canonicalize().ok()).collect(),
            force,
            _lock: lock,
            committed: false,
        };
        roll_forward(dir)?;
        super::clean_temporary(dir);
        remove_stages(dir);
        w.refuse_overwritten_inputs(writes)?;
        std::fs::create_dir(&w.stage).map_err(folder_err)?;
        Ok(w)
    }

    /// The staging folder: where the command writes its files.
    pub fn stage(&self) -> &Path {
        &self.stage
    }

    /// The output folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    fn is_input(&self, p: &Path) -> bool {
        p.canonicalize().is_ok_and(|c| self.inputs.contains(&c))
    }

    fn refuse_overwritten_inputs(&self, writes: &[&str]) -> Result<()> {
        for name in writes {
            let p = self.dir.join(name);
            if self.is_input(&p) {
                return Err(overwrites_input(&p));
            }
        }
        Ok(())
    }

    /// Decide and apply the staged set (see the module's doc); returns the final paths
    /// and the notes on the earlier run's files.
    pub fn commit(mut self) -> Result<Committed> {
        let written = files_below(&self.stage)?;
        let mut notes = Vec::new();
        let old = match Manifest::read(&self.dir) {
            Ok(m) => m,
            Err(e) => {
                notes.push(format!("note: no earlier file removed: {}", e.message()));
                None
            }
        };
        for w in &written {
            self.check_replace(w, old.as_ref())?;
        }
        let mut manifest = Manifest::of(&self.stage, &written)?;
        for e in old.iter().flat_map(|m| &m.files) {
            if written.contains(&e.path) {
                continue;
            }
            let p = self.dir.join(&e.path);
            if !p.is_file() {
                continue;
            }
            if self.is_input(&p) {
                notes.push(format!(
                    "note: kept {} (an earlier run's file, and an input of this run)",
                    p.display()
                ));
            } else if e.path == "model.json" && !self.force {
                notes.push(format!(
                    "note: kept {} (an earlier run's model; this run does not write one, and removes a model only with --force)",
                    p.display()
                ));
            } else if !old.as_ref().is_some_and(|m| m.holds(&self.dir, &e.path)) {
                notes.push(format!(
                    "note: kept {} (an earlier run's file, changed since it was written)",
                    p.display()
                ));
            } else {
                notes.push(format!(
                    "note: removed {} (an earlier run's file, which this run does not write)",
                    p.display()
                ));
                manifest.removed.push(e.path.clone());
            }
        }
        manifest.write(&self.stage)?;
        fault(1);
        let commit = self.dir.join(COMMIT);
        std::fs::rename(&self.stage, &commit).map_err(|e| Error::Folder {
            path: self.dir.clone(),
            message: format!("cannot commit the run's files: {e}"),
        })?;
        self.committed = true;
        fault(2);
        roll_forward(&self.dir)?;
        Ok(Committed {
            files: written.iter().map(|w| self.dir.join(w)).collect(),
            notes,
        })
    }

    /// Refuse, before anything moves, a staged file that would overwrite an input, a
    /// folder, or (without `force`) a different model.json or a different file that the
    /// folder's manifest `old` does not list as it is now (the user's, or edited since).
    fn check_replace(&self, w: &str, old: Option<&Manifest>) -> Result<()> {
        let target = self.dir.join(w);
        let mut parent = target.parent();
        while let Some(p) = parent {
            if p == self.dir {
                break;
            }
            if p.exists() && !p.is_dir() {
                return Err(Error::File {
                    path: p.to_path_buf(),
                    message: format!("is a file where this run writes the folder of {w}"),
                });
            }
            parent = p.parent();
        }
        if !target.exists() {
            return Ok(());
        }
        if !target.is_file() {
            return Err(Error::File {
                path: target,
                message: "is not a file, and this run writes a file of that name: move it, or give another output folder"
                    .into(),
            });
        }
        if self.is_input(&target) {
            return Err(overwrites_input(&target));
        }
        if self.force || std::fs::read(&target).ok() == std::fs::read(self.stage.join(w)).ok() {
            return Ok(());
        }
        if w == "model.json" {
            return Err(Error::File {
                path: target,
                message: "holds another model: nothing written; give --force (Python: force=True) to replace it, or another output folder"
                    .into(),
            });
        }
        if !old.is_some_and(|m| m.holds(&self.dir, w)) {
            return Err(Error::File {
                path: target,
                message: format!(
                    "exists and is not a file an earlier rhonn run wrote here ({MANIFEST} does not list it as it is now): nothing written; move it, or give another output folder"
                ),
            });
        }
        Ok(())
    }
}

impl Drop for Writing {
    fn drop(&mut self) {
        if self.committed {
            return;
        }
        let _ = std::fs::remove_dir_all(&self.stage);
        // Remove what this writing created, innermost first, while it is empty (under the
        // lock: a writer refused at the lock has no `Writing` and removes nothing).
        if let Some(top) = &self.created {
            let mut p = Some(self.dir.as_path());
            while let Some(d) = p {
                if std::fs::remove_dir(d).is_err() || d == top {
                    break;
                }
                p = d.parent();
            }
        }
    }
}

/// Create `dir` (with its missing parents) and lock it. Another writer refused at the
/// lock removes nothing, but a writer that held the lock and failed removes the empty
/// folder it created: the folder may vanish between creating and locking it, so that
/// step is retried.
fn lock_created(dir: &Path, folder_err: &dyn Fn(std::io::Error) -> Error) -> Result<FolderLock> {
    let mut tries = 0;
    loop {
        std::fs::create_dir_all(dir).map_err(folder_err)?;
        match FolderLock::acquire(dir) {
            Ok(lock) => return Ok(lock),
            Err(_) if !dir.exists() && tries < 8 => tries += 1,
            Err(e) => return Err(e),
        }
    }
}

/// Remove the staging folders of earlier runs: each was a run's that held the folder's
/// lock, which the caller holds now, so those runs have ended. Also the write probes
/// (`.rhonn-probe-PID`, `folder::check_writable`) of runs killed between creating and
/// removing one: a probe is never read, so removing one still in use costs nothing.
fn remove_stages(dir: &Path) {
    let Ok(rd) = std::fs::read_dir(dir) else { return };
    for e in rd.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        let is_dir = e.file_type().is_ok_and(|t| t.is_dir());
        if name.starts_with(".rhonn-stage-") && is_dir {
            let _ = std::fs::remove_dir_all(e.path());
        } else if name.starts_with(".rhonn-probe-") && !is_dir {
            let _ = std::fs::remove_file(e.path());
        }
    }
}

fn overwrites_input(p: &Path) -> Error {
    Error::File {
        path: p.to_path_buf(),
        message: "is an input of this run and a file it writes: give another output folder (rhonn never overwrites its own input)"
            .into(),
    }
}

/// The outermost folder of `dir` that does not exist yet (None: it exists).
fn outermost_missing(dir: &Path) -> Option<PathBuf> {
    let mut top = None;
    let mut p = Some(dir);
    while let Some(d) = p {
        if d.as_os_str().is_empty() || d.exists() {
            break;
        }
        top = Some(d.to_path_buf());
        p = d.parent();
    }
    top
}

/// A test's fault injection: abort the process at commit step `k` when
/// `RHONN_TEST_ABORT_AT_COMMIT_STEP` says so (as a kill would stop it there).
fn fault(k: usize) {
    if std::env::var("RHONN_TEST_ABORT_AT_COMMIT_STEP").is_ok_and(|v| v.trim() == k.to_string()) {
        std::process::abort();
    }
}

/// Finish a decided commit in `dir` (its `.rhonn-commit` folder), if one is there: move
/// each of its files into place, remove the files it replaces, move its manifest last.
/// The caller holds the folder's lock. Idempotent: a roll-forward killed midway is
/// finished by the next.
pub fn roll_forward(dir: &Path) -> Result<()> {
    let commit = dir.join(COMMIT);
    if !commit.is_dir() {
        return Ok(());
    }
    let fail = |p: &Path, e: std::io::Error| Error::Folder {
        path: dir.to_path_buf(),
        message: format!(
            "cannot finish the commit of an earlier run ({}): {}",
            p.display(),
            rhonn::error::path_problem(p, &e)
        ),
    };
    if let Some(m) = Manifest::read(&commit)? {
        for (k, e) in m.files.iter().enumerate() {
            let (src, dst) = (commit.join(&e.path), dir.join(&e.path));
            if src.is_file() {
                if let Some(parent) = dst.parent() {
                    std::fs::create_dir_all(parent).map_err(|e| fail(parent, e))?;
                }
                std::fs::rename(&src, &dst).map_err(|e| fail(&dst, e))?;
            }
            fault(3 + k);
        }
        for r in &m.removed {
            let p = dir.join(r);
            match std::fs::remove_file(&p) {
                Err(e) if e.kind() != std::io::ErrorKind::NotFound => return Err(fail(&p, e)),
                _ => remove_empty_parents(dir, &p),
            }
        }
        fault(3 + m.files.len());
        let src = commit.join(MANIFEST);
        std::fs::rename(&src, dir.join(MANIFEST)).map_err(|e| fail(&src, e))?;
    }
    std::fs::remove_dir_all(&commit).map_err(|e| fail(&commit, e))
}

fn remove_empty_parents(dir: &Path, file: &Path) {
    let mut p = file.parent();
    while let Some(d) = p {
        if d == dir || std::fs::remove_dir(d).is_err() {
            break;
        }
        p = d.parent();
    }
}

/// A folder that a command reads (`rhonn report`, a model's folder for `rhonn predict`):
/// an interrupted commit finished (refused while another command writes it), then every
/// file its manifest lists checked but `model.json`, which a user may edit by hand (see
/// [`Manifest::holds`]). Returns the manifest (None: the folder has none).
pub fn check_whole(dir: &Path) -> Result<Option<Manifest>> {
    if dir.join(COMMIT).is_dir() {
        let _lock = FolderLock::acquire(dir)?;
        roll_forward(dir)?;
    }
    let m = Manifest::read(dir)?;
    if let Some(m) = &m {
        m.verify_except(dir, &["model.json"])?;
    }
    Ok(m)
}
