//! Online RHONN identification of sampled signals, the one place its update is
//! written: [`Online::update`] takes one sample `(t, u, y)`, returns the estimate of
//! `y(t)` made before seeing `y`, then learns from `y`. The host library's
//! `OnlineIdentifier` (`rhonn identify`, a user's own loop, Python) borrows its buffers
//! into an [`Online`] for every update; a target's `FixedOnline` (module `online_fixed`)
//! does the same from fixed-size arrays.
//!
//! Between samples the identifier's ODE ([`crate::ident::Ident::rhs_general`], any
//! [`NeuronLaw`]) is integrated by classical RK4 in substeps short enough for its
//! fastest motion; the measured outputs are held (series-parallel), the inputs held or
//! linear; each input also enters through first-order filters (the stand-ins for states
//! nobody measures); errors below a dead zone do not adapt; a filtered-error estimate
//! is held within bounds (a limited integrator). Signals are normalised:
//! `(signal - offset) / scale`.

use crate::ident::{Ident, Mode, NeuronLaw, Structure, Work};
use crate::law::{dot, Zone};
use crate::Real;

/// How inputs move between two samples.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum InputHold {
    /// Held at the last sample (zero-order hold).
    #[default]
    Hold,
    /// Linear between the last sample and this one.
    Linear,
}

/// Offsets and scales of the outputs and the inputs, borrowed.
#[derive(Debug, Clone, Copy)]
pub struct Scaling<'a, T> {
    /// Per output.
    pub y_offset: &'a [T],
    /// Per output, > 0.
    pub y_scale: &'a [T],
    /// Per input.
    pub u_offset: &'a [T],
    /// Per input, > 0.
    pub u_scale: &'a [T],
    /// Per output, the range the estimate is held in (output units); none: unbounded.
    pub y_bounds: Option<&'a [[T; 2]]>,
}

/// The settings of an online identifier, borrowed.
#[derive(Debug, Clone, Copy)]
pub struct Settings<'a, T> {
    /// The signals' scaling.
    pub scaling: Scaling<'a, T>,
    /// Inputs held or linear between samples.
    pub hold: InputHold,
    /// Time constants \[s\] of each input's filters.
    pub filters_s: &'a [T],
    /// Per output, the dead zone in normalised units.
    pub dead_zone: &'a [T],
    /// The nominal sample time \[s\] (substeps are at most this long).
    pub period_s: T,
}

/// Buffers of an online identifier, borrowed (lengths: `state`, `k`, `acc`, `tmp` the
/// identifier's dimension; `y_last`, `yn`, `y_hat` the outputs; `u_last`, `u_now`,
/// `u_mid` the network's inputs, `nu (1 + filters) + 1`).
#[derive(Debug)]
pub struct Buffers<'a, T> {
    /// The identifier state.
    pub state: &'a mut [T],
    /// An RK4 stage's derivative.
    pub k: &'a mut [T],
    /// RK4's weighted sum of the stages, `k1 + 2 k2 + 2 k3 + k4`, added up stage by
    /// stage (the same sums in the same order as the formula: the same bits, two
    /// buffers fewer than keeping the four stages).
    pub acc: &'a mut [T],
    /// RK4's intermediate state.
    pub tmp: &'a mut [T],
    /// The last sample's normalised outputs.
    pub y_last: &'a mut [T],
    /// The last sample's network inputs (inputs, filters, 1).
    pub u_last: &'a mut [T],
    /// This sample's normalised outputs.
    pub yn: &'a mut [T],
    /// This sample's network inputs.
    pub u_now: &'a mut [T],
    /// The network inputs at a stage.
    pub u_mid: &'a mut [T],
    /// The estimate (output units).
    pub y_hat: &'a mut [T],
    /// The evaluations' work space.
    pub work: Work<'a, T>,
}

/// What changes with a sample besides the buffers.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Status<T> {
    /// The last sample's time (none: the next sample starts a record).
    pub t_last: Option<T>,
    /// Weights frozen.
    pub frozen: bool,
    /// Free run: the model on its own outputs, weights frozen.
    pub free_run: bool,
}

/// Why an update was refused or failed (the state is unchanged by a refusal).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum UpdateError<T> {
    /// `u` or `y` has the wrong length (or the identifier has no output or no input:
    /// an empty `FixedOnline` not configured).
    Sizes,
    /// A time, input or (outside a free run) output is not finite.
    NotFinite,
    /// The time is not after the last sample's.
    NotAfter {
        /// The last sample's time.
        t_last: T,
    },
    /// The identifier's state became infinite or NaN: the weights diverged.
    Diverged,
}

/// An online identifier, borrowed (see the module docs).
#[derive(Debug)]
pub struct Online<'a, T, L> {
    /// The network and its law; the mode is set by each update.
    pub ident: Ident<'a, T, L>,
    /// Each neuron's zone (robust laws).
    pub zones: &'a mut [Zone],
    /// Settings.
    pub settings: Settings<'a, T>,
    /// Buffers.
    pub buf: Buffers<'a, T>,
    /// The last sample's time and the flags.
    pub status: &'a mut Status<T>,
}

impl<T: Real, L: NeuronLaw<T>> Online<'_, T, L> {
    /// Take the sample `(t, u, y)`: integrate from the last sample to `t`, leave in
    /// `buf.y_hat` the estimate of `y(t)` made before seeing `y` (the first sample of a
    /// record gives `y`), then learn from `y`. In a free run `y` is not read beyond its
    /// length.
    pub fn update(&mut self, t: T, u: &[T], y: &[T]) -> Result<(), UpdateError<T>> {
        let sc = self.settings.scaling;
        let (ny, nu) = (sc.y_scale.len(), sc.u_scale.len());
        let m = nu * (1 + self.settings.filters_s.len()) + 1;
        if u.len() != nu || y.len() != ny || ny == 0 || nu == 0 || self.buf.u_now.len() != m {
            return Err(UpdateError::Sizes);
        }
        if !t.is_finite()
            || !u.iter().all(|v| v.is_finite())
            || (!self.status.free_run && !y.iter().all(|v| v.is_finite()))
        {
            return Err(UpdateError::NotFinite);
        }
        for (i, v) in y.iter().enumerate() {
            self.buf.yn[i] = (*v - sc.y_offset[i]) / sc.y_scale[i];
        }
        let Some(t0) = self.status.t_last else {
            self.regressor_inputs(u);
            // The first sample: the model starts at the measurement, the filters at rest.
            self.set_estimate_normalised_from_yn();
            self.start_filters();
            self.start_regressor_filters();
            self.remember(t);
            self.denormalise();
            return Ok(());
        };
        let h = t - t0;
        // Not `h <= 0`: a NaN is refused too.
        if h.partial_cmp(&T::default()) != Some(core::cmp::Ordering::Greater) {
            return Err(UpdateError::NotAfter { t_last: t0 });
        }
        self.regressor_inputs(u);
        let status = *self.status;
        let adapt = !status.frozen
            && !status.free_run
            && (0..ny).any(|i| {
                (self.estimate_normalised(i) - self.buf.y_last[i]).abs() >= self.settings.dead_zone[i]
            });
        self.ident.mode = match (status.free_run, adapt) {
            (true, _) => Mode::Parallel,
            (false, true) => Mode::Train,
            (false, false) => Mode::SeriesParallel,
        };
        self.integrate(h);
        self.advance_filters(h);
        self.hold_in_bounds();
        if !self.buf.state.iter().all(|v| v.is_finite()) {
            return Err(UpdateError::Diverged);
        }
        self.remember(t);
        self.denormalise();
        Ok(())
    }

    /// Neuron i's estimate (normalised).
    pub fn estimate_normalised(&self, i: usize) -> T {
        let b = self.ident.block();
        let blk = &self.buf.state[i * b..(i + 1) * b];
        match self.ident.structure {
            Structure::FilteredError => blk[0],
            Structure::FilteredRegressor => {
                let l = self.ident.net.n_terms();
                dot(&blk[..l], &blk[l..2 * l])
            }
        }
    }

    /// Put a filtered-error model's estimate at `y` (output units, one per output; extra
    /// values are ignored), as at a record's first sample (a filtered-regressor model's estimate is its weights times its
    /// filters: left alone).
    pub fn set_estimate(&mut self, y: &[T]) {
        let sc = self.settings.scaling;
        for (i, v) in y.iter().enumerate().take(self.buf.yn.len()) {
            self.buf.yn[i] = (*v - sc.y_offset[i]) / sc.y_scale[i];
        }
        self.set_estimate_normalised_from_yn();
    }

    fn set_estimate_normalised_from_yn(&mut self) {
        if self.ident.structure == Structure::FilteredError {
            let b = self.ident.block();
            for (i, y) in self.buf.yn.iter().enumerate() {
                self.buf.state[i * b] = *y;
            }
        }
    }

    /// Keep this sample as the last one.
    fn remember(&mut self, t: T) {
        self.status.t_last = Some(t);
        self.buf.y_last.copy_from_slice(self.buf.yn);
        self.buf.u_last.copy_from_slice(self.buf.u_now);
    }

    /// The estimate in output units into `buf.y_hat`.
    fn denormalise(&mut self) {
        let sc = self.settings.scaling;
        for i in 0..self.buf.y_hat.len() {
            self.buf.y_hat[i] = self.estimate_normalised(i) * sc.y_scale[i] + sc.y_offset[i];
        }
    }

    /// A frozen filtered-regressor model's filters zeta at rest for the first sample's
    /// regressor z (from the measurement and the inputs): zeta = z / a, where
    /// zeta' = -a zeta + z stands still. Not what an earlier record left in them: the
    /// frozen model's run of a record then begins alike whatever ran before. While
    /// learning, the filters carry over from the last record: set at rest, their size
    /// (1/a times z's) with a fresh covariance would make the least-squares law stiff
    /// at once.
    fn start_regressor_filters(&mut self) {
        if self.ident.structure != Structure::FilteredRegressor
            || !(self.status.frozen || self.status.free_run)
        {
            return;
        }
        let (n, l, b) = (self.ident.net.n, self.ident.net.n_terms(), self.ident.block());
        let w = &mut self.buf.work;
        self.ident.net.regressor(self.buf.yn, self.buf.u_now, w.y, w.z);
        for i in 0..n {
            let a = self.ident.net.a[i];
            for k in 0..l {
                self.buf.state[i * b + k] = w.z[k] / a;
            }
        }
    }

    /// A filtered-error model's state held within the bounds (a limited integrator).
    fn hold_in_bounds(&mut self) {
        let sc = self.settings.scaling;
        let Some(bounds) = sc.y_bounds else {
            return;
        };
        if self.ident.structure != Structure::FilteredError {
            return;
        }
        let b = self.ident.block();
        for (i, [lo, hi]) in bounds.iter().enumerate() {
            let (lo, hi) = (
                (*lo - sc.y_offset[i]) / sc.y_scale[i],
                (*hi - sc.y_offset[i]) / sc.y_scale[i],
            );
            self.buf.state[i * b] = self.buf.state[i * b].clamp(lo, hi);
        }
    }

    /// The network's inputs for the sample `u`: normalised inputs, their filters (kept
    /// from the last sample), and the constant 1.
    fn regressor_inputs(&mut self, u: &[T]) {
        let sc = self.settings.scaling;
        let nu = u.len();
        for (j, v) in u.iter().enumerate() {
            self.buf.u_now[j] = (*v - sc.u_offset[j]) / sc.u_scale[j];
        }
        if self.status.t_last.is_some() {
            self.buf.u_now[nu..].copy_from_slice(&self.buf.u_last[nu..]);
        }
        let m = self.buf.u_now.len();
        self.buf.u_now[m - 1] = T::of(1.0);
    }

    fn start_filters(&mut self) {
        let nu = self.settings.scaling.u_scale.len();
        for q in 0..self.settings.filters_s.len() {
            for j in 0..nu {
                self.buf.u_now[nu * (1 + q) + j] = self.buf.u_now[j];
            }
        }
    }

    /// The filters over `h` with the last sample's input held (exact for a held input).
    fn advance_filters(&mut self, h: T) {
        let nu = self.settings.scaling.u_scale.len();
        let u0 = &self.buf.u_last;
        for (q, tau) in self.settings.filters_s.iter().enumerate() {
            let k = T::of(1.0) - (-h / *tau).exp();
            for j in 0..nu {
                let c = nu * (1 + q) + j;
                self.buf.u_now[c] = u0[c] + k * (u0[j] - u0[c]);
            }
        }
    }

    /// A substep's first stage: the robust laws' zones, the inputs at fraction `f`, and
    /// the derivative into `k` and `acc` (with the previous regressor when
    /// `same_regressor`).
    fn start_substep(&mut self, f: T, same_regressor: bool) {
        let b = &mut self.buf;
        self.ident
            .update_zones(b.y_last, b.u_last, b.state, self.zones, &mut b.work);
        let nu = self.settings.scaling.u_scale.len();
        stage_inputs(b.u_mid, b.u_last, b.u_now, nu, self.settings.hold, f);
        self.ident.rhs_general(
            b.y_last,
            b.u_mid,
            b.state,
            b.k,
            self.zones,
            &mut b.work,
            same_regressor,
        );
        b.acc.copy_from_slice(b.k);
    }

    /// The inputs at fraction `f` of the interval, for a linear hold.
    fn stage_linear(&mut self, f: T) {
        if self.settings.hold == InputHold::Linear {
            let b = &mut self.buf;
            let nu = self.settings.scaling.u_scale.len();
            stage_inputs(b.u_mid, b.u_last, b.u_now, nu, self.settings.hold, f);
        }
    }

    /// One RK4 stage: `k = f(state + c k)` (`c`: the step times the stage's fraction),
    /// then `acc += weight k`.
    fn stage(&mut self, c: T, weight: Option<T>, reuse: bool) {
        let b = &mut self.buf;
        for ((t, s), k) in b.tmp.iter_mut().zip(b.state.iter()).zip(b.k.iter()) {
            *t = *s + c * *k;
        }
        self.ident
            .rhs_general(b.y_last, b.u_mid, b.tmp, b.k, self.zones, &mut b.work, reuse);
        match weight {
            Some(w) => b.acc.iter_mut().zip(b.k.iter()).for_each(|(a, k)| *a += w * *k),
            None => b.acc.iter_mut().zip(b.k.iter()).for_each(|(a, k)| *a += *k),
        }
    }

    /// Classical RK4 over `h` (in substeps of at most one sample time), the measured
    /// outputs (the last sample's) held and the inputs held or linear to this sample's.
    fn integrate(&mut self, h: T) {
        // Substeps short enough for RK4 to follow the identifier's fastest motion (the
        // neuron's pole a, and the weight-error oscillation sqrt(gamma |z|^2)), so the
        // law's continuous-time stability carries over to the sampled run. The first
        // stage's regressor gives |z|^2 (it does not depend on the substep).
        // With inputs and measurements held over the sample, the regressor is the same at
        // every stage: computed once, used again by every later stage.
        let reuse = self.settings.hold == InputHold::Hold;
        self.start_substep(T::default(), false);
        let rate = self.fastest_rate();
        let n_sub = (h / self.settings.period_s)
            .max(h * rate / T::of(0.5))
            .ceil()
            .clamp(T::of(1.0), T::of(10_000.0))
            .to_usize();
        let n_t = T::of_usize(n_sub);
        let hs = h / n_t;
        let (half, two, six) = (T::of(0.5), T::of(2.0), T::of(6.0));
        for j in 0..n_sub {
            let j_t = T::of_usize(j);
            let f = |x: f64| (j_t + T::of(x)) / n_t;
            if j > 0 {
                self.start_substep(f(0.0), reuse);
            }
            self.stage_linear(f(0.5));
            self.stage(half * hs, Some(two), reuse);
            self.stage(half * hs, Some(two), reuse);
            self.stage_linear(f(1.0));
            self.stage(hs, None, reuse);
            let b = &mut self.buf;
            let step = hs / six;
            b.state
                .iter_mut()
                .zip(b.acc.iter())
                .for_each(|(s, a)| *s += step * *a);
        }
    }

    /// The identifier's fastest rate \[1/s\] after an evaluation of its derivative by
    /// the general path (which left the regressor z in the work space).
    fn fastest_rate(&self) -> T {
        let a_max = self.ident.net.a.iter().copied().fold(T::default(), T::max);
        if self.ident.mode != Mode::Train {
            // Frozen weights: only the neurons move (and a frozen model runs alike
            // whatever covariance its law last had, e.g. when rebuilt from model.json).
            return a_max;
        }
        let l = self.ident.net.n_terms();
        let z2: T = self.buf.work.z[..l].iter().map(|v| *v * *v).sum();
        let (b, wo) = (self.ident.block(), self.ident.w_off());
        let g_max = (0..self.ident.net.n)
            .map(|i| {
                self.ident
                    .law
                    .rate(i, &self.buf.state[i * b + wo + l..(i + 1) * b], l)
            })
            .fold(T::default(), T::max);
        a_max.max((g_max * z2).sqrt())
    }
}

/// The network inputs at fraction `f` of the interval: `u0` held, or its first `nu`
/// (the inputs, not their filters) linear to this sample's `u_now`.
fn stage_inputs<T: Real>(u_mid: &mut [T], u0: &[T], u_now: &[T], nu: usize, hold: InputHold, f: T) {
    u_mid.copy_from_slice(u0);
    if hold == InputHold::Linear {
        for c in 0..nu {
            u_mid[c] = u0[c] + f * (u_now[c] - u0[c]);
        }
    }
}
