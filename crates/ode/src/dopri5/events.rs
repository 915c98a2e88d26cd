//! Events of the solver: their functions evaluated on the dense output, located by
//! root finding between the step's ends, and handled (mode switches, restarts).

use super::*;

impl<Sys: System> Dopri5<Sys> {
    /// Value of the event function of `kind` at time `t` inside the last step (on the
    /// dense output). Bound-release events need the right-hand side there.
    fn event_value(&mut self, kind: EventKind, t: f64) -> f64 {
        let theta = (t - self.t_prev) / self.h_step;
        Self::dense_eval(&self.dense, theta, self.scratch.as_mut_slice());
        match kind {
            EventKind::User(j) => {
                let mut g = [0.0; MAX_EVENTS];
                self.sys
                    .events(t, self.scratch.as_slice(), &mut g[..self.n_events]);
                g[j]
            }
            EventKind::Lower(i) => self.scratch.as_slice()[i] - self.lo.as_slice()[i],
            EventKind::Upper(i) => self.scratch.as_slice()[i] - self.hi.as_slice()[i],
            EventKind::Released(i) => {
                self.sys
                    .rhs(t, self.scratch.as_slice(), self.rhs_tmp.as_mut_slice());
                self.stats.rhs_evaluations += 1;
                self.rhs_tmp.as_slice()[i]
            }
        }
    }

    /// The earliest event in `(t, t_new]` of the step just accepted, located to within
    /// the event tolerance (the returned time lies just past the crossing).
    pub(super) fn find_event(&mut self, t_new: f64) -> Option<(f64, EventKind)> {
        let mut best: Option<(f64, EventKind)> = None;
        let t0 = self.t;
        if self.n_events > 0 {
            self.sys
                .events(t_new, self.x_new.as_slice(), &mut self.g_new[..self.n_events]);
            for j in 0..self.n_events {
                let dir = self.sys.event_direction(j);
                let (g0, g1) = (self.g_old[j], self.g_new[j]);
                if dir.crossed(g0, g1) {
                    let tb = best.map_or(t_new, |b| b.0);
                    // Only look for it if it may come before the best so far.
                    let g_tb = if tb == t_new {
                        g1
                    } else {
                        self.event_value(EventKind::User(j), tb)
                    };
                    if dir.past(g0, g_tb) {
                        let te = self.locate(EventKind::User(j), dir, t0, g0, tb, g_tb);
                        best = Some((te, EventKind::User(j)));
                    }
                }
            }
        }
        if self.has_bounds {
            for i in self.bounded.clone() {
                let m = self.mode.as_slice()[i];
                let (lo, hi) = (self.lo.as_slice()[i], self.hi.as_slice()[i]);
                let x0 = self.x.as_slice()[i];
                let x1 = self.x_new.as_slice()[i];
                let cands: [(EventKind, Direction, f64, f64); 2] = if m == FREE {
                    [
                        (EventKind::Lower(i), Direction::Falling, x0 - lo, x1 - lo),
                        (EventKind::Upper(i), Direction::Rising, x0 - hi, x1 - hi),
                    ]
                } else {
                    let f0 = self.unc_old.as_slice()[i];
                    let f1 = self.unclamped.as_slice()[i];
                    let dir = if m == AT_LOWER {
                        Direction::Rising
                    } else {
                        Direction::Falling
                    };
                    [
                        (EventKind::Released(i), dir, f0, f1),
                        (EventKind::Released(i), dir, 0.0, 0.0),
                    ]
                };
                for (kind, dir, g0, g1) in cands {
                    if !g0.is_finite() || !dir.crossed(g0, g1) {
                        continue;
                    }
                    let tb = best.map_or(t_new, |b| b.0);
                    let g_tb = if tb == t_new {
                        g1
                    } else {
                        self.event_value(kind, tb)
                    };
                    if dir.past(g0, g_tb) {
                        let te = self.locate(kind, dir, t0, g0, tb, g_tb);
                        best = Some((te, kind));
                    }
                }
            }
        }
        best
    }

    /// Illinois (modified regula falsi) on the dense output. `ga` is not past the
    /// crossing, `gb` is; returns the right end of a bracket narrower than the event
    /// tolerance, so the event function is strictly past zero there.
    fn locate(
        &mut self,
        kind: EventKind,
        dir: Direction,
        mut ta: f64,
        mut ga: f64,
        mut tb: f64,
        mut gb: f64,
    ) -> f64 {
        let tol = self.opts.event_tol_s;
        let g_ref = ga;
        let mut side = 0i8;
        let mut iter = 0;
        while tb - ta > tol && iter < 200 {
            iter += 1;
            let width = tb - ta;
            let mut tm = if iter % 4 == 0 || gb == ga {
                0.5 * (ta + tb)
            } else {
                (ta * gb - tb * ga) / (gb - ga)
            };
            if !(tm > ta && tm < tb) {
                tm = 0.5 * (ta + tb);
            }
            let margin = (0.45 * tol).min(0.25 * width);
            tm = tm.max(ta + margin).min(tb - margin);
            let gm = self.event_value(kind, tm);
            if dir.past(g_ref, gm) {
                tb = tm;
                gb = gm;
                if side == -1 {
                    ga *= 0.5;
                }
                side = -1;
            } else {
                ta = tm;
                ga = gm;
                if side == 1 {
                    gb *= 0.5;
                }
                side = 1;
            }
        }
        tb
    }

    /// Cut the step at the event, act on it, restart.
    pub(super) fn handle_event(&mut self, t_e: f64, kind: EventKind) -> Result<StepResult, Error> {
        let theta = (t_e - self.t_prev) / self.h_step;
        Self::dense_eval(&self.dense, theta, self.x.as_mut_slice());
        self.t = t_e;
        self.stats.events += 1;
        if t_e - self.last_event_t <= 10.0 * self.opts.event_tol_s {
            self.chatter += 1;
            if self.chatter > 1000 {
                return Err(Error::EventChatter {
                    t: t_e,
                    count: self.chatter,
                    last: kind,
                    state: self.snapshot(),
                });
            }
        } else {
            self.chatter = 0;
        }
        self.last_event_t = t_e;
        let mut action = EventAction::Continue;
        match kind {
            EventKind::User(j) => {
                action = self.sys.on_event(j, t_e, self.x.as_mut_slice());
            }
            EventKind::Lower(i) => {
                self.x.as_mut_slice()[i] = self.lo.as_slice()[i];
                self.mode.as_mut_slice()[i] = AT_LOWER;
            }
            EventKind::Upper(i) => {
                self.x.as_mut_slice()[i] = self.hi.as_slice()[i];
                self.mode.as_mut_slice()[i] = AT_UPPER;
            }
            EventKind::Released(i) => {
                self.mode.as_mut_slice()[i] = FREE;
            }
        }
        if self.x.as_slice().iter().any(|v| !v.is_finite()) {
            return Err(Error::NonFinite {
                t: t_e,
                state: self.snapshot(),
            });
        }
        self.restart();
        Ok(match action {
            EventAction::Continue => StepResult::Event { t: t_e, kind },
            EventAction::Stop => StepResult::Stopped { t: t_e, kind },
        })
    }
}
