//! The pump's actuator identified online, for the adaptive cascade's stroke loop
//! (`RhonnCascade` in the `adaptive` module, which owns a bank): how late and how fast the
//! stroke answers the current.
//!
//! A bank of candidate actuators ([`CANDIDATES`]): a solenoid lag `tau`, after a transport
//! delay of zero or one control period. Each candidate passes the applied current through
//! its delay and first-order lag and predicts the stroke rate of the **nominal**
//! pilot valve (`pump::PumpEquations::THESIS`, section 1 of pump-model.md) at the measured
//! pressure and stroke; one ratio `theta` per candidate scales that prediction to the
//! measured rate (least squares with forgetting). The candidate with the smallest residual
//! is the actuator; its lag plus its delay is the actuator's lag, its ratio is the plant's pilot flow against the nominal one
//! (`mu_1`, `mu_2` off their table values: 0.8 when both are 20 % low).
//!
//! Why a bank, not one ratio: a solenoid lag (or a transport delay) makes the stroke answer
//! the current late, and a single ratio reads that as a slow valve (measured: the ratio
//! fell to its lower bound on a 20 ms lag with a nominal valve), whose compensation would
//! raise the very gain a lag cannot take. With the lag in the model the ratio stays
//! unbiased (1.00 on the 5 and 20 ms lags, 0.80 and 1.20 on the corners with `mu_1`, `mu_2`
//! at -20 % and +20 %), and the lag itself is identified (5 ms and 20 ms found exactly). A
//! one-period delay without its own candidate read as a 5 ms lag with a ratio of 1.42 (a
//! fast valve), whose compensation slowed the loop; with it the delay is found as itself.
//!
//! Only periods with the stroke inside its range are used (at a bound the stroke does not
//! move whatever the valve). Units: pressure MPa, stroke mm, time s, current A.

use crate::pump::PumpEquations;
use crate::Real;

/// Number of candidate actuators.
pub const N_CANDIDATES: usize = 5;
/// The candidate actuators: (transport delay in control periods, solenoid lag \[s\]).
/// (Five: each candidate costs 32 bytes of an f64 firmware's 8 KiB of RAM; a lag beyond
/// 20 ms reads as 20 ms.) A delay's lag is not modelled beside it.
pub const CANDIDATES: [(u32, f64); N_CANDIDATES] = [(0, 0.0), (0, 0.005), (0, 0.01), (0, 0.02), (1, 0.0)];
/// The range the pilot valve's ratio is held in: a valve beyond half or twice the nominal
/// flow is another valve, not a tolerance.
pub const RATIO_RANGE: (f64, f64) = (0.5, 2.0);
/// Information \[(mm/s)^2\] (the sum of the nominal rates squared, forgotten as the sums
/// are) before the best candidate's lag and ratio are used: about ten periods of the stroke
/// moving at 10 mm/s. Until then no lag and the nominal valve are assumed.
pub const MIN_INFORMATION: f64 = 1000.0;
/// Distance \[mm\] from a stroke bound within which a period is not used.
const BOUND_MARGIN_MM: f64 = 0.05;

/// One candidate lag: its lagged current and its least squares sums.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
struct Candidate<T> {
    /// The current through this lag at the end of the last period \[A\]; for a delay, the
    /// current applied over the last period (what acts over the next).
    current: T,
    /// Sums of nominal rate x measured rate, and of nominal rate squared.
    qy: T,
    qq: T,
}

/// The bank of candidate lags (see the module docs).
#[derive(Debug, Clone, PartialEq)]
pub struct ActuatorBank<T = f64> {
    /// The control period \[s\].
    period_s: T,
    /// What the sums keep of themselves per period, `e^(-T/memory)`.
    keep: T,
    /// Per candidate, what is left of the lagged current's distance to the held current
    /// at the end of a period, `e^(-T/tau)` (0 without a lag).
    decay: [T; N_CANDIDATES],
    candidates: [Candidate<T>; N_CANDIDATES],
    /// The best candidate so far (an index of [`CANDIDATES`]).
    best: u8,
}

impl<T: Real> ActuatorBank<T> {
    /// A bank sampled every `period_s` \[s\] whose sums forget with time constant
    /// `memory_s` \[s\] (both > 0); no lag and the nominal valve until the data say
    /// otherwise.
    pub fn new(period_s: f64, memory_s: f64) -> Self {
        let c = T::of;
        let decay = CANDIDATES.map(|(_, tau)| {
            c(if tau > 0.0 {
                libm::exp(-period_s / tau)
            } else {
                0.0
            })
        });
        ActuatorBank {
            period_s: c(period_s),
            keep: c(libm::exp(-period_s / memory_s)),
            decay,
            candidates: [Candidate::default(); N_CANDIDATES],
            best: 0,
        }
    }

    /// The identified lag \[s\]: the candidate's solenoid lag plus its delay.
    pub fn lag_s(&self) -> T {
        if !self.informed() {
            return T::default();
        }
        let (delay, tau) = CANDIDATES[self.best as usize];
        T::of(tau) + T::of(delay as f64) * self.period_s
    }

    /// Whether the best candidate has seen [`MIN_INFORMATION`] (before, no lag and the
    /// nominal valve are assumed).
    fn informed(&self) -> bool {
        self.candidates[self.best as usize].qq > T::of(MIN_INFORMATION)
    }

    /// The identified pilot flow against the nominal valve's (1: nominal).
    pub fn ratio(&self) -> T {
        let (b, c) = (&self.candidates[self.best as usize], T::of);
        match self.informed() {
            true => (b.qy / b.qq).clamp(c(RATIO_RANGE.0), c(RATIO_RANGE.1)),
            false => c(1.0),
        }
    }

    /// One period: the pressure and stroke measured at its start `(p0, x0)` and end
    /// `(p, x)` (MPa, mm), the current `applied_a` held over it, the stroke's range
    /// `[0, x_max_mm]`.
    pub fn update(&mut self, (p0, x0): (T, T), (p, x): (T, T), applied_a: T, x_max_mm: T) {
        let c = T::of;
        let inside = |v: T| v > c(BOUND_MARGIN_MM) && v < x_max_mm - c(BOUND_MARGIN_MM);
        let used = inside(x0) && inside(x);
        // In the target's arithmetic (a single-precision FPU evaluates the bank in f32).
        let (p_pa, x_m) = ((p0 + p) * c(0.5e6), (x0 + x) * c(0.5e-3));
        let (measured, keep) = ((x - x0) / self.period_s, self.keep);
        let mut best: Option<(usize, T)> = None;
        for (j, cand) in self.candidates.iter_mut().enumerate() {
            let mean = match CANDIDATES[j] {
                // A delay of one period: the current applied the period before acts.
                (1, _) => core::mem::replace(&mut cand.current, applied_a),
                // The lagged current over the period, exact for a held input: its end,
                // and its mean `a - (a - start) tau/T (1 - e^(-T/tau))`.
                (_, tau) => {
                    let gap = applied_a - cand.current;
                    cand.current = applied_a - gap * self.decay[j];
                    applied_a - gap * c(tau) / self.period_s * (c(1.0) - self.decay[j])
                }
            };
            if used {
                let eq = &PumpEquations::THESIS;
                let neg = c(eq.phi) * mean - c(eq.k_a) * x_m < T::default();
                let q = eq.pilot(p_pa, x_m, mean, neg).q_a * c(1e3 / eq.a_a);
                cand.qy = keep * cand.qy + q * measured;
                cand.qq = keep * cand.qq + q * q;
            }
            // The residual sum of squares is the measured rates' (the same for every
            // candidate) less qy^2 / qq: the best candidate explains the most.
            if cand.qq > T::default() {
                let explained = cand.qy * cand.qy / cand.qq;
                if best.is_none_or(|(_, e)| explained > e) {
                    best = Some((j, explained));
                }
            }
        }
        if let Some((j, _)) = best {
            self.best = j as u8;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The stroke of the nominal pilot valve scaled by `ratio`, driven through a `lag_s`
    /// solenoid by a current that switches (a stroke loop's chatter), at 10 MPa:
    /// the bank finds the lag and the ratio.
    fn identified(lag_s: f64, ratio: f64, delayed: bool) -> (f64, f64) {
        let eq = PumpEquations::THESIS;
        let (dt, n_sub) = (0.005, 50);
        let mut bank = ActuatorBank::<f64>::new(0.005, 5.0);
        // The solenoid starts at rest, as the bank's candidates do.
        let (mut x, mut i_eff) = (0.008, 0.0);
        let mut seed = 12345u64;
        let (mut applied, mut previous) = (0.4, 0.0);
        for _ in 0..2000 {
            // A current that jumps at random within [0.3, 0.6] A, as a loop's chatter does.
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            if seed >> 62 == 0 {
                applied = 0.3 + 0.3 * ((seed >> 11) as f64 / (1u64 << 53) as f64);
            }
            let acting = if delayed { previous } else { applied };
            previous = applied;
            let x0 = x;
            let h = dt / n_sub as f64;
            for _ in 0..n_sub {
                i_eff += if lag_s > 0.0 {
                    h / lag_s * (acting - i_eff)
                } else {
                    acting - i_eff
                };
                let neg = eq.phi * i_eff - eq.k_a * x < 0.0;
                x += h * ratio * eq.pilot(10e6, x, i_eff, neg).q_a / eq.a_a;
            }
            bank.update((10.0, x0 * 1e3), (10.0, x * 1e3), applied, 24.0);
        }
        (bank.lag_s(), bank.ratio())
    }

    #[test]
    fn the_bank_finds_the_lag_and_the_valves_ratio() {
        for (lag, ratio) in [(0.0, 1.0), (0.005, 1.0), (0.02, 1.0), (0.0, 0.8), (0.02, 1.2)] {
            let (l, r) = identified(lag, ratio, false);
            assert_eq!(l, lag, "lag {lag}, ratio {ratio}: found lag {l}");
            assert!(
                (r - ratio).abs() < 0.03,
                "lag {lag}, ratio {ratio}: found ratio {r}"
            );
        }
    }

    #[test]
    fn a_delay_of_one_period_is_found_as_itself_not_as_a_fast_valve() {
        let (l, r) = identified(0.0, 1.0, true);
        assert_eq!(l, 0.005, "found lag {l}");
        assert!((r - 1.0).abs() < 0.03, "found ratio {r}");
    }

    #[test]
    fn a_stroke_at_its_bound_teaches_nothing() {
        let mut bank = ActuatorBank::<f64>::new(0.005, 5.0);
        for _ in 0..100 {
            bank.update((10.0, 0.0), (10.0, 0.0), 0.8, 24.0);
        }
        assert_eq!((bank.lag_s(), bank.ratio()), (0.0, 1.0));
    }
}
