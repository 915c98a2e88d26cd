//! How much an actuator moves: the figures a control engineer reads beside a tracking
//! error, from the command at each control instant (held until the next). Two
//! controllers with the same IAE are not equal if one of them chatters.

use serde::Serialize;

/// Control periods within which a command at one bound of its range, having been at the
/// other bound, counts as switching between the bounds (bang-bang).
pub const SWITCH_WINDOW: usize = 10;

/// An actuator's activity over a run (the command's units).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, schemars::JsonSchema)]
pub struct ActuatorActivity {
    /// Sum over the instants of |u(k) - u(k-1)|.
    pub total_variation: f64,
    /// RMS of u(k) - u(k-1) over the instants.
    pub rms_change_per_sample: f64,
    /// Time at a bound of the range \[s\].
    pub time_saturated_s: f64,
    /// Time at a bound reached from the other bound within [`SWITCH_WINDOW`] control
    /// periods \[s\]: bang-bang.
    pub time_switching_s: f64,
}

/// Builds [`ActuatorActivity`] one command at a time.
#[derive(Debug, Clone)]
pub struct ActivityCounter {
    lo: f64,
    hi: f64,
    period_s: f64,
    last: Option<f64>,
    tv: f64,
    sq: f64,
    changes: usize,
    saturated: usize,
    switching: usize,
    /// The last instant at a bound: (at the high bound, its index).
    last_bound: Option<(bool, usize)>,
    k: usize,
}

impl ActivityCounter {
    /// For a command held within `[lo, hi]` for `period_s` after each instant.
    pub fn new((lo, hi): (f64, f64), period_s: f64) -> Self {
        ActivityCounter {
            lo,
            hi,
            period_s,
            last: None,
            tv: 0.0,
            sq: 0.0,
            changes: 0,
            saturated: 0,
            switching: 0,
            last_bound: None,
            k: 0,
        }
    }

    /// The command `u` applied at the next instant.
    pub fn add(&mut self, u: f64) {
        if let Some(prev) = self.last {
            let d = u - prev;
            self.tv += d.abs();
            self.sq += d * d;
            self.changes += 1;
        }
        self.last = Some(u);
        let tol = 1e-9 * (self.hi - self.lo).abs();
        let bound = if u <= self.lo + tol {
            Some(false)
        } else if u >= self.hi - tol {
            Some(true)
        } else {
            None
        };
        if let Some(high) = bound {
            self.saturated += 1;
            if let Some((was_high, at)) = self.last_bound {
                if was_high != high && self.k - at <= SWITCH_WINDOW {
                    self.switching += 1;
                }
            }
            self.last_bound = Some((high, self.k));
        }
        self.k += 1;
    }

    /// The figures so far.
    pub fn finish(&self) -> ActuatorActivity {
        ActuatorActivity {
            total_variation: self.tv,
            rms_change_per_sample: (self.sq / self.changes.max(1) as f64).sqrt(),
            time_saturated_s: self.saturated as f64 * self.period_s,
            time_switching_s: self.switching as f64 * self.period_s,
        }
    }
}

/// The activity of the commands `u`, one per control instant.
pub fn activity(u: &[f64], range: (f64, f64), period_s: f64) -> ActuatorActivity {
    let mut c = ActivityCounter::new(range, period_s);
    u.iter().for_each(|&v| c.add(v));
    c.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_still_command_has_no_activity_and_bang_bang_is_told_from_saturation() {
        let still = activity(&[3.0; 50], (0.0, 10.0), 0.1);
        assert_eq!((still.total_variation, still.time_saturated_s), (0.0, 0.0));
        // Held at the top for 20 instants: saturated 2 s, never switching.
        let held = activity(&[10.0; 20], (0.0, 10.0), 0.1);
        assert!((held.time_saturated_s - 2.0).abs() < 1e-12 && held.time_switching_s == 0.0);
        // 0, 10, 0, 10, ...: every instant but the first is a switch; TV 10 per change.
        let bang: Vec<f64> = (0..20).map(|k| if k % 2 == 0 { 0.0 } else { 10.0 }).collect();
        let b = activity(&bang, (0.0, 10.0), 0.1);
        assert!((b.time_switching_s - 1.9).abs() < 1e-12, "{b:?}");
        assert!((b.total_variation - 190.0).abs() < 1e-9 && (b.rms_change_per_sample - 10.0).abs() < 1e-12);
        // A bound left for longer than the window before the other: not switching.
        let mut slow = vec![0.0; 1];
        slow.extend([5.0; 15]);
        slow.push(10.0);
        assert_eq!(activity(&slow, (0.0, 10.0), 0.1).time_switching_s, 0.0);
    }
}
