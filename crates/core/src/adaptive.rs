//! RHONN indirect adaptive control (pump-model.md section 4, thesis 4.5.2): an affine RHONN
//! neuron identified online, with a projection that keeps its input gain away from zero,
//! and the certainty-equivalence control law computed from it.
//!
//! # The design for the pump
//!
//! The pump is not square-affine in the current (current -> pilot valve -> stroke ->
//! pressure), so the controller is a cascade:
//!
//! * **Outer loop, adaptive.** The line pressure is modelled by one affine RHONN neuron
//!   with the stroke `x` as its (virtual) input, in MPa, mm and s:
//!
//!   `dp^/dt = -a (p^ - p) + W S(p) + (W_1 S'(p)) x`,  `S(p) = [1, s(p/p_n)]`, `S'(p) = [1, s(p/p_n)]`
//!
//!   which has the plant's structure: `dP_l/dt = beta/V_l (k_l omega x - Q - Q_0)` is
//!   affine in `x`, with a gain `W_1 S'` that falls with the pressure (the line volume
//!   grows) and a drift `W S` holding the unknown demand. Learning laws (filtered-error
//!   gradient, thesis eq. 4.5x): `dW/dt = -Gamma e S`, `dW_1/dt = -Gamma_1 e S' x`, with
//!   `e = p^ - p`; `W_1` is projected onto a ball around its identified value whose
//!   radius keeps `W_1 S'` positive for every `S'` (so the law below never divides by
//!   zero), and `W` onto a large ball (bounded weights whatever the noise).
//!   Control (certainty equivalence, shifted to a set-point): the stroke that makes the
//!   model's pressure follow `dp/dt = -lambda (p - p_ref)`:
//!   `x_d = (-lambda (p - p_ref) - W S) / (W_1 S')`.
//! * **Inner loop, the pilot valve's static inverse plus feedback.** At rest the stroke
//!   is `x = phi I / K_a`, so `I = K_a/phi (x_d + g (x_d - x) + tau_lead dx_d/dt)`, with
//!   `dx_d/dt` computed analytically from the model and the learning law (no numerical
//!   differentiation of the noisy pressure), clipped to `[0, I_max]`.
//!
//! Assumptions, stated: the stroke is measured (variable-displacement pumps with
//! electronic displacement control carry a swash-plate angle sensor); the pressure is
//! measured with noise; both are sampled every control period T and the current is
//! held over it (zero-order hold). The identifier runs one period behind, on the
//! measurements interpolated linearly between samples, so that it compares its model
//! with the plant at the same instants (a model integrated against a held sample is
//! biased by the sample's staleness). Anti-windup: the controller has no integrator
//! driven by its own output: the weights are driven by the measured pressure and
//! stroke only, so a saturated current cannot wind them up. While the measured
//! pressure sits on a bound of the limited integrator (near 0 or P_max) the model's
//! derivative is not the plant's, and adaptation pauses.
//!
//! **The actuator identified online** (`actuator_memory_s` > 0, the default): a bank of
//! candidate solenoid lags fitted to the measured stroke ([`crate::actuator`]) gives the
//! actuator's lag `tau` and its pilot valve's flow against the nominal one, `theta`. The
//! stroke loop keeps its nominal speed on a slow or fast valve and backs off on a slow
//! solenoid: `I = K_a/phi (x + (1 + g') (x_d - x) / theta + tau_lead dx_d/dt / theta)`
//! with `g' = g / (1 + tau / tau_c)` (`lag_scale_s` = tau_c; g = 3 and tau_c = 40 ms give
//! g' = 2 at a 20 ms lag, the best stroke gain there); the lead is off while `x_d` is held
//! at a bound of the stroke (the derivative of a reference that does not move).
//!
//! Identification phase (thesis 4.5.1): for the first `identification_s` the same law
//! runs with a gentle `lambda_ident` around the first set-point while the weights
//! learn; then the ball's centre is set to the identified `W_1` and the full `lambda`
//! takes over.

use crate::actuator::ActuatorBank;
use crate::dot;
use crate::law::{descend, project};
use crate::sigmoid::Sigmoid;
use crate::Real;

/// Number of drift terms `S(p)`.
pub const L_DRIFT: usize = 2;
/// Number of gain terms `S'(p)`.
pub const L_GAIN: usize = 2;

/// A neuron's features: the drift terms `S` and the gain terms `S'`.
pub type Features<const L: usize, const L1: usize, T = f64> = ([T; L], [T; L1]);

/// One neuron of an affine RHONN, `dx^/dt = -a (x^ - x) + W S + (W_1 S') u`, with the
/// filtered-error gradient laws and projection (see the module docs). Units are the
/// caller's; `T` is `f64` unless a target asks for `f32`.
#[derive(Debug, Clone, PartialEq)]
pub struct AffineNeuron<const L: usize, const L1: usize, T = f64> {
    /// Filter pole a > 0.
    pub a: T,
    /// Learning rate of `W`.
    pub gamma: T,
    /// Learning rate of `W_1`.
    pub gamma1: T,
    /// Drift weights.
    pub w: [T; L],
    /// Gain weights.
    pub w1: [T; L1],
    /// Centre of `W_1`'s ball.
    pub center: [T; L1],
    /// Radius of `W_1`'s ball.
    pub radius: T,
    /// Radius of `W`'s ball (around 0).
    pub w_bound: T,
    /// The model's state.
    pub xh: T,
}

/// `w + c k`.
#[inline(always)]
fn axpy<T: Real, const N: usize>(w: &[T; N], k: &[T; N], c: T) -> [T; N] {
    let mut r = *w;
    for i in 0..N {
        r[i] += c * k[i];
    }
    r
}

impl<const L: usize, const L1: usize, T: Real> AffineNeuron<L, L1, T> {
    /// The model's derivative `W S + (W_1 S') u` (without the filter term).
    #[inline]
    pub fn drift_and_gain(&self, s: &[T; L], s1: &[T; L1]) -> (T, T) {
        (dot(&self.w, s), dot(&self.w1, s1))
    }

    /// Integrate the identifier over `dt` with the plant's state going linearly from
    /// `x0` to `x1` and the input from `u0` to `u1`; `features(x)` gives `(S, S')`.
    /// Classical RK4 with `n_sub` substeps; the weights are projected after each.
    /// Returns whether a projection acted.
    #[allow(clippy::too_many_arguments)]
    pub fn advance(
        &mut self,
        dt: T,
        n_sub: usize,
        (x0, x1): (T, T),
        (u0, u1): (T, T),
        adapt: bool,
        features: impl Fn(T) -> Features<L, L1, T>,
    ) -> bool {
        let c = T::of;
        let h = dt / c(n_sub as f64);
        let mut projected = false;
        let x_at = |f: T| x0 + (x1 - x0) * f;
        // The features at a fraction of the period, the last one kept: RK4's two middle
        // stages share theirs, and a substep's end is the next one's start, so 2 substeps
        // evaluate 5 instead of 8 (the sigmoid is most of a step's cost on a
        // microcontroller); the same values, bit for bit.
        let mut last: Option<(T, Features<L, L1, T>)> = None;
        let mut features_at = |f: T| match last {
            Some((g, v)) if g.bits() == f.bits() => v,
            _ => {
                let v = features(x_at(f));
                last = Some((f, v));
                v
            }
        };
        // The state is (xh, W, W_1); its derivative at fraction `f` of the period.
        let deriv = |f: T, (s, s1): Features<L, L1, T>, xh: T, w: &[T; L], w1: &[T; L1]| {
            let x = x_at(f);
            let u = u0 + (u1 - u0) * f;
            let e = xh - x;
            let dxh = -self.a * e + dot(w, &s) + dot(w1, &s1) * u;
            let mut dw = [T::default(); L];
            let mut dw1 = [T::default(); L1];
            if adapt {
                // The gradient law, phi = S for W and phi = S' u for W_1.
                descend(self.gamma, &s, e, &mut dw);
                let mut phi1 = s1;
                phi1.iter_mut().for_each(|p| *p *= u);
                descend(self.gamma1, &phi1, e, &mut dw1);
            }
            (dxh, dw, dw1)
        };
        let (half, two, six) = (c(0.5), c(2.0), c(6.0));
        for j in 0..n_sub {
            let f0 = c(j as f64) / c(n_sub as f64);
            let fh = half / c(n_sub as f64);
            let (xh, w, w1) = (self.xh, self.w, self.w1);
            let k1 = deriv(f0, features_at(f0), xh, &w, &w1);
            let k2 = deriv(
                f0 + fh,
                features_at(f0 + fh),
                xh + half * h * k1.0,
                &axpy(&w, &k1.1, half * h),
                &axpy(&w1, &k1.2, half * h),
            );
            let k3 = deriv(
                f0 + fh,
                features_at(f0 + fh),
                xh + half * h * k2.0,
                &axpy(&w, &k2.1, half * h),
                &axpy(&w1, &k2.2, half * h),
            );
            let k4 = deriv(
                f0 + two * fh,
                features_at(f0 + two * fh),
                xh + h * k3.0,
                &axpy(&w, &k3.1, h),
                &axpy(&w1, &k3.2, h),
            );
            self.xh += h / six * (k1.0 + two * k2.0 + two * k3.0 + k4.0);
            for i in 0..L {
                self.w[i] += h / six * (k1.1[i] + two * k2.1[i] + two * k3.1[i] + k4.1[i]);
            }
            for i in 0..L1 {
                self.w1[i] += h / six * (k1.2[i] + two * k2.2[i] + two * k3.2[i] + k4.2[i]);
            }
            projected |= project(&mut self.w1, &self.center, self.radius);
            projected |= project(&mut self.w, &[T::default(); L], self.w_bound);
        }
        projected
    }

    /// |W|.
    pub fn w_norm(&self) -> T {
        dot(&self.w, &self.w).sqrt()
    }

    /// |W_1|.
    pub fn w1_norm(&self) -> T {
        dot(&self.w1, &self.w1).sqrt()
    }

    /// |W_1 - centre|.
    pub fn w1_distance(&self) -> T {
        let d2 = self
            .w1
            .iter()
            .zip(&self.center)
            .map(|(a, b)| (*a - *b) * (*a - *b))
            .sum::<T>();
        d2.sqrt()
    }
}

impl<T: Real> AffineNeuron<L_DRIFT, L_GAIN, T> {
    /// A neuron with filter pole `a`, learning rates `gamma` (W) and `gamma1` (W_1), the
    /// drift weights at 0, the gain weights at `[w1_initial, 0]` with a ball of
    /// `ball_fraction` of the safe radius around them, W within 1e6, the model at `xh`.
    pub fn new(a: T, (gamma, gamma1): (T, T), w1_initial: T, ball_fraction: T, xh: T) -> Self {
        let w1 = [w1_initial, T::default()];
        AffineNeuron {
            a,
            gamma,
            gamma1,
            w: [T::default(); L_DRIFT],
            w1,
            center: w1,
            radius: ball_fraction * safe_radius(&w1),
            w_bound: T::of(1e6),
            xh,
        }
    }

    /// Centre W_1's ball on the identified W_1 (the end of the identification phase).
    pub fn recentre(&mut self, ball_fraction: T) {
        self.center = self.w1;
        self.radius = ball_fraction * safe_radius(&self.w1);
    }
}

/// The largest radius around `c` on which `W_1 S' > 0` for every `S' = [1, s - 1/2]`,
/// `s` in \[0, 1\]: `W_1 S' >= c_0 - |c_1|/2 - r |S'|` and `|S'| <= sqrt(5)/2`.
pub fn safe_radius<T: Real>(c: &[T; L_GAIN]) -> T {
    ((c[0] - T::of(0.5) * c[1].abs()) / T::of(1.25).sqrt()).max(T::default())
}

/// Settings of the cascade (display units where named so; see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct CascadeSettings {
    /// Closed-loop pressure pole lambda \[1/s\].
    pub lambda_per_s: f64,
    /// lambda during the identification phase \[1/s\].
    pub lambda_ident_per_s: f64,
    /// Length of the identification phase \[s\].
    pub identification_s: f64,
    /// Stroke feedback gain g \[-\].
    pub stroke_gain: f64,
    /// Lead on the stroke reference tau_lead \[s\].
    pub lead_s: f64,
    /// Identifier filter pole a \[1/s\].
    pub observer_pole_per_s: f64,
    /// Learning rate of the drift weights W \[1/s^2\] (the model is in MPa, mm, s).
    pub gamma_w: f64,
    /// Learning rate of the gain weights W_1.
    pub gamma_w1: f64,
    /// Radius of W_1's ball as a fraction of |centre| (< 1 keeps W_1 S' > 0).
    pub ball_fraction: f64,
    /// Pressure scale of the sigmoid p_n \[MPa\].
    pub p_scale_mpa: f64,
    /// Integral action k_i on the tracking error \[1/s^2\] (0: none): the control law
    /// aims at `dp/dt = -lambda (p - r) - k_i int(p - r) dt`.
    ///
    /// Why it keeps the loop stable: the identifier's error and weights stay bounded
    /// (Lyapunov, with the projection), so the model's mismatch d = (W S + W_1 S' x) -
    /// dp/dt is bounded, and the tracking error eps = p - r obeys
    /// `eps' = -lambda eps - k_i int(eps) + d`, whose characteristic polynomial
    /// `s^2 + lambda s + k_i` is Hurwitz for lambda, k_i > 0 (lambda 100, k_i 1000:
    /// real poles at -10.1 and -89.9 1/s). eps is then bounded by a multiple of sup |d|
    /// (input-to-state stable), and a constant d (the model's residual bias, which left
    /// eps 0.07-0.15 MPa below the set-point without it) is absorbed by the integral:
    /// eps -> 0. Integral separation (only |eps| <= 1 MPa is integrated) and the
    /// anti-windup only stop the integration, which keeps the integral bounded.
    pub integral_per_s2: f64,
    /// Memory \[s\] of the actuator's online identification ([`crate::actuator`]): the
    /// stroke loop's gain and lead divided by the identified pilot valve's flow ratio,
    /// its gain scheduled on the identified lag (`lag_scale_s`). 0: off, the stroke loop
    /// as designed for the nominal valve.
    pub actuator_memory_s: f64,
    /// tau_c \[s\]: the stroke gain is divided by `1 + tau / tau_c` for an identified lag
    /// tau (0: not scheduled). Only with `actuator_memory_s` > 0.
    pub lag_scale_s: f64,
}

impl Default for CascadeSettings {
    fn default() -> Self {
        CascadeSettings {
            lambda_per_s: 100.0,
            lambda_ident_per_s: 10.0,
            identification_s: 2.0,
            stroke_gain: 3.0,
            lead_s: 0.06,
            observer_pole_per_s: 70.0,
            gamma_w: 1e4,
            gamma_w1: 5.0,
            ball_fraction: 0.5,
            p_scale_mpa: 10.0,
            integral_per_s2: 1000.0,
            actuator_memory_s: 5.0,
            lag_scale_s: 0.04,
        }
    }
}

/// What the controller shows of itself at a control instant.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CascadeState<T = f64> {
    /// Stroke reference x_d \[m\].
    pub stroke_ref: T,
    /// The model's pressure p^ \[Pa\].
    pub p_hat: T,
    /// |W| (MPa/s units).
    pub w_norm: T,
    /// |W_1| (MPa/(s mm) units).
    pub w1_norm: T,
    /// |W_1 - centre| (MPa/(s mm) units): the projection keeps it within `ball_radius`.
    pub w1_distance: T,
    /// Radius of W_1's ball (MPa/(s mm) units).
    pub ball_radius: T,
}

/// Tracking errors integrated by the integral action: within this band \[MPa\].
pub const INTEGRAL_BAND_MPA: f64 = 1.0;

/// The pump's RHONN cascade controller: call [`RhonnCascade::update`] every period.
/// `T` is the arithmetic (`f64` unless a target asks for `f32`); the settings stay `f64`.
#[derive(Debug, Clone)]
pub struct RhonnCascade<T = f64> {
    /// Settings.
    pub settings: CascadeSettings,
    /// The pressure neuron (MPa, mm, s).
    pub neuron: AffineNeuron<L_DRIFT, L_GAIN, T>,
    sigmoid: Sigmoid,
    period_s: T,
    /// K_a / phi \[A/mm\].
    amp_per_mm: T,
    i_max: T,
    x_max_mm: T,
    p_max_mpa: T,
    prev: Option<(T, T)>,
    ball_set: bool,
    x_d: T,
    projections: u64,
    /// int (p - r) dt since the identification phase ended \[MPa s\].
    integral: T,
    /// The actuator's online identification (None: off).
    actuator: Option<ActuatorBank<T>>,
    /// The current applied over the last period \[A\].
    last_i: T,
}

impl<T: Real> RhonnCascade<T> {
    /// A controller for a pump with feedback spring `k_a` \[N/m\], solenoid gain `phi`
    /// \[N/A\], current range `[0, i_max]` \[A\], stroke range `[0, x_max]` \[m\], pressure
    /// bound `p_max` \[Pa\], period `period_s`; the gain weights start at
    /// `w1_initial` (the nominal plant's `beta k_l omega / V_l` in MPa/(s mm), split
    /// over `S'`), the drift weights at 0, the model at `p0` \[Pa\].
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        settings: CascadeSettings,
        k_a: f64,
        phi: f64,
        i_max: f64,
        x_max: f64,
        p_max: f64,
        period_s: f64,
        w1_initial: f64,
        p0: f64,
    ) -> Self {
        let c = T::of;
        let neuron = AffineNeuron::new(
            c(settings.observer_pole_per_s),
            (c(settings.gamma_w), c(settings.gamma_w1)),
            c(w1_initial),
            c(settings.ball_fraction),
            c(p0 * 1e-6),
        );
        let memory_s = settings.actuator_memory_s;
        let actuator = (memory_s > 0.0).then(|| ActuatorBank::new(period_s, memory_s));
        RhonnCascade {
            settings,
            neuron,
            sigmoid: Sigmoid::LOGISTIC,
            period_s: c(period_s),
            amp_per_mm: c(k_a / phi * 1e-3),
            i_max: c(i_max),
            x_max_mm: c(x_max * 1e3),
            p_max_mpa: c(p_max * 1e-6),
            prev: None,
            ball_set: false,
            x_d: T::default(),
            projections: 0,
            integral: T::default(),
            actuator,
            last_i: T::default(),
        }
    }

    /// The largest radius around `c` on which `W_1 S' > 0` (see [`safe_radius`]).
    pub fn safe_radius(c: &[T; L_GAIN]) -> T {
        safe_radius(c)
    }

    #[inline]
    fn features(sig: Sigmoid, scale: T, p_mpa: T) -> Features<L_DRIFT, L_GAIN, T> {
        let s = sig.eval_in(p_mpa / scale);
        let one = T::of(1.0);
        ([one, s], [one, s - T::of(0.5)])
    }

    /// One control instant at time `t` \[s\] with the measured pressure \[Pa\] and
    /// stroke \[m\] and the set-point \[Pa\]: returns the current \[A\].
    #[inline]
    pub fn update(&mut self, t: T, p_meas: T, x_meas: T, p_ref: T) -> T {
        let c = T::of;
        let zero = T::default();
        let (p, x, r) = (p_meas * c(1e-6), x_meas * c(1e3), p_ref * c(1e-6));
        let (sig, scale) = (self.sigmoid, c(self.settings.p_scale_mpa));
        // The identifier catches up over the last period, on interpolated measurements.
        if let Some((p0, x0)) = self.prev {
            let margin = c(0.2);
            let adapt = p0.min(p) > margin && p0.max(p) < self.p_max_mpa - margin;
            let projected = self
                .neuron
                .advance(self.period_s, 2, (p0, p), (x0, x), adapt, |pm| {
                    Self::features(sig, scale, pm)
                });
            self.projections += projected as u64;
            if let Some(a) = &mut self.actuator {
                a.update((p0, x0), (p, x), self.last_i, self.x_max_mm);
            }
        }
        self.prev = Some((p, x));
        let ident = t < c(self.settings.identification_s);
        if !ident && !self.ball_set {
            // The identified gain becomes the centre of the projection's ball.
            self.neuron.recentre(c(self.settings.ball_fraction));
            self.ball_set = true;
        }
        let lambda = c(if ident {
            self.settings.lambda_ident_per_s
        } else {
            self.settings.lambda_per_s
        });
        let (s, s1) = Self::features(sig, scale, p);
        let (f, g) = self.neuron.drift_and_gain(&s, &s1);
        let g = g.max(c(1e-9));
        // Integral action after the identification phase, held (anti-windup) while the
        // stroke reference or the current is saturated in the error's direction.
        let ki = if ident {
            zero
        } else {
            c(self.settings.integral_per_s2)
        };
        // Integral separation: only small errors are integrated (a set-point step or a
        // demand ramp is the proportional part's job), so the integral does not wind up
        // on a transient and overshoot after it.
        let near = (p - r).abs() <= c(INTEGRAL_BAND_MPA);
        let candidate = self.integral + if near { self.period_s * (p - r) } else { zero };
        let x_d_raw = (-lambda * (p - r) - ki * candidate - f) / g;
        let x_d = x_d_raw.clamp(zero, self.x_max_mm);
        // dx_d/dt from the model: d/dt of (-lambda (p - r) - k_i int(p - r) - W S) / (W_1 S'),
        // with the weights' rates from the learning law (S, S' and r taken as constant).
        let e = self.neuron.xh - p;
        let p_dot = f + g * x;
        let w_dot_s: T = -c(self.settings.gamma_w) * e * dot(&s, &s);
        let w1_dot_s1: T = -c(self.settings.gamma_w1) * e * x * dot(&s1, &s1);
        let x_d_dot = (-lambda * p_dot - ki * (p - r) - w_dot_s - w1_dot_s1 * x_d) / g;
        self.x_d = x_d;
        let st = &self.settings;
        let i = match &self.actuator {
            None => self.amp_per_mm * (x_d + c(st.stroke_gain) * (x_d - x) + c(st.lead_s) * x_d_dot),
            Some(a) => {
                let g = match st.lag_scale_s > 0.0 {
                    true => c(st.stroke_gain) / (c(1.0) + a.lag_s() / c(st.lag_scale_s)),
                    false => c(st.stroke_gain),
                };
                let x_d_dot = if x_d == x_d_raw { x_d_dot } else { zero };
                let per_theta = c(1.0) / a.ratio();
                let feedback = (c(1.0) + g) * (x_d - x) + c(st.lead_s) * x_d_dot;
                self.amp_per_mm * (x + per_theta * feedback)
            }
        };
        if ki > zero {
            // p > r asks for less stroke: winding while the output sits at its bottom.
            let low = x_d_raw < zero || i < zero;
            let high = x_d_raw > self.x_max_mm || i > self.i_max;
            if !((low && p > r) || (high && p < r)) {
                self.integral = candidate;
            }
        }
        let i = i.clamp(zero, self.i_max);
        self.last_i = i;
        i
    }

    /// The actuator's identified lag \[s\] and pilot flow ratio (None: not identified,
    /// `actuator_memory_s` = 0).
    pub fn actuator(&self) -> Option<(T, T)> {
        self.actuator.as_ref().map(|a| (a.lag_s(), a.ratio()))
    }

    /// Internal state for the trace.
    pub fn state(&self) -> CascadeState<T> {
        CascadeState {
            stroke_ref: self.x_d * T::of(1e-3),
            p_hat: self.neuron.xh * T::of(1e6),
            w_norm: self.neuron.w_norm(),
            w1_norm: self.neuron.w1_norm(),
            w1_distance: self.neuron.w1_distance(),
            ball_radius: self.neuron.radius,
        }
    }

    /// How many substeps ended with a projection.
    pub fn projections(&self) -> u64 {
        self.projections
    }
}
