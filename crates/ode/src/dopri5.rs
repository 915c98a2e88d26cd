//! The integrator: explicit Dormand-Prince 5(4), FSAL, adaptive step, 4th-order dense
//! output, event location on the dense output, limited integrators and breakpoints.

use crate::error::Snapshot;
use crate::tableau::*;
use crate::{Direction, Error, EventAction, Options, Profile, State, Stats, System};

mod dense;
mod events;
mod size;
pub use dense::DenseComponent;

/// `x^y`: the platform's with `std` (several times faster than `libm`'s, and the step
/// controller calls it twice per step), `libm`'s without.
#[inline(always)]
fn powf(x: f64, y: f64) -> f64 {
    #[cfg(feature = "std")]
    {
        x.powf(y)
    }
    #[cfg(not(feature = "std"))]
    {
        libm::pow(x, y)
    }
}

#[inline(always)]
fn sqrtf(x: f64) -> f64 {
    #[cfg(feature = "std")]
    {
        x.sqrt()
    }
    #[cfg(not(feature = "std"))]
    {
        libm::sqrt(x)
    }
}

/// The most event functions a system may declare (their values live on the stack).
pub const MAX_EVENTS: usize = 32;

/// Which event fired.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EventKind {
    /// The system's event function `j` crossed zero.
    User(usize),
    /// Limited state `i` reached its lower bound and is held there.
    Lower(usize),
    /// Limited state `i` reached its upper bound and is held there.
    Upper(usize),
    /// Limited state `i` left the bound it was held on (its derivative turned inward).
    Released(usize),
}

impl core::fmt::Display for EventKind {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            EventKind::User(j) => write!(f, "event function {j}"),
            EventKind::Lower(i) => write!(f, "state {i} reached its lower bound"),
            EventKind::Upper(i) => write!(f, "state {i} reached its upper bound"),
            EventKind::Released(i) => write!(f, "state {i} left its bound"),
        }
    }
}

/// What one call of [`Dopri5::step`] did. The interval of the last step is
/// `[t_prev(), t()]`, on which [`Dopri5::interpolate`] is valid.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StepResult {
    /// An ordinary accepted step.
    Internal,
    /// The step was cut at an event, which was handled; integration may go on.
    Event {
        /// When.
        t: f64,
        /// Which.
        kind: EventKind,
    },
    /// The step landed on a breakpoint of an input.
    Breakpoint {
        /// When.
        t: f64,
    },
    /// The step landed on the stop time.
    Reached {
        /// When.
        t: f64,
    },
    /// An event whose handler asked to stop.
    Stopped {
        /// When.
        t: f64,
        /// Which.
        kind: EventKind,
    },
}

/// Mode of a limited state (stored as a code in a state-sized vector, so that no
/// allocation or size parameter beyond the state's is needed).
const FREE: f64 = 0.0;
const AT_LOWER: f64 = -1.0;
const AT_UPPER: f64 = 1.0;

/// The Dormand-Prince 5(4) integrator working on one [`System`].
///
/// # Example
/// ```
/// use rhonn_ode::{Dopri5, Options, StepResult, System};
/// struct Decay;
/// impl System for Decay {
///     type State = [f64; 1];
///     fn dim(&self) -> usize { 1 }
///     fn rhs(&self, _t: f64, x: &[f64], dx: &mut [f64]) { dx[0] = -x[0]; }
/// }
/// let mut s = Dopri5::new(Decay, 0.0, [1.0], Options::default()).unwrap();
/// while !matches!(s.step(1.0).unwrap(), StepResult::Reached { .. }) {}
/// assert!((s.state()[0] - (-1.0f64).exp()).abs() < 1e-6);
/// ```
pub struct Dopri5<Sys: System> {
    sys: Sys,
    opts: Options<Sys::State>,
    t: f64,
    x: Sys::State,
    t_prev: f64,
    /// Length of the last full step (the interpolant's interval may extend past `t`
    /// when the step was cut at an event).
    h_step: f64,
    /// Next step size to try.
    h: f64,
    k: [Sys::State; 7],
    dense: [Sys::State; 5],
    x_new: Sys::State,
    scratch: Sys::State,
    mode: Sys::State,
    unclamped: Sys::State,
    unc_old: Sys::State,
    rhs_tmp: Sys::State,
    lo: Sys::State,
    hi: Sys::State,
    has_bounds: bool,
    /// The span of the components with a finite bound, first to last (the bound events
    /// look only there).
    bounded: core::ops::Range<usize>,
    /// Whether some component is held at a bound now (else the stages skip the mask).
    any_held: bool,
    n_events: usize,
    g_old: [f64; MAX_EVENTS],
    g_new: [f64; MAX_EVENTS],
    needs_restart: bool,
    facold: f64,
    /// facold^0.04, computed when facold changes (one pow per step saved).
    facold_beta: f64,
    steps: u64,
    stats: Stats,
    last_event_t: f64,
    chatter: u32,
}

impl<Sys: System> Dopri5<Sys> {
    /// Set up the integrator at `(t0, x0)`. Checks the options and that the initial
    /// state is finite and within the bounds of the limited states.
    pub fn new(sys: Sys, t0: f64, x0: Sys::State, opts: Options<Sys::State>) -> Result<Self, Error> {
        let n = sys.dim();
        opts.check(n)?;
        if x0.dim() != n {
            return Err(Error::InvalidInitial {
                what: "initial state has the wrong dimension",
                t: t0,
                state: Snapshot::of(x0.as_slice()),
            });
        }
        if !t0.is_finite() || x0.as_slice().iter().any(|v| !v.is_finite()) {
            return Err(Error::InvalidInitial {
                what: "initial time or state is not finite",
                t: t0,
                state: Snapshot::of(x0.as_slice()),
            });
        }
        let n_events = sys.n_events();
        if n_events > MAX_EVENTS {
            return Err(Error::TooManyEvents {
                n: n_events,
                max: MAX_EVENTS,
            });
        }
        let mut lo = Sys::State::zeros(n);
        let mut hi = Sys::State::zeros(n);
        let mut has_bounds = false;
        for i in 0..n {
            let (l, u) = sys.bounds(i);
            lo.as_mut_slice()[i] = l;
            hi.as_mut_slice()[i] = u;
            has_bounds |= l.is_finite() || u.is_finite();
            let xi = x0.as_slice()[i];
            if !(l <= u) || xi < l || xi > u {
                return Err(Error::InvalidInitial {
                    what: "initial state outside the limits of a limited state",
                    t: t0,
                    state: Snapshot::of(x0.as_slice()),
                });
            }
        }
        let is_bounded = |i: &usize| lo.as_slice()[*i].is_finite() || hi.as_slice()[*i].is_finite();
        let first = (0..n).find(is_bounded).unwrap_or(0);
        let bounded = first..(0..n).rev().find(is_bounded).map_or(0, |l| l + 1);
        let z = Sys::State::zeros(n);
        let mut s = Dopri5 {
            sys,
            t: t0,
            t_prev: t0,
            h_step: 0.0,
            h: 0.0,
            k: core::array::from_fn(|_| z.clone()),
            dense: core::array::from_fn(|_| z.clone()),
            x_new: z.clone(),
            scratch: z.clone(),
            mode: z.clone(),
            unclamped: z.clone(),
            unc_old: z.clone(),
            rhs_tmp: z.clone(),
            lo,
            hi,
            has_bounds,
            bounded,
            any_held: false,
            n_events,
            g_old: [0.0; MAX_EVENTS],
            g_new: [0.0; MAX_EVENTS],
            needs_restart: true,
            facold: 1e-4,
            facold_beta: powf(1e-4, 0.04),
            steps: 0,
            stats: Stats::default(),
            last_event_t: f64::NEG_INFINITY,
            chatter: 0,
            x: x0,
            opts,
        };
        s.restart();
        // Dense output of the (empty) first interval is the initial state.
        for d in s.dense.iter_mut() {
            d.as_mut_slice().iter_mut().for_each(|v| *v = 0.0);
        }
        s.dense[0] = s.x.clone();
        s.h = match s.opts.h_init_s {
            Some(h) => h.min(s.opts.h_max_s),
            None => s.initial_step(),
        };
        Ok(s)
    }

    /// Current time \[s\].
    pub fn t(&self) -> f64 {
        self.t
    }

    /// Start of the last step \[s\].
    pub fn t_prev(&self) -> f64 {
        self.t_prev
    }

    /// Current state.
    pub fn state(&self) -> &[f64] {
        self.x.as_slice()
    }

    /// The system.
    pub fn system(&self) -> &Sys {
        &self.sys
    }

    /// The system, to change its inputs between steps (a sampled controller does).
    /// The solver restarts (modes, first stage) before the next step.
    pub fn system_mut(&mut self) -> &mut Sys {
        self.needs_restart = true;
        &mut self.sys
    }

    /// Replace the current state (a reset). The solver restarts before the next step.
    pub fn set_state(&mut self, x: &[f64]) {
        self.x.as_mut_slice().copy_from_slice(x);
        self.needs_restart = true;
    }

    /// Counters so far.
    pub fn stats(&self) -> Stats {
        self.stats
    }

    /// The options in use.
    pub fn options(&self) -> &Options<Sys::State> {
        &self.opts
    }

    /// Whether limited state `i` is currently held at a bound: -1 lower, +1 upper, 0 free.
    pub fn held(&self, i: usize) -> i8 {
        self.mode.as_slice()[i] as i8
    }

    /// Give the system back.
    pub fn into_system(self) -> Sys {
        self.sys
    }

    /// Evaluate the right-hand side in the current modes: held states get a zero
    /// derivative, their unclamped derivative is kept in `unclamped`.
    #[inline(always)]
    #[allow(clippy::too_many_arguments)] // split borrows of the solver's fields
    fn eval(
        sys: &Sys,
        stats: &mut Stats,
        has_bounds: bool,
        mode: &Sys::State,
        unclamped: &mut Sys::State,
        t: f64,
        x: &[f64],
        dx: &mut [f64],
    ) {
        sys.rhs(t, x, dx);
        stats.rhs_evaluations += 1;
        if has_bounds {
            let m = mode.as_slice();
            let u = unclamped.as_mut_slice();
            for i in 0..dx.len() {
                if m[i] != FREE {
                    u[i] = dx[i];
                    dx[i] = 0.0;
                }
            }
        }
    }

    /// Choose modes at the current point, resolve limited states, compute the first
    /// stage and the event functions there.
    fn restart(&mut self) {
        self.sys.update_modes(self.t, self.x.as_slice());
        if self.has_bounds {
            // Resolve held / free with the unclamped derivative at this point; a clamp
            // moves the state, so evaluate again until nothing changes (at most twice
            // per limited state in practice).
            for _ in 0..4 {
                self.sys.rhs(self.t, self.x.as_slice(), self.k[0].as_mut_slice());
                self.stats.rhs_evaluations += 1;
                let mut clamped = false;
                let n = self.x.dim();
                for i in 0..n {
                    let (lo, hi) = (self.lo.as_slice()[i], self.hi.as_slice()[i]);
                    let f = self.k[0].as_slice()[i];
                    let xi = &mut self.x.as_mut_slice()[i];
                    let m = &mut self.mode.as_mut_slice()[i];
                    if *m == FREE {
                        if *xi <= lo && f <= 0.0 {
                            *m = AT_LOWER;
                            clamped |= *xi != lo;
                            *xi = lo;
                        } else if *xi >= hi && f >= 0.0 {
                            *m = AT_UPPER;
                            clamped |= *xi != hi;
                            *xi = hi;
                        }
                    } else if (*m == AT_LOWER && f > 0.0) || (*m == AT_UPPER && f < 0.0) {
                        *m = FREE;
                    }
                }
                if !clamped {
                    break;
                }
            }
            self.any_held = self.mode.as_slice().iter().any(|&m| m != FREE);
        }
        let (k0, _) = self.k.split_at_mut(1);
        Self::eval(
            &self.sys,
            &mut self.stats,
            self.any_held,
            &self.mode,
            &mut self.unclamped,
            self.t,
            self.x.as_slice(),
            k0[0].as_mut_slice(),
        );
        if self.n_events > 0 {
            self.sys
                .events(self.t, self.x.as_slice(), &mut self.g_old[..self.n_events]);
        }
        if self.has_bounds {
            self.unc_old
                .as_mut_slice()
                .copy_from_slice(self.unclamped.as_slice());
        }
        self.needs_restart = false;
    }

    /// Initial step: Hairer's rule (two evaluations) or ode45's (none beyond f0).
    fn initial_step(&mut self) -> f64 {
        let n = self.x.dim();
        let x0 = self.x.as_slice();
        let f0 = self.k[0].as_slice();
        let rtol = self.opts.rtol.as_slice();
        let atol = self.opts.atol.as_slice();
        let h_max = self.opts.h_max_s;
        match self.opts.profile {
            Profile::Ode45 => {
                let mut rh: f64 = 0.0;
                for i in 0..n {
                    let thr = atol[i] / rtol[i];
                    rh = rh.max(f64::abs(f0[i]) / x0[i].abs().max(thr) / (0.8 * powf(rtol[i], 0.2)));
                }
                let mut h = h_max.min(1.0);
                if h * rh > 1.0 {
                    h = 1.0 / rh;
                }
                h.max(self.opts.h_min_s.max(1e-12))
            }
            Profile::Hairer => {
                let (mut dnf, mut dny) = (0.0, 0.0);
                for i in 0..n {
                    let sk = atol[i] + rtol[i] * x0[i].abs();
                    dnf += (f0[i] / sk) * (f0[i] / sk);
                    dny += (x0[i] / sk) * (x0[i] / sk);
                }
                let mut h = if dnf <= 1e-10 || dny <= 1e-10 {
                    1e-6
                } else {
                    0.01 * sqrtf(dny / dnf)
                };
                h = h.min(h_max);
                {
                    let xs = self.x_new.as_mut_slice();
                    for i in 0..n {
                        xs[i] = x0[i] + h * f0[i];
                    }
                }
                let (k0, rest) = self.k.split_at_mut(1);
                Self::eval(
                    &self.sys,
                    &mut self.stats,
                    self.any_held,
                    &self.mode,
                    &mut self.unclamped,
                    self.t + h,
                    self.x_new.as_slice(),
                    rest[0].as_mut_slice(),
                );
                let f0 = k0[0].as_slice();
                let f1 = rest[0].as_slice();
                let mut der2: f64 = 0.0;
                for i in 0..n {
                    let sk = atol[i] + rtol[i] * x0[i].abs();
                    der2 += ((f1[i] - f0[i]) / sk) * ((f1[i] - f0[i]) / sk);
                }
                der2 = sqrtf(der2) / h;
                let der12 = der2.abs().max(sqrtf(dnf));
                let h1 = if der12 <= 1e-15 {
                    (h * 1e-3).max(1e-6)
                } else {
                    powf(0.01 / der12, 0.2)
                };
                (100.0 * h).min(h1).min(h_max)
            }
        }
    }

    fn snapshot(&self) -> Snapshot {
        Snapshot::of(self.x.as_slice())
    }

    /// Take one step towards `t_stop`, landing exactly on `t_stop` and on every
    /// breakpoint of the system, and stopping at the first event.
    pub fn step(&mut self, t_stop: f64) -> Result<StepResult, Error> {
        if self.needs_restart {
            self.restart();
        }
        if !(t_stop > self.t) {
            self.t_prev = self.t;
            self.h_step = 0.0;
            return Ok(StepResult::Reached { t: self.t });
        }
        let t_bp = self.sys.next_breakpoint(self.t).min(t_stop);
        let mut rejected_once = false;
        let mut rejections = 0u32;
        let h_taken;
        let lands;
        loop {
            self.steps += 1;
            if self.steps > self.opts.max_steps {
                return Err(Error::TooManySteps {
                    t: self.t,
                    max_steps: self.opts.max_steps,
                    state: self.snapshot(),
                });
            }
            let mut h = self.h.min(self.opts.h_max_s);
            let remaining = t_bp - self.t;
            // Land on the breakpoint when it is within reach, or so close that the step
            // after this one would be tiny (ode45 stretches within 10 %).
            let mut land = false;
            if h >= remaining || 1.1 * h >= remaining {
                h = remaining;
                land = true;
            }
            if !land && h < self.opts.h_min_s {
                return Err(Error::StepSizeUnderflow {
                    t: self.t,
                    h,
                    h_min: self.opts.h_min_s,
                    state: self.snapshot(),
                });
            }
            let err = self.try_step(h);
            if !err.is_finite() {
                return Err(Error::NonFinite {
                    t: self.t,
                    state: self.snapshot(),
                });
            }
            if err <= 1.0 {
                let proposal = self.h;
                self.accept_size(h, err, rejected_once);
                if land && !rejected_once {
                    // The step was shortened to land on a breakpoint, perhaps to a
                    // sliver: its size says nothing about the solution, so the next
                    // step may be as long as the one planned before.
                    self.h = self.h.max(proposal);
                }
                h_taken = h;
                lands = land;
                break;
            }
            self.stats.rejected_steps += 1;
            rejections += 1;
            self.h = self.reject_size(h, err, rejections);
            rejected_once = true;
            if self.h < self.opts.h_min_s && !(self.h >= t_bp - self.t) {
                return Err(Error::StepSizeUnderflow {
                    t: self.t,
                    h: self.h,
                    h_min: self.opts.h_min_s,
                    state: self.snapshot(),
                });
            }
        }
        self.stats.accepted_steps += 1;
        let t_new = if lands { t_bp } else { self.t + h_taken };
        self.build_dense(h_taken);
        self.t_prev = self.t;
        self.h_step = h_taken;

        // Events: find the earliest crossing in (t, t_new].
        if let Some((t_e, kind)) = self.find_event(t_new) {
            return self.handle_event(t_e, kind);
        }
        self.t = t_new;
        core::mem::swap(&mut self.x, &mut self.x_new);
        self.k.swap(0, 6);
        if self.n_events > 0 {
            self.g_old[..self.n_events].copy_from_slice(&self.g_new[..self.n_events]);
        }
        if self.has_bounds {
            self.unc_old
                .as_mut_slice()
                .copy_from_slice(self.unclamped.as_slice());
        }
        if lands {
            self.stats.breakpoints += 1;
            self.restart();
            if t_bp >= t_stop {
                return Ok(StepResult::Reached { t: self.t });
            }
            return Ok(StepResult::Breakpoint { t: self.t });
        }
        Ok(StepResult::Internal)
    }

    /// One trial step of size `h` from `(t, x)` with `k[0] = f(t, x)`. Leaves the new
    /// state in `x_new` and `f(t + h, x_new)` in `k[6]`; returns the scaled error
    /// (accept when <= 1), NaN when anything is not finite.
    fn try_step(&mut self, h: f64) -> f64 {
        let n = self.x.dim();
        let t = self.t;
        // Every slice cut to n up front: the loops below then carry no bounds checks.
        let x = &self.x.as_slice()[..n];
        let (sys, stats, hb) = (&self.sys, &mut self.stats, self.any_held);
        let (mode, unc) = (&self.mode, &mut self.unclamped);
        let [k1, k2, k3, k4, k5, k6, k7] = &mut self.k;
        let y = &mut self.scratch.as_mut_slice()[..n];
        macro_rules! stage {
            ($c:expr, $out:expr, |$i:ident| $e:expr) => {{
                for $i in 0..n {
                    y[$i] = $e;
                }
                Self::eval(
                    sys,
                    stats,
                    hb,
                    mode,
                    unc,
                    t + $c * h,
                    y,
                    $out.as_mut_slice(),
                );
            }};
        }
        let a1 = &k1.as_slice()[..n];
        stage!(C2, k2, |i| x[i] + h * A21 * a1[i]);
        let a2 = &k2.as_slice()[..n];
        stage!(C3, k3, |i| x[i] + h * (A31 * a1[i] + A32 * a2[i]));
        let a3 = &k3.as_slice()[..n];
        stage!(C4, k4, |i| x[i] + h * (A41 * a1[i] + A42 * a2[i] + A43 * a3[i]));
        let a4 = &k4.as_slice()[..n];
        stage!(C5, k5, |i| x[i]
            + h * (A51 * a1[i] + A52 * a2[i] + A53 * a3[i] + A54 * a4[i]));
        let a5 = &k5.as_slice()[..n];
        stage!(1.0, k6, |i| x[i]
            + h * (A61 * a1[i]
                + A62 * a2[i]
                + A63 * a3[i]
                + A64 * a4[i]
                + A65 * a5[i]));
        let a6 = &k6.as_slice()[..n];
        let xn = &mut self.x_new.as_mut_slice()[..n];
        for i in 0..n {
            xn[i] = x[i] + h * (B1 * a1[i] + B3 * a3[i] + B4 * a4[i] + B5 * a5[i] + B6 * a6[i]);
        }
        Self::eval(sys, stats, hb, mode, unc, t + h, xn, k7.as_mut_slice());
        let a7 = &k7.as_slice()[..n];
        let rtol = &self.opts.rtol.as_slice()[..n];
        let atol = &self.opts.atol.as_slice()[..n];
        match self.opts.profile {
            Profile::Hairer => {
                let mut sum = 0.0;
                for i in 0..n {
                    let e = h * (E1 * a1[i] + E3 * a3[i] + E4 * a4[i] + E5 * a5[i] + E6 * a6[i] + E7 * a7[i]);
                    let sk = atol[i] + rtol[i] * x[i].abs().max(xn[i].abs());
                    sum += (e / sk) * (e / sk);
                    if !xn[i].is_finite() || !a7[i].is_finite() {
                        return f64::NAN;
                    }
                }
                sqrtf(sum / n as f64)
            }
            Profile::Ode45 => {
                let mut m: f64 = 0.0;
                for i in 0..n {
                    let e = h * (E1 * a1[i] + E3 * a3[i] + E4 * a4[i] + E5 * a5[i] + E6 * a6[i] + E7 * a7[i]);
                    let sk = (rtol[i] * x[i].abs().max(xn[i].abs())).max(atol[i]);
                    let r = f64::abs(e) / sk;
                    if !xn[i].is_finite() || !a7[i].is_finite() || r.is_nan() {
                        return f64::NAN;
                    }
                    m = m.max(r);
                }
                m
            }
        }
    }

    /// Integrate to `t_end`, calling `each(self)` after every step (use
    /// [`Dopri5::interpolate`] on `[t_prev(), t()]` for output). Stops early on an
    /// event whose handler returns [`EventAction::Stop`]; returns the last result.
    pub fn solve_to(
        &mut self,
        t_end: f64,
        mut each: impl FnMut(&Self, StepResult),
    ) -> Result<StepResult, Error> {
        loop {
            let r = self.step(t_end)?;
            each(self, r);
            match r {
                StepResult::Reached { .. } | StepResult::Stopped { .. } => return Ok(r),
                _ => {}
            }
        }
    }
}
