//! The engines of the online identifier behind one trait: each structure of
//! [`OnlineSpec`](super::OnlineSpec) (`structure = ...`) is one file with one
//! implementation of [`OnlineEngine`]: the thesis's continuous-time neurons
//! (`continuous.rs`), the lagged structure (`lagged.rs`) and the cascade (`cascade_online.rs`).
//! [`OnlineIdentifier`](super::OnlineIdentifier) holds one and calls through it;
//! `OnlineIdentifier::new` is the one place that maps a structure to its engine, so a new
//! online structure is its file, a variant of `OnlineStructure` and one line there.

use super::online_spec::Scaling;
use crate::error::Result;
use std::any::Any;
use std::fmt::Debug;

/// What an engine saves around a K-step-ahead prediction: a type of its own.
pub(crate) trait EngineState: Debug + Send + Sync {
    /// A copy in a box.
    fn clone_box(&self) -> Box<dyn EngineState>;
    /// For the engine to find its own type again.
    fn as_any(&self) -> &dyn Any;
}

impl<T: Debug + Clone + Send + Sync + 'static> EngineState for T {
    fn clone_box(&self) -> Box<dyn EngineState> {
        Box::new(self.clone())
    }
    fn as_any(&self) -> &dyn Any {
        self
    }
}

/// One online structure, one sample at a time (see `OnlineIdentifier`'s methods of the
/// same names).
pub(crate) trait OnlineEngine: Debug + Send + Sync {
    /// Take the sample `(t, u, y)`: the estimate of `y(t)` made before seeing `y`, then
    /// learn from it.
    fn update(&mut self, t: f64, u: &[f64], y: &[f64]) -> Result<&[f64]>;
    /// The last estimate (output units).
    fn estimate(&self) -> &[f64];
    /// Stop (`true`) or resume adapting.
    fn freeze(&mut self, frozen: bool);
    /// Run on its own outputs (`true`), or series-parallel.
    fn set_free_run(&mut self, free: bool);
    /// Forget the last sample (a new record starts).
    fn reset(&mut self);
    /// A new pass over recordings starts (nothing by default).
    fn new_pass(&mut self) {}
    /// Put the estimate at `y` (output units).
    fn set_estimate(&mut self, y: &[f64]);
    /// Weights, one vector per output's neuron (normalised units).
    fn weights(&self) -> Vec<Vec<f64>>;
    /// Set the weights.
    fn set_weights(&mut self, w: &[Vec<f64>]);
    /// Each term's name, in weight order.
    fn term_names(&self, outputs: &[String], inputs: &[String]) -> Vec<String>;
    /// Number of terms (weights) per neuron.
    fn n_terms(&self) -> usize;
    /// The length of each weight vector, in `weights`' order (every neuron's `n_terms`,
    /// but for a `per-output` structure, whose parts differ).
    fn weight_lengths(&self) -> Vec<usize> {
        self.weights().iter().map(Vec::len).collect()
    }
    /// What each weight vector belongs to, in `weights`' order: its output's name.
    fn weight_labels(&self, outputs: &[String]) -> Vec<String> {
        outputs.to_vec()
    }
    /// The scaling.
    fn scaling(&self) -> &Scaling;
    /// Hold the estimate within `b` (output units, per output).
    fn set_y_bounds(&mut self, b: Vec<[f64; 2]>);
    /// A `per-output` structure's own parts' ranges (`OnlineModel::own_y_bounds`): empty
    /// for every other structure.
    fn own_y_bounds(&self) -> Vec<Option<[f64; 2]>> {
        Vec::new()
    }
    /// Set them (a saved model read back).
    fn set_own_y_bounds(&mut self, _b: &[Option<[f64; 2]>]) {}
    /// Track the outputs' range from `[lo, hi]` itself, widened by `margin` (a
    /// `per-output` structure: each part by its own), and return `true`; or leave it to
    /// `OnlineIdentifier::track_bounds` (`false`, the default).
    fn track_bounds(&mut self, _lo: &[f64], _hi: &[f64], _margin: f64) -> bool {
        false
    }
    /// Everything that changes with a sample.
    fn snapshot(&self) -> Box<dyn EngineState>;
    /// Restore a snapshot of this engine (one of another engine is ignored).
    fn restore(&mut self, s: &dyn EngineState);
    /// Refuse stored weights the structure cannot run (each is finite and of the right
    /// length already).
    fn check_weights(&self, _w: &[Vec<f64>]) -> Result<()> {
        Ok(())
    }
    /// Why the structure has no model to freeze yet (a block structure before its
    /// window is full), or None.
    fn unfinished(&self) -> Option<String> {
        None
    }
    /// A copy in a box.
    fn box_clone(&self) -> Box<dyn OnlineEngine>;
}

impl Clone for Box<dyn OnlineEngine> {
    fn clone(&self) -> Self {
        self.box_clone()
    }
}

/// Refuse a sample whose time, an input, or (when `y_used`: the outputs are read, not in
/// a frozen model's free run) an output is not finite, naming the first such value
/// (`t`, `u[i]` or `y[i]`) and the sample's time: the one check every online engine makes.
pub(super) fn check_sample_finite(t: f64, u: &[f64], y: &[f64], y_used: bool) -> Result<()> {
    if !t.is_finite() {
        return Err(crate::Error::Argument(format!(
            "t = {t} is not allowed: a sample's time must be a finite number of seconds"
        )));
    }
    let ys = if y_used { y } else { &[] };
    let named = |s: &'static str| move |(i, v): (usize, &f64)| (s, i, *v);
    let first = u.iter().enumerate().map(named("u"));
    match first
        .chain(ys.iter().enumerate().map(named("y")))
        .find(|(_, _, v)| !(v.is_finite() && v.abs() <= crate::data::MAX_MAGNITUDE))
    {
        Some((s, i, v)) => Err(crate::Error::Argument(format!(
            "{s}[{i}] = {} (the sample at t = {t} s) is not allowed: every value must be finite and of magnitude at most 1e150 (as in a file)",
            crate::error::readable(v.to_string())
        ))),
        None => Ok(()),
    }
}
