//! Scenario files of any plant of the library (`[plant] kind = "tanks"`, `"pump"`, see
//! `plant::with_kind`): what drives the plant, and either an online identification (then a frozen-weight
//! validation on other inputs) or a controller and a baseline on the same plant. Values
//! are in the display units of the quantity they belong to (mm for a tank's level, V for
//! the pump voltage); times in seconds.

use super::campaign_plan::CampaignSpec;
use super::loop_conditions::{LoopConditions, SensorNoise};
pub use super::solver_spec::{ProfileSpec, SolverSpec};
pub use crate::control::LoopSpec;
use crate::error::{invalid, Error, Result};
use crate::ident::IdentifierSpec;
use crate::plant::{Input, Plant, Quantity};
use crate::signal::{Limits, Signal, SignalSpec};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// A scenario of any plant of the library, the pump's too: the one scenario type, which
/// `preset::load_any` reads and [`ScenarioSpec::run`] runs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ScenarioSpec {
    /// Name: the output folder's (one plain path component).
    pub name: String,
    /// One line on what it shows.
    #[serde(default)]
    pub description: String,
    /// Simulated time \[s\].
    pub duration_s: f64,
    /// Sample interval of the outputs \[s\] (a control run samples at its period, or at
    /// this interval from the solver's dense output when it is shorter).
    #[serde(default = "one")]
    pub output_interval_s: f64,
    /// The plant, its parameters and initial state.
    pub plant: PlantSection,
    /// A profile per plant input, by name (display units); inputs not named are 0.
    #[serde(default)]
    pub input: BTreeMap<String, SignalSpec>,
    /// An online RHONN identifier (the same section as the pump's scenarios).
    #[serde(default)]
    pub identifier: Option<IdentifierSpec>,
    /// A frozen-weight validation after the identification, on other inputs.
    #[serde(default)]
    pub validation: Option<ValidationSpec>,
    /// A controller and its baseline.
    #[serde(default)]
    pub control: Option<ControlSpec>,
    /// Noisy sensors of a control run's states.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub measurement: Option<SensorNoiseSpec>,
    /// The solver's settings (unset: the runner's tolerances).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub solver: Option<SolverSpec>,
    /// `rhonn campaign`'s distributions of the pump's uncertain parameters (the pump
    /// only; default: uniform within the thesis's tolerances).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub campaign: Option<CampaignSpec>,
}

/// `[measurement]`: white Gaussian noise on what a control run's controllers measure
/// (the controller and its baseline see the same noise; the figures are of the true
/// states).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SensorNoiseSpec {
    /// Standard deviation of the noise per state, by name (display units of the state).
    pub noise_std: BTreeMap<String, f64>,
    /// Seed of the noise streams (default 0; one stream per state).
    #[serde(default)]
    pub seed: u64,
}

fn one() -> f64 {
    1.0
}

/// `[plant]`: which plant, its initial state, and any of its parameters.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PlantSection {
    /// The plant: one of `plant::KINDS` (`tanks`, `pump`).
    pub kind: String,
    /// Initial state, one value per state (display units); default all 0.
    #[serde(default)]
    pub initial: Vec<f64>,
    /// Parameters by name (display units; the plant's list says which), the rest nominal.
    #[serde(flatten)]
    pub parameters: BTreeMap<String, f64>,
}

/// `[validation]`: run the frozen model (free run) on other inputs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ValidationSpec {
    /// Simulated time \[s\].
    pub duration_s: f64,
    /// A profile per plant input, as `input`.
    pub input: BTreeMap<String, SignalSpec>,
}

/// `[control]`: a controller and a baseline, each run on an identical plant.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ControlSpec {
    /// The plant input the controllers drive.
    pub input: String,
    /// Its allowed range `[min, max]` (display units).
    pub input_range: [f64; 2],
    /// The state they regulate.
    pub output: String,
    /// Its set-point (display units of the output).
    pub setpoint: SignalSpec,
    /// Control period \[s\] (zero-order hold).
    pub period_s: f64,
    /// The controller under test.
    pub controller: LoopSpec,
    /// The controller it is compared with, on an identical plant (none: the controller
    /// runs alone).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub baseline: Option<LoopSpec>,
    /// A second baseline on a third identical plant: a stored tuning of the baseline's
    /// kind, by its name (the pump's cascade PI: `nominal-optimal` or `robust`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub second_baseline: Option<String>,
    /// Transport delay: the command reaches the plant this many control periods late
    /// (default 0; both loops).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub delay_periods: u32,
    /// An excitation added to both loops' command (display units of the input), the sum
    /// clipped to `input_range`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dither: Option<SignalSpec>,
}

/// What a name that becomes a folder or file name may be: one plain path component.
pub const FOLDER_NAME_RULE: &str =
    "a name of letters, digits, '-', '_' and '.' that does not start with '.' \
     (it names a folder inside the output folder: no separators, no `.` or `..`, not empty)";

/// Check that `value` (the field `field` of a file) is one plain path component that stays
/// inside the folder it is joined to: letters, digits, `-`, `_` and `.`, not empty and not
/// starting with `.` (which also refuses `.` and `..`). A scenario received from someone
/// else must never write outside the folder the user chose.
pub fn check_folder_name(field: &str, value: &str) -> Result<()> {
    let ok = !value.is_empty()
        && !value.starts_with('.')
        && value.len() <= 200
        && value
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_' || c == '.');
    if ok {
        Ok(())
    } else {
        Err(invalid(field, format!("{value:?}"), FOLDER_NAME_RULE))
    }
}

fn is_zero(v: &u32) -> bool {
    *v == 0
}

/// At most this many periods of transport delay.
pub const MAX_DELAY_PERIODS: u32 = 100_000;

/// Index of state `name` of `plant`, or an error naming `field` and the states.
pub(crate) fn state_index<P: Plant>(plant: &P, field: &str, name: &str) -> Result<usize> {
    crate::plant::state_named(plant.name(), plant.states(), field, name)
}

fn names(qs: &[Quantity]) -> String {
    qs.iter().map(|q| q.name).collect::<Vec<_>>().join(", ")
}

/// Build `spec` (display units of `q`) as an SI signal clipped to `[lo, hi]` (display units of `q`).
pub(crate) fn signal(spec: &SignalSpec, field: &str, q: &Quantity, (lo, hi): (f64, f64)) -> Result<Signal> {
    let lim = Limits {
        lo,
        hi,
        max_slew: None,
        max_peak: None,
    };
    spec.build(field, 1.0 / q.display_per_si, lim)
}

/// `plant` with each input driven as `inputs` says over `duration_s` (names checked), the
/// others held at 0. A profile that leaves the range the plant takes the input in
/// ([`Plant::input_range`]) is clipped to it (and warned of: [`clipped_inputs`]); one
/// within it runs as written, its rounding at a ramp's end (1e-19 below 0) not clamped.
pub(crate) fn drive<P: Plant>(
    mut plant: P,
    inputs: &BTreeMap<String, SignalSpec>,
    field: &str,
    duration_s: f64,
) -> Result<P> {
    for (name, spec) in inputs {
        let k = plant
            .inputs()
            .iter()
            .position(|q| q.name == name.as_str())
            .ok_or_else(|| {
                invalid(
                    format!("{field}.{name}"),
                    "a profile",
                    format!("an input of the {}: {}", plant.name(), names(plant.inputs())),
                )
            })?;
        let q = &plant.inputs()[k];
        let (max_slew, max_peak) = plant.input_profile_limits(k);
        let lim = Limits {
            lo: f64::NEG_INFINITY,
            hi: f64::INFINITY,
            max_slew,
            max_peak,
        };
        let f = format!("{field}.{name}");
        let mut s = spec.build(&f, 1.0 / q.display_per_si, lim)?;
        let (lo, hi) = plant.input_range(k);
        if (lo.is_finite() || hi.is_finite()) && duration_s <= CLIP_CHECK_S {
            let clipped = Limits {
                lo: q.to_display(lo),
                hi: q.to_display(hi),
                ..lim
            };
            let within = spec.build(&f, 1.0 / q.display_per_si, clipped)?;
            if within.clips_on(duration_s) {
                s = within;
            }
        }
        plant.set_input(k, Input::Signal(s))?;
    }
    Ok(plant)
}

/// The longest run whose input profiles are checked for clipping \[s\] (a million
/// milliseconds).
pub(crate) const CLIP_CHECK_S: f64 = 1e6;

/// A warning per input of `inputs` whose profile leaves the range the plant clips it to
/// ([`Plant::input_range`]) within `duration_s` (`field` names the section). The profile
/// is read every millisecond, so runs longer than [`CLIP_CHECK_S`] are not read (the pump's
/// own format refuses them).
pub(crate) fn clipped_inputs<P: Plant>(
    plant: &P,
    inputs: &BTreeMap<String, SignalSpec>,
    field: &str,
    duration_s: f64,
) -> Result<Vec<String>> {
    let mut warnings = Vec::new();
    for (name, spec) in inputs {
        let Some(k) = plant.inputs().iter().position(|q| q.name == name.as_str()) else {
            continue;
        };
        let (lo, hi) = plant.input_range(k);
        if (lo.is_finite() || hi.is_finite()) && duration_s <= CLIP_CHECK_S {
            let q = &plant.inputs()[k];
            let s = signal(
                spec,
                &format!("{field}.{name}"),
                q,
                (q.to_display(lo), q.to_display(hi)),
            )?;
            if s.clips_on(duration_s) {
                warnings.push(format!(
                    "{field}.{name} leaves [{}, {}] {} and is clipped",
                    crate::metrics::sig(q.to_display(lo), 4),
                    crate::metrics::sig(q.to_display(hi), 4),
                    q.display_unit
                ));
            }
        }
    }
    Ok(warnings)
}

/// The plant of `section` from its nominal instance: parameters set (unknown names are
/// errors listing the known), and the given initial states in SI (all of them, or the
/// plant's [`Plant::initial_given`]; [`Plant::initial_state`] completes them).
pub(crate) fn configure<P: Plant>(nominal: &P, section: &PlantSection) -> Result<(P, Vec<f64>)> {
    let params = nominal.parameters();
    for key in section.parameters.keys() {
        if !params.iter().any(|p| p.name == key.as_str()) {
            let known: Vec<&str> = params.iter().map(|p| p.name).collect();
            return Err(invalid(
                format!("plant.{key}"),
                section.parameters[key],
                format!(
                    "a parameter of the {}: kind, initial, {}",
                    nominal.name(),
                    known.join(", ")
                ),
            ));
        }
    }
    let values: Vec<f64> = params
        .iter()
        .map(|p| section.parameters.get(p.name).copied().unwrap_or(p.nominal))
        .collect();
    let plant = nominal.with_parameters(&values)?;
    let states = plant.states();
    let default = plant.initial_given();
    let n = section.initial.len();
    let x0 = if n == 0 {
        default
    } else if n != states.len() && n != default.len() {
        let first = if default.len() < states.len() {
            format!(
                ", or the first {} ({}; the others start at the inputs)",
                default.len(),
                names(&states[..default.len()])
            )
        } else {
            String::new()
        };
        return Err(invalid(
            "plant.initial",
            format!("{:?}", section.initial),
            format!("one value per state ({}){first}", names(states)),
        ));
    } else {
        section
            .initial
            .iter()
            .zip(states)
            .map(|(v, q)| v / q.display_per_si)
            .collect()
    };
    if let Some(v) = x0.iter().find(|v| !v.is_finite()) {
        return Err(invalid("plant.initial", v, "finite values"));
    }
    within_bounds(&plant, &x0)?;
    Ok((plant, x0))
}

/// Each given initial state within the plant's bounds ([`Plant::state_bounds`]; the
/// pump's pressure in [0, P_max], its stroke in [0, x_max]): an error naming
/// `plant.initial[i]`, in display units.
fn within_bounds<P: Plant>(plant: &P, x0: &[f64]) -> Result<()> {
    for (i, ((v, (lo, hi)), q)) in x0
        .iter()
        .zip(plant.state_bounds())
        .zip(plant.states())
        .enumerate()
    {
        if !(lo..=hi).contains(v) {
            let show = |v: f64| crate::metrics::sig(q.to_display(v), 4);
            return Err(invalid(
                format!("plant.initial[{i}] ({}, {})", q.name, q.display_unit),
                show(*v),
                format!(
                    "a value in [{}, {}] {} ({})",
                    show(lo),
                    show(hi),
                    q.display_unit,
                    q.description
                ),
            ));
        }
    }
    Ok(())
}

impl ScenarioSpec {
    /// Parse a scenario file's text; `source` names it in errors.
    pub fn from_toml(text: &str, source: &str) -> Result<Self> {
        toml::from_str(text).map_err(|e| Error::Parse {
            source_name: source.to_string(),
            message: e.to_string(),
        })
    }

    /// The scenario as TOML (what a campaign records).
    pub fn to_toml(&self) -> String {
        toml::to_string(self).unwrap_or_else(|e| format!("# cannot be written as TOML: {e}"))
    }

    /// The checks that need no plant: name, times, at most one experiment.
    pub fn check_common(&self) -> Result<()> {
        self.check_times()?;
        self.check_experiment()
    }

    /// Name, duration and output interval.
    pub(crate) fn check_times(&self) -> Result<()> {
        check_folder_name("name", &self.name)?;
        if !(self.duration_s.is_finite() && self.duration_s > 0.0) {
            return Err(invalid("duration_s", self.duration_s, "finite and > 0"));
        }
        if !(self.output_interval_s.is_finite() && self.output_interval_s > 0.0) {
            return Err(invalid(
                "output_interval_s",
                self.output_interval_s,
                "finite and > 0",
            ));
        }
        if self.output_interval_s > self.duration_s {
            return Err(invalid(
                "output_interval_s",
                self.output_interval_s,
                format!(
                    "at most duration_s = {} s: at least one output sample",
                    self.duration_s
                ),
            ));
        }
        if self.duration_s / self.output_interval_s > 1e7 {
            return Err(invalid(
                "duration_s, output_interval_s",
                format!("{} s, {} s", self.duration_s, self.output_interval_s),
                "at most 10,000,000 output samples (duration_s / output_interval_s): a shorter duration_s or a longer output_interval_s",
            ));
        }
        Ok(())
    }

    /// At most one experiment: an identifier or a control loop (neither: the plant driven
    /// by its inputs alone).
    fn check_experiment(&self) -> Result<()> {
        match (&self.identifier, &self.control) {
            (Some(_), Some(_)) => Err(invalid(
                "identifier, control",
                "both",
                "at most one of an [identifier] section and a [control] section (neither: the plant driven by its [input] profiles alone)",
            )),
            (None, _) if self.validation.is_some() => {
                Err(invalid("validation", "a section", "only with an [identifier]"))
            }
            (None, None) if self.measurement.is_some() => Err(invalid(
                "measurement",
                "a section",
                "only with a [control] section (what the controllers measure)",
            )),
            (Some(_), None) if self.measurement.is_some() => Err(invalid(
                "measurement",
                "a section",
                "only with a [control] section (the identifier learns from the plant's states as they are integrated, not from sampled measurements)",
            )),
            _ => Ok(()),
        }
    }
}

/// Whether a scenario text is a plant scenario (its `[plant]` has a `kind`; the pump's
/// own scenario format has none).
pub fn is_plant_scenario(text: &str) -> bool {
    let Ok(v) = toml::from_str::<toml::Value>(text) else {
        return false;
    };
    v.get("plant")
        .and_then(|p| p.get("kind"))
        .and_then(|k| k.as_str())
        .is_some()
}

/// The loop conditions of `spec`'s control run on `plant`: noise on the named states,
/// the delay and the dither of `control` on input `qu` in `range` (SI).
pub(crate) fn loop_conditions<P: Plant>(
    plant: &P,
    spec: &ScenarioSpec,
    control: &ControlSpec,
    qu: &Quantity,
    range: (f64, f64),
) -> Result<LoopConditions> {
    let mut c = LoopConditions {
        input_range: range,
        delay_periods: control.delay_periods,
        ..LoopConditions::default()
    };
    if control.delay_periods > MAX_DELAY_PERIODS {
        return Err(invalid(
            "control.delay_periods",
            control.delay_periods,
            format!("a whole number of control periods from 0 to {MAX_DELAY_PERIODS}"),
        ));
    }
    if let Some(d) = &control.dither {
        c.dither = Some(signal(d, "control.dither", qu, (-1e150, 1e150))?);
    }
    if let Some(m) = &spec.measurement {
        for (name, std) in &m.noise_std {
            let field = format!("measurement.noise_std.{name}");
            let i = state_index(plant, &field, name)?;
            let si = std / plant.states()[i].display_per_si;
            // Bounded so that a measurement plus its noise stays finite.
            if !(std.is_finite() && *std >= 0.0 && si < 1e150) {
                return Err(invalid(
                    field,
                    std,
                    format!("a standard deviation >= 0 in {}", plant.states()[i].display_unit),
                ));
            }
            c.noise.push(SensorNoise::per_state(i, si, m.seed));
        }
        c.noise.sort_by_key(|n| n.state);
    }
    Ok(c)
}
