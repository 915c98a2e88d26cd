//! What the run loop needs from the system it integrates, for any plant: the plant
//! inside it, and the model's estimates when an identifier runs along (`Integrated`).

use crate::ident::{FrozenPair, Identified, MAX_SIGNALS};
use crate::plant::{Plant, SignalRef};
use rhonn_ode::{Direction, EventAction, State, System};

/// What the run loop needs from the integrated system: the plant inside it (its states
/// first in the system's state), and the model's estimates when an identifier runs along.
pub trait Integrated: System {
    /// The plant's type.
    type Plant: Plant;
    /// The plant.
    fn plant(&self) -> &Self::Plant;
    /// The plant, to hold its inputs.
    fn plant_mut(&mut self) -> &mut Self::Plant;
    /// The estimates in state `x` of model `slot` (0: the identifier, or the
    /// series-parallel copy of a frozen model; 1: the parallel copy), written at the
    /// place of the plant state they estimate in `out` (at least the plant's state
    /// count long); the others are set to None, as are all when no such model runs.
    fn hats(&self, _x: &[f64], _slot: usize, out: &mut [Option<f64>]) {
        out.fill(None);
    }
    /// Where the estimate of plant state `state` by model `slot` is a state component
    /// itself (the filtered-error laws' x_hat, a frozen model's), its index: the
    /// summaries then interpolate that component alone.
    fn hat_index(&self, _slot: usize, _state: usize) -> Option<usize> {
        None
    }
}

/// A plant integrated alone, with no identifier: every `System` call goes to the
/// plant unchanged (so a run of `Alone(p)` is the run of `p`, bit for bit).
#[derive(Debug, Clone)]
pub struct Alone<P>(pub P);

impl<P: Plant> System for Alone<P> {
    type State = P::State;
    #[inline(always)]
    fn dim(&self) -> usize {
        self.0.dim()
    }
    #[inline(always)]
    fn rhs(&self, t: f64, x: &[f64], dx: &mut [f64]) {
        self.0.rhs(t, x, dx)
    }
    fn n_events(&self) -> usize {
        self.0.n_events()
    }
    #[inline(always)]
    fn events(&self, t: f64, x: &[f64], g: &mut [f64]) {
        self.0.events(t, x, g)
    }
    fn event_direction(&self, j: usize) -> Direction {
        self.0.event_direction(j)
    }
    fn on_event(&mut self, j: usize, t: f64, x: &mut [f64]) -> EventAction {
        self.0.on_event(j, t, x)
    }
    fn update_modes(&mut self, t: f64, x: &[f64]) {
        self.0.update_modes(t, x)
    }
    fn next_breakpoint(&self, t: f64) -> f64 {
        self.0.next_breakpoint(t)
    }
    #[inline(always)]
    fn bounds(&self, i: usize) -> (f64, f64) {
        self.0.bounds(i)
    }
}

impl<P: Plant> Integrated for Alone<P> {
    type Plant = P;
    fn plant(&self) -> &P {
        &self.0
    }
    fn plant_mut(&mut self) -> &mut P {
        &mut self.0
    }
}

impl<P: Plant, St: State> Integrated for Identified<P, St> {
    type Plant = P;
    fn plant(&self) -> &P {
        &self.plant
    }
    fn plant_mut(&mut self) -> &mut P {
        &mut self.plant
    }
    fn hats(&self, x: &[f64], slot: usize, out: &mut [Option<f64>]) {
        out.fill(None);
        if slot != 0 {
            return;
        }
        let mut xh = [0.0; MAX_SIGNALS];
        let n = self.states.len();
        self.ident.outputs(&x[self.plant.dim()..], &mut xh[..n]);
        by_plant_state(&self.states, |k| xh[k], out);
    }
    fn hat_index(&self, slot: usize, state: usize) -> Option<usize> {
        if slot != 0 || self.ident.law.structure != crate::law::Structure::FilteredError {
            return None;
        }
        let k = neuron_of(&self.states, state)?;
        Some(self.plant.dim() + k * self.ident.block())
    }
}

impl<P: Plant, St: State> Integrated for FrozenPair<P, St> {
    type Plant = P;
    fn plant(&self) -> &P {
        &self.plant
    }
    fn plant_mut(&mut self) -> &mut P {
        &mut self.plant
    }
    fn hats(&self, x: &[f64], slot: usize, out: &mut [Option<f64>]) {
        out.fill(None);
        if slot > 1 {
            return;
        }
        let off = self.plant.dim() + slot * self.states.len();
        by_plant_state(&self.states, |k| x[off + k], out);
    }
    fn hat_index(&self, slot: usize, state: usize) -> Option<usize> {
        if slot > 1 {
            return None;
        }
        let k = neuron_of(&self.states, state)?;
        Some(self.plant.dim() + slot * self.states.len() + k)
    }
}

/// The neuron that identifies plant state `state`, if any.
fn neuron_of(states: &[SignalRef], state: usize) -> Option<usize> {
    states.iter().position(|s| *s == SignalRef::State(state))
}

/// Neuron k's `value(k)` written at the place of the plant state it identifies in `out`.
fn by_plant_state(states: &[SignalRef], value: impl Fn(usize) -> f64, out: &mut [Option<f64>]) {
    for (k, s) in states.iter().enumerate() {
        if let SignalRef::State(i) = s {
            if let Some(o) = out.get_mut(*i) {
                *o = Some(value(k));
            }
        }
    }
}
