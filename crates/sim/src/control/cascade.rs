//! Two controllers in cascade: the outer one turns the set-point of the controlled state
//! into a set-point for an inner state, the inner one turns that into the plant's input.
//! For plants of relative degree two (the lower of two tanks, the pump's pressure through
//! its stroke), with any [`Controller`] at either level: a RHONN indirect adaptive outer
//! loop over a PI inner loop, or a PI over a PI as the classical baseline with the same
//! sensors.

use super::{AdaptiveView, Controller, LoopContext, LoopSettings, LoopSpec};
use crate::error::{invalid, Result};
use serde::{Deserialize, Serialize};

/// An outer and an inner controller; measures what both measure (the outer's first).
pub struct Cascade {
    name: &'static str,
    outer: Box<dyn Controller>,
    inner: Box<dyn Controller>,
    measured: Vec<usize>,
    n_outer: usize,
    inner_reference: f64,
}

impl Cascade {
    /// `outer` gives the inner set-point (in the inner state's SI units, its output range
    /// being the inner state's allowed range), `inner` the plant input.
    pub fn new(name: &'static str, outer: Box<dyn Controller>, inner: Box<dyn Controller>) -> Self {
        let mut measured = outer.measurements().to_vec();
        let n_outer = measured.len();
        measured.extend_from_slice(inner.measurements());
        Cascade {
            name,
            outer,
            inner,
            measured,
            n_outer,
            inner_reference: f64::NAN,
        }
    }

    /// The inner set-point of the last control instant (NaN before the first).
    pub fn inner_reference(&self) -> f64 {
        self.inner_reference
    }
}

impl Controller for Cascade {
    fn name(&self) -> &'static str {
        self.name
    }
    fn measurements(&self) -> &[usize] {
        &self.measured
    }
    fn control(&mut self, t: f64, measured: &[f64], setpoint: f64) -> f64 {
        let (outer, inner) = measured.split_at(self.n_outer);
        self.inner_reference = self.outer.control(t, outer, setpoint);
        self.inner.control(t, inner, self.inner_reference)
    }
    fn inner_reference(&self) -> Option<f64> {
        Some(self.inner_reference)
    }
    fn adaptive(&self, t: f64) -> Option<AdaptiveView> {
        self.outer.adaptive(t).map(|v| AdaptiveView {
            inner_reference: Some(self.inner_reference),
            ..v
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::control::Pi;

    #[test]
    fn the_outer_output_is_the_inner_set_point() {
        // Outer: P on state 1 (kp 2, output in [0, 10]); inner: P on state 0 (kp 3).
        let mut outer = Pi::new(2.0, 1e12, 1.0, 0.0, 0.0, 10.0);
        outer.measured = [1];
        let inner = Pi::new(3.0, 1e12, 1.0, 0.0, -100.0, 100.0);
        let mut c = Cascade::new("pi-cascade", Box::new(outer), Box::new(inner));
        assert_eq!(c.measurements(), &[1, 0]);
        // Outer error 5 - 1 = 4 -> inner set-point 8; inner error 8 - 2 = 6 -> 18.
        let u = c.control(0.0, &[1.0, 2.0], 5.0);
        assert!(
            (c.inner_reference() - 8.0).abs() < 1e-9 && (u - 18.0).abs() < 1e-9,
            "{u}"
        );
        assert!(c.adaptive(0.0).is_none());
    }
}

/// `kind = "cascade"` in a scenario file: an outer loop that sets an inner state's
/// set-point, and an inner loop that drives the input (one level: neither is a cascade).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CascadeLoop {
    /// The outer loop (on the regulated state).
    pub outer: Box<LoopSpec>,
    /// The inner loop (on the inner state).
    pub inner: Box<LoopSpec>,
    /// The range of the inner set-point `[min, max]` (display units of the inner loop's
    /// state).
    pub inner_range: [f64; 2],
}

impl LoopSettings for CascadeLoop {
    fn state(&self) -> &str {
        self.outer.state()
    }
    fn name(&self) -> &'static str {
        match (self.outer.name(), self.inner.name()) {
            ("rhonn-indirect", _) => "rhonn-cascade",
            (_, "rhonn-indirect") => "pi-over-rhonn-cascade",
            _ => "pi-cascade",
        }
    }
    fn inner_state(&self) -> Option<&str> {
        Some(self.inner.state())
    }
    fn build(&self, cx: &LoopContext) -> Result<Box<dyn Controller>> {
        let field = &cx.field;
        let j = cx.state_index("inner.state", self.inner.state())?;
        let qi = &cx.states[j];
        let r = (
            self.inner_range[0] / qi.display_per_si,
            self.inner_range[1] / qi.display_per_si,
        );
        if !(r.0.is_finite() && r.1.is_finite() && r.0 < r.1) {
            return Err(invalid(
                format!("{field}.inner_range"),
                format!("{:?}", self.inner_range),
                "[min, max] with min < max",
            ));
        }
        if self.inner.inner_state().is_some() || self.outer.inner_state().is_some() {
            return Err(invalid(
                format!("{field}.outer"),
                "a cascade",
                "a pi or rhonn-indirect loop (one level of cascade)",
            ));
        }
        let outer_cx = LoopContext {
            field: format!("{field}.outer"),
            output: qi,
            range: r,
            operating_input: 0.0,
            ..cx.clone()
        };
        let o = self.outer.build(&outer_cx)?;
        let inner_cx = LoopContext {
            field: format!("{field}.inner"),
            setpoint0: f64::NAN,
            ..cx.clone()
        };
        let n = self.inner.build(&inner_cx)?;
        Ok(Box::new(Cascade::new(self.name(), o, n)))
    }
}
