//! How a case runs besides its mutant. Most run once into a fresh folder; one case in four
//! writes into the folder that holds its input (the input must come out unchanged); of the
//! others, chosen by a hash of the case's index (so a seed's mutants stay what they were):
//! a recording grown to [`LONG_ROWS`] rows (a quarter of the recordings' cases), two
//! writers into one folder at once, or a run killed part-way and run again (an eighth each).

use crate::corpus::Surface;
use crate::mutation::Format;
use std::time::Duration;

/// The rows of a grown recording.
pub const LONG_ROWS: usize = 100_000;

/// How a case runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Flavor {
    /// Once, into a fresh folder.
    Once,
    /// Once, into the folder that holds its input.
    InputInOut,
    /// Once, its recording grown to [`LONG_ROWS`] rows.
    LongRecord,
    /// Twice at once into the same folder.
    TwoWriters,
    /// Killed after this long, then run again (with `--force` where the command has it).
    Killed(Duration),
}

impl Flavor {
    /// Its name in the report.
    pub fn name(&self) -> &'static str {
        match self {
            Flavor::Once => "once",
            Flavor::InputInOut => "input inside --out",
            Flavor::LongRecord => "recording grown long",
            Flavor::TwoWriters => "two writers at once",
            Flavor::Killed(_) => "killed, then run again",
        }
    }
}

/// The flavor of case `i` on surface `s`.
pub fn of(i: usize, s: &Surface) -> Flavor {
    if i % 4 == 3 {
        return Flavor::InputInOut;
    }
    let h = (i as u64 ^ 0x5851_f42d_4c95_7f2d).wrapping_mul(0x9e37_79b9_7f4a_7c15);
    let (kind, ms) = (h >> 60, (h >> 20) % 400);
    match kind {
        0..=3 if s.format == Format::Csv => Flavor::LongRecord,
        4 | 5 => Flavor::TwoWriters,
        6 | 7 => Flavor::Killed(Duration::from_millis(ms)),
        _ => Flavor::Once,
    }
}

/// `text`, a CSV recording, grown to at least `rows` rows: its rows repeated, the times
/// (column `t`, when there is one and it reads) of each repetition moved past the last by
/// the record's span and one step. Text without a header and a row comes back as it is.
pub fn grown(text: &str, rows: usize) -> String {
    let mut lines = text.lines();
    let Some(header) = lines.next() else {
        return text.to_string();
    };
    let body: Vec<&str> = lines.collect();
    if body.is_empty() {
        return text.to_string();
    }
    let t_col = header.split(',').position(|c| c.trim() == "t");
    let time = |l: &str| {
        t_col
            .and_then(|c| l.split(',').nth(c))
            .and_then(|v| v.trim().parse::<f64>().ok())
    };
    let (first, last, second) = (
        time(body[0]),
        time(body[body.len() - 1]),
        body.get(1).and_then(|l| time(l)),
    );
    let shift = match (first, last, second) {
        (Some(a), Some(b), Some(c)) if (b - a + (c - a)).is_finite() => Some(b - a + (c - a)),
        _ => None,
    };
    let mut out = String::with_capacity(text.len() * rows.div_ceil(body.len()));
    out.push_str(header);
    out.push('\n');
    let (mut k, mut rep) = (0, 0.0);
    while k < rows {
        for l in &body {
            match (shift, t_col) {
                (Some(s), Some(c)) if rep > 0.0 => {
                    let cells: Vec<String> = l
                        .split(',')
                        .enumerate()
                        .map(|(j, v)| match v.trim().parse::<f64>() {
                            Ok(t) if j == c => format!("{}", t + rep * s),
                            _ => v.to_string(),
                        })
                        .collect();
                    out.push_str(&cells.join(","));
                }
                _ => out.push_str(l),
            }
            out.push('\n');
            k += 1;
        }
        rep += 1.0;
    }
    out
}

/// The arguments of a rerun after a kill: `--force` added where the command has it (a
/// killed run may have finished its folder, whose model a command replaces only then).
pub fn rerun_args(args: &[String]) -> Vec<String> {
    let mut a = args.to_vec();
    if matches!(args.first().map(String::as_str), Some("fit" | "identify")) {
        a.push("--force".into());
    }
    a
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_grown_recording_continues_its_times() {
        let g = grown("t,u,y\n0,1,2\n0.5,3,4\n", 5);
        assert_eq!(g, "t,u,y\n0,1,2\n0.5,3,4\n1,1,2\n1.5,3,4\n2,1,2\n2.5,3,4\n");
        // Times that do not read are repeated as they are.
        assert_eq!(grown("t,u\nx,1\ny,2\n", 3), "t,u\nx,1\ny,2\nx,1\ny,2\n");
        assert_eq!(grown("t,u\n", 3), "t,u\n");
    }

    #[test]
    fn every_flavor_is_drawn() {
        let s = |format| Surface {
            name: String::new(),
            file_name: String::new(),
            base: String::new(),
            format,
            args: Vec::new(),
            base_out: Default::default(),
        };
        let (csv, toml) = (s(Format::Csv), s(Format::Toml));
        let drawn: Vec<Flavor> = (0..400)
            .map(|i| of(i, if i % 2 == 0 { &csv } else { &toml }))
            .collect();
        let count = |f: fn(&Flavor) -> bool| drawn.iter().filter(|x| f(x)).count();
        assert_eq!(count(|f| *f == Flavor::InputInOut), 100);
        for n in [
            count(|f| *f == Flavor::LongRecord),
            count(|f| *f == Flavor::TwoWriters),
            count(|f| matches!(f, Flavor::Killed(_))),
        ] {
            assert!((8..60).contains(&n), "{n} of 400");
        }
        // A recording's cases only are grown.
        assert!((1..400).step_by(2).all(|i| drawn[i] != Flavor::LongRecord));
    }
}
