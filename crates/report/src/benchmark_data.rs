//! The shipped benchmarks' data (`data/benchmarks/NAME/`): `benchmark.toml` (the protocol:
//! columns, start-up window, test sets, published figures) and its CSV files, gzip-
//! compressed or plain. A file's time column is `t_s` or `t`; without one, `k` (the
//! sample index) times the protocol's `sample_time_s`. A `record` column splits a file
//! into records. Every error names the file, and the line and column where it applies.

use crate::{Error, Result};
use rhonn::benchmark::{Benchmark, BenchmarkSpec};
use rhonn::data::Record;
use std::io::Read;
use std::path::Path;

/// The benchmarks in `dir`: every sub-folder holding a `benchmark.toml`, by name.
pub fn available(dir: &Path) -> Result<Vec<String>> {
    let entries = std::fs::read_dir(dir).map_err(|e| {
        Error::Input(format!(
            "cannot read the benchmarks' folder {}: {} (run from the repository's root, or give --data-dir)",
            dir.display(),
            rhonn::error::path_problem(dir, &e)
        ))
    })?;
    let mut names: Vec<String> = entries
        .filter_map(|e| e.ok())
        .filter(|e| e.path().join("benchmark.toml").is_file())
        .filter_map(|e| e.file_name().to_str().map(str::to_string))
        .collect();
    names.sort();
    Ok(names)
}

/// Load the benchmark `name` from `dir/name/`.
pub fn load(dir: &Path, name: &str) -> Result<Benchmark> {
    let folder = dir.join(name);
    let toml_path = folder.join("benchmark.toml");
    let text = rhonn::error::read_text(&toml_path).map_err(|e| {
        // What the user can pick instead: the folder's benchmarks, or why there are none
        // (a folder that cannot be read says so, and how to give another).
        let known = match available(dir) {
            Err(folder) => return folder,
            Ok(v) if v.is_empty() => format!(
                "{} holds no benchmark (a folder per benchmark with its benchmark.toml)",
                dir.display()
            ),
            Ok(v) => format!("the benchmarks in {}: {}", dir.display(), v.join(", ")),
        };
        Error::Input(format!(
            "no benchmark `{name}`: cannot read {} ({}); {known}",
            toml_path.display(),
            rhonn::error::path_problem(&toml_path, &e),
        ))
    })?;
    let spec: BenchmarkSpec = toml::from_str(&text)
        .map_err(|e| Error::Input(format!("cannot read {}: {e}", toml_path.display())))?;
    let file = |f: &str| folder.join(f);
    let train = read_records(&file(&spec.train), &spec, None, None)?;
    let tests = spec
        .test
        .iter()
        .map(|t| {
            let mut recs = read_records(&file(&t.file), &spec, t.record, t.rows)?;
            if recs.len() != 1 {
                return Err(Error::Input(format!(
                    "{}: test `{}` holds {} records; give `record = N` to pick one",
                    toml_path.display(),
                    t.label,
                    recs.len()
                )));
            }
            Ok(recs.remove(0))
        })
        .collect::<Result<Vec<_>>>()?;
    let b = Benchmark {
        name: name.to_string(),
        spec,
        train,
        tests,
    };
    b.check()
        .map_err(|e| Error::Input(format!("{}: {e}", toml_path.display())))?;
    Ok(b)
}

/// The text of a file, decompressed when its name ends in `.gz`.
fn read_text(path: &Path) -> Result<String> {
    let fail = |e: std::io::Error| {
        Error::Input(format!(
            "cannot read {}: {}",
            path.display(),
            rhonn::error::path_problem(path, &e)
        ))
    };
    let mut f = std::fs::File::open(path).map_err(fail)?;
    let mut text = String::new();
    if path.extension().is_some_and(|x| x == "gz") {
        flate2::read::GzDecoder::new(f)
            .read_to_string(&mut text)
            .map_err(fail)?;
    } else {
        f.read_to_string(&mut text).map_err(fail)?;
    }
    Ok(text)
}

/// The records of a benchmark file: all, or the rows of `record`, at most `rows` rows.
fn read_records(
    path: &Path,
    spec: &BenchmarkSpec,
    record: Option<i64>,
    rows: Option<usize>,
) -> Result<Vec<Record>> {
    let text = read_text(path)?;
    let source = path.display().to_string();
    let mut rd = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let header: Vec<String> = rd
        .headers()
        .map_err(|e| Error::Input(format!("cannot read {source}: {e}")))?
        .iter()
        .map(str::to_string)
        .collect();
    let col = |name: &str| header.iter().position(|h| h == name);
    let need = |name: &String| {
        col(name).ok_or_else(|| {
            Error::Input(format!(
                "{source}: no column `{name}` (columns: {})",
                header.join(", ")
            ))
        })
    };
    let ins: Vec<usize> = spec.inputs.iter().map(need).collect::<Result<_>>()?;
    let outs: Vec<usize> = spec.outputs.iter().map(need).collect::<Result<_>>()?;
    let time = match (col("t_s").or(col("t")), col("k"), spec.sample_time_s) {
        (Some(c), _, _) => Time::Column(c),
        (None, Some(k), Some(dt)) if dt.is_finite() && dt > 0.0 => Time::Index(k, dt),
        _ => {
            return Err(Error::Input(format!(
                "{source}: no time column (`t_s` or `t`), and no `k` with the protocol's `sample_time_s`"
            )))
        }
    };
    let rec_col = col("record");
    let mut out: Vec<(i64, Record)> = Vec::new();
    for (line, row) in rd.records().enumerate() {
        let line = line + 2;
        let row = row.map_err(|e| Error::Input(format!("{source}, line {line}: {e}")))?;
        let num = |c: usize| -> Result<f64> {
            let cell = row.get(c).unwrap_or("");
            cell.parse::<f64>().ok().filter(|v| v.is_finite()).ok_or_else(|| {
                Error::Input(format!(
                    "{source}, line {line}, column `{}`: `{cell}` is not a finite number",
                    header[c]
                ))
            })
        };
        let id = match rec_col {
            Some(c) => num(c)? as i64,
            None => 0,
        };
        if record.is_some_and(|r| r != id) {
            continue;
        }
        let r = match out.last_mut() {
            Some((k, r)) if *k == id => r,
            _ => {
                out.push((id, empty(&source, id, rec_col.is_some(), spec)));
                &mut out
                    .last_mut()
                    .ok_or_else(|| Error::Input(format!("{source}: no record")))?
                    .1
            }
        };
        if rows.is_some_and(|n| r.len() >= n) {
            continue;
        }
        r.t.push(match time {
            Time::Column(c) => num(c)?,
            Time::Index(k, dt) => num(k)? * dt,
        });
        for (v, &c) in r.inputs.iter_mut().zip(&ins) {
            v.push(num(c)?);
        }
        for (v, &c) in r.outputs.iter_mut().zip(&outs) {
            v.push(num(c)?);
        }
    }
    if out.is_empty() {
        return Err(Error::Input(format!(
            "{source}: no rows{}",
            record.map_or(String::new(), |r| format!(" of record {r}"))
        )));
    }
    Ok(out.into_iter().map(|(_, r)| r).collect())
}

#[derive(Clone, Copy)]
enum Time {
    Column(usize),
    Index(usize, f64),
}

fn empty(source: &str, id: i64, split: bool, spec: &BenchmarkSpec) -> Record {
    Record {
        source: if split {
            format!("{source} (record {id})")
        } else {
            source.to_string()
        },
        t: Vec::new(),
        inputs: vec![Vec::new(); spec.inputs.len()],
        outputs: vec![Vec::new(); spec.outputs.len()],
    }
}
