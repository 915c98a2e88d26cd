//! Experiments on any [`Plant`] from the library: online identification of its states
//! and its run on its inputs alone (sampled at the output instants), through the one run
//! loop ([`super::sim`]); a controller on one of its inputs is `closed_loop.rs`'s.

use super::ident_figures::{IdentAcc, RunFigures};
use super::integrated::{Alone, Integrated};
pub use super::loop_conditions::LoopConditions;
use super::plant_summary::FloorFigures;
use super::quadrature::Scale;
use super::regulation::Tracker;
use super::sim::{drive, start, Hooks, Instants};
use super::solver_spec::Tolerances;
use crate::error::Result;
use crate::ident::{FrozenPair, IdentSettings, Identified};
use crate::metrics::{fit_percent, rms_error};
use crate::plant::Plant;
use rhonn_ode::{Dopri5, State, System};

/// `system` from `x0` (the plant's states, then `rest`) in the event-locating solver.
pub(super) fn solver<S: Integrated>(
    system: S,
    x0: &[f64],
    rest: &[f64],
    tol: &Tolerances,
) -> Result<Dopri5<S>> {
    let mut s0 = S::State::zeros(system.dim());
    s0.as_mut_slice()[..x0.len()].copy_from_slice(x0);
    s0.as_mut_slice()[x0.len()..].copy_from_slice(rest);
    let dim = system.dim();
    start(system, s0, tol.options(dim))
}

/// The solver's settings of an identification when `[solver]` sets none: rtol 1e-6,
/// atol 1e-9 on every state, no step limit.
pub const IDENTIFY_RTOL: f64 = 1e-6;
/// The same of a closed loop: rtol 1e-7.
pub const LOOP_RTOL: f64 = 1e-7;

/// What one identification of a plant gives: per identified state, the samples and the
/// estimates while training, and the frozen weights.
#[derive(Debug, Clone, PartialEq)]
pub struct IdentRun {
    /// Sample times \[s\].
    pub t: Vec<f64>,
    /// Per identified state: its values (SI).
    pub y: Vec<Vec<f64>>,
    /// Per identified state: the online estimate (with [`Weights::Frozen`], the frozen
    /// model's free run).
    pub y_hat: Vec<Vec<f64>>,
    /// Per identified state, with [`Weights::Frozen`] only (else empty): the frozen model's
    /// series-parallel estimate (its regressor on the measured states), from the same
    /// integration as its free run.
    pub y_hat_series_parallel: Vec<Vec<f64>>,
    /// What the solver did.
    pub stats: rhonn_ode::Stats,
    /// The final weights, one vector per neuron.
    pub weights: Vec<Vec<f64>>,
    /// A training run's time below the plant's floor (None for a frozen model's run, or a
    /// plant without a floor).
    pub floor: Option<FloorFigures>,
    /// The whole run's figures on the dense output, per identified state (display units):
    /// a training run's online estimates, or a frozen model's series-parallel estimate
    /// then its free run.
    pub whole_run: Vec<Vec<RunFigures>>,
}

impl IdentRun {
    /// Fit \[%\] of each state's estimate over the samples from `from_s` on.
    pub fn fit_percent_after(&self, from_s: f64) -> Vec<f64> {
        let k = self.t.iter().position(|&t| t >= from_s).unwrap_or(self.t.len());
        self.y
            .iter()
            .zip(&self.y_hat)
            .map(|(y, h)| fit_percent(&y[k..], &h[k..]))
            .collect()
    }

    /// RMS error (SI) of each state's estimate over the samples from `from_s` on.
    pub fn rms_after(&self, from_s: f64) -> Vec<f64> {
        let k = self.t.iter().position(|&t| t >= from_s).unwrap_or(self.t.len());
        self.y
            .iter()
            .zip(&self.y_hat)
            .map(|(y, h)| rms_error(&y[k..], &h[k..]))
            .collect()
    }
}

/// Where an identification's weights start, and whether they learn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Weights<'a> {
    /// The identifier's initial weights, learning (a first epoch).
    Initial,
    /// These weights, learning (a later epoch starts from the one before's).
    From(&'a [Vec<f64>]),
    /// These weights, held: the estimates are the parallel (free-run) model's.
    Frozen(&'a [Vec<f64>]),
}

/// Identify `plant` (driven by its own inputs) online from `x0` with the checked
/// identifier `is` (series-parallel, weights adapting from `weights`) for `duration_s`,
/// sampled every `sample_s`; with [`Weights::Frozen`] the weights are held and the
/// estimates are the parallel (free-run) model's instead. `tol`: the solver's settings
/// (see [`IDENTIFY_RTOL`] for the scenarios' default).
pub fn identify<P: Plant>(
    plant: P,
    x0: &[f64],
    is: &IdentSettings,
    times: (f64, f64),
    weights: Weights<'_>,
    tol: &Tolerances,
) -> Result<IdentRun> {
    // The thesis's identifiers make systems of 5 to 11 states: those run on fixed-size
    // states (the solver's vector operations unrolled: a vector cost thesis-ch5 a tenth
    // of its time), any other on a vector. The same arithmetic either way, to the bit.
    let (states, inputs) = (is.states.clone(), is.inputs.clone());
    let dim = match weights {
        Weights::Frozen(w) => FrozenPair::<P>::new(plant.clone(), &is.ident, w, states, inputs)?.dim(),
        _ => Identified::<P>::new(plant.clone(), is.ident.clone(), states, inputs)?.dim(),
    };
    match dim {
        5 => identify_as::<P, [f64; 5]>(plant, x0, is, times, weights, tol),
        7 => identify_as::<P, [f64; 7]>(plant, x0, is, times, weights, tol),
        9 => identify_as::<P, [f64; 9]>(plant, x0, is, times, weights, tol),
        11 => identify_as::<P, [f64; 11]>(plant, x0, is, times, weights, tol),
        _ => identify_as::<P, Vec<f64>>(plant, x0, is, times, weights, tol),
    }
}

/// [`identify`] on states of type `St`.
fn identify_as<P: Plant, St: State>(
    plant: P,
    x0: &[f64],
    is: &IdentSettings,
    (duration_s, sample_s): (f64, f64),
    weights: Weights<'_>,
    tol: &Tolerances,
) -> Result<IdentRun> {
    let (frozen, start) = match weights {
        Weights::Initial => (None, None),
        Weights::From(w) => (None, Some(w)),
        Weights::Frozen(w) => (Some(w), None),
    };
    let n = is.states.len();
    let mut sampler = Sampler {
        run: IdentRun {
            t: Vec::new(),
            y: vec![Vec::new(); n],
            y_hat: vec![Vec::new(); n],
            y_hat_series_parallel: if frozen.is_some() {
                vec![Vec::new(); n]
            } else {
                Vec::new()
            },
            weights: Vec::new(),
            stats: rhonn_ode::Stats::default(),
            floor: None,
            whole_run: Vec::new(),
        },
        idx: is.states.iter().filter_map(|s| s.state_index()).collect(),
        // The training identifier's estimates, or the frozen model's parallel copy's.
        slot: usize::from(frozen.is_some()),
        hats: Vec::new(),
        dense: tol.max_step_s.is_finite(),
        clock: Instants::seconds(sample_s),
        next: 0,
        count: sampling_steps(duration_s, sample_s)?,
        buf: Vec::new(),
        floor: None,
        accs: Vec::new(),
    };
    let t_end = sampler.clock.at(sampler.count);
    let stops = (!sampler.dense).then_some(sampler.clock);
    let np = plant.dim();
    let scales: Vec<Scale> = is
        .states
        .iter()
        .map(|s| Scale(s.quantity(&plant).display_per_si))
        .collect();
    if let Some(w) = frozen {
        let init = FrozenPair::<P, St>::initial_state(&is.ident, &is.xhat0);
        let sys = FrozenPair::<P, St>::new(plant, &is.ident, w, is.states.clone(), is.inputs.clone())?;
        let dim = sys.dim();
        // Slot 0: the series-parallel copy; slot 1: the free run.
        sampler.accs = (0..2)
            .map(|slot| IdentAcc::new(sampler.idx.clone(), dim, slot))
            .collect();
        let mut s = solver(sys, x0, &init, tol)?;
        drive(&mut s, t_end, stops, &mut sampler)?;
        sampler.run.weights = w.to_vec();
        sampler.run.stats = s.stats();
        sampler.run.whole_run = whole_run(&sampler.accs, &scales);
        return Ok(sampler.run);
    }
    let init = is.ident.initial_state(&is.xhat0, start);
    sampler.floor = Tracker::of_floor(&plant, t_end);
    let states = plant.states();
    let sys = Identified::<P, St>::new(plant, is.ident.clone(), is.states.clone(), is.inputs.clone())?;
    sampler.accs = vec![IdentAcc::new(sampler.idx.clone(), sys.dim(), 0)];
    let mut s = solver(sys, x0, &init, tol)?;
    drive(&mut s, t_end, stops, &mut sampler)?;
    sampler.run.weights = s.system().ident.weights(&s.state()[np..]);
    sampler.run.stats = s.stats();
    sampler.run.floor = sampler.floor.and_then(|f| f.floor_figures(states));
    sampler.run.whole_run = whole_run(&sampler.accs, &scales);
    Ok(sampler.run)
}

/// Each followed slot's figures, per state in display units.
fn whole_run(accs: &[IdentAcc], scales: &[Scale]) -> Vec<Vec<RunFigures>> {
    accs.iter()
        .map(|a| {
            scales
                .iter()
                .enumerate()
                .map(|(k, &sc)| a.figures(k, sc))
                .collect()
        })
        .collect()
}

/// What a plant driven by its own inputs does (open loop): every state at every sample.
#[derive(Debug, Clone, PartialEq)]
pub struct OpenRun {
    /// Sample times \[s\].
    pub t: Vec<f64>,
    /// Every plant state at each sample, SI (`states[i][k]`: state i at sample k).
    pub states: Vec<Vec<f64>>,
    /// What the solver did.
    pub stats: rhonn_ode::Stats,
    /// The time below the plant's floor (None for a plant without one).
    pub floor: Option<FloorFigures>,
}

/// Simulate `plant`, driven by its own inputs, from `x0` for `duration_s`, sampled every
/// `sample_s` (`tol`: the solver's settings; where they bound the step, the samples come
/// from the dense output, else the run stops at each, as an identification's).
pub fn simulate<P: Plant>(
    plant: P,
    x0: &[f64],
    (duration_s, sample_s): (f64, f64),
    tol: &Tolerances,
) -> Result<OpenRun> {
    /// The samples (at each stop, or from each step's dense output as an
    /// identification's, `Sampler`, the end's from the last step) and the floor.
    struct Record {
        out: OpenRun,
        dense: Option<DenseSampler>,
        floor: Option<Tracker<'static>>,
    }
    impl Record {
        fn take<P: Plant>(&mut self, s: &Dopri5<Alone<P>>) {
            self.out.t.push(s.t());
            for (v, x) in self.out.states.iter_mut().zip(s.state()) {
                v.push(*x);
            }
        }
    }
    impl<P: Plant> Hooks<Alone<P>> for Record {
        fn instant(&mut self, s: &mut Dopri5<Alone<P>>) -> Result<()> {
            if self.dense.is_none() {
                self.take(s);
            }
            Ok(())
        }
        fn stepped(&mut self, s: &Dopri5<Alone<P>>, done: bool) -> Result<()> {
            if let Some(f) = self.floor.as_mut() {
                f.add_step(s);
            }
            if let Some(d) = self.dense.as_mut() {
                d.take(s);
            }
            if done {
                self.take(s);
            }
            Ok(())
        }
    }
    let n = plant.states().len();
    let states = plant.states();
    let steps = sampling_steps(duration_s, sample_s)?;
    let instants = Instants::seconds(sample_s);
    let t_end = instants.at(steps);
    let dense = tol.max_step_s.is_finite();
    let mut rec = Record {
        out: OpenRun {
            t: Vec::new(),
            states: vec![Vec::new(); n],
            stats: rhonn_ode::Stats::default(),
            floor: None,
        },
        dense: dense
            .then(|| DenseSampler::new(sample_s, duration_s, n))
            .transpose()?,
        floor: Tracker::of_floor(&plant, t_end),
    };
    let mut s = solver(Alone(plant), x0, &[], tol)?;
    drive(&mut s, t_end, (!dense).then_some(instants), &mut rec)?;
    if let Some(d) = rec.dense.take() {
        // The dense samples, then the end's (taken by `take` above into `out`).
        let DenseSamples {
            mut t,
            states: mut xs,
        } = d.out;
        t.append(&mut rec.out.t);
        for (a, b) in xs.iter_mut().zip(&mut rec.out.states) {
            a.append(b);
        }
        rec.out.t = t;
        rec.out.states = xs;
    }
    rec.out.stats = s.stats();
    rec.out.floor = rec.floor.and_then(|f| f.floor_figures(states));
    Ok(rec.out)
}

/// The whole sampling periods in `duration_s` (rounded), at least one.
pub(super) fn sampling_steps(duration_s: f64, period_s: f64) -> Result<u64> {
    let steps = (duration_s / period_s).round();
    if !(period_s > 0.0 && steps >= 1.0 && steps.is_finite()) {
        return Err(crate::error::invalid(
            "duration_s",
            duration_s,
            format!("at least one sampling period ({period_s} s)"),
        ));
    }
    Ok(steps as u64)
}

/// The state at `t` within the solver's last step into `buf`: the step's end itself, or
/// its dense output.
fn state_at<S: Integrated>(solver: &Dopri5<S>, t: f64, buf: &mut Vec<f64>) {
    if t == solver.t() {
        buf.clear();
        buf.extend_from_slice(solver.state());
    } else {
        buf.resize(solver.state().len(), 0.0);
        solver.interpolate(t, buf);
    }
}

/// Takes an identification's samples: the identified states and model `slot`'s
/// estimates at every output instant (the end included). Nothing discrete happens at a
/// sample of an identification (no controller, no measurement fed back), so where the
/// solver's settings bound its step (`[solver] max_step_ms`, as the pump's scenarios do)
/// the samples come from each step's dense output and the solver steps as the dynamics
/// ask; where they leave it unbounded the run stops at each sample, which bounds the step
/// at the sample interval (the accuracy every such run was measured at).
struct Sampler {
    run: IdentRun,
    /// The identified plant states.
    idx: Vec<usize>,
    slot: usize,
    hats: Vec<Option<f64>>,
    /// Whether the samples come from the dense output (else the run stops at each).
    dense: bool,
    /// The output instants: the next to take, and how many before the end.
    clock: Instants,
    next: u64,
    count: u64,
    buf: Vec<f64>,
    /// A training run's floor, followed on each step.
    floor: Option<Tracker<'static>>,
    /// The whole run's figures of each model slot it follows.
    accs: Vec<IdentAcc>,
}

impl Sampler {
    /// The samples at the output instants in the solver's last step (and its end when
    /// `done`).
    fn take<S: Integrated>(&mut self, solver: &Dopri5<S>, done: bool) {
        while self.dense && self.next < self.count && self.clock.at(self.next) <= solver.t() {
            let t = self.clock.at(self.next);
            self.next += 1;
            state_at(solver, t, &mut self.buf);
            self.record(solver.system(), t);
        }
        if done {
            self.buf.clear();
            self.buf.extend_from_slice(solver.state());
            self.record(solver.system(), solver.t());
        }
    }

    fn record<S: Integrated>(&mut self, system: &S, t: f64) {
        let x = &self.buf;
        self.hats.resize(x.len(), None);
        system.hats(x, self.slot, &mut self.hats);
        self.run.t.push(t);
        for (k, &i) in self.idx.iter().enumerate() {
            self.run.y[k].push(x[i]);
            self.run.y_hat[k].push(self.hats[i].unwrap_or(f64::NAN));
        }
        // A frozen model's series-parallel copy (slot 0) rides on the same integration.
        if !self.run.y_hat_series_parallel.is_empty() {
            system.hats(x, 0, &mut self.hats);
            for (k, &i) in self.idx.iter().enumerate() {
                self.run.y_hat_series_parallel[k].push(self.hats[i].unwrap_or(f64::NAN));
            }
        }
    }
}

impl<S: Integrated> Hooks<S> for Sampler {
    /// A run that stops at each sample (`drive` with instants): the sample is the state.
    fn instant(&mut self, solver: &mut Dopri5<S>) -> Result<()> {
        self.buf.clear();
        self.buf.extend_from_slice(solver.state());
        self.next += 1;
        self.record(solver.system(), solver.t());
        Ok(())
    }
    fn stepped(&mut self, solver: &Dopri5<S>, done: bool) -> Result<()> {
        if let Some(f) = self.floor.as_mut() {
            f.add_step(solver);
        }
        for a in &mut self.accs {
            a.add_step(solver);
        }
        self.take(solver, done);
        Ok(())
    }
}

/// A run's states at its output instants, from the solver's dense output.
#[derive(Debug, Clone, PartialEq)]
pub struct DenseSamples {
    /// Output instants \[s\].
    pub t: Vec<f64>,
    /// Every plant state at each output instant, SI (`states[i][j]`: state i at instant j).
    pub states: Vec<Vec<f64>>,
}

impl DenseSamples {
    /// `values`, one per control instant of `instants`, held to each output instant (the
    /// value of the last control instant at or before it: what the loop held there).
    pub fn held(&self, instants: &[f64], values: &[f64]) -> Vec<f64> {
        // A control instant k * T and an output instant j * dt that are the same decimal
        // time may differ in the last bit: one within 1e-9 of the gap counts as reached.
        let tol = 1e-9 * instants.get(1).map_or(1.0, |t1| t1 - instants[0]);
        let mut k = 0;
        self.t
            .iter()
            .map(|&t| {
                while k + 1 < instants.len() && instants[k + 1] <= t + tol {
                    k += 1;
                }
                values.get(k).copied().unwrap_or(f64::NAN)
            })
            .collect()
    }
}

/// Takes a run's states every output interval from each step's dense output.
pub(super) struct DenseSampler {
    clock: Instants,
    next: u64,
    count: u64,
    pub(super) out: DenseSamples,
    buf: Vec<f64>,
}

impl DenseSampler {
    /// The output instants `0, dt, ...` before `duration_s` of `n` plant states.
    pub(super) fn new(dt: f64, duration_s: f64, n: usize) -> Result<Self> {
        let count = sampling_steps(duration_s, dt)?;
        // Every instant's room at once (a run's samples are known before it starts), up
        // to 4 Mi samples: a longer run grows as it goes rather than asking for it all.
        let room = usize::try_from(count).unwrap_or(0).saturating_add(1).min(1 << 22);
        Ok(DenseSampler {
            clock: Instants::seconds(dt),
            next: 0,
            count,
            out: DenseSamples {
                t: Vec::with_capacity(room),
                states: (0..n).map(|_| Vec::with_capacity(room)).collect(),
            },
            buf: Vec::new(),
        })
    }

    /// The output instants up to the solver's time, from its last step.
    pub(super) fn take<S: Integrated>(&mut self, s: &Dopri5<S>) {
        while self.next < self.count && self.clock.at(self.next) <= s.t() {
            let t = self.clock.at(self.next);
            state_at(s, t, &mut self.buf);
            self.out.t.push(t);
            for (col, v) in self.out.states.iter_mut().zip(&self.buf) {
                col.push(*v);
            }
            self.next += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::solver_spec::SolverDefaults;
    use super::*;
    use crate::plant::{Input, Tanks, TanksParams};

    #[test]
    fn identify_records_the_states_and_their_estimates() {
        let tanks = Tanks::new(TanksParams::default(), Input::Held(5.0));
        let spec: crate::ident::IdentifierSpec = toml::from_str(
            "states = [\"h1\"]\ninputs = [\"voltage\"]\nstate_scale = [0.15]\ninput_scale = [10.0]\n\
             degree = 2\na = [0.05]\nlaw = { kind = \"filtered-regressor-ls\", p0 = [100.0] }",
        )
        .unwrap();
        let is = spec.check_for(&tanks).unwrap();
        let tol = Tolerances::of_defaults(&SolverDefaults::plant(IDENTIFY_RTOL), 2);
        let run = identify(
            tanks.clone(),
            &[0.0, 0.0],
            &is,
            (200.0, 1.0),
            Weights::Initial,
            &tol,
        )
        .unwrap();
        assert_eq!((run.t.len(), run.y.len(), run.weights.len()), (201, 1, 1));
        assert!(run.rms_after(100.0)[0] < 5e-3, "{:?}", run.rms_after(100.0));
        // With the step bounded by the settings the samples come from the dense output: the
        // same instants, the same levels to the solver's accuracy.
        let bounded = Tolerances {
            max_step_s: 10.0,
            ..tol.clone()
        };
        let dense = identify(
            tanks.clone(),
            &[0.0, 0.0],
            &is,
            (200.0, 1.0),
            Weights::Initial,
            &bounded,
        )
        .unwrap();
        assert_eq!(dense.t, run.t);
        let apart = dense.y[0]
            .iter()
            .zip(&run.y[0])
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(apart > 0.0 && apart < 1e-5, "{apart} m");
        let frozen = identify(
            tanks,
            &[0.0, 0.0],
            &is,
            (50.0, 1.0),
            Weights::Frozen(&run.weights),
            &tol,
        )
        .unwrap();
        assert_eq!(frozen.weights, run.weights);
        assert_eq!(frozen.y_hat[0][0], 0.0);
        // The series-parallel copy rides along: one estimate per sample, on the measured
        // level (close to it, as while training), while the training run has none.
        let sp = &frozen.y_hat_series_parallel;
        assert_eq!((sp.len(), sp[0].len()), (1, frozen.t.len()));
        assert!(run.y_hat_series_parallel.is_empty());
        let sp_rms = crate::metrics::rms_error(&frozen.y[0][25..], &sp[0][25..]);
        assert!(sp_rms < 5e-3, "{sp_rms}");
        // Less than one sample: an error, not an empty or doubled record.
        let e = identify(
            Tanks::new(TanksParams::default(), Input::Held(5.0)),
            &[0.0, 0.0],
            &is,
            (0.2, 1.0),
            Weights::Initial,
            &tol,
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("duration_s") && e.contains("at least one sampling period"),
            "{e}"
        );
    }
}
