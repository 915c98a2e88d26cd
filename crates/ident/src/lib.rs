//! rhonn's online identification (`rhonn::ident`). The RHONN identifier: one definition of the network and its learning law, run two
//! ways — integrated together with the plant by the event-locating solver
//! ([`Identified`], as the thesis's Simulink model does), or one sample at a time
//! from measured signals ([`DiscreteIdentifier`], for online use on a controller).
//!
//! Modes of running (named plainly):
//! - *training*: the weights adapt, z from the measured states (series-parallel);
//! - *series-parallel validation*: weights frozen, z from the measured states (one-step
//!   tracking);
//! - *parallel validation* (free run): weights frozen, z from the model's own states
//!   (the model runs on its own).

#![deny(missing_docs)]
// `!(a < b)` is deliberate throughout: it is also true when either side is NaN.
#![allow(clippy::neg_cmp_op_on_partial_ord)]
// Numerical kernels index several slices in lockstep; index loops read best there.
#![allow(clippy::needless_range_loop)]

// The foundations, under the names this crate's modules use (`crate::plant`, ...).
pub(crate) use rhonn_base::{data, error, law, metrics, models, net, plant, Error};

use crate::law::sigma::Zone;
use crate::law::{Law, LearningLaw, Robust, Rule, Structure};
use crate::net::Network;
use rhonn_ode::Direction;

mod frozen;
pub mod guard;
mod identified;
pub use frozen::FrozenPair;
pub use identified::{Identified, MAX_SIGNALS};

/// How the identifier runs (the core's, [`rhonn_core::ident::Mode`]).
pub use rhonn_core::ident::Mode;

/// A network, its law and its mode; knows the layout of its states.
#[derive(Debug, Clone, PartialEq)]
pub struct Identifier {
    /// Structure.
    pub net: Network,
    /// Learning law.
    pub law: Law,
    /// Mode.
    pub mode: Mode,
    zones: Vec<Zone>,
    /// The gradient law's scalar gains, one per neuron, when every gain is one (the fast
    /// paths' case), read once here rather than matched in every evaluation.
    scalar_gains: Option<Vec<f64>>,
}

/// Work space of one identifier evaluation, allocated once per run (an owner that is
/// not shared between threads keeps it, e.g. in a `RefCell`), so that evaluations
/// neither allocate nor clear kilobytes of stack.
#[derive(Debug, Clone, Default)]
pub struct Scratch {
    xhat: Vec<f64>,
    y: Vec<f64>,
    z: Vec<f64>,
    q: Vec<f64>,
    r: Vec<f64>,
}

impl Scratch {
    /// The work space borrowed as `rhonn_core`'s identifier uses it.
    #[inline]
    pub fn work(&mut self) -> rhonn_core::ident::Work<'_, f64> {
        rhonn_core::ident::Work {
            xhat: &mut self.xhat,
            y: &mut self.y,
            z: &mut self.z,
            q: &mut self.q,
            r: &mut self.r,
        }
    }

    /// Work space for `ident`.
    pub fn for_identifier(ident: &Identifier) -> Self {
        let (ny, l) = (ident.net.n + ident.net.m, ident.net.n_terms());
        Scratch {
            xhat: vec![0.0; ident.net.n],
            y: vec![0.0; ny],
            z: vec![0.0; l],
            q: vec![0.0; l],
            r: vec![0.0; l],
        }
    }
}

pub(crate) use crate::law::dot;

/// An identifier's parts borrowed as `rhonn_core` evaluates them.
#[inline(always)]
fn view_of<'a>(net: &'a Network, law: &'a Law, mode: Mode) -> rhonn_core::ident::Ident<'a, f64, Rule> {
    rhonn_core::ident::Ident {
        net: net.view(),
        law: &law.rule,
        structure: law.structure,
        robust: law.robust,
        radius: &law.m,
        sigma: &law.sigma,
        mode,
    }
}

impl Identifier {
    /// An identifier in `mode`.
    pub fn new(net: Network, law: Law, mode: Mode) -> Self {
        let n = net.n;
        let scalar_gains = LearningLaw::scalar_gains(&law.rule);
        Identifier {
            net,
            law,
            mode,
            zones: vec![Zone::Inside; n],
            scalar_gains,
        }
    }

    /// The identifier borrowed as `rhonn_core` evaluates it (every evaluation below is
    /// the core's).
    #[inline(always)]
    pub fn view(&self) -> rhonn_core::ident::Ident<'_, f64, Rule> {
        view_of(&self.net, &self.law, self.mode)
    }

    /// The view and the zones, the latter to update.
    pub fn view_and_zones(&mut self) -> (rhonn_core::ident::Ident<'_, f64, Rule>, &mut [Zone]) {
        (view_of(&self.net, &self.law, self.mode), &mut self.zones)
    }

    /// States per neuron.
    pub fn block(&self) -> usize {
        self.view().block()
    }

    /// Number of identifier states.
    pub fn dim(&self) -> usize {
        self.view().dim()
    }

    /// Offset of neuron i's weights in its block (after x_i or zeta_i).
    fn w_off(&self) -> usize {
        self.view().w_off()
    }

    /// Initial identifier state: model states `xhat0` (filtered-error laws; the
    /// filtered-regressor laws start their filters at 0), weights `w0[i]` (or 0), and
    /// the law's own states (P_i(0) = p0_i I).
    pub fn initial_state(&self, xhat0: &[f64], w0: Option<&[Vec<f64>]>) -> Vec<f64> {
        let (n, l, b, wo) = (self.net.n, self.net.n_terms(), self.block(), self.w_off());
        let mut s = vec![0.0; self.dim()];
        for i in 0..n {
            let blk = &mut s[i * b..(i + 1) * b];
            if self.law.structure == Structure::FilteredError {
                blk[0] = xhat0[i];
            }
            if let Some(w) = w0 {
                blk[wo..wo + l].copy_from_slice(&w[i]);
            }
            self.law.rule.init(i, l, &mut blk[wo + l..]);
        }
        s
    }

    /// The model's estimates x_hat (one per neuron) from the identifier state.
    #[inline]
    pub fn outputs(&self, s: &[f64], xhat: &mut [f64]) {
        self.view().outputs(s, xhat)
    }

    /// The weights, one vector per neuron.
    pub fn weights(&self, s: &[f64]) -> Vec<Vec<f64>> {
        let (l, b, wo) = (self.net.n_terms(), self.block(), self.w_off());
        (0..self.net.n)
            .map(|i| s[i * b + wo..i * b + wo + l].to_vec())
            .collect()
    }

    /// Set the weights (e.g. those of the previous epoch).
    pub fn set_weights(&self, s: &mut [f64], w: &[Vec<f64>]) {
        let (l, b, wo) = (self.net.n_terms(), self.block(), self.w_off());
        for (i, wi) in w.iter().enumerate() {
            s[i * b + wo..i * b + wo + l].copy_from_slice(wi);
        }
    }

    /// Derivative of the identifier state `s` given the measured states `chi` and
    /// inputs `u` (no allocation).
    pub fn rhs(&self, chi: &[f64], u: &[f64], s: &[f64], ds: &mut [f64], sc: &mut Scratch) {
        if self.law.structure == Structure::FilteredError
            && (self.law.robust == Robust::None || self.zones.iter().all(|z| *z == Zone::Inside))
            && self.scalar_gains.is_some()
        {
            if let Some(idx) = self.net.terms.plain_indices() {
                // The thesis's sizes with their loop lengths known to the compiler.
                return match (self.net.n, idx.len()) {
                    (1, 1) if self.net.m <= 2 => self.rhs_plain_fixed::<1, 1>(idx, chi, u, s, ds),
                    (1, 2) if self.net.m <= 2 => self.rhs_plain_fixed::<1, 2>(idx, chi, u, s, ds),
                    (2, 2) if self.net.m <= 2 => self.rhs_plain_fixed::<2, 2>(idx, chi, u, s, ds),
                    (2, 3) if self.net.m <= 2 => self.rhs_plain_fixed::<2, 3>(idx, chi, u, s, ds),
                    (2, 4) if self.net.m <= 2 => self.rhs_plain_fixed::<2, 4>(idx, chi, u, s, ds),
                    _ => self.rhs_plain(idx, chi, u, s, ds, &mut sc.y),
                };
            }
        }
        self.rhs_general(chi, u, s, ds, sc, false);
    }

    /// [`Identifier::rhs`] by its general path; with `same_regressor`, the regressor z
    /// of the previous general evaluation is used again (valid when z did not change:
    /// z from held measurements and held inputs, not in a free run), which saves its
    /// sigmoids and products at every stage of a step.
    pub fn rhs_general(
        &self,
        chi: &[f64],
        u: &[f64],
        s: &[f64],
        ds: &mut [f64],
        sc: &mut Scratch,
        same_regressor: bool,
    ) {
        self.view()
            .rhs_general(chi, u, s, ds, &self.zones, &mut sc.work(), same_regressor)
    }

    /// [`Identifier::rhs`] for the common case, the thesis's: a filtered-error law with
    /// scalar gains, every weight inside its ball (or no robust term), and terms that are
    /// single sigmoids or inputs (z_k = y_{idx_k}). Same arithmetic in the same order,
    /// without the general path's matrix products, zone logic and term products:
    /// identical results, measured 1.18 -> 1.0 ms per thesis-ch5 run.
    #[inline]
    fn rhs_plain(&self, idx: &[usize], chi: &[f64], u: &[f64], s: &[f64], ds: &mut [f64], y: &mut [f64]) {
        let (n, m, l) = (self.net.n, self.net.m, idx.len());
        let b = 1 + l;
        let parallel = self.mode == Mode::Parallel;
        let y = &mut y[..n + m];
        for i in 0..n {
            let src = if parallel { s[i * b] } else { chi[i] };
            y[i] = self.net.sigmoid.eval(self.net.scaled_state(i, src));
        }
        for j in 0..m {
            y[n + j] = u[j] / self.net.input_scale[j];
        }
        let train = self.mode == Mode::Train;
        for i in 0..n {
            let blk = &s[i * b..(i + 1) * b];
            let dblk = &mut ds[i * b..(i + 1) * b];
            let xh = blk[0];
            let w = &blk[1..];
            let mut acc = 0.0;
            for k in 0..l {
                acc += w[k] * y[idx[k]];
            }
            dblk[0] = -self.net.a[i] * xh + acc;
            let dw = &mut dblk[1..];
            // gradient::descend's arithmetic, on z_k = y[idx_k]
            if let (true, Some(g)) = (train, self.scalar_gains.as_ref().map(|g| g[i])) {
                let e = xh - chi[i];
                for k in 0..l {
                    dw[k] = -(g * y[idx[k]] * e);
                }
            } else {
                dw.iter_mut().for_each(|v| *v = 0.0);
            }
        }
    }

    /// [`Identifier::rhs_plain`] for `N` neurons and `L` terms known at compile time
    /// (at most 2 inputs): the same arithmetic in the same order, so the same results;
    /// the loops unroll and lose their bounds checks (thesis-ch5's identifier, N = L =
    /// 2: 330 -> 150 instructions per evaluation under callgrind).
    #[inline(always)]
    fn rhs_plain_fixed<const N: usize, const L: usize>(
        &self,
        idx: &[usize],
        chi: &[f64],
        u: &[f64],
        s: &[f64],
        ds: &mut [f64],
    ) {
        let m = self.net.m;
        let idx: &[usize; L] = idx.try_into().expect("L terms");
        let (s, ds) = (&s[..N * (1 + L)], &mut ds[..N * (1 + L)]);
        let mut y = [0.0; 4];
        let parallel = self.mode == Mode::Parallel;
        for i in 0..N {
            let src = if parallel { s[i * (1 + L)] } else { chi[i] };
            y[i] = self.net.sigmoid.eval(self.net.scaled_state(i, src));
        }
        for j in 0..m {
            y[N + j] = u[j] / self.net.input_scale[j];
        }
        let train = self.mode == Mode::Train;
        for i in 0..N {
            let blk = &s[i * (1 + L)..(i + 1) * (1 + L)];
            let dblk = &mut ds[i * (1 + L)..(i + 1) * (1 + L)];
            let xh = blk[0];
            let mut acc = 0.0;
            for k in 0..L {
                acc += blk[1 + k] * y[idx[k]];
            }
            dblk[0] = -self.net.a[i] * xh + acc;
            // gradient::descend's arithmetic, on z_k = y[idx_k]
            if let (true, Some(g)) = (train, self.scalar_gains.as_ref().map(|g| g[i])) {
                let e = xh - chi[i];
                for k in 0..L {
                    dblk[1 + k] = -(g * y[idx[k]] * e);
                }
            } else {
                dblk[1..].iter_mut().for_each(|v| *v = 0.0);
            }
        }
    }

    /// Event functions: two per neuron for the robust laws in training (|w|^2 - M^2,
    /// or on the sphere the two conditions of the smooth law), none otherwise.
    pub fn n_events(&self) -> usize {
        if self.law.robust != Robust::None && self.mode == Mode::Train {
            2 * self.net.n
        } else {
            0
        }
    }

    /// `w^T Gamma z e` and `w^T Gamma w` for neuron i.
    fn robust_terms(&self, i: usize, chi: &[f64], u: &[f64], s: &[f64], sc: &mut Scratch) -> (f64, f64) {
        self.view().robust_terms(i, chi, u, s, &mut sc.work())
    }

    fn norm2(&self, i: usize, s: &[f64]) -> f64 {
        self.view().norm2(i, s)
    }

    /// Evaluate the event functions.
    pub fn events(&self, chi: &[f64], u: &[f64], s: &[f64], g: &mut [f64], sc: &mut Scratch) {
        for i in 0..g.len() / 2 {
            let m2 = self.law.m[i] * self.law.m[i];
            match self.zones[i] {
                Zone::Sphere => {
                    let (g1, wgw) = self.robust_terms(i, chi, u, s, sc);
                    g[2 * i] = g1;
                    g[2 * i + 1] = g1 + self.law.sigma[i] * wgw;
                }
                _ => {
                    g[2 * i] = self.norm2(i, s) - m2;
                    g[2 * i + 1] = 1.0;
                }
            }
        }
    }

    /// Direction of event j.
    pub fn event_direction(&self, j: usize) -> Direction {
        match (self.zones[j / 2], j % 2) {
            (Zone::Inside, _) => Direction::Rising,
            (Zone::Outside, _) => Direction::Falling,
            (Zone::Sphere, 0) => Direction::Rising,
            (Zone::Sphere, _) => Direction::Falling,
        }
    }

    /// At an event of the smooth law reaching the sphere, put w exactly on it.
    pub fn on_event(&mut self, j: usize, s: &mut [f64]) {
        let i = j / 2;
        if self.law.robust != Robust::None && self.zones[i] != Zone::Sphere {
            let r = self.norm2(i, s).sqrt();
            let m = self.law.m[i];
            if r > 0.0 && (r - m).abs() < 1e-3 * m {
                let (l, b, wo) = (self.net.n_terms(), self.block(), self.w_off());
                s[i * b + wo..i * b + wo + l].iter_mut().for_each(|v| *v *= m / r);
            }
        }
    }

    /// Choose each neuron's zone at the start of an interval.
    pub fn update_modes(&mut self, chi: &[f64], u: &[f64], s: &[f64], sc: &mut Scratch) {
        let (view, zones) = self.view_and_zones();
        view.update_zones(chi, u, s, zones, &mut sc.work());
    }
}

/// The identifier taking one sample every `period_s` from measured signals: the
/// identifier's ODE integrated over the period by classical RK4 with the measurements
/// held (zero-order hold). Buffers are allocated once; a step does not allocate.
#[derive(Debug, Clone)]
pub struct DiscreteIdentifier {
    /// The identifier.
    pub ident: Identifier,
    /// Sampling period \[s\].
    pub period_s: f64,
    state: Vec<f64>,
    k: [Vec<f64>; 4],
    tmp: Vec<f64>,
    scratch: Scratch,
}

impl DiscreteIdentifier {
    /// Start from `state` (see [`Identifier::initial_state`]).
    pub fn new(ident: Identifier, state: Vec<f64>, period_s: f64) -> Self {
        let d = ident.dim();
        let scratch = Scratch::for_identifier(&ident);
        DiscreteIdentifier {
            ident,
            period_s,
            state,
            k: std::array::from_fn(|_| vec![0.0; d]),
            tmp: vec![0.0; d],
            scratch,
        }
    }

    /// Take one sample of the identified states `chi` and inputs `u`.
    pub fn step(&mut self, chi: &[f64], u: &[f64]) {
        let h = self.period_s;
        self.ident.update_modes(chi, u, &self.state, &mut self.scratch);
        let d = self.state.len();
        let [k1, k2, k3, k4] = &mut self.k;
        self.ident.rhs(chi, u, &self.state, k1, &mut self.scratch);
        for j in 0..d {
            self.tmp[j] = self.state[j] + 0.5 * h * k1[j];
        }
        self.ident.rhs(chi, u, &self.tmp, k2, &mut self.scratch);
        for j in 0..d {
            self.tmp[j] = self.state[j] + 0.5 * h * k2[j];
        }
        self.ident.rhs(chi, u, &self.tmp, k3, &mut self.scratch);
        for j in 0..d {
            self.tmp[j] = self.state[j] + h * k3[j];
        }
        self.ident.rhs(chi, u, &self.tmp, k4, &mut self.scratch);
        for j in 0..d {
            self.state[j] += h / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j]);
        }
    }

    /// The model's current estimates.
    pub fn outputs(&self, xhat: &mut [f64]) {
        self.ident.outputs(&self.state, xhat);
    }

    /// The identifier state.
    pub fn state(&self) -> &[f64] {
        &self.state
    }
}

pub mod bank;
mod block_online;
mod cascade_online;
mod continuous;
mod engine;
mod lagged;
pub use lagged::{first_prediction, outputs_read_in_free_run};
mod online;
mod online_spec;
mod per_output;
mod recordings;
mod session;
pub mod shared_spec;
mod spec;
mod stream;
pub use online::{widened, InputHold, OnlineIdentifier, OnlineModel, OnlineSpec, Scaling, Snapshot};
pub use online_spec::{CascadeOnlineSpec, LagSpec, OnlineStructure};
pub use per_output::{OwnStructure, PerOutputSpec};
pub use recordings::{
    check_outputs_vary, identify_records, identify_records_scaled, predict_records, record_scaling,
    sample_time, OnlineFigures, OnlineRun, WarmUp, MAX_LISTED_WEIGHTS,
};
pub use session::{OnlineSession, SessionOptions};
pub use spec::{IdentSettings, IdentifierSpec, SigmoidSpec};
pub use stream::{Stream, StreamStep, StreamSummary};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::law::{GainSpec, LawSpec};
    use crate::net::{Sigmoid, Terms};

    /// An identifier with `n` neurons, `m` inputs and `l` single-factor terms.
    fn plain(n: usize, m: usize, l: usize, mode: Mode) -> Identifier {
        let lists: Vec<Vec<[usize; 2]>> = (0..l).map(|k| vec![[k % (n + m), 1]]).collect();
        let net = Network {
            n,
            m,
            sigmoid: Sigmoid::LOGISTIC,
            state_scale: (0..n).map(|i| 0.5 + i as f64).collect(),
            input_scale: (0..m).map(|j| 2.0 + j as f64).collect(),
            terms: Terms::from_lists(&lists, n + m, "terms").unwrap(),
            a: (0..n).map(|i| 3.0 + i as f64).collect(),
        };
        let law = LawSpec::FilteredError {
            gamma: (0..n).map(|i| GainSpec::Scalar(7.0 + i as f64)).collect(),
        }
        .check(n, l, "law")
        .unwrap();
        Identifier::new(net, law, mode)
    }

    #[test]
    fn the_fixed_size_fast_path_gives_the_general_fast_paths_results_bit_for_bit() {
        let mut checked = 0;
        for (n, l) in [(1, 1), (1, 2), (2, 2), (2, 3), (2, 4), (2, 5)] {
            for m in 0..=2 {
                for mode in [Mode::Train, Mode::SeriesParallel, Mode::Parallel] {
                    let id = plain(n, m, l, mode);
                    let idx = id.net.terms.plain_indices().unwrap().to_vec();
                    let mut sc = Scratch::for_identifier(&id);
                    for k in 0..20 {
                        let v = |j: usize| ((k * 7 + j * 13) as f64 * 0.37).sin() * 2.0;
                        let chi: Vec<f64> = (0..n).map(v).collect();
                        let u: Vec<f64> = (0..m).map(|j| v(10 + j)).collect();
                        let s: Vec<f64> = (0..id.dim()).map(|j| v(20 + j)).collect();
                        let (mut fast, mut general) = (vec![0.0; id.dim()], vec![0.0; id.dim()]);
                        id.rhs(&chi, &u, &s, &mut fast, &mut sc);
                        let mut y = vec![0.0; n + m];
                        id.rhs_plain(&idx, &chi, &u, &s, &mut general, &mut y);
                        let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
                        assert_eq!(bits(&fast), bits(&general), "n {n} m {m} l {l} {mode:?}");
                        checked += 1;
                    }
                }
            }
        }
        assert_eq!(checked, 6 * 3 * 3 * 20);
    }
}
