//! A fitted model as `model.json` holds it (members of an ensemble, the ARX baseline,
//! units), the spec file's parser, and fitting with the baseline or an ensemble.

use super::*;
use rayon::prelude::*;

/// What `rhonn fit` writes to `model.json`: the model (with an ensemble's further
/// members) and, for a RHONN, an ARX baseline trained on the same data: the one with the
/// same lags, or the best ARX of a structure selection.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FittedModel {
    /// rhonn's version.
    pub rhonn_version: String,
    /// The model (an ensemble's first member).
    pub model: Model,
    /// An ensemble's further members: its prediction is the mean of every member's own
    /// prediction (free run or K steps ahead). Empty for a single model.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub members: Vec<Model>,
    /// The linear baseline: the ARX with the first member's lags, or the best ARX on the
    /// folds when the structure was selected (None when the model is an ARX for every output).
    pub baseline: Option<Model>,
    /// The data's units by column (`rhonn fit --units`), for what people read; absent
    /// when none were given.
    #[serde(default, skip_serializing_if = "std::collections::BTreeMap::is_empty")]
    pub units: std::collections::BTreeMap<String, String>,
    /// The outputs where no structure the selection tried ran free on the folds better
    /// than their training mean (`select_mean`): the model is no better than a constant
    /// there, and `rhonn predict` says so. Absent when none.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub no_better_than_mean: Vec<String>,
    /// The outputs a structure of their own predicts (the selection's `by_output`): the
    /// prediction of each is taken from its own structure's, the others from `model`'s.
    /// Absent when one structure predicts every output.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub by_output: Vec<OutputModel>,
}

/// An output predicted by a structure of its own. The structure is trained on every
/// output, as `model` is: its free run feeds back its own predictions of the others, so
/// it runs on the inputs alone, like the rest of the model.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OutputModel {
    /// The output it predicts.
    pub output: String,
    /// The structure (an ensemble's first member).
    pub model: Model,
    /// An ensemble's further members (the mean of every member's prediction).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub members: Vec<Model>,
}

impl OutputModel {
    /// Every member, the first one first.
    pub fn all_members(&self) -> impl Iterator<Item = &Model> {
        std::iter::once(&self.model).chain(&self.members)
    }
}

/// The mean of `members`' predictions (see [`Model::predict`]) from the latest member's first
/// predictable sample on (the measurement repeated before it).
fn mean_prediction<'a>(
    mut members: impl Iterator<Item = &'a Model>,
    r: &Record,
    steps_ahead: Option<usize>,
) -> Result<(Vec<Vec<f64>>, usize)> {
    let first_member = members.next().expect("at least one member");
    let (mut sum, mut first) = first_member.predict(r, steps_ahead)?;
    let mut k = 1.0;
    for m in members {
        let (p, f) = m.predict(r, steps_ahead)?;
        first = first.max(f);
        for (s, pj) in sum.iter_mut().zip(&p) {
            for (a, b) in s.iter_mut().zip(pj) {
                *a += b;
            }
        }
        k += 1.0;
    }
    for (j, s) in sum.iter_mut().enumerate() {
        for (i, v) in s.iter_mut().enumerate() {
            *v = if i < first { r.outputs[j][i] } else { *v / k };
        }
    }
    Ok((sum, first))
}

impl FittedModel {
    /// Every member, the first one first.
    pub fn all_members(&self) -> impl Iterator<Item = &Model> {
        std::iter::once(&self.model).chain(&self.members)
    }

    /// Check every member (and that they share inputs, outputs and sample time) and the
    /// baseline.
    pub fn validate(&self) -> Result<()> {
        for (k, m) in self.all_members().enumerate() {
            let checked = m.validate();
            if k == 0 {
                checked?;
            } else {
                checked.map_err(|e| crate::error::rerooted(e, &format!("members[{}]", k - 1)))?;
            }
            if m.inputs != self.model.inputs
                || m.outputs != self.model.outputs
                || (m.sample_time_s - self.model.sample_time_s).abs() > 1e-9 * self.model.sample_time_s
            {
                return Err(invalid(
                    format!("members[{k}]"),
                    "other inputs, outputs or sample time",
                    "the first member's",
                ));
            }
        }
        for (i, o) in self.by_output.iter().enumerate() {
            self.validate_own(i, o)?;
        }
        if let Some(b) = &self.baseline {
            b.validate().map_err(|e| crate::error::rerooted(e, "baseline"))?;
            // The baseline was fitted on the model's own signals and grid: an edit of one
            // of them would otherwise be read and ignored.
            if b.inputs != self.model.inputs
                || b.outputs != self.model.outputs
                || (b.sample_time_s - self.model.sample_time_s).abs() > 1e-9 * self.model.sample_time_s
            {
                return Err(invalid(
                    "baseline",
                    "other inputs, outputs or sample time than the model's",
                    "the model's own (the baseline was fitted beside it: edit both, or neither)",
                ));
            }
        }
        Ok(())
    }

    /// Samples needed before the first prediction, over every member.
    pub fn max_lag(&self) -> usize {
        let own = self.by_output.iter().flat_map(OutputModel::all_members);
        self.all_members()
            .chain(own)
            .map(|m| m.spec.max_lag())
            .max()
            .unwrap_or(0)
    }

    /// The prediction of every output (see [`Model::predict`]): a single model's, or the
    /// mean of an ensemble's members' predictions, from the latest member's first
    /// predictable sample on (the measurement repeated before it); an output of
    /// `by_output` from its own structure's, run on its own as on the selection's folds
    /// (from the latest structure's first sample on).
    pub fn predict(&self, r: &Record, steps_ahead: Option<usize>) -> Result<(Vec<Vec<f64>>, usize)> {
        let (mut pred, mut first) = mean_prediction(self.all_members(), r, steps_ahead)?;
        for o in &self.by_output {
            let (own, f) = mean_prediction(o.all_members(), r, steps_ahead)?;
            let j = self.model.outputs.iter().position(|y| *y == o.output);
            let j = j.ok_or_else(|| invalid("by_output.output", &o.output, "one of the model's outputs"))?;
            pred[j] = own.into_iter().nth(j).unwrap_or_default();
            first = first.max(f);
        }
        if !self.by_output.is_empty() {
            for (p, y) in pred.iter_mut().zip(&r.outputs) {
                p[..first].copy_from_slice(&y[..first]);
            }
        }
        Ok((pred, first))
    }

    /// Check `by_output[i]`: its members, their signals and grid (the model's), its output
    /// (one of the model's, named once).
    fn validate_own(&self, i: usize, o: &OutputModel) -> Result<()> {
        let at = format!("by_output[{i}]");
        if self.model.outputs.iter().all(|y| *y != o.output) {
            return Err(invalid(
                format!("{at}.output"),
                &o.output,
                format!("one of the model's outputs {:?}", self.model.outputs),
            ));
        }
        if self.by_output[..i].iter().any(|p| p.output == o.output) {
            return Err(invalid(
                format!("{at}.output"),
                &o.output,
                "an output named once in by_output",
            ));
        }
        for m in o.all_members() {
            m.validate().map_err(|e| crate::error::rerooted(e, &at))?;
            if m.inputs != self.model.inputs
                || m.outputs != self.model.outputs
                || (m.sample_time_s - self.model.sample_time_s).abs() > 1e-9 * self.model.sample_time_s
            {
                return Err(invalid(
                    at,
                    "other inputs, outputs or sample time",
                    "the model's own (every structure runs on the same signals)",
                ));
            }
        }
        Ok(())
    }
}

/// Read a model spec file: one structure, or an ensemble as `[[members]]` tables (each
/// a structure; its prediction is the mean of the members'). Errors name the key.
pub fn parse_spec_file(text: &str) -> std::result::Result<Vec<ModelSpec>, String> {
    let v: toml::Value = toml::from_str(text).map_err(|e| e.to_string())?;
    match v.get("members") {
        None => Ok(vec![toml::from_str::<ModelSpec>(text).map_err(|e| e.to_string())?]),
        Some(members) => {
            let table = v.as_table().expect("a TOML document is a table");
            if let Some(k) = table.keys().find(|k| *k != "members") {
                return Err(format!(
                    "`{k}` beside `members`: an ensemble file holds only `[[members]]` tables"
                ));
            }
            let list = members
                .as_array()
                .filter(|a| !a.is_empty())
                .ok_or("`members` must be a non-empty list of `[[members]]` tables")?;
            list.iter()
                .enumerate()
                .map(|(i, m)| {
                    m.clone()
                        .try_into::<ModelSpec>()
                        .map_err(|e| format!("members[{i}]: {e}"))
                })
                .collect()
        }
    }
}

/// Train `spec` and, for a RHONN, the ARX baseline with the same lags.
pub fn fit_with_baseline(
    spec: &ModelSpec,
    records: &[Record],
    inputs: &[String],
    outputs: &[String],
) -> Result<FittedModel> {
    fit_ensemble(std::slice::from_ref(spec), records, inputs, outputs, None)
}

/// Train every structure of an ensemble (one structure: a single model) and, when the
/// first is not an ARX, an ARX baseline: `baseline` when given (a structure selection's
/// best ARX; it must be an ARX), else the ARX with the first structure's lags.
pub fn fit_ensemble(
    specs: &[ModelSpec],
    records: &[Record],
    inputs: &[String],
    outputs: &[String],
    baseline: Option<&ModelSpec>,
) -> Result<FittedModel> {
    let spec = specs
        .first()
        .ok_or_else(|| invalid("members", "[]", "at least one model structure"))?;
    let mut fitted = fit_members(specs, records, inputs, outputs)?.into_iter();
    let model = fitted
        .next()
        .ok_or_else(|| invalid("members", "[]", "at least one model structure"))?;
    let members: Vec<Model> = fitted.collect();
    if let Some(b) = baseline.filter(|b| b.kind != Kind::Arx) {
        return Err(invalid("baseline.kind", format!("{:?}", b.kind), "arx"));
    }
    let baseline = if spec.kind != Kind::Arx {
        let arx = baseline.cloned().unwrap_or_else(|| ModelSpec {
            kind: Kind::Arx,
            law: Estimator::BatchLs,
            ridge: 1e-9,
            ..spec.clone()
        });
        Some(fit(&arx, records, inputs, outputs)?)
    } else {
        None
    };
    Ok(FittedModel {
        rhonn_version: env!("CARGO_PKG_VERSION").to_string(),
        model,
        members,
        baseline,
        units: Default::default(),
        no_better_than_mean: Vec::new(),
        by_output: Vec::new(),
    })
}

/// Every member of `specs` at once (each fit is deterministic: the same models in any
/// order); the first member's error first.
fn fit_members(
    specs: &[ModelSpec],
    records: &[Record],
    inputs: &[String],
    outputs: &[String],
) -> Result<Vec<Model>> {
    let fits: Vec<Result<Model>> = specs
        .par_iter()
        .map(|s| fit(s, records, inputs, outputs))
        .collect();
    fits.into_iter().collect()
}

/// Train each output's own structure (`own`: the output and its structures, an ensemble's
/// members first to last) on `records` and put it in `fitted.by_output`; outputs of one
/// structure share one fit, and a structure that is the baseline's takes the baseline.
pub fn fit_own_structures(
    fitted: &mut FittedModel,
    own: &[(String, Vec<ModelSpec>)],
    records: &[Record],
    inputs: &[String],
    outputs: &[String],
) -> Result<()> {
    let mut trained: Vec<(Vec<ModelSpec>, Vec<Model>)> = (fitted.baseline.iter())
        .map(|b| (vec![b.spec.clone()], vec![b.clone()]))
        .collect();
    for (output, specs) in own {
        let models = match trained.iter().find(|(s, _)| s == specs) {
            Some((_, m)) => m.clone(),
            None => {
                let m = fit_members(specs, records, inputs, outputs)?;
                trained.push((specs.clone(), m.clone()));
                m
            }
        };
        let mut members = models.into_iter();
        let model = members
            .next()
            .ok_or_else(|| invalid("by_output.members", "[]", "at least one model structure"))?;
        fitted.by_output.push(OutputModel {
            output: output.clone(),
            model,
            members: members.collect(),
        });
    }
    Ok(())
}
