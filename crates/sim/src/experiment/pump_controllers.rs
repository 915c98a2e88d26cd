//! The pump's classical controllers as a scenario names them: the cascade PI (outer PI
//! on the pressure, inner stroke loop; the adaptive cascade's sensors) and the baseline
//! an adaptive run is compared with (`baseline = "cascade-pi"`, the default, or `"pi"`,
//! the pressure-only PI).

use crate::control::{CascadePi, CascadePiGains};
use crate::error::{invalid, Result};
use crate::plant::{PumpParams, P_LINE, STROKE};
use crate::signal::Signal;
use crate::units::PA_PER_MPA;

/// The cascade PI's gains when a scenario gives none: the **robust** tuning found by
/// `cargo run --release -p rhonn-study --example tune_cascade_pi` (the lowest nominal IAE
/// that still regulates with doubled gains, a 5 ms solenoid lag and a one-period delay,
/// and keeps a gain margin of 6 dB and a phase margin of 45 degrees measured on the
/// simulated pump at every operating point: `rhonn_study::tuning`).
pub const ROBUST: CascadePiGainsMpa = CascadePiGainsMpa {
    kp_mm_per_mpa: 0.15,
    ti_s: 0.07,
    setpoint_weight: 0.8,
    stroke_gain: 8.0,
};

/// The **nominal-optimal** tuning of the same search: the lowest IAE on the nominal
/// plant with every set-point step's overshoot at most 10 %.
pub const NOMINAL_OPTIMAL: CascadePiGainsMpa = CascadePiGainsMpa {
    kp_mm_per_mpa: 0.75,
    ti_s: 0.05,
    setpoint_weight: 0.2,
    stroke_gain: 4.0,
};

/// Cascade PI gains in the units a scenario file uses.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CascadePiGainsMpa {
    /// Outer proportional gain \[mm/MPa\].
    pub kp_mm_per_mpa: f64,
    /// Outer integral time \[s\].
    pub ti_s: f64,
    /// Set-point weight b, in [0, 1].
    pub setpoint_weight: f64,
    /// Inner stroke gain g.
    pub stroke_gain: f64,
}

/// A checked cascade PI (SI).
#[derive(Debug, Clone, PartialEq)]
pub struct CascadePiSettings {
    /// Set-point \[Pa\].
    pub setpoint: Signal,
    /// Gains (SI).
    pub gains: CascadePiGains,
    /// The current at t = 0 \[A\] (the one whose steady stroke gives the flow Q_0).
    pub bias: f64,
}

impl CascadePiSettings {
    /// The gains in a scenario's units.
    pub fn gains_mpa(&self) -> CascadePiGainsMpa {
        let g = &self.gains;
        CascadePiGainsMpa {
            kp_mm_per_mpa: g.kp * 1e3 * PA_PER_MPA,
            ti_s: g.ti_s,
            setpoint_weight: g.setpoint_weight,
            stroke_gain: g.stroke_gain,
        }
    }

    /// The controller, built from the **nominal** table (the controller does not know the
    /// plant's deviations): feed-forward K_a/phi, stroke bias Q_0/(k_l omega).
    pub fn controller(&self, period_s: f64) -> CascadePi {
        let n = PumpParams::default();
        let mut c = CascadePi::new(
            self.gains,
            n.k_a / n.phi,
            n.q_0 / (n.k_l * n.omega),
            n.x_max,
            n.i_max,
            period_s,
        );
        c.measured = [P_LINE, STROKE];
        c
    }
}

/// Check a cascade PI's gains (fields named `<prefix>kp_mm_per_mpa` ...).
pub fn check_cascade_pi(
    g: CascadePiGainsMpa,
    setpoint: Signal,
    params: &PumpParams,
    prefix: &str,
) -> Result<CascadePiSettings> {
    let field = |name: &str| format!("{prefix}{name}");
    if !(g.kp_mm_per_mpa.is_finite() && g.kp_mm_per_mpa >= 0.0) {
        return Err(invalid(
            field("kp_mm_per_mpa"),
            g.kp_mm_per_mpa,
            "a finite number >= 0",
        ));
    }
    if !(g.ti_s.is_finite() && g.ti_s > 0.0) {
        return Err(invalid(field("ti_s"), g.ti_s, "a number > 0"));
    }
    if !(0.0..=1.0).contains(&g.setpoint_weight) {
        return Err(invalid(
            field("setpoint_weight"),
            g.setpoint_weight,
            "a number in [0, 1]",
        ));
    }
    if !(g.stroke_gain.is_finite() && g.stroke_gain >= 0.0) {
        return Err(invalid(
            field("stroke_gain"),
            g.stroke_gain,
            "a finite number >= 0",
        ));
    }
    Ok(CascadePiSettings {
        setpoint,
        gains: CascadePiGains {
            kp: g.kp_mm_per_mpa * 1e-3 / PA_PER_MPA,
            ti_s: g.ti_s,
            setpoint_weight: g.setpoint_weight,
            stroke_gain: g.stroke_gain,
        },
        bias: params.k_a * params.q_0 / (params.k_l * params.omega * params.phi),
    })
}

/// The controller an adaptive run is compared with, on an identical plant.
#[derive(Debug, Clone, PartialEq)]
pub enum Baseline {
    /// The pressure-only PI.
    Pi(PiSettings),
    /// The cascade PI with the adaptive controller's sensors.
    CascadePi(CascadePiSettings),
}

impl Baseline {
    /// The current at t = 0 \[A\].
    pub fn bias(&self) -> f64 {
        match self {
            Baseline::Pi(s) => s.bias,
            Baseline::CascadePi(s) => s.bias,
        }
    }

    /// Its name in reports.
    pub fn name(&self) -> &'static str {
        match self {
            Baseline::Pi(_) => "pi",
            Baseline::CascadePi(_) => "cascade-pi",
        }
    }
}

/// The keys of an adaptive controller's baseline, as the scenario gives them.
pub(super) struct BaselineKeys<'a> {
    pub kind: Option<&'a str>,
    pub kp_a_per_mpa: Option<f64>,
    pub ti_s: Option<f64>,
    pub kp_mm_per_mpa: Option<f64>,
    pub setpoint_weight: Option<f64>,
    pub stroke_gain: Option<f64>,
}

impl BaselineKeys<'static> {
    /// The keys of an adaptive controller's `[control.baseline]` (`pump-cascade-pi`, or `pi`
    /// on `p_line` without a bias: `pump_scenario::lower` refuses any other), all unset
    /// without one (the default baseline).
    pub(super) fn of(b: Option<&crate::control::LoopSpec>) -> Self {
        use crate::control::LoopSpec;
        let none = BaselineKeys {
            kind: None,
            kp_a_per_mpa: None,
            ti_s: None,
            kp_mm_per_mpa: None,
            setpoint_weight: None,
            stroke_gain: None,
        };
        match b {
            Some(LoopSpec::PumpCascadePi(b)) => BaselineKeys {
                kind: Some("cascade-pi"),
                ti_s: Some(b.ti_s),
                kp_mm_per_mpa: Some(b.kp_mm_per_mpa),
                setpoint_weight: Some(b.setpoint_weight),
                stroke_gain: Some(b.stroke_gain),
                ..none
            },
            Some(LoopSpec::Pi(b)) => BaselineKeys {
                kind: Some("pi"),
                kp_a_per_mpa: Some(b.kp),
                ti_s: Some(b.ti_s),
                ..none
            },
            _ => none,
        }
    }
}

/// The kind of an adaptive controller's baseline: `kind` as written, else the one its keys
/// imply (`"pi"` when the PI's gain `kp_a_per_mpa` is given, `"cascade-pi"` otherwise).
/// The one statement of that rule: the check, the one format's writer and the report's
/// labels ask it.
pub fn baseline_kind(kind: Option<&str>, kp_a_per_mpa: Option<f64>) -> &str {
    kind.unwrap_or(if kp_a_per_mpa.is_some() {
        "pi"
    } else {
        "cascade-pi"
    })
}

/// The pressure-only PI baseline's defaults: gain \[A/MPa\] and integral time \[s\].
pub const PI_BASELINE: [f64; 2] = [0.15, 0.15];

/// The baseline an adaptive run compares with: `cascade-pi` (the default, robust tuning
/// for unset gains) or `pi` (the default when `baseline_kp_a_per_mpa` is given); a key of
/// the other kind is an error.
pub(super) fn check_baseline(k: BaselineKeys, setpoint: &Signal, params: &PumpParams) -> Result<Baseline> {
    let prefix = "controller.baseline_";
    let kind = baseline_kind(k.kind, k.kp_a_per_mpa);
    match kind {
        "pi" => {
            let cascade_keys = [k.kp_mm_per_mpa, k.setpoint_weight, k.stroke_gain];
            if let Some(j) = cascade_keys.iter().position(|v| v.is_some()) {
                let name = ["kp_mm_per_mpa", "setpoint_weight", "stroke_gain"][j];
                return Err(invalid(
                    format!("{prefix}{name}"),
                    "a value",
                    "absent with baseline = \"pi\" (it belongs to the cascade PI)",
                ));
            }
            let (kp, ti) = (
                k.kp_a_per_mpa.unwrap_or(PI_BASELINE[0]),
                k.ti_s.unwrap_or(PI_BASELINE[1]),
            );
            Ok(Baseline::Pi(check_pi(
                kp,
                ti,
                None,
                setpoint.clone(),
                params,
                prefix,
            )?))
        }
        "cascade-pi" => {
            if k.kp_a_per_mpa.is_some() {
                return Err(invalid(
                    format!("{prefix}kp_a_per_mpa"),
                    "a value",
                    "absent with baseline = \"cascade-pi\" (give baseline_kp_mm_per_mpa)",
                ));
            }
            let g = CascadePiGainsMpa {
                kp_mm_per_mpa: k.kp_mm_per_mpa.unwrap_or(ROBUST.kp_mm_per_mpa),
                ti_s: k.ti_s.unwrap_or(ROBUST.ti_s),
                setpoint_weight: k.setpoint_weight.unwrap_or(ROBUST.setpoint_weight),
                stroke_gain: k.stroke_gain.unwrap_or(ROBUST.stroke_gain),
            };
            Ok(Baseline::CascadePi(check_cascade_pi(
                g,
                setpoint.clone(),
                params,
                prefix,
            )?))
        }
        other => Err(invalid(
            "controller.baseline",
            format!("\"{other}\""),
            "\"cascade-pi\" (the same sensors) or \"pi\" (the pressure only)",
        )),
    }
}

/// The cascade PI with a named tuning (`nominal-optimal` or `robust`): a second baseline.
pub(super) fn check_named_cascade_pi(
    name: &str,
    setpoint: &Signal,
    params: &PumpParams,
) -> Result<(&'static str, Baseline)> {
    let (name, g) = match name {
        "nominal-optimal" => ("nominal-optimal", NOMINAL_OPTIMAL),
        "robust" => ("robust", ROBUST),
        other => {
            return Err(invalid(
                "controller.second_baseline",
                format!("\"{other}\""),
                "\"nominal-optimal\" or \"robust\" (a tuning of the cascade PI)",
            ))
        }
    };
    let s = check_cascade_pi(g, setpoint.clone(), params, "controller.second_baseline.")?;
    Ok((name, Baseline::CascadePi(s)))
}

/// A checked PI controller (SI).
#[derive(Debug, Clone, PartialEq)]
pub struct PiSettings {
    /// Set-point \[Pa\].
    pub setpoint: Signal,
    /// Gain \[A/Pa\].
    pub kp: f64,
    /// Integral time \[s\].
    pub ti_s: f64,
    /// Output offset \[A\].
    pub bias: f64,
    /// Excitation added to the output \[A\].
    pub dither: Option<Signal>,
}

/// Check a PI's gains (fields named `<prefix>kp_a_per_mpa` ...) and convert to SI.
pub(super) fn check_pi(
    kp_a_per_mpa: f64,
    ti_s: f64,
    bias_a: Option<f64>,
    setpoint: Signal,
    params: &PumpParams,
    prefix: &str,
) -> Result<PiSettings> {
    if !(kp_a_per_mpa.is_finite() && kp_a_per_mpa >= 0.0) {
        return Err(invalid(
            format!("{prefix}kp_a_per_mpa"),
            kp_a_per_mpa,
            "a finite number >= 0",
        ));
    }
    if !(ti_s.is_finite() && ti_s > 0.0) {
        return Err(invalid(format!("{prefix}ti_s"), ti_s, "a number > 0"));
    }
    let bias = bias_a.unwrap_or(params.k_a * params.q_0 / (params.k_l * params.omega * params.phi));
    if !(bias.is_finite() && (0.0..=params.i_max).contains(&bias)) {
        return Err(invalid(
            format!("{prefix}bias_a"),
            bias,
            format!("a current in [0, {}] A", params.i_max),
        ));
    }
    Ok(PiSettings {
        setpoint,
        kp: kp_a_per_mpa / PA_PER_MPA,
        ti_s,
        bias,
        dither: None,
    })
}

#[cfg(test)]
mod tests {
    use super::baseline_kind;

    #[test]
    fn a_baseline_is_the_kind_written_else_a_pi_when_its_gain_is_given() {
        assert_eq!(baseline_kind(None, None), "cascade-pi");
        assert_eq!(baseline_kind(None, Some(0.2)), "pi");
        assert_eq!(baseline_kind(Some("cascade-pi"), Some(0.2)), "cascade-pi");
        assert_eq!(baseline_kind(Some("pi"), None), "pi");
    }
}
