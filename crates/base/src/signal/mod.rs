//! Input signals: piecewise-linear profiles (with jumps), steps, PRBS, multisines and
//! demanded-flow trapezoids, each clipped to a range.
//!
//! A signal is evaluated per *segment*: the solver selects the segment at the start of
//! every step ([`Signal::segment`]) and lands on every breakpoint
//! ([`Signal::next_breakpoint`]), so within a step the input is one smooth formula and
//! a jump never sits inside a step.

mod spec;
pub use spec::Limits;
pub use spec::{Pulse, SignalSpec};

/// Limits a context puts on a signal spec: clip range, largest trapezoid slew, and the
/// bound trapezoid peaks must stay below (each with the reason shown in errors).
pub fn spec_limits(
    lo: f64,
    hi: f64,
    max_slew: Option<(f64, &'static str)>,
    max_peak: Option<(f64, &'static str)>,
) -> Limits {
    Limits {
        lo,
        hi,
        max_slew,
        max_peak,
    }
}

use std::f64::consts::PI;

/// Points `(t_k, v_k)` joined by straight lines; equal consecutive times make a jump.
/// Before the first point and after the last the value is held.
#[derive(Debug, Clone, PartialEq)]
pub struct PiecewiseLinear {
    t: Vec<f64>,
    v: Vec<f64>,
    /// Slope of segment j (between points j-1 and j) at index j; 0 for jumps and the
    /// held ends.
    slope: Vec<f64>,
}

impl PiecewiseLinear {
    /// From points with non-decreasing times (checked by the spec layer).
    pub fn new(points: Vec<(f64, f64)>) -> Self {
        debug_assert!(points.windows(2).all(|w| w[0].0 <= w[1].0));
        let (t, v) = points.into_iter().unzip();
        Self::with_slopes(t, v)
    }

    fn with_slopes(t: Vec<f64>, v: Vec<f64>) -> Self {
        let n = t.len();
        let slope = (0..=n)
            .map(|j| {
                if j == 0 || j >= n || t[j] == t[j - 1] {
                    0.0
                } else {
                    // A ramp too short for its slope to be a number (5e-324 s) is a step
                    // at its end: its slope would make the signal NaN.
                    let s = (v[j] - v[j - 1]) / (t[j] - t[j - 1]);
                    if s.is_finite() {
                        s
                    } else {
                        0.0
                    }
                }
            })
            .collect();
        PiecewiseLinear { t, v, slope }
    }

    /// A constant.
    pub fn constant(v: f64) -> Self {
        Self::with_slopes(vec![0.0], vec![v])
    }

    /// Segment index at `t` (right-continuous): 0 before the first point, `n` after the
    /// last, `j` between points `j-1` and `j`.
    #[inline]
    pub fn segment(&self, t: f64) -> usize {
        self.t.partition_point(|&tk| tk <= t)
    }

    /// Value of segment `seg`'s formula at `t` (extended beyond its ends).
    #[inline]
    pub fn eval_in(&self, seg: usize, t: f64) -> f64 {
        let n = self.t.len();
        if seg == 0 {
            self.v[0]
        } else if seg >= n {
            self.v[n - 1]
        } else {
            self.v[seg - 1] + self.slope[seg] * (t - self.t[seg - 1])
        }
    }

    /// First breakpoint strictly after `t`, or infinity.
    #[inline]
    pub fn next_breakpoint(&self, t: f64) -> f64 {
        let k = self.t.partition_point(|&tk| tk <= t);
        self.t.get(k).copied().unwrap_or(f64::INFINITY)
    }

    /// The points.
    pub fn points(&self) -> impl Iterator<Item = (f64, f64)> + '_ {
        self.t.iter().copied().zip(self.v.iter().copied())
    }
}

/// One segment of a signal without sines: `(v0 + slope (t - t0))` clipped to
/// `[lo, hi]`, the arithmetic of [`Signal::eval_in`] in the same order (a solver's
/// right-hand side evaluates it at every stage; the segment lookups once per step).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Affine {
    /// Value at `t0`.
    pub v0: f64,
    /// Slope (per second).
    pub slope: f64,
    /// Start time \[s\].
    pub t0: f64,
    /// Clip range.
    pub lo: f64,
    /// Clip range.
    pub hi: f64,
}

impl Affine {
    /// A constant (not clipped).
    pub fn constant(v: f64) -> Self {
        Affine {
            v0: v,
            slope: 0.0,
            t0: 0.0,
            lo: f64::NEG_INFINITY,
            hi: f64::INFINITY,
        }
    }

    /// Value at `t`.
    #[inline(always)]
    pub fn at(&self, t: f64) -> f64 {
        (self.v0 + self.slope * (t - self.t0)).clamp(self.lo, self.hi)
    }
}

/// One sine of a multisine.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sine {
    /// Amplitude.
    pub amplitude: f64,
    /// Frequency \[Hz\].
    pub freq_hz: f64,
    /// Phase \[rad\].
    pub phase: f64,
}

/// A signal: a piecewise-linear part plus a sum of sines active on `[on_s, off_s)`,
/// clipped to `[lo, hi]`.
#[derive(Debug, Clone, PartialEq)]
pub struct Signal {
    pwl: PiecewiseLinear,
    sines: Vec<Sine>,
    on_s: f64,
    off_s: f64,
    lo: f64,
    hi: f64,
}

impl Signal {
    /// A piecewise-linear signal clipped to `[lo, hi]`.
    pub fn piecewise(pwl: PiecewiseLinear, lo: f64, hi: f64) -> Self {
        Signal {
            pwl,
            sines: Vec::new(),
            on_s: 0.0,
            off_s: 0.0,
            lo,
            hi,
        }
    }

    /// A constant (not clipped).
    pub fn constant(v: f64) -> Self {
        Self::piecewise(PiecewiseLinear::constant(v), f64::NEG_INFINITY, f64::INFINITY)
    }

    /// Add sines, active on `[on_s, off_s)`.
    pub fn with_sines(mut self, sines: Vec<Sine>, on_s: f64, off_s: f64) -> Self {
        self.sines = sines;
        self.on_s = on_s;
        self.off_s = off_s;
        self
    }

    /// Scale every value (a unit conversion), including the clip range.
    pub fn scaled(mut self, k: f64) -> Self {
        self.pwl.v.iter_mut().for_each(|v| *v *= k);
        self.pwl.slope.iter_mut().for_each(|v| *v *= k);
        self.sines.iter_mut().for_each(|s| s.amplitude *= k);
        self.lo *= k;
        self.hi *= k;
        self
    }

    /// Segment at `t` (see the module doc).
    #[inline]
    pub fn segment(&self, t: f64) -> usize {
        let s = self.pwl.segment(t);
        // The multisine's window edges are breakpoints too: encode "inside" in bit 0.
        (s << 1) | usize::from(!self.sines.is_empty() && t >= self.on_s && t < self.off_s)
    }

    /// Segment `seg`'s formula as an [`Affine`] (None where the multisine is on):
    /// [`Affine::at`] then gives exactly [`Signal::eval_in`], without the lookups.
    pub fn affine_in(&self, seg: usize) -> Option<Affine> {
        if seg & 1 == 1 {
            return None;
        }
        let (p, j) = (&self.pwl, seg >> 1);
        let n = p.t.len();
        let (v0, slope, t0) = if j == 0 {
            (p.v[0], 0.0, 0.0)
        } else if j >= n {
            (p.v[n - 1], 0.0, 0.0)
        } else {
            (p.v[j - 1], p.slope[j], p.t[j - 1])
        };
        Some(Affine {
            v0,
            slope,
            t0,
            lo: self.lo,
            hi: self.hi,
        })
    }

    /// Value in segment `seg` at `t`, clipped.
    #[inline]
    pub fn eval_in(&self, seg: usize, t: f64) -> f64 {
        let mut v = self.pwl.eval_in(seg >> 1, t);
        if seg & 1 == 1 {
            for s in &self.sines {
                v += s.amplitude * (2.0 * PI * s.freq_hz * t + s.phase).sin();
            }
        }
        v.clamp(self.lo, self.hi)
    }

    /// Value at `t`.
    #[inline]
    pub fn eval(&self, t: f64) -> f64 {
        self.eval_in(self.segment(t), t)
    }

    /// First breakpoint strictly after `t`, or infinity.
    #[inline]
    pub fn next_breakpoint(&self, t: f64) -> f64 {
        let mut b = self.pwl.next_breakpoint(t);
        if !self.sines.is_empty() {
            for e in [self.on_s, self.off_s] {
                if e > t && e < b {
                    b = e;
                }
            }
        }
        b
    }

    /// Whether the unclipped signal leaves `[lo, hi]` somewhere on `[0, t_end]`, for a
    /// warning: exactly for a piecewise-linear profile, on a 1 ms grid with sines.
    pub fn clips_on(&self, t_end: f64) -> bool {
        let outside = |v: f64| v < self.lo - 1e-12 || v > self.hi + 1e-12;
        if self.sines.is_empty() {
            // Piecewise linear: its extremes on [0, t_end] are at the ends of its
            // segments (each segment's formula at both ends, cut at t_end) or at 0.
            let p = &self.pwl;
            let at = |seg: usize, t: f64| outside(p.eval_in(seg, t));
            return at(p.segment(0.0), 0.0)
                || at(p.segment(t_end), t_end)
                || (1..p.t.len())
                    .filter(|&j| p.t[j - 1] <= t_end)
                    .any(|j| at(j, p.t[j - 1]) || at(j, p.t[j].min(t_end)));
        }
        let n = (t_end / 1e-3).ceil() as usize;
        (0..=n).any(|k| {
            let t = (k as f64 * 1e-3).min(t_end);
            let seg = self.segment(t);
            let mut v = self.pwl.eval_in(seg >> 1, t);
            if seg & 1 == 1 {
                v += self
                    .sines
                    .iter()
                    .map(|s| s.amplitude * (2.0 * PI * s.freq_hz * t + s.phase).sin())
                    .sum::<f64>();
            }
            outside(v)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_ramp_too_short_for_its_slope_is_a_step_not_nan() {
        // Found by the mutation sweep: an input ramp of 5e-324 s made the run's input NaN.
        let p = PiecewiseLinear::new(vec![(0.0, 1.0), (5e-324, 3.0), (2.0, 3.0)]);
        let s = Signal::piecewise(p, f64::NEG_INFINITY, f64::INFINITY);
        for t in [0.0, 5e-324, 1e-300, 1.0, 3.0] {
            assert!(s.eval(t).is_finite(), "t = {t}: {}", s.eval(t));
        }
        assert_eq!(s.eval(0.0), 1.0);
        assert_eq!(s.eval(1.0), 3.0);
    }

    #[test]
    fn piecewise_linear_segments_jumps_and_breakpoints() {
        let p = PiecewiseLinear::new(vec![(0.0, 0.0), (1.0, 2.0), (1.0, 5.0), (3.0, 5.0)]);
        let s = Signal::piecewise(p, f64::NEG_INFINITY, f64::INFINITY);
        assert_eq!(s.eval(0.5), 1.0);
        assert_eq!(s.eval(1.0), 5.0); // right-continuous at the jump
                                      // The segment before the jump, extended to the jump, gives the left limit.
        assert_eq!(s.eval_in(s.segment(0.999), 1.0), 2.0);
        assert_eq!(s.eval(10.0), 5.0);
        assert_eq!(s.eval(-1.0), 0.0);
        assert_eq!(s.next_breakpoint(0.0), 1.0);
        assert_eq!(s.next_breakpoint(1.0), 3.0);
        assert_eq!(s.next_breakpoint(3.0), f64::INFINITY);
    }

    #[test]
    fn clipping_and_sines() {
        let s = Signal::piecewise(PiecewiseLinear::constant(0.4), 0.0, 0.8).with_sines(
            vec![Sine {
                amplitude: 0.6,
                freq_hz: 1.0,
                phase: 0.0,
            }],
            1.0,
            2.0,
        );
        assert_eq!(s.eval(0.5), 0.4);
        assert!((s.eval(1.25) - 0.8).abs() < 1e-12); // 0.4 + 0.6 clipped
        assert!((s.eval(1.75) - 0.0).abs() < 1e-12);
        assert_eq!(s.eval(2.5), 0.4);
        assert_eq!(s.next_breakpoint(0.0), 1.0);
        assert_eq!(s.next_breakpoint(1.0), 2.0);
        assert!(s.clips_on(3.0));
    }

    #[test]
    fn a_segments_affine_form_gives_exactly_its_value_and_none_where_sines_act() {
        let p = PiecewiseLinear::new(vec![(0.5, 0.1), (1.0, 0.7), (1.0, 0.2), (3.0, 0.9), (4.0, -0.3)]);
        let s = Signal::piecewise(p, 0.0, 0.8).with_sines(
            vec![Sine {
                amplitude: 0.05,
                freq_hz: 3.0,
                phase: 0.2,
            }],
            3.5,
            3.7,
        );
        let mut with_sines = 0;
        for k in 0..=6000 {
            let t = k as f64 * 1e-3 - 0.5;
            let seg = s.segment(t);
            match s.affine_in(seg) {
                // Bit for bit, at the segment's own points and past its ends.
                Some(a) => {
                    for tt in [t, t + 0.37e-3, t + 0.1] {
                        assert_eq!(a.at(tt).to_bits(), s.eval_in(seg, tt).to_bits(), "t = {tt}");
                    }
                }
                None => {
                    assert!((3.5..3.7).contains(&t), "t = {t}");
                    with_sines += 1;
                }
            }
        }
        assert_eq!(with_sines, 200);
        assert_eq!(Affine::constant(0.3).at(12.0), 0.3);
    }
}
