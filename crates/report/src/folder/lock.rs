//! One writer per output folder: an exclusive advisory lock (`flock`) on the folder
//! itself, held for the whole command and released by the system when the process ends,
//! however it ends (a killed run leaves no lock behind and no lock file in the folder).

use crate::{Error, Result};
use std::fs::File;
use std::path::{Path, PathBuf};

/// The lock of one output folder, released when dropped.
#[derive(Debug)]
pub struct FolderLock {
    _file: File,
    dir: PathBuf,
}

impl FolderLock {
    /// Lock `dir` (an existing folder) for this process, or refuse at once when another
    /// process holds it.
    pub fn acquire(dir: &Path) -> Result<FolderLock> {
        let file = open(dir).map_err(|e| Error::Folder {
            path: dir.to_path_buf(),
            message: format!("cannot lock it: {}", rhonn::error::path_problem(dir, &e)),
        })?;
        match file.try_lock() {
            Ok(()) => Ok(FolderLock {
                _file: file,
                dir: dir.to_path_buf(),
            }),
            Err(std::fs::TryLockError::WouldBlock) => Err(Error::Folder {
                path: dir.to_path_buf(),
                message: "another rhonn command is writing into it now: wait until it ends, \
                          or give another output folder"
                    .into(),
            }),
            Err(std::fs::TryLockError::Error(e)) => Err(Error::Folder {
                path: dir.to_path_buf(),
                message: format!("cannot lock it: {e}"),
            }),
        }
    }

    /// The folder locked.
    pub fn dir(&self) -> &Path {
        &self.dir
    }
}

/// The folder opened for its lock: the folder itself where the system allows it (Unix),
/// else a lock file inside it.
#[cfg(unix)]
fn open(dir: &Path) -> std::io::Result<File> {
    File::open(dir)
}

#[cfg(not(unix))]
fn open(dir: &Path) -> std::io::Result<File> {
    File::options()
        .create(true)
        .truncate(false)
        .write(true)
        .open(dir.join(".rhonn.lock"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_second_lock_on_the_same_folder_is_refused_until_the_first_is_dropped() {
        let d = tempfile::tempdir().unwrap();
        let first = FolderLock::acquire(d.path()).unwrap();
        let e = FolderLock::acquire(d.path()).unwrap_err().to_string();
        assert!(e.contains("another rhonn command is writing"), "{e}");
        drop(first);
        FolderLock::acquire(d.path()).unwrap();
        assert_eq!(
            std::fs::read_dir(d.path()).unwrap().count(),
            0,
            "no lock file left"
        );
    }
}
