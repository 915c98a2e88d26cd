//! A trained model run along a plant with frozen weights, twice: series-parallel and
//! parallel (free run).

use super::identified::{check_signal_counts, plant_signals, MAX_SIGNALS};
use super::{dot, Identifier};
use crate::error::Result;
use crate::law::Structure;
use crate::net::Network;
use crate::plant::{Plant, SignalRef};
use rhonn_ode::{Direction, EventAction, State, System};
use std::cell::RefCell;

/// A plant with a trained model run along twice, weights frozen: *series-parallel*
/// (z from the plant's states) and *parallel* (free run: z from the model's own
/// states). State `[plant..., x_hat series-parallel (n), x_hat parallel (n)]`.
///
/// Both validations ride on one integration of the plant, so they see the very same
/// plant trajectory, and the frozen weights are parameters rather than states: with
/// frozen weights every learning law's model is `dx_hat_i/dt = -a_i x_hat_i + w_i^T z`
/// (for the filtered-regressor laws x_hat = w^T zeta with `dzeta/dt = -a zeta + z`,
/// the same model in other coordinates, from x_hat(0) = 0 as their filters start at 0).
/// thesis-ch5: one run of 7 states instead of two, 31,057 -> 21,486 rhs evaluations.
#[derive(Debug, Clone)]
pub struct FrozenPair<P, St = Vec<f64>> {
    /// The plant.
    pub plant: P,
    /// The network.
    pub net: Network,
    /// Identified plant states (one per neuron).
    pub states: Vec<SignalRef>,
    /// External inputs of the network.
    pub inputs: Vec<SignalRef>,
    /// The frozen weights, neuron after neuron (`n_terms` each).
    weights: Vec<f64>,
    /// The plant's state count and event count.
    np: usize,
    ne: usize,
    /// Regressor scratch: y, then z.
    scratch: RefCell<(Vec<f64>, Vec<f64>)>,
    state: std::marker::PhantomData<St>,
}

impl<P: Plant, St> FrozenPair<P, St> {
    /// `ident`'s network with `weights` (one vector per neuron) frozen.
    pub fn new(
        plant: P,
        ident: &Identifier,
        weights: &[Vec<f64>],
        states: Vec<SignalRef>,
        inputs: Vec<SignalRef>,
    ) -> Result<Self> {
        check_signal_counts(&states, &inputs)?;
        let net = ident.net.clone();
        let ny = net.n + net.m;
        let l = net.n_terms();
        Ok(FrozenPair {
            np: plant.dim(),
            ne: plant.n_events(),
            plant,
            weights: weights.iter().flatten().copied().collect(),
            scratch: RefCell::new((vec![0.0; ny], vec![0.0; l])),
            net,
            states,
            inputs,
            state: std::marker::PhantomData,
        })
    }

    /// Initial model states of both copies: `xhat0` for the filtered-error laws, 0 for
    /// the filtered-regressor laws (their filters start at 0).
    pub fn initial_state(ident: &Identifier, xhat0: &[f64]) -> Vec<f64> {
        let n = ident.net.n;
        let x: Vec<f64> = if ident.law.structure == Structure::FilteredError {
            xhat0[..n].to_vec()
        } else {
            vec![0.0; n]
        };
        [x.clone(), x].concat()
    }

    /// Both copies' `dx_hat` for `N` neurons and `L` single-factor terms known at compile
    /// time (at most 2 inputs), in the arithmetic of [`FrozenPair::model`]: the loops
    /// unroll and lose their bounds checks. Returns true (it always handles the call).
    #[allow(clippy::too_many_arguments)] // the two copies' states and derivatives
    #[inline(always)]
    fn plain_fixed<const N: usize, const L: usize>(
        &self,
        idx: &[usize],
        chi: &[f64; MAX_SIGNALS],
        u: &[f64],
        sp: &[f64],
        par: &[f64],
        dsp: &mut [f64],
        dpar: &mut [f64],
    ) -> bool {
        let idx: &[usize; L] = idx.try_into().expect("L terms");
        let w: &[f64] = &self.weights[..N * L];
        let copy = |src: &[f64], xh: &[f64], dxh: &mut [f64]| {
            let mut y = [0.0; 4];
            for i in 0..N {
                y[i] = self.net.sigmoid.eval(self.net.scaled_state(i, src[i]));
            }
            for (j, &uj) in u.iter().enumerate() {
                y[N + j] = uj / self.net.input_scale[j];
            }
            for i in 0..N {
                let mut acc = 0.0;
                for k in 0..L {
                    acc += w[i * L + k] * y[idx[k]];
                }
                dxh[i] = -self.net.a[i] * xh[i] + acc;
            }
        };
        copy(&chi[..N], &sp[..N], &mut dsp[..N]);
        copy(&par[..N], &par[..N], &mut dpar[..N]);
        true
    }

    /// `dx_hat = -a x_hat + W z(src, u)`.
    #[inline(always)]
    fn model(&self, src: &[f64], u: &[f64], xh: &[f64], dxh: &mut [f64], y: &mut [f64], z: &mut [f64]) {
        let l = z.len();
        if let Some(idx) = self.net.terms.plain_indices() {
            // Single-factor terms (the thesis's): z_k = y_{idx_k}, without the general
            // product loop.
            let (n, m) = (src.len(), u.len());
            for i in 0..n {
                y[i] = self.net.sigmoid.eval(self.net.scaled_state(i, src[i]));
            }
            for j in 0..m {
                y[n + j] = u[j] / self.net.input_scale[j];
            }
            for (i, (d, &x)) in dxh.iter_mut().zip(xh).enumerate() {
                let w = &self.weights[i * l..(i + 1) * l];
                let mut acc = 0.0;
                for k in 0..l {
                    acc += w[k] * y[idx[k]];
                }
                *d = -self.net.a[i] * x + acc;
            }
            return;
        }
        self.net.regressor(src, u, y, z);
        for (i, (d, &x)) in dxh.iter_mut().zip(xh).enumerate() {
            *d = -self.net.a[i] * x + dot(&self.weights[i * l..(i + 1) * l], z);
        }
    }
}

impl<P: Plant, St: State> System for FrozenPair<P, St> {
    type State = St;

    fn dim(&self) -> usize {
        self.np + 2 * self.net.n
    }

    #[inline]
    fn rhs(&self, t: f64, x: &[f64], dx: &mut [f64]) {
        let np = self.np;
        self.plant.rhs(t, &x[..np], &mut dx[..np]);
        let (mut chi, mut u) = ([0.0; MAX_SIGNALS], [0.0; MAX_SIGNALS]);
        let (n, m) = (self.states.len(), self.inputs.len());
        plant_signals(
            &self.plant,
            &self.states,
            &self.inputs,
            t,
            x,
            &mut chi[..n],
            &mut u[..m],
        );
        let (sp, par) = x[self.np..].split_at(n);
        let (dsp, dpar) = dx[self.np..].split_at_mut(n);
        if let Some(idx) = self.net.terms.plain_indices() {
            // The thesis's sizes with their loop lengths known to the compiler.
            let done = match (n, idx.len()) {
                (1, 1) if m <= 2 => self.plain_fixed::<1, 1>(idx, &chi, &u[..m], sp, par, dsp, dpar),
                (1, 2) if m <= 2 => self.plain_fixed::<1, 2>(idx, &chi, &u[..m], sp, par, dsp, dpar),
                (2, 2) if m <= 2 => self.plain_fixed::<2, 2>(idx, &chi, &u[..m], sp, par, dsp, dpar),
                (2, 3) if m <= 2 => self.plain_fixed::<2, 3>(idx, &chi, &u[..m], sp, par, dsp, dpar),
                (2, 4) if m <= 2 => self.plain_fixed::<2, 4>(idx, &chi, &u[..m], sp, par, dsp, dpar),
                _ => false,
            };
            if done {
                return;
            }
        }
        let mut sc = self.scratch.borrow_mut();
        let (y, z) = &mut *sc;
        self.model(&chi[..n], &u[..m], sp, dsp, y, z);
        self.model(par, &u[..m], par, dpar, y, z);
    }

    fn n_events(&self) -> usize {
        self.ne
    }

    fn events(&self, t: f64, x: &[f64], g: &mut [f64]) {
        self.plant.events(t, &x[..self.np], g);
    }

    fn event_direction(&self, j: usize) -> Direction {
        self.plant.event_direction(j)
    }

    fn on_event(&mut self, _j: usize, _t: f64, _x: &mut [f64]) -> EventAction {
        EventAction::Continue
    }

    fn update_modes(&mut self, t: f64, x: &[f64]) {
        self.plant.update_modes(t, &x[..self.np]);
    }

    fn next_breakpoint(&self, t: f64) -> f64 {
        self.plant.next_breakpoint(t)
    }

    fn bounds(&self, i: usize) -> (f64, f64) {
        if i < self.np {
            self.plant.bounds(i)
        } else {
            (f64::NEG_INFINITY, f64::INFINITY)
        }
    }
}
