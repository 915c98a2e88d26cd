//! A controller kind added as any new one is (this file and one line in `loop_kinds!`),
//! to show and test that nothing else needs to change: an on/off controller with a
//! hysteresis band, `kind = "test-bang-bang"` in a scenario file (built in tests only).

use super::{Controller, LoopContext, LoopSettings};
use crate::error::Result;
use serde::{Deserialize, Serialize};

/// On/off: the top of the range below `setpoint - band`, the bottom above
/// `setpoint + band`, unchanged in between.
struct BangBang {
    measured: [usize; 1],
    band: f64,
    range: (f64, f64),
    on: bool,
}

impl Controller for BangBang {
    fn name(&self) -> &'static str {
        "test-bang-bang"
    }
    fn measurements(&self) -> &[usize] {
        &self.measured
    }
    fn control(&mut self, _t: f64, measured: &[f64], setpoint: f64) -> f64 {
        if measured[0] < setpoint - self.band {
            self.on = true;
        } else if measured[0] > setpoint + self.band {
            self.on = false;
        }
        if self.on {
            self.range.1
        } else {
            self.range.0
        }
    }
}

/// Its settings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BangBangLoop {
    /// The state it measures.
    pub state: String,
    /// Half the hysteresis band (display units of the state).
    pub band: f64,
}

impl LoopSettings for BangBangLoop {
    fn state(&self) -> &str {
        &self.state
    }
    fn name(&self) -> &'static str {
        "test-bang-bang"
    }
    fn build(&self, cx: &LoopContext) -> Result<Box<dyn Controller>> {
        let i = cx.state_index("state", &self.state)?;
        let band = cx.positive("band", self.band)? / cx.states[i].display_per_si;
        Ok(Box::new(BangBang {
            measured: [i],
            band,
            range: cx.range,
            on: false,
        }))
    }
}

#[cfg(test)]
mod tests {
    use crate::experiment::{run_plant_scenario, ScenarioSpec};

    /// The tanks' scenario with the baseline's inner loop replaced by the new kind: it
    /// runs, is named in the figures, regulates within its band, and its errors name
    /// the field.
    #[test]
    fn a_controller_kind_added_in_one_file_runs_in_a_scenario() {
        let text = include_str!("../../../../scenarios/tanks-control.toml").replace(
            "inner = { kind = \"pi\", state = \"h1\", kp = 0.2, ti_s = 10.0 }",
            "inner = { kind = \"test-bang-bang\", state = \"h1\", band = 2.0 }",
        );
        let spec = ScenarioSpec::from_toml(&text, "t.toml").unwrap();
        let out = run_plant_scenario(&spec, None).unwrap();
        let [a, b]: [_; 2] = out.summary.control.unwrap().try_into().unwrap();
        assert_eq!((a.controller, b.controller), ("rhonn-cascade", "pi-cascade"));
        // On/off: the voltage only takes its bounds, and the level still follows.
        let u = &out
            .trajectory
            .iter()
            .find(|c| c.name == "voltage_baseline")
            .unwrap()
            .values;
        assert!(u.iter().all(|v| *v == 0.0 || *v == 10.0));
        assert!(b.final_error.abs() < 5.0, "{} mm", b.final_error);
        assert!(b.time_input_switching_s > 100.0, "{}", b.time_input_switching_s);
        let bad = text.replace("band = 2.0", "band = -2.0");
        let spec = ScenarioSpec::from_toml(&bad, "t.toml").unwrap();
        let e = run_plant_scenario(&spec, None).unwrap_err().to_string();
        assert!(e.contains("control.baseline.inner.band"), "{e}");
    }
}
