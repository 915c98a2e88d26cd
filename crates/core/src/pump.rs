//! The pump's equations (pump-model.md section 1, thesis chapter 3): the pilot valve
//! and the line, as pure functions of the state. The host library's `PumpSystem` (the
//! exact model on the event-locating solver) evaluates these; [`DiscretePump`] steps
//! them with a fixed-step RK4 for a plant on a microcontroller (hardware-in-the-loop
//! tests, the `embedded/` firmware), without the events: the valve's branch is chosen
//! at the start of each substep.

use crate::Real;

/// Coefficients of the pump's equations, SI.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PumpEquations {
    /// Line volume at zero pressure V_l0 \[m^3\].
    pub v_l0: f64,
    /// Bulk modulus beta \[Pa\].
    pub beta: f64,
    /// Line compliance alpha_v \[1/Pa\].
    pub alpha_v: f64,
    /// Pump displacement constant k_l \[m^2\].
    pub k_l: f64,
    /// Shaft speed omega \[rad/s\].
    pub omega: f64,
    /// Leakage flow Q_0 \[m^3/s\].
    pub q_0: f64,
    /// Actuator piston area A_a \[m^2\].
    pub a_a: f64,
    /// Pilot valve flow coefficients mu_1, mu_2.
    pub mu_1: f64,
    /// See `mu_1`.
    pub mu_2: f64,
    /// Solenoid force gain phi \[N/A\].
    pub phi: f64,
    /// Pilot valve spring k_c \[N/m\].
    pub k_c: f64,
    /// Feedback spring k_a \[N/m\].
    pub k_a: f64,
    /// Actuator spring k \[N/m\].
    pub k: f64,
    /// Actuator spring preload F_u \[N\].
    pub f_u: f64,
    /// Pressure ratio gamma_l.
    pub gamma_l: f64,
    /// Case pressure P_0 \[Pa\].
    pub p_0: f64,
}

/// Intermediate quantities of the pilot valve (`T`: `f64` unless a controller on a
/// single-precision target evaluates the nominal valve in `f32`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Pilot<T = f64> {
    /// Pilot valve stroke s \[m\].
    pub s: T,
    /// Pressure drop across the pilot valve \[Pa\].
    pub dpa: T,
    /// Pilot flow Q_a \[m^3/s\].
    pub q_a: T,
}

impl PumpEquations {
    /// Table 3.3 of the thesis in SI (the host library checks that its nominal
    /// parameters give exactly these).
    pub const THESIS: PumpEquations = PumpEquations {
        v_l0: 0.00025,
        beta: 1200000000.0,
        alpha_v: 4e-8,
        k_l: 0.0006,
        omega: 200.0,
        q_0: 0.00013000000000000002,
        a_a: 0.0005,
        mu_1: 7.8e-5,
        mu_2: 7.8e-5,
        phi: 28.0,
        k_c: 27300.0,
        k_a: 1300.0,
        k: 8300.0,
        f_u: 400.0,
        gamma_l: 0.2,
        p_0: 400000.0,
    };

    /// The pilot valve at `(P_l, x)` and current `i`, on the branch `neg` (s < 0), in the
    /// arithmetic `T` (for `f64` exactly the operations of the plant's model).
    #[inline(always)]
    pub fn pilot<T: Real>(&self, p: T, x: T, i: T, neg: bool) -> Pilot<T> {
        let c = T::of;
        let k = self;
        let s = (c(k.phi) * i - c(k.k_a) * x) / c(k.k_c + k.k_a);
        let bias = (c(k.f_u) - c(k.k) * x) / c(k.a_a);
        let dpa = if neg {
            c(1.0 - k.gamma_l) * p - bias
        } else {
            c(k.gamma_l) * p + bias - c(k.p_0)
        };
        let mag = dpa.abs().sqrt();
        let sign = if dpa >= T::default() { c(1.0) } else { c(-1.0) };
        let q_a = sign * s * (c(k.mu_1) + c(k.mu_2) * s.abs()) * mag;
        Pilot { s, dpa, q_a }
    }

    /// Derivatives `(dP_l/dt, dx/dt)` at `(P_l, x)` with inputs `i`, `q` on branch `neg`.
    #[inline(always)]
    pub fn derivative(&self, p: f64, x: f64, i: f64, q: f64, neg: bool) -> (f64, f64) {
        let k = self;
        let pil = self.pilot(p, x, i, neg);
        let draw = if neg { libm::fabs(pil.q_a) } else { 0.0 };
        let v_l = k.v_l0 * (1.0 + k.alpha_v * p);
        let dp = k.beta / v_l * (k.k_l * k.omega * x - q - k.q_0 - draw);
        (dp, pil.q_a / k.a_a)
    }
}

/// The pump stepped with a fixed-step classical RK4, both states held in their ranges
/// (limited integrators: every stage's state clamped, no motion beyond a bound), the
/// current and the demand held over a step.
#[derive(Debug, Clone, PartialEq)]
pub struct DiscretePump {
    /// The equations.
    pub eq: PumpEquations,
    /// Pressure range \[0, p_max\] \[Pa\].
    pub p_max: f64,
    /// Stroke range \[0, x_max\] \[m\].
    pub x_max: f64,
    /// Line pressure P_l \[Pa\].
    pub p: f64,
    /// Stroke x \[m\].
    pub x: f64,
}

impl DiscretePump {
    /// The thesis's pump (P_max 25 MPa, x_max 24 mm) at `p` \[Pa\] and `x` \[m\].
    pub fn thesis(p: f64, x: f64) -> Self {
        DiscretePump {
            eq: PumpEquations::THESIS,
            p_max: 25e6,
            x_max: 0.024,
            p,
            x,
        }
    }

    /// Advance by `dt` \[s\] in `n_sub` RK4 substeps with current `i` \[A\] and demand
    /// `q` \[m^3/s\] held.
    pub fn step(&mut self, dt: f64, n_sub: u32, i: f64, q: f64) {
        let h = dt / n_sub as f64;
        for _ in 0..n_sub {
            let (p, x) = (self.p, self.x);
            let neg = self.eq.pilot(p, x, i, false).s < 0.0;
            // Limited integrators, as in the exact model: a stage sees its state held in
            // range, and a state at a bound does not move beyond it.
            let f = |p: f64, x: f64| {
                let (p, x) = (p.clamp(0.0, self.p_max), x.clamp(0.0, self.x_max));
                let (dp, dx) = self.eq.derivative(p, x, i, q, neg);
                let held = |v: f64, d: f64, hi: f64| {
                    if (v <= 0.0 && d < 0.0) || (v >= hi && d > 0.0) {
                        0.0
                    } else {
                        d
                    }
                };
                (held(p, dp, self.p_max), held(x, dx, self.x_max))
            };
            let k1 = f(p, x);
            let k2 = f(p + 0.5 * h * k1.0, x + 0.5 * h * k1.1);
            let k3 = f(p + 0.5 * h * k2.0, x + 0.5 * h * k2.1);
            let k4 = f(p + h * k3.0, x + h * k3.1);
            let p1 = p + h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
            let x1 = x + h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
            self.p = p1.clamp(0.0, self.p_max);
            self.x = x1.clamp(0.0, self.x_max);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_states_stay_in_their_ranges() {
        let mut pump = DiscretePump::thesis(2e6, 0.0);
        for k in 0..4000 {
            let i = if k < 2000 { 0.8 } else { 0.0 };
            pump.step(0.005, 10, i, 0.0);
            assert!((0.0..=25e6).contains(&pump.p) && (0.0..=0.024).contains(&pump.x));
        }
    }
}
