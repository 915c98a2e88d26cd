//! Identification figures of a pump run: per identified state and mode, accumulated on
//! the dense output, and the model file.

pub use super::ident_figures::{ModelFile, RunFigures};
use serde::Serialize;

/// Figures of one identified state in one mode (display units: MPa, mm).
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct StateFigures {
    /// State.
    pub state: &'static str,
    /// Unit of the errors below.
    pub unit: &'static str,
    /// RMS of x_hat - x.
    pub rms_error: f64,
    /// 100 (1 - |y - yhat| / |y - mean y|); left out of JSON when undefined (a state
    /// that does not move).
    #[serde(skip_serializing_if = "crate::metrics::undefined")]
    pub fit_percent: f64,
    /// RMS error / range of the state; left out of JSON when undefined.
    #[serde(skip_serializing_if = "crate::metrics::undefined")]
    pub nrmse: f64,
    /// The band: 1 % of the state's range over the run.
    pub convergence_band: f64,
    /// First time after which |e| stays within the band (null: it does not).
    pub convergence_time_s: Option<f64>,
    /// |w_i| at the end of training.
    pub final_weight_norm: f64,
}

impl StateFigures {
    /// A state's whole-run figures `r` and its neuron's weights `w`.
    pub(super) fn of(state: &'static str, unit: &'static str, r: RunFigures, w: &[f64]) -> Self {
        StateFigures {
            state,
            unit,
            rms_error: r.rms_error,
            fit_percent: r.fit_percent,
            nrmse: r.nrmse,
            convergence_band: r.convergence_band,
            convergence_time_s: r.convergence_time_s,
            final_weight_norm: w.iter().map(|v| v * v).sum::<f64>().sqrt(),
        }
    }
}

/// Identification figures of `summary.json`.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct IdentReport {
    /// Law.
    pub law: &'static str,
    /// Epochs.
    pub epochs: usize,
    /// Terms L.
    pub n_terms: usize,
    /// Last training epoch.
    pub training: Vec<StateFigures>,
    /// Frozen weights, z from the plant's states.
    pub series_parallel: Vec<StateFigures>,
    /// Frozen weights, z from the model's own states (free run).
    pub parallel: Vec<StateFigures>,
    /// Weights at the end of training.
    pub final_weights: Vec<Vec<f64>>,
    /// What the figures say, in words (e.g. that a model tracks while it adapts but
    /// does not run on its own).
    pub findings: Vec<String>,
}

impl std::fmt::Display for IdentReport {
    /// The findings first (what the figures mean), then one line per mode and state: the
    /// weight norm and the convergence band on the training lines, where they belong (the
    /// validations run with those weights frozen), and a validation's convergence only
    /// when it converged.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        writeln!(
            f,
            "identification ({}, {} terms, {} epoch(s)):",
            self.law, self.n_terms, self.epochs
        )?;
        for finding in &self.findings {
            writeln!(f, "  finding: {finding}")?;
        }
        for (mode, figs) in [
            ("training", &self.training),
            ("frozen series-parallel", &self.series_parallel),
            ("frozen parallel (free run)", &self.parallel),
        ] {
            for s in figs {
                let band = format!("the band +-{:.4} {}", s.convergence_band, s.unit);
                let tail = match (mode, s.convergence_time_s) {
                    (_, Some(t)) => format!(", converged within {band} at {t:.3} s"),
                    ("training", None) => format!(
                        ", not converged: the error leaves {band} (1 % of the state's range) before the run ends"
                    ),
                    _ => String::new(),
                };
                let norm = if mode == "training" {
                    format!(", |w| {:.4e}", s.final_weight_norm)
                } else {
                    String::new()
                };
                writeln!(
                    f,
                    "  {mode:<26} {:<7} rms error {:.4} {}, fit {:.1} %{norm}{tail}",
                    s.state, s.rms_error, s.unit, s.fit_percent
                )?;
            }
        }
        Ok(())
    }
}
