//! Measured data: records of a time column, inputs and outputs (SI or the user's own
//! units; a model keeps whatever units it was trained in).

mod gaps;
pub use gaps::{Gap, Split, MAX_FILLED_GAP, MAX_FILLED_SHARE};

use crate::error::{invalid, Result};

/// How far a time may sit from the uniform grid and still count as on it, as a share of
/// the step: 1e-3 (times rounded to 1e-6 s at a 1 ms step, as benchmark files are, are
/// uniform; a missing or doubled sample is not).
pub const TIME_JITTER: f64 = 1e-3;

/// What putting a record on a uniform grid changed (`Record::regrid`), for the messages
/// and summary.json.
#[derive(Debug, Clone, PartialEq, serde::Serialize, schemars::JsonSchema)]
pub struct Regrid {
    /// The record.
    pub source: String,
    /// The grid's interval \[s\].
    pub interval_s: f64,
    /// The record's shortest and longest interval \[s\].
    pub intervals_s: (f64, f64),
    /// Rows read.
    pub rows_in: usize,
    /// Rows on the grid.
    pub rows_out: usize,
    /// Input values taken from an earlier sample (zero-order hold).
    pub inputs_held: usize,
    /// Output values interpolated between two samples.
    pub outputs_interpolated: usize,
}

impl std::fmt::Display for Regrid {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}: the times are not uniform (intervals from {} to {} s): put on a grid of {} s, {} rows read, {} written, {} input values held from the sample before, {} output values interpolated",
            self.source, self.intervals_s.0, self.intervals_s.1, self.interval_s, self.rows_in, self.rows_out, self.inputs_held, self.outputs_interpolated
        )
    }
}

/// One recording: time, then input and output columns, all the same length.
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    /// Where it came from (file name), for messages.
    pub source: String,
    /// Times \[s\], strictly increasing.
    pub t: Vec<f64>,
    /// Input columns.
    pub inputs: Vec<Vec<f64>>,
    /// Output columns.
    pub outputs: Vec<Vec<f64>>,
}

/// Refuse a signal named twice among the inputs or among the outputs (`--inputs u,u`
/// was a model of two identical inputs, without a word). An input that is also an output
/// stays a warning of the fit.
pub fn check_names(inputs: &[String], outputs: &[String]) -> Result<()> {
    for (what, names) in [("inputs", inputs), ("outputs", outputs)] {
        for (k, n) in names.iter().enumerate() {
            if names[..k].contains(n) {
                return Err(crate::Error::Argument(format!(
                    "{what} name `{n}` twice ({}): give each column once",
                    names.join(",")
                )));
            }
        }
    }
    Ok(())
}

/// The largest magnitude a value may have, in a file, an array or a stream: its square, in
/// every variance and least-squares sum, stays finite.
pub const MAX_MAGNITUDE: f64 = 1e150;

/// The smallest magnitude a signal's largest value may have, unless the signal is all
/// zeros: below it, its squares in every variance and least-squares sum underflow (a
/// column of 1e-310 read as a constant; the mirror of [`MAX_MAGNITUDE`]).
pub const MIN_MAGNITUDE: f64 = 1e-150;

/// Refuse a signal of `records` whose values are not all zero but all below
/// [`MIN_MAGNITUDE`] in magnitude, naming the record, the column and its largest value.
pub fn check_tiny(records: &[Record], inputs: &[String], outputs: &[String]) -> Result<()> {
    for r in records {
        for (cols, names) in [(&r.inputs, inputs), (&r.outputs, outputs)] {
            for (name, col) in names.iter().zip(cols) {
                let largest = col.iter().fold(0.0f64, |m, x| m.max(x.abs()));
                if largest > 0.0 && largest < MIN_MAGNITUDE {
                    return Err(crate::Error::Argument(format!(
                        "{}: column `{name}`: its largest magnitude is {}, below 1e-150: values this small underflow when squared (every variance and least-squares sum); rescale the column (multiply it by a power of ten)",
                        r.source,
                        crate::metrics::sig(largest, 3)
                    )));
                }
            }
        }
    }
    Ok(())
}

/// The most samples [`Record::regrid`] puts on a grid (beyond a record's own rows).
pub const MAX_GRID_SAMPLES: f64 = 1e7;

/// How many times its own rows [`Record::regrid`] may put a record on.
pub const MAX_UPSAMPLING: f64 = 10.0;

/// The shape `(rows, columns)` of a caller's array named `name` (Python's `u` or `y`):
/// at least one row, and `k` columns, one per signal.
pub fn check_shape(name: &str, (rows, cols): (usize, usize), k: usize) -> Result<()> {
    if rows == 0 {
        return Err(crate::Error::Argument(format!(
            "{name} is empty: give at least one sample (row)"
        )));
    }
    if cols != k {
        return Err(crate::Error::Argument(format!(
            "{name} has {cols} columns; {k} are needed (one per signal)"
        )));
    }
    Ok(())
}

impl Record {
    /// Number of samples.
    pub fn len(&self) -> usize {
        self.t.len()
    }

    /// Whether there are no samples.
    pub fn is_empty(&self) -> bool {
        self.t.is_empty()
    }

    /// Samples `a..b` as a record of their own (source named with the range).
    pub fn slice(&self, a: usize, b: usize) -> Record {
        Record {
            source: format!("{} (samples {a}..{b})", self.source),
            t: self.t[a..b].to_vec(),
            inputs: self.inputs.iter().map(|c| c[a..b].to_vec()).collect(),
            outputs: self.outputs.iter().map(|c| c[a..b].to_vec()).collect(),
        }
    }

    /// This record with `n` samples before it that hold its first one (its first inputs
    /// and outputs, times one sampling interval apart): the history a model that needs
    /// more past outputs than it may see is given ([`within_window`]).
    pub fn held_before(&self, n: usize) -> Record {
        let dt = self.sample_interval();
        let t0 = self.t.first().copied().unwrap_or(0.0);
        let held = |c: &Vec<f64>| {
            let first = c.first().copied().unwrap_or(0.0);
            std::iter::repeat_n(first, n).chain(c.iter().copied()).collect()
        };
        Record {
            source: self.source.clone(),
            t: (0..n)
                .map(|k| t0 - (n - k) as f64 * dt)
                .chain(self.t.iter().copied())
                .collect(),
            inputs: self.inputs.iter().map(held).collect(),
            outputs: self.outputs.iter().map(held).collect(),
        }
    }

    /// The median sampling interval \[s\].
    pub fn median_interval(&self) -> f64 {
        let mut d: Vec<f64> = self.t.windows(2).map(|w| w[1] - w[0]).collect();
        d.sort_by(f64::total_cmp);
        d.get(d.len() / 2).copied().unwrap_or(f64::NAN)
    }

    /// Whether the times lie on the uniform grid `t0 + k dt` to within [`TIME_JITTER`] of
    /// `dt`: clock jitter, or times printed with few digits (a file of `k / 1024` s
    /// rounded to 1e-6 s) are uniform; nothing is changed for them.
    pub fn on_grid(&self, dt: f64) -> bool {
        let t0 = self.t.first().copied().unwrap_or(0.0);
        let tol = TIME_JITTER * dt;
        self.evenly_spaced(dt)
            || self
                .t
                .iter()
                .enumerate()
                .all(|(k, &t)| (t - (t0 + k as f64 * dt)).abs() <= tol)
    }

    /// Whether every interval is `dt` to within 1e-6 of it.
    fn evenly_spaced(&self, dt: f64) -> bool {
        self.t.windows(2).all(|w| ((w[1] - w[0]) - dt).abs() <= 1e-6 * dt)
    }

    /// The sampling interval \[s\]: the median interval, or, when the times sit on a
    /// uniform grid only to within [`TIME_JITTER`] (rounded times), the grid's own
    /// interval, from the first to the last time; [`step_as_written`] either way.
    pub fn sample_interval(&self) -> f64 {
        let med = self.median_interval();
        if self.len() < 3 || self.evenly_spaced(med) {
            return step_as_written(med);
        }
        let fit = (self.t[self.len() - 1] - self.t[0]) / (self.len() - 1) as f64;
        step_as_written(if self.on_grid(fit) { fit } else { med })
    }

    /// The record on a uniform grid of interval `dt` from its first time: inputs held
    /// (zero-order hold), outputs interpolated linearly. A record already on that grid
    /// ([`Record::on_grid`]) comes back unchanged.
    /// `field` names `dt` in the error of a grid too fine (see [`Record::regrid`]).
    pub fn uniform(&self, dt: f64, field: &str) -> Result<Record> {
        Ok(self.regrid(dt, field)?.0)
    }

    /// [`Record::uniform`], and what it changed (None when nothing). A grid of more than
    /// [`MAX_GRID_SAMPLES`] samples (and more than the record's rows) is an error naming
    /// `field`: a sample time of nanoseconds over a record of minutes would otherwise
    /// fill the memory.
    pub fn regrid(&self, dt: f64, field: &str) -> Result<(Record, Option<Regrid>)> {
        if self.on_grid(dt) {
            return Ok((self.clone(), None));
        }
        let t0 = self.t[0];
        let span = self.t[self.len() - 1] - t0;
        let n_f = (span / dt).floor() + 1.0;
        // At most MAX_UPSAMPLING times the rows: interpolation adds no information, and a
        // grid of nanoseconds over a record of minutes would fill the memory.
        let most = (MAX_UPSAMPLING * self.len() as f64)
            .min(MAX_GRID_SAMPLES)
            .max(self.len() as f64);
        if !(dt.is_finite() && dt > 0.0 && n_f <= most) {
            return Err(invalid(
                field,
                crate::metrics::sig(dt, 6),
                format!(
                    "a sample time of at least {} s: at most {} samples over {}'s {} s ({} times its {} rows at the most, and 10,000,000: interpolation adds no information)",
                    crate::metrics::sig(span / (most - 1.0).max(1.0), 3),
                    most as u64,
                    self.source,
                    crate::metrics::sig(span, 6),
                    MAX_UPSAMPLING,
                    self.len()
                ),
            ));
        }
        let n = n_f as usize;
        let grid: Vec<f64> = (0..n).map(|k| t0 + k as f64 * dt).collect();
        let mut j = 0;
        let mut inputs = vec![Vec::with_capacity(n); self.inputs.len()];
        let mut outputs = vec![Vec::with_capacity(n); self.outputs.len()];
        // A grid time within a millionth of an interval of a sample is that sample's time
        // (grid times k dt and the file's decimal times differ in their last bits; taking
        // the sample before would delay a held input by a whole sample).
        let tol = 1e-6 * dt;
        let (mut held, mut interpolated) = (0, 0);
        for &t in &grid {
            while j + 1 < self.len() && self.t[j + 1] <= t + tol {
                j += 1;
            }
            let exact = (self.t[j] - t).abs() <= tol;
            for (c, col) in self.inputs.iter().enumerate() {
                inputs[c].push(col[j]);
            }
            if !exact {
                held += self.inputs.len();
                interpolated += self.outputs.len();
            }
            for (c, col) in self.outputs.iter().enumerate() {
                let v = if j + 1 < self.len() {
                    let f = ((t - self.t[j]) / (self.t[j + 1] - self.t[j])).max(0.0);
                    col[j] + f * (col[j + 1] - col[j])
                } else {
                    col[j]
                };
                outputs[c].push(v);
            }
        }
        let (lo, hi) = self
            .t
            .windows(2)
            .map(|w| w[1] - w[0])
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), d| {
                (l.min(d), h.max(d))
            });
        let report = Regrid {
            source: self.source.clone(),
            interval_s: dt,
            intervals_s: (lo, hi),
            rows_in: self.len(),
            rows_out: n,
            inputs_held: held,
            outputs_interpolated: interpolated,
        };
        let r = Record {
            source: self.source.clone(),
            t: grid,
            inputs,
            outputs,
        };
        Ok((r, Some(report)))
    }

    /// A record sampled every `dt` s from columns given in memory (a caller's arrays, as
    /// `u` (inputs) and `y` (outputs) name them in errors): every value finite, the same
    /// number of samples in each, at least one output.
    pub fn sampled(source: &str, dt: f64, inputs: Vec<Vec<f64>>, outputs: Vec<Vec<f64>>) -> Result<Record> {
        let arg = |m: String| crate::Error::Argument(m);
        if !(dt.is_finite() && dt > 0.0) {
            return Err(arg(format!(
                "dt = {dt} is not allowed: give the sample time in seconds, finite and > 0"
            )));
        }
        if outputs.is_empty() {
            return Err(arg("outputs is empty: name at least one output".into()));
        }
        for (name, cols) in [("u", &inputs), ("y", &outputs)] {
            for (j, c) in cols.iter().enumerate() {
                if let Some((i, x)) = c
                    .iter()
                    .enumerate()
                    .find(|(_, x)| !(x.is_finite() && x.abs() <= MAX_MAGNITUDE))
                {
                    return Err(arg(format!(
                        "{name}[{i}, {j}] = {x} is not allowed: every value must be finite and of magnitude at most 1e150"
                    )));
                }
            }
        }
        let (n, ny) = (
            inputs.first().map_or(outputs[0].len(), Vec::len),
            outputs[0].len(),
        );
        if inputs.iter().chain(&outputs).any(|c| c.len() != n) {
            return Err(arg(format!(
                "u has {n} rows and y {ny}: give one row per sample in both"
            )));
        }
        let span = n.saturating_sub(1) as f64 * dt;
        if !span.is_finite() {
            return Err(arg(format!(
                "dt = {} is not allowed: the last of {n} samples, at {} x dt, is not a finite time; give the sample time in seconds",
                crate::metrics::sig(dt, 6),
                n - 1
            )));
        }
        Ok(Record {
            source: source.to_string(),
            t: (0..n).map(|k| k as f64 * dt).collect(),
            inputs,
            outputs,
        })
    }

    /// Check lengths, finiteness and increasing time (a reader does this with line
    /// numbers; this is the library's own guard).
    pub fn check(&self, min_samples: usize) -> Result<()> {
        if self.len() < min_samples {
            return Err(invalid(
                format!("{}: samples", self.source),
                self.len(),
                format!("at least {min_samples} samples for this model"),
            ));
        }
        for c in self.inputs.iter().chain(&self.outputs) {
            if c.len() != self.len() {
                return Err(invalid(
                    format!("{}: column length", self.source),
                    c.len(),
                    "the length of t",
                ));
            }
        }
        Ok(())
    }
}

/// A free run of `r` by a model that sees only its first `window` outputs (a benchmark's
/// state-initialisation window, `rhonn predict --init-window`). `free_run` runs the model on
/// a record, measuring the outputs before its first prediction, and returns one column per
/// output and that first prediction's index. A model whose first prediction comes after
/// the window is run on `r` held before its start ([`Record::held_before`]) by as many
/// samples as it lacks, so that its measured outputs are the window's and its predictions
/// start at sample `window`. Returns the columns, aligned with `r` (its samples before the
/// model's first prediction are the measurements), and the first predicted sample.
pub fn within_window(
    r: &Record,
    window: usize,
    mut free_run: impl FnMut(&Record) -> Result<(Vec<Vec<f64>>, usize)>,
) -> Result<(Vec<Vec<f64>>, usize)> {
    let (cols, first) = free_run(r)?;
    if first <= window {
        return Ok((cols, first));
    }
    let lacking = first - window;
    let (cols, shifted) = free_run(&r.held_before(lacking))?;
    debug_assert_eq!(
        shifted, first,
        "a model's first prediction does not move with the record"
    );
    let cols = cols.into_iter().map(|c| c[lacking..].to_vec()).collect();
    Ok((cols, window))
}

/// A sample time as the data's times were written: the difference of two decimal times
/// carries the subtraction's rounding (`0.08 - 0` is 0.08, `61.36 - 61.28` is
/// 0.0799999999999983), so the step is rounded to 12 significant digits, a relative
/// change below 1e-12, far inside [`TIME_JITTER`]. A file's step of 0.08 s, a stream's
/// first interval and Python's `dt = 0.1` then give the same `sample_time_s`.
pub fn step_as_written(dt: f64) -> f64 {
    if !(dt.is_finite() && dt > 0.0) {
        return dt;
    }
    format!("{dt:.11e}").parse().unwrap_or(dt)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn resampling_to_a_coarser_grid_takes_the_samples_at_its_times() {
        // 1 ms decimal times onto a 5 ms grid whose interval was read off float
        // differences (4.999999999999893 ms): every grid point is a sample of the file.
        let n = 12_001;
        let t: Vec<f64> = (0..n).map(|k| k as f64 / 1000.0).collect();
        let held: Vec<f64> = (0..n).map(|k| (k / 5) as f64).collect();
        let ramp: Vec<f64> = (0..n).map(|k| k as f64).collect();
        let r = Record {
            source: "r".into(),
            t,
            inputs: vec![held],
            outputs: vec![ramp],
        };
        let dt = 0.004_999_999_999_999_893;
        let u = r.uniform(dt, "dt").unwrap();
        assert_eq!(u.len(), 2401);
        for k in 0..u.len() {
            assert_eq!(u.inputs[0][k], k as f64, "input at grid point {k}");
            assert!((u.outputs[0][k] - 5.0 * k as f64).abs() < 1e-6, "output at {k}");
        }
    }

    #[test]
    fn a_sample_time_whose_last_sample_is_not_a_finite_time_is_refused() {
        let cols = || vec![vec![0.0, 1.0, 2.0]];
        let e = Record::sampled("x", 1.7e308, cols(), cols())
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("dt = 1.7e308 is not allowed") && e.contains("2 x dt"),
            "{e}"
        );
        assert!(Record::sampled("x", 1e300, cols(), cols()).is_ok());
    }

    #[test]
    fn a_signal_named_twice_is_refused() {
        let v = |s: &[&str]| s.iter().map(|x| x.to_string()).collect::<Vec<_>>();
        assert!(check_names(&v(&["u", "v"]), &v(&["y"])).is_ok());
        assert!(check_names(&v(&["u"]), &v(&["u"])).is_ok());
        let e = check_names(&v(&["u", "u"]), &v(&["y"])).unwrap_err().to_string();
        assert!(e.contains("inputs name `u` twice (u,u)"), "{e}");
        let e = check_names(&v(&["u"]), &v(&["y", "z", "y"]))
            .unwrap_err()
            .to_string();
        assert!(e.contains("outputs name `y` twice"), "{e}");
    }

    #[test]
    fn resampling_holds_inputs_and_interpolates_outputs() {
        let r = Record {
            source: "x".into(),
            t: vec![0.0, 1.0, 3.0],
            inputs: vec![vec![1.0, 2.0, 3.0]],
            outputs: vec![vec![0.0, 10.0, 30.0]],
        };
        assert_eq!(r.median_interval(), 2.0);
        let u = r.uniform(1.0, "dt").unwrap();
        assert_eq!(u.t, vec![0.0, 1.0, 2.0, 3.0]);
        let e = r.uniform(1e-9, "--resample").unwrap_err().to_string();
        assert!(
            e.contains("`--resample` = 1e-9")
                && e.contains("at most 30 samples")
                && e.contains("10 times its 3 rows"),
            "{e}"
        );
        assert_eq!(u.inputs[0], vec![1.0, 2.0, 2.0, 3.0]);
        assert_eq!(u.outputs[0], vec![0.0, 10.0, 20.0, 30.0]);
    }

    #[test]
    fn a_model_that_needs_more_outputs_than_the_window_sees_only_the_window() {
        let r = Record {
            source: "r".into(),
            t: vec![1.0, 1.5, 2.0, 2.5, 3.0, 3.5],
            inputs: vec![vec![0.1, 0.2, 0.3, 0.4, 0.5, 0.6]],
            outputs: vec![vec![10.0, 11.0, 12.0, 13.0, 14.0, 15.0]],
        };
        let h = r.held_before(2);
        assert_eq!(h.t, [0.0, 0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5]);
        assert_eq!(h.inputs[0][..3], [0.1, 0.1, 0.1]);
        assert_eq!(h.outputs[0][..4], [10.0, 10.0, 10.0, 11.0]);
        // A "model" that measures its first 4 outputs and then predicts the sum of what
        // it measured: with a window of 2 it may only have seen 10 and 11.
        let model = |r: &Record| -> Result<(Vec<Vec<f64>>, usize)> {
            let y = &r.outputs[0];
            let seen: f64 = y[..4].iter().sum();
            let col = (0..r.len()).map(|k| if k < 4 { y[k] } else { seen }).collect();
            Ok((vec![col], 4))
        };
        let (cols, first) = within_window(&r, 2, model).unwrap();
        assert_eq!(first, 2);
        assert_eq!(cols[0], [10.0, 11.0, 41.0, 41.0, 41.0, 41.0]);
        // A window as long as the model needs changes nothing.
        let (cols, first) = within_window(&r, 4, model).unwrap();
        assert_eq!((first, &cols[0][4..]), (4, &[46.0, 46.0][..]));
    }
}
