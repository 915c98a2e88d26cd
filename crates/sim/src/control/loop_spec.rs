//! What a controller kind of a scenario file implements ([`LoopSettings`]: the state it
//! regulates, its name in reports, and how it is built), and what it is built against
//! ([`LoopContext`]: the plant's states, the quantity and range it drives, the period).
//! The kinds themselves are registered in `control/mod.rs` (`loop_kinds!`), one line each.

use super::Controller;
use crate::error::{invalid, Result};
use crate::plant::{state_named, Quantity};

/// What a loop is built against: the plant's states by name and unit, what the loop drives
/// (the plant's input, or a cascade's inner set-point) and in which range, the control
/// period and the plant's initial state.
#[derive(Debug, Clone)]
pub struct LoopContext<'a> {
    /// The plant's name (for errors).
    pub plant: &'a str,
    /// The plant's states.
    pub states: &'a [Quantity],
    /// Where the loop sits in the file (`control.controller.outer`), for errors.
    pub field: String,
    /// The quantity the loop's output is (its display unit is that of the settings).
    pub output: &'a Quantity,
    /// The output's allowed range, SI.
    pub range: (f64, f64),
    /// Control period \[s\].
    pub period_s: f64,
    /// The loop's set-point at t = 0 (SI; NaN for a cascade's inner loop, whose set-point
    /// the outer loop makes).
    pub setpoint0: f64,
    /// The plant's initial state, SI.
    pub x0: &'a [f64],
    /// The plant's operating input on the loop's output (SI, [`crate::plant::Plant::operating_input`];
    /// 0 for a cascade's outer loop, whose output is a set-point): a PI's bias when its
    /// settings give none.
    pub operating_input: f64,
}

impl LoopContext<'_> {
    /// Index of the plant state `name`, given as the loop's key `key`, or an error naming
    /// the field and the plant's states.
    pub fn state_index(&self, key: &str, name: &str) -> Result<usize> {
        state_named(self.plant, self.states, &format!("{}.{key}", self.field), name)
    }

    /// `v` if finite and > 0, else an error naming the loop's key `key`.
    pub fn positive(&self, key: &str, v: f64) -> Result<f64> {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(invalid(format!("{}.{key}", self.field), v, "finite and > 0"))
        }
    }
}

/// A controller kind's settings as a scenario file writes them (a `serde` struct whose
/// keys are the table's, `kind` aside).
pub trait LoopSettings {
    /// The plant state the loop regulates (a cascade: its outer loop's).
    fn state(&self) -> &str;
    /// Its name in reports.
    fn name(&self) -> &'static str;
    /// A cascade's inner state (None for a single loop).
    fn inner_state(&self) -> Option<&str> {
        None
    }
    /// The output the loop's settings add at rest (display units of its output: a PI's
    /// `bias`), when they give one; else the loop starts from the plant's operating input.
    fn bias(&self) -> Option<f64> {
        None
    }
    /// The baseline it is compared with when `[control]` names none (default: none, the
    /// controller runs alone).
    fn default_baseline(&self) -> Option<super::LoopSpec> {
        None
    }
    /// The names of the kind's stored tunings (a second baseline names one).
    fn tunings(&self) -> &'static [&'static str] {
        &[]
    }
    /// The same kind on the same state with the stored tuning `name`, if there is one.
    fn tuning(&self, _name: &str) -> Option<super::LoopSpec> {
        None
    }
    /// The controller, checked against `cx` (errors name `cx.field` and the key).
    fn build(&self, cx: &LoopContext) -> Result<Box<dyn Controller>>;
}
