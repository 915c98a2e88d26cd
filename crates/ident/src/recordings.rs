//! Online identification of recordings (`rhonn identify` as a library call): an
//! [`OnlineIdentifier`] run over records in time order for a number of passes, then
//! frozen and run free or K samples ahead on other records.

use super::online::{OnlineIdentifier, OnlineSpec, Scaling};
use crate::data::Record;
use crate::error::{invalid, Result};
use crate::metrics;
use serde::Serialize;

/// Per output: how well the online estimate followed it.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct OnlineFigures {
    /// Output column.
    pub output: String,
    /// RMS error over the last half of the final pass (output units).
    pub rms_error_last_half: f64,
    /// Fit \[%\] over the last half of the final pass.
    pub fit_percent_last_half: f64,
    /// First time \[s\] (from the final pass's start) after which |error| stays within
    /// the band (twice the last half's RMS error), or None (left out of summary.json, where
    /// a null would read as a NaN).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub converged_s: Option<f64>,
    /// The band \[output units\].
    pub band: f64,
}

/// What an online identification over recordings gives.
#[derive(Debug, Clone)]
pub struct OnlineRun {
    /// The identifier after the last pass (weights as learned).
    pub identifier: OnlineIdentifier,
    /// The final pass, per record: the estimate of each output at each sample.
    pub estimates: Vec<Vec<Vec<f64>>>,
    /// The final pass, per record and sample: the weight norm of each neuron.
    pub weight_norms: Vec<Vec<Vec<f64>>>,
    /// The final pass, per record and sample: every weight, neuron after neuron, when
    /// there are at most [`MAX_LISTED_WEIGHTS`] (else empty).
    pub weights: Vec<Vec<Vec<f64>>>,
    /// Per pass, the largest weight norm of each neuron.
    pub max_norm_per_pass: Vec<Vec<f64>>,
    /// Per output.
    pub figures: Vec<OnlineFigures>,
}

/// Most weights listed one by one in a run's trace.
pub const MAX_LISTED_WEIGHTS: usize = 50;

/// The sample time of records: the first record's median interval; every record must
/// be uniform within 1 % of it.
pub fn sample_time(records: &[Record]) -> Result<f64> {
    let dt = records.first().map_or(f64::NAN, |r| r.sample_interval());
    if !(dt.is_finite() && dt > 0.0) {
        return Err(invalid(
            "data",
            "fewer than two samples",
            "a record with at least two samples",
        ));
    }
    for r in records {
        for (k, w) in r.t.windows(2).enumerate() {
            let d = w[1] - w[0];
            if !(d > 0.0) || (d - dt).abs() > 0.01 * dt {
                let what = if d > 1.5 * dt {
                    format!(
                        "{} or a gap",
                        crate::metrics::count((d / dt).round() as usize - 1, "missing sample")
                    )
                } else {
                    "an uneven interval".to_string()
                };
                return Err(invalid(
                    format!("{}, line {}, column `t`", r.source, k + 3),
                    w[1],
                    format!(
                        "samples every {} s: after {} s comes {} s, but `t` moves by {} s here ({what}); resample the record first",
                        metrics::sig(dt, 6),
                        w[0],
                        metrics::sig(w[0] + dt, 9),
                        metrics::sig(d, 6)
                    ),
                ));
            }
        }
    }
    Ok(dt)
}

/// A constant output has nothing to identify: an error naming the records and the output.
pub fn check_outputs_vary(records: &[Record], outputs: &[String]) -> Result<()> {
    let ny = records.first().map_or(0, |r| r.outputs.len());
    for j in 0..ny {
        let first = records[0].outputs[j].first().copied().unwrap_or(0.0);
        if records.iter().all(|r| r.outputs[j].iter().all(|v| *v == first)) {
            let sources: Vec<&str> = records.iter().map(|r| r.source.as_str()).collect();
            return Err(invalid(
                format!(
                    "{}: output `{}`",
                    sources.join(", "),
                    outputs.get(j).map_or("?", |s| s.as_str())
                ),
                format!("constant {first}"),
                "an output that varies: a constant output has nothing to identify",
            ));
        }
    }
    Ok(())
}

/// The scaling an identification of `records` with `spec` uses: each output's and
/// input's mean and standard deviation over the records, and, unless `output_margin` is
/// negative, each output's range widened by `output_margin` of it on each side.
pub fn record_scaling(spec: &OnlineSpec, records: &[Record]) -> Scaling {
    let (ny, nu) = (records[0].outputs.len(), records[0].inputs.len());
    let cols = |f: fn(&Record) -> &Vec<Vec<f64>>, j: usize| -> Vec<f64> {
        records.iter().flat_map(|r| f(r)[j].iter().copied()).collect()
    };
    let ys: Vec<Vec<f64>> = (0..ny).map(|j| cols(|r| &r.outputs, j)).collect();
    let us: Vec<Vec<f64>> = (0..nu).map(|j| cols(|r| &r.inputs, j)).collect();
    let mut scaling = Scaling::of(
        &ys.iter().map(|v| v.as_slice()).collect::<Vec<_>>(),
        &us.iter().map(|v| v.as_slice()).collect::<Vec<_>>(),
    );
    if spec.output_margin >= 0.0 {
        let (lo, hi) = ranges(&ys);
        scaling.y_bounds = Some(super::online::widened(&lo, &hi, spec.output_margin));
    }
    scaling
}

/// Per column, its lowest and highest value.
fn ranges(cols: &[Vec<f64>]) -> (Vec<f64>, Vec<f64>) {
    cols.iter()
        .map(|c| {
            let lo = c.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = c.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            (lo, hi)
        })
        .unzip()
}

/// Normalisation an online identifier may use: taken from a warm-up window at the
/// stream's start, never from samples after it.
#[derive(Debug, Clone, PartialEq)]
pub struct WarmUp {
    /// Each output's and input's mean and standard deviation over the window (no bounds).
    pub scaling: Scaling,
    /// Per output, the lowest and highest value in the window.
    pub lo: Vec<f64>,
    /// See `lo`.
    pub hi: Vec<f64>,
}

impl WarmUp {
    /// From the window's columns: `ys[j]`, `us[j]` the samples of output and input `j`.
    pub fn of(ys: &[Vec<f64>], us: &[Vec<f64>]) -> Self {
        let scaling = Scaling::of(
            &ys.iter().map(|v| v.as_slice()).collect::<Vec<_>>(),
            &us.iter().map(|v| v.as_slice()).collect::<Vec<_>>(),
        );
        let (lo, hi) = ranges(ys);
        WarmUp { scaling, lo, hi }
    }

    /// From the first `samples` samples of `records`, in order.
    pub fn of_records(records: &[Record], samples: usize) -> Self {
        let (ny, nu) = (records[0].outputs.len(), records[0].inputs.len());
        let (mut ys, mut us) = (vec![Vec::new(); ny], vec![Vec::new(); nu]);
        let mut left = samples.max(1);
        for r in records {
            let n = left.min(r.len());
            for (c, src) in ys.iter_mut().zip(&r.outputs) {
                c.extend_from_slice(&src[..n]);
            }
            for (c, src) in us.iter_mut().zip(&r.inputs) {
                c.extend_from_slice(&src[..n]);
            }
            left -= n;
            if left == 0 {
                break;
            }
        }
        Self::of(&ys, &us)
    }

    /// A new identifier with `spec` normalised by this window; unless
    /// `spec.output_margin` is negative, its estimate held within the outputs' range seen
    /// so far, widened by the margin (see [`OnlineIdentifier::track_bounds`]).
    pub fn identifier(&self, spec: &OnlineSpec, dt: f64) -> Result<OnlineIdentifier> {
        let mut scaling = self.scaling.clone();
        let tracked = spec.output_margin >= 0.0;
        if tracked {
            scaling.y_bounds = Some(super::online::widened(&self.lo, &self.hi, spec.output_margin));
        }
        let (ny, nu) = (scaling.y_scale.len(), scaling.u_scale.len());
        let mut id = OnlineIdentifier::new(spec, ny, nu, dt, scaling)?;
        if tracked {
            id.track_bounds(self.lo.clone(), self.hi.clone(), spec.output_margin);
        }
        Ok(id)
    }
}

/// Identify `records` online with `spec`: `spec.epochs` passes, weights carried, the
/// model restarted at each record's first measurement; scaled by the records' means and
/// standard deviations.
pub fn identify_records(spec: &OnlineSpec, records: &[Record], outputs: &[String]) -> Result<OnlineRun> {
    identify_records_scaled(spec, records, outputs, None)
}

/// As [`identify_records`]; with `warmup = Some(n)`, normalised by the stream's first
/// `n` samples and held within the outputs' range seen so far ([`WarmUp::identifier`]),
/// as an online identifier must be.
pub fn identify_records_scaled(
    spec: &OnlineSpec,
    records: &[Record],
    outputs: &[String],
    warmup: Option<usize>,
) -> Result<OnlineRun> {
    let dt = sample_time(records)?;
    check_outputs_vary(records, outputs)?;
    let (ny, nu) = (records[0].outputs.len(), records[0].inputs.len());
    let mut id = match warmup {
        Some(n) => WarmUp::of_records(records, n).identifier(spec, dt)?,
        None => OnlineIdentifier::new(spec, ny, nu, dt, record_scaling(spec, records))?,
    };
    let mut max_norm_per_pass = Vec::new();
    let (mut estimates, mut weight_norms, mut weights) = (Vec::new(), Vec::new(), Vec::new());
    let listed = id.weight_lengths().iter().sum::<usize>() <= MAX_LISTED_WEIGHTS;
    let (mut u, mut y) = (vec![0.0; nu], vec![0.0; ny]);
    for pass in 0..spec.epochs {
        let last = pass + 1 == spec.epochs;
        let mut max_norm = vec![0.0f64; ny];
        id.new_pass();
        for r in records {
            id.reset();
            id.freeze(false);
            let (mut est, mut norms, mut all) = (Vec::new(), Vec::new(), Vec::new());
            for k in 0..r.len() {
                if let Some(f) = spec.freeze_after_s {
                    id.freeze(r.t[k] - r.t[0] >= f);
                }
                sample(r, k, &mut u, &mut y);
                let yh = id.update(r.t[k], &u, &y)?.to_vec();
                let w = id.weights();
                let n: Vec<f64> = w.iter().map(|w| super::dot(w, w).sqrt()).collect();
                for (m, v) in max_norm.iter_mut().zip(&n) {
                    *m = m.max(*v);
                }
                if last {
                    est.push(yh);
                    norms.push(n);
                    if listed {
                        all.push(w.concat());
                    }
                }
            }
            if last {
                estimates.push(est);
                weight_norms.push(norms);
                weights.push(all);
            }
        }
        max_norm_per_pass.push(max_norm);
    }
    if let Some(why) = id.unfinished() {
        return Err(crate::Error::Argument(why));
    }
    let figures = figures(records, &estimates, outputs, dt);
    Ok(OnlineRun {
        identifier: id,
        estimates,
        weight_norms,
        weights,
        max_norm_per_pass,
        figures,
    })
}

pub(super) fn sample(r: &Record, k: usize, u: &mut [f64], y: &mut [f64]) {
    for (j, c) in r.inputs.iter().enumerate() {
        u[j] = c[k];
    }
    for (j, c) in r.outputs.iter().enumerate() {
        y[j] = c[k];
    }
}

fn figures(
    records: &[Record],
    estimates: &[Vec<Vec<f64>>],
    outputs: &[String],
    dt: f64,
) -> Vec<OnlineFigures> {
    (0..outputs.len())
        .map(|j| {
            let (mut y, mut yh) = (Vec::new(), Vec::new());
            let (mut all_y, mut all_h) = (Vec::new(), Vec::new());
            for (r, est) in records.iter().zip(estimates) {
                let h = r.len() / 2;
                y.extend_from_slice(&r.outputs[j][h..]);
                yh.extend(est[h..].iter().map(|e| e[j]));
                all_y.extend_from_slice(&r.outputs[j]);
                all_h.extend(est.iter().map(|e| e[j]));
            }
            let rms = metrics::rms_error(&y, &yh);
            let band = 2.0 * rms;
            let last_out = all_y.iter().zip(&all_h).rposition(|(a, b)| (a - b).abs() > band);
            let converged_s = match last_out {
                None => Some(0.0),
                Some(k) if k + 1 < all_y.len() => Some((k + 1) as f64 * dt),
                Some(_) => None,
            };
            OnlineFigures {
                output: outputs[j].clone(),
                rms_error_last_half: rms,
                fit_percent_last_half: metrics::fit_percent(&y, &yh),
                converged_s,
                band,
            }
        })
        .collect()
}

/// Run the frozen `id` over `records`: free (`horizon = None`: from each record's first
/// measurement on the inputs alone) or `K` samples ahead (the estimate of `y(t_k)` from
/// the model restarted at the measurement `y(t_(k-K))` and run K samples on the inputs).
/// Returns the prediction of each output at each sample, per record.
pub fn predict_records(
    id: &mut OnlineIdentifier,
    records: &[Record],
    horizon: Option<usize>,
) -> Result<Vec<Vec<Vec<f64>>>> {
    for r in records {
        if let Some(k) = horizon.filter(|&k| k == 0 || k >= r.len()) {
            return Err(crate::error::invalid(
                "steps_ahead",
                k,
                format!("at least 1 and fewer than {}'s {} samples", r.source, r.len()),
            ));
        }
    }
    id.freeze(true);
    let (ny, nu) = (records[0].outputs.len(), records[0].inputs.len());
    let (mut u, mut y) = (vec![0.0; nu], vec![0.0; ny]);
    let mut out = Vec::new();
    for r in records {
        let mut pred = Vec::with_capacity(r.len());
        match horizon {
            None => {
                id.reset();
                id.set_free_run(true);
                for k in 0..r.len() {
                    sample(r, k, &mut u, &mut y);
                    pred.push(id.update(r.t[k], &u, &y)?.to_vec());
                }
            }
            Some(kh) => {
                // A frozen series-parallel tracker follows the measurements (so the
                // filters and the model's state are those at each sample); from its state
                // at sample k, restarted at y(t_k), a free run of kh samples predicts
                // y(t_(k+kh)). The first kh samples have no prediction: they hold the
                // measurement.
                id.reset();
                id.set_free_run(false);
                let mut pred_k = vec![None; r.len()];
                for k in 0..r.len() {
                    sample(r, k, &mut u, &mut y);
                    id.update(r.t[k], &u, &y)?;
                    if k + kh < r.len() {
                        let snap = id.snapshot();
                        id.set_estimate(&y);
                        id.set_free_run(true);
                        let mut yh = Vec::new();
                        for j in k + 1..=k + kh {
                            sample(r, j, &mut u, &mut y);
                            yh = id.update(r.t[j], &u, &y)?.to_vec();
                        }
                        id.set_free_run(false);
                        id.restore(&snap);
                        pred_k[k + kh] = Some(yh);
                    }
                }
                for (k, p) in pred_k.into_iter().enumerate() {
                    pred.push(p.unwrap_or_else(|| r.outputs.iter().map(|c| c[k]).collect()));
                }
            }
        }
        id.set_free_run(false);
        if let Some((k, j)) =
            (0..pred.len()).find_map(|k| pred[k].iter().position(|v| !v.is_finite()).map(|j| (k, j)))
        {
            return Err(crate::Error::NotFinite {
                what: format!("the frozen model's prediction of output {j} on {} at t = {} s", r.source, r.t[k]),
                cause: "the model overflows on these data (its scaling or weights far outside what identification gives, or data far outside the training range); nothing was written".into(),
            });
        }
        out.push(pred);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::OnlineFigures;

    /// An estimate that never stays within its band has no `converged_s` in summary.json
    /// (a null there read as a NaN to the mutation harness, and would to a user).
    #[test]
    fn never_converged_is_left_out_not_null() {
        let mut f = OnlineFigures {
            output: "y".into(),
            rms_error_last_half: 0.5,
            fit_percent_last_half: 10.0,
            converged_s: None,
            band: 1.0,
        };
        let json = serde_json::to_string(&f).unwrap();
        assert!(!json.contains("converged_s") && !json.contains("null"), "{json}");
        f.converged_s = Some(2.0);
        assert!(serde_json::to_string(&f).unwrap().contains("\"converged_s\":2.0"));
    }
}
