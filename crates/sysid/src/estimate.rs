//! The estimators of the lagged models: batch ridge least squares, recursive laws over
//! epochs, and the free-run (simulation-error) refinement by Levenberg-Marquardt.

use super::*;
use crate::lagged_normal::free_run_residuals;
use crate::law::{Gradient, LearningLaw, LeastSquares, Rule};

/// Levenberg-Marquardt on the free-run error (`horizon` None) or on the `horizon`-step
/// predictions' error, from the current weights. The free run's Jacobian comes from its
/// forward sensitivities ([`lagged_normal`](super::lagged_normal)); the K-step predictions',
/// whose every window restarts from measurements, by forward differences (a free run per
/// weight).
pub(super) fn simulation_error(m: &mut Model, records: &[Record], horizon: Option<usize>) {
    let shapes: Vec<usize> = m.weights.iter().map(|w| w.len()).collect();
    let set = |m: &mut Model, th: &[f64]| {
        let mut o = 0;
        for (w, &l) in m.weights.iter_mut().zip(&shapes) {
            w.copy_from_slice(&th[o..o + l]);
            o += l;
        }
    };
    let mut theta: Vec<f64> = m.weights.iter().flatten().copied().collect();
    let iters = m.spec.epochs;
    let base = m.clone();
    let at = |th: &[f64]| {
        let mut w = base.clone();
        set(&mut w, th);
        w
    };
    if horizon.is_none() {
        lm_normal(
            &mut theta,
            iters,
            &|th| {
                let mut out = Vec::new();
                free_run_residuals(&at(th), records, None, &mut out);
                Some(out.iter().map(|v| v * v).sum::<f64>())
            },
            &|th| Some(crate::lagged_normal::normal(&at(th), records)),
        );
    } else {
        lm(&mut theta, iters, 1e-6, &|th, out| {
            free_run_residuals(&at(th), records, horizon, out);
            true
        });
    }
    set(m, &theta);
}

/// Ridge least squares by the normal equations and a Cholesky factorisation.
pub(super) fn batch_ls(rows: &[Vec<f64>], targets: &[Vec<f64>], ridge: f64) -> Result<Vec<Vec<f64>>> {
    let nf = rows[0].len();
    let x = DMatrix::from_fn(rows.len(), nf, |i, j| rows[i][j]);
    let mut xtx = x.transpose() * &x;
    let mean_diag = (0..nf).map(|i| xtx[(i, i)]).sum::<f64>() / nf as f64;
    for i in 0..nf {
        xtx[(i, i)] += ridge * mean_diag + 1e-12 * mean_diag;
    }
    // Collinear regressors (an input that is constant or equals another, an output lag
    // that repeats an input) leave the Gram matrix singular without a ridge.
    let chol = xtx.cholesky().ok_or_else(|| {
        invalid(
            "model.ridge",
            ridge,
            "a larger ridge (e.g. 1e-6): the regressors are collinear on these data (a constant \
             input, an input equal to another or to an output, or more lags than the data can tell \
             apart), so least squares has no unique solution without one",
        )
    })?;
    Ok(targets
        .iter()
        .map(|y| {
            let rhs = x.transpose() * DVector::from_column_slice(y);
            chol.solve(&rhs).iter().copied().collect()
        })
        .collect())
}

/// The recursive least-squares law (gain None) or the normalised gradient law over
/// epochs, the weights of one epoch starting the next.
pub(super) fn recursive(
    rows: &[Vec<f64>],
    targets: &[Vec<f64>],
    epochs: usize,
    gain: Option<f64>,
) -> Vec<Vec<f64>> {
    let nf = rows[0].len();
    // One neuron per output; normalised gradient or recursive least squares with
    // P reset to 1e3 I each epoch (the library's laws, sampled).
    let rule = match gain {
        Some(g) => Rule::Gradient(Gradient::scalar(g, 1)),
        None => Rule::LeastSquares(LeastSquares {
            p0: vec![1e3],
            floor: vec![0.0],
        }),
    };
    let mut p = vec![0.0; rule.law_states(nf)];
    let mut work = vec![0.0; nf];
    targets
        .iter()
        .map(|y| {
            let mut w = vec![0.0; nf];
            for _ in 0..epochs {
                rule.init(0, nf, &mut p);
                for (row, &yk) in rows.iter().zip(y) {
                    let e = crate::law::dot(&w, row) - yk;
                    rule.update(0, row, e, &mut w, &mut p, &mut work);
                }
            }
            w
        })
        .collect()
}

/// Train a model of `outputs` from `inputs` on `records` (uniformly sampled at the same
/// interval; see [`Record::uniform`]).
pub fn fit(spec: &ModelSpec, records: &[Record], inputs: &[String], outputs: &[String]) -> Result<Model> {
    let model = fit_pruned(spec, records, inputs, outputs)?;
    ensure_finite_model(&model, records)?;
    Ok(model)
}

/// [`fit`] of a cascade (`spec.kind` = cascade), with the training cost of the start it
/// kept: the selection merges two halves of a cascade's starts by it (`select_cascade`).
pub(crate) fn fit_cascade(
    spec: &ModelSpec,
    records: &[Record],
    inputs: &[String],
    outputs: &[String],
) -> Result<(Model, f64)> {
    let mut model = blank_model(spec, records, inputs, outputs)?;
    let cost = cascade::fit(spec, records, &mut model)?;
    ensure_finite_model(&model, records)?;
    Ok((model, cost))
}

fn fit_pruned(spec: &ModelSpec, records: &[Record], inputs: &[String], outputs: &[String]) -> Result<Model> {
    let full = fit_terms(spec, records, inputs, outputs, None)?;
    match spec.max_terms {
        Some(keep) if spec.kind == Kind::Rhonn && full.terms.len() > keep => {
            let nphi = n_phi(spec, inputs.len(), outputs.len());
            let nt = full.terms.len();
            let mut kept: Vec<usize> = match spec.term_selection {
                TermSelection::Weight => {
                    // Prune by weight magnitude: the terms work on normalised signals, so
                    // their weights are comparable; keep the `keep` largest (largest over
                    // the outputs).
                    let mut rank: Vec<(usize, f64)> = (0..nt)
                        .map(|q| {
                            (
                                q,
                                full.weights.iter().map(|w| w[nphi + q].abs()).fold(0.0, f64::max),
                            )
                        })
                        .collect();
                    rank.sort_by(|a, b| b.1.total_cmp(&a.1));
                    rank[..keep].iter().map(|r| r.0).collect()
                }
                TermSelection::ErrorReduction => {
                    // The linear regressors and the bias (the last feature) in from the
                    // start, the terms by error reduction ratio.
                    let (rows, targets) = regression_rows(&full, records);
                    let fixed: Vec<usize> = (0..nphi).chain([nphi + nt]).collect();
                    let terms: Vec<usize> = (nphi..nphi + nt).collect();
                    super::term_selection::by_error_reduction(&rows, &targets, &fixed, &terms, keep)
                        .into_iter()
                        .map(|c| c - nphi)
                        .collect()
                }
            };
            // In their original order, and train again.
            kept.sort_unstable();
            let terms = kept.iter().map(|&q| full.terms[q].clone()).collect();
            fit_terms(spec, records, inputs, outputs, Some(terms))
        }
        _ => Ok(full),
    }
}

fn fit_terms(
    spec: &ModelSpec,
    records: &[Record],
    inputs: &[String],
    outputs: &[String],
    given_terms: Option<Vec<Vec<[usize; 2]>>>,
) -> Result<Model> {
    let mut model = blank_model(spec, records, inputs, outputs)?;
    match given_terms {
        // A RHONN refitted on the terms its first fit kept (`max_terms`).
        Some(t) if spec.kind == Kind::Rhonn => {
            check_regressor_count(spec, inputs.len(), outputs.len())?;
            model.terms = t;
            fit_weights(&mut model, records)?;
        }
        _ => super::fitter(spec.kind).fit(spec, records, &mut model)?,
    }
    Ok(model)
}

/// Check the spec and the records and make an untrained model: names, sample time,
/// normalisation and output ranges.
fn blank_model(spec: &ModelSpec, records: &[Record], inputs: &[String], outputs: &[String]) -> Result<Model> {
    spec.check()?;
    super::model_kind(spec.kind).check_outputs(outputs)?;
    if records.is_empty() {
        return Err(invalid("records", "none", "at least one record"));
    }
    let lag = spec.max_lag();
    for r in records {
        r.check(lag + 2)?;
    }
    let dt = records[0].sample_interval();
    for r in &records[1..] {
        let d = r.sample_interval();
        if (d - dt).abs() > 1e-6 * dt {
            return Err(invalid(
                format!("{}: sampling interval", r.source),
                d,
                format!("the first file's, {dt} s"),
            ));
        }
    }
    let ni = inputs.len();
    let no = outputs.len();
    let input_norm = (0..ni)
        .map(|j| {
            crate::metrics::mean_std(&records.iter().map(|r| r.inputs[j].as_slice()).collect::<Vec<_>>())
        })
        .collect();
    let output_norm: Vec<(f64, f64)> = (0..no)
        .map(|j| {
            crate::metrics::mean_std(
                &records
                    .iter()
                    .map(|r| r.outputs[j].as_slice())
                    .collect::<Vec<_>>(),
            )
        })
        .collect();
    let output_range = (0..no)
        .map(|j| crate::metrics::extent(records.iter().flat_map(|r| &r.outputs[j])))
        .collect();
    let input_range = (0..inputs.len())
        .map(|j| crate::metrics::extent(records.iter().flat_map(|r| &r.inputs[j])))
        .collect();
    Ok(Model {
        spec: spec.clone(),
        inputs: inputs.to_vec(),
        outputs: outputs.to_vec(),
        sample_time_s: dt,
        input_norm,
        output_norm,
        output_range,
        input_range,
        terms: vec![],
        weights: vec![],
    })
}

/// The regression rows of a lagged model over `records` and the normalised outputs they
/// predict (series-parallel: lagged measured outputs).
fn regression_rows(model: &Model, records: &[Record]) -> (Vec<Vec<f64>>, Vec<Vec<f64>>) {
    let (no, lag, nf) = (model.no(), model.spec.max_lag(), model.n_features());
    let t = model.terms();
    let mut rows: Vec<Vec<f64>> = Vec::new();
    let mut targets: Vec<Vec<f64>> = vec![Vec::new(); no];
    for r in records {
        let (un, yn) = model.normalise(r);
        for k in lag..r.len() {
            let mut feat = vec![0.0; nf];
            model.features(&|j, i| yn[j][i], &un, k, &t, &mut feat);
            rows.push(feat);
            for j in 0..no {
                targets[j].push(yn[j][k]);
            }
        }
    }
    (rows, targets)
}

/// Train the weights of a lagged model (`arx` or `rhonn`) whose terms are set.
pub(super) fn fit_weights(model: &mut Model, records: &[Record]) -> Result<()> {
    let spec = model.spec.clone();
    let spec = &spec;
    if model.terms.len() > crate::net::MAX_TERMS {
        return Err(invalid(
            "model.degree",
            spec.degree,
            format!(
                "a structure with at most {} high-order terms (this one gives {}: lower degree, max_factors or the lags)",
                crate::net::MAX_TERMS,
                model.terms.len()
            ),
        ));
    }
    let (rows, targets) = regression_rows(model, records);
    let weights = match spec.law {
        Estimator::BatchLs | Estimator::SimulationError | Estimator::MultiStep => {
            batch_ls(&rows, &targets, spec.ridge)?
        }
        Estimator::Rls => recursive(&rows, &targets, spec.epochs, None),
        Estimator::Gradient => recursive(&rows, &targets, spec.epochs, Some(spec.gain)),
    };
    model.weights = weights;
    match spec.law {
        Estimator::SimulationError => simulation_error(model, records, None),
        Estimator::MultiStep => simulation_error(model, records, Some(spec.horizon)),
        _ => {}
    }
    Ok(())
}
