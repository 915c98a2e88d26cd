//! Signals as scenario files write them. The unit of every value is the one the
//! enclosing section names (`current_a`: A, `demand_dm3_s`: dm^3/s, `setpoint_mpa`:
//! MPa); times are in seconds.

use super::{PiecewiseLinear, Signal, Sine};
use crate::error::{invalid, Result};
use rand::{Rng, SeedableRng};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// One trapezoid of a demanded-flow series: from 0 up to `peak` at the slew rate,
/// held for `hold_s`, back to 0 at the slew rate.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Pulse {
    /// When the ramp up starts \[s\].
    pub start_s: f64,
    /// Peak value.
    pub peak: f64,
    /// Time at the peak \[s\].
    pub hold_s: f64,
}

/// A signal in a scenario file, tagged by `kind`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum SignalSpec {
    /// A constant value.
    Constant {
        /// The value.
        value: f64,
    },
    /// Straight lines through `[t_s, value]` points (equal times make a jump).
    PiecewiseLinear {
        /// `[t_s, value]` pairs, times non-decreasing.
        points: Vec<[f64; 2]>,
    },
    /// A value that jumps at given times.
    Steps {
        /// Value before the first step.
        initial: f64,
        /// `[t_s, new value]` pairs, times increasing.
        steps: Vec<[f64; 2]>,
    },
    /// A seeded pseudo-random binary sequence between `low` and `high`, one bit every
    /// `bit_s`, on `[start_s, end_s)`; `low` outside.
    Prbs {
        /// Start \[s\].
        start_s: f64,
        /// End \[s\].
        end_s: f64,
        /// Bit length \[s\].
        bit_s: f64,
        /// Low level.
        low: f64,
        /// High level.
        high: f64,
        /// Seed of the bit sequence.
        seed: u64,
    },
    /// An amplitude-modulated PRBS: a level drawn uniformly in `[low, high]` held for
    /// `hold_s`, then the next, on `[start_s, end_s)`, reached by ramps of `ramp_s`
    /// (0: jumps); `low` outside. The excitation nonlinear identification wants: every
    /// level of the operating range, not two.
    Aprbs {
        /// Start \[s\].
        start_s: f64,
        /// End \[s\].
        end_s: f64,
        /// How long each level is held \[s\].
        hold_s: f64,
        /// Ramp between levels \[s\] (default 0).
        #[serde(default)]
        ramp_s: f64,
        /// Lowest level.
        low: f64,
        /// Highest level.
        high: f64,
        /// Seed of the levels.
        seed: u64,
    },
    /// `offset` plus `n_sines` sines of equal amplitude at frequencies evenly spaced in
    /// `[f_min_hz, f_max_hz]`, with Schroeder phases (low crest factor), on
    /// `[start_s, end_s)`; `offset` outside.
    Multisine {
        /// Offset.
        offset: f64,
        /// Amplitude of each sine.
        amplitude: f64,
        /// Lowest frequency \[Hz\].
        f_min_hz: f64,
        /// Highest frequency \[Hz\].
        f_max_hz: f64,
        /// Number of sines.
        n_sines: usize,
        /// Start \[s\].
        start_s: f64,
        /// End \[s\].
        end_s: f64,
    },
    /// A series of trapezoids (demanded flow): ramps at `slew_per_s`.
    Trapezoids {
        /// Slew rate of the ramps \[unit/s\].
        slew_per_s: f64,
        /// The trapezoids, in time order, not overlapping.
        pulses: Vec<Pulse>,
    },
}

/// Limits the context puts on a signal (in the signal's unit).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Limits {
    /// Clip range: low.
    pub lo: f64,
    /// Clip range: high.
    pub hi: f64,
    /// Largest trapezoid slew rate allowed, and why.
    pub max_slew: Option<(f64, &'static str)>,
    /// Trapezoid peaks must be below this, and why.
    pub max_peak: Option<(f64, &'static str)>,
}

pub fn finite(field: &str, v: f64) -> Result<f64> {
    if v.is_finite() {
        Ok(v)
    } else {
        Err(invalid(field, v, "a finite number"))
    }
}

impl SignalSpec {
    /// Validate and build, naming fields under `field`; `si` converts the signal's
    /// unit to SI.
    pub fn build(&self, field: &str, si: f64, lim: Limits) -> Result<Signal> {
        let sig = match self {
            SignalSpec::Constant { value } => Signal::piecewise(
                PiecewiseLinear::constant(finite(&format!("{field}.value"), *value)?),
                lim.lo,
                lim.hi,
            ),
            SignalSpec::PiecewiseLinear { points } => {
                if points.is_empty() {
                    return Err(invalid(
                        format!("{field}.points"),
                        "[]",
                        "at least one [t_s, value] point",
                    ));
                }
                let mut prev = f64::NEG_INFINITY;
                for (k, p) in points.iter().enumerate() {
                    finite(&format!("{field}.points[{k}]"), p[1])?;
                    if !(p[0].is_finite() && p[0] >= prev) {
                        return Err(invalid(
                            format!("{field}.points[{k}][0]"),
                            p[0],
                            "a finite time not before the previous point's",
                        ));
                    }
                    prev = p[0];
                }
                Signal::piecewise(
                    PiecewiseLinear::new(points.iter().map(|p| (p[0], p[1])).collect()),
                    lim.lo,
                    lim.hi,
                )
            }
            SignalSpec::Steps { initial, steps } => {
                let mut pts = vec![(0.0, finite(&format!("{field}.initial"), *initial)?)];
                let mut prev = 0.0;
                let mut level = *initial;
                for (k, s) in steps.iter().enumerate() {
                    if !(s[0].is_finite() && s[0] > prev || (k == 0 && s[0] == 0.0)) {
                        return Err(invalid(
                            format!("{field}.steps[{k}][0]"),
                            s[0],
                            "a finite time >= 0, after the previous step's",
                        ));
                    }
                    finite(&format!("{field}.steps[{k}][1]"), s[1])?;
                    pts.push((s[0], level));
                    pts.push((s[0], s[1]));
                    level = s[1];
                    prev = s[0];
                }
                Signal::piecewise(PiecewiseLinear::new(pts), lim.lo, lim.hi)
            }
            SignalSpec::Prbs {
                start_s,
                end_s,
                bit_s,
                low,
                high,
                seed,
            } => prbs(field, start_s, end_s, bit_s, low, high, seed, lim)?,
            SignalSpec::Aprbs {
                start_s,
                end_s,
                hold_s,
                ramp_s,
                low,
                high,
                seed,
            } => aprbs(field, start_s, end_s, hold_s, ramp_s, low, high, seed, lim)?,
            SignalSpec::Multisine {
                offset,
                amplitude,
                f_min_hz,
                f_max_hz,
                n_sines,
                start_s,
                end_s,
            } => multisine(
                field, offset, amplitude, f_min_hz, f_max_hz, n_sines, start_s, end_s, lim,
            )?,
            SignalSpec::Trapezoids { slew_per_s, pulses } => trapezoids(field, slew_per_s, pulses, lim)?,
        };
        Ok(sig.scaled(si))
    }
}

pub fn window(field: &str, start: f64, end: f64) -> Result<()> {
    if !(start.is_finite() && start >= 0.0) {
        return Err(invalid(format!("{field}.start_s"), start, "a finite time >= 0"));
    }
    if !(end.is_finite() && end > start) {
        return Err(invalid(
            format!("{field}.end_s"),
            end,
            format!("a finite time after start_s = {start}"),
        ));
    }
    Ok(())
}

/// A pseudo-random binary sequence (`kind = "prbs"`).
#[allow(clippy::too_many_arguments)]
pub fn prbs(
    field: &str,
    start_s: &f64,
    end_s: &f64,
    bit_s: &f64,
    low: &f64,
    high: &f64,
    seed: &u64,
    lim: Limits,
) -> Result<Signal> {
    window(field, *start_s, *end_s)?;
    if !(bit_s.is_finite() && *bit_s > 0.0) {
        return Err(invalid(format!("{field}.bit_s"), bit_s, "a number > 0"));
    }
    if !(low.is_finite() && high.is_finite() && low <= high) {
        return Err(invalid(
            format!("{field}.high"),
            high,
            format!("a finite number >= low = {low}"),
        ));
    }
    let n_bits = ((end_s - start_s) / bit_s).ceil() as usize;
    if n_bits > 10_000_000 {
        return Err(invalid(
            format!("{field}.bit_s"),
            bit_s,
            "at most 10,000,000 bits in the window",
        ));
    }
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(*seed);
    let mut pts = vec![(0.0, *low)];
    let mut level = *low;
    for b in 0..n_bits {
        let t = (start_s + b as f64 * bit_s).min(*end_s);
        let next = if rng.gen::<bool>() { *high } else { *low };
        if next != level {
            pts.push((t, level));
            pts.push((t, next));
            level = next;
        }
    }
    if level != *low {
        pts.push((*end_s, level));
        pts.push((*end_s, *low));
    }
    Ok(Signal::piecewise(PiecewiseLinear::new(pts), lim.lo, lim.hi))
}

/// An amplitude-modulated PRBS (`kind = "aprbs"`).
#[allow(clippy::too_many_arguments)]
pub fn aprbs(
    field: &str,
    start_s: &f64,
    end_s: &f64,
    hold_s: &f64,
    ramp_s: &f64,
    low: &f64,
    high: &f64,
    seed: &u64,
    lim: Limits,
) -> Result<Signal> {
    window(field, *start_s, *end_s)?;
    if !(hold_s.is_finite() && *hold_s > 0.0) {
        return Err(invalid(format!("{field}.hold_s"), hold_s, "a number > 0"));
    }
    if !(ramp_s.is_finite() && *ramp_s >= 0.0 && ramp_s < hold_s) {
        return Err(invalid(
            format!("{field}.ramp_s"),
            ramp_s,
            format!("in [0, hold_s = {hold_s})"),
        ));
    }
    if !(low.is_finite() && high.is_finite() && low <= high) {
        return Err(invalid(
            format!("{field}.high"),
            high,
            format!("a finite number >= low = {low}"),
        ));
    }
    if (end_s - start_s) / hold_s > 1e6 {
        return Err(invalid(
            format!("{field}.hold_s"),
            hold_s,
            "at most 1,000,000 levels in the window",
        ));
    }
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(*seed);
    let mut pts = vec![(0.0, *low), (*start_s, *low)];
    let mut t = *start_s;
    while t < *end_s {
        let level = low + (high - low) * rng.gen::<f64>();
        pts.push(((t + ramp_s).min(*end_s), level));
        t += hold_s;
        pts.push((t.min(*end_s), level));
    }
    pts.push(((end_s + ramp_s).max(*end_s), *low));
    Ok(Signal::piecewise(PiecewiseLinear::new(pts), lim.lo, lim.hi))
}

/// A Schroeder-phased multisine (`kind = "multisine"`).
#[allow(clippy::too_many_arguments)]
pub fn multisine(
    field: &str,
    offset: &f64,
    amplitude: &f64,
    f_min_hz: &f64,
    f_max_hz: &f64,
    n_sines: &usize,
    start_s: &f64,
    end_s: &f64,
    lim: Limits,
) -> Result<Signal> {
    window(field, *start_s, *end_s)?;
    finite(&format!("{field}.offset"), *offset)?;
    if !(amplitude.is_finite() && *amplitude >= 0.0) {
        return Err(invalid(
            format!("{field}.amplitude"),
            amplitude,
            "a finite number >= 0",
        ));
    }
    if !(f_min_hz.is_finite() && *f_min_hz > 0.0) {
        return Err(invalid(format!("{field}.f_min_hz"), f_min_hz, "a number > 0"));
    }
    if !(f_max_hz.is_finite() && f_max_hz >= f_min_hz) {
        return Err(invalid(
            format!("{field}.f_max_hz"),
            f_max_hz,
            format!("a number >= f_min_hz = {f_min_hz}"),
        ));
    }
    if !(1..=1000).contains(n_sines) {
        return Err(invalid(
            format!("{field}.n_sines"),
            n_sines,
            "an integer in [1, 1000]",
        ));
    }
    let n = *n_sines;
    let sines = (0..n)
        .map(|k| Sine {
            amplitude: *amplitude,
            freq_hz: if n == 1 {
                *f_min_hz
            } else {
                f_min_hz + (f_max_hz - f_min_hz) * k as f64 / (n - 1) as f64
            },
            phase: -PI * (k * (k + 1)) as f64 / n as f64,
        })
        .collect();
    Ok(
        Signal::piecewise(PiecewiseLinear::constant(*offset), lim.lo, lim.hi)
            .with_sines(sines, *start_s, *end_s),
    )
}

/// Trapezoidal pulses (`kind = "trapezoids"`).
#[allow(clippy::too_many_arguments)]
pub fn trapezoids(field: &str, slew_per_s: &f64, pulses: &[Pulse], lim: Limits) -> Result<Signal> {
    let f = format!("{field}.slew_per_s");
    if !(slew_per_s.is_finite() && *slew_per_s > 0.0) {
        return Err(invalid(f, slew_per_s, "a number > 0"));
    }
    if let Some((max, why)) = lim.max_slew {
        if *slew_per_s > max * (1.0 + 1e-12) {
            return Err(invalid(f, slew_per_s, format!("at most {max} ({why})")));
        }
    }
    let mut pts = vec![(0.0, 0.0)];
    let mut free_from = 0.0;
    for (k, p) in pulses.iter().enumerate() {
        let pf = |name: &str| format!("{field}.pulses[{k}].{name}");
        if !(p.start_s.is_finite() && p.start_s >= free_from) {
            return Err(invalid(
                pf("start_s"),
                p.start_s,
                format!("a time >= {free_from} s (pulses in order, not overlapping)"),
            ));
        }
        if !(p.peak.is_finite() && p.peak > 0.0) {
            return Err(invalid(pf("peak"), p.peak, "a number > 0"));
        }
        if let Some((max, why)) = lim.max_peak {
            if p.peak >= max {
                return Err(invalid(pf("peak"), p.peak, format!("below {max} ({why})")));
            }
        }
        if !(p.hold_s.is_finite() && p.hold_s >= 0.0) {
            return Err(invalid(pf("hold_s"), p.hold_s, "a number >= 0"));
        }
        let ramp = p.peak / slew_per_s;
        let t1 = p.start_s + ramp;
        let t2 = t1 + p.hold_s;
        let t3 = t2 + ramp;
        pts.extend([(p.start_s, 0.0), (t1, p.peak), (t2, p.peak), (t3, 0.0)]);
        free_from = t3;
    }
    Ok(Signal::piecewise(PiecewiseLinear::new(pts), lim.lo, lim.hi))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lim() -> Limits {
        Limits {
            lo: 0.0,
            hi: 2.1,
            max_slew: Some((2.0, "Qdot_max")),
            max_peak: Some((2.1, "max pump flow")),
        }
    }

    #[test]
    fn trapezoid_shape_and_limits() {
        let s = SignalSpec::Trapezoids {
            slew_per_s: 2.0,
            pulses: vec![Pulse {
                start_s: 1.0,
                peak: 1.8,
                hold_s: 2.0,
            }],
        };
        let sig = s.build("demand_dm3_s", 1.0, lim()).unwrap();
        assert_eq!(sig.eval(1.0), 0.0);
        assert!((sig.eval(1.45) - 0.9).abs() < 1e-12);
        assert!((sig.eval(2.9) - 1.8).abs() < 1e-12);
        assert!((sig.eval(4.35) - 0.9).abs() < 1e-12);
        assert_eq!(sig.eval(5.0), 0.0);

        let too_fast = SignalSpec::Trapezoids {
            slew_per_s: 2.5,
            pulses: vec![],
        };
        let e = too_fast
            .build("demand_dm3_s", 1.0, lim())
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            "invalid value: `demand_dm3_s.slew_per_s` = 2.5 is not allowed: at most 2 (Qdot_max)"
        );
        let too_high = SignalSpec::Trapezoids {
            slew_per_s: 2.0,
            pulses: vec![Pulse {
                start_s: 1.0,
                peak: 2.1,
                hold_s: 2.0,
            }],
        };
        let e = too_high
            .build("demand_dm3_s", 1.0, lim())
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("`demand_dm3_s.pulses[0].peak` = 2.1") && e.contains("below 2.1"),
            "{e}"
        );
        let overlap = SignalSpec::Trapezoids {
            slew_per_s: 2.0,
            pulses: vec![
                Pulse {
                    start_s: 1.0,
                    peak: 1.0,
                    hold_s: 2.0,
                },
                Pulse {
                    start_s: 3.0,
                    peak: 1.0,
                    hold_s: 2.0,
                },
            ],
        };
        assert!(overlap
            .build("d", 1.0, lim())
            .unwrap_err()
            .to_string()
            .contains("pulses[1].start_s"));
    }

    #[test]
    fn prbs_is_seeded_and_binary_and_aprbs_holds_drawn_levels() {
        let a = SignalSpec::Aprbs {
            start_s: 10.0,
            end_s: 110.0,
            hold_s: 20.0,
            ramp_s: 2.0,
            low: 1.0,
            high: 9.0,
            seed: 3,
        }
        .build(
            "input.voltage",
            1.0,
            Limits {
                lo: 0.0,
                hi: 10.0,
                max_slew: None,
                max_peak: None,
            },
        )
        .unwrap();
        // Low before the start, five held levels in [1, 9] (each a different draw),
        // ramps of 2 s between them, low again after the end.
        assert_eq!(a.eval(5.0), 1.0);
        let levels: Vec<f64> = (0..5).map(|k| a.eval(10.0 + 20.0 * k as f64 + 10.0)).collect();
        assert!(levels.iter().all(|v| (1.0..=9.0).contains(v)), "{levels:?}");
        assert!(levels.windows(2).all(|w| w[0] != w[1]), "{levels:?}");
        assert_eq!(a.eval(10.0 + 20.0 + 1.0), 0.5 * (levels[0] + levels[1]));
        assert_eq!(a.eval(120.0), 1.0);
        let s = SignalSpec::Prbs {
            start_s: 0.0,
            end_s: 10.0,
            bit_s: 0.1,
            low: 0.2,
            high: 0.6,
            seed: 7,
        };
        let a = s
            .build(
                "c",
                1.0,
                Limits {
                    lo: 0.0,
                    hi: 0.8,
                    max_slew: None,
                    max_peak: None,
                },
            )
            .unwrap();
        let b = s
            .build(
                "c",
                1.0,
                Limits {
                    lo: 0.0,
                    hi: 0.8,
                    max_slew: None,
                    max_peak: None,
                },
            )
            .unwrap();
        assert_eq!(a, b);
        let vals: Vec<f64> = (0..100).map(|k| a.eval(k as f64 * 0.1 + 0.05)).collect();
        assert!(vals.iter().all(|&v| v == 0.2 || v == 0.6));
        let highs = vals.iter().filter(|&&v| v == 0.6).count();
        assert!((30..70).contains(&highs), "{highs}");
        assert_eq!(a.eval(10.5), 0.2);
    }
}
