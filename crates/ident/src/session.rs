//! An online identification session for a user's own loop (Python's
//! `rhonn.OnlineIdentifier`): one model given by the caller, or, without one, the bank
//! choosing online (`bank::OnlineBank`) until it is frozen. Every argument is checked
//! here, so a binding only converts.

use super::bank::{default_candidates, BankSelection, BankSettings, OnlineBank};
use super::guard::{SampleGuard, Verdict};
use super::{OnlineIdentifier, OnlineModel, OnlineSpec, Scaling};
use crate::error::{Error, Result};
use std::borrow::Cow;

/// The caller's scaling of a given model: the identifier sees `(signal - offset) / scale`;
/// `y_bounds` per output the range its estimate is held in. All None: the defaults (0, 1,
/// no bounds). `samples`: the stream's length, for the bank (no model).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SessionOptions {
    /// Per output.
    pub y_offset: Option<Vec<f64>>,
    /// Per output, > 0.
    pub y_scale: Option<Vec<f64>>,
    /// Per input.
    pub u_offset: Option<Vec<f64>>,
    /// Per input, > 0.
    pub u_scale: Option<Vec<f64>>,
    /// Per output, `[low, high]` with low < high.
    pub y_bounds: Option<Vec<[f64; 2]>>,
    /// The stream's length (at least 4), when known.
    pub samples: Option<usize>,
}

/// One model given by the caller, or the bank choosing one online until `freeze`.
#[derive(Debug, Clone)]
enum Engine {
    One {
        inner: Box<OnlineIdentifier>,
        spec: Box<OnlineSpec>,
    },
    Bank(Box<OnlineBank>),
}

/// Online identification of a sampled plant, one sample at a time.
#[derive(Debug, Clone)]
pub struct OnlineSession {
    engine: Engine,
    inputs: Vec<String>,
    outputs: Vec<String>,
    dt: f64,
    /// What is let in (`super::guard`): glitches skipped, gaps restarted over.
    guard: SampleGuard,
    /// The last estimate returned (returned again for a skipped sample).
    held: Vec<f64>,
    t_last: Option<f64>,
}

fn argument(msg: impl Into<String>) -> Error {
    Error::Argument(msg.into())
}

/// The bank's settings for a stream of `samples` samples (None: not known).
fn bank_settings(samples: Option<usize>) -> Result<BankSettings> {
    match samples {
        Some(n) if n < 4 => Err(argument(format!(
            "samples = {n} is not allowed: give the stream's length, at least 4 samples, or None"
        ))),
        Some(n) => Ok(BankSettings::for_stream(n)),
        None => Ok(BankSettings::open_ended()),
    }
}

/// A per-signal vector given by the caller, or `default` repeated.
fn per_signal(name: &str, v: Option<Vec<f64>>, n: usize, default: f64, positive: bool) -> Result<Vec<f64>> {
    let v = v.unwrap_or_else(|| vec![default; n]);
    if v.len() != n {
        return Err(argument(format!(
            "{name} has {} values; {n} are needed (one per signal)",
            v.len()
        )));
    }
    if let Some((i, x)) = v
        .iter()
        .enumerate()
        .find(|(_, x)| !x.is_finite() || (positive && **x <= 0.0))
    {
        let allowed = if positive { "finite and > 0" } else { "finite" };
        let x = crate::error::readable(x.to_string());
        return Err(argument(format!("{name}[{i}] = {x} is not allowed: {allowed}")));
    }
    Ok(v)
}

/// Per output, a range `[low, high]` the estimate is held in.
fn check_bounds(b: Option<Vec<[f64; 2]>>, n: usize) -> Result<Option<Vec<[f64; 2]>>> {
    let Some(b) = b else { return Ok(None) };
    if b.len() != n {
        return Err(argument(format!(
            "y_bounds has {} ranges; {n} are needed (one per output)",
            b.len()
        )));
    }
    if let Some((i, r)) = b
        .iter()
        .enumerate()
        .find(|(_, r)| !(r[0].is_finite() && r[1].is_finite() && r[0] < r[1]))
    {
        return Err(argument(format!(
            "y_bounds[{i}] = [{}, {}] is not allowed: give finite [low, high] with low < high",
            crate::error::readable(r[0].to_string()),
            crate::error::readable(r[1].to_string())
        )));
    }
    Ok(Some(b))
}

impl OnlineSession {
    /// A session on signals `inputs` -> `outputs` sampled every `dt` s: `model` given
    /// (with `opts`' scaling), or None for the online selection (with `opts.samples`).
    pub fn new(
        inputs: Vec<String>,
        outputs: Vec<String>,
        dt: f64,
        model: Option<OnlineSpec>,
        opts: SessionOptions,
    ) -> Result<Self> {
        if outputs.is_empty() {
            return Err(argument("outputs is empty: name at least one output"));
        }
        crate::data::check_names(&inputs, &outputs)?;
        if !(dt.is_finite() && dt > 0.0) {
            return Err(argument(format!(
                "dt = {dt} is not allowed: give the sample time in seconds, finite and > 0"
            )));
        }
        let (ny, nu) = (outputs.len(), inputs.len());
        let engine = match model {
            None => {
                let given = [
                    ("y_offset", opts.y_offset.is_some()),
                    ("y_scale", opts.y_scale.is_some()),
                    ("u_offset", opts.u_offset.is_some()),
                    ("u_scale", opts.u_scale.is_some()),
                    ("y_bounds", opts.y_bounds.is_some()),
                ];
                if let Some((name, _)) = given.iter().find(|(_, g)| *g) {
                    return Err(argument(format!(
                        "{name} needs a model: without one the identifier picks its model online and normalises by its warm-up window (give model={{}} for the continuous-time neurons with your scaling)"
                    )));
                }
                let settings = bank_settings(opts.samples)?;
                let n = opts.samples.unwrap_or(usize::MAX);
                let bank = OnlineBank::new(default_candidates(ny, nu, n), ny, nu, dt, settings)?
                    .with_own_banks(default_candidates(1, nu, n))?;
                Engine::Bank(Box::new(bank))
            }
            Some(spec) => {
                if opts.samples.is_some() {
                    return Err(argument(
                        "samples is for the online selection (no model): a given model does not use it",
                    ));
                }
                let scaling = Scaling {
                    y_offset: per_signal("y_offset", opts.y_offset, ny, 0.0, false)?,
                    y_scale: per_signal("y_scale", opts.y_scale, ny, 1.0, true)?,
                    u_offset: per_signal("u_offset", opts.u_offset, nu, 0.0, false)?,
                    u_scale: per_signal("u_scale", opts.u_scale, nu, 1.0, true)?,
                    y_bounds: check_bounds(opts.y_bounds, ny)?,
                };
                let inner = Box::new(OnlineIdentifier::new(&spec, ny, nu, dt, scaling)?);
                Engine::One {
                    inner,
                    spec: Box::new(spec),
                }
            }
        };
        Ok(OnlineSession {
            engine,
            held: vec![0.0; outputs.len()],
            inputs,
            outputs,
            dt,
            guard: SampleGuard::new(dt),
            t_last: None,
        })
    }

    /// The input names, the output names and the sample time \[s\].
    pub fn signals(&self) -> (&[String], &[String], f64) {
        (&self.inputs, &self.outputs, self.dt)
    }

    /// Take the sample `(t, u, y)` (t in s, strictly after the last one); returns the
    /// estimate of `y(t)` made before seeing `y` (the first sample returns `y`). A glitch
    /// (`super::guard`) is skipped, not learned (the last estimate is returned again), and
    /// learning restarts after it and after a gap in time; [`Self::notes`] says so.
    pub fn update(&mut self, t: f64, u: &[f64], y: &[f64]) -> Result<&[f64]> {
        if u.len() != self.inputs.len() || y.len() != self.outputs.len() {
            return Err(argument(format!(
                "the sample has {} inputs and {} outputs; {} and {} are needed",
                u.len(),
                y.len(),
                self.inputs.len(),
                self.outputs.len()
            )));
        }
        super::engine::check_sample_finite(t, u, y, true)?;
        if let Some(tl) = self.t_last.filter(|tl| t <= *tl) {
            return Err(argument(format!(
                "t = {t} is not allowed: a time after the previous sample's, {tl} s"
            )));
        }
        self.t_last = Some(t);
        match self.guard.judge(t, u, y) {
            Verdict::Skip => {
                self.restart();
                return Ok(&self.held);
            }
            Verdict::AfterGap => self.restart(),
            Verdict::Learn => {}
        }
        let estimate = match &mut self.engine {
            Engine::One { inner, .. } => inner.update(t, u, y)?,
            Engine::Bank(b) => b.update(t, u, y)?,
        };
        self.held.copy_from_slice(estimate);
        Ok(&self.held)
    }

    /// What the guard skipped or restarted over, for the user (empty for a clean stream).
    pub fn notes(&self) -> Vec<String> {
        self.guard.notes()
    }

    /// The lag buffers restart with the next sample (the weights stay).
    fn restart(&mut self) {
        match &mut self.engine {
            Engine::One { inner, .. } => inner.reset(),
            Engine::Bank(b) => b.reset(),
        }
    }

    /// Stop adapting and return the frozen model; the session stays frozen until
    /// `resume`. Choosing online: the winner so far becomes the identifier (the other
    /// candidates are dropped).
    pub fn freeze(&mut self) -> Result<OnlineModel> {
        if let Engine::Bank(b) = &self.engine {
            let (sel, id) = self.bank_selection(b)?;
            self.engine = Engine::One {
                inner: Box::new(id),
                spec: Box::new(sel.chosen_spec()),
            };
        }
        let Engine::One { inner, spec } = &mut self.engine else {
            return Err(argument("no model to freeze"));
        };
        if let Some(why) = inner.unfinished() {
            return Err(argument(why));
        }
        inner.freeze(true);
        Ok(OnlineModel::of(
            inner,
            spec.as_ref().clone(),
            &self.inputs,
            &self.outputs,
            self.dt,
        ))
    }

    /// Adapt the weights again after `freeze`.
    pub fn resume(&mut self) {
        if let Engine::One { inner, .. } = &mut self.engine {
            inner.freeze(false);
        }
    }

    /// Forget the last sample (a new record starts); the weights stay.
    pub fn reset(&mut self) {
        self.restart();
        self.guard.reset();
        self.t_last = None;
    }

    /// The identifier: the one given, or, choosing online, the leader so far.
    pub fn current(&self) -> Result<Cow<'_, OnlineIdentifier>> {
        match &self.engine {
            Engine::One { inner, .. } => Ok(Cow::Borrowed(inner.as_ref())),
            Engine::Bank(b) => Ok(Cow::Owned(self.bank_selection(b)?.1)),
        }
    }

    /// The current identifier's weights as rows of one length (an array's): an error for a
    /// `per-output` structure, whose parts' vectors differ in length.
    pub fn weight_rows(&self) -> Result<Vec<Vec<f64>>> {
        let w = self.current()?.weights();
        let lengths: Vec<usize> = w.iter().map(Vec::len).collect();
        if lengths.windows(2).any(|p| p[0] != p[1]) {
            return Err(argument(format!(
                "weights: the per-output structure's weight vectors differ in length ({lengths:?}: the joint model's, then each output's own), so they make no array; read them as lists from the frozen model's JSON (\"weights\")"
            )));
        }
        Ok(w)
    }

    /// The current identifier's term names, in weight order (inputs and outputs by their
    /// names in this session).
    pub fn term_names(&self) -> Result<Vec<String>> {
        Ok(self.current()?.term_names(&self.outputs, &self.inputs))
    }

    /// Choosing online: every candidate's prequential figures and the winner so far; None
    /// with a given model.
    pub fn selection(&self) -> Result<Option<BankSelection>> {
        match &self.engine {
            Engine::One { .. } => Ok(None),
            Engine::Bank(b) => Ok(Some(self.bank_selection(b)?.0)),
        }
    }

    /// [`OnlineSession::selection`] as JSON text (`rhonn identify`'s `selection` in
    /// summary.json).
    pub fn selection_json(&self) -> Result<Option<String>> {
        let text = |s| {
            serde_json::to_string(&s)
                .map_err(|e| Error::Argument(format!("cannot write the selection as JSON: {e}")))
        };
        self.selection()?.map(text).transpose()
    }

    /// The bank's selection and winner, its outputs named as in this session.
    fn bank_selection(&self, b: &OnlineBank) -> Result<(BankSelection, OnlineIdentifier)> {
        let (mut sel, id) = b.selection()?;
        for o in &mut sel.by_output {
            o.output.clone_from(&self.outputs[o.index]);
        }
        Ok((sel, id))
    }

    /// The given model's identifier (None while choosing online).
    pub fn given(&self) -> Option<&OnlineIdentifier> {
        match &self.engine {
            Engine::One { inner, .. } => Some(inner),
            Engine::Bank(_) => None,
        }
    }

    /// For Python's bench (`python/bench.py`): the seconds per update of the updates
    /// [`OnlineSession::update`] would make on the samples `t`, `u` (one column per input)
    /// and `y` (one per output), made on a copy of the given model's identifier (this
    /// session stays as it was).
    pub fn seconds_per_update(&self, t: &[f64], u: &[Vec<f64>], y: &[Vec<f64>]) -> Result<f64> {
        let Some(given) = self.given() else {
            return Err(Error::Argument(
                "the bench times a given model (give model=...)".into(),
            ));
        };
        if u.len() != self.inputs.len()
            || y.len() != self.outputs.len()
            || u.iter().chain(y).any(|c| c.len() != t.len())
        {
            return Err(Error::Argument(format!(
                "t, u and y need one row per sample and {} inputs and {} outputs",
                self.inputs.len(),
                self.outputs.len()
            )));
        }
        let mut id = given.clone();
        let (mut uk, mut yk) = (vec![0.0; u.len()], vec![0.0; y.len()]);
        let start = std::time::Instant::now();
        for (k, tk) in t.iter().enumerate() {
            uk.iter_mut().zip(u).for_each(|(v, c)| *v = c[k]);
            yk.iter_mut().zip(y).for_each(|(v, c)| *v = c[k]);
            std::hint::black_box(id.update(*tk, &uk, &yk)?);
        }
        Ok(start.elapsed().as_secs_f64() / t.len().max(1) as f64)
    }
}

#[cfg(test)]
mod tests {
    use super::{check_bounds, per_signal};

    #[test]
    fn refused_scalings_and_bounds_print_huge_numbers_readably() {
        let e = check_bounds(Some(vec![[1e300, -1e300]]), 1)
            .unwrap_err()
            .to_string();
        assert!(e.contains("y_bounds[0] = [1e300, -1e300] is not allowed"), "{e}");
        let e = per_signal("y_scale", Some(vec![-1e300]), 1, 1.0, true)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("y_scale[0] = -1e300 is not allowed: finite and > 0"),
            "{e}"
        );
        assert!(e.len() < 120, "{e}");
    }
}
