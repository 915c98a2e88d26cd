//! Measured data in: CSV files with a header, a time column `t` \[s\] and numeric
//! columns. Every problem names the file, the line and the column.

use rhonn::data::Record;
use std::path::Path;

/// What is wrong with a data file.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum DataError {
    /// The file cannot be opened or read.
    #[error("{file}: cannot read: {message}")]
    Unreadable {
        /// File.
        file: String,
        /// Message.
        message: String,
    },
    /// A requested column is not in the header.
    #[error(
        "{file}: no column `{column}` in the header (columns: {available}){}",
        delimiter_hint(available, column)
    )]
    MissingColumn {
        /// File.
        file: String,
        /// Column asked for.
        column: String,
        /// Columns present.
        available: String,
    },
    /// A column the command reads is named twice in the header.
    #[error("{file}: column `{column}` appears twice in the header (columns {first} and {second}): rename one, so that it is clear which is meant")]
    DuplicateColumn {
        /// File.
        file: String,
        /// The name.
        column: String,
        /// Its first position (1-based).
        first: usize,
        /// Its second position (1-based).
        second: usize,
    },
    /// A cell is not a number, not finite, or so large that its square overflows.
    #[error("{file}, line {line}, column `{column}`: {}", cell_problem(value))]
    BadCell {
        /// File.
        file: String,
        /// Line (1-based, the header is line 1).
        line: u64,
        /// Column.
        column: String,
        /// The cell.
        value: String,
    },
    /// Time does not increase.
    #[error("{file}, line {line}, column `{column}`: time {t} does not increase (previous {previous})")]
    TimeNotIncreasing {
        /// File.
        file: String,
        /// Line.
        line: u64,
        /// The time column.
        column: String,
        /// This time.
        t: f64,
        /// The previous one.
        previous: f64,
    },
    /// Too few rows.
    #[error("{file}: {rows} data rows; at least {min} are needed")]
    TooFew {
        /// File.
        file: String,
        /// Rows found.
        rows: usize,
        /// Needed.
        min: usize,
    },
}

/// The largest magnitude a cell may have (`rhonn::data::MAX_MAGNITUDE`).
pub use rhonn::data::MAX_MAGNITUDE;

/// A hint when the header looks separated by something other than commas (`;` files often
/// write decimal commas: the conversion then turns those into points first), or when the
/// missing column is the time and another looks like it.
fn delimiter_hint(available: &str, column: &str) -> String {
    if let Some(c) = [';', '\t', '|'].into_iter().find(|c| available.contains(*c)) {
        let convert = if c == ';' {
            "e.g. with `sed 's/,/./g; s/;/,/g'`, which also turns decimal commas into points".to_string()
        } else {
            format!("e.g. with `tr '{c}' ','`")
        };
        return format!(": the header holds {c:?}, so the file looks separated by {c:?}; rhonn reads comma-separated files with decimal points (convert it, {convert})");
    }
    let time_like = available
        .split(", ")
        .find(|h| ["time", "time_s", "t_s", "seconds", "timestamp"].contains(&h.to_lowercase().as_str()));
    match time_like {
        Some(h) if column == "t" => format!(
            ": the time column is `t`, in seconds; `{h}` looks like it: give `--time-column {h}` (its values in seconds) or rename it `t`"
        ),
        _ => String::new(),
    }
}

/// A cell's number: finite and of magnitude at most [`MAX_MAGNITUDE`] (None otherwise, which
/// `DataError::BadCell` words), for files and streams alike.
pub fn cell_value(s: &str) -> Option<f64> {
    s.parse::<f64>()
        .ok()
        .filter(|v| v.is_finite() && v.abs() <= MAX_MAGNITUDE)
}

/// What is wrong with a cell that is not a usable number, and what to write instead.
fn cell_problem(value: &str) -> String {
    let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
    let unsigned = value.trim_start_matches(['+', '-']);
    let parts: Vec<&str> = unsigned.split(',').collect();
    if value.is_empty() {
        return "the cell is empty: every row needs a number in every column read (fill the missing sample, or cut the record there into two files)".into();
    }
    if parts.len() == 2 && digits(parts[0]) && parts[1].len() != 3 && digits(parts[1]) {
        return format!(
            "`{value}` has a decimal comma: write it with a decimal point, `{}`",
            value.replace(',', ".")
        );
    }
    if parts.len() >= 2 && digits(parts[0]) && parts[0].len() <= 3 {
        let (last, decimals) = parts[parts.len() - 1]
            .split_once('.')
            .unwrap_or((parts[parts.len() - 1], ""));
        let groups = parts[1..parts.len() - 1]
            .iter()
            .all(|g| g.len() == 3 && digits(g));
        if groups && last.len() == 3 && digits(last) && (decimals.is_empty() || digits(decimals)) {
            return format!(
                "`{value}` holds a comma: if it is a thousands separator write `{}`, if a decimal comma `{}` (rhonn reads numbers with a decimal point and no separators)",
                value.replace(',', ""),
                value.replace(',', ".")
            );
        }
    }
    match value.parse::<f64>() {
        Ok(v) if !v.is_finite() => format!("`{value}` is not a finite number: give a number (a missing sample: cut the record there into two files)"),
        Ok(_) => format!("`{value}` is beyond the magnitude at most 1e150 a cell may have (its square overflows): rescale the column"),
        Err(_) => format!("`{value}` is not a number: give a number with a decimal point (e.g. `1.5`, `-2e-3`)"),
    }
}

/// Read `t`, the `inputs` and the `outputs` columns of a CSV file.
pub fn read_record(
    path: &Path,
    inputs: &[String],
    outputs: &[String],
    min_rows: usize,
) -> Result<Record, DataError> {
    read_record_timed(path, "t", inputs, outputs, min_rows)
}

/// The CSV reader of `path` (through its gzip decoder for a `.gz`) and its header;
/// `file` names it in errors.
fn open_csv(path: &Path, file: &str) -> Result<(CsvReader, Vec<String>), DataError> {
    let unreadable = |e: &dyn std::fmt::Display| DataError::Unreadable {
        file: file.to_string(),
        message: e.to_string(),
    };
    if path.is_dir() {
        return Err(unreadable(&"it is a directory, not a file"));
    }
    let f = std::fs::File::open(path).map_err(|e| unreadable(&rhonn::error::path_problem(path, &e)))?;
    // A gzip file (how the benchmarks ship their records) is read through its decoder.
    let f: Box<dyn std::io::Read> = if path.extension().is_some_and(|e| e == "gz") {
        Box::new(flate2::read::GzDecoder::new(f))
    } else {
        Box::new(f)
    };
    let mut rd = csv::ReaderBuilder::new()
        .has_headers(true)
        .trim(csv::Trim::All)
        .from_reader(rhonn::error::LineLimited::new(f));
    let header: Vec<String> = rd
        .headers()
        .map_err(|e| unreadable(&e))?
        .iter()
        .map(|s| s.to_string())
        .collect();
    Ok((rd, header))
}

/// The column names of a CSV file's header (plain or gzip).
pub fn csv_header(path: &Path) -> Result<Vec<String>, DataError> {
    open_csv(path, &path.display().to_string()).map(|(_, h)| h)
}

/// A CSV reader of a file, plain or gzip.
type CsvReader = csv::Reader<rhonn::error::LineLimited<Box<dyn std::io::Read>>>;

/// The index of column `name` in `header`: an error naming `file` when it is missing or
/// twice there.
fn column_index(header: &[String], name: &str, file: &str) -> Result<usize, DataError> {
    let mut at = header
        .iter()
        .enumerate()
        .filter(|(_, h)| *h == name)
        .map(|(k, _)| k);
    match (at.next(), at.next()) {
        (Some(first), Some(second)) => Err(DataError::DuplicateColumn {
            file: file.to_string(),
            column: name.to_string(),
            first: first + 1,
            second: second + 1,
        }),
        (Some(first), None) => Ok(first),
        (None, _) => Err(DataError::MissingColumn {
            file: file.to_string(),
            column: name.to_string(),
            available: header.join(", "),
        }),
    }
}

/// [`read_record`] with the time \[s\] in the column `time` (`--time-column`).
pub fn read_record_timed(
    path: &Path,
    time: &str,
    inputs: &[String],
    outputs: &[String],
    min_rows: usize,
) -> Result<Record, DataError> {
    let file = path.display().to_string();
    let unreadable = |e: &dyn std::fmt::Display| DataError::Unreadable {
        file: file.clone(),
        message: e.to_string(),
    };
    let (mut rd, header) = open_csv(path, &file)?;
    let find = |name: &str| column_index(&header, name, &file);
    let it = find(time)?;
    let ii: Vec<usize> = inputs.iter().map(|c| find(c)).collect::<Result<_, _>>()?;
    let io: Vec<usize> = outputs.iter().map(|c| find(c)).collect::<Result<_, _>>()?;
    let mut rec = Record {
        source: file.clone(),
        t: vec![],
        inputs: vec![vec![]; inputs.len()],
        outputs: vec![vec![]; outputs.len()],
    };
    for (row, result) in rd.records().enumerate() {
        let line = row as u64 + 2;
        let r = result.map_err(|e| match e.kind() {
            csv::ErrorKind::UnequalLengths { len, .. } => unreadable(&format!(
                "line {line}: {len} fields where the header has {}: a decimal comma or a thousands separator splits a number in two in a comma-separated file (write numbers with a decimal point and no separators)",
                header.len()
            )),
            _ => unreadable(&e),
        })?;
        let cell = |idx: usize| -> Result<f64, DataError> {
            let s = r.get(idx).unwrap_or("");
            match cell_value(s) {
                Some(v) => Ok(v),
                None => Err(DataError::BadCell {
                    file: file.clone(),
                    line,
                    column: header[idx].clone(),
                    value: s.to_string(),
                }),
            }
        };
        let t = cell(it)?;
        if let Some(&prev) = rec.t.last() {
            if t <= prev {
                return Err(DataError::TimeNotIncreasing {
                    file: file.clone(),
                    line,
                    column: time.to_string(),
                    t,
                    previous: prev,
                });
            }
        }
        rec.t.push(t);
        for (k, &c) in ii.iter().enumerate() {
            rec.inputs[k].push(cell(c)?);
        }
        for (k, &c) in io.iter().enumerate() {
            rec.outputs[k].push(cell(c)?);
        }
    }
    if rec.len() < min_rows {
        return Err(DataError::TooFew {
            file,
            rows: rec.len(),
            min: min_rows,
        });
    }
    Ok(rec)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn write(d: &tempfile::TempDir, text: &str) -> std::path::PathBuf {
        let p = d.path().join("d.csv");
        std::fs::write(&p, text).unwrap();
        p
    }

    #[test]
    fn a_column_named_twice_in_the_header_is_refused_naming_both_positions() {
        let d = tempfile::tempdir().unwrap();
        let s = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
        for (text, name, at) in [
            ("t,u,y,y\n0,1,2,3\n1,1,2,3\n", "y", "columns 3 and 4"),
            ("t,u,t,y\n0,1,2,3\n1,1,2,3\n", "t", "columns 1 and 3"),
        ] {
            let p = write(&d, text);
            let e = read_record(&p, &s(&["u"]), &s(&["y"]), 1)
                .unwrap_err()
                .to_string();
            assert!(
                e.contains(&format!("column `{name}` appears twice")) && e.contains(at),
                "{e}"
            );
        }
        // A duplicate the command does not read is no matter.
        let p = write(&d, "t,u,y,x,x\n0,1,2,3,3\n1,1,2,3,3\n");
        read_record(&p, &s(&["u"]), &s(&["y"]), 1).unwrap();
    }

    #[test]
    fn reads_and_names_every_problem() {
        let d = tempfile::tempdir().unwrap();
        let s = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
        let p = write(&d, "t,u,y\n0,1,2\n1,1.5,2.5\n2,2,3\n");
        let r = read_record(&p, &s(&["u"]), &s(&["y"]), 2).unwrap();
        assert_eq!(r.t, vec![0.0, 1.0, 2.0]);
        assert_eq!(r.outputs[0], vec![2.0, 2.5, 3.0]);
        let e = read_record(&p, &s(&["v"]), &s(&["y"]), 2)
            .unwrap_err()
            .to_string();
        assert!(
            e.ends_with("no column `v` in the header (columns: t, u, y)"),
            "{e}"
        );
        let p = write(&d, "t,u,y\n0,1,2\n1,abc,2.5\n");
        let e = read_record(&p, &s(&["u"]), &s(&["y"]), 1)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("d.csv, line 3, column `u`: `abc` is not a number"),
            "{e}"
        );
        let p = write(&d, "t,u,y\n0,1,2\n1,1,NaN\n");
        assert!(read_record(&p, &s(&["u"]), &s(&["y"]), 1)
            .unwrap_err()
            .to_string()
            .contains("line 3, column `y`: `NaN`"));
        let p = write(&d, "t,u,y\n0,1,2\n0,1,2\n");
        let e = read_record(&p, &s(&["u"]), &s(&["y"]), 1)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("line 3, column `t`: time 0 does not increase (previous 0)"),
            "{e}"
        );
        let p = write(&d, "t,u,y\n0,1,2\n");
        let e = read_record(&p, &s(&["u"]), &s(&["y"]), 10)
            .unwrap_err()
            .to_string();
        assert!(e.ends_with("1 data rows; at least 10 are needed"), "{e}");
    }

    #[test]
    fn values_whose_squares_overflow_and_other_delimiters_are_named() {
        // Issue 33: a 1.7e308 cell hung the plots of identify and predict.
        let d = tempfile::tempdir().unwrap();
        let s = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
        let p = write(&d, "t,u,y\n0,1,2\n1,1,1.7e308\n2,1,2\n");
        let e = read_record(&p, &s(&["u"]), &s(&["y"]), 1)
            .unwrap_err()
            .to_string();
        assert!(e.contains("d.csv, line 3, column `y`: `1.7e308`"), "{e}");
        assert!(e.contains("magnitude at most 1e150"), "{e}");
        let p = write(&d, "t,u,y\n0,1,2\n1,1,-1e151\n");
        assert!(read_record(&p, &s(&["u"]), &s(&["y"]), 1).is_err());
        let p = write(&d, "t,u,y\n0,1,2\n1,1,1e150\n");
        assert!(read_record(&p, &s(&["u"]), &s(&["y"]), 1).is_ok());
        // Issue 38: a semicolon-separated file gets a hint.
        let p = write(&d, "t;u;y\n0;1;2\n1;1;2\n");
        let e = read_record(&p, &s(&["u"]), &s(&["y"]), 1)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("no column `t`") && e.contains("separated by ';'"),
            "{e}"
        );
        // ... whose conversion also turns its decimal commas into points.
        assert!(e.contains("sed 's/,/./g; s/;/,/g'"), "{e}");
    }

    #[test]
    fn each_kind_of_bad_cell_is_named_with_what_to_write() {
        let d = tempfile::tempdir().unwrap();
        let s = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
        let err = |text: &str| {
            let p = write(&d, text);
            read_record(&p, &s(&["u"]), &s(&["y"]), 1)
                .unwrap_err()
                .to_string()
        };
        for (cell, said) in [
            ("", "the cell is empty"),
            (
                "\"3,2567\"",
                "`3,2567` has a decimal comma: write it with a decimal point, `3.2567`",
            ),
            (
                "\"-0,5\"",
                "`-0,5` has a decimal comma: write it with a decimal point, `-0.5`",
            ),
            (
                "\"1,000\"",
                "if it is a thousands separator write `1000`, if a decimal comma `1.000`",
            ),
            (
                "\"12,345,678.5\"",
                "if it is a thousands separator write `12345678.5`",
            ),
            ("abc", "`abc` is not a number"),
            ("inf", "`inf` is not a finite number"),
        ] {
            let e = err(&format!("t,u,y\n0,1,2\n1,{cell},2\n"));
            assert!(
                e.contains("line 3, column `u`") && e.contains(said),
                "{cell}: {e}"
            );
        }
        // An unquoted decimal comma splits the row.
        let e = err("t,u,y\n0,1,2\n1,1,5,2\n");
        assert!(
            e.contains("line 3: 4 fields where the header has 3") && e.contains("decimal comma"),
            "{e}"
        );
        // A time column under another name.
        let e = err("time,u,y\n0,1,2\n1,1,2\n");
        assert!(
            e.contains("no column `t`") && e.contains("`time` looks like it: give `--time-column time`"),
            "{e}"
        );
        assert!(!err("x,u,y\n0,1,2\n").contains("looks like it"));
    }

    #[test]
    fn a_gzip_file_is_read_as_its_csv() {
        use std::io::Write;
        let d = tempfile::tempdir().unwrap();
        let p = d.path().join("d.csv.gz");
        let mut z =
            flate2::write::GzEncoder::new(std::fs::File::create(&p).unwrap(), flate2::Compression::default());
        z.write_all(b"t,u,y\n0,1,2\n1,1.5,2.5\n").unwrap();
        z.finish().unwrap();
        let s = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
        let r = read_record(&p, &s(&["u"]), &s(&["y"]), 2).unwrap();
        assert_eq!(r.outputs[0], vec![2.0, 2.5]);
        // A file named .gz that is not gzip is refused, naming it.
        std::fs::write(d.path().join("bad.csv.gz"), "t,u,y\n0,1,2\n").unwrap();
        let e = read_record(&d.path().join("bad.csv.gz"), &s(&["u"]), &s(&["y"]), 1)
            .unwrap_err()
            .to_string();
        assert!(e.contains("bad.csv.gz: cannot read"), "{e}");
    }
}
