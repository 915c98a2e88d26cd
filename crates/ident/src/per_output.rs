//! The `per-output` structure: one model of every output (the `joint` structure, as the
//! bank chose it for all outputs together) and, for the outputs whose own bank found a
//! better structure, that structure learned on that output alone (from every input).
//! Each output's estimate is its own structure's where it has one, the joint model's
//! otherwise. The joint model keeps learning and running on every output (its free run
//! feeds back its own estimates of all of them), so an output with a structure of its own
//! changes nothing of the others. `rhonn identify` builds it when outputs differ
//! (`bank::per_output`); a `--model` file may give one too.

use super::engine::{EngineState, OnlineEngine};
use super::online_spec::{OnlineSpec, Scaling};
use crate::error::{invalid, rerooted, Result};
use serde::{Deserialize, Serialize};

/// The settings of the `per-output` structure (`per_output = { joint = ..., own = [...] }`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct PerOutputSpec {
    /// The structure of every output.
    pub joint: Box<OnlineSpec>,
    /// The outputs with a structure of their own.
    pub own: Vec<OwnStructure>,
}

/// An output predicted by a structure of its own, learned on that output alone.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OwnStructure {
    /// The output's index (0 for the first output).
    pub output: usize,
    /// Its structure (one output, every input).
    pub model: OnlineSpec,
}

impl PerOutputSpec {
    /// Check the outputs named (each below `ny`, once) and that no part is itself
    /// `per-output`; each part's own settings are checked when it is built.
    pub(super) fn check(&self, ny: usize) -> Result<()> {
        use super::OnlineStructure::PerOutput;
        if self.joint.structure == PerOutput {
            return Err(invalid(
                "model.per_output.joint.structure",
                "per-output",
                "one structure",
            ));
        }
        if self.own.is_empty() {
            return Err(invalid(
                "model.per_output.own",
                "empty",
                "at least one output with a structure of its own (else give the joint structure alone)",
            ));
        }
        for (i, o) in self.own.iter().enumerate() {
            let at = format!("model.per_output.own[{i}]");
            if o.output >= ny || self.own[..i].iter().any(|p| p.output == o.output) {
                return Err(invalid(
                    format!("{at}.output"),
                    o.output,
                    format!("an output index below {ny}, named once"),
                ));
            }
            if o.model.structure == PerOutput {
                return Err(invalid(
                    format!("{at}.model.structure"),
                    "per-output",
                    "one structure",
                ));
            }
        }
        Ok(())
    }

    /// The largest of the parts' `f` (e.g. the samples a free run reads first).
    pub(super) fn most(&self, f: impl Fn(&OnlineSpec) -> usize) -> usize {
        self.own
            .iter()
            .map(|o| f(&o.model))
            .fold(f(&self.joint), usize::max)
    }
}

/// The scaling of output `j` alone (every input).
fn of_output(s: &Scaling, j: usize) -> Scaling {
    Scaling {
        y_offset: vec![s.y_offset[j]],
        y_scale: vec![s.y_scale[j]],
        u_offset: s.u_offset.clone(),
        u_scale: s.u_scale.clone(),
        y_bounds: s.y_bounds.as_ref().map(|b| vec![b[j]]),
    }
}

/// Builds one part: a spec, its outputs and its scaling, at the structure's own inputs and
/// sample time (`OnlineIdentifier::new`, given by the registry, so that this module does
/// not import the identifier that holds it).
pub(super) type Build<'a> = &'a dyn Fn(&OnlineSpec, usize, Scaling) -> Result<Box<dyn OnlineEngine>>;

/// The engine: the joint identifier and one per output with a structure of its own (each
/// an `OnlineIdentifier`, which tracks its own range).
#[derive(Debug, Clone)]
pub(super) struct PerOutputOnline {
    joint: Box<dyn OnlineEngine>,
    own: Vec<(usize, Box<dyn OnlineEngine>)>,
    /// Each part's output margin (`output_margin`): the joint's, then each own one's.
    margins: Vec<f64>,
    estimate: Vec<f64>,
}

fn margins(p: &PerOutputSpec) -> Vec<f64> {
    std::iter::once(p.joint.output_margin)
        .chain(p.own.iter().map(|o| o.model.output_margin))
        .collect()
}

impl PerOutputOnline {
    pub(super) fn new(spec: &OnlineSpec, ny: usize, scaling: Scaling, build: Build<'_>) -> Result<Self> {
        let p = spec.per_output.as_ref().ok_or_else(|| {
            invalid(
                "model.per_output",
                "absent",
                "a table with `structure = \"per-output\"`",
            )
        })?;
        p.check(ny)?;
        let joint =
            build(&p.joint, ny, scaling.clone()).map_err(|e| rerooted(e, "model.per_output.joint"))?;
        let mut own = Vec::with_capacity(p.own.len());
        for (i, o) in p.own.iter().enumerate() {
            let id = build(&o.model, 1, of_output(&scaling, o.output))
                .map_err(|e| rerooted(e, &format!("model.per_output.own[{i}].model")))?;
            own.push((o.output, id));
        }
        Ok(PerOutputOnline {
            joint,
            own,
            margins: margins(p),
            estimate: vec![0.0; ny],
        })
    }

    /// Of identifiers that have learned already (see `OnlineIdentifier::per_output`).
    pub(super) fn from_parts(
        joint: Box<dyn OnlineEngine>,
        own: Vec<(usize, Box<dyn OnlineEngine>)>,
        p: &PerOutputSpec,
    ) -> Self {
        let mut estimate = joint.estimate().to_vec();
        for (j, id) in &own {
            estimate[*j] = id.estimate()[0];
        }
        PerOutputOnline {
            margins: margins(p),
            joint,
            own,
            estimate,
        }
    }

    fn parts_mut(&mut self) -> impl Iterator<Item = &mut Box<dyn OnlineEngine>> {
        std::iter::once(&mut self.joint).chain(self.own.iter_mut().map(|(_, id)| id))
    }

    fn parts(&self) -> impl Iterator<Item = &Box<dyn OnlineEngine>> {
        std::iter::once(&self.joint).chain(self.own.iter().map(|(_, id)| id))
    }

    /// `w` cut into each part's vectors.
    fn split<'a>(&self, w: &'a [Vec<f64>]) -> Vec<&'a [Vec<f64>]> {
        let mut at = 0;
        self.parts()
            .map(|p| {
                let n = p.weight_lengths().len();
                let s = &w[at.min(w.len())..(at + n).min(w.len())];
                at += n;
                s
            })
            .collect()
    }
}

impl OnlineEngine for PerOutputOnline {
    fn update(&mut self, t: f64, u: &[f64], y: &[f64]) -> Result<&[f64]> {
        self.estimate.copy_from_slice(self.joint.update(t, u, y)?);
        for (j, id) in &mut self.own {
            self.estimate[*j] = id.update(t, u, &y[*j..=*j])?[0];
        }
        Ok(&self.estimate)
    }

    fn estimate(&self) -> &[f64] {
        &self.estimate
    }

    fn freeze(&mut self, frozen: bool) {
        self.parts_mut().for_each(|p| p.freeze(frozen));
    }

    fn set_free_run(&mut self, free: bool) {
        self.parts_mut().for_each(|p| p.set_free_run(free));
    }

    fn reset(&mut self) {
        self.parts_mut().for_each(|p| p.reset());
    }

    fn new_pass(&mut self) {
        self.parts_mut().for_each(|p| p.new_pass());
    }

    fn set_estimate(&mut self, y: &[f64]) {
        self.joint.set_estimate(y);
        for (j, id) in &mut self.own {
            id.set_estimate(&y[*j..=*j]);
        }
        self.estimate.copy_from_slice(y);
    }

    fn weights(&self) -> Vec<Vec<f64>> {
        self.parts().flat_map(|p| p.weights()).collect()
    }

    fn set_weights(&mut self, w: &[Vec<f64>]) {
        let cut: Vec<Vec<Vec<f64>>> = self.split(w).into_iter().map(<[_]>::to_vec).collect();
        for (p, w) in self.parts_mut().zip(cut) {
            p.set_weights(&w);
        }
    }

    fn term_names(&self, outputs: &[String], inputs: &[String]) -> Vec<String> {
        self.joint.term_names(outputs, inputs)
    }

    fn n_terms(&self) -> usize {
        self.joint.n_terms()
    }

    fn weight_lengths(&self) -> Vec<usize> {
        self.parts().flat_map(|p| p.weight_lengths()).collect()
    }

    fn weight_labels(&self, outputs: &[String]) -> Vec<String> {
        let mut v = self.joint.weight_labels(outputs);
        for (j, id) in &self.own {
            let name = outputs.get(*j).cloned().unwrap_or_else(|| format!("y{j}"));
            v.extend(id.weight_labels(&[format!("{name}_own")]));
        }
        v
    }

    /// The joint structure's (its bounds are every output's as the joint model holds
    /// them; each own structure's are `own_y_bounds`).
    fn scaling(&self) -> &Scaling {
        self.joint.scaling()
    }

    fn set_y_bounds(&mut self, b: Vec<[f64; 2]>) {
        for (j, id) in &mut self.own {
            id.set_y_bounds(vec![b[*j]]);
        }
        self.joint.set_y_bounds(b);
    }

    fn own_y_bounds(&self) -> Vec<Option<[f64; 2]>> {
        self.own
            .iter()
            .map(|(_, id)| id.scaling().y_bounds.as_ref().map(|b| b[0]))
            .collect()
    }

    fn set_own_y_bounds(&mut self, b: &[Option<[f64; 2]>]) {
        for ((_, id), b) in self.own.iter_mut().zip(b) {
            if let Some(b) = b {
                id.set_y_bounds(vec![*b]);
            }
        }
    }

    /// Each part tracks its own outputs' range with its own margin (a negative one:
    /// unbounded).
    fn track_bounds(&mut self, lo: &[f64], hi: &[f64], _margin: f64) -> bool {
        let mut m = self.margins.clone().into_iter();
        if let Some(mj) = m.next().filter(|v| *v >= 0.0) {
            self.joint.track_bounds(lo, hi, mj);
        }
        for ((j, id), mo) in self.own.iter_mut().zip(m) {
            if mo >= 0.0 {
                id.track_bounds(&lo[*j..=*j], &hi[*j..=*j], mo);
            }
        }
        true
    }

    fn snapshot(&self) -> Box<dyn EngineState> {
        Box::new(self.parts().map(|p| Part(p.snapshot())).collect::<Vec<Part>>())
    }

    fn restore(&mut self, s: &dyn EngineState) {
        if let Some(snaps) = s.as_any().downcast_ref::<Vec<Part>>() {
            for (p, snap) in self.parts_mut().zip(snaps) {
                p.restore(&*snap.0);
            }
            self.estimate.copy_from_slice(self.joint.estimate());
            for (j, id) in &self.own {
                self.estimate[*j] = id.estimate()[0];
            }
        }
    }

    fn unfinished(&self) -> Option<String> {
        self.parts().find_map(|p| p.unfinished())
    }
    fn check_weights(&self, w: &[Vec<f64>]) -> Result<()> {
        for (p, w) in self.parts().zip(self.split(w)) {
            p.check_weights(w)?;
        }
        Ok(())
    }

    fn box_clone(&self) -> Box<dyn OnlineEngine> {
        Box::new(self.clone())
    }
}

/// One part's snapshot.
#[derive(Debug)]
struct Part(Box<dyn EngineState>);

impl Clone for Part {
    fn clone(&self) -> Self {
        Part(self.0.clone_box())
    }
}
