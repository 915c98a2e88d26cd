//! The tanks' equations as a [`rhonn_ode::System`].

use super::{TanksParams, G};
use crate::plant::Input;
use rhonn_ode::System;

/// Index of the upper tank's level h1 \[m\] in the state.
pub const H1: usize = 0;
/// Index of the lower tank's level h2 \[m\] in the state.
pub const H2: usize = 1;
/// Number of states.
pub const TANKS_DIM: usize = 2;

/// The two tanks driven by a pump voltage (see the module's equations).
///
/// Modes, constant within a step: the voltage's segment, and whether the upper tank is
/// full (overflowing), chosen when the step starts. The solver locates the instant the
/// upper tank fills (a bound of its limited integrator) and the instant its net inflow
/// turns negative (the release), so neither is stepped across.
#[derive(Debug, Clone)]
pub struct Tanks {
    /// Parameters (SI).
    pub params: TanksParams,
    /// Pump voltage \[V\], clipped to `[0, voltage_max]` when evaluated.
    pub voltage: Input,
    seg: usize,
    full: bool,
}

impl Tanks {
    /// The tanks driven by `voltage`.
    pub fn new(params: TanksParams, voltage: Input) -> Self {
        Tanks {
            params,
            voltage,
            seg: 0,
            full: false,
        }
    }

    /// The voltage at `t` in the current modes \[V\] (clipped).
    #[inline]
    pub fn voltage_at(&self, t: f64) -> f64 {
        self.voltage
            .eval_in(self.seg, t)
            .clamp(0.0, self.params.voltage_max)
    }

    /// Hold the voltage at `u` \[V\] from now on (a sampled controller's output).
    pub fn set_voltage(&mut self, u: f64) {
        self.voltage = Input::Held(u);
    }

    /// The flows `(q_in, q_12, q_out)` \[m^3/s\] at levels `h` and voltage `u`.
    #[inline]
    pub fn flows(&self, h: &[f64], u: f64) -> (f64, f64, f64) {
        let p = &self.params;
        let torricelli = |a: f64, h: f64| a * (2.0 * G * h.max(0.0)).sqrt();
        (
            p.pump_gain * u,
            torricelli(p.outlet_1, h[H1]),
            torricelli(p.outlet_2, h[H2]),
        )
    }
}

impl System for Tanks {
    type State = [f64; TANKS_DIM];

    fn dim(&self) -> usize {
        TANKS_DIM
    }

    #[inline]
    fn rhs(&self, t: f64, x: &[f64], dx: &mut [f64]) {
        let p = &self.params;
        let (q_in, q_12, q_out) = self.flows(x, self.voltage_at(t));
        let overflow = if self.full { (q_in - q_12).max(0.0) } else { 0.0 };
        dx[H1] = (q_in - q_12) / p.area_1;
        dx[H2] = (q_12 + p.overflow_share * overflow - q_out) / p.area_2;
    }

    fn update_modes(&mut self, t: f64, x: &[f64]) {
        self.seg = self.voltage.segment(t);
        self.full = x[H1] >= self.params.height_1;
    }

    fn next_breakpoint(&self, t: f64) -> f64 {
        self.voltage.next_breakpoint(t)
    }

    fn bounds(&self, i: usize) -> (f64, f64) {
        match i {
            H1 => (0.0, self.params.height_1),
            H2 => (0.0, self.params.height_2),
            _ => (f64::NEG_INFINITY, f64::INFINITY),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::signal::{PiecewiseLinear, Signal};
    use rhonn_ode::{Dopri5, Options};

    fn profile(points: &[(f64, f64)]) -> Signal {
        Signal::piecewise(
            PiecewiseLinear::new(points.to_vec()),
            f64::NEG_INFINITY,
            f64::INFINITY,
        )
    }

    fn simulate(tanks: Tanks, x0: [f64; 2], t_end: f64) -> (Dopri5<Tanks>, Vec<(f64, [f64; 2])>) {
        let mut s = Dopri5::new(tanks, 0.0, x0, Options::uniform(2, 1e-8, 1e-10)).unwrap();
        let mut samples = Vec::new();
        while s.t() < t_end {
            s.step(t_end).unwrap();
            samples.push((s.t(), [s.state()[H1], s.state()[H2]]));
        }
        (s, samples)
    }

    #[test]
    fn levels_settle_at_torricelli_equilibrium() {
        let p = TanksParams::default();
        let want = p.steady_levels(5.0);
        assert!((want[H1] - 0.1792).abs() < 1e-3, "{want:?}");
        let (s, _) = simulate(Tanks::new(p, Input::Held(5.0)), [0.02, 0.0], 2000.0);
        for i in [H1, H2] {
            assert!(
                (s.state()[i] - want[i]).abs() < 1e-6 * want[i].max(1.0),
                "{:?} vs {want:?}",
                s.state()
            );
        }
    }

    #[test]
    fn mass_balances_over_a_run_with_an_empty_start() {
        // Without overflow, the water pumped in equals the change of volume plus what
        // left through the lower outlet (integrated by the trapezoid rule on the steps).
        let p = TanksParams::default();
        let sig = profile(&[(0.0, 0.0), (10.0, 6.0), (200.0, 6.0), (210.0, 2.0), (400.0, 2.0)]);
        let tanks = Tanks::new(p.clone(), Input::Signal(sig));
        let (s, samples) = simulate(tanks.clone(), [0.0, 0.0], 400.0);
        let mut out = 0.0;
        let mut prev = (0.0, [0.0, 0.0]);
        for &(t, h) in &samples {
            let q = |h: [f64; 2]| tanks.flows(&h, 0.0).2;
            out += 0.5 * (q(prev.1) + q(h)) * (t - prev.0);
            prev = (t, h);
        }
        // Pumped in: integral of k_p u over the profile (trapezoids are exact on it).
        let volt_s = 0.5 * 6.0 * 10.0 + 6.0 * 190.0 + 0.5 * (6.0 + 2.0) * 10.0 + 2.0 * 190.0;
        let pumped = p.pump_gain * volt_s;
        let stored = p.area_1 * s.state()[H1] + p.area_2 * s.state()[H2];
        assert!(s.state()[H1] < p.height_1, "no overflow in this test");
        assert!(
            (pumped - stored - out).abs() < 1e-3 * pumped,
            "{pumped} {stored} {out}"
        );
    }

    #[test]
    fn a_full_upper_tank_holds_its_height_and_passes_its_share_of_the_overflow() {
        // A wider lower outlet, so that the lower tank does not fill too.
        let p = TanksParams {
            outlet_2: 50e-6,
            ..TanksParams::default()
        };
        let u = 9.0;
        let (s, samples) = simulate(Tanks::new(p.clone(), Input::Held(u)), [0.29, 0.1], 1500.0);
        assert!(samples.iter().all(|(_, h)| h[H1] <= p.height_1));
        assert_eq!(s.state()[H1], p.height_1, "held at the top");
        // Lower tank in equilibrium with q_12 at the top plus the share of the excess.
        let q_in = p.pump_gain * u;
        let q_12 = p.outlet_1 * (2.0 * G * p.height_1).sqrt();
        let q_2 = q_12 + p.overflow_share * (q_in - q_12);
        let h2 = (q_2 / (p.outlet_2 * (2.0 * G).sqrt())).powi(2);
        assert!(h2 < p.height_2);
        assert!((s.state()[H2] - h2).abs() < 1e-5, "{} vs {h2}", s.state()[H2]);
        // With no share, the lower tank settles lower: the overflow really is passed on.
        let mut p0 = p.clone();
        p0.overflow_share = 0.0;
        let (s0, _) = simulate(Tanks::new(p0, Input::Held(u)), [0.29, 0.1], 1500.0);
        assert!(s0.state()[H2] < s.state()[H2] - 0.01);
    }

    #[test]
    fn a_draining_upper_tank_leaves_the_top_when_the_pump_slows() {
        let p = TanksParams::default();
        let sig = profile(&[(0.0, 9.0), (300.0, 9.0), (300.0, 2.0), (600.0, 2.0)]);
        let (s, samples) = simulate(Tanks::new(p.clone(), Input::Signal(sig)), [0.2, 0.1], 600.0);
        assert!(samples.iter().any(|(t, h)| *t < 300.0 && h[H1] == p.height_1));
        assert!(s.state()[H1] < 0.5 * p.height_1, "{:?}", s.state());
    }
}
