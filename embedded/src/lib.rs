//! The loop the firmware runs, written once for the target and the host: the pump's
//! RHONN adaptive pressure controller (`rhonn_core::adaptive::RhonnCascade`, whose
//! affine neuron identifies the line pressure online) against the pump discretised by
//! `rhonn_core::pump::DiscretePump`, every 5 ms for 2,000 periods (10 s).
//!
//! The scenario: the pump starts at 2 MPa with the stroke at 0; the set-point is 10 MPa,
//! then 15 MPa from 6 s; the demand ramps (2 dm^3/s^2) to 1.0 dm^3/s from 3 s, holds 2 s
//! and ramps back; the pressure is measured with a uniform noise of standard deviation
//! 0.05 MPa from a fixed-seed xorshift generator, the stroke without noise.
#![no_std]

use rhonn_core::adaptive::{CascadeSettings, RhonnCascade};
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

/// Run the loop; `sample` sees every period, `timed` wraps each controller step (the
/// target counts its instructions there; the host just calls it).
pub fn run(mut sample: impl FnMut(&Sample), mut timed: impl FnMut(&mut dyn FnMut())) {
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
    let mut noise = Noise(0x2545_F491_4F6C_DD1D);
    for k in 0..PERIODS {
        let t = k as f64 * PERIOD_S;
        let p_meas = pump.p + noise.next_pa();
        let (x_meas, r) = (pump.x, setpoint(t));
        let mut current = Ctl::default();
        let c = Ctl::of;
        timed(&mut || current = ctl.update(c(t), c(p_meas), c(x_meas), c(r)));
        let current = current.to_f64();
        let st = ctl.state();
        sample(&Sample {
            k,
            t,
            error_mpa: (pump.p - r) * 1e-6,
            ident_error_mpa: (st.p_hat.to_f64() - pump.p) * 1e-6,
            w_norm: st.w_norm.to_f64(),
            w1_norm: st.w1_norm.to_f64(),
            current_a: current,
        });
        pump.step(PERIOD_S, 10, current, demand(t));
    }
}

/// The regulation over the run: RMS and largest |p - p_ref| from 1 s after each
/// set-point change (the start and 6 s), in MPa.
#[derive(Debug, Clone, Copy, Default)]
pub struct Regulation {
    sum_sq: f64,
    n: u32,
    /// Largest |p - p_ref| \[MPa\].
    pub max_abs_mpa: f64,
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
        "k={} t={:.3} error_mpa={:.6} ident_error_mpa={:.6} w_norm={:.4} w1_norm={:.4} current_a={:.5} bits={:016x},{:016x},{:016x},{:016x},{:016x}",
        s.k,
        s.t,
        s.error_mpa,
        s.ident_error_mpa,
        s.w_norm,
        s.w1_norm,
        s.current_a,
        s.error_mpa.to_bits(),
        s.ident_error_mpa.to_bits(),
        s.w_norm.to_bits(),
        s.w1_norm.to_bits(),
        s.current_a.to_bits(),
    )
}
