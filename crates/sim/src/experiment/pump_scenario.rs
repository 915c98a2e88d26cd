//! A scenario of the one format whose plant is the pump (`[plant] kind = "pump"`),
//! lowered to the settings the pump's own runner takes ([`PumpSettings`], then checked
//! into a [`super::Scenario`]): the runner that samples the dense output, reports the
//! pressure regulation and draws the thesis's figures. Every key is the one format's;
//! an error names the key the user wrote.

use super::pump_settings::{InitialSpec, MeasurementSpec, PumpSettings};
use super::scenario::{ControlSpec, ScenarioSpec};
use crate::control::LoopSpec;
use crate::error::{invalid, Error, Result};
use crate::plant::PumpParamsSpec;

/// The pump's inputs in `[input]`.
const INPUTS: &str = "current (A, open loop), demand (dm^3/s)";

/// `spec` (its plant the pump) as the pump runner's settings.
pub fn lower(spec: &ScenarioSpec) -> Result<PumpSettings> {
    spec.check_times()?;
    if spec.validation.is_some() {
        return Err(invalid(
            "validation",
            "a section",
            "for the pump, `[identifier] validate = true` (frozen-weight runs on the same inputs)",
        ));
    }
    let mut plant = plant_parameters(spec)?;
    let mut out = PumpSettings {
        name: spec.name.clone(),
        description: spec.description.clone(),
        duration_s: spec.duration_s,
        output_interval_ms: spec.output_interval_s * 1e3,
        seed: spec.measurement.as_ref().map_or(0, |m| m.seed),
        plant: PumpParamsSpec::default(),
        initial: initial(&spec.plant.initial)?,
        current_a: None,
        demand_dm3_s: None,
        controller: None,
        measurement: measurement(spec)?,
        solver: spec.solver.clone().unwrap_or_default(),
        identifier: spec.identifier.clone(),
        campaign: spec.campaign.clone(),
    };
    for (name, signal) in &spec.input {
        match name.as_str() {
            "current" => out.current_a = Some(signal.clone()),
            "demand" => out.demand_dm3_s = Some(signal.clone()),
            _ => {
                return Err(invalid(
                    format!("input.{name}"),
                    "a profile",
                    format!("an input of the pump: {INPUTS}"),
                ))
            }
        }
    }
    if let Some(c) = &spec.control {
        if out.current_a.is_some() {
            return Err(invalid(
                "input.current",
                "a profile",
                "none with a [control] section (the controller drives the current)",
            ));
        }
        check_loop(c, &plant, spec.duration_s)?;
        plant.t_control_ms = c.period_s * 1e3;
        plant.transport_delay_periods = c.delay_periods;
        check_controller(c)?;
        out.controller = Some(c.clone());
    }
    out.plant = plant;
    Ok(out)
}

/// `[plant]`'s parameters (the pump's names, display units) over the thesis's table.
fn plant_parameters(spec: &ScenarioSpec) -> Result<PumpParamsSpec> {
    let nominal =
        toml::Table::try_from(PumpParamsSpec::default()).map_err(|e| Error::Argument(e.to_string()))?;
    let mut table = toml::Table::new();
    for (key, value) in &spec.plant.parameters {
        let moved = match key.as_str() {
            "t_control_ms" => Some("[control] period_s"),
            "transport_delay_periods" => Some("[control] delay_periods"),
            _ => None,
        };
        if let Some(to) = moved {
            return Err(invalid(
                format!("plant.{key}"),
                value,
                format!("not here: give {to}"),
            ));
        }
        if !nominal.contains_key(key) {
            let known: Vec<&str> = nominal
                .keys()
                .map(String::as_str)
                .filter(|k| !matches!(*k, "t_control_ms" | "transport_delay_periods"))
                .collect();
            return Err(invalid(
                format!("plant.{key}"),
                value,
                format!("a parameter of the pump: kind, initial, {}", known.join(", ")),
            ));
        }
        table.insert(key.clone(), toml::Value::Float(*value));
    }
    table.try_into().map_err(|e: toml::de::Error| {
        invalid(
            "plant",
            "its parameters",
            format!("numbers in the pump's units ({})", e.message()),
        )
    })
}

/// `[plant] initial`: the line pressure \[MPa\] and the stroke \[mm\] (default 2 MPa, 0 mm).
fn initial(values: &[f64]) -> Result<InitialSpec> {
    match values {
        [] => Ok(InitialSpec::default()),
        [p, x] => Ok(InitialSpec {
            p_line_mpa: *p,
            stroke_mm: *x,
        }),
        _ => Err(invalid(
            "plant.initial",
            format!("{values:?}"),
            "[p_line MPa, stroke mm] (the solenoid's current starts at the drive's first value)",
        )),
    }
}

/// `[measurement]`: noise on the pressure \[MPa\] and the stroke \[mm\].
fn measurement(spec: &ScenarioSpec) -> Result<MeasurementSpec> {
    let mut m = MeasurementSpec::default();
    for (name, std) in spec.measurement.iter().flat_map(|m| &m.noise_std) {
        match name.as_str() {
            "p_line" => m.noise_std_mpa = *std,
            "stroke" => m.stroke_noise_std_mm = *std,
            _ => {
                return Err(invalid(
                    format!("measurement.noise_std.{name}"),
                    std,
                    "a measured state of the pump: p_line (MPa), stroke (mm)",
                ))
            }
        }
    }
    Ok(m)
}

/// The loop's input, output and range are the pump's current and pressure.
fn check_loop(c: &ControlSpec, plant: &PumpParamsSpec, duration_s: f64) -> Result<()> {
    if c.input != "current" {
        return Err(invalid(
            "control.input",
            format!("\"{}\"", c.input),
            "\"current\" (the pump's controllers drive the solenoid)",
        ));
    }
    if c.output != "p_line" {
        return Err(invalid(
            "control.output",
            format!("\"{}\"", c.output),
            "\"p_line\" (the pump's controllers regulate the line pressure)",
        ));
    }
    if c.input_range != [0.0, plant.i_max_a] {
        return Err(invalid(
            "control.input_range",
            format!("{:?}", c.input_range),
            format!(
                "[0.0, {}]: the solenoid's range, 0 to plant.i_max_a (A)",
                plant.i_max_a
            ),
        ));
    }
    if !(c.period_s.is_finite() && c.period_s > 0.0) {
        return Err(invalid("control.period_s", c.period_s, "finite and > 0"));
    }
    super::plant_run::check_control_periods(duration_s, c.period_s)?;
    if c.dither.is_some() && !matches!(c.controller, LoopSpec::Pi(_)) {
        return Err(invalid(
            "control.dither",
            "a profile",
            "only with a pi controller on the pump",
        ));
    }
    Ok(())
}

/// The pump's controller of `[control]`: its state, and its baseline's kind.
fn check_controller(c: &ControlSpec) -> Result<()> {
    let state = c.controller.state();
    if state != "p_line" {
        return Err(invalid(
            "control.controller.state",
            format!("\"{state}\""),
            "\"p_line\"",
        ));
    }
    let alone = |kind: &str| -> Result<()> {
        for (field, given) in [
            ("control.baseline", c.baseline.is_some()),
            ("control.second_baseline", c.second_baseline.is_some()),
        ] {
            if given {
                return Err(invalid(
                    field,
                    "given",
                    format!("none with a {kind} controller on the pump (it runs alone)"),
                ));
            }
        }
        Ok(())
    };
    match &c.controller {
        LoopSpec::Pi(_) => alone("pi"),
        LoopSpec::PumpCascadePi(_) => alone("pump-cascade-pi"),
        LoopSpec::PumpRhonnAdaptive(_) => match &c.baseline {
            None | Some(LoopSpec::PumpCascadePi(_)) => Ok(()),
            Some(LoopSpec::Pi(b)) if b.bias.is_none() && b.state == "p_line" => Ok(()),
            Some(other) => Err(invalid(
                "control.baseline",
                format!("kind \"{}\" on \"{}\"", other.name(), other.state()),
                "beside the pump's adaptive controller: pump-cascade-pi, or pi on p_line without a bias (the balance current's)",
            )),
        },
        other => Err(invalid(
            "control.controller.kind",
            format!("\"{}\"", other.name()),
            "for the pump: pi, pump-rhonn-adaptive, pump-cascade-pi",
        )),
    }
}

/// The pump runner's field names as the one format writes them, for the errors of
/// [`PumpSettings::check`] on a lowered scenario (first matching prefix wins).
const FIELDS: &[(&str, &str)] = &[
    ("controller.setpoint_mpa", "control.setpoint"),
    ("controller.dither_a", "control.dither"),
    ("controller.second_baseline", "control.second_baseline"),
    ("controller.baseline_kp_a_per_mpa", "control.baseline.kp"),
    (
        "controller.baseline_kp_mm_per_mpa",
        "control.baseline.kp_mm_per_mpa",
    ),
    ("controller.baseline_ti_s", "control.baseline.ti_s"),
    (
        "controller.baseline_setpoint_weight",
        "control.baseline.setpoint_weight",
    ),
    ("controller.baseline_stroke_gain", "control.baseline.stroke_gain"),
    ("controller.baseline", "control.baseline"),
    ("controller.kp_a_per_mpa", "control.controller.kp"),
    ("controller.bias_a", "control.controller.bias"),
    ("controller.kind", "control.controller.kind"),
    ("controller.", "control.controller."),
    ("controller", "control"),
    ("current_a", "input.current"),
    ("demand_dm3_s", "input.demand"),
    ("measurement.noise_std_mpa", "measurement.noise_std.p_line"),
    ("measurement.stroke_noise_std_mm", "measurement.noise_std.stroke"),
    ("initial.p_line_mpa", "plant.initial[0] (p_line, MPa)"),
    ("initial.stroke_mm", "plant.initial[1] (stroke, mm)"),
    ("plant.t_control_ms", "control.period_s (in ms)"),
    ("plant.transport_delay_periods", "control.delay_periods"),
    ("output_interval_ms", "output_interval_s (in ms)"),
    ("seed", "measurement.seed"),
];

/// `field` (one or more, comma-separated) as the one format names it.
fn one_format_field(field: &str) -> String {
    field
        .split(", ")
        .map(|f| {
            FIELDS
                .iter()
                .find(|(old, _)| f.starts_with(old))
                .map_or(f.to_string(), |(old, new)| format!("{new}{}", &f[old.len()..]))
        })
        .collect::<Vec<_>>()
        .join(", ")
}

/// [`lower`], then the pump runner's checks, their errors naming the one format's keys.
pub fn lower_checked(spec: &ScenarioSpec) -> Result<PumpSettings> {
    let named = |e: Error| match e {
        Error::Invalid {
            value,
            scenario: None,
        } => Error::Invalid {
            value,
            scenario: Some(spec.name.clone()),
        },
        e => e,
    };
    let out = lower(spec).map_err(named)?;
    match out.check() {
        Ok(_) => Ok(out),
        Err(Error::Invalid { mut value, scenario }) => {
            value.field = one_format_field(&value.field);
            Err(Error::Invalid { value, scenario })
        }
        Err(e) => Err(e),
    }
}

/// The pump runner's settings written back in the one format (a campaign's worst-run
/// files): [`lower`] of the result checks into the same [`super::Scenario`]. Parameters
/// at the thesis's values are left out; a cascade PI's unset gains are written as the
/// robust tuning they default to.
pub fn raise(spec: &PumpSettings) -> ScenarioSpec {
    use super::scenario::{PlantSection, SensorNoiseSpec};
    use std::collections::BTreeMap;
    let nominal = toml::Table::try_from(PumpParamsSpec::default()).unwrap_or_default();
    let given = toml::Table::try_from(spec.plant.clone()).unwrap_or_default();
    let parameters: BTreeMap<String, f64> = given
        .iter()
        .filter(|(k, v)| {
            nominal.get(*k) != Some(*v) && !matches!(k.as_str(), "t_control_ms" | "transport_delay_periods")
        })
        .filter_map(|(k, v)| Some((k.clone(), v.as_float()?)))
        .collect();
    let mut input = BTreeMap::new();
    for (name, s) in [("current", &spec.current_a), ("demand", &spec.demand_dm3_s)] {
        if let Some(s) = s {
            input.insert(name.to_string(), s.clone());
        }
    }
    let m = &spec.measurement;
    let measurement = (m.noise_std_mpa != 0.0 || m.stroke_noise_std_mm != 0.0 || spec.seed != 0).then(|| {
        let mut noise_std = BTreeMap::from([("p_line".to_string(), m.noise_std_mpa)]);
        if m.stroke_noise_std_mm != 0.0 {
            noise_std.insert("stroke".into(), m.stroke_noise_std_mm);
        }
        SensorNoiseSpec {
            noise_std,
            seed: spec.seed,
        }
    });
    ScenarioSpec {
        name: spec.name.clone(),
        description: spec.description.clone(),
        duration_s: spec.duration_s,
        output_interval_s: spec.output_interval_ms / 1e3,
        plant: PlantSection {
            kind: "pump".into(),
            initial: vec![spec.initial.p_line_mpa, spec.initial.stroke_mm],
            parameters,
        },
        input,
        identifier: spec.identifier.clone(),
        validation: None,
        control: spec.controller.as_ref().map(|c| raised_control(spec, c)),
        measurement,
        solver: (spec.solver != Default::default()).then(|| spec.solver.clone()),
        campaign: spec.campaign.clone(),
    }
}

/// `spec` serialised as [`raise`] writes it (summary.json's echo of the scenario).
pub(crate) fn serialize_raised<S: serde::Serializer>(
    spec: &PumpSettings,
    s: S,
) -> std::result::Result<S::Ok, S::Error> {
    serde::Serialize::serialize(&raise(spec), s)
}

/// `[control]` of the pump runner's controller `c`: its range, period and delay the
/// plant's, an adaptive controller's baseline written out (the robust cascade PI when unset).
fn raised_control(spec: &PumpSettings, c: &ControlSpec) -> ControlSpec {
    let p_line = || "p_line".to_string();
    let adaptive = matches!(c.controller, LoopSpec::PumpRhonnAdaptive(_));
    let baseline = adaptive.then(|| super::pump_controllers::adaptive_baseline(c));
    ControlSpec {
        input: "current".into(),
        input_range: [0.0, spec.plant.i_max_a],
        output: p_line(),
        setpoint: c.setpoint.clone(),
        period_s: spec.plant.t_control_ms / 1e3,
        controller: c.controller.clone(),
        baseline,
        second_baseline: if adaptive { c.second_baseline.clone() } else { None },
        delay_periods: spec.plant.transport_delay_periods,
        dither: match c.controller {
            LoopSpec::Pi(_) => c.dither.clone(),
            _ => None,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::experiment::preset::{load_pump, SHIPPED};

    #[test]
    fn every_shipped_pump_scenario_raised_and_lowered_again_runs_the_same() {
        let mut n = 0;
        for (name, text) in SHIPPED {
            if !text.contains("kind = \"pump\"") {
                continue;
            }
            let spec = load_pump(name);
            let mut perturbed = spec.clone();
            perturbed.plant.beta_mpa *= 1.1;
            for s in [spec, perturbed] {
                // Equal but for the echoed spec (a cascade PI's unset gains written out).
                let again = lower(&raise(&s)).unwrap();
                let (a, mut b) = (s.check().unwrap(), again.check().unwrap());
                b.spec = s.clone();
                assert_eq!(a, b, "{name}");
                // And through the file's text.
                let text = toml::to_string(&raise(&s)).unwrap();
                let reread = ScenarioSpec::from_toml(&text, name).unwrap();
                assert_eq!(
                    lower_checked(&reread).unwrap().check().unwrap().drive,
                    a.drive,
                    "{name}"
                );
            }
            n += 1;
        }
        assert_eq!(n, 8);
    }

    #[test]
    fn errors_name_the_keys_of_the_one_format() {
        let base = ScenarioSpec::from_toml(
            crate::experiment::preset::SHIPPED
                .iter()
                .find(|(n, _)| *n == "regulated-pi")
                .unwrap()
                .1,
            "regulated-pi",
        )
        .unwrap();
        let err = |edit: &dyn Fn(&mut ScenarioSpec)| {
            let mut s = base.clone();
            edit(&mut s);
            lower_checked(&s).unwrap_err().to_string()
        };
        let e = err(&|s| s.control.as_mut().unwrap().period_s = -1.0);
        assert!(e.contains("`control.period_s` = -1"), "{e}");
        let e = err(&|s| {
            s.solver.get_or_insert_with(Default::default).max_step_ms = Some(1e-9);
        });
        assert!(
            e.contains("`solver.max_step_ms` = 1e-9") && e.contains("10,000,000 steps"),
            "{e}"
        );
        let e = err(&|s| s.control.as_mut().unwrap().period_s = 1e-9);
        assert!(
            e.contains("`control.period_s` = 1e-9") && e.contains("1,000,000 control periods"),
            "{e}"
        );
        let e = err(&|s| s.control.as_mut().unwrap().input_range = [0.0, 1.0]);
        assert!(
            e.contains("`control.input_range`") && e.contains("plant.i_max_a"),
            "{e}"
        );
        let e = err(&|s| {
            s.measurement
                .as_mut()
                .unwrap()
                .noise_std
                .insert("p_line".into(), -1.0);
        });
        assert!(e.contains("`measurement.noise_std.p_line` = -1"), "{e}");
        let e = err(&|s| {
            s.plant.parameters.insert("t_control_ms".into(), 1.0);
        });
        assert!(
            e.contains("`plant.t_control_ms`") && e.contains("[control] period_s"),
            "{e}"
        );
        let e = err(&|s| {
            s.input
                .insert("voltage".into(), s.control.as_ref().unwrap().setpoint.clone());
        });
        assert!(e.contains("`input.voltage`") && e.contains("current"), "{e}");
        let e = err(&|s| s.plant.initial = vec![2.0, 0.0, 0.1]);
        assert!(e.contains("`plant.initial`"), "{e}");
        let e = err(&|s| {
            if let LoopSpec::Pi(p) = &mut s.control.as_mut().unwrap().controller {
                p.kp = f64::NAN;
            }
        });
        assert!(e.contains("`control.controller.kp`"), "{e}");
        assert!(e.contains("scenario `regulated-pi`"), "{e}");
    }
}
