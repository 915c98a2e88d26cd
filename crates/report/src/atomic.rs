//! Write a set of files so that either all of them appear, complete, or none does.

use crate::{Error, Result};
use std::fs::{self, File};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

/// Files staged under temporary names in one folder, renamed into place together by
/// [`OutputSet::commit`]. Dropped without a commit, the staged files are removed.
#[derive(Debug)]
pub struct OutputSet {
    dir: PathBuf,
    staged: Vec<(PathBuf, PathBuf)>,
    committed: bool,
}

impl OutputSet {
    /// Create the folder if needed and check that it can be written.
    pub fn new(dir: &Path) -> Result<Self> {
        let folder_err = |e: std::io::Error| Error::Folder {
            path: dir.to_path_buf(),
            message: rhonn::error::path_problem(dir, &e),
        };
        if dir.exists() && !dir.is_dir() {
            return Err(Error::Folder {
                path: dir.to_path_buf(),
                message: "it exists and is not a folder".into(),
            });
        }
        fs::create_dir_all(dir).map_err(folder_err)?;
        crate::folder::clean_temporary(dir);
        Ok(OutputSet {
            dir: dir.to_path_buf(),
            staged: Vec::new(),
            committed: false,
        })
    }

    /// Stage the file `name` with the bytes `f` writes.
    pub fn write(&mut self, name: &str, f: impl FnOnce(&mut dyn Write) -> std::io::Result<()>) -> Result<()> {
        let final_path = self.dir.join(name);
        // Only plain file names: whatever a name is made of, it stays in this folder.
        if name.is_empty() || name.starts_with('.') || name.contains(['/', '\\']) {
            return Err(Error::File {
                path: final_path,
                message: "not a plain file name inside the output folder".into(),
            });
        }
        let tmp = self.dir.join(format!(".{name}.tmp-{}", std::process::id()));
        let file_err = |e: std::io::Error| Error::File {
            path: final_path.clone(),
            message: rhonn::error::path_problem(&final_path, &e),
        };
        let file = File::create(&tmp).map_err(file_err)?;
        self.staged.push((tmp.clone(), final_path.clone()));
        let mut w = BufWriter::new(file);
        f(&mut w).map_err(file_err)?;
        let file = w.into_inner().map_err(|e| file_err(e.into_error()))?;
        file.sync_all().map_err(file_err)?;
        Ok(())
    }

    /// Rename every staged file into place; returns the final paths.
    pub fn commit(mut self) -> Result<Vec<PathBuf>> {
        let mut done = Vec::new();
        for (tmp, fin) in &self.staged {
            fs::rename(tmp, fin).map_err(|e| Error::File {
                path: fin.clone(),
                message: e.to_string(),
            })?;
            done.push(fin.clone());
        }
        self.committed = true;
        Ok(done)
    }
}

impl Drop for OutputSet {
    fn drop(&mut self) {
        if !self.committed {
            for (tmp, _) in &self.staged {
                let _ = fs::remove_file(tmp);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nothing_appears_until_commit_and_a_failure_leaves_nothing() {
        let d = tempfile::tempdir().unwrap();
        {
            let mut s = OutputSet::new(d.path()).unwrap();
            s.write("a.txt", |w| w.write_all(b"hello")).unwrap();
            let e = s
                .write("b.txt", |_| Err(std::io::Error::other("disk full")))
                .unwrap_err();
            assert!(e.to_string().contains("b.txt") && e.to_string().contains("disk full"));
            assert!(!d.path().join("a.txt").exists());
        }
        assert_eq!(
            fs::read_dir(d.path()).unwrap().count(),
            0,
            "temporary files are removed"
        );
        let mut s = OutputSet::new(d.path()).unwrap();
        s.write("a.txt", |w| w.write_all(b"hello")).unwrap();
        s.commit().unwrap();
        assert_eq!(fs::read_to_string(d.path().join("a.txt")).unwrap(), "hello");
    }

    #[test]
    fn a_name_with_a_path_in_it_is_refused() {
        let d = tempfile::tempdir().unwrap();
        let inner = d.path().join("in");
        let mut s = OutputSet::new(&inner).unwrap();
        for name in ["../a.txt", "", ".", "..", "sub/a.txt", "a\\b"] {
            let e = s.write(name, |w| w.write_all(b"x")).unwrap_err().to_string();
            assert!(e.contains("not a plain file name"), "{name:?}: {e}");
        }
        s.commit().unwrap();
        assert_eq!(fs::read_dir(d.path()).unwrap().count(), 1);
        assert_eq!(fs::read_dir(&inner).unwrap().count(), 0);
    }

    #[test]
    fn a_file_in_place_of_the_folder_is_a_clear_error() {
        let d = tempfile::tempdir().unwrap();
        let f = d.path().join("x");
        fs::write(&f, "").unwrap();
        let e = OutputSet::new(&f).unwrap_err().to_string();
        assert!(e.contains("is not a folder"), "{e}");
    }
}
