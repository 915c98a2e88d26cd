//! Mutations of a CSV recording (header `t,...`): hostile cells, rows lost, doubled or
//! swapped, a time column rounded or in milliseconds, another delimiter, a column lost.

use crate::mutant::Mutant;
use rand::seq::SliceRandom;
use rand::Rng;
use rand_chacha::ChaCha8Rng;

const HOSTILE_CELLS: [&str; 13] = [
    "nan", "inf", "-inf", "1.7e308", "-1.7e308", "5e-324", "", "abc", "1,5", "0x10", "1e400", "1e300", "-0",
];

/// Every parseable time of `rows` rewritten by `f`.
fn map_times(rows: &mut [Vec<String>], f: impl Fn(f64) -> String) {
    for row in rows {
        if let Some(cell) = row.first_mut() {
            if let Ok(t) = cell.parse::<f64>() {
                *cell = f(t);
            }
        }
    }
}

/// The text cut in its second half.
fn truncated(t: &str, rng: &mut ChaCha8Rng) -> Mutant {
    let mut cut = rng.gen_range(t.len() / 2..t.len());
    while !t.is_char_boundary(cut) {
        cut -= 1;
    }
    Mutant {
        text: t[..cut].to_string(),
        what: format!("truncated at byte {cut}"),
        names: vec!["line".into()],
    }
}

/// One change to a CSV text. An error about it names the column or the line.
pub fn mutate_csv(text: &str, rng: &mut ChaCha8Rng) -> Mutant {
    let lines: Vec<&str> = text.lines().collect();
    let header: Vec<String> = lines
        .first()
        .map(|h| h.split(',').map(str::to_string).collect())
        .unwrap_or_default();
    let rows: Vec<Vec<String>> = lines[1.min(lines.len())..]
        .iter()
        .map(|l| l.split(',').map(str::to_string).collect())
        .collect();
    if rows.len() < 4 || header.is_empty() {
        return Mutant {
            text: String::new(),
            what: "emptied".into(),
            names: vec!["line".into()],
        };
    }
    let k = rng.gen_range(0..rows.len());
    let line = k + 2;
    let line_names = |extra: &[&str]| line_names(line, extra);
    let mut r = rows.clone();
    let mut h = header.clone();
    let (what, names) = match rng.gen_range(0..20) {
        0..=5 => {
            let c = rng.gen_range(0..h.len());
            let cell = *HOSTILE_CELLS.choose(rng).unwrap();
            if let Some(x) = r[k].get_mut(c) {
                *x = cell.to_string();
            }
            (
                format!("line {line}, column {}: {cell:?}", h[c]),
                line_names(&[&h[c]]),
            )
        }
        6 => {
            let c = rng.gen_range(0..h.len());
            let v = r[0].get(c).cloned().unwrap_or_default();
            for row in &mut r {
                if let Some(x) = row.get_mut(c) {
                    *x = v.clone();
                }
            }
            (format!("column {} constant {v}", h[c]), vec![h[c].to_lowercase()])
        }
        c @ 7..=9 => row_fault(c, k, &mut r),
        10 => {
            // Times rounded to 1e-6 s, as some benchmark files are: must read as uniform.
            map_times(&mut r, |t| format!("{:.6}", t * (1.0 + 3e-9)));
            ("t rounded to 1e-6".into(), vec!["t".into()])
        }
        11 => {
            map_times(&mut r, |t| format!("{}", t * 1000.0));
            ("t in milliseconds".into(), vec!["t".into()])
        }
        12 => {
            let t = join(&h, &r, ";");
            return Mutant {
                text: t,
                what: "';' as the delimiter".into(),
                names: vec!["t".into(), ";".into()],
            };
        }
        13 => {
            let c = rng.gen_range(0..h.len());
            let name = h.remove(c);
            for row in &mut r {
                if c < row.len() {
                    row.remove(c);
                }
            }
            (format!("column {name} removed"), vec![name.to_lowercase()])
        }
        14 => {
            r[k].push("1.0".into());
            (format!("line {line}: an extra cell"), line_names(&[]))
        }
        15..=18 => stream_fault(rng, k, &mut h, &mut r),
        _ => return truncated(&join(&h, &r, ","), rng),
    };
    Mutant {
        text: join(&h, &r, ","),
        what,
        names,
    }
}

/// The faults of a stream (a glitch, a paused logger, rows lost) and a header naming a
/// column twice: row `k` of `r` (header `h`) changed; what was done and what an error
/// about it names.
fn stream_fault(
    rng: &mut ChaCha8Rng,
    k: usize,
    h: &mut [String],
    r: &mut Vec<Vec<String>>,
) -> (String, Vec<String>) {
    let line = k + 2;
    let line_names = |extra: &[&str]| line_names(line, extra);
    match rng.gen_range(0..4) {
        0 => {
            // A sensor glitch: finite, inside the files' range, far outside the signal's.
            let c = rng.gen_range(1..h.len().max(2)).min(h.len() - 1);
            if let Some(x) = r[k].get_mut(c) {
                *x = "1e10".into();
            }
            (
                format!("line {line}, column {}: a glitch 1e10", h[c]),
                line_names(&[&h[c]]),
            )
        }
        1 => {
            // A paused logger: every time from line `line` on jumps forward.
            let jump = [1e3, 1e6, 3.9e7][rng.gen_range(0..3)];
            for row in r.iter_mut().skip(k) {
                if let Some(t) = row.first_mut().and_then(|c| c.parse::<f64>().ok()) {
                    row[0] = format!("{}", t + jump);
                }
            }
            (format!("t jumps by {jump} s at line {line}"), line_names(&["t"]))
        }
        2 => {
            // Many rows lost: every fifth.
            let kept: Vec<Vec<String>> = r
                .iter()
                .enumerate()
                .filter(|(j, _)| j % 5 != 2)
                .map(|(_, x)| x.clone())
                .collect();
            *r = kept;
            (
                "every fifth row deleted".into(),
                vec!["t".into(), "missing".into()],
            )
        }
        _ => {
            // A column named twice in the header.
            let (a, b) = (rng.gen_range(0..h.len()), rng.gen_range(0..h.len()));
            let name = h[a].clone();
            h[b] = name.clone();
            (
                format!("column {} renamed {name}", b + 1),
                vec![name.to_lowercase()],
            )
        }
    }
}

/// The CSV text of header `h` and rows `r`, cells separated by `sep`.
fn join(h: &[String], r: &[Vec<String>], sep: &str) -> String {
    let mut s = h.join(sep);
    s.push('\n');
    for row in r {
        s.push_str(&row.join(sep));
        s.push('\n');
    }
    s
}

/// What an error about line `line` names: the line, and the `extra` names.
fn line_names(line: usize, extra: &[&str]) -> Vec<String> {
    let mut v = vec![format!("line {line}"), "line".to_string()];
    v.extend(extra.iter().map(|s| s.to_lowercase()));
    v
}

/// Row `k` of `r` deleted (7), doubled (8) or swapped with the next (9): what was done and
/// what an error about it names.
fn row_fault(choice: i32, k: usize, r: &mut Vec<Vec<String>>) -> (String, Vec<String>) {
    let line = k + 2;
    match choice {
        7 => {
            r.remove(k);
            (format!("line {line} deleted"), line_names(line, &["t"]))
        }
        8 => {
            r.insert(k, r[k].clone());
            (format!("line {line} doubled"), line_names(line, &["t"]))
        }
        _ => {
            let j = (k + 1).min(r.len() - 1);
            r.swap(k, j);
            (
                format!("lines {line} and {} swapped", j + 2),
                line_names(line, &["t"]),
            )
        }
    }
}
