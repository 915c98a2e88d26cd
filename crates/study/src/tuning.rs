//! Fair baselines for the pump's adaptive controller: the cascade PI's tuning search and
//! the robustness study's plants. `examples/tune_cascade_pi.rs` and
//! `examples/control_robustness.rs` print them; tests rerun them.
//!
//! The search scores every gain set of a grid on the `control-adaptive` scenario (its
//! set-points, demand, noise and seed) with the cascade PI as the only controller, by IAE,
//! the overshoot of each set-point step and the time within 1 % of the set-point, and
//! measures its robustness in simulation: with every feedback gain doubled (kp, ki, g:
//! a 6 dB gain margin), with a 5 ms solenoid lag and with a one-period transport delay.
//! A variant "holds" when its IAE stays within twice the nominal one and it is within 1 %
//! of the set-point at least half as long. The robust tuning must also keep a 6 dB gain
//! margin and a 45 degree phase margin at six operating points, measured on the
//! simulated pump by sine injection at the current ([`margins`], [`worst_margins`]).
//!
//! Why simulation rather than a linearisation: at every operating point the pilot valve's
//! spool sits at its switching point (s = 0), where the pump's equations change branch
//! (on the s < 0 branch the valve draws line flow); the one-sided linearisations differ,
//! and a loop one of them calls unstable (kp 1 mm/MPa at 10 MPa: a pole at |z| = 1.014)
//! is well damped in the simulated pump.

use rayon::prelude::*;
use rhonn::control::{Controller, LoopContext, LoopSpec, PumpCascadePiLoop};
use rhonn::error::invalid;
use rhonn::experiment::campaign::{draw, Sampling};
use rhonn::experiment::{
    campaign_plan, drawn_scenario, nominal_plant_parameters, CascadePiGainsMpa, ScenarioSpec,
};
use rhonn::Result;

/// One run's figures.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TuningRun {
    /// IAE \[MPa s\] (infinite when the run failed).
    pub iae_mpa_s: f64,
    /// The largest overshoot of a set-point step \[%\].
    pub overshoot_percent: f64,
    /// Share of the run within 1 % of the set-point \[%\].
    pub within_1pct_percent: f64,
}

impl TuningRun {
    /// Whether a variant of the plant or loop still regulates like `nominal`.
    pub fn holds(&self, nominal: &TuningRun) -> bool {
        self.iae_mpa_s <= 2.0 * nominal.iae_mpa_s
            && self.within_1pct_percent >= 0.5 * nominal.within_1pct_percent
    }
}

/// A gain set's scores.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TuningScore {
    /// The gains.
    pub gains: CascadePiGainsMpa,
    /// On the nominal plant.
    pub nominal: TuningRun,
    /// With kp, ki and g doubled.
    pub doubled: TuningRun,
    /// With a 5 ms solenoid lag.
    pub lag_5ms: TuningRun,
    /// With a one-period transport delay.
    pub delay_1: TuningRun,
    /// The worst margins over [`OPERATING_POINTS`] ([`worst_margins`]), where the
    /// search measured them.
    pub margins: Option<Margins>,
}

/// Margins measured over several operating points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Margins {
    /// The smallest gain margin (a factor).
    pub gain: f64,
    /// The smallest phase margin \[degrees\].
    pub phase_deg: f64,
    /// Whether the measurement held at every point: the peak sensitivity measured with
    /// 2.5 and 10 mA agree within [`AMPLITUDE_TOLERANCE`]. Where they do not, the loop
    /// answers small and large signals differently (the valve's two branches) and no
    /// single margin describes it.
    pub measurable: bool,
}

impl Margins {
    /// Measurable, with at least [`MIN_GAIN_MARGIN`] and [`MIN_PHASE_MARGIN_DEG`].
    pub fn kept(&self) -> bool {
        self.measurable && self.gain >= MIN_GAIN_MARGIN && self.phase_deg >= MIN_PHASE_MARGIN_DEG
    }
}

/// How far apart (relative) the peak sensitivities measured with 2.5 and 10 mA may be for
/// a margin measurement to count.
pub const AMPLITUDE_TOLERANCE: f64 = 0.05;

/// The operating points of the margin measurements: (pressure \[MPa\], demand
/// \[dm^3/s\]), 5, 10 and 15 MPa with no demand and with 1.8 dm^3/s.
pub const OPERATING_POINTS: [(f64, f64); 6] = [
    (5.0, 0.0),
    (5.0, 1.8),
    (10.0, 0.0),
    (10.0, 1.8),
    (15.0, 0.0),
    (15.0, 1.8),
];

/// The margins the robust tuning keeps at every operating point: a gain margin of at
/// least 2 (6 dB) and a phase margin of at least 45 degrees.
pub const MIN_GAIN_MARGIN: f64 = 2.0;
/// See [`MIN_GAIN_MARGIN`] \[degrees\].
pub const MIN_PHASE_MARGIN_DEG: f64 = 45.0;

/// Injection amplitude of the sensitivity measurement in the search \[A\] (5 mA).
pub const INJECTION_A: f64 = 0.005;

/// Frequencies per operating point in the search's sensitivity measurement.
pub const SENSITIVITY_FREQUENCIES: usize = 32;

/// The smallest gain margin and phase margin of the cascade PI `gains` over
/// [`OPERATING_POINTS`], measured on the simulated pump ([`margins`]), and whether the
/// measurement held at every point ([`Margins::measurable`]).
pub fn worst_margins(gains: CascadePiGainsMpa) -> Result<Margins> {
    let mut m = Margins {
        gain: f64::INFINITY,
        phase_deg: f64::INFINITY,
        measurable: true,
    };
    for (p, q) in OPERATING_POINTS {
        let (g, ph) = margins(gains, p, q)?;
        m.gain = m.gain.min(g);
        m.phase_deg = m.phase_deg.min(ph);
        let small = sensitivity_peak(gains, p, q, SENSITIVITY_FREQUENCIES, 0.0025)?.0;
        let large = sensitivity_peak(gains, p, q, SENSITIVITY_FREQUENCIES, 0.01)?.0;
        m.measurable &= (small / large - 1.0).abs() <= AMPLITUDE_TOLERANCE;
    }
    Ok(m)
}

impl TuningScore {
    /// Every step's overshoot at most 10 % on the nominal plant.
    pub fn within_overshoot_limit(&self) -> bool {
        self.nominal.overshoot_percent <= 10.0
    }

    /// The overshoot limit, and every variant holds.
    pub fn robust(&self) -> bool {
        self.within_overshoot_limit()
            && self.doubled.holds(&self.nominal)
            && self.lag_5ms.holds(&self.nominal)
            && self.delay_1.holds(&self.nominal)
    }
}

/// The pump's cascade PI loop of gains `g` on the line pressure.
fn with_cascade_pi_loop(g: CascadePiGainsMpa) -> LoopSpec {
    LoopSpec::PumpCascadePi(PumpCascadePiLoop {
        state: "p_line".into(),
        kp_mm_per_mpa: g.kp_mm_per_mpa,
        ti_s: g.ti_s,
        setpoint_weight: g.setpoint_weight,
        stroke_gain: g.stroke_gain,
    })
}

/// `spec` (an adaptive scenario) with the cascade PI of `g` as its only controller.
pub fn with_cascade_pi(spec: &ScenarioSpec, g: CascadePiGainsMpa) -> ScenarioSpec {
    let mut s = spec.clone();
    if let Some(c) = &mut s.control {
        c.controller = with_cascade_pi_loop(g);
        (c.baseline, c.second_baseline, c.dither) = (None, None, None);
    }
    s
}

/// `spec` with the pump's solenoid lag set to `lag_ms` \[ms\].
fn with_solenoid_lag(spec: &ScenarioSpec, lag_ms: f64) -> ScenarioSpec {
    let mut s = spec.clone();
    s.plant.parameters.insert("solenoid_lag_ms".into(), lag_ms);
    s
}

/// `spec` with its command reaching the plant `periods` control periods late.
fn with_delay(spec: &ScenarioSpec, periods: u32) -> ScenarioSpec {
    let mut s = spec.clone();
    if let Some(c) = &mut s.control {
        c.delay_periods = periods;
    }
    s
}

fn simulate(spec: &ScenarioSpec) -> TuningRun {
    let figures = spec
        .run_summary()
        .ok()
        .and_then(|s| s.control)
        .and_then(|c| c.into_iter().next());
    match figures {
        Some(r) => TuningRun {
            iae_mpa_s: r.iae,
            overshoot_percent: r.overshoot_percent.iter().fold(0.0f64, |a, &b| a.max(b)),
            within_1pct_percent: r.within_1pct_percent,
        },
        None => TuningRun {
            iae_mpa_s: f64::INFINITY,
            overshoot_percent: f64::INFINITY,
            within_1pct_percent: 0.0,
        },
    }
}

/// Score one gain set on `spec`'s set-points, demand and noise.
pub fn score(spec: &ScenarioSpec, gains: CascadePiGainsMpa) -> TuningScore {
    let doubled = CascadePiGainsMpa {
        kp_mm_per_mpa: 2.0 * gains.kp_mm_per_mpa,
        stroke_gain: 2.0 * gains.stroke_gain,
        ..gains
    };
    let lag = with_solenoid_lag(&with_cascade_pi(spec, gains), 5.0);
    let delay = with_delay(&with_cascade_pi(spec, gains), 1);
    TuningScore {
        gains,
        nominal: simulate(&with_cascade_pi(spec, gains)),
        doubled: simulate(&with_cascade_pi(spec, doubled)),
        lag_5ms: simulate(&lag),
        delay_1: simulate(&delay),
        margins: None,
    }
}

/// Every combination of the given kp \[mm/MPa\], ti \[s\], b and g.
pub fn grid(kp: &[f64], ti: &[f64], b: &[f64], g: &[f64]) -> Vec<CascadePiGainsMpa> {
    let mut v = Vec::new();
    for &kp_mm_per_mpa in kp {
        for &ti_s in ti {
            for &setpoint_weight in b {
                for &stroke_gain in g {
                    v.push(CascadePiGainsMpa {
                        kp_mm_per_mpa,
                        ti_s,
                        setpoint_weight,
                        stroke_gain,
                    });
                }
            }
        }
    }
    v
}

/// The grid of `tune_cascade_pi` (5,400 gain sets).
pub fn full_grid() -> Vec<CascadePiGainsMpa> {
    grid(
        &[
            0.1, 0.15, 0.2, 0.25, 0.3, 0.35, 0.4, 0.5, 0.6, 0.75, 1.0, 1.5, 2.0, 3.0, 4.0,
        ],
        &[0.03, 0.05, 0.07, 0.1, 0.15, 0.2, 0.3, 0.4, 0.8],
        &[0.2, 0.4, 0.6, 0.8, 1.0],
        &[0.5, 1.0, 2.0, 3.0, 4.0, 6.0, 8.0, 12.0],
    )
}

/// The search on every core: (all scores, the nominal-optimal one, the robust one).
///
/// Nominal-optimal: the lowest nominal IAE within the overshoot limit. Robust: the
/// lowest nominal IAE within the overshoot limit that holds in every simulated variant
/// ([`TuningScore::robust`]) and keeps a gain margin of [`MIN_GAIN_MARGIN`] and a phase
/// margin of [`MIN_PHASE_MARGIN_DEG`] at every operating point, measurably
/// ([`Margins::kept`]); the margins are measured in order of nominal IAE until a gain set
/// qualifies (each measurement is 1,344 short simulations).
pub fn search(
    spec: &ScenarioSpec,
    gains: &[CascadePiGainsMpa],
) -> (Vec<TuningScore>, Option<TuningScore>, Option<TuningScore>) {
    let scores: Vec<TuningScore> = gains.par_iter().map(|g| score(spec, *g)).collect();
    let by_iae = |ok: &dyn Fn(&TuningScore) -> bool| {
        let mut v: Vec<TuningScore> = scores
            .iter()
            .filter(|s| ok(s) && s.nominal.iae_mpa_s.is_finite())
            .copied()
            .collect();
        v.sort_by(|a, b| a.nominal.iae_mpa_s.total_cmp(&b.nominal.iae_mpa_s));
        v
    };
    let optimal = by_iae(&TuningScore::within_overshoot_limit).first().copied();
    let robust = by_iae(&TuningScore::robust).into_iter().find_map(|mut s| {
        let m = worst_margins(s.gains).ok()?;
        s.margins = Some(m);
        m.kept().then_some(s)
    });
    (scores, optimal, robust)
}

/// The plants of the robustness study, each as the scenario `spec` changed: nominal,
/// solenoid lags of 1, 5 and 20 ms, a one-period transport delay, and the 32 corners of
/// the thesis's uncertainty box.
pub fn robustness_cases(spec: &ScenarioSpec) -> Result<Vec<(String, ScenarioSpec)>> {
    if spec.plant.kind != "pump" {
        return Err(invalid(
            "plant.kind",
            format!("{:?}", spec.plant.kind),
            "\"pump\" (the robustness study varies the pump's parameters)",
        ));
    }
    let plan = campaign_plan(spec)?;
    // The scenario's values of the plant's parameters (its `[plant]` keys, else nominal).
    let base: Vec<f64> = nominal_plant_parameters("pump")?
        .iter()
        .map(|p| spec.plant.parameters.get(p.name).copied().unwrap_or(p.nominal))
        .collect();
    let mut v = vec![("nominal".to_string(), spec.clone())];
    for lag in [1.0, 5.0, 20.0] {
        v.push((format!("solenoid lag {lag} ms"), with_solenoid_lag(spec, lag)));
    }
    v.push(("transport delay 1 period".into(), with_delay(spec, 1)));
    for k in 0..32u64 {
        let f = draw(&plan, 0, k, Sampling::Corners);
        let pct = |j: usize| 100.0 * (f[j] / base[j] - 1.0);
        v.push((
            format!(
                "beta {:+.0}% mu1 {:+.0}% mu2 {:+.0}% Q0 {:+.0}% slew {:+.0}%",
                pct(0),
                pct(1),
                pct(2),
                pct(3),
                pct(4)
            ),
            drawn_scenario(spec, &f)?,
        ));
    }
    Ok(v)
}

/// The cascade PI with a sinusoid added to its output after `t_on`, keeping what it
/// computed (for the loop gain at the current).
struct Injected {
    inner: Box<dyn Controller>,
    amplitude_a: f64,
    w: f64,
    t_on: f64,
    computed: Vec<f64>,
}

impl Controller for Injected {
    fn name(&self) -> &'static str {
        "cascade-pi with injection"
    }
    fn measurements(&self) -> &[usize] {
        self.inner.measurements()
    }
    fn control(&mut self, t: f64, measured: &[f64], setpoint: f64) -> f64 {
        let c = self.inner.control(t, measured, setpoint);
        self.computed.push(c);
        c + if t >= self.t_on {
            self.amplitude_a * (self.w * t).sin()
        } else {
            0.0
        }
    }
}

/// A complex number as (real, imaginary): a first harmonic.
type Harmonic = (f64, f64);

/// First harmonics (cosine, sine parts) over whole periods of the controller's output
/// u = c + d, of what it computed, c, and of the injected sinusoid d of `amplitude_a`
/// \[A\] at `w` \[rad/s\], with the cascade PI `gains` on the nominal pump held at
/// `p_mpa` with a constant demand `q_dm3_s`, after the transient.
fn harmonics(
    gains: CascadePiGainsMpa,
    p_mpa: f64,
    q_dm3_s: f64,
    w: f64,
    amplitude_a: f64,
) -> Result<[Harmonic; 3]> {
    use rhonn::plant::{pump, Input, PumpParams, PumpSystem};
    // An angular frequency below 0.1 rad/s would ask for hours of simulated loop.
    if !(w.is_finite() && (0.1..=1e4).contains(&w)) {
        return Err(invalid("w (rad/s)", w, "a number in [0.1, 10000]"));
    }
    if !(amplitude_a.is_finite() && (0.0..=0.8).contains(&amplitude_a)) {
        return Err(invalid(
            "amplitude_a",
            amplitude_a,
            "a number of amperes in [0, 0.8]",
        ));
    }
    if !(p_mpa.is_finite() && q_dm3_s.is_finite() && p_mpa > 0.0 && q_dm3_s >= 0.0) {
        return Err(invalid(
            "operating point",
            format!("{p_mpa} MPa, {q_dm3_s} dm^3/s"),
            "a pressure > 0 and a demand >= 0",
        ));
    }
    let k = PumpParams::default();
    let q = q_dm3_s * 1e-3;
    let x_eq = (q + k.q_0) / (k.k_l * k.omega);
    let i_eq = k.k_a * x_eq / k.phi;
    let plant = PumpSystem::new(k.clone(), Input::Held(i_eq), Input::Held(q));
    let setpoint = rhonn::signal::Signal::constant(p_mpa * 1e6);
    let x0 = [p_mpa * 1e6, x_eq, i_eq];
    // The cascade PI as a scenario names it, built against the nominal pump by the
    // controller registry.
    let spec = with_cascade_pi_loop(gains);
    let cx = LoopContext {
        plant: "pump",
        states: &pump::STATES,
        field: "cascade-pi".into(),
        output: &pump::INPUTS[0],
        range: (0.0, k.i_max),
        period_s: k.t_control,
        setpoint0: setpoint.eval(0.0),
        x0: &x0,
        operating_input: i_eq,
    };
    let period = 2.0 * std::f64::consts::PI / w;
    let t_on = 1.0;
    let (skip, count) = (3.0, (8.0f64).max((2.0 / period).ceil()));
    let duration = t_on + (skip + count) * period + k.t_control;
    let (from, to) = (t_on + skip * period, t_on + (skip + count) * period);
    let run_with = |amplitude_a: f64| -> Result<[Harmonic; 3]> {
        let mut ctl = Injected {
            inner: spec.build(&cx)?,
            amplitude_a,
            w,
            t_on,
            computed: Vec::new(),
        };
        let run = rhonn::experiment::closed_loop::closed_loop(
            plant.clone(),
            &x0,
            &mut ctl,
            0,
            &setpoint,
            k.t_control,
            duration,
        )?;
        let mut h = [(0.0, 0.0); 3];
        for ((&t, &u), &c) in run.t.iter().zip(&run.u).zip(&ctl.computed) {
            if t >= from && t < to {
                let (s, co) = (w * t).sin_cos();
                for (hk, v) in h.iter_mut().zip([u, c, amplitude_a * s]) {
                    *hk = (hk.0 + v * co, hk.1 - v * s);
                }
            }
        }
        Ok(h)
    };
    // The same loop without the injection, subtracted: what the loop does on its own
    // (the valve's hunting between its branches, a slow settling) is not a response to d.
    let (with, without) = (run_with(amplitude_a)?, run_with(0.0)?);
    let mut h = with;
    for (hk, b) in h.iter_mut().zip(without) {
        *hk = (hk.0 - b.0, hk.1 - b.1);
    }
    Ok(h)
}

/// `a / b` for complex numbers as (re, im) pairs.
fn cdiv(a: Harmonic, b: Harmonic) -> Harmonic {
    let den = b.0 * b.0 + b.1 * b.1;
    ((a.0 * b.0 + a.1 * b.1) / den, (a.1 * b.0 - a.0 * b.1) / den)
}

/// The loop gain L(jw) at the current of the cascade PI `gains` on the nominal pump held
/// at `p_mpa` with a constant demand `q_dm3_s`, **measured on the simulated pump**: a
/// sinusoid of 5 mA at `w` \[rad/s\] is added to the controller's output u = c + d; with
/// c = -L u, L = -C/U from the first harmonics of c and u over whole periods after the
/// transient, minus those of the same run without the sinusoid (a describing function:
/// the pilot valve's two branches are averaged as the loop sees them). Returns (|L|,
/// arg L in degrees).
pub fn loop_gain(gains: CascadePiGainsMpa, p_mpa: f64, q_dm3_s: f64, w: f64) -> Result<(f64, f64)> {
    let l = loop_gain_complex(gains, p_mpa, q_dm3_s, w, INJECTION_A)?;
    Ok((l.0.hypot(l.1), l.1.atan2(l.0).to_degrees()))
}

/// L(jw) = -C/U as a complex number, with an injection of `amplitude_a` \[A\].
fn loop_gain_complex(
    gains: CascadePiGainsMpa,
    p_mpa: f64,
    q_dm3_s: f64,
    w: f64,
    amplitude_a: f64,
) -> Result<Harmonic> {
    let [u, c, _] = harmonics(gains, p_mpa, q_dm3_s, w, amplitude_a)?;
    Ok(cdiv((-c.0, -c.1), u))
}

/// |S(jw)| = |U/D| = |1 / (1 + L(jw))|, the sensitivity at the current of the cascade PI
/// `gains` on the simulated pump, from an injected sinusoid of `amplitude_a` \[A\] as in
/// [`loop_gain`]. Unlike L, S is measured where it matters for the margins: near the
/// crossover |U| is about |D|, so the ratio is well conditioned however slow the loop.
pub fn sensitivity(
    gains: CascadePiGainsMpa,
    p_mpa: f64,
    q_dm3_s: f64,
    w: f64,
    amplitude_a: f64,
) -> Result<f64> {
    let [u, _, d] = harmonics(gains, p_mpa, q_dm3_s, w, amplitude_a)?;
    let s = cdiv(u, d);
    Ok(s.0.hypot(s.1))
}

fn log_grid(from: f64, to: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|j| from * (to / from).powf(j as f64 / (n - 1) as f64))
        .collect()
}

/// Frequencies of the sensitivity measurement: a log grid of `n` from 2 to 400 rad/s.
/// Above about 64 % of the Nyquist frequency (628 rad/s) the first harmonic of a
/// sampled sinusoid over a few periods mixes with its alias at 2 pi / T - w, and the
/// ratio |U/D| is no longer a measurement of S.
pub fn sensitivity_frequencies(n: usize) -> Vec<f64> {
    log_grid(2.0, 400.0, n)
}

/// The peak sensitivity M_s = max_w |S(jw)| over [`sensitivity_frequencies`]`(n)` at one
/// operating point, and the frequency of the peak \[rad/s\]. M_s bounds both margins
/// from below, whatever the shape of L (the Nyquist curve keeps a distance 1/M_s from
/// -1; Astrom & Hagglund, *Advanced PID Control*, 2006, section 4.2): the gain margin is
/// at least M_s / (M_s - 1), the phase margin at least 2 arcsin(1 / (2 M_s)); M_s = 1.3
/// gives at least 12.7 dB and 45.2 degrees.
pub fn sensitivity_peak(
    gains: CascadePiGainsMpa,
    p_mpa: f64,
    q_dm3_s: f64,
    n: usize,
    amplitude_a: f64,
) -> Result<(f64, f64)> {
    if n < 2 {
        return Err(invalid("n (frequencies)", n, "at least 2"));
    }
    let ws = sensitivity_frequencies(n);
    let s: Vec<f64> = ws
        .par_iter()
        .map(|&w| sensitivity(gains, p_mpa, q_dm3_s, w, amplitude_a))
        .collect::<Result<_>>()?;
    let j = (0..n).max_by(|&a, &b| s[a].total_cmp(&s[b])).unwrap_or(0);
    Ok((s[j], ws[j]))
}

/// The margins M_s guarantees: (gain margin as a factor, phase margin in degrees).
pub fn margins_of_peak(ms: f64) -> (f64, f64) {
    let gm = if ms > 1.0 { ms / (ms - 1.0) } else { f64::INFINITY };
    let pm = 2.0 * (1.0 / (2.0 * ms)).min(1.0).asin().to_degrees();
    (gm, pm)
}

/// Gain margin (factor) and phase margin (degrees) of the cascade PI `gains` at one
/// operating point, read from the loop gain L(jw) = 1/S - 1 measured as in
/// [`sensitivity`] on [`sensitivity_frequencies`]`(48)` (2-400 rad/s), on the Nyquist
/// curve itself, so no phase is unwrapped: the phase margin is 180 degrees + arg L
/// (wrapped to (-180, 180]) where |L| crosses 1, the gain margin 1/|L| where the curve
/// crosses the negative real axis inside the unit circle. Without such a crossing below
/// 400 rad/s, the gain margin returned is 1/|L(400 rad/s)|, a lower bound when the
/// phase keeps falling.
///
/// The measurement subtracts the loop's motion without injection, so it does not depend
/// on the injected amplitude (2.5-10 mA agree to about 1 % on the shipped tunings; a
/// test checks it), which an earlier version without the subtraction did not.
pub fn margins(gains: CascadePiGainsMpa, p_mpa: f64, q_dm3_s: f64) -> Result<(f64, f64)> {
    let ws = sensitivity_frequencies(48);
    let ls: Vec<Harmonic> = ws
        .par_iter()
        .map(|&w| loop_gain_complex(gains, p_mpa, q_dm3_s, w, INJECTION_A))
        .collect::<Result<_>>()?;
    let abs = |l: Harmonic| l.0.hypot(l.1);
    let lerp = |a: Harmonic, b: Harmonic, f: f64| (a.0 + f * (b.0 - a.0), a.1 + f * (b.1 - a.1));
    let (mut gm, mut pm) = (1.0 / abs(ls[ls.len() - 1]), f64::INFINITY);
    for pair in ls.windows(2) {
        let (l0, l1) = (pair[0], pair[1]);
        let (m0, m1) = (abs(l0), abs(l1));
        if (m0 - 1.0) * (m1 - 1.0) <= 0.0 && m0 != m1 {
            let l = lerp(l0, l1, m0.ln() / (m0.ln() - m1.ln()));
            let mut margin = 180.0 + l.1.atan2(l.0).to_degrees();
            if margin > 180.0 {
                margin -= 360.0;
            }
            pm = pm.min(margin);
        }
        if l0.1 * l1.1 <= 0.0 && l0.1 != l1.1 {
            let l = lerp(l0, l1, l0.1 / (l0.1 - l1.1));
            if l.0 < 0.0 && abs(l) < 1.0 {
                gm = gm.min(1.0 / abs(l));
            }
        }
    }
    Ok((gm, pm))
}
