//! The pump's equations as a [`rhonn_ode::System`].

use super::super::Input;
use super::PumpParams;
use crate::signal::Affine;
use rhonn_ode::{Direction, System};

/// Index of the line pressure P_l \[Pa\] in the state.
pub const P_LINE: usize = 0;
/// Index of the pump stroke x \[m\] in the state.
pub const STROKE: usize = 1;
/// Index of the current the solenoid actually carries \[A\] in the state: the commanded
/// current through a first-order lag of `solenoid_lag` (unmodeled dynamics, pump-model.md
/// section 3); without a lag it stays unused and the commanded current acts directly.
pub const CURRENT_EFF: usize = 2;
/// Number of plant states.
pub const PLANT_DIM: usize = 3;
/// Number of the pump's event functions.
pub const PUMP_EVENTS: usize = 2;

/// The pump and line (states `[P_l, x, i]`, SI) driven by a solenoid current \[A\] and a
/// demanded flow \[m^3/s\].
///
/// Modes, constant within a step: the segments of the two inputs, the pilot valve's
/// branch (`s >= 0` or `s < 0`) and the sign of the pilot pressure drop. Event 0 is
/// `s = 0` (the valve switches: the pressure-drop formula and the line's draw change),
/// event 1 is `dPa = 0` (the pilot flow reverses; `sqrt|dPa|` has a vertical tangent
/// there). Both states are limited integrators: `0 <= P_l <= P_max`, `0 <= x <= x_max`.
#[derive(Debug, Clone)]
pub struct PumpSystem {
    /// Parameters (SI).
    pub params: PumpParams,
    /// Solenoid current \[A\], clipped to `[0, i_max]` when evaluated.
    pub current: Input,
    /// Demanded flow \[m^3/s\].
    pub demand: Input,
    seg_i: usize,
    seg_q: usize,
    /// The inputs' formulas in their segments (None: a multisine, evaluated in full),
    /// set with the segments.
    lin_i: Option<Affine>,
    lin_q: Option<Affine>,
    /// The inputs' next breakpoint after `bp_from`, found when the modes were chosen
    /// there: the answer for every time in `[bp_from, bp_next)`.
    bp_from: f64,
    bp_next: f64,
    branch_neg: bool,
    dpa_pos: bool,
}

pub use rhonn_core::pump::Pilot;

impl PumpSystem {
    /// A pump with the given inputs.
    pub fn new(params: PumpParams, current: Input, demand: Input) -> Self {
        let (lin_i, lin_q) = (current.affine_in(0), demand.affine_in(0));
        PumpSystem {
            params,
            current,
            demand,
            seg_i: 0,
            seg_q: 0,
            lin_i,
            lin_q,
            bp_from: f64::INFINITY,
            bp_next: f64::INFINITY,
            branch_neg: false,
            dpa_pos: true,
        }
    }

    /// Solenoid current at `t` in the current modes \[A\] (clipped).
    #[inline]
    pub fn current_at(&self, t: f64) -> f64 {
        match &self.lin_i {
            Some(a) => a.at(t),
            None => self.current.eval_in(self.seg_i, t),
        }
        .clamp(0.0, self.params.i_max)
    }

    /// Demanded flow at `t` in the current modes \[m^3/s\].
    #[inline]
    pub fn demand_at(&self, t: f64) -> f64 {
        match &self.lin_q {
            Some(a) => a.at(t),
            None => self.demand.eval_in(self.seg_q, t),
        }
    }

    /// First breakpoint of either input strictly after `t`.
    fn inputs_next_breakpoint(&self, t: f64) -> f64 {
        self.current
            .next_breakpoint(t)
            .min(self.demand.next_breakpoint(t))
    }

    /// Set the held current (a sampled controller's output) \[A\].
    pub fn set_current(&mut self, i: f64) {
        self.current = Input::Held(i);
        self.lin_i = self.current.affine_in(self.seg_i);
        self.bp_from = f64::INFINITY;
    }

    /// Hold the demanded flow at `q` \[m^3/s\] from now on.
    pub fn set_demand(&mut self, q: f64) {
        self.demand = Input::Held(q);
        self.lin_q = self.demand.affine_in(self.seg_q);
        self.bp_from = f64::INFINITY;
    }

    /// The pilot valve at `(P_l, x)` and current `i`, on the branch `neg` (s < 0)
    /// (`rhonn_core::pump`: the same equations on a microcontroller).
    #[inline(always)]
    pub fn pilot(&self, p: f64, x: f64, i: f64, neg: bool) -> Pilot {
        self.params.equations().pilot(p, x, i, neg)
    }

    /// Derivatives `(dP_l/dt, dx/dt)` at `(P_l, x)` with inputs `i`, `q` on branch `neg`.
    #[inline(always)]
    pub fn derivative(&self, p: f64, x: f64, i: f64, q: f64, neg: bool) -> (f64, f64) {
        self.params.equations().derivative(p, x, i, q, neg)
    }

    /// The current acting on the pilot valve in state `x` at `t` \[A\]: the lagged
    /// current when the solenoid has a lag, the commanded one otherwise.
    #[inline(always)]
    pub fn acting_current(&self, t: f64, x: &[f64]) -> f64 {
        if self.params.solenoid_lag > 0.0 {
            x[CURRENT_EFF].clamp(0.0, self.params.i_max)
        } else {
            self.current_at(t)
        }
    }

    /// Whether the pilot valve is on its `s < 0` branch.
    pub fn branch_negative(&self) -> bool {
        self.branch_neg
    }
}

impl System for PumpSystem {
    type State = [f64; PLANT_DIM];

    fn dim(&self) -> usize {
        PLANT_DIM
    }

    #[inline]
    fn rhs(&self, t: f64, x: &[f64], dx: &mut [f64]) {
        let i = self.acting_current(t, x);
        let q = self.demand_at(t);
        let (dp, ds) = self.derivative(x[P_LINE], x[STROKE], i, q, self.branch_neg);
        dx[P_LINE] = dp;
        dx[STROKE] = ds;
        dx[CURRENT_EFF] = if self.params.solenoid_lag > 0.0 {
            (self.current_at(t) - x[CURRENT_EFF]) / self.params.solenoid_lag
        } else {
            0.0
        };
    }

    fn n_events(&self) -> usize {
        PUMP_EVENTS
    }

    #[inline]
    fn events(&self, t: f64, x: &[f64], g: &mut [f64]) {
        let pil = self.pilot(x[P_LINE], x[STROKE], self.acting_current(t, x), self.branch_neg);
        g[0] = pil.s;
        g[1] = pil.dpa;
    }

    fn event_direction(&self, j: usize) -> Direction {
        let positive = if j == 0 { !self.branch_neg } else { self.dpa_pos };
        if positive {
            Direction::Falling
        } else {
            Direction::Rising
        }
    }

    fn update_modes(&mut self, t: f64, x: &[f64]) {
        self.seg_i = self.current.segment(t);
        self.seg_q = self.demand.segment(t);
        self.lin_i = self.current.affine_in(self.seg_i);
        self.lin_q = self.demand.affine_in(self.seg_q);
        self.bp_from = t;
        self.bp_next = self.inputs_next_breakpoint(t);
        let i = self.acting_current(t, x);
        let s = self.pilot(x[P_LINE], x[STROKE], i, self.branch_neg).s;
        if s > 0.0 {
            self.branch_neg = false;
        } else if s < 0.0 {
            self.branch_neg = true;
        }
        self.dpa_pos = self.pilot(x[P_LINE], x[STROKE], i, self.branch_neg).dpa >= 0.0;
    }

    fn next_breakpoint(&self, t: f64) -> f64 {
        // Every breakpoint after t >= bp_from is one after bp_from, so none comes before
        // bp_next: the cached answer is exact (a lookup per step fewer).
        if t >= self.bp_from && t < self.bp_next {
            self.bp_next
        } else {
            self.inputs_next_breakpoint(t)
        }
    }

    fn bounds(&self, i: usize) -> (f64, f64) {
        match i {
            P_LINE => (0.0, self.params.p_max),
            STROKE => (0.0, self.params.x_max),
            _ => (f64::NEG_INFINITY, f64::INFINITY),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::signal::{PiecewiseLinear, Signal};

    fn signal(points: &[(f64, f64)]) -> Input {
        Input::Signal(Signal::piecewise(
            PiecewiseLinear::new(points.to_vec()),
            f64::NEG_INFINITY,
            f64::INFINITY,
        ))
    }

    #[test]
    fn cached_breakpoints_and_segment_formulas_answer_as_the_signals_do() {
        let current = signal(&[(0.0, 0.1), (1.0, 0.5), (1.0, 0.3), (2.5, 0.6)]);
        let demand = signal(&[(0.5, 0.0), (1.75, 1e-4), (3.0, 0.0)]);
        let mut pump = PumpSystem::new(PumpParams::default(), current.clone(), demand.clone());
        let x = [2e6, 1e-3, 0.0];
        let direct = |t: f64| current.next_breakpoint(t).min(demand.next_breakpoint(t));
        let mut checked = 0;
        // Modes chosen at t0 (as the solver does at every restart), then asked at later
        // times of the same interval and beyond it.
        for k in 0..40 {
            let t0 = k as f64 * 0.1;
            pump.update_modes(t0, &x);
            for dt in [0.0, 0.01, 0.049, 0.2, 0.9] {
                let t = t0 + dt;
                assert_eq!(pump.next_breakpoint(t), direct(t), "t0 {t0} t {t}");
                checked += 1;
            }
            let t = t0 + 0.03;
            let (si, sq) = (current.segment(t0), demand.segment(t0));
            assert_eq!(
                pump.current_at(t),
                current.eval_in(si, t).clamp(0.0, pump.params.i_max)
            );
            assert_eq!(pump.demand_at(t), demand.eval_in(sq, t));
        }
        // A held current has no breakpoints of its own from then on.
        pump.update_modes(0.2, &x);
        pump.set_current(0.4);
        assert_eq!(pump.next_breakpoint(0.3), demand.next_breakpoint(0.3));
        assert_eq!(pump.current_at(0.3), 0.4);
        assert_eq!(checked, 200);
    }
}
