//! The pump runner's settings ([`PumpSettings`]: what a `[plant] kind = "pump"` scenario
//! file lowers to, `pump_scenario::lower`), checked once into a [`Scenario`] that the runner
//! accepts. Every failure names the field, the value and what is allowed (in the file's
//! keys, see `pump_scenario::lower_checked`); unknown keys are errors.

use super::pump_controllers::{adaptive_baseline, named_cascade_pi, PumpLoop};
use super::scenario::{check_folder_name, ControlSpec, ProfileSpec, SolverSpec};
use crate::error::{invalid, Error, Result};
use crate::ident::{IdentSettings, IdentifierSpec};
use crate::plant::{PumpParams, PumpParamsSpec};
use crate::signal::{Signal, SignalSpec};
use crate::units::*;
use serde::Serialize;

/// The largest steady pump flow of the thesis, Q_l,max = 2.1 dm^3/s (its eq. (1)):
/// demanded-flow peaks must stay below it.
pub const Q_L_MAX_DM3_S: f64 = 2.1;

/// Initial state, display units.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct InitialSpec {
    /// P_l(0) \[MPa\] (2).
    pub p_line_mpa: f64,
    /// x(0) \[mm\] (0).
    pub stroke_mm: f64,
}

impl Default for InitialSpec {
    fn default() -> Self {
        InitialSpec {
            p_line_mpa: 2.0,
            stroke_mm: 0.0,
        }
    }
}

/// Measurement of the line pressure.
#[derive(Debug, Clone, PartialEq, Default)]
pub(crate) struct MeasurementSpec {
    /// Standard deviation of the white Gaussian noise on the measured pressure \[MPa\] (0).
    pub noise_std_mpa: f64,
    /// Standard deviation of the white Gaussian noise on the measured stroke \[mm\] (0;
    /// only controllers that use the stroke see it).
    pub stroke_noise_std_mm: f64,
}

/// The pump runner's settings, in display units (see each field): a scenario file of the
/// pump lowered (`pump_scenario::lower`); written back in the one format by
/// `pump_scenario::raise`, never as themselves.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct PumpSettings {
    /// Short name (used for the default output folder).
    pub name: String,
    /// One line saying what the scenario shows.
    pub description: String,
    /// Simulated time \[s\].
    pub duration_s: f64,
    /// Interval of the output samples \[ms\] (1).
    pub output_interval_ms: f64,
    /// Seed of every random draw (noise, PRBS) (0).
    pub seed: u64,
    /// Parameter overrides (table 3.3 of the thesis by default).
    pub plant: PumpParamsSpec,
    /// Initial state.
    pub initial: InitialSpec,
    /// Open-loop solenoid current \[A\]; exclusive with `controller`.
    pub current_a: Option<SignalSpec>,
    /// Demanded flow \[dm^3/s\] (zero when absent).
    pub demand_dm3_s: Option<SignalSpec>,
    /// The pressure's controller (the one format's `[control]`, checked by
    /// `pump_scenario::lower`); exclusive with `current_a`.
    pub controller: Option<ControlSpec>,
    /// Measurement.
    pub measurement: MeasurementSpec,
    /// Solver settings.
    pub solver: SolverSpec,
    /// A RHONN identifier running along with the plant.
    pub identifier: Option<IdentifierSpec>,
    /// `rhonn campaign`'s distributions of the uncertain parameters (default: uniform
    /// within the thesis's tolerances); ignored by `rhonn run`, but checked.
    pub campaign: Option<super::campaign_plan::CampaignSpec>,
}

/// A checked adaptive controller and its baselines.
#[derive(Debug, Clone, PartialEq)]
pub struct AdaptiveSettings {
    /// The adaptive controller.
    pub adaptive: PumpLoop,
    /// The baseline run beside it on an identical plant (same set-point).
    pub baseline: PumpLoop,
    /// A second baseline (a named cascade PI tuning) run beside it too.
    pub second_baseline: Option<(&'static str, PumpLoop)>,
}

/// How the current is produced.
#[derive(Debug, Clone, PartialEq)]
pub enum Drive {
    /// An open-loop profile \[A\].
    OpenLoop(Signal),
    /// A controller (the PI, the cascade PI).
    Closed(Box<PumpLoop>),
    /// The RHONN adaptive cascade, compared with its baselines in the same run.
    Adaptive(Box<AdaptiveSettings>),
}

impl Drive {
    /// The loop that drives the current (None for an open-loop profile).
    pub fn closed(&self) -> Option<&PumpLoop> {
        match self {
            Drive::OpenLoop(_) => None,
            Drive::Closed(l) => Some(l),
            Drive::Adaptive(a) => Some(&a.adaptive),
        }
    }

    /// The set-point of a regulated run.
    pub fn setpoint(&self) -> Option<&Signal> {
        self.closed().map(|l| &l.setpoint)
    }

    /// The current at t = 0 of a regulated run \[A\] (None for an open-loop profile; an
    /// adaptive run's is its baseline's, so that both start alike).
    pub fn bias(&self) -> Option<f64> {
        match self {
            Drive::OpenLoop(_) => None,
            Drive::Closed(l) => Some(l.bias),
            Drive::Adaptive(a) => Some(a.baseline.bias),
        }
    }
}

/// Checked solver settings (SI).
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct SolverSettings {
    /// Profile.
    #[schemars(with = "serde_json::Value")]
    pub profile: ProfileSpec,
    /// Relative tolerance.
    pub rtol: f64,
    /// Absolute tolerance of P_l \[Pa\].
    pub atol_p_line_pa: f64,
    /// Absolute tolerance of x \[m\].
    pub atol_stroke_m: f64,
    /// Largest step \[s\].
    pub max_step_s: f64,
}

/// A validated scenario: only this type runs.
#[derive(Debug, Clone, PartialEq)]
pub struct Scenario {
    /// The settings it came from (echoed in summaries).
    pub(crate) spec: PumpSettings,
    /// Parameters (SI).
    pub(crate) params: PumpParams,
    /// P_l(0) \[Pa\], x(0) \[m\].
    pub(crate) initial: [f64; 2],
    /// Current source.
    pub(crate) drive: Drive,
    /// Demanded flow \[m^3/s\].
    pub(crate) demand: Signal,
    /// Noise standard deviation \[Pa\].
    pub(crate) noise_std_pa: f64,
    /// Noise on the measured stroke \[m\].
    pub(crate) stroke_noise_std_m: f64,
    /// Output interval \[s\].
    pub(crate) output_interval_s: f64,
    /// Solver.
    pub solver: SolverSettings,
    /// Identifier.
    pub(crate) identifier: Option<IdentSettings>,
    /// Things the user should know (printed and written to the summary).
    pub warnings: Vec<String>,
}

impl Scenario {
    /// The scenario's name.
    pub fn name(&self) -> &str {
        &self.spec.name
    }
}

impl PumpSettings {
    /// The values of the uncertain parameters a campaign draws (display units, in the
    /// order of the pump's tolerance table).
    pub fn uncertain_values(&self) -> [f64; 5] {
        let p = &self.plant;
        [p.beta_mpa, p.mu_1, p.mu_2, p.q_0_dm3_s, p.qdot_max_dm3_s2]
    }

    /// The kind of the adaptive controller's baseline, `"pi"` or `"cascade-pi"`
    /// ([`adaptive_baseline`] of its `[control]`); none without an adaptive controller.
    pub fn adaptive_baseline_kind(&self) -> Option<&'static str> {
        let c = self.controller.as_ref()?;
        matches!(c.controller, crate::control::LoopSpec::PumpRhonnAdaptive(_))
            .then(|| adaptive_baseline(c).name())
    }

    fn check_setpoint(&self, setpoint_mpa: &SignalSpec, params: &PumpParams) -> Result<Signal> {
        let lim =
            crate::signal::spec_limits(params.p_min / PA_PER_MPA, params.p_max / PA_PER_MPA, None, None);
        let setpoint = setpoint_mpa.build("controller.setpoint_mpa", PA_PER_MPA, lim)?;
        if setpoint.clips_on(self.duration_s) {
            return Err(invalid(
                "controller.setpoint_mpa",
                "a set-point",
                format!(
                    "within [{}, {}] MPa (P_min, P_max) at all times",
                    self.plant.p_min_mpa, self.plant.p_max_mpa
                ),
            ));
        }
        Ok(setpoint)
    }

    /// Validate everything and convert to SI.
    pub fn check(&self) -> Result<Scenario> {
        self.check_inner().map_err(|e| match e {
            Error::Invalid {
                value,
                scenario: None,
            } => Error::Invalid {
                value,
                scenario: Some(self.name.clone()),
            },
            other => other,
        })
    }

    fn check_inner(&self) -> Result<Scenario> {
        let mut warnings = Vec::new();
        check_folder_name("name", &self.name)?;
        if !(self.duration_s.is_finite() && self.duration_s > 0.0 && self.duration_s <= 1e6) {
            return Err(invalid("duration_s", self.duration_s, "a number in (0, 1e6] s"));
        }
        if !(self.output_interval_ms.is_finite() && self.output_interval_ms > 0.0) {
            return Err(invalid(
                "output_interval_ms",
                self.output_interval_ms,
                "a number > 0",
            ));
        }
        let dt = self.output_interval_ms * S_PER_MS;
        if self.duration_s / dt > 5e7 {
            return Err(invalid(
                "output_interval_ms",
                self.output_interval_ms,
                "at most 50,000,000 samples per run (raise the interval)",
            ));
        }
        let params = self.plant.check()?;
        let p0 = self.initial.p_line_mpa;
        if !(p0.is_finite() && p0 >= 0.0 && p0 <= self.plant.p_max_mpa) {
            return Err(invalid(
                "initial.p_line_mpa",
                p0,
                format!("a pressure in [0, {}] MPa (P_max)", self.plant.p_max_mpa),
            ));
        }
        if p0 < self.plant.p_min_mpa {
            warnings.push(format!(
                "initial.p_line_mpa = {p0} MPa is below P_min = {} MPa: the model is not valid there",
                self.plant.p_min_mpa
            ));
        }
        let x0 = self.initial.stroke_mm;
        if !(x0.is_finite() && x0 >= 0.0 && x0 <= self.plant.x_max_mm) {
            return Err(invalid(
                "initial.stroke_mm",
                x0,
                format!("a stroke in [0, {}] mm (x_max)", self.plant.x_max_mm),
            ));
        }
        let state0 = [p0 * PA_PER_MPA, x0 * M_PER_MM, 0.0];
        let drive = self.check_drive(&params, &state0, &mut warnings)?;
        let demand_lim = crate::signal::spec_limits(
            0.0,
            f64::INFINITY,
            Some((self.plant.qdot_max_dm3_s2, "Qdot_max of the plant, dm^3/s^2")),
            Some((Q_L_MAX_DM3_S, "the max pump flow Q_l,max, dm^3/s")),
        );
        let demand = match &self.demand_dm3_s {
            Some(d) => d.build("demand_dm3_s", M3_PER_DM3, demand_lim)?,
            None => Signal::constant(0.0),
        };
        if demand.clips_on(self.duration_s) {
            return Err(invalid(
                "demand_dm3_s",
                "a profile",
                "a demanded flow >= 0 at all times",
            ));
        }
        let xn = self.measurement.stroke_noise_std_mm;
        // Bounded so that the value in SI stays finite for the noise's distribution.
        if !(xn.is_finite() && (0.0..=100.0).contains(&xn)) {
            return Err(invalid(
                "measurement.stroke_noise_std_mm",
                xn,
                "a number in [0, 100] mm",
            ));
        }
        let noise = self.measurement.noise_std_mpa;
        if !(noise.is_finite() && (0.0..=100.0).contains(&noise)) {
            return Err(invalid(
                "measurement.noise_std_mpa",
                noise,
                "a number in [0, 100] MPa",
            ));
        }
        let solver = self.check_solver()?;
        if self.identifier.is_some() && matches!(drive, Drive::Adaptive(_)) {
            return Err(invalid(
                "identifier",
                "a section",
                "absent with controller kind `rhonn-adaptive` (it identifies its own model online)",
            ));
        }
        if let Some(i) = &self.identifier {
            i.check_pole_speed(self.duration_s, "duration_s")?;
        }
        if self.campaign.is_some() {
            super::campaign_plan::Plan::of(self)?;
        }
        Ok(Scenario {
            spec: self.clone(),
            params,
            initial: [p0 * PA_PER_MPA, x0 * M_PER_MM],
            drive,
            demand,
            noise_std_pa: noise * PA_PER_MPA,
            stroke_noise_std_m: xn * M_PER_MM,
            output_interval_s: dt,
            solver,
            identifier: self.identifier.as_ref().map(|i| i.check()).transpose()?,
            warnings,
        })
    }

    /// The current's drive: an open-loop profile or a controller.
    fn check_drive(&self, params: &PumpParams, x0: &[f64], warnings: &mut Vec<String>) -> Result<Drive> {
        let current_lim = crate::signal::spec_limits(0.0, params.i_max, None, None);
        Ok(match (&self.current_a, &self.controller) {
            (Some(_), Some(_)) => {
                return Err(invalid(
                    "current_a",
                    "a profile",
                    "absent when a `controller` drives the current (give one or the other)",
                ))
            }
            (None, None) => {
                return Err(invalid(
                    "current_a",
                    "nothing",
                    "a current profile, or a `controller` section",
                ))
            }
            (Some(c), None) => {
                let sig = c.build("current_a", 1.0, current_lim)?;
                if sig.clips_on(self.duration_s) {
                    warnings.push(format!("current_a leaves [0, {}] A and is clipped", params.i_max));
                }
                Drive::OpenLoop(sig)
            }
            (None, Some(c)) => self.check_controller(c, params, x0)?,
        })
    }

    /// The pressure's controller of `[control]` (its kinds and keys checked by `lower`),
    /// each loop checked by building it through the controller registry.
    fn check_controller(&self, c: &ControlSpec, params: &PumpParams, x0: &[f64]) -> Result<Drive> {
        use crate::control::LoopSpec;
        let setpoint = self.check_setpoint(&c.setpoint, params)?;
        let lp = |spec: LoopSpec, field: &str| PumpLoop::new(setpoint.clone(), spec, params, x0, field);
        Ok(match &c.controller {
            LoopSpec::Pi(_) => {
                let mut pi = lp(c.controller.clone(), "control.controller")?;
                let no_clip = crate::signal::spec_limits(f64::NEG_INFINITY, f64::INFINITY, None, None);
                pi.dither = c
                    .dither
                    .as_ref()
                    .map(|d| d.build("controller.dither_a", 1.0, no_clip))
                    .transpose()?;
                Drive::Closed(Box::new(pi))
            }
            LoopSpec::PumpRhonnAdaptive(_) => {
                let second_baseline = match c.second_baseline.as_deref() {
                    None => None,
                    Some(name) => {
                        let (name, spec) = named_cascade_pi(name)?;
                        Some((name, lp(spec, "control.second_baseline")?))
                    }
                };
                Drive::Adaptive(Box::new(AdaptiveSettings {
                    adaptive: lp(c.controller.clone(), "control.controller")?,
                    baseline: lp(adaptive_baseline(c), "control.baseline")?,
                    second_baseline,
                }))
            }
            LoopSpec::PumpCascadePi(_) => {
                Drive::Closed(Box::new(lp(c.controller.clone(), "control.controller")?))
            }
            other => {
                return Err(invalid(
                    "controller.kind",
                    format!("\"{}\"", other.name()),
                    "for the pump: pi, pump-rhonn-adaptive, pump-cascade-pi",
                ))
            }
        })
    }

    /// The solver's settings: the profile's defaults, then the file's values, checked.
    /// The generic `[solver]` on the pump's pressure and stroke (the pump's defaults:
    /// rtol 1e-6, atol 1 Pa and 1e-9 m, largest step 100 ms).
    fn check_solver(&self) -> Result<SolverSettings> {
        let defaults = crate::plant::pump::solver_defaults();
        let states = &crate::plant::pump::STATES[..2];
        let t = self.solver.check("pump", states, &defaults, self.duration_s)?;
        Ok(SolverSettings {
            profile: t.profile,
            rtol: t.rtol,
            atol_p_line_pa: t.atol[0],
            atol_stroke_m: t.atol[1],
            max_step_s: t.max_step_s,
        })
    }
}
