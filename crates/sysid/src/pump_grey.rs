//! The training of `kind = "pump"` (its structure, filter and prediction:
//! `models::pump_grey`, whose public items this module re-exports).
//!
//! Training (`law = "multi-step"`, horizon K): Levenberg-Marquardt on the logarithms of
//! the unknown parameters, minimising the K-step simulation error of windows that start
//! every K samples from the filter's estimate (multiple shooting: each window starts
//! from the state the data say, not from the previous window's end). The measurement
//! noise is estimated from each record (covariance matching of the filter's
//! innovations) unless `measurement_noise_mpa` is given.
//!

use super::{Model, ModelSpec};
use crate::data::Record;
use crate::error::{invalid, Error, Result};
use crate::models::pump_grey::ekf::{filter, Noise};
use crate::models::pump_grey::{check_record_units, check_values, noise_for, param_index, pump_of, simulate};
pub use crate::models::pump_grey::{
    describe_estimates, estimate_states, predict_from_state, thesis_values, PumpGreySpec, PARAM_NAMES,
};

/// The `spec.horizon`-step errors of windows every `horizon` samples, in MPa, for the
/// stored values `v`.
fn window_residuals(
    spec: &ModelSpec,
    dt: f64,
    v: &[f64],
    records: &[Record],
    noises: &[Noise],
    out: &mut Vec<f64>,
) -> bool {
    let kk = spec.horizon;
    let pump = pump_of(v, spec, dt);
    out.clear();
    let mut buf = Vec::new();
    for (r, noise) in records.iter().zip(noises) {
        let y = &r.outputs[0];
        let n = r.len();
        let f = filter(&pump, *noise, &r.inputs[0], &r.inputs[1], y, n);
        let mut k = spec.settle.min(n) - 1;
        while k + kk < n {
            simulate(&pump, r, k, f.states[k], kk, &mut buf);
            out.extend(buf.iter().zip(&y[k + 1..=k + kk]).map(|(p, y)| (p - y) / 1e6));
            k += kk;
        }
    }
    out.iter().all(|e| e.is_finite())
}

/// Train a `pump` model's unknown parameters (see the module's docs).
pub(crate) fn fit(spec: &ModelSpec, records: &[Record], m: &mut Model) -> Result<()> {
    if m.inputs.len() != 2 || m.outputs.len() != 1 {
        return Err(invalid(
            "inputs and outputs",
            format!("{} / {}", m.inputs.join(","), m.outputs.join(",")),
            "two inputs (the current [A], then the demand [m^3/s]) and one output (the line pressure [Pa])",
        ));
    }
    let mut start = thesis_values();
    for (n, x) in &spec.pump.known {
        start[param_index(n, "model.pump.known")?] = *x;
    }
    m.weights = vec![start.clone()];
    for r in records {
        check_record_units(m, r)?;
    }
    let idx: Vec<usize> = spec
        .pump
        .estimate
        .iter()
        .map(|n| param_index(n, "model.pump.estimate"))
        .collect::<Result<_>>()?;
    // Coordinates 1 + ln(value / start): the log keeps every value positive, and the
    // offset makes the LM's relative finite-difference step a relative step of the value.
    let values = |theta: &[f64]| {
        let mut v = start.clone();
        for (&j, t) in idx.iter().zip(theta) {
            // Within a factor of 10 of the start.
            v[j] = start[j] * (t - 1.0).clamp(-10f64.ln(), 10f64.ln()).exp();
        }
        v
    };
    // Stages (continuation). First a forgiving filter (process noise 1 MPa/sqrt(s) on the
    // pressure, 0.01 mm/sqrt(s) on the stroke: it follows the measured pressure closely)
    // and a short horizon: far from the parameters, a filter that trusts the equations
    // loses the state and the error stops saying which way to go, while this one's
    // short-horizon error stays a smooth function of the parameters. Then the spec's
    // horizon, with the process noise lowered tenfold per stage down to the spec's, each
    // stage starting where the last ended. (Thirtyfold steps were tried: faster, the same
    // 10-step fits, but 200-step fits 40 points lower on some records.)
    let mut stages = Vec::new();
    let mut level = 1.0f64;
    loop {
        let mut st = spec.clone();
        st.pump.process_noise_mpa = spec.pump.process_noise_mpa.max(level);
        st.pump.process_noise_mm = spec.pump.process_noise_mm.max(level * 1e-2);
        let last = st.pump.process_noise_mpa == spec.pump.process_noise_mpa
            && st.pump.process_noise_mm == spec.pump.process_noise_mm;
        if stages.is_empty() {
            let mut first = st.clone();
            first.horizon = spec.horizon.min(5);
            stages.push(first);
        }
        stages.push(st);
        if last || stages.len() > 8 {
            break;
        }
        level /= 10.0;
    }
    let mut theta = vec![1.0; idx.len()];
    let dt = m.sample_time_s;
    for stage in &stages {
        if theta.is_empty() {
            break;
        }
        let here = pump_of(&values(&theta), stage, dt);
        let noises: Vec<Noise> = records.iter().map(|r| noise_for(stage, &here, r)).collect();
        let resid =
            |th: &[f64], out: &mut Vec<f64>| window_residuals(stage, dt, &values(th), records, &noises, out);
        let cost = super::lm::lm(&mut theta, spec.epochs, 1e-3, &resid);
        if !cost.is_finite() {
            return Err(Error::NotFinite {
                what: "the pump model's K-step error at its starting parameters".into(),
                cause: "the data or the `known` values; check the units (Pa, A, m^3/s)".into(),
            });
        }
    }
    m.weights = vec![values(&theta)];
    check_values(&m.weights[0], "the fitted pump parameters")
}

/// `kind = "pump"`.
pub(crate) struct PumpGrey;

impl super::kinds::Fit for PumpGrey {
    fn fit(&self, spec: &ModelSpec, records: &[Record], m: &mut Model) -> Result<()> {
        fit(spec, records, m)
    }

    fn parameters(&self, _spec: &ModelSpec, _ni: usize, _no: usize) -> usize {
        8
    }
}
