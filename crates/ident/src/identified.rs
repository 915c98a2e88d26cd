//! A plant and an online identifier integrated together by the event-locating solver,
//! as the thesis's Simulink model does.

use super::{Identifier, Scratch};
use crate::error::{invalid, Result};
use crate::plant::{Plant, SignalRef};
use rhonn_ode::{Direction, EventAction, State, System};
use std::cell::RefCell;

/// Most identified states, and most network inputs, a plant-coupled identifier reads: the
/// signals are gathered on the stack in every right-hand side call, so the bound is small.
pub const MAX_SIGNALS: usize = 4;

/// A plant and an identifier integrated together: state `[plant..., identifier...]`,
/// stored as `St` (a `Vec`, or an array when the size is known).
#[derive(Debug, Clone)]
pub struct Identified<P, St = Vec<f64>> {
    /// The plant.
    pub plant: P,
    /// The identifier.
    pub ident: Identifier,
    /// Identified plant states (one per neuron).
    pub states: Vec<SignalRef>,
    /// External inputs of the network (plant inputs or states).
    pub inputs: Vec<SignalRef>,
    /// The plant's state count and event count.
    np: usize,
    ne: usize,
    scratch: RefCell<Scratch>,
    state: std::marker::PhantomData<St>,
}

impl<P: Plant, St> Identified<P, St> {
    /// `plant` with `ident` running along, identifying `states` with `inputs` (at most
    /// [`MAX_SIGNALS`] of each).
    pub fn new(plant: P, ident: Identifier, states: Vec<SignalRef>, inputs: Vec<SignalRef>) -> Result<Self> {
        check_signal_counts(&states, &inputs)?;
        let scratch = RefCell::new(Scratch::for_identifier(&ident));
        Ok(Identified {
            np: plant.dim(),
            ne: plant.n_events(),
            plant,
            ident,
            states,
            inputs,
            scratch,
            state: std::marker::PhantomData,
        })
    }

    #[inline(always)]
    fn signals(&self, t: f64, x: &[f64], chi: &mut [f64], u: &mut [f64]) {
        plant_signals(&self.plant, &self.states, &self.inputs, t, x, chi, u);
    }
}

impl<P: Plant, St: State> System for Identified<P, St> {
    type State = St;

    fn dim(&self) -> usize {
        self.np + self.ident.dim()
    }

    #[inline]
    fn rhs(&self, t: f64, x: &[f64], dx: &mut [f64]) {
        let np = self.np;
        self.plant.rhs(t, &x[..np], &mut dx[..np]);
        let (mut chi, mut u) = ([0.0; MAX_SIGNALS], [0.0; MAX_SIGNALS]);
        let (n, m) = (self.states.len(), self.inputs.len());
        self.signals(t, x, &mut chi[..n], &mut u[..m]);
        self.ident.rhs(
            &chi[..n],
            &u[..m],
            &x[self.np..],
            &mut dx[self.np..],
            &mut self.scratch.borrow_mut(),
        );
    }

    fn n_events(&self) -> usize {
        self.ne + self.ident.n_events()
    }

    fn events(&self, t: f64, x: &[f64], g: &mut [f64]) {
        let (np, ne) = (self.np, self.ne);
        self.plant.events(t, &x[..np], &mut g[..ne]);
        if g.len() > self.ne {
            let (mut chi, mut u) = ([0.0; MAX_SIGNALS], [0.0; MAX_SIGNALS]);
            let (n, m) = (self.states.len(), self.inputs.len());
            self.signals(t, x, &mut chi[..n], &mut u[..m]);
            self.ident.events(
                &chi[..n],
                &u[..m],
                &x[self.np..],
                &mut g[self.ne..],
                &mut self.scratch.borrow_mut(),
            );
        }
    }

    fn event_direction(&self, j: usize) -> Direction {
        if j < self.ne {
            self.plant.event_direction(j)
        } else {
            self.ident.event_direction(j - self.ne)
        }
    }

    fn on_event(&mut self, j: usize, _t: f64, x: &mut [f64]) -> EventAction {
        if j >= self.ne {
            self.ident.on_event(j - self.ne, &mut x[self.np..]);
        }
        EventAction::Continue
    }

    fn update_modes(&mut self, t: f64, x: &[f64]) {
        self.plant.update_modes(t, &x[..self.np]);
        let (mut chi, mut u) = ([0.0; MAX_SIGNALS], [0.0; MAX_SIGNALS]);
        let (n, m) = (self.states.len(), self.inputs.len());
        self.signals(t, x, &mut chi[..n], &mut u[..m]);
        self.ident
            .update_modes(&chi[..n], &u[..m], &x[self.np..], self.scratch.get_mut());
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

/// At most [`MAX_SIGNALS`] identified states and network inputs.
pub(crate) fn check_signal_counts(states: &[SignalRef], inputs: &[SignalRef]) -> Result<()> {
    for (field, n) in [
        ("identifier.states", states.len()),
        ("identifier.inputs", inputs.len()),
    ] {
        if n > MAX_SIGNALS {
            return Err(invalid(field, n, format!("at most {MAX_SIGNALS} signals")));
        }
    }
    Ok(())
}

/// The identified states `chi` and the inputs `u` of the network at `(t, x)`.
#[inline(always)]
pub(crate) fn plant_signals<P: Plant>(
    plant: &P,
    states: &[SignalRef],
    inputs: &[SignalRef],
    t: f64,
    x: &[f64],
    chi: &mut [f64],
    u: &mut [f64],
) {
    for (c, s) in chi.iter_mut().zip(states) {
        *c = s.value(plant, t, x);
    }
    for (c, s) in u.iter_mut().zip(inputs) {
        *c = s.value(plant, t, x);
    }
}
