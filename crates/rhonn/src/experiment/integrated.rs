//! What the pump's run loop needs from the system it integrates: the pump inside it, and
//! the model's estimates when an identifier runs along (`Integrated`).

use crate::ident::{FrozenPair, Identified};
use crate::plant::{PumpSystem, SignalRef, PLANT_DIM, P_LINE, STROKE};
use rhonn_ode::{State, System};

/// What the run loop needs from the integrated system: the pump inside it, and the
/// model's estimates when an identifier runs along.
pub trait Integrated: System {
    /// The pump.
    fn pump(&self) -> &PumpSystem;
    /// The pump, to set the held current.
    fn pump_mut(&mut self) -> &mut PumpSystem;
    /// The estimates of `[p_line, stroke]` in state `x` of model `slot` (0: the
    /// identifier, or the series-parallel copy of a frozen model; 1: the parallel copy),
    /// None where a state is not identified, or no such model runs.
    fn hats(&self, _x: &[f64], _slot: usize) -> [Option<f64>; 2] {
        [None, None]
    }
    /// Where the estimates of `[p_line, stroke]` of model `slot` are state components
    /// themselves (the filtered-error laws' x_hat, a frozen model's), their indices: the
    /// summaries then interpolate those components alone.
    fn hat_indices(&self, _slot: usize) -> [Option<usize>; 2] {
        [None, None]
    }
}

impl Integrated for PumpSystem {
    fn pump(&self) -> &PumpSystem {
        self
    }
    fn pump_mut(&mut self) -> &mut PumpSystem {
        self
    }
}

impl<St: State> Integrated for Identified<PumpSystem, St> {
    fn pump(&self) -> &PumpSystem {
        &self.plant
    }
    fn pump_mut(&mut self) -> &mut PumpSystem {
        &mut self.plant
    }
    fn hats(&self, x: &[f64], slot: usize) -> [Option<f64>; 2] {
        if slot != 0 {
            return [None, None];
        }
        let mut xh = [0.0; 2];
        let n = self.states.len();
        self.ident.outputs(&x[PLANT_DIM..], &mut xh[..n]);
        by_plant_state(&self.states, |k| xh[k])
    }
    fn hat_indices(&self, slot: usize) -> [Option<usize>; 2] {
        if slot != 0 || self.ident.law.structure != crate::law::Structure::FilteredError {
            return [None, None];
        }
        let b = self.ident.block();
        by_plant_state(&self.states, |k| PLANT_DIM + k * b)
    }
}

impl<St: State> Integrated for FrozenPair<PumpSystem, St> {
    fn pump(&self) -> &PumpSystem {
        &self.plant
    }
    fn pump_mut(&mut self) -> &mut PumpSystem {
        &mut self.plant
    }
    fn hats(&self, x: &[f64], slot: usize) -> [Option<f64>; 2] {
        self.hat_indices(slot).map(|i| i.map(|i| x[i]))
    }
    fn hat_indices(&self, slot: usize) -> [Option<usize>; 2] {
        if slot > 1 {
            return [None, None];
        }
        let off = PLANT_DIM + slot * self.states.len();
        by_plant_state(&self.states, |k| off + k)
    }
}

/// `[p_line, stroke]` from per-neuron values: neuron k's `value(k)` at the place of the
/// plant state it identifies, None for a plant state no neuron identifies.
pub(super) fn by_plant_state<T>(states: &[SignalRef], value: impl Fn(usize) -> T) -> [Option<T>; 2] {
    let mut out = [None, None];
    for (k, s) in states.iter().enumerate() {
        match s {
            SignalRef::State(P_LINE) => out[P_LINE] = Some(value(k)),
            SignalRef::State(STROKE) => out[STROKE] = Some(value(k)),
            _ => {}
        }
    }
    out
}
