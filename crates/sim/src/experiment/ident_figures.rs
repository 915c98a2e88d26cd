//! The thesis's identification figures of one run, on the solver's dense output, for any
//! plant: per identified state, the RMS error, fit, NRMSE and the time after which the
//! error stays within 1 % of the state's range, accumulated step by step.

use super::integrated::Integrated;
use super::quadrature::{Scale, GAUSS};
use crate::net::Sigmoid;
use rhonn_ode::Dopri5;
use serde::Serialize;

/// A trained RHONN: everything needed to run it (`weights.json`).
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct ModelFile {
    /// Identified states (neurons), SI.
    pub states: Vec<String>,
    /// External inputs, SI.
    pub inputs: Vec<String>,
    /// Sigmoid.
    #[schemars(with = "serde_json::Value")]
    pub sigmoid: Sigmoid,
    /// State divisors before the sigmoid.
    pub state_scale: Vec<f64>,
    /// Input divisors.
    pub input_scale: Vec<f64>,
    /// Terms: `[y index, exponent]` factors each.
    pub terms: Vec<Vec<[usize; 2]>>,
    /// Poles a_i.
    pub a: Vec<f64>,
    /// The law that trained it.
    pub law: &'static str,
    /// Weights, one vector per neuron.
    pub weights: Vec<Vec<f64>>,
}

/// One identified state's figures over a whole run in one mode (training, a frozen model's
/// series-parallel estimate or its free run), on the dense output (display units).
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct RunFigures {
    /// RMS of x_hat - x.
    pub rms_error: f64,
    /// 100 (1 - |y - yhat| / |y - mean y|); left out of JSON when undefined (a state
    /// that does not move).
    #[serde(skip_serializing_if = "crate::metrics::undefined")]
    pub fit_percent: f64,
    /// RMS error / range of the state; left out of JSON when undefined.
    #[serde(skip_serializing_if = "crate::metrics::undefined")]
    pub nrmse: f64,
    /// The band: 1 % of the state's range over the run.
    pub convergence_band: f64,
    /// First time after which |e| stays within the band (null: it does not).
    pub convergence_time_s: Option<f64>,
}

/// Identification figures accumulated step by step on the dense output (3-point
/// Gauss-Legendre per step, like `regulation::Tracker`): the continuous-time forms of the sample
/// formulas (RMS error sqrt(int e^2 / T), fit 100 (1 - sqrt(int e^2) / sqrt(int (y -
/// mean y)^2)), convergence as the last time |e| exceeds the band, seen at the step
/// ends and Gauss points), so that a summary-only run needs no sampling.
pub(super) struct IdentAcc {
    /// Which model's estimates (see [`Integrated::hats`]).
    slot: usize,
    states: Vec<usize>,
    full: Vec<f64>,
    /// The estimates by plant state at one point (scratch).
    hats: Vec<Option<f64>>,
    per: Vec<StateAcc>,
}

#[derive(Default)]
struct StateAcc {
    time: f64,
    e2: f64,
    y0: Option<f64>,
    dy: f64,
    dy2: f64,
    lo: f64,
    hi: f64,
    t_end: f64,
    /// (t, |e|) with |e| strictly decreasing: the suffix maxima of the error.
    stair: Vec<(f64, f64)>,
}

impl IdentAcc {
    /// The figures of the plant states `states` (indices) from model `slot`'s estimates, on
    /// a system of `dim` states.
    pub(super) fn new(states: Vec<usize>, dim: usize, slot: usize) -> Self {
        let per = states
            .iter()
            .map(|_| StateAcc {
                lo: f64::INFINITY,
                hi: f64::NEG_INFINITY,
                ..Default::default()
            })
            .collect();
        IdentAcc {
            slot,
            states,
            full: vec![0.0; dim],
            hats: vec![None; dim],
            per,
        }
    }

    pub(super) fn add_step<S: Integrated>(&mut self, solver: &Dopri5<S>) {
        let (t0, t1) = (solver.t_prev(), solver.t());
        if !(t1 > t0) {
            return;
        }
        let h = t1 - t0;
        let pts = [
            t0,
            t0 + GAUSS[0].0 * h,
            t0 + GAUSS[1].0 * h,
            t0 + GAUSS[2].0 * h,
            t1,
        ];
        let mut vals = [[(0.0, 0.0); 5]; 2];
        let sys = solver.system();
        if self.states.iter().all(|&i| sys.hat_index(self.slot, i).is_some()) {
            // Only the identified states and their estimates.
            // A step cut at an event ends before its dense output's end.
            let r = solver.step_fraction();
            let thetas = [0.0, GAUSS[0].0 * r, GAUSS[1].0 * r, GAUSS[2].0 * r, r];
            for (k, &i) in self.states.iter().enumerate() {
                let j = sys.hat_index(self.slot, i).unwrap_or(i); // Some: checked above
                let (y, yh) = (solver.dense_component(i), solver.dense_component(j));
                for (p, &th) in thetas.iter().enumerate() {
                    vals[k][p] = (y.at(th), yh.at(th));
                }
            }
        } else {
            for (p, &t) in pts.iter().enumerate() {
                solver.interpolate(t, &mut self.full);
                sys.hats(&self.full, self.slot, &mut self.hats);
                for (k, &i) in self.states.iter().enumerate() {
                    vals[k][p] = (self.full[i], self.hats[i].unwrap_or(f64::NAN));
                }
            }
        }
        for (k, a) in self.per.iter_mut().enumerate() {
            let y0 = *a.y0.get_or_insert(vals[k][0].0);
            for q in 0..3 {
                let (y, yh) = vals[k][q + 1];
                let w = GAUSS[q].1 * h;
                a.e2 += w * (yh - y) * (yh - y);
                a.dy += w * (y - y0);
                a.dy2 += w * (y - y0) * (y - y0);
            }
            a.time += h;
            a.t_end = t1;
            let (mut lo, mut hi) = (a.lo, a.hi);
            let mut v = [0.0; 5];
            for (p, &(y, yh)) in vals[k].iter().enumerate() {
                lo = lo.min(y);
                hi = hi.max(y);
                v[p] = (yh - y).abs();
            }
            (a.lo, a.hi) = (lo, hi);
            // The stair after this step: the earlier entries above the step's largest
            // error, then the step's own suffix maxima (what pushing the five points one
            // by one, popping the entries they reach, leaves; in one pass).
            let mut keep = [false; 5];
            let mut top = f64::NEG_INFINITY;
            for p in (0..5).rev() {
                if v[p] > top {
                    keep[p] = true;
                    top = v[p];
                }
            }
            while a.stair.last().is_some_and(|&(_, last)| last <= top) {
                a.stair.pop();
            }
            for p in 0..5 {
                if keep[p] {
                    a.stair.push((pts[p], v[p]));
                }
            }
        }
    }

    /// State `k`'s figures, its errors converted to display units by `scale`.
    pub(super) fn figures(&self, k: usize, scale: Scale) -> RunFigures {
        let a = &self.per[k];
        let rms = (a.e2 / a.time).sqrt();
        let var_int = (a.dy2 - a.dy * a.dy / a.time).max(0.0);
        let range = a.hi - a.lo;
        let band = 0.01 * range;
        let conv = match a.stair.iter().rposition(|&(_, v)| v > band) {
            None => Some(0.0),
            Some(j) if a.stair[j].0 >= a.t_end => None,
            Some(j) => Some(a.stair[j].0),
        };
        RunFigures {
            rms_error: scale.apply(rms),
            fit_percent: 100.0 * (1.0 - a.e2.sqrt() / var_int.sqrt()),
            nrmse: rms / range,
            convergence_band: scale.apply(band),
            convergence_time_s: conv,
        }
    }
}

impl ModelFile {
    /// The model `is` trained, with its final `weights`, its states and inputs named by
    /// `name`.
    pub(super) fn of(
        is: &crate::ident::IdentSettings,
        name: impl Fn(&crate::plant::SignalRef) -> &'static str,
        weights: Vec<Vec<f64>>,
    ) -> Self {
        let net = &is.ident.net;
        ModelFile {
            states: is.states.iter().map(|s| name(s).to_string()).collect(),
            inputs: is.inputs.iter().map(|s| name(s).to_string()).collect(),
            sigmoid: net.sigmoid,
            state_scale: net.state_scale.clone(),
            input_scale: net.input_scale.clone(),
            terms: (0..net.n_terms()).map(|k| net.terms.factors(k)).collect(),
            a: net.a.clone(),
            law: is.ident.law.name,
            weights,
        }
    }
}
