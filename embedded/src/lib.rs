//! The loop the firmware runs, written once for the target and the host: the pump's
//! RHONN adaptive pressure controller (`rhonn_core::adaptive::RhonnCascade`, whose
//! affine neuron identifies the line pressure online) and a general online identifier
//! (`rhonn_core::online_fixed::FixedOnline`, the update `rhonn identify` runs: the
//! pressure from the current and the demand, one 20 ms filter standing in for the
//! stroke, every monomial up to degree 2, gain 5, a 0.05 MPa dead zone) against the pump
//! discretised by `rhonn_core::pump::DiscretePump`, every 5 ms for 2,000 periods (10 s).
//!
//! The scenario: the pump starts at 2 MPa with the stroke at 0; the set-point is 10 MPa,
//! then 15 MPa from 6 s; the demand ramps (2 dm^3/s^2) to 1.0 dm^3/s from 3 s, holds 2 s
//! and ramps back; the pressure is measured with a uniform noise of standard deviation
//! 0.05 MPa from a fixed-seed xorshift generator, the stroke without noise.
#![no_std]

use rhonn_core::adaptive::{CascadeSettings, RhonnCascade};
use rhonn_core::online::{InputHold, Scaling, UpdateError};
use rhonn_core::online_fixed::{FixedOnline, FixedSpec, SpecError};
use rhonn_core::pump::{DiscretePump, PumpEquations};
use rhonn_core::Real;

/// The controller's arithmetic: `f32` with the `single` feature (a single-precision FPU
/// such as the Cortex-M4F's does it in hardware), `f64` otherwise. The plant is `f64`.
#[cfg(feature = "single")]
pub type Ctl = f32;
/// The controller's arithmetic: `f32` with the `single` feature (a single-precision FPU
/// such as the Cortex-M4F's does it in hardware), `f64` otherwise. The plant is `f64`.
#[cfg(not(feature = "single"))]
pub type Ctl = f64;

/// Control periods.
pub const PERIODS: u32 = 2000;
/// Control period \[s\].
pub const PERIOD_S: f64 = 0.005;
/// Print a line every this many periods.
pub const PRINT_EVERY: u32 = 100;

/// What one period shows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// Period index.
    pub k: u32,
    /// Time \[s\].
    pub t: f64,
    /// Pressure minus set-point \[MPa\].
    pub error_mpa: f64,
    /// The identifier's pressure minus the plant's \[MPa\].
    pub ident_error_mpa: f64,
    /// |W| (MPa/s).
    pub w_norm: f64,
    /// |W_1| (MPa/(s mm)).
    pub w1_norm: f64,
    /// Commanded current \[A\].
    pub current_a: f64,
    /// The general online identifier's estimate (made before the measurement was seen)
    /// minus the plant's pressure \[MPa\].
    pub online_error_mpa: f64,
    /// |w| of the general online identifier's neuron (normalised units).
    pub online_w_norm: f64,
    /// Persistence, the baseline of the online identifier: the last period's measured
    /// pressure minus the plant's pressure now \[MPa\].
    pub persistence_error_mpa: f64,
}

/// The general online identifier: signals (outputs and network inputs) at most 8;
/// state, terms and factors at most 32.
pub type Online = FixedOnline<Ctl, 8, 32>;

/// Set `id` up as the general online identifier of the pressure \[Pa\] from the
/// current \[A\] and the demand \[m^3/s\], normalised around 10 MPa, 0.4 A and 0.5
/// dm^3/s.
pub fn online_identifier(id: &mut Online) -> Result<(), SpecError> {
    let c = Ctl::of;
    id.configure(&FixedSpec {
        filters_s: &[c(0.02)],
        degree: 2,
        max_factors: 2,
        output_terms: true,
        a_per_s: None,
        gain: c(5.0),
        dead_zone: &[c(0.05e6)],
        hold: InputHold::Hold,
        period_s: c(PERIOD_S),
        scaling: Scaling {
            y_offset: &[c(10e6)],
            y_scale: &[c(3e6)],
            u_offset: &[c(0.4), c(0.5e-3)],
            u_scale: &[c(0.2), c(0.4e-3)],
            y_bounds: Some(&[[c(0.0), c(25e6)]]),
        },
        robust: None,
    })
}

/// The set-point \[Pa\] at `t`.
fn setpoint(t: f64) -> f64 {
    if t < 6.0 {
        10e6
    } else {
        15e6
    }
}

/// The demanded flow \[m^3/s\] at `t`: a trapezoid to 1.0 dm^3/s.
fn demand(t: f64) -> f64 {
    let (start, peak, hold, slew) = (3.0, 1.0e-3, 2.0, 2.0e-3);
    let rise = peak / slew;
    let q = if t < start {
        0.0
    } else if t < start + rise {
        (t - start) * slew
    } else if t < start + rise + hold {
        peak
    } else {
        (peak - (t - start - rise - hold) * slew).max(0.0)
    };
    q.max(0.0)
}

/// A fixed-seed xorshift64 generator of the measurement noise.
struct Noise(u64);

impl Noise {
    /// Uniform in `[-a, a]` with `a = sqrt(3) 0.05 MPa` (standard deviation 0.05 MPa) \[Pa\].
    fn next_pa(&mut self) -> f64 {
        let mut x = self.0;
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        self.0 = x;
        let unit = (x >> 11) as f64 / (1u64 << 53) as f64; // [0, 1)
        (2.0 * unit - 1.0) * 0.05e6 * 1.7320508075688772
    }
}

/// One update of the general online identifier: the estimate of the pressure. Not
/// inlined into the loop: one copy of the update's code (flash), not one per call site.
#[inline(never)]
fn online_step(id: &mut Online, t: Ctl, u: &[Ctl; 2], p: Ctl) -> Result<Ctl, UpdateError<Ctl>> {
    id.update(t, u, &[p]).map(|y| y[0])
}

/// The two parts of a control step, timed apart.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Part {
    /// The adaptive controller's update (with its own neuron's identification).
    Controller,
    /// The general online identifier's update.
    Identifier,
}

/// Run the loop; `sample` sees every period, `timed` wraps each part of a control step
/// (the controller, then the general identifier's update: the target counts their
/// instructions there; the host just calls them). An error names what failed.
pub fn run(
    mut sample: impl FnMut(&Sample),
    mut timed: impl FnMut(Part, &mut dyn FnMut()),
) -> Result<(), &'static str> {
    let eq = PumpEquations::THESIS;
    let (p0, x0) = (2e6, 0.0);
    let mut pump = DiscretePump::thesis(p0, x0);
    let (i_max, x_max, p_max) = (0.8, pump.x_max, pump.p_max);
    // The gain weights start from beta k_l omega / V_l at the first set-point, MPa/(s mm).
    let gain = eq.beta * eq.k_l * eq.omega / (eq.v_l0 * (1.0 + eq.alpha_v * setpoint(0.0))) * 1e-9;
    let mut ctl = RhonnCascade::<Ctl>::new(
        CascadeSettings::default(),
        eq.k_a,
        eq.phi,
        i_max,
        x_max,
        p_max,
        PERIOD_S,
        gain,
        p0,
    );
    let mut online = Online::empty();
    online_identifier(&mut online).map_err(|_| "the online identifier's settings do not fit")?;
    let mut noise = Noise(0x2545_F491_4F6C_DD1D);
    let mut p_last = p0;
    for k in 0..PERIODS {
        let t = k as f64 * PERIOD_S;
        let p_meas = pump.p + noise.next_pa();
        let (x_meas, r) = (pump.x, setpoint(t));
        let mut current = Ctl::default();
        let mut p_hat = Ok(Ctl::default());
        let c = Ctl::of;
        timed(Part::Controller, &mut || {
            current = ctl.update(c(t), c(p_meas), c(x_meas), c(r))
        });
        timed(Part::Identifier, &mut || {
            p_hat = online_step(&mut online, c(t), &[current, c(demand(t))], c(p_meas));
        });
        let p_hat = p_hat
            .map_err(|_| "the general online identifier failed (a non-finite sample or diverged weights)")?;
        let current = current.to_f64();
        let w = online.weights(0);
        let st = ctl.state();
        sample(&Sample {
            k,
            t,
            error_mpa: (pump.p - r) * 1e-6,
            ident_error_mpa: (st.p_hat.to_f64() - pump.p) * 1e-6,
            w_norm: st.w_norm.to_f64(),
            w1_norm: st.w1_norm.to_f64(),
            current_a: current,
            online_error_mpa: (p_hat.to_f64() - pump.p) * 1e-6,
            online_w_norm: libm::sqrt(w.iter().map(|v| v.to_f64() * v.to_f64()).sum()),
            persistence_error_mpa: (p_last - pump.p) * 1e-6,
        });
        p_last = p_meas;
        pump.step(PERIOD_S, 10, current, demand(t));
    }
    Ok(())
}

/// The regulation over the run: RMS and largest |p - p_ref| from 1 s after each
/// set-point change (the start and 6 s), in MPa; and the general online identifier's RMS
/// error over the second half (5 to 10 s).
#[derive(Debug, Clone, Copy, Default)]
pub struct Regulation {
    sum_sq: f64,
    n: u32,
    /// Largest |p - p_ref| \[MPa\].
    pub max_abs_mpa: f64,
    online_sq: f64,
    persistence_sq: f64,
    online_n: u32,
}

impl Regulation {
    /// Count a period in (outside the second after a set-point change).
    pub fn add(&mut self, s: &Sample) {
        let settled = (1.0..6.0).contains(&s.t) || s.t >= 7.0;
        if settled {
            self.sum_sq += s.error_mpa * s.error_mpa;
            self.n += 1;
            self.max_abs_mpa = self.max_abs_mpa.max(libm::fabs(s.error_mpa));
        }
        if s.t >= 5.0 {
            self.online_sq += s.online_error_mpa * s.online_error_mpa;
            self.persistence_sq += s.persistence_error_mpa * s.persistence_error_mpa;
            self.online_n += 1;
        }
    }

    /// RMS of the general online identifier's error over the second half \[MPa\].
    pub fn online_rms_mpa(&self) -> f64 {
        libm::sqrt(self.online_sq / self.online_n.max(1) as f64)
    }

    /// RMS of persistence's error over the second half \[MPa\].
    pub fn persistence_rms_mpa(&self) -> f64 {
        libm::sqrt(self.persistence_sq / self.online_n.max(1) as f64)
    }
    /// RMS of p - p_ref \[MPa\].
    pub fn rms_mpa(&self) -> f64 {
        libm::sqrt(self.sum_sq / self.n.max(1) as f64)
    }
}

/// FNV-1a over the bits of every value of every period: one number that changes if any
/// value of any period does.
#[derive(Debug, Clone, Copy)]
pub struct Digest(pub u64);

impl Default for Digest {
    fn default() -> Self {
        Digest(0xcbf2_9ce4_8422_2325)
    }
}

impl Digest {
    /// Fold a period's values in.
    pub fn add(&mut self, s: &Sample) {
        for v in [
            s.t,
            s.error_mpa,
            s.ident_error_mpa,
            s.w_norm,
            s.w1_norm,
            s.current_a,
            s.online_error_mpa,
            s.online_w_norm,
            s.persistence_error_mpa,
        ] {
            for b in v.to_bits().to_le_bytes() {
                self.0 ^= b as u64;
                self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
            }
        }
    }
}

/// Write the line printed for a period: readable values, then their bits in hex.
pub fn write_line(w: &mut impl core::fmt::Write, s: &Sample) -> core::fmt::Result {
    write!(
        w,
        "k={} t={:.3} error_mpa={:.6} ident_error_mpa={:.6} w_norm={:.4} w1_norm={:.4} current_a={:.5} online_error_mpa={:.6} online_w_norm={:.4} bits={:016x},{:016x},{:016x},{:016x},{:016x},{:016x},{:016x}",
        s.k,
        s.t,
        s.error_mpa,
        s.ident_error_mpa,
        s.w_norm,
        s.w1_norm,
        s.current_a,
        s.online_error_mpa,
        s.online_w_norm,
        s.error_mpa.to_bits(),
        s.ident_error_mpa.to_bits(),
        s.w_norm.to_bits(),
        s.w1_norm.to_bits(),
        s.current_a.to_bits(),
        s.online_error_mpa.to_bits(),
        s.online_w_norm.to_bits(),
    )
}
