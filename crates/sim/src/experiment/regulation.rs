//! A run's figures accumulated step by step on the solver's dense output, on any plant:
//! the regulated state's errors against its set-point (IAE, ISE, deviations, the time
//! within 1 %, each set-point step's overshoot), the time the driven input spent at a
//! bound, every plant state's range, and the time a state spent below its floor (the
//! pump's P_min). They do not depend on the output interval or the control period:
//! time-weighted figures are integrated with 3-point Gauss-Legendre quadrature on each
//! step (split where the set-point has a breakpoint and where a settling window ends), the time below the floor from the located crossings, extremes from the step
//! ends and the Gauss points.

use super::integrated::Integrated;
use super::plant_summary::FloorFigures;
use super::quadrature::{Scale, GAUSS};
use crate::plant::Plant;
use crate::signal::Signal;
use rhonn_ode::Dopri5;

/// What a [`Tracker`] follows on a plant.
pub(super) struct Tracked<'a> {
    /// The regulated state and its set-point (None: no set-point, ranges and floor only).
    pub(super) regulated: Option<(usize, &'a Signal)>,
    /// The unit of the regulated state's errors, applied at each point.
    pub(super) display: Scale,
    /// A state's lower working limit (SI; the pump's P_min on its pressure).
    pub(super) floor: Option<(usize, f64)>,
    /// Each plant state's bounds (SI): the dense interpolant, which may pass a bound the
    /// step ends on by a hair, is clamped to them.
    pub(super) bounds: Vec<(f64, f64)>,
    /// The driven input and its range (SI): the time at a bound.
    pub(super) input: Option<(usize, (f64, f64))>,
    /// The settling time \[s\] ([`crate::plant::Plant::settle_s`]).
    pub(super) settle_s: f64,
}

/// The figures of one run, accumulated step by step.
pub(super) struct Tracker<'a> {
    of: Tracked<'a>,
    /// Times where an interval must be split, sorted; `cursor` is the next one.
    splits: Vec<f64>,
    cursor: usize,
    /// Set-point breakpoints (sorted) for the settling windows.
    changes: Vec<f64>,
    /// Each followed plant state's smallest and largest value over the points (infinite
    /// for the others).
    pub(super) lo: Vec<f64>,
    pub(super) hi: Vec<f64>,
    pub(super) below: f64,
    /// Of `below`, the time from the settling time on (the start's transient excluded).
    pub(super) below_after_settle: f64,
    pub(super) ise: f64,
    pub(super) max_dev: f64,
    pub(super) max_dev_settled: f64,
    pub(super) saturated: f64,
    pub(super) iae: f64,
    /// max |y - r| from a tenth of the settling time after each set-point change on.
    pub(super) max_dev_0_1: f64,
    pub(super) within: f64,
    /// Per set-point step after t = 0: (time, old value, new value, largest overshoot %).
    pub(super) steps: Vec<(f64, f64, f64, f64)>,
    /// The plant states at the five points of the current interval (those
    /// [`Tracker::tracks`]; the others stay 0).
    xs: Vec<[f64; 5]>,
    /// Whether a state is followed: the regulated state, the floor's, and each bounded
    /// one (an unbounded state without a role costs nothing).
    tracks: Vec<bool>,
}

impl Tracker<'static> {
    /// A tracker of `plant`'s floor alone over a run to `t_end` (an open loop's or an
    /// identification's); None for a plant without a floor.
    pub(super) fn of_floor<P: Plant>(plant: &P, t_end: f64) -> Option<Self> {
        let floor = plant.floor()?;
        let of = Tracked {
            regulated: None,
            display: Scale(1.0),
            floor: Some(floor),
            bounds: plant.state_bounds(),
            input: None,
            settle_s: plant.settle_s(),
        };
        Some(Tracker::new(of, t_end))
    }
}

impl<'a> Tracker<'a> {
    /// The floor's figures (display units of `states`, the plant's), if it follows one.
    pub(super) fn floor_figures(&self, states: &[crate::plant::Quantity]) -> Option<FloorFigures> {
        let (i, limit) = self.of.floor?;
        let q = states.get(i)?;
        Some(FloorFigures {
            state: q.name,
            unit: q.display_unit,
            floor: q.to_display(limit),
            time_below_s: self.below,
            settle_s: self.of.settle_s,
            time_below_after_settle_s: self.below_after_settle,
        })
    }

    /// The tracker of `of` over a run to `t_end`.
    pub(super) fn new(of: Tracked<'a>, t_end: f64) -> Self {
        let setpoint = of.regulated.map(|(_, sp)| sp);
        let mut changes = vec![0.0];
        // The floor's figure after the settling time needs an interval edge there.
        let mut splits: Vec<f64> = of.floor.map(|_| of.settle_s).into_iter().collect();
        if let Some(sp) = setpoint {
            let mut t = 0.0;
            loop {
                let b = sp.next_breakpoint(t);
                if !(b < t_end) {
                    break;
                }
                changes.push(b);
                t = b;
            }
            for &c in &changes {
                splits.push(c);
                splits.push(c + of.settle_s);
            }
        }
        let steps = match setpoint {
            Some(sp) => changes[1..]
                .iter()
                .map(|&c| (c, sp.eval(c - 1e-9), sp.eval(c + 1e-9), 0.0))
                .collect(),
            None => Vec::new(),
        };
        splits.retain(|&v| v > 0.0 && v < t_end);
        splits.sort_by(f64::total_cmp);
        splits.dedup();
        let n = of.bounds.len();
        let tracks = (0..n)
            .map(|i| {
                of.regulated.is_some_and(|(y, _)| y == i)
                    || of.floor.is_some_and(|(f, _)| f == i)
                    || of.bounds[i].0.is_finite()
                    || of.bounds[i].1.is_finite()
            })
            .collect();
        Tracker {
            tracks,
            of,
            splits,
            cursor: 0,
            changes,
            lo: vec![f64::INFINITY; n],
            hi: vec![f64::NEG_INFINITY; n],
            below: 0.0,
            below_after_settle: 0.0,
            ise: 0.0,
            max_dev: 0.0,
            max_dev_settled: 0.0,
            saturated: 0.0,
            iae: 0.0,
            max_dev_0_1: 0.0,
            within: 0.0,
            steps,
            xs: vec![[0.0; 5]; n],
        }
    }

    /// Whether every plant state stayed within its bounds over the points.
    pub(super) fn states_bounded(&self) -> bool {
        self.of
            .bounds
            .iter()
            .zip(self.lo.iter().zip(&self.hi))
            .all(|(b, (lo, hi))| *lo >= b.0 && *hi <= b.1 * (1.0 + 1e-12))
    }

    /// Account for the last step `[t_prev, t]` of `solver`.
    pub(super) fn add_step<S: Integrated>(&mut self, solver: &Dopri5<S>) {
        let (t0, t1) = (solver.t_prev(), solver.t());
        if !(t1 > t0) {
            return;
        }
        while self.cursor < self.splits.len() && self.splits[self.cursor] <= t0 {
            self.cursor += 1;
        }
        let mut a = t0;
        let mut k = self.cursor;
        while k < self.splits.len() && self.splits[k] < t1 {
            self.add_interval(solver, a, self.splits[k]);
            a = self.splits[k];
            k += 1;
        }
        self.add_interval(solver, a, t1);
    }

    /// Plant state `i` at `t` in the last step, clamped to its bounds.
    fn state_at<S: Integrated>(&self, solver: &Dopri5<S>, i: usize, t: f64) -> f64 {
        let b = self.of.bounds[i];
        solver.dense_component(i).at(solver.theta_of(t)).clamp(b.0, b.1)
    }

    /// `[a, b]` lies in one step, one set-point segment and one settling window.
    fn add_interval<S: Integrated>(&mut self, solver: &Dopri5<S>, a: f64, b: f64) {
        let h = b - a;
        if !(h > 0.0) {
            return;
        }
        let ts = [a, a + GAUSS[0].0 * h, a + GAUSS[1].0 * h, a + GAUSS[2].0 * h, b];
        let thetas = ts.map(|t| solver.theta_of(t));
        let each = self.xs.iter_mut().zip(&self.tracks).zip(&self.of.bounds);
        for (i, ((xs, _), b)) in each.enumerate().filter(|(_, ((_, t), _))| **t) {
            let d = solver.dense_component(i);
            for (x, th) in xs.iter_mut().zip(thetas) {
                *x = d.at(th).clamp(b.0, b.1);
            }
        }
        for (((xs, lo), hi), _) in self
            .xs
            .iter()
            .zip(&mut self.lo)
            .zip(&mut self.hi)
            .zip(&self.tracks)
            .filter(|(_, t)| **t)
        {
            for &x in xs {
                *lo = lo.min(x);
                *hi = hi.max(x);
            }
        }
        if let Some((y, sp)) = self.of.regulated {
            let mid = 0.5 * (a + b);
            let sg = sp.segment(mid);
            let settled = {
                let last_change = self
                    .changes
                    .iter()
                    .rev()
                    .find(|&&c| c <= mid)
                    .copied()
                    .unwrap_or(0.0);
                mid >= last_change + self.of.settle_s
            };
            let pts: [(f64, f64); 5] = std::array::from_fn(|k| (ts[k], self.xs[y][k]));
            // The set-point at the five points, evaluated once.
            let r = pts.map(|(t, _)| sp.eval_in(sg, t));
            let display = self.of.display;
            for (&(_, p), &rk) in pts.iter().zip(&r) {
                let dev = display.apply((p - rk).abs());
                self.max_dev = self.max_dev.max(dev);
                if settled {
                    self.max_dev_settled = self.max_dev_settled.max(dev);
                }
            }
            self.add_tracking(&pts, &r, mid);
            let inner = || GAUSS.iter().zip(&pts[1..4]).zip(&r[1..4]);
            self.iae += h * inner()
                .map(|(((_, w), &(_, p)), &rk)| w * display.apply((p - rk).abs()))
                .sum::<f64>();
            self.ise += h * inner()
                .map(|(((_, w), &(_, p)), &rk)| w * display.apply(p - rk).powi(2))
                .sum::<f64>();
            if let Some((k, (lo, hi))) = self.of.input {
                let u = solver.system().plant().input_at(mid, k);
                if u <= lo || u >= hi {
                    self.saturated += h;
                }
            }
        }
        if let Some((i, limit)) = self.of.floor {
            let below = self.time_below(solver, i, limit, &ts, self.xs[i]);
            self.below += below;
            if a >= self.of.settle_s {
                self.below_after_settle += below;
            }
        }
    }

    /// Time below `limit` of state `i` (`xs` at the five points `ts`) over the
    /// sub-intervals between the points, the crossings located by bisection on the dense
    /// output.
    fn time_below<S: Integrated>(
        &self,
        solver: &Dopri5<S>,
        i: usize,
        limit: f64,
        ts: &[f64; 5],
        xs: [f64; 5],
    ) -> f64 {
        let mut below = 0.0;
        for k in 0..4 {
            let ((ta, pa), (tb, pb)) = ((ts[k], xs[k]), (ts[k + 1], xs[k + 1]));
            let (ba, bb) = (pa < limit, pb < limit);
            if ba && bb {
                below += tb - ta;
            } else if ba != bb {
                let (mut lo, mut hi) = (ta, tb);
                while hi - lo > 1e-10 * (1.0 + hi.abs()) {
                    let m = 0.5 * (lo + hi);
                    if (self.state_at(solver, i, m) < limit) == ba {
                        lo = m;
                    } else {
                        hi = m;
                    }
                }
                let tc = 0.5 * (lo + hi);
                below += if ba { tc - ta } else { tb - tc };
            }
        }
        below
    }

    /// The tracking figures of one interval's five points (`r`: the set-point there).
    fn add_tracking(&mut self, pts: &[(f64, f64); 5], r: &[f64; 5], mid: f64) {
        let step = self.steps.iter().rposition(|s| s.0 <= mid);
        let last_change = step.map_or(0.0, |k| self.steps[k].0);
        // Signed distance outside the 1 % band (< 0 inside).
        let out: [f64; 5] = std::array::from_fn(|k| (pts[k].1 - r[k]).abs() - 0.01 * r[k].abs());
        for k in 0..4 {
            let (dt, da, db) = (pts[k + 1].0 - pts[k].0, out[k], out[k + 1]);
            self.within += match (da <= 0.0, db <= 0.0) {
                (true, true) => dt,
                (false, false) => 0.0,
                // One crossing, located linearly between the points.
                (true, false) => dt * da / (da - db),
                (false, true) => dt * db / (db - da),
            };
        }
        let display = self.of.display;
        for (&(t, p), &rk) in pts.iter().zip(r) {
            // A tenth of the settling time (the pump's 0.1 s: 1.0 / 10.0 is 0.1 exactly).
            if t >= last_change + self.of.settle_s / 10.0 {
                self.max_dev_0_1 = self.max_dev_0_1.max(display.apply((p - rk).abs()));
            }
            if let Some(k) = step.filter(|_| t < last_change + self.of.settle_s) {
                let (_, old, new, worst) = &mut self.steps[k];
                let size = (*new - *old).abs();
                if size > 0.0 {
                    let over = (*new - *old).signum() * (p - rk) / size * 100.0;
                    *worst = worst.max(over);
                }
            }
        }
    }
}
