//! The stored model (`model.json`): its fields, its checks, and its prediction through
//! its kind's [`Structure`](super::kinds::Structure).

use super::{model_kind, n_phi, Activation, Kind, ModelSpec, MAX_REGRESSORS};
use crate::data::Record;
use crate::error::{invalid, Result};
use crate::metrics;
use crate::net::Terms;
use serde::{Deserialize, Serialize};

/// A trained model (`model.json`): everything needed to run it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Model {
    /// The structure it was trained with.
    pub spec: ModelSpec,
    /// Input column names.
    pub inputs: Vec<String>,
    /// Output column names.
    pub outputs: Vec<String>,
    /// Sampling interval \[s\].
    pub sample_time_s: f64,
    /// (mean, std) of each input.
    pub input_norm: Vec<(f64, f64)>,
    /// (mean, std) of each output.
    pub output_norm: Vec<(f64, f64)>,
    /// (min, max) of each output in the training data.
    pub output_range: Vec<(f64, f64)>,
    /// (min, max) of each input in the training data: `rhonn predict` says where a record's
    /// inputs leave it. Empty for an online model and in a model.json saved before rhonn
    /// kept it.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub input_range: Vec<(f64, f64)>,
    /// High-order terms (rhonn), `[y index, exponent]` factors.
    pub terms: Vec<Vec<[usize; 2]>>,
    /// One weight vector per output.
    pub weights: Vec<Vec<f64>>,
}

/// `v` held within `(lo, hi)`; unlike `f64::clamp`, never a panic (a NaN bound, or
/// bounds in the wrong order from data whose statistics overflowed): NaN then propagates
/// to the figures' finiteness checks, which name the data.
pub(crate) fn hold(v: f64, (lo, hi): (f64, f64)) -> f64 {
    v.max(lo).min(hi)
}

/// Figures of one output.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct OutputFigures {
    /// Output name.
    pub output: String,
    /// RMS of y - yhat.
    pub rms_error: f64,
    /// 100 (1 - |y - yhat| / |y - mean y|); undefined (left out of JSON) for a constant y.
    #[serde(skip_serializing_if = "crate::metrics::undefined")]
    pub fit_percent: f64,
    /// RMS error / range of y; undefined (left out of JSON) for a constant y.
    #[serde(skip_serializing_if = "crate::metrics::undefined")]
    pub nrmse: f64,
    /// Samples compared.
    pub samples: usize,
}

impl Model {
    /// Number of inputs.
    pub fn ni(&self) -> usize {
        self.inputs.len()
    }
    /// Number of outputs.
    pub fn no(&self) -> usize {
        self.outputs.len()
    }

    /// The features at sample k, given normalised output history `yn(j, k - i)` and
    /// inputs; written into `feat` (length [`Model::n_features`]).
    pub fn features(
        &self,
        yhist: &dyn Fn(usize, usize) -> f64,
        un: &[Vec<f64>],
        k: usize,
        terms: &Terms,
        feat: &mut [f64],
    ) {
        let s = &self.spec;
        let mut c = 0;
        for j in 0..self.no() {
            for i in s.output_lag_start..s.output_lag_start + s.na {
                feat[c] = yhist(j, k - i);
                c += 1;
            }
        }
        for u in un.iter().take(self.ni()) {
            for i in 0..s.nb {
                feat[c] = u[k - s.nk - i];
                c += 1;
            }
        }
        // Filtered inputs (appended to `un` by `normalise`), at lag nk.
        for u in un.iter().skip(self.ni()) {
            feat[c] = u[k - s.nk];
            c += 1;
        }
        let nphi = c;
        if s.kind == Kind::Rhonn {
            // y = [tanh of the output lags (or the lags themselves), input lags]
            let ny = nphi;
            let mut y = [0.0; MAX_REGRESSORS];
            let n_out_lags = self.no() * s.na;
            let squash = s.activation == Activation::Tanh;
            for q in 0..ny {
                y[q] = if q < n_out_lags && squash {
                    feat[q].tanh()
                } else {
                    feat[q]
                };
            }
            let l = terms.len();
            terms.eval(&y[..ny], &mut feat[nphi..nphi + l]);
            c += l;
        }
        feat[c] = 1.0;
    }

    /// Normalisation and ranges as a file may hold them: one per input and output (the
    /// inputs' ranges may be absent),
    /// means and ranges finite and of magnitude at most 1e150, standard deviations in
    /// [1e-150, 1e150], each range low <= high. Errors name the field and its index.
    pub(crate) fn check_scaling(&self) -> Result<()> {
        const BIG: f64 = 1e150;
        type Pairs<'a> = &'a [(f64, f64)];
        let lists: [(&str, Pairs, usize); 4] = [
            ("model.input_norm", &self.input_norm, self.ni()),
            ("model.output_norm", &self.output_norm, self.no()),
            ("model.output_range", &self.output_range, self.no()),
            ("model.input_range", &self.input_range, self.ni()),
        ];
        for (name, v, n) in lists {
            // A model without the inputs' range (online, or saved before rhonn kept it).
            if name == "model.input_range" && v.is_empty() {
                continue;
            }
            if v.len() != n {
                return Err(invalid(
                    name,
                    format!("{} entries", v.len()),
                    format!("{n}, one per column"),
                ));
            }
            for (k, &(a, b)) in v.iter().enumerate() {
                let ok = if name.ends_with("range") {
                    a.is_finite() && b.is_finite() && a <= b && a.abs() <= BIG && b.abs() <= BIG
                } else {
                    a.is_finite() && a.abs() <= BIG && b.is_finite() && (1.0 / BIG..=BIG).contains(&b)
                };
                if !ok {
                    let allowed = if name.ends_with("range") {
                        "[low, high], finite, low <= high, of magnitude at most 1e150"
                    } else {
                        "[mean, standard deviation]: a finite mean of magnitude at most 1e150, a deviation in [1e-150, 1e150]"
                    };
                    return Err(invalid(format!("{name}[{k}]"), format!("[{a}, {b}]"), allowed));
                }
            }
        }
        Ok(())
    }

    /// Check a model read from a file: names, normalisation, terms and weight lengths.
    pub fn validate(&self) -> Result<()> {
        self.spec.check()?;
        if self.outputs.is_empty() {
            return Err(invalid("model.outputs", "[]", "at least one output"));
        }
        self.check_scaling()?;
        if !(self.sample_time_s.is_finite() && self.sample_time_s > 0.0) {
            return Err(invalid(
                "model.sample_time_s",
                self.sample_time_s,
                "a finite number > 0",
            ));
        }
        model_kind(self.spec.kind).validate(self)
    }

    /// Number of features (regressors, terms, bias).
    pub fn n_features(&self) -> usize {
        model_kind(self.spec.kind).n_params(self)
    }

    /// The high-order terms over the regressors (none for an ARX).
    pub fn terms(&self) -> Terms {
        if self.terms.is_empty() {
            Terms::empty()
        } else {
            Terms::from_lists(&self.terms, n_phi(&self.spec, self.ni(), self.no()), "terms")
                .expect("a trained model's terms are valid")
        }
    }

    /// Normalised inputs (then each input through each first-order filter of
    /// `input_filters_s`, started at its first value) and normalised outputs.
    pub fn normalise(&self, r: &Record) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
        let mut un: Vec<Vec<f64>> = r
            .inputs
            .iter()
            .zip(&self.input_norm)
            .map(|(c, (m, s))| c.iter().map(|v| (v - m) / s).collect())
            .collect();
        for j in 0..self.ni() {
            for &tau in &self.spec.input_filters_s {
                let a = (-self.sample_time_s / tau).exp();
                let mut z = un[j][0];
                let f: Vec<f64> = un[j]
                    .iter()
                    .map(|&v| {
                        z = a * z + (1.0 - a) * v;
                        z
                    })
                    .collect();
                un.push(f);
            }
        }
        let yn = r
            .outputs
            .iter()
            .zip(&self.output_norm)
            .map(|(c, (m, s))| c.iter().map(|v| (v - m) / s).collect())
            .collect();
        (un, yn)
    }

    /// Predict every output of `r`: free run (`steps_ahead = None`: the model sees the
    /// inputs and the first `max_lag` measured outputs only) or `K` steps ahead (from
    /// the measurements up to k and the inputs, predict k + K). Returns the predictions
    /// (the first samples, which the model cannot predict, hold the measurements) and
    /// the index of the first genuine prediction.
    ///
    /// A `cascade` model settles its hidden states on the measured samples before each
    /// prediction's start (see [`cascade`](super::cascade)); its simulation reports a solver failure
    /// with the time and the levels.
    pub fn predict(&self, r: &Record, steps_ahead: Option<usize>) -> Result<(Vec<Vec<f64>>, usize)> {
        model_kind(self.spec.kind).predict(self, r, steps_ahead)
    }

    /// Figures per output of predictions against the record, from `first` on.
    pub fn figures(&self, r: &Record, pred: &[Vec<f64>], first: usize) -> Vec<OutputFigures> {
        self.outputs
            .iter()
            .enumerate()
            .map(|(j, name)| {
                let y = &r.outputs[j][first..];
                let yh = &pred[j][first..];
                OutputFigures {
                    output: name.clone(),
                    rms_error: metrics::rms_error(y, yh),
                    fit_percent: metrics::fit_percent(y, yh),
                    nrmse: metrics::nrmse(y, yh),
                    samples: y.len(),
                }
            })
            .collect()
    }
}
