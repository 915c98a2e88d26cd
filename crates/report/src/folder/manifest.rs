//! `rhonn-manifest.json`: the files one run wrote into its output folder, each with its
//! size and CRC-32, written last. It is what a later run may remove (only files it lists,
//! unchanged since), and what ties a folder's files to one run: `rhonn report` and
//! `rhonn predict` refuse a folder whose files no longer match it.

use crate::{Error, Result};
use serde::{Deserialize, Serialize};
use std::io::Read;
use std::path::{Path, PathBuf};

/// The manifest's file name.
pub const MANIFEST: &str = "rhonn-manifest.json";

/// One file a run wrote, by its path inside the folder (`/`-separated).
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Entry {
    /// The path inside the output folder.
    pub path: String,
    /// Its size.
    pub bytes: u64,
    /// Its CRC-32 (`crc32fast`): a check against mixed or edited files, not a signature.
    pub crc32: u32,
}

/// What one run wrote into its output folder.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Manifest {
    /// The rhonn that wrote it.
    pub rhonn_version: String,
    /// The files the run wrote, sorted by path (this manifest not included).
    pub files: Vec<Entry>,
    /// The files of the earlier run in the folder that this run removed (listed by the
    /// earlier manifest, unchanged, not an input, not written again).
    #[serde(default)]
    pub removed: Vec<String>,
}

impl Manifest {
    /// The manifest of `paths` (inside `root`, `/`-separated) as they are now.
    pub fn of(root: &Path, paths: &[String]) -> Result<Manifest> {
        let mut files = paths.iter().map(|p| entry(root, p)).collect::<Result<Vec<_>>>()?;
        files.sort_by(|a, b| a.path.cmp(&b.path));
        Ok(Manifest {
            rhonn_version: env!("CARGO_PKG_VERSION").to_string(),
            files,
            removed: Vec::new(),
        })
    }

    /// The manifest in `dir`, if any. An unreadable one is an error naming it.
    pub fn read(dir: &Path) -> Result<Option<Manifest>> {
        let path = dir.join(MANIFEST);
        let text = match std::fs::read_to_string(&path) {
            Ok(t) => t,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(e) => {
                return Err(Error::File {
                    message: rhonn::error::path_problem(&path, &e),
                    path,
                })
            }
        };
        let m: Manifest = serde_json::from_str(&text).map_err(|e| Error::File {
            path: path.clone(),
            message: format!("not a manifest rhonn wrote ({e}): remove it, or write the folder again"),
        })?;
        for f in m.files.iter().map(|e| &e.path).chain(&m.removed) {
            inside(f).map_err(|why| Error::File {
                path: path.clone(),
                message: format!("lists `{f}`, {why}"),
            })?;
        }
        Ok(Some(m))
    }

    /// Write the manifest into `dir` (a folder no other reader sees yet).
    pub fn write(&self, dir: &Path) -> Result<()> {
        let path = dir.join(MANIFEST);
        let mut text = serde_json::to_string_pretty(self).map_err(|e| Error::Input(e.to_string()))?;
        text.push('\n');
        std::fs::write(&path, text).map_err(|e| Error::File {
            message: rhonn::error::path_problem(&path, &e),
            path,
        })
    }

    /// Whether the file at `path` (inside `dir`) is still the one this manifest lists.
    pub fn holds(&self, dir: &Path, path: &str) -> bool {
        self.files
            .iter()
            .find(|e| e.path == path)
            .is_some_and(|e| entry(dir, path).is_ok_and(|now| &now == e))
    }

    /// Check that every file it lists in `dir` is still the one its run wrote: the folder
    /// is whole, from one run.
    pub fn verify(&self, dir: &Path) -> Result<()> {
        self.verify_except(dir, &[])
    }

    /// [`Manifest::verify`] but for the files named in `edited` (a user may edit a
    /// `model.json` by hand: it is read as it is now).
    pub fn verify_except(&self, dir: &Path, edited: &[&str]) -> Result<()> {
        for e in self.files.iter().filter(|e| !edited.contains(&e.path.as_str())) {
            let full = dir.join(&e.path);
            let why = match entry(dir, &e.path) {
                Err(_) => "is missing".to_string(),
                Ok(now) if now == *e => continue,
                Ok(now) => format!(
                    "is not the file the folder's run wrote ({} bytes, CRC-32 {:08x}; {MANIFEST} lists {} bytes, {:08x})",
                    now.bytes, now.crc32, e.bytes, e.crc32
                ),
            };
            return Err(Error::Folder {
                path: dir.to_path_buf(),
                message: format!(
                    "{} {why}: the folder mixes files of different runs, or was edited; write it again \
                     with the command that made it",
                    full.display()
                ),
            });
        }
        Ok(())
    }
}

/// Why `p` is not a plain relative path inside a folder, if it is not.
fn inside(p: &str) -> std::result::Result<(), &'static str> {
    let ok = !p.is_empty()
        && !p.starts_with('/')
        && !p.contains('\\')
        && p.split('/').all(|c| !c.is_empty() && c != "." && c != "..");
    if ok {
        Ok(())
    } else {
        Err("which is not a path inside the folder")
    }
}

/// The size and CRC-32 of `root/path`.
fn entry(root: &Path, path: &str) -> Result<Entry> {
    let full = root.join(path);
    let io = |e: std::io::Error| Error::File {
        path: full.clone(),
        message: rhonn::error::path_problem(&full, &e),
    };
    let mut f = std::fs::File::open(&full).map_err(io)?;
    let mut h = crc32fast::Hasher::new();
    let mut buf = vec![0u8; 1 << 16];
    let mut bytes = 0u64;
    loop {
        let n = f.read(&mut buf).map_err(io)?;
        if n == 0 {
            break;
        }
        bytes += n as u64;
        h.update(&buf[..n]);
    }
    Ok(Entry {
        path: path.to_string(),
        bytes,
        crc32: h.finalize(),
    })
}

/// Every file below `root`, as `/`-separated paths, sorted.
pub fn files_below(root: &Path) -> Result<Vec<String>> {
    let mut out = Vec::new();
    let mut todo: Vec<(PathBuf, String)> = vec![(root.to_path_buf(), String::new())];
    while let Some((dir, prefix)) = todo.pop() {
        let rd = std::fs::read_dir(&dir).map_err(|e| Error::Folder {
            path: dir.clone(),
            message: rhonn::error::path_problem(&dir, &e),
        })?;
        for e in rd.flatten() {
            let name = e.file_name().to_string_lossy().into_owned();
            let rel = format!("{prefix}{name}");
            match e.file_type() {
                Ok(t) if t.is_dir() => todo.push((e.path(), format!("{rel}/"))),
                Ok(t) if t.is_file() => out.push(rel),
                _ => {}
            }
        }
    }
    out.sort();
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_changed_or_missing_file_fails_the_check_and_names_it() {
        let d = tempfile::tempdir().unwrap();
        std::fs::create_dir(d.path().join("sub")).unwrap();
        std::fs::write(d.path().join("a.csv"), "1,2\n").unwrap();
        std::fs::write(d.path().join("sub/b.svg"), "<svg/>").unwrap();
        let paths = files_below(d.path()).unwrap();
        assert_eq!(paths, ["a.csv", "sub/b.svg"]);
        let m = Manifest::of(d.path(), &paths).unwrap();
        m.write(d.path()).unwrap();
        let back = Manifest::read(d.path()).unwrap().unwrap();
        assert_eq!(back, m);
        back.verify(d.path()).unwrap();
        assert!(back.holds(d.path(), "a.csv"));
        std::fs::write(d.path().join("a.csv"), "1,3\n").unwrap();
        assert!(!back.holds(d.path(), "a.csv"));
        let e = back.verify(d.path()).unwrap_err().to_string();
        assert!(
            e.contains("a.csv is not the file") && e.contains("mixes files"),
            "{e}"
        );
        std::fs::remove_file(d.path().join("a.csv")).unwrap();
        let e = back.verify(d.path()).unwrap_err().to_string();
        assert!(e.contains("a.csv is missing"), "{e}");
    }

    #[test]
    fn a_manifest_naming_a_path_outside_its_folder_is_refused() {
        let d = tempfile::tempdir().unwrap();
        for bad in ["../x", "/etc/passwd", "a//b", "", "a/./b", "a\\b"] {
            let m = Manifest {
                rhonn_version: "0.1.0".into(),
                files: vec![Entry {
                    path: bad.into(),
                    bytes: 0,
                    crc32: 0,
                }],
                removed: vec![],
            };
            m.write(d.path()).unwrap();
            let e = Manifest::read(d.path()).unwrap_err().to_string();
            assert!(e.contains("not a path inside the folder"), "{bad}: {e}");
        }
        std::fs::write(d.path().join(MANIFEST), "{").unwrap();
        let e = Manifest::read(d.path()).unwrap_err().to_string();
        assert!(e.contains("not a manifest rhonn wrote"), "{e}");
    }
}
