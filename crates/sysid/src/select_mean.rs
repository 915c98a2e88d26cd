//! Whether anything the selection tried says more than a constant: per output, each
//! candidate's free-run error on the folds (the ARX included) against the error of
//! predicting each fold's training mean (`folds::mean_scores`). As a structure replaces
//! the best ARX only when it is below it on every fold, a candidate beats the mean only
//! when it is below it on every fold (a lower mean alone is within the folds' spread). An
//! output where nothing beats the mean is said plainly (the console, `summary.json`, the
//! report) and flagged in the saved model (`FittedModel::no_better_than_mean`), which is
//! still the best of what was tried.

/// The outputs (by name) where no candidate beat the mean on every fold, and a warning for
/// each; `candidates`: each candidate's name and per-output, per-fold scores; `mean`: the
/// mean's per output and fold.
pub(super) fn verdict(
    candidates: &[(&str, &[Vec<f64>])],
    mean: &[Vec<f64>],
    outputs: &[String],
    judged_by: &str,
) -> (Vec<String>, Vec<String>) {
    let avg = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
    let mut flagged = Vec::new();
    let mut warnings = Vec::new();
    for (j, (name, m)) in outputs.iter().zip(mean).enumerate() {
        let scored: Vec<(&str, &Vec<f64>)> = candidates
            .iter()
            .filter_map(|(who, s)| s.get(j).filter(|f| f.len() == m.len()).map(|f| (*who, f)))
            .collect();
        if scored.is_empty() || scored.iter().any(|(_, f)| f.iter().zip(m).all(|(c, m)| c < m)) {
            continue;
        }
        let (who, best) = scored
            .iter()
            .map(|(w, f)| (*w, avg(f)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .expect("a scored candidate");
        flagged.push(name.clone());
        warnings.push(format!(
            "output `{name}`: no candidate, the ARX included, beat predicting its training mean on every fold ({judged_by}; the best on average, {who}, {best:.4}; the mean {:.4}; in output standard deviations): the model is the best of what was tried and no better than a constant for `{name}` (flagged in model.json); judge K samples ahead (--select-steps-ahead K), give longer records or a structure",
            avg(m)
        ));
    }
    (flagged, warnings)
}
