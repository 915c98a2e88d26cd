//! `kind = "pump"`: a grey-box model of the variable-displacement pump, for records where
//! only the line pressure is measured (with noise) and the current and the demand are
//! known.
//!
//! The model is the plant's own equations (docs/pump-model.md, `rhonn_core::pump`) with
//! the parameters named in `[pump] estimate` unknown (default: the four the thesis gives
//! a tolerance for, beta, Q_0, mu_1, mu_2), and an extended Kalman filter
//! (the `ekf` submodule) estimating the hidden stroke, the pressure and an unmodelled flow from the
//! measured pressure and the current. A prediction K samples ahead starts from the
//! filter's estimate at k and runs the equations over the next K samples' inputs (the
//! current held, as a controller's zero-order hold gives it; the demand linear between
//! samples, or held), as MATLAB's `compare(data, model, K)` does with a state estimate.
//!
//! This folder is the structure, its filter and its prediction; its training is
//! `sysid::pump_grey`.
//!
//! Inputs, in this order: the solenoid current \[A\] and the demanded flow \[m^3/s\];
//! output: the line pressure \[Pa\] (the units of `rhonn run`'s trajectory.csv).

pub mod ekf;

use super::{Estimator, Model, ModelSpec};
use crate::data::Record;
use crate::error::{invalid, Error, Result};
use crate::plant::pump::PumpParams;
use ekf::{filter, measurement_noise, GreyPump, Noise};
use rayon::prelude::*;
use rhonn_core::pump::PumpEquations;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The `[pump]` table of a `kind = "pump"` model spec.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PumpGreySpec {
    /// Parameters to estimate, by name (see [`PARAM_NAMES`]); default beta, q_0, mu_1,
    /// mu_2 (the thesis's uncertain ones).
    pub estimate: Vec<String>,
    /// Known values (SI) that replace the thesis's table, by name.
    pub known: BTreeMap<String, f64>,
    /// The demand linear between samples (default true); else held like the current.
    pub interpolate_demand: bool,
    /// RK4 substeps per sample (default 4).
    pub substeps: usize,
    /// The state estimator's process noise density on the pressure \[MPa / sqrt(s)\].
    pub process_noise_mpa: f64,
    /// ... on the stroke \[mm / sqrt(s)\].
    pub process_noise_mm: f64,
    /// ... on the unmodelled flow \[dm^3/s / sqrt(s)\].
    pub process_noise_dm3_s: f64,
    /// Measurement noise standard deviation \[MPa\]; default: estimated from each record.
    pub measurement_noise_mpa: Option<f64>,
}

impl Default for PumpGreySpec {
    fn default() -> Self {
        PumpGreySpec {
            estimate: ["beta", "q_0", "mu_1", "mu_2"].map(String::from).to_vec(),
            known: BTreeMap::new(),
            interpolate_demand: true,
            substeps: 4,
            process_noise_mpa: 0.01,
            process_noise_mm: 0.00001,
            process_noise_dm3_s: 0.0,
            measurement_noise_mpa: None,
        }
    }
}

/// The names of the grey-box's parameters, in the order `model.json` stores them (SI):
/// `rhonn_core::pump::PumpEquations`'s fields, then the pressure and stroke bounds.
pub const PARAM_NAMES: [&str; 18] = [
    "v_l0", "beta", "alpha_v", "k_l", "omega", "q_0", "a_a", "mu_1", "mu_2", "phi", "k_c", "k_a", "k", "f_u",
    "gamma_l", "p_0", "p_max", "x_max",
];

/// The thesis's values in [`PARAM_NAMES`]' order.
pub fn thesis_values() -> Vec<f64> {
    let p = PumpParams::default();
    let e = p.equations();
    vec![
        e.v_l0, e.beta, e.alpha_v, e.k_l, e.omega, e.q_0, e.a_a, e.mu_1, e.mu_2, e.phi, e.k_c, e.k_a, e.k,
        e.f_u, e.gamma_l, e.p_0, p.p_max, p.x_max,
    ]
}

/// The index in [`PARAM_NAMES`] of `name`, or the error naming `field`.
pub fn param_index(name: &str, field: &str) -> Result<usize> {
    PARAM_NAMES
        .iter()
        .position(|n| *n == name)
        .ok_or_else(|| invalid(field, name, format!("one of {}", PARAM_NAMES.join(", "))))
}

/// Check stored values: every one finite and > 0, gamma_l below 1.
pub fn check_values(v: &[f64], field: &str) -> Result<()> {
    if v.len() != PARAM_NAMES.len() {
        return Err(invalid(field, v.len(), format!("{} values", PARAM_NAMES.len())));
    }
    for (name, x) in PARAM_NAMES.iter().zip(v) {
        if !(x.is_finite() && *x > 0.0) || (*name == "gamma_l" && *x >= 1.0) {
            return Err(invalid(
                format!("{field} ({name})"),
                x,
                if *name == "gamma_l" {
                    "a number in (0, 1)"
                } else {
                    "a finite number > 0 (SI)"
                },
            ));
        }
    }
    Ok(())
}

impl PumpGreySpec {
    /// Validate the table (and the law of the spec it belongs to).
    pub fn check(&self, law: Estimator) -> Result<()> {
        if law != Estimator::MultiStep {
            return Err(invalid(
                "model.law",
                law.name(),
                "multi-step (a `pump` model is trained on its K-step error)",
            ));
        }
        for n in &self.estimate {
            param_index(n, "model.pump.estimate")?;
        }
        if self.estimate.len() > 8 {
            return Err(invalid(
                "model.pump.estimate",
                self.estimate.len(),
                "at most 8 parameters",
            ));
        }
        let mut v = thesis_values();
        for (n, x) in &self.known {
            v[param_index(n, "model.pump.known")?] = *x;
        }
        check_values(&v, "model.pump.known")?;
        if !(1..=100).contains(&self.substeps) {
            return Err(invalid(
                "model.pump.substeps",
                self.substeps,
                "an integer in [1, 100]",
            ));
        }
        for (name, x) in [
            ("process_noise_mpa", self.process_noise_mpa),
            ("process_noise_mm", self.process_noise_mm),
            ("process_noise_dm3_s", self.process_noise_dm3_s),
        ] {
            if !(x.is_finite() && x >= 0.0) {
                return Err(invalid(format!("model.pump.{name}"), x, "a number >= 0"));
            }
        }
        if let Some(x) = self.measurement_noise_mpa {
            if !(x.is_finite() && x > 0.0) {
                return Err(invalid("model.pump.measurement_noise_mpa", x, "a number > 0"));
            }
        }
        Ok(())
    }

    /// Whether every setting is the default (then `model.json` leaves the table out).
    pub fn is_default(&self) -> bool {
        *self == Self::default()
    }

    fn process(&self) -> [f64; 3] {
        [
            self.process_noise_mpa,
            self.process_noise_mm,
            self.process_noise_dm3_s,
        ]
    }
}

/// The estimated parameters of a fitted model, in display units and against the
/// thesis's table, e.g. "beta 1200.3 MPa (1.0002 x table), ...".
pub fn describe_estimates(m: &Model) -> String {
    let table = thesis_values();
    let v = &m.weights[0];
    let shown: Vec<String> = m
        .spec
        .pump
        .estimate
        .iter()
        .filter_map(|name| {
            let j = PARAM_NAMES.iter().position(|n| n == name)?;
            let (scale, unit) = display_unit(name);
            let x = v[j] * scale;
            let shown = if x.abs() < 0.01 {
                format!("{x:.4e}")
            } else {
                format!("{x:.5}")
            };
            Some(format!("{name} {shown} {unit}({:.4} x table)", v[j] / table[j]))
        })
        .collect();
    if shown.is_empty() {
        "nothing (every parameter from the table and `known`)".into()
    } else {
        shown.join(", ")
    }
}

/// The display scale and unit (with a trailing space, or empty) of a parameter.
pub fn display_unit(name: &str) -> (f64, &'static str) {
    match name {
        "beta" | "p_0" | "p_max" => (1e-6, "MPa "),
        "alpha_v" => (1e6, "1/MPa "),
        "q_0" => (1e3, "dm^3/s "),
        "v_l0" => (1e3, "dm^3 "),
        "x_max" => (1e3, "mm "),
        "a_a" => (1e2, "dm^2 "),
        "k_l" => (1.0, "m^2 "),
        "omega" => (1.0, "rad/s "),
        "phi" => (1.0, "N/A "),
        "k_c" | "k_a" | "k" => (1.0, "N/m "),
        "f_u" => (1.0, "N "),
        _ => (1.0, ""),
    }
}

/// Number of stored parameters.
pub fn n_params() -> usize {
    PARAM_NAMES.len()
}

/// Check a stored model (read from `model.json`).
pub fn validate(m: &Model) -> Result<()> {
    if m.inputs.len() != 2 || m.outputs.len() != 1 || m.weights.len() != 1 {
        return Err(invalid(
            "model",
            format!("{} inputs, {} outputs", m.inputs.len(), m.outputs.len()),
            "a `pump` model has two inputs (current, demand) and one output (pressure)",
        ));
    }
    check_values(&m.weights[0], "model.weights")
}

/// The grey-box pump of the stored `values`, sampled every `dt` seconds.
pub fn pump_of(values: &[f64], spec: &ModelSpec, dt: f64) -> GreyPump {
    let v = values;
    GreyPump {
        eq: PumpEquations {
            v_l0: v[0],
            beta: v[1],
            alpha_v: v[2],
            k_l: v[3],
            omega: v[4],
            q_0: v[5],
            a_a: v[6],
            mu_1: v[7],
            mu_2: v[8],
            phi: v[9],
            k_c: v[10],
            k_a: v[11],
            k: v[12],
            f_u: v[13],
            gamma_l: v[14],
            p_0: v[15],
        },
        p_max: v[16],
        x_max: v[17],
        dt,
        substeps: spec.pump.substeps,
        interpolate_demand: spec.pump.interpolate_demand,
    }
}

/// Check the units of a record: pressure in Pa, current in A, demand in m^3/s.
pub fn check_record_units(m: &Model, r: &Record) -> Result<()> {
    let max_abs = |c: &[f64]| c.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let p = max_abs(&r.outputs[0]);
    if p < 1e4 {
        return Err(invalid(
            format!("column `{}` of {}", m.outputs[0], r.source),
            format!("largest |value| {p}"),
            "a line pressure in Pa (a `pump` model reads SI: multiply MPa by 1e6)",
        ));
    }
    let q = max_abs(&r.inputs[1]);
    if q > 0.1 {
        return Err(invalid(
            format!("column `{}` of {}", m.inputs[1], r.source),
            format!("largest |value| {q}"),
            "a demanded flow in m^3/s (a `pump` model reads SI: multiply dm^3/s by 1e-3)",
        ));
    }
    Ok(())
}

/// The noise settings for record `r` under `spec` and the parameters of `pump`.
pub fn noise_for(spec: &ModelSpec, pump: &GreyPump, r: &Record) -> Noise {
    let process = spec.pump.process();
    let measurement_mpa = spec
        .pump
        .measurement_noise_mpa
        .unwrap_or_else(|| measurement_noise(pump, process, &r.inputs[0], &r.inputs[1], &r.outputs[0]));
    Noise {
        process,
        measurement_mpa,
    }
}

/// A non-finite estimate as an error with the time and the state.
pub fn ensure_finite_state(m: &Model, r: &Record, k: usize, z: [f64; 3]) -> Result<()> {
    if z.iter().all(|v| v.is_finite()) {
        return Ok(());
    }
    Err(Error::NotFinite {
        what: format!(
            "the pump model's state at t = {} s of {} (pressure {} MPa, stroke {} mm, unmodelled flow {} dm^3/s)",
            r.t[k],
            r.source,
            z[0] / 1e6,
            z[1] * 1e3,
            z[2] * 1e3
        ),
        cause: format!(
            "the parameters {:?} or the data; check the units (Pa, A, m^3/s)",
            m.weights[0]
        ),
    })
}

/// Run the equations from the estimate `z` at sample `k` for `steps` samples; the
/// pressures at k + 1 ..= k + steps go to `out`.
pub fn simulate(pump: &GreyPump, r: &Record, k: usize, mut z: [f64; 3], steps: usize, out: &mut Vec<f64>) {
    out.clear();
    let (i, q) = (&r.inputs[0], &r.inputs[1]);
    for j in k..k + steps {
        z = pump.step(z, i[j], q[j], q[j + 1]);
        out.push(z[0]);
    }
}

/// The state the fitted `pump` model's filter estimates after each sample of `r`:
/// `[P_l Pa, x m, b m^3/s]` (the same estimates its K-step predictions start from).
pub fn estimate_states(m: &Model, r: &Record) -> Result<Vec<[f64; 3]>> {
    if m.spec.kind != super::Kind::Pump {
        return Err(invalid(
            "estimate_states",
            format!("{:?} model", m.spec.kind),
            "a `pump` model",
        ));
    }
    check_record_units(m, r)?;
    let pump = pump_of(&m.weights[0], &m.spec, m.sample_time_s);
    let noise = noise_for(&m.spec, &pump, r);
    let f = filter(&pump, noise, &r.inputs[0], &r.inputs[1], &r.outputs[0], r.len());
    for (k, z) in f.states.iter().enumerate() {
        ensure_finite_state(m, r, k, *z)?;
    }
    Ok(f.states)
}

/// The pressures \[Pa\] a fitted `pump` model predicts for samples k + 1 ..= k + steps of
/// `r` from a given state `[P_l Pa, x m, b m^3/s]` at sample k (for instance the true
/// state of a simulated record, to measure what the state estimate costs).
pub fn predict_from_state(
    m: &Model,
    r: &Record,
    k: usize,
    state: [f64; 3],
    steps: usize,
) -> Result<Vec<f64>> {
    if m.spec.kind != super::Kind::Pump || k + steps >= r.len() {
        return Err(invalid(
            "predict_from_state",
            format!("{:?} model, sample {k} + {steps} of {}", m.spec.kind, r.len()),
            "a `pump` model and k + steps within the record",
        ));
    }
    let pump = pump_of(&m.weights[0], &m.spec, m.sample_time_s);
    let mut out = Vec::new();
    simulate(&pump, r, k, state, steps, &mut out);
    Ok(out)
}

/// Prediction of a pump model: free run (`None`: the filter on the first `settle`
/// samples, then the equations on the inputs alone) or `K` samples ahead (the filter
/// up to k, the equations to k + K). The first samples hold the measurements.
pub fn predict(m: &Model, r: &Record, steps_ahead: Option<usize>) -> Result<(Vec<Vec<f64>>, usize)> {
    check_record_units(m, r)?;
    let pump = pump_of(&m.weights[0], &m.spec, m.sample_time_s);
    let noise = noise_for(&m.spec, &pump, r);
    let n = r.len();
    let s = m.spec.settle.min(n);
    let y = &r.outputs[0];
    let mut pred = y.clone();
    let mut out = Vec::new();
    let first = match steps_ahead {
        None => {
            let f = filter(&pump, noise, &r.inputs[0], &r.inputs[1], y, s);
            let z = f.states[s - 1];
            ensure_finite_state(m, r, s - 1, z)?;
            simulate(&pump, r, s - 1, z, n - s, &mut out);
            pred[s..].copy_from_slice(&out);
            s
        }
        Some(kk) => {
            let kk = kk.max(1);
            let f = filter(&pump, noise, &r.inputs[0], &r.inputs[1], y, n);
            for (k, z) in f.states.iter().enumerate() {
                ensure_finite_state(m, r, k, *z)?;
            }
            let first = (s - 1 + kk).min(n);
            let tail: Vec<f64> = (first..n)
                .into_par_iter()
                .map_init(Vec::new, |buf, end| {
                    simulate(&pump, r, end - kk, f.states[end - kk], kk, buf);
                    buf[kk - 1]
                })
                .collect();
            pred[first..].copy_from_slice(&tail);
            first
        }
    };
    if let Some(k) = pred.iter().position(|v| !v.is_finite()) {
        return Err(Error::NotFinite {
            what: format!("the pump model's prediction at t = {} s of {}", r.t[k], r.source),
            cause: format!(
                "the parameters {:?}; check the units (Pa, A, m^3/s)",
                m.weights[0]
            ),
        });
    }
    Ok((vec![pred], first))
}

/// `kind = "pump"`.
pub struct PumpGrey;

impl super::kinds::Structure for PumpGrey {
    fn with_article(&self, _kind: super::Kind) -> &'static str {
        "the pump's grey-box"
    }

    fn check_spec(&self, spec: &ModelSpec) -> Result<()> {
        super::int_in("settle", spec.settle, 1, 1000)?;
        spec.pump.check(spec.law)
    }

    fn predict(&self, m: &Model, r: &Record, steps_ahead: Option<usize>) -> Result<(Vec<Vec<f64>>, usize)> {
        predict(m, r, steps_ahead)
    }

    fn validate(&self, m: &Model) -> Result<()> {
        validate(m)
    }

    fn n_params(&self, _m: &Model) -> usize {
        n_params()
    }

    fn holds_outputs_in_range(&self) -> bool {
        false
    }

    /// A grey-box pump model has no lags: the lagged models' warnings do not apply.
    fn data_warnings_apply(&self) -> bool {
        false
    }

    fn named_parameters(&self, m: &Model) -> Option<std::collections::BTreeMap<String, f64>> {
        Some(
            PARAM_NAMES
                .iter()
                .zip(&m.weights[0])
                .map(|(n, v)| (n.to_string(), *v))
                .collect(),
        )
    }
}
