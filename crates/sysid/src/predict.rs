//! `rhonn predict` as a library call: a fitted model (and its ARX baseline) on one
//! record, free run or K steps ahead, with the figures.

use super::checks::{outputs_at_bound, OutputAtBound};
use super::{ensure_finite_figures, FittedModel, OutputFigures};
use crate::data::{within_window, Record};
use crate::error::{invalid, Result};
use serde::Serialize;

/// A prediction of every output of one record.
#[derive(Debug, Clone, PartialEq)]
pub struct Prediction {
    /// The record on the model's sampling grid (resampled when it was sampled otherwise).
    pub record: Record,
    /// The record's own interval \[s\] when it was resampled onto the model's grid.
    pub resampled_from_s: Option<f64>,
    /// None: free run; K: K steps ahead.
    pub steps_ahead: Option<usize>,
    /// A free run's state-initialisation window: the outputs it saw (None: what the model
    /// needs).
    pub init_window: Option<usize>,
    /// One column per output (the measurement repeated before `first`).
    pub outputs: Vec<Vec<f64>>,
    /// The first predicted sample (with a state-initialisation window: the window's end,
    /// the first sample scored).
    pub first: usize,
    /// The model's figures per output.
    pub figures: Vec<OutputFigures>,
    /// The ARX baseline's prediction and figures, when the model has one.
    pub baseline: Option<(Vec<Vec<f64>>, Vec<OutputFigures>)>,
    /// The record's inputs that leave the model's training range ([`inputs_beyond_training`]).
    pub inputs_beyond: Vec<InputBeyond>,
    /// The record's measured outputs that leave it ([`outputs_beyond_training`]).
    pub outputs_beyond: Vec<OutputBeyond>,
    /// A free run's outputs that reach the bound the model holds them in
    /// ([`outputs_at_bound`]; empty K steps ahead).
    pub at_bound: Vec<OutputAtBound>,
}

/// An input of a record that leaves the model's training range.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct InputBeyond {
    /// The input's column.
    pub input: String,
    /// Its (min, max) on the record.
    pub record_range: (f64, f64),
    /// Its (min, max) in the training data.
    pub training_range: (f64, f64),
    /// The share of the record's samples outside the training range, in [0, 1].
    pub share_outside: f64,
}

/// An output whose measurement on a record leaves the model's training range: the record
/// runs where the training data never went.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct OutputBeyond {
    /// The output's column.
    pub output: String,
    /// Its measured (min, max) on the record.
    pub record_range: (f64, f64),
    /// Its (min, max) in the training data.
    pub training_range: (f64, f64),
    /// The share of the record's samples outside the training range, in [0, 1].
    pub share_outside: f64,
}

/// How far beyond its training range, as a share of that range's span, an input or a
/// measured output must go for a prediction to say so: a record of the same kind reaches a
/// little past its training's extremes (noise, a longer record), which says nothing.
pub const BEYOND_SPAN: f64 = 0.1;

/// The inputs of `record` that go beyond `m`'s training range by more than [`BEYOND_SPAN`]
/// of its span on either side: there every model extrapolates, a nonlinear one in a way no
/// training data checked (on the unseen-systems corpus a closed-loop positioning system
/// tested on pulses met forces 5 x its training's, and its nonlinear models ran free
/// several times worse than the ARX). Empty for a model that does not keep the range.
pub fn inputs_beyond_training(m: &crate::Model, record: &Record) -> Vec<InputBeyond> {
    m.input_range
        .iter()
        .zip(&m.inputs)
        .zip(&record.inputs)
        .filter_map(|((&range, name), u)| {
            beyond(u, range).map(|(record_range, share_outside)| InputBeyond {
                input: name.clone(),
                record_range,
                training_range: range,
                share_outside,
            })
        })
        .collect()
}

/// The measured outputs of `record` that go beyond `m`'s training range by more than
/// [`BEYOND_SPAN`] of its span: the record's operating point is one the training data never
/// reached, even where its inputs stay within theirs (on the unseen-systems corpus a
/// backlash trained and tested on multisines sat at -0.91 on average in training and at
/// -0.03 on test, half the test above every training output; its nonlinear models ran free
/// 2 to 4 x worse than the ARX there).
pub fn outputs_beyond_training(m: &crate::Model, record: &Record) -> Vec<OutputBeyond> {
    m.output_range
        .iter()
        .zip(&m.outputs)
        .zip(&record.outputs)
        .filter_map(|((&range, name), y)| {
            beyond(y, range).map(|(record_range, share_outside)| OutputBeyond {
                output: name.clone(),
                record_range,
                training_range: range,
                share_outside,
            })
        })
        .collect()
}

/// `v`'s (min, max) and the share of its samples outside `(lo, hi)`, when it leaves that
/// range by more than [`BEYOND_SPAN`] of its span on either side.
fn beyond(v: &[f64], (lo, hi): (f64, f64)) -> Option<((f64, f64), f64)> {
    let (min, max) = crate::metrics::extent(v);
    let margin = BEYOND_SPAN * (hi - lo);
    (min < lo - margin || max > hi + margin).then(|| {
        (
            (min, max),
            v.iter().filter(|&&x| x < lo || x > hi).count() as f64 / v.len().max(1) as f64,
        )
    })
}

impl Prediction {
    /// The warnings of a record's inputs and measured outputs beyond the training range,
    /// in words.
    pub fn range_warnings(&self) -> Vec<String> {
        let source = &self.record.source;
        self.inputs_beyond
            .iter()
            .map(|b| b.said(source))
            .chain(self.outputs_beyond.iter().map(|b| b.said(source)))
            .chain(self.at_bound.iter().map(|b| {
                format!(
                    "the model's free run of output `{}` on {source} reaches the bound it is held in (the training range widened by output_margin) at t = {} s and sits on it for {} % of the predicted samples: there it ran away from the system and was clipped; compare its free run with the ARX baseline's",
                    b.output,
                    crate::metrics::sig(b.first_t_s, 6),
                    crate::metrics::sig(100.0 * b.share, 3)
                )
            }))
            .collect()
    }
}

impl InputBeyond {
    /// In words, for the record `source`.
    pub fn said(&self, source: &str) -> String {
        let sig = |v: f64| crate::metrics::sig(v, 3);
        format!(
            "input `{}` of {source} spans [{}, {}] where the model was trained on [{}, {}] ({} % of its samples outside): the model extrapolates there, a nonlinear one in a way no training data checked; compare its free run with the ARX baseline's",
            self.input,
            sig(self.record_range.0),
            sig(self.record_range.1),
            sig(self.training_range.0),
            sig(self.training_range.1),
            sig(100.0 * self.share_outside)
        )
    }
}

impl OutputBeyond {
    /// In words, for the record `source`.
    pub fn said(&self, source: &str) -> String {
        let sig = |v: f64| crate::metrics::sig(v, 3);
        format!(
            "output `{}` of {source} was measured over [{}, {}] where the model was trained on [{}, {}] ({} % of its samples outside): the record runs where the training data never went, and a nonlinear model extrapolates there; compare its free run with the ARX baseline's",
            self.output,
            sig(self.record_range.0),
            sig(self.record_range.1),
            sig(self.training_range.0),
            sig(self.training_range.1),
            sig(100.0 * self.share_outside)
        )
    }
}

/// What `rhonn predict` writes to `summary.json`.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct PredictSummary<'a> {
    /// rhonn's version.
    pub rhonn_version: &'static str,
    /// Where the model came from.
    pub model: &'a str,
    /// The record's source.
    pub data: &'a str,
    /// "free run", "1 step ahead" or "K steps ahead".
    pub mode: String,
    /// None: free run.
    pub steps_ahead: Option<usize>,
    /// A free run's state-initialisation window (outputs seen; absent: what the model needs).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub init_window: Option<usize>,
    /// The model's figures.
    pub outputs: &'a [OutputFigures],
    /// The baseline's figures.
    pub baseline_arx: Option<&'a [OutputFigures]>,
    /// The record's inputs beyond the training range (absent: none).
    #[serde(skip_serializing_if = "<[_]>::is_empty")]
    pub inputs_beyond_training: &'a [InputBeyond],
    /// The record's measured outputs beyond the training range (absent: none).
    #[serde(skip_serializing_if = "<[_]>::is_empty")]
    pub outputs_beyond_training: &'a [OutputBeyond],
    /// What the figures say, in words.
    pub findings: Vec<String>,
}

/// Per output: the prediction against the mean and against the ARX baseline, in words.
fn findings(mode: &str, figures: &[OutputFigures], baseline: Option<&[OutputFigures]>) -> Vec<String> {
    let sig = crate::metrics::sig;
    let mut v = Vec::new();
    for (j, f) in figures.iter().enumerate() {
        if !f.fit_percent.is_finite() {
            continue;
        }
        let mut line = format!(
            "{} ({mode}): fit {:.1} % over {} samples ({})",
            f.output,
            f.fit_percent,
            f.samples,
            if f.fit_percent < 0.0 {
                "worse than predicting the mean"
            } else {
                "better than predicting the mean"
            }
        );
        if let Some(b) = baseline
            .and_then(|b| b.get(j))
            .filter(|b| b.fit_percent.is_finite())
        {
            line += &format!(
                "; the ARX baseline's {:.1} %: the model's RMS error is {} x the baseline's",
                b.fit_percent,
                sig(f.rms_error / b.rms_error, 3)
            );
        }
        v.push(line);
    }
    v
}

impl Prediction {
    /// "free run", "1 step ahead" or "K steps ahead".
    pub fn mode(&self) -> String {
        crate::metrics::prediction_mode(self.steps_ahead)
    }

    /// The summary, naming the model's source `model`.
    pub fn summary<'a>(&'a self, model: &'a str) -> PredictSummary<'a> {
        PredictSummary {
            rhonn_version: env!("CARGO_PKG_VERSION"),
            model,
            data: &self.record.source,
            mode: self.mode(),
            steps_ahead: self.steps_ahead,
            init_window: self.init_window,
            outputs: &self.figures,
            baseline_arx: self.baseline.as_ref().map(|(_, f)| f.as_slice()),
            inputs_beyond_training: &self.inputs_beyond,
            outputs_beyond_training: &self.outputs_beyond,
            findings: findings(
                &self.mode(),
                &self.figures,
                self.baseline.as_ref().map(|(_, f)| f.as_slice()),
            )
            .into_iter()
            .chain(self.range_warnings())
            .collect(),
        }
    }
}

/// Samples a record needs for `fitted` to predict `steps_ahead` (None: free run).
pub fn samples_needed(fitted: &FittedModel, steps_ahead: Option<usize>) -> usize {
    fitted
        .max_lag()
        .saturating_add(steps_ahead.unwrap_or(1))
        .saturating_add(1)
}

/// Predict every output of `record` with `fitted`, free run (`steps_ahead` None) or K
/// steps ahead. A record sampled at another interval than the model's is put on the
/// model's grid first (inputs held, outputs interpolated: [`Record::uniform`]).
pub fn predict(fitted: &FittedModel, record: &Record, steps_ahead: Option<usize>) -> Result<Prediction> {
    predict_with(fitted, record, steps_ahead, None)
}

/// A prediction's options, the one place of their rules (the doors rename the fields:
/// `--steps-ahead`, `--init-window` on the command line): K steps ahead at least 1; a
/// state-initialisation window of N >= 1 outputs, for a free run only.
pub fn check_prediction_options(steps_ahead: Option<usize>, init_window: Option<usize>) -> Result<()> {
    let wide = |v: Option<usize>| v.map(|v| v as i128);
    prediction_options(wide(steps_ahead), wide(init_window)).map(|_| ())
}

/// [`check_prediction_options`] for a door whose integers may be negative or beyond a
/// `usize` (Python's): the options as counts, or what is wrong with the value given.
pub fn prediction_options(
    steps_ahead: Option<i128>,
    init_window: Option<i128>,
) -> Result<(Option<usize>, Option<usize>)> {
    let count = |v: Option<i128>, field: &str, allowed: &str| {
        v.map(|v| {
            usize::try_from(v)
                .ok()
                .filter(|&c| c >= 1)
                .ok_or_else(|| invalid(field, v, allowed))
        })
        .transpose()
    };
    let steps = count(
        steps_ahead,
        "steps_ahead",
        "K >= 1 steps ahead, or none for a free run",
    )?;
    match init_window {
        Some(w) if steps.is_some() => Err(invalid(
            "init_window",
            w,
            "a free run's window (K steps ahead measures every output up to each start): give one or the other",
        )),
        _ => Ok((steps, count(init_window, "init_window", "N >= 1 measured outputs")?)),
    }
}

/// Check a state-initialisation window against a prediction's mode and a record.
pub fn check_window(init_window: Option<usize>, steps_ahead: Option<usize>, r: &Record) -> Result<()> {
    check_prediction_options(steps_ahead, init_window)?;
    match init_window {
        Some(w) if w >= r.len() => Err(invalid(
            format!("init_window for {}", r.source),
            w,
            format!("at least 1 sample and fewer than its {}", r.len()),
        )),
        _ => Ok(()),
    }
}

/// [`predict`], and with `init_window` = N a free run that sees only the record's first
/// N outputs (a benchmark's state-initialisation window; a model that needs more past
/// outputs gets the first sample held before the record: [`crate::data::within_window`]);
/// the model and its baseline are then both scored from sample N on.
pub fn predict_with(
    fitted: &FittedModel,
    record: &Record,
    steps_ahead: Option<usize>,
    init_window: Option<usize>,
) -> Result<Prediction> {
    check_prediction_options(steps_ahead, init_window)?;
    if let Some(k) = steps_ahead.filter(|&k| k >= record.len()) {
        return Err(invalid(
            "steps_ahead",
            k,
            format!("fewer steps than {}'s {} samples", record.source, record.len()),
        ));
    }
    let m = &fitted.model;
    let need = samples_needed(fitted, steps_ahead);
    let dt = record.sample_interval();
    let (record, resampled_from_s) = if record.on_grid(m.sample_time_s) {
        (record.clone(), None)
    } else {
        (record.uniform(m.sample_time_s, "model.sample_time_s")?, Some(dt))
    };
    if record.len() < need {
        return Err(invalid(
            format!(
                "{} (samples on the grid of the model's model.sample_time_s = {} s)",
                record.source,
                crate::metrics::sig(m.sample_time_s, 6)
            ),
            record.len(),
            format!("at least {need} samples for this model"),
        ));
    }
    check_window(init_window, steps_ahead, &record)?;
    type Run<'a> = &'a dyn Fn(&Record) -> Result<(Vec<Vec<f64>>, usize)>;
    let run = |predict: Run| match init_window {
        Some(w) => within_window(&record, w, predict).map(|(p, _)| (p, w)),
        None => predict(&record),
    };
    let (outputs, first) = run(&|r| fitted.predict(r, steps_ahead))?;
    let figures = m.figures(&record, &outputs, first);
    ensure_finite_figures(&figures, &record.source)?;
    let baseline = match &fitted.baseline {
        Some(b) => {
            let need_b = b.spec.max_lag() + steps_ahead.unwrap_or(1) + 1;
            if record.len() < need_b {
                return Err(invalid(
                    format!("{} (the model's ARX baseline)", record.source),
                    record.len(),
                    format!("at least {need_b} samples for its lags (model.json's baseline.spec)"),
                ));
            }
            let (pb, fb) = run(&|r| b.predict(r, steps_ahead))?;
            let f = b.figures(&record, &pb, fb);
            ensure_finite_figures(&f, &format!("{} (ARX baseline)", record.source))?;
            Some((pb, f))
        }
        None => None,
    };
    let inputs_beyond = inputs_beyond_training(m, &record);
    let outputs_beyond = outputs_beyond_training(m, &record);
    let at_bound = match steps_ahead {
        None => outputs_at_bound(m, &record, &outputs, first),
        Some(_) => Vec::new(),
    };
    Ok(Prediction {
        record,
        resampled_from_s,
        steps_ahead,
        init_window,
        outputs,
        first,
        figures,
        baseline,
        inputs_beyond,
        outputs_beyond,
        at_bound,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{train, ModelSpec};

    fn record(n: usize, dt: f64) -> Record {
        let mut y = 0.0;
        let (mut t, mut u, mut ys) = (Vec::new(), Vec::new(), Vec::new());
        for k in 0..n {
            let uk = if (k / 9) % 2 == 0 { 1.0 } else { -1.0 };
            t.push(k as f64 * dt);
            u.push(uk);
            ys.push(y);
            y = 0.8 * y + 0.2 * uk;
        }
        Record {
            source: "r.csv".into(),
            t,
            inputs: vec![u],
            outputs: vec![ys],
        }
    }

    /// An ARX of one input `u` and one output `y` trained on `r`.
    fn arx_on(r: &Record) -> (FittedModel, crate::FitSummary) {
        let (u, y) = (vec!["u".to_string()], vec!["y".to_string()]);
        let spec = ModelSpec {
            kind: crate::Kind::Arx,
            ..ModelSpec::default()
        };
        train(&[spec], std::slice::from_ref(r), &u, &y).unwrap()
    }

    #[test]
    fn train_then_predict_are_library_calls_with_clear_errors() {
        let (fitted, summary) = arx_on(&record(200, 0.1));
        assert!(summary.training.free_run[0].outputs[0].fit_percent > 99.0);
        let p = predict(&fitted, &record(100, 0.1), Some(3)).unwrap();
        assert_eq!((p.steps_ahead, p.resampled_from_s), (Some(3), None));
        assert!(p.figures[0].fit_percent > 99.0, "{:?}", p.figures);
        // Sampled at another interval: put on the model's grid, and said so.
        let p = predict(&fitted, &record(200, 0.05), None).unwrap();
        assert_eq!(p.resampled_from_s.map(|d| (d * 1e6).round()), Some(50_000.0));
        assert_eq!(p.record.len(), 100);
        let e = predict(&fitted, &record(100, 0.1), Some(0))
            .unwrap_err()
            .to_string();
        assert!(e.contains("`steps_ahead` = 0"), "{e}");
        let e = predict(&fitted, &record(3, 0.1), None).unwrap_err().to_string();
        assert!(e.contains("r.csv") && e.contains("at least"), "{e}");
    }

    #[test]
    fn a_measured_output_beyond_the_training_range_is_said_even_where_the_inputs_stay_within() {
        let (fitted, _) = arx_on(&record(200, 0.1));
        let (lo, hi) = fitted.model.output_range[0];
        // The same record: nothing to say.
        let p = predict(&fitted, &record(100, 0.1), None).unwrap();
        assert!(p.outputs_beyond.is_empty(), "{:?}", p.outputs_beyond);
        // The same inputs at another operating point: the second half's output raised by
        // twice the training span (a backlash that kept its position, a drift).
        let mut shifted = record(100, 0.1);
        for v in &mut shifted.outputs[0][50..] {
            *v += 2.0 * (hi - lo);
        }
        let p = predict(&fitted, &shifted, None).unwrap();
        assert!(p.inputs_beyond.is_empty(), "{:?}", p.inputs_beyond);
        assert_eq!(p.outputs_beyond.len(), 1, "{:?}", p.outputs_beyond);
        let b = &p.outputs_beyond[0];
        assert_eq!(b.training_range, (lo, hi));
        assert!((b.share_outside - 0.5).abs() < 1e-12, "{}", b.share_outside);
        let said = p.summary("m.json").findings.join("\n");
        assert!(
            said.contains("output `y` of r.csv was measured over [")
                && said.contains(
                    "(50 % of its samples outside): the record runs where the training data never went"
                ),
            "{said}"
        );
    }

    #[test]
    fn inputs_beyond_the_training_range_are_said_and_inputs_within_it_are_not() {
        let (fitted, _) = arx_on(&record(200, 0.1));
        assert_eq!(fitted.model.input_range, vec![(-1.0, 1.0)]);
        // The same kind of record: nothing to say.
        let p = predict(&fitted, &record(100, 0.1), None).unwrap();
        assert!(p.inputs_beyond.is_empty(), "{:?}", p.inputs_beyond);
        // Within a tenth of the span beyond it: nothing either.
        let mut near = record(100, 0.1);
        near.inputs[0][5] = 1.19;
        assert!(predict(&fitted, &near, None).unwrap().inputs_beyond.is_empty());
        // Three times the training amplitude, on every other hold.
        let mut far = record(100, 0.1);
        for (k, v) in far.inputs[0].iter_mut().enumerate() {
            if (k / 18) % 2 == 0 {
                *v *= 3.0;
            }
        }
        let p = predict(&fitted, &far, None).unwrap();
        assert_eq!(p.inputs_beyond.len(), 1, "{:?}", p.inputs_beyond);
        let b = &p.inputs_beyond[0];
        assert_eq!((b.record_range, b.training_range), ((-3.0, 3.0), (-1.0, 1.0)));
        assert!((b.share_outside - 0.54).abs() < 1e-12, "{}", b.share_outside);
        let said = p.summary("m.json").findings.join("\n");
        assert!(
            said.contains("input `u` of r.csv spans [-3, 3] where the model was trained on [-1, 1] (54 % of its samples outside)"),
            "{said}"
        );
        // A model that does not keep the range (online, or saved before it was kept).
        let mut old = fitted.clone();
        old.model.input_range.clear();
        assert!(predict(&old, &far, None).unwrap().inputs_beyond.is_empty());
        let text = serde_json::to_string(&old.model).unwrap();
        assert!(!text.contains("input_range"));
        let back: crate::Model = serde_json::from_str(&text).unwrap();
        back.validate().unwrap();
    }

    #[test]
    fn a_free_run_that_reaches_the_bound_its_output_is_held_in_is_said_with_its_share() {
        let (mut fitted, _) = arx_on(&record(200, 0.1));
        // The same kind of record: the free run stays within the range.
        let p = predict(&fitted, &record(100, 0.1), None).unwrap();
        assert!(p.at_bound.is_empty(), "{:?}", p.at_bound);
        // A model held in a fifth of its range (bound +-0.4 where the system swings to
        // about +-0.87): its free run is clipped on every swing, and said so.
        fitted.model.output_range = vec![(-0.2, 0.2)];
        let p = predict(&fitted, &record(100, 0.1), None).unwrap();
        assert_eq!(p.at_bound.len(), 1, "{:?}", p.at_bound);
        let b = &p.at_bound[0];
        assert_eq!(b.output, "y");
        assert!(b.share > 0.2 && b.share < 1.0 && b.first_t_s > 0.0, "{b:?}");
        let on = p.outputs[0][p.first..]
            .iter()
            .filter(|v| (v.abs() - 0.4).abs() < 1e-9)
            .count();
        assert!(
            (b.share - on as f64 / (100 - p.first) as f64).abs() < 1e-12,
            "{b:?} {on}"
        );
        let said = p.summary("m.json").findings.join("\n");
        assert!(
            said.contains("the model's free run of output `y` on r.csv reaches the bound it is held in")
                && said.contains(&format!(
                    "for {} % of the predicted samples",
                    crate::metrics::sig(100.0 * b.share, 3)
                )),
            "{said}"
        );
        // K steps ahead is not a free run: nothing to say.
        assert!(predict(&fitted, &record(100, 0.1), Some(1))
            .unwrap()
            .at_bound
            .is_empty());
    }

    /// A model.json whose ARX baseline has lags longer than the record (a hand-edited
    /// `output_lag_start`): a clear error, not a panic (found by the mutation harness).
    #[test]
    fn a_baseline_longer_than_the_record_is_an_error() {
        let (mut fitted, _) = arx_on(&record(200, 0.1));
        let mut b = fitted.model.clone();
        b.spec.output_lag_start = 1000;
        fitted.baseline = Some(b);
        let e = predict(&fitted, &record(200, 0.1), None).unwrap_err().to_string();
        assert!(
            e.contains("r.csv (the model's ARX baseline)") && e.contains("at least 1003"),
            "{e}"
        );
    }

    #[test]
    fn prediction_options_name_the_field_and_the_value_given() {
        assert_eq!(prediction_options(Some(3), None).unwrap(), (Some(3), None));
        assert_eq!(prediction_options(None, Some(2)).unwrap(), (None, Some(2)));
        let err = |s, w| prediction_options(s, w).unwrap_err().to_string();
        assert!(err(Some(-3), None).contains("`steps_ahead` = -3 is not allowed: K >= 1"));
        assert!(err(Some(0), None).contains("`steps_ahead` = 0 is not allowed"));
        assert!(err(Some(1 << 100), None).contains("`steps_ahead` = 1.2676506"));
        assert!(err(None, Some(-1)).contains("`init_window` = -1 is not allowed: N >= 1"));
        assert!(err(Some(2), Some(0)).contains("give one or the other"));
        assert!(check_prediction_options(Some(0), None).is_err());
        assert!(check_prediction_options(Some(1), None).is_ok());
    }
}
