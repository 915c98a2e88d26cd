//! Checks of the data given to `fit` that do not stop it but usually spoil it: the time
//! column used as a signal, an input that is also an output, a constant input, and a
//! sample time far below the system's time constants (the lags then see almost none of
//! the dynamics). Each is a warning in words with what to do.

use super::{Model, OutputFigures};
use crate::data::Record;
use crate::error::{Error, Result};

/// An output's autocorrelation must fall to 1/e within this many model lag spans; past
/// it the warning on fast sampling fires. Measured with `rhonn fit` and the default
/// structure (lags of 2 samples): a Duffing oscillator sampled at 10 ms falls to 1/e after
/// 101 samples (50 spans) and fits at 10.9 % in free run on its training record, 84.1 %
/// with `--resample 0.07`; the cascaded tanks (4 s) fall to 1/e after 47 samples
/// (23 spans) and run free on the validation record at 0.93 V RMS error, 0.68 V with
/// `--resample 8`.
pub const SLOW_SPANS: usize = 20;

/// The first lag at which the autocorrelation of `y` (mean removed) falls below 1/e, or
/// None when it never does within half the record (or `y` is constant).
///
/// Every lag's sum at once by the FFT (Wiener-Khinchin: the inverse transform of the
/// zero-padded signal's power), O(n log n): a drifting record of a million samples is
/// checked in a fraction of a second, where one sum per lag took minutes. A lag whose
/// FFT sum lies within rounding of the threshold is decided by its exact sum, so the lag
/// found is the one the sums give.
pub fn decorrelation_lag(y: &[f64]) -> Option<usize> {
    use rustfft::{num_complex::Complex, FftPlanner};
    let n = y.len();
    if n < 2 {
        return None;
    }
    let mean = y.iter().sum::<f64>() / n as f64;
    let d: Vec<f64> = y.iter().map(|v| v - mean).collect();
    let c0: f64 = d.iter().map(|v| v * v).sum();
    if c0 <= 0.0 || !c0.is_finite() {
        return None;
    }
    let target = (-1.0f64).exp() * c0;
    let m = (2 * n).next_power_of_two();
    let mut buf: Vec<Complex<f64>> = d.iter().map(|&v| Complex::new(v, 0.0)).collect();
    buf.resize(m, Complex::new(0.0, 0.0));
    let mut planner = FftPlanner::new();
    planner.plan_fft_forward(m).process(&mut buf);
    for c in &mut buf {
        *c = Complex::new(c.norm_sqr(), 0.0);
    }
    planner.plan_fft_inverse(m).process(&mut buf);
    let exact = |k: usize| d[..n - k].iter().zip(&d[k..]).map(|(a, b)| a * b).sum::<f64>();
    // The FFT's rounding is about n ulps of c0; a sum this close to the threshold is
    // computed exactly.
    let tol = 1e-9 * c0;
    (1..n / 2).find(|&k| {
        let sum = buf[k].re / m as f64;
        if (sum - target).abs() <= tol {
            exact(k) < target
        } else {
            sum < target
        }
    })
}

fn constant(cols: &[&[f64]]) -> bool {
    let mut it = cols.iter().flat_map(|c| c.iter());
    match it.next() {
        Some(first) => it.all(|v| v == first),
        None => true,
    }
}

/// A warning on the data, with the numbers its advice needs: each door words its advice
/// in its own terms (the command line's `--resample`, Python's `dt`); [`std::fmt::Display`]
/// gives words that name no door's option.
#[derive(Debug, Clone, PartialEq)]
pub enum DataWarning {
    /// Words the same at every door ([`signal_warnings`]).
    Said(String),
    /// The times step by a whole number that reads as a common sample time in
    /// milliseconds: `sample_s` as read, over `span_s`.
    Milliseconds {
        /// The sample time as read \[s\].
        sample_s: f64,
        /// The records' span as read \[s\].
        span_s: f64,
    },
    /// An output changes slowly against the sample time: its autocorrelation falls to 1/e
    /// after `samples` samples, the model looks back `span`; resampling to about
    /// `suggest_s` gives about 5 spans to 1/e.
    Slow {
        /// The output.
        output: String,
        /// Samples to 1/e.
        samples: usize,
        /// The model's look-back in samples.
        span: usize,
        /// The sample time \[s\].
        sample_s: f64,
        /// The suggested sample time \[s\], to 2 significant digits.
        suggest_s: f64,
    },
}

impl DataWarning {
    /// The warning with its advice: `resample(s)` says how to resample to `s` seconds, `ms`
    /// what to do when the times are milliseconds (the sample time in seconds given).
    pub fn worded(&self, resample: &dyn Fn(f64) -> String, ms: &dyn Fn(f64) -> String) -> String {
        match self {
            DataWarning::Said(w) => w.clone(),
            DataWarning::Milliseconds { sample_s, span_s } => format!(
                "the samples are {sample_s} s apart, on whole numbers, over {} s: if the times are milliseconds, the sample time is {} s: {}",
                round_sig(*span_s, 3),
                sample_s / 1000.0,
                ms(sample_s / 1000.0)
            ),
            DataWarning::Slow {
                output,
                samples,
                span,
                sample_s,
                suggest_s,
            } => format!(
                "output `{output}` changes slowly against the sample time: its autocorrelation falls to 1/e only after \
                 {samples} samples ({} s), while the model looks back {span} sample{} ({} s); lagged models then see \
                 almost none of the dynamics and often run away in free run. {} (about {} samples to 1/e), or give the model more lags",
                round_sig(*samples as f64 * sample_s, 3),
                if *span == 1 { "" } else { "s" },
                round_sig(*span as f64 * sample_s, 3),
                resample(*suggest_s),
                5 * span
            ),
        }
    }
}

impl std::fmt::Display for DataWarning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let resample = |s: f64| format!("Resample to a longer sample time, e.g. {s} s");
        let ms = |s: f64| format!("give the times in seconds ({s} s apart)");
        f.write_str(&self.worded(&resample, &ms))
    }
}

/// Warnings on `records` (already on their uniform grid of `sample_s`) for a model that
/// looks back `max_lag` samples.
pub fn data_warnings(
    records: &[Record],
    inputs: &[String],
    outputs: &[String],
    max_lag: usize,
    sample_s: f64,
) -> Vec<DataWarning> {
    let mut w: Vec<DataWarning> = signal_warnings(records, inputs, outputs)
        .into_iter()
        .map(DataWarning::Said)
        .collect();
    w.extend(milliseconds_hint(records, sample_s));
    let span = max_lag.max(1);
    for (j, name) in outputs.iter().enumerate() {
        let lags: Vec<usize> = records
            .iter()
            .filter_map(|r| decorrelation_lag(&r.outputs[j]))
            .collect();
        let Some(&n) = lags.iter().min() else { continue };
        if n > SLOW_SPANS * span {
            w.push(DataWarning::Slow {
                output: name.clone(),
                samples: n,
                span,
                sample_s,
                suggest_s: round_sig(sample_s * n as f64 / (5 * span) as f64, 2),
            });
        }
    }
    w
}

/// Warnings on the signals chosen, whatever the model: the time column as a signal, a
/// column both an input and an output, an input equal to an output, a constant input
/// (`rhonn fit`'s and `rhonn identify`'s).
pub fn signal_warnings(records: &[Record], inputs: &[String], outputs: &[String]) -> Vec<String> {
    let mut w = Vec::new();
    for name in inputs.iter().chain(outputs).filter(|n| n.as_str() == "t") {
        w.push(format!(
            "`{name}` is the time column, used here as a signal: a model of time predicts nothing on another record"
        ));
    }
    for (i, name) in inputs.iter().enumerate() {
        if outputs.contains(name) {
            w.push(format!(
                "`{name}` is both an input and an output: the model can copy it and learn nothing"
            ));
            continue;
        }
        for (j, out) in outputs.iter().enumerate() {
            if records.iter().all(|r| r.inputs[i] == r.outputs[j]) {
                w.push(format!(
                    "input `{name}` equals output `{out}` sample for sample: the model can copy it and learn nothing"
                ));
            }
        }
        let cols: Vec<&[f64]> = records.iter().map(|r| r.inputs[i].as_slice()).collect();
        if constant(&cols) {
            w.push(format!(
                "input `{name}` is constant: nothing in the data shows how the output answers it"
            ));
        }
    }
    w
}

/// Sample times, in seconds, that are common sample times in milliseconds of a logger (10 ms
/// and more: 2 s and 5 s are common sample times in seconds too, so they get no hint).
const MS_LIKE_STEPS: [f64; 7] = [10.0, 20.0, 25.0, 50.0, 100.0, 200.0, 250.0];

/// A hint when the times look like milliseconds read as seconds, every time a whole number
/// and either a sample time that is a logger's in milliseconds (10 to 250) over at least
/// 1,000 "seconds" (a 50 ms log of a minute reads as 16 hours at 50 s), or a whole number
/// of thousands (a 2 s log in milliseconds steps by 2,000).
pub fn milliseconds_hint(records: &[Record], sample_s: f64) -> Option<DataWarning> {
    let whole = records.iter().all(|r| r.t.iter().all(|t| t.fract() == 0.0));
    let span_s: f64 = records
        .iter()
        .map(|r| r.t.last().unwrap_or(&0.0) - r.t.first().unwrap_or(&0.0))
        .sum();
    let logger = span_s >= 1000.0 && MS_LIKE_STEPS.contains(&sample_s);
    let thousands = sample_s >= 1000.0 && sample_s % 1000.0 == 0.0;
    (whole && (logger || thousands)).then_some(DataWarning::Milliseconds { sample_s, span_s })
}

/// `v` rounded to `digits` significant digits (for advice).
fn round_sig(v: f64, digits: i32) -> f64 {
    if v <= 0.0 || !v.is_finite() {
        return v;
    }
    let p = 10f64.powi(v.log10().floor() as i32 + 1 - digits);
    // Dividing by a power of ten below 1 would leave float noise: multiply then.
    if p < 1.0 {
        let q = 10f64.powi(digits - 1 - v.log10().floor() as i32);
        (v * q).round() / q
    } else {
        (v / p).round() * p
    }
}

/// A fitted model whose scaling or weights are NaN or infinite is an error that names the
/// data's range (the usual cause: values so large that their squares overflow).
pub(super) fn ensure_finite_model(m: &Model, records: &[Record]) -> Result<()> {
    let finite_pairs = |v: &[(f64, f64)]| v.iter().all(|(a, b)| a.is_finite() && b.is_finite());
    let ok = finite_pairs(&m.input_norm)
        && finite_pairs(&m.output_norm)
        && finite_pairs(&m.output_range)
        && m.weights.iter().flatten().all(|w| w.is_finite());
    if ok {
        return Ok(());
    }
    let mut largest = (0.0_f64, String::new(), String::new());
    for r in records {
        let cols = m
            .inputs
            .iter()
            .zip(&r.inputs)
            .chain(m.outputs.iter().zip(&r.outputs));
        for (name, col) in cols {
            for v in col {
                if v.abs() > largest.0 {
                    largest = (v.abs(), name.clone(), r.source.clone());
                }
            }
        }
    }
    let cause = if largest.0 > 1e150 {
        format!(
            "the data reach |{:e}| (column `{}` of {}); values beyond about 1e150 overflow the \
             scaling's squares: rescale the data (e.g. to other units) so that they stay well below",
            largest.0, largest.1, largest.2
        )
    } else {
        format!(
            "the data's largest value is |{:e}| (column `{}` of {}); the training diverged: \
             try a smaller `degree`, fewer lags, a larger `ridge` or the `batch-ls` law",
            largest.0, largest.1, largest.2
        )
    };
    Err(Error::NotFinite {
        what: "a scale or weight of the fitted model".into(),
        cause,
    })
}

/// An error when any figure (RMS error, fit, NRMSE) of a prediction on `source` is NaN or
/// infinite: a prediction that overflowed must not be written as a result.
pub fn ensure_finite_figures(figures: &[OutputFigures], source: &str) -> Result<()> {
    ensure_finite_errors(figures.iter().map(|f| (f.output.as_str(), f.rms_error)), source)
}

/// [`ensure_finite_figures`] for any prediction's `(output, rms error)` pairs (an online
/// model's too).
pub fn ensure_finite_errors<'a>(
    errors: impl IntoIterator<Item = (&'a str, f64)>,
    source: &str,
) -> Result<()> {
    // The fit and NRMSE of a constant output are undefined, not an overflow: only the
    // error itself must be finite.
    match errors.into_iter().find(|(_, e)| !e.is_finite()) {
        None => Ok(()),
        Some((output, _)) => Err(Error::NotFinite {
            what: format!("the prediction of `{output}` on {source}"),
            cause: "it overflows on these data (a free run that diverges, or data far outside the \
                    training range); nothing was written"
                .into(),
        }),
    }
}

/// The bound a model holds output `j` in (the training range widened by `output_margin`),
/// as (low, high, tolerance); None for a kind that does not hold its outputs in range.
fn output_bound(m: &Model, j: usize) -> Option<(f64, f64, f64)> {
    if !super::model_kind(m.spec.kind).holds_outputs_in_range() {
        return None;
    }
    let (lo, hi) = *m.output_range.get(j)?;
    let w = (hi - lo) * m.spec.output_margin;
    let (a, b) = (lo - w, hi + w);
    Some((a, b, 1e-9 * (b - a).abs().max(1e-300)))
}

/// The stability check of a frozen lagged model: where its free run on `r` (the
/// prediction `pred`, from sample `first`) sits on the bound its outputs are held in (the
/// training range widened by `output_margin`), which a stable model that fits the data
/// never reaches: (output name, time \[s\]) of the first such sample.
pub fn free_run_at_bound(m: &Model, r: &Record, pred: &[Vec<f64>], first: usize) -> Option<(String, f64)> {
    outputs_at_bound(m, r, pred, first)
        .into_iter()
        .next()
        .map(|b| (b.output, b.first_t_s))
}

/// An output whose free run on a record sits on the bound the model holds it in.
#[derive(Debug, Clone, PartialEq)]
pub struct OutputAtBound {
    /// The output's column.
    pub output: String,
    /// The time \[s\] of the record's first sample on the bound.
    pub first_t_s: f64,
    /// The share of the predicted samples on the bound, in (0, 1].
    pub share: f64,
}

/// Each output whose free run `pred` on `r` (from sample `first`) reaches the bound `m`
/// holds it in: where its output is clipped, the model ran away from the system (on the
/// unseen-systems corpus, seed 45, a Wiener system's RHONN sat there for most of a test of
/// pulses at 29.5 x the ARX's error).
pub fn outputs_at_bound(m: &Model, r: &Record, pred: &[Vec<f64>], first: usize) -> Vec<OutputAtBound> {
    let mut v = Vec::new();
    for (j, col) in pred.iter().enumerate() {
        let Some((a, b, tol)) = output_bound(m, j) else {
            continue;
        };
        let end = col.len().min(r.len());
        let on: Vec<usize> = (first..end)
            .filter(|&k| col[k] <= a + tol || col[k] >= b - tol)
            .collect();
        if let (Some(&k), Some(name)) = (on.first(), m.outputs.get(j)) {
            v.push(OutputAtBound {
                output: name.clone(),
                first_t_s: r.t[k],
                share: on.len() as f64 / (end - first) as f64,
            });
        }
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(t_s: f64, n: usize, u: impl Fn(usize) -> f64, y: impl Fn(usize) -> f64) -> Record {
        Record {
            source: "r.csv".into(),
            t: (0..n).map(|k| k as f64 * t_s).collect(),
            inputs: vec![(0..n).map(&u).collect()],
            outputs: vec![(0..n).map(&y).collect()],
        }
    }

    /// The warnings as words naming no door's option.
    fn said(records: &[Record], inputs: &[&str], lag: usize, sample_s: f64) -> Vec<String> {
        let s = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
        data_warnings(records, &s(inputs), &s(&["y"]), lag, sample_s)
            .iter()
            .map(ToString::to_string)
            .collect()
    }

    #[test]
    fn each_warning_fires_on_its_case_and_not_on_good_data() {
        // A fast-changing output and a varying input: nothing to say.
        let good = record(1.0, 400, |k| (k % 7) as f64, |k| ((k * 37) % 11) as f64);
        assert!(said(std::slice::from_ref(&good), &["u"], 2, 1.0).is_empty());
        let w = said(std::slice::from_ref(&good), &["t"], 2, 1.0);
        assert!(w.iter().any(|m| m.contains("time column")), "{w:?}");
        let w = said(std::slice::from_ref(&good), &["y"], 2, 1.0);
        assert!(
            w.iter().any(|m| m.contains("both an input and an output")),
            "{w:?}"
        );
        let same = record(1.0, 400, |k| ((k * 37) % 11) as f64, |k| ((k * 37) % 11) as f64);
        let w = said(&[same], &["u"], 2, 1.0);
        assert!(w.iter().any(|m| m.contains("equals output `y`")), "{w:?}");
        let flat = record(1.0, 400, |_| 3.0, |k| ((k * 37) % 11) as f64);
        let w = said(&[flat], &["u"], 2, 1.0);
        assert!(w.iter().any(|m| m.contains("`u` is constant")), "{w:?}");
        // A slow sine sampled finely: period 2,000 samples, 1/e after about 310.
        let slow = record(
            0.01,
            4000,
            |k| (k % 7) as f64,
            |k| (k as f64 * std::f64::consts::TAU / 2000.0).sin(),
        );
        let s = |v: &[&str]| v.iter().map(|x| x.to_string()).collect::<Vec<_>>();
        let w = data_warnings(std::slice::from_ref(&slow), &s(&["u"]), &s(&["y"]), 3, 0.01);
        assert!(
            matches!(&w[..], [DataWarning::Slow { suggest_s, samples, span: 3, .. }]
                if (*suggest_s - 0.01 * *samples as f64 / 15.0).abs() < 0.005),
            "{w:?}"
        );
        // Each door words its own advice; the words of none name an option.
        let flag = w[0].worded(&|s| format!("`--resample {s}`"), &|_| String::new());
        assert!(
            flag.contains("`--resample 0.2") && flag.contains("changes slowly"),
            "{flag}"
        );
        assert!(!w[0].to_string().contains("--"), "{}", w[0]);
        // With lags spanning more of it, no warning.
        assert!(said(&[slow], &["u"], 30, 0.01).is_empty());
        // A 50 ms log of 100 s with `t` in milliseconds: read as 50 s steps over 5,000 s;
        // a 2 s log in milliseconds: steps of 2,000.
        for (step, n, seconds) in [(50.0, 2000, "0.05 s"), (2000.0, 50, "2 s")] {
            let ms = record(step, n, |k| (k % 7) as f64, |k| ((k * 37) % 11) as f64);
            let w = said(&[ms], &["u"], 2, step);
            assert!(
                w.len() == 1
                    && w[0].contains("if the times are milliseconds")
                    && w[0].contains(&format!("the sample time is {seconds}")),
                "{w:?}"
            );
        }
        // The tanks' 4 s, 2 s and 5 s over an hour (common sample times in seconds), a
        // sample index (1) and a short record of whole 50 s steps: none.
        for (step, n) in [(4.0, 1024), (2.0, 1800), (5.0, 720), (1.0, 2000), (50.0, 10)] {
            let r = record(step, n, |k| (k % 7) as f64, |k| ((k * 37) % 11) as f64);
            let w = said(&[r], &["u"], 2, step);
            assert!(w.iter().all(|m| !m.contains("milliseconds")), "{step}: {w:?}");
        }
    }

    /// The lag by one exact sum per lag: what the FFT's must give.
    fn decorrelation_by_sums(y: &[f64]) -> Option<usize> {
        let n = y.len();
        let mean = y.iter().sum::<f64>() / n as f64;
        let d: Vec<f64> = y.iter().map(|v| v - mean).collect();
        let c0: f64 = d.iter().map(|v| v * v).sum();
        if c0 <= 0.0 {
            return None;
        }
        let target = (-1.0f64).exp() * c0;
        (1..n / 2).find(|&k| d[..n - k].iter().zip(&d[k..]).map(|(a, b)| a * b).sum::<f64>() < target)
    }

    #[test]
    fn the_fft_decorrelation_lag_is_the_one_the_sums_give() {
        let mut x = 0.1_f64;
        for n in [2, 3, 17, 100, 1000, 4097] {
            for (kind, f) in [
                ("noise", &(|_: usize, r: f64| r) as &dyn Fn(usize, f64) -> f64),
                ("slow sine", &|k, r| (k as f64 * 0.01).sin() + 0.01 * r),
                ("drift", &|k, r| k as f64 * 1e-3 + 1e-4 * r),
                ("steps", &|k, _| ((k / 37) % 3) as f64),
            ] {
                let y: Vec<f64> = (0..n)
                    .map(|k| {
                        x = (x * 3.9 * (1.0 - x)).clamp(1e-6, 1.0 - 1e-6);
                        f(k, x - 0.5)
                    })
                    .collect();
                assert_eq!(
                    decorrelation_lag(&y),
                    decorrelation_by_sums(&y),
                    "{kind}, n = {n}"
                );
            }
        }
    }

    #[test]
    fn decorrelation_of_white_and_constant_signals() {
        assert_eq!(decorrelation_lag(&[1.0; 50]), None);
        let alt: Vec<f64> = (0..100).map(|k| if k % 2 == 0 { 1.0 } else { -1.0 }).collect();
        assert_eq!(decorrelation_lag(&alt), Some(1));
        assert_eq!(round_sig(0.2067, 2), 0.21);
        assert_eq!(round_sig(188.0, 3), 188.0);
        assert_eq!(round_sig(1.01, 3), 1.01);
        assert_eq!(round_sig(18.8, 2), 19.0);
    }
}
