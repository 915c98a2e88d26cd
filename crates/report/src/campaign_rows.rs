//! A campaign's finished runs, kept on disk: the rows stay in the files they were
//! appended to (`runs.partial.csv`, or a merge's shards' `runs.csv`) and [`Runs`] holds
//! only where each run's row is (16 bytes a run) and the traces of the runs that keep
//! them (at most `--envelope-runs`). A finish reads the rows back one at a time, so a
//! campaign of a million runs is finished in a few tens of megabytes (issue 56: memory
//! grew about 1.2 KB a run when every row was held).

use crate::Error;
use std::collections::BTreeMap;
use std::io::{Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

type Result<T, E = Error> = std::result::Result<T, E>;

// The CSV written into memory buffers: an error there is a formatting one.
impl From<csv::Error> for Error {
    fn from(e: csv::Error) -> Self {
        Error::Campaign(format!("CSV: {e}"))
    }
}

fn err(msg: String) -> Error {
    Error::Campaign(msg)
}

/// An input/output error on `path`: what was tried and what the path is.
pub fn io_err(verb: &str, path: &Path, e: std::io::Error) -> Error {
    err(format!(
        "cannot {verb} {}: {}",
        path.display(),
        rhonn::error::path_problem(path, &e)
    ))
}

/// A row's reading: whether run `index` failed, or what is wrong with its fields.
pub type RowReading<'a> = Box<dyn Fn(u64, &[String]) -> std::result::Result<bool, String> + 'a>;

/// How a campaign's rows read: `runs.csv`'s header, a row's reading (whether the run
/// failed, or what is wrong with the row, in words), and `traces.csv`'s header when the
/// campaign keeps traces.
pub struct RowFormat<'a> {
    /// `runs.csv`'s header.
    pub header: Vec<String>,
    /// A row's reading.
    pub failed: RowReading<'a>,
    /// `traces.csv`'s header, when the campaign keeps traces.
    pub traces_header: Option<Vec<String>>,
}

/// Where one run's row is: its bytes (terminator included) in one of the row files.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Place {
    start: u64,
    len: u32,
    file: u16,
    failed: bool,
}

/// A slot with no run yet.
const EMPTY: Place = Place {
    start: u64::MAX,
    len: 0,
    file: 0,
    failed: false,
};

/// The finished runs of a campaign over run indices `[first, first + places.len())`.
#[derive(Debug)]
pub struct Runs {
    files: Vec<PathBuf>,
    first: u64,
    places: Vec<Place>,
    traces: BTreeMap<u64, Vec<Vec<String>>>,
}

/// A reader of the CSV file `path`, whose header must be `want`.
pub fn reader(path: &Path, want: &[String]) -> Result<csv::Reader<std::fs::File>> {
    let mut rd = csv::ReaderBuilder::new()
        .flexible(false)
        .from_path(path)
        .map_err(|e| err(format!("cannot read {}: {e}", path.display())))?;
    let got: Vec<String> = rd
        .headers()
        .map_err(|e| err(format!("cannot read {}: {e}", path.display())))?
        .iter()
        .map(String::from)
        .collect();
    if got != want {
        return Err(err(format!(
            "{}: the header does not match this campaign's scenario",
            path.display()
        )));
    }
    Ok(rd)
}

/// Whether the byte of `path` at `at` is a line break (a row cut by a kill does not end
/// with one).
fn newline_at(path: &Path, at: u64) -> Result<bool> {
    let mut f = std::fs::File::open(path).map_err(|e| io_err("read", path, e))?;
    let mut byte = [0u8];
    f.seek(SeekFrom::Start(at))
        .and_then(|_| f.read_exact(&mut byte))
        .map_err(|e| io_err("read", path, e))?;
    Ok(byte[0] == b'\n')
}

impl Runs {
    /// The rows of `files` (each with the campaign's header) for runs in `range`: a row
    /// cut by an interruption (a field missing, or the last row read without its line
    /// break) ends its file's reading, with a note; a run outside the range, or twice, is
    /// an error (`twice` says where the two rows were looked for).
    pub fn scan(
        format: &RowFormat,
        files: Vec<PathBuf>,
        range: [u64; 2],
        twice: &str,
        notes: &mut Vec<String>,
    ) -> Result<Runs> {
        let n = usize::try_from(range[1].saturating_sub(range[0])).map_err(|_| {
            err(format!(
                "{} runs are too many for this machine",
                range[1] - range[0]
            ))
        })?;
        let mut runs = Runs {
            files,
            first: range[0],
            places: vec![EMPTY; n],
            traces: BTreeMap::new(),
        };
        let header = &format.header;
        for (file, path) in runs.files.iter().enumerate() {
            let mut rd = reader(path, header)?;
            let mut rec = csv::StringRecord::new();
            let mut last: Option<usize> = None;
            for line in 2.. {
                let start = rd.position().byte();
                match rd.read_record(&mut rec) {
                    Ok(true) => {}
                    Ok(false) => break,
                    Err(_) => {
                        notes.push(format!(
                            "warning: {} line {line}: an incomplete row is ignored",
                            path.display()
                        ));
                        break;
                    }
                }
                let fields: Vec<String> = rec.iter().map(String::from).collect();
                let at = |e: String| err(format!("{} line {line}: {e}", path.display()));
                let index = fields[0]
                    .parse::<u64>()
                    .map_err(|_| at(format!("run `{}` is not an index", fields[0])))?;
                let failed = (format.failed)(index, &fields).map_err(at)?;
                if !(range[0]..range[1]).contains(&index) {
                    return Err(at(format!(
                        "run {index} is outside this campaign's runs {} to {}",
                        range[0],
                        range[1] - 1
                    )));
                }
                let slot = (index - range[0]) as usize;
                if runs.places[slot] != EMPTY {
                    return Err(err(format!("run {index} appears twice {twice}")));
                }
                let len = u32::try_from(rd.position().byte() - start)
                    .map_err(|_| at("a row longer than 4 GB".into()))?;
                runs.places[slot] = Place {
                    start,
                    len,
                    file: file as u16,
                    failed,
                };
                last = Some(slot);
            }
            // Only the last row read can have been cut at its end (the rows before it
            // end where the next one starts, after a line break).
            if let Some(slot) = last {
                let p = runs.places[slot];
                if p.len == 0 || !newline_at(path, p.start + u64::from(p.len) - 1)? {
                    runs.places[slot] = EMPTY;
                    notes.push(format!(
                        "warning: {}: its last row was cut and is ignored",
                        path.display()
                    ));
                }
            }
        }
        Ok(runs)
    }

    /// Attach the rows of a traces file (if the campaign keeps traces and the file
    /// exists) to their runs; rows of runs not held are dropped (a kill between the two
    /// files).
    pub fn attach_traces(&mut self, format: &RowFormat, path: &Path) -> Result<()> {
        let Some(header) = &format.traces_header else {
            return Ok(());
        };
        if !path.exists() {
            return Ok(());
        }
        let mut rd = reader(path, header)?;
        for rec in rd.records() {
            let Ok(rec) = rec else { break };
            let Ok(index) = rec[0].parse::<u64>() else { break };
            if self.place(index).is_some() {
                self.traces
                    .entry(index)
                    .or_default()
                    .push(rec.iter().map(String::from).collect());
            }
        }
        Ok(())
    }

    /// Forget the runs that should have traces (`wants(index, failed)`) and have none
    /// (they are run again).
    pub fn drop_runs_without_traces(&mut self, wants: impl Fn(u64, bool) -> bool) {
        for (k, p) in self.places.iter_mut().enumerate() {
            let index = self.first + k as u64;
            if *p != EMPTY && wants(index, p.failed) && !self.traces.contains_key(&index) {
                *p = EMPTY;
            }
        }
    }

    fn place(&self, index: u64) -> Option<Place> {
        let k = usize::try_from(index.checked_sub(self.first)?).ok()?;
        self.places.get(k).copied().filter(|p| *p != EMPTY)
    }

    /// Whether run `index` is held.
    pub fn has(&self, index: u64) -> bool {
        self.place(index).is_some()
    }

    /// How many runs are held.
    pub fn len(&self) -> usize {
        self.places.iter().filter(|p| **p != EMPTY).count()
    }

    /// Whether no run is held.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// How many of them failed.
    pub fn failed(&self) -> usize {
        self.places.iter().filter(|p| **p != EMPTY && p.failed).count()
    }

    /// Whether every run of the range is held.
    pub fn complete(&self) -> bool {
        self.places.iter().all(|p| *p != EMPTY)
    }

    /// The traces' rows, in run order.
    pub fn traces(&self) -> impl Iterator<Item = &Vec<String>> {
        self.traces.values().flatten()
    }

    /// Every held run's row as `f(index, fields, failed)`, in the files' order (not the
    /// runs': what is read this way must not depend on the order), each file read
    /// straight through.
    pub fn for_each(&self, mut f: impl FnMut(u64, &[String], bool) -> Result<()>) -> Result<()> {
        for (file, path) in self.files.iter().enumerate() {
            let mut rd = csv::ReaderBuilder::new()
                .flexible(true)
                .from_path(path)
                .map_err(|e| err(format!("cannot read {}: {e}", path.display())))?;
            // The header first, so that the positions are those the scan saw.
            rd.headers()
                .map_err(|e| err(format!("cannot read {}: {e}", path.display())))?;
            let mut rec = csv::StringRecord::new();
            loop {
                let start = rd.position().byte();
                // Rows past a cut one were never held: stop there as the scan did.
                if !matches!(rd.read_record(&mut rec), Ok(true)) {
                    break;
                }
                let Some(index) = rec.get(0).and_then(|s| s.parse::<u64>().ok()) else {
                    continue;
                };
                match self.place(index) {
                    Some(p) if usize::from(p.file) == file && p.start == start => {
                        let fields: Vec<String> = rec.iter().map(String::from).collect();
                        f(index, &fields, p.failed)?;
                    }
                    _ => {}
                }
            }
        }
        Ok(())
    }

    /// Every held run's row as written, in run order, after `header`: `runs.csv` (the
    /// same bytes as the rows written one by one).
    pub fn write_csv(&self, header: &[String], w: &mut dyn Write) -> std::io::Result<()> {
        {
            let mut c = csv::Writer::from_writer(&mut *w);
            c.write_record(header)?;
            c.flush()?;
        }
        let mut files = self.open().map_err(std::io::Error::other)?;
        let mut buf = Vec::new();
        for p in self.places.iter().filter(|p| **p != EMPTY) {
            self.read(&mut files, p, &mut buf)
                .map_err(std::io::Error::other)?;
            w.write_all(&buf)?;
        }
        Ok(())
    }

    fn open(&self) -> Result<Vec<std::fs::File>> {
        self.files
            .iter()
            .map(|p| std::fs::File::open(p).map_err(|e| io_err("read", p, e)))
            .collect()
    }

    fn read(&self, files: &mut [std::fs::File], p: &Place, buf: &mut Vec<u8>) -> Result<()> {
        let path = &self.files[p.file as usize];
        let f = &mut files[p.file as usize];
        buf.resize(p.len as usize, 0);
        f.seek(SeekFrom::Start(p.start))
            .and_then(|_| f.read_exact(buf))
            .map_err(|e| io_err("read", path, e))
    }
}

/// Each figure's statistics and its histogram panel (when `shown(name)`), one figure at a
/// time: a pass over the runs each, so that one figure's values are in memory at once.
/// Figure `k` of a finished run is its field `first + k` (a value that does not read, or is
/// not finite, is left out of both).
pub fn figure_statistics(
    runs: &Runs,
    (names, first): (&[String], usize),
    scenario: &str,
    shown: impl Fn(&str) -> bool,
) -> Result<(
    Vec<rhonn::experiment::campaign::FigureStats>,
    Vec<crate::Histogram>,
)> {
    let mut stats = Vec::new();
    let mut panels = Vec::new();
    for (k, name) in names.iter().enumerate() {
        let mut v = Vec::new();
        runs.for_each(|_, fields, failed| {
            if !failed {
                v.extend(fields.get(first + k).and_then(|x| x.parse::<f64>().ok()));
            }
            Ok(())
        })?;
        if shown(name) {
            panels.push(crate::Histogram::new(
                format!("{scenario}: {name}"),
                name.clone(),
                &v,
                30,
            ));
        }
        stats.push(rhonn::experiment::campaign::figure_stats(name, v));
    }
    Ok((stats, panels))
}
