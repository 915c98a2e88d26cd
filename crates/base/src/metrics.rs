//! Small pure functions of a measured series `y` and an estimate `yhat`, and the words
//! that print them (significant digits, counts, prediction modes).

/// Mean and standard deviation (population) of columns taken together; a constant or
/// empty set gets standard deviation 1 (a scale to divide by).
pub fn mean_std(cols: &[&[f64]]) -> (f64, f64) {
    let n: usize = cols.iter().map(|c| c.len()).sum();
    let m = cols.iter().flat_map(|c| c.iter()).sum::<f64>() / n as f64;
    let v = cols
        .iter()
        .flat_map(|c| c.iter())
        .map(|x| (x - m) * (x - m))
        .sum::<f64>()
        / n as f64;
    (m, if v > 0.0 { v.sqrt() } else { 1.0 })
}

/// Root mean square of `y - yhat`.
pub fn rms_error(y: &[f64], yhat: &[f64]) -> f64 {
    let n = y.len().min(yhat.len());
    if n == 0 {
        return f64::NAN;
    }
    (y.iter().zip(yhat).map(|(a, b)| (a - b) * (a - b)).sum::<f64>() / n as f64).sqrt()
}

/// A count with its noun, for people to read: "1 record", "2 records", "0 samples" (`noun`
/// singular, its plural by an added s: every noun counted in rhonn's messages takes one).
pub fn count(n: usize, noun: &str) -> String {
    if n == 1 {
        format!("1 {noun}")
    } else {
        format!("{n} {noun}s")
    }
}

/// How a prediction runs, in words (summary.json's `mode`, offline and online): "free run"
/// (`steps_ahead` None), "1 step ahead", "K steps ahead".
pub fn prediction_mode(steps_ahead: Option<usize>) -> String {
    steps_ahead.map_or("free run".to_string(), |k| count(k, "step") + " ahead")
}

/// `v` with `digits` significant digits, for people to read: plain decimals from 1e-4 to
/// 1e6 (`0.007589`, `27.65`), else scientific (`5.331e-5`); trailing zeros dropped.
pub fn sig(v: f64, digits: usize) -> String {
    if v == 0.0 || !v.is_finite() {
        return v.to_string();
    }
    let digits = digits.max(1);
    let mag = v.abs().log10().floor() as i32;
    if !(-4..6).contains(&mag) {
        let s = format!("{v:.*e}", digits - 1);
        return match s.split_once('e') {
            Some((m, e)) if m.contains('.') => {
                format!("{}e{e}", m.trim_end_matches('0').trim_end_matches('.'))
            }
            _ => s,
        };
    }
    let decimals = (digits as i32 - 1 - mag).max(0) as usize;
    let s = format!("{v:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}

/// Whether a figure is undefined (NaN or infinite): the fit and NRMSE of a constant output,
/// which `summary.json` leaves out rather than writing null.
pub fn undefined(v: &f64) -> bool {
    !v.is_finite()
}

/// Whether an optional figure is absent (not run) or undefined: left out of JSON, so that a
/// run without the part writes no `null` a reader could take for a failed number.
pub fn absent_or_undefined(v: &Option<f64>) -> bool {
    !v.is_some_and(f64::is_finite)
}

/// MATLAB `compare`'s fit: `100 (1 - |y - yhat| / |y - mean(y)|)` \[%\]; 100 is perfect,
/// 0 is no better than the mean, negative is worse.
pub fn fit_percent(y: &[f64], yhat: &[f64]) -> f64 {
    let n = y.len().min(yhat.len());
    let mean = y[..n].iter().sum::<f64>() / n as f64;
    let num: f64 = y
        .iter()
        .zip(yhat)
        .map(|(a, b)| (a - b) * (a - b))
        .sum::<f64>()
        .sqrt();
    let den: f64 = y[..n].iter().map(|a| (a - mean) * (a - mean)).sum::<f64>().sqrt();
    100.0 * (1.0 - num / den)
}

/// RMS error divided by the range of `y`.
pub fn nrmse(y: &[f64], yhat: &[f64]) -> f64 {
    let (lo, hi) = extent(y);
    rms_error(y, yhat) / (hi - lo)
}

/// The first time after which `|e|` stays at or below `band` to the end of the series,
/// or `None` if the last sample is outside the band.
pub fn convergence_time(t: &[f64], e: &[f64], band: f64) -> Option<f64> {
    let last_out = e.iter().rposition(|v| !(v.abs() <= band));
    match last_out {
        None => t.first().copied(),
        Some(k) if k + 1 < t.len() => Some(t[k + 1]),
        Some(_) => None,
    }
}

/// Range `max - min` of a series.
pub fn range(y: &[f64]) -> f64 {
    let (lo, hi) = extent(y);
    hi - lo
}

/// `(min, max)` of the values (`(inf, -inf)` when there are none).
pub fn extent<'a>(values: impl IntoIterator<Item = &'a f64>) -> (f64, f64) {
    values
        .into_iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(l, h), &v| {
            (l.min(v), h.max(v))
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hand_computed_series() {
        let y = [1.0, 2.0, 3.0, 4.0];
        let yhat = [1.0, 2.0, 3.0, 6.0];
        assert_eq!(rms_error(&y, &yhat), 1.0);
        // |y - yhat| = 2, |y - mean| = sqrt(5)
        assert!((fit_percent(&y, &yhat) - 100.0 * (1.0 - 2.0 / 5f64.sqrt())).abs() < 1e-12);
        assert_eq!(fit_percent(&y, &y), 100.0);
        assert_eq!(sig(0.007589123, 4), "0.007589");
        assert_eq!(sig(27.654, 4), "27.65");
        assert_eq!(sig(5.3312e-5, 4), "5.331e-5");
        assert_eq!(sig(1.0e-4, 4), "0.0001");
        assert_eq!(sig(1234567.0, 3), "1.23e6");
        assert_eq!(sig(-0.5, 4), "-0.5");
        assert_eq!(count(1, "record"), "1 record");
        assert_eq!(count(0, "sample"), "0 samples");
        assert_eq!(count(10, "step"), "10 steps");
        assert_eq!(prediction_mode(Some(1)), "1 step ahead");
        assert_eq!(prediction_mode(None), "free run");
        assert!((nrmse(&y, &yhat) - 1.0 / 3.0).abs() < 1e-15);
        let t = [0.0, 0.1, 0.2, 0.3, 0.4];
        let e = [5.0, -2.0, 0.5, -0.1, 0.05];
        assert_eq!(convergence_time(&t, &e, 1.0), Some(0.2));
        assert_eq!(convergence_time(&t, &e, 10.0), Some(0.0));
        assert_eq!(convergence_time(&t, &e, 0.01), None);
        assert_eq!(range(&y), 3.0);
    }
}
