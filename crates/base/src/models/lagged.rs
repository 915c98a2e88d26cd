//! The lagged models, `kind = "arx"` and `kind = "rhonn"` (see the [`models`](super)
//! module's docs): their [`Structure`], prediction by the regressor of lagged outputs and
//! inputs (free run or K steps ahead). Their training: `sysid::lagged`.

use super::kinds::Structure;
use super::{check_regressor_count, hold, int_in, n_phi, Kind, Model, ModelSpec};
use crate::data::Record;
use crate::error::{invalid, Result};
use crate::net::Terms;

/// `kind = "arx"` and `kind = "rhonn"`.
pub(crate) struct Lagged;

impl Structure for Lagged {
    fn polynomial_terms(&self, spec: &ModelSpec) -> bool {
        spec.kind == super::Kind::Rhonn && spec.activation == super::Activation::Identity
    }

    fn with_article(&self, kind: super::Kind) -> &'static str {
        if kind == super::Kind::Arx {
            "an ARX"
        } else {
            "a RHONN"
        }
    }

    fn check_spec(&self, spec: &ModelSpec) -> Result<()> {
        if spec.kind == Kind::Rhonn {
            int_in("degree", spec.degree, 1, 5)?;
            int_in("max_factors", spec.max_factors, 1, spec.degree)?;
        }
        Ok(())
    }

    fn max_lag(&self, spec: &ModelSpec) -> usize {
        (spec.output_lag_start + spec.na - 1)
            .max(if spec.nb > 0 { spec.nk + spec.nb - 1 } else { 0 })
            .max(spec.nk)
    }

    fn predict(
        &self,
        model: &Model,
        r: &Record,
        steps_ahead: Option<usize>,
    ) -> Result<(Vec<Vec<f64>>, usize)> {
        let (un, yn) = model.normalise(r);
        let n = r.len();
        let lag = model.spec.max_lag();
        let terms = model.terms();
        let nf = model.n_features();
        let mut feat = vec![0.0; nf];
        let no = model.no();
        let bounds: Vec<(f64, f64)> = model
            .output_range
            .iter()
            .zip(&model.output_norm)
            .map(|((lo, hi), (m, s))| {
                let w = (hi - lo) * model.spec.output_margin;
                ((lo - w - m) / s, (hi + w - m) / s)
            })
            .collect();
        let mut pred = yn.clone();
        let first;
        match steps_ahead {
            None => {
                first = lag;
                for k in lag..n {
                    {
                        let p = &pred;
                        model.features(&|j, i| p[j][i], &un, k, &terms, &mut feat);
                    }
                    for j in 0..no {
                        let v: f64 = model.weights[j].iter().zip(&feat).map(|(w, f)| w * f).sum();
                        pred[j][k] = hold(v, bounds[j]);
                    }
                }
            }
            Some(kk) => {
                let kk = kk.max(1);
                first = lag + kk - 1;
                // A window of the last lag + K values: measured, then predicted.
                let mut hist = vec![vec![0.0; n]; no];
                for end in first..n {
                    let start = end + 1 - kk;
                    for j in 0..no {
                        hist[j][start - lag..start].copy_from_slice(&yn[j][start - lag..start]);
                    }
                    for k in start..=end {
                        {
                            let h = &hist;
                            model.features(&|j, i| h[j][i], &un, k, &terms, &mut feat);
                        }
                        for j in 0..no {
                            let v: f64 = model.weights[j].iter().zip(&feat).map(|(w, f)| w * f).sum();
                            hist[j][k] = hold(v, bounds[j]);
                        }
                    }
                    for j in 0..no {
                        pred[j][end] = hist[j][end];
                    }
                }
            }
        }
        let out = pred
            .iter()
            .zip(&model.output_norm)
            .map(|(c, (m, s))| c.iter().map(|v| v * s + m).collect())
            .collect();
        Ok((out, first))
    }

    fn validate(&self, m: &Model) -> Result<()> {
        check_regressor_count(&m.spec, m.ni(), m.no())?;
        if !m.terms.is_empty() {
            Terms::from_lists(&m.terms, n_phi(&m.spec, m.ni(), m.no()), "model.terms")?;
        }
        let nf = m.n_features();
        if m.weights.len() != m.no()
            || m.weights
                .iter()
                .any(|w| w.len() != nf || w.iter().any(|v| !v.is_finite()))
        {
            return Err(invalid(
                "model.weights",
                format!("{} vectors", m.weights.len()),
                format!("one vector of {nf} finite weights per output"),
            ));
        }
        Ok(())
    }

    fn n_params(&self, m: &Model) -> usize {
        n_phi(&m.spec, m.ni(), m.no()) + m.terms.len() + 1
    }
}
