//! The online identifier's continuous-time engine (`structure = "continuous"`, the
//! default): the thesis's RHONN neurons integrated between samples by classical RK4, the
//! update `rhonn_core::online`'s (see the `online` module's docs).

use super::engine::{EngineState, OnlineEngine};
use super::online_spec::{InputHold, OnlineSpec, Scaling};
use super::{Identifier, Mode, Scratch};
use crate::error::{invalid, Error, Result};
use crate::law::{GainSpec, LawSpec, Rule};
use crate::net::{Network, Sigmoid, Terms};
use rhonn_core::online::{Buffers, Online, Settings, Status, UpdateError};
use rhonn_core::online_fixed::online_terms;

/// The continuous-time engine.
#[derive(Debug, Clone)]
pub(super) struct Continuous {
    ident: Identifier,
    scaling: Scaling,
    hold: InputHold,
    filters_s: Vec<f64>,
    dead_zone: Vec<f64>,
    period_s: f64,
    state: Vec<f64>,
    k: Vec<f64>,
    acc: Vec<f64>,
    tmp: Vec<f64>,
    scratch: Scratch,
    /// Last sample's time, frozen, free run.
    status: Status<f64>,
    /// Last sample's normalised outputs and regressor inputs (inputs, filters, 1).
    y_last: Vec<f64>,
    u_last: Vec<f64>,
    yn: Vec<f64>,
    u_now: Vec<f64>,
    u_mid: Vec<f64>,
    y_hat: Vec<f64>,
}

/// What [`Continuous`] saves around a K-step-ahead prediction.
#[derive(Debug, Clone)]
struct ContinuousSnapshot {
    state: Vec<f64>,
    t_last: Option<f64>,
    y_last: Vec<f64>,
    u_last: Vec<f64>,
}

impl Continuous {
    pub(super) fn new(
        spec: &OnlineSpec,
        ny: usize,
        nu: usize,
        period_s: f64,
        scaling: Scaling,
    ) -> Result<Self> {
        let nf = spec.filters_s.len();
        let m = nu * (1 + nf) + 1;
        // Monomials of the outputs' sigmoids, the inputs and their filters, and one
        // constant term (the last network input is 1).
        let first = if spec.output_terms { 0 } else { ny };
        // An upper bound on the monomials before building them (a spec with many filters
        // and a high degree would otherwise take the memory before the check below).
        let signals = (ny + m - 1 - first) as f64;
        let bound: f64 = (1..=spec.degree)
            .map(|k| {
                (0..k)
                    .map(|j| (signals + j as f64) / (j + 1) as f64)
                    .product::<f64>()
            })
            .sum();
        if bound > 1e6 {
            return Err(invalid(
                "model.degree",
                spec.degree,
                format!("a structure with at most 400 terms (degree {} over {signals} signals gives up to {bound:.0}: lower degree or max_factors, or use fewer filters)", spec.degree),
            ));
        }
        // The terms as a target's fixed-size identifier builds them (rhonn_core).
        let mut lists: Vec<Vec<[usize; 2]>> = vec![vec![]];
        let mut cur = vec![0; ny + m - 1];
        let dims = (ny, nu, nf);
        online_terms(
            dims,
            spec.output_terms,
            spec.degree,
            spec.max_factors,
            &mut cur,
            |f| match f {
                Some((j, d)) => {
                    if let Some(term) = lists.last_mut() {
                        term.push([j, d as usize]);
                    }
                }
                None => lists.push(vec![]),
            },
        );
        lists.pop();
        let terms = Terms::from_lists(&lists, ny + m, "model.terms")?;
        let l = terms.len();
        if l > 400 {
            return Err(invalid(
                "model.degree",
                spec.degree,
                format!("a structure with at most 400 terms (this one has {l}: lower degree or max_factors, or use fewer filters)"),
            ));
        }
        let a = spec.a_per_s.unwrap_or(0.1 / period_s);
        let net = Network {
            n: ny,
            m,
            sigmoid: Sigmoid::TANH,
            state_scale: vec![1.0; ny],
            input_scale: vec![1.0; m],
            terms,
            a: vec![a; ny],
        };
        let law_spec = spec.law.clone().unwrap_or_else(|| LawSpec::FilteredError {
            gamma: vec![GainSpec::Scalar(spec.gain / (period_s * l as f64)); ny],
        });
        let law = law_spec.check(ny, l, "model.law")?;
        let ident = Identifier::new(net, law, Mode::Train);
        let state = ident.initial_state(&vec![0.0; ny], None);
        let d = ident.dim();
        let scratch = Scratch::for_identifier(&ident);
        Ok(Continuous {
            dead_zone: scaling.y_scale.iter().map(|s| spec.dead_zone / s).collect(),
            scaling,
            hold: spec.inputs,
            filters_s: spec.filters_s.clone(),
            period_s,
            k: vec![0.0; d],
            acc: vec![0.0; d],
            tmp: vec![0.0; d],
            state,
            scratch,
            status: Status::default(),
            y_last: vec![0.0; ny],
            u_last: vec![0.0; m],
            yn: vec![0.0; ny],
            u_now: vec![0.0; m],
            u_mid: vec![0.0; m],
            y_hat: vec![0.0; ny],
            ident,
        })
    }

    /// Take the sample `(t, u, y)`: integrate from the last sample to `t`, return the
    /// estimate of `y(t)` made before seeing `y` (the first sample returns `y`), then
    /// learn from `y`. In a free run `y` is ignored (give anything of the right length).
    fn sample(&mut self, t: f64, u: &[f64], y: &[f64]) -> Result<&[f64]> {
        match self.core().update(t, u, y) {
            Ok(()) => Ok(&self.y_hat),
            Err(UpdateError::Sizes) => Err(invalid(
                "update",
                format!("{} inputs and {} outputs", u.len(), y.len()),
                format!(
                    "{} inputs and {} outputs",
                    self.scaling.u_scale.len(),
                    self.scaling.y_scale.len()
                ),
            )),
            // The core refused a value it reads: the first non-finite one is it (a refusal
            // stays one even if the check named none).
            Err(UpdateError::NotFinite) => Err(super::engine::check_sample_finite(t, u, y, true)
                .err()
                .unwrap_or_else(|| {
                    Error::Argument(format!(
                        "the sample at t = {t} s holds a value that is not finite"
                    ))
                })),
            Err(UpdateError::NotAfter { t_last }) => Err(invalid(
                "t",
                t,
                format!("a time after the previous sample's, {t_last} s"),
            )),
            Err(UpdateError::Diverged) => {
                // The last estimate is that of the sample before (the core left y_hat).
                Err(Error::NotFinite {
                    what: format!("the online identifier's state at t = {t} s"),
                    cause: format!(
                        "the weights diverged (last estimate {:?}, measured {:?}): lower the gain, add a dead zone, or use a sigma law",
                        self.y_hat, y
                    ),
                })
            }
        }
    }

    /// The buffers borrowed as `rhonn_core`'s update runs on them.
    fn core(&mut self) -> Online<'_, f64, Rule> {
        let (ident, zones) = self.ident.view_and_zones();
        Online {
            ident,
            zones,
            settings: Settings {
                scaling: rhonn_core::online::Scaling {
                    y_offset: &self.scaling.y_offset,
                    y_scale: &self.scaling.y_scale,
                    u_offset: &self.scaling.u_offset,
                    u_scale: &self.scaling.u_scale,
                    y_bounds: self.scaling.y_bounds.as_deref(),
                },
                hold: self.hold,
                filters_s: &self.filters_s,
                dead_zone: &self.dead_zone,
                period_s: self.period_s,
            },
            buf: Buffers {
                state: &mut self.state,
                k: &mut self.k,
                acc: &mut self.acc,
                tmp: &mut self.tmp,
                y_last: &mut self.y_last,
                u_last: &mut self.u_last,
                yn: &mut self.yn,
                u_now: &mut self.u_now,
                u_mid: &mut self.u_mid,
                y_hat: &mut self.y_hat,
                work: self.scratch.work(),
            },
            status: &mut self.status,
        }
    }
}

impl OnlineEngine for Continuous {
    /// Stop (`true`) or resume adapting the weights.
    fn freeze(&mut self, frozen: bool) {
        self.status.frozen = frozen;
    }

    /// Run free (`true`): the model on its own outputs, weights frozen; or back to
    /// series-parallel.
    fn set_free_run(&mut self, free: bool) {
        self.status.free_run = free;
    }

    /// Forget the last sample (a new record starts): the next update restarts the model
    /// at its measurement; the weights stay.
    fn reset(&mut self) {
        self.status.t_last = None;
    }

    /// Put the model's estimate at `y` (output units), as at a record's first sample.
    fn set_estimate(&mut self, y: &[f64]) {
        self.core().set_estimate(y);
    }

    /// Weights, one vector per output's neuron (normalised units).
    fn weights(&self) -> Vec<Vec<f64>> {
        self.ident.weights(&self.state)
    }

    /// Set the weights (e.g. saved ones).
    fn set_weights(&mut self, w: &[Vec<f64>]) {
        self.ident.set_weights(&mut self.state, w);
    }

    /// Each term's name, in weight order, e.g. `tanh(y)*u`, `u^2`, `u[filter 20 s]`, `1`
    /// (outputs are scaled before the tanh, inputs before entering).
    fn term_names(&self, outputs: &[String], inputs: &[String]) -> Vec<String> {
        let (ny, nu) = (outputs.len(), inputs.len());
        let signal = |i: usize| -> String {
            if i < ny {
                format!("tanh({})", outputs[i])
            } else if i - ny < nu {
                inputs[i - ny].clone()
            } else if i - ny < nu * (1 + self.filters_s.len()) {
                let q = (i - ny) / nu - 1;
                format!("{}[filter {} s]", inputs[(i - ny) % nu], self.filters_s[q])
            } else {
                "1".into()
            }
        };
        let terms = &self.ident.net.terms;
        (0..terms.len())
            .map(|k| {
                terms
                    .factors(k)
                    .iter()
                    .map(|[i, e]| {
                        if *e == 1 {
                            signal(*i)
                        } else {
                            format!("{}^{e}", signal(*i))
                        }
                    })
                    .collect::<Vec<_>>()
                    .join("*")
            })
            .collect()
    }

    /// Number of terms per neuron.
    fn n_terms(&self) -> usize {
        self.ident.net.n_terms()
    }

    /// The scaling.
    fn scaling(&self) -> &Scaling {
        &self.scaling
    }

    fn snapshot(&self) -> Box<dyn EngineState> {
        Box::new(ContinuousSnapshot {
            state: self.state.clone(),
            t_last: self.status.t_last,
            y_last: self.y_last.clone(),
            u_last: self.u_last.clone(),
        })
    }

    fn restore(&mut self, snap: &dyn EngineState) {
        if let Some(s) = snap.as_any().downcast_ref::<ContinuousSnapshot>() {
            self.state.copy_from_slice(&s.state);
            self.status.t_last = s.t_last;
            self.y_last.copy_from_slice(&s.y_last);
            self.u_last.copy_from_slice(&s.u_last);
        }
    }

    fn update(&mut self, t: f64, u: &[f64], y: &[f64]) -> Result<&[f64]> {
        self.sample(t, u, y)
    }

    fn estimate(&self) -> &[f64] {
        &self.y_hat
    }

    fn set_y_bounds(&mut self, b: Vec<[f64; 2]>) {
        self.scaling.y_bounds = Some(b);
    }

    fn box_clone(&self) -> Box<dyn OnlineEngine> {
        Box::new(self.clone())
    }
}
