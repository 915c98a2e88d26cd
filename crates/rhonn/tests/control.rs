//! Issue 5: RHONN indirect adaptive control. Tests of the theory (an affine RHONN plant
//! with known weights; the projection), and the pump: the adaptive cascade against the
//! PI baseline on the nominal plant, lagged and delayed solenoids, and every corner of
//! the thesis's uncertainty box.

use rhonn::control::AffineNeuron;
use rhonn::experiment::campaign::{draw, PumpCampaign, Sampling};
use rhonn::experiment::{preset, run_full, NoRecorder, RunOutput, ScenarioSpec, Trace};
use rhonn::net::Sigmoid;

fn features(x: f64) -> ([f64; 2], [f64; 2]) {
    let s = Sigmoid::LOGISTIC.eval(x);
    ([1.0, s], [1.0, s - 0.5])
}

/// A plant that is an affine RHONN with known weights, `dx/dt = w* S(x) + (w1* S'(x)) u`,
/// regulated by the certainty-equivalence law `u = (-lambda x - W S) / (W_1 S')` of a
/// neuron that learns online from `W = 0` and a wrong `W_1`. Returns the final
/// `(x, x^, e)` and the largest `|W_1 - centre|`.
fn regulate(
    w_star: [f64; 2],
    w1_star: [f64; 2],
    w1_0: [f64; 2],
    radius: f64,
    t_end: f64,
) -> (f64, f64, f64, f64) {
    let mut nn = AffineNeuron::<2, 2> {
        a: 5.0,
        gamma: 20.0,
        gamma1: 20.0,
        w: [0.0; 2],
        w1: w1_0,
        center: w1_0,
        radius,
        w_bound: 1e3,
        xh: 1.0,
    };
    let lambda = 2.0;
    let dt = 1e-3;
    let mut x: f64 = 1.0;
    let mut dist_max: f64 = 0.0;
    let plant = |x: f64, u: f64| {
        let (s, s1) = features(x);
        w_star[0] * s[0] + w_star[1] * s[1] + (w1_star[0] * s1[0] + w1_star[1] * s1[1]) * u
    };
    let steps = (t_end / dt) as usize;
    for _ in 0..steps {
        let (s, s1) = features(x);
        let (f, g) = nn.drift_and_gain(&s, &s1);
        let u = (-lambda * x - f) / g;
        // The plant over one step (RK4, input held), then the identifier over the same
        // step on the plant's start and end states.
        let k1 = plant(x, u);
        let k2 = plant(x + 0.5 * dt * k1, u);
        let k3 = plant(x + 0.5 * dt * k2, u);
        let k4 = plant(x + dt * k3, u);
        let x1 = x + dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
        nn.advance(dt, 1, (x, x1), (u, u), true, features);
        x = x1;
        dist_max = dist_max.max(nn.w1_distance());
        assert!(x.is_finite() && nn.w_norm().is_finite());
    }
    (x, nn.xh, nn.xh - x, dist_max)
}

#[test]
fn the_closed_loop_drives_the_state_the_model_and_the_error_to_zero() {
    // The plant would leave 0 on its own (positive drift); the neuron starts knowing
    // nothing of the drift and with a gain 40 % off.
    let (x, xh, e, dist) = regulate([0.6, 1.5], [2.0, 0.4], [1.2, 0.0], 1.0, 30.0);
    assert!(x.abs() < 1e-3, "x = {x}");
    assert!(xh.abs() < 1e-3, "x^ = {xh}");
    assert!(e.abs() < 1e-4, "e = {e}");
    assert!(dist <= 1.0 + 1e-12);
    // Without learning the same loop does not reach zero: the test can fail.
    let mut frozen = AffineNeuron::<2, 2> {
        a: 5.0,
        gamma: 0.0,
        gamma1: 0.0,
        w: [0.0; 2],
        w1: [1.2, 0.0],
        center: [1.2, 0.0],
        radius: 1.0,
        w_bound: 1e3,
        xh: 1.0,
    };
    let mut x: f64 = 1.0;
    for _ in 0..30_000 {
        let (s, s1) = features(x);
        let (f, g) = frozen.drift_and_gain(&s, &s1);
        let u = (-2.0 * x - f) / g;
        let dx = 0.6 + 1.5 * s[1] + (2.0 + 0.4 * s1[1]) * u;
        x += 1e-3 * dx;
        frozen.xh = x;
    }
    assert!(x.abs() > 0.1, "a frozen wrong model leaves an offset: x = {x}");
}

#[test]
fn the_projection_keeps_the_gain_weights_in_their_ball() {
    // The true gain is 3 times the ball's centre and the input is exciting: the
    // learning law pushes W_1 out of the ball; the projection must hold it on the
    // sphere at every step.
    let (w_star, w1_star, c, radius) = ([0.3, 0.5], [3.6, 0.6], [1.2, 0.0], 0.5);
    let mut nn = AffineNeuron::<2, 2> {
        a: 5.0,
        gamma: 20.0,
        gamma1: 20.0,
        w: [0.0; 2],
        w1: c,
        center: c,
        radius,
        w_bound: 1e3,
        xh: 0.0,
    };
    let plant = |x: f64, u: f64| {
        let (s, s1) = features(x);
        w_star[0] * s[0] + w_star[1] * s[1] + (w1_star[0] * s1[0] + w1_star[1] * s1[1]) * u
    };
    let (dt, mut x, mut dist_max, mut projected) = (1e-3, 0.0f64, 0.0f64, false);
    for k in 0..20_000 {
        let t = k as f64 * dt;
        // Bounded by a feedback of its own, exciting by the sine.
        let u = -x - 0.2 + (2.0 * t).sin();
        let k1 = plant(x, u);
        let k2 = plant(x + 0.5 * dt * k1, u);
        let k3 = plant(x + 0.5 * dt * k2, u);
        let k4 = plant(x + dt * k3, u);
        let x1 = x + dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
        projected |= nn.advance(dt, 1, (x, x1), (u, u), true, features);
        x = x1;
        let d = nn.w1_distance();
        assert!(d <= radius * (1.0 + 1e-12), "t = {t}: |W_1 - c| = {d} > {radius}");
        dist_max = dist_max.max(d);
    }
    assert!(projected, "the projection never acted");
    assert!(
        dist_max > 0.999 * radius,
        "the run did not push W_1 to the boundary: {dist_max}"
    );
    // W_1 S' stays away from zero on the whole sigmoid range.
    for k in 0..=10 {
        let s1 = [1.0, k as f64 / 10.0 - 0.5];
        assert!(nn.w1[0] * s1[0] + nn.w1[1] * s1[1] > 0.5);
    }
    assert!(x.is_finite() && x.abs() < 10.0, "x = {x}");
    // Without the projection the same run leaves the ball: the test can fail.
    let mut free = AffineNeuron {
        radius: 1e9,
        ..nn.clone()
    };
    free.w1 = c;
    free.center = c;
    let mut x = 0.0f64;
    for k in 0..20_000 {
        let u = -x - 0.2 + (2.0 * k as f64 * dt).sin();
        let x1 = x + dt * plant(x, u);
        free.advance(dt, 1, (x, x1), (u, u), true, features);
        x = x1;
    }
    assert!(
        free.w1_distance() > radius,
        "unprojected |W_1 - c| = {}",
        free.w1_distance()
    );
}

/// `s` with the pump's solenoid lag set to `ms`.
fn lag(s: &mut ScenarioSpec, ms: f64) {
    s.plant.parameters.insert("solenoid_lag_ms".into(), ms);
}

fn run_case(f: impl Fn(&mut ScenarioSpec)) -> RunOutput {
    let mut spec = preset::load_any("control-adaptive").unwrap();
    f(&mut spec);
    run_full(&spec.pump_run().unwrap(), &mut NoRecorder).unwrap()
}

/// (ISE, settled max deviation, time below P_min after 1 s, bounded) of both controllers.
fn figures(out: &RunOutput) -> ([f64; 3], [f64; 3], bool, bool) {
    let fa = &out.summary.figures;
    let c = out.summary.control.as_ref().expect("an adaptive run");
    let fb = &c.baseline.figures;
    let (ra, rb) = (fa.regulation.as_ref().unwrap(), fb.regulation.as_ref().unwrap());
    (
        [
            ra.ise_mpa2_s,
            ra.max_abs_deviation_settled_mpa,
            fa.time_below_p_min_after_1s_s,
        ],
        [
            rb.ise_mpa2_s,
            rb.max_abs_deviation_settled_mpa,
            fb.time_below_p_min_after_1s_s,
        ],
        ra.signals_bounded,
        rb.signals_bounded,
    )
}

#[test]
fn nominal_plant_adaptive_beats_the_cascade_pi_in_the_same_run() {
    let mut spec = preset::load_any("control-adaptive").unwrap();
    spec.duration_s = 60.0;
    let sc = spec.pump_run().unwrap();
    let mut trace = Trace::default();
    let out = run_full(&sc, &mut trace).unwrap();
    for col in [
        "p_line",
        "p_line_pi",
        "current",
        "current_pi",
        "p_ref",
        "stroke_ref",
        "w_norm",
        "w1_norm",
    ] {
        assert!(trace.column(col).is_some(), "missing column {col}");
    }
    let (a, b, bounded_a, bounded_b) = figures(&out);
    assert!(bounded_a && bounded_b);
    assert!(a[0] < b[0], "ISE adaptive {} vs PI {}", a[0], b[0]);
    assert!(a[1] < b[1], "max dev adaptive {} vs PI {}", a[1], b[1]);
    assert_eq!(a[2], 0.0, "adaptive below P_min after the start");
    let c = out.summary.control.as_ref().unwrap();
    assert!(c.adaptive.w1_distance_max <= c.adaptive.w1_ball_radius);
    assert!(c.adaptive_better(&out.summary.figures));
    // The two plants saw the same demand and set-point, and differ only by controller.
    let (p, p_pi) = (
        trace.column("p_line").unwrap(),
        trace.column("p_line_pi").unwrap(),
    );
    assert_eq!(p.len(), p_pi.len());
    assert!(p.iter().zip(p_pi).any(|(a, b)| (a - b).abs() > 1e5));
}

#[test]
fn fast_unmodeled_dynamics_and_a_delay_adaptive_stays_above_p_min_and_beats_the_robust_cascade_pi() {
    type Change = Box<dyn Fn(&mut ScenarioSpec)>;
    let cases: [(&str, Change); 3] = [
        ("lag 1 ms", Box::new(|s| lag(s, 1.0))),
        ("lag 5 ms", Box::new(|s| lag(s, 5.0))),
        (
            "delay 1 period",
            Box::new(|s| s.control.as_mut().unwrap().delay_periods = 1),
        ),
    ];
    for (name, f) in cases {
        let out = run_case(f);
        let (a, b, ba, _) = figures(&out);
        assert!(ba, "{name}: adaptive unbounded");
        assert!(a[0] < b[0] && a[1] < b[1], "{name}: adaptive {a:?} PI {b:?}");
        assert_eq!(a[2], 0.0, "{name}: adaptive below P_min {a:?}");
    }
}

#[test]
fn a_slow_solenoid_20_ms_adaptive_stays_bounded_and_beats_the_cascade_pi() {
    // Documented in the README: with a 20 ms lag the adaptive controller spends about
    // 1.2 s below P_min (the PI: 21 s); it stays bounded and has the lower ISE.
    let out = run_case(|s| lag(s, 20.0));
    let (a, b, ba, _) = figures(&out);
    assert!(ba);
    assert!(
        a[0] < b[0] && a[1] < b[1] && a[2] < b[2],
        "adaptive {a:?} PI {b:?}"
    );
}

#[test]
fn every_corner_of_the_uncertainty_box_bounded_and_lower_ise_than_the_cascade_pi() {
    let mut worse_max_dev = Vec::new();
    let mut below = Vec::new();
    for k in 0..32u64 {
        // Bit j of k picks the sign of tolerance j (beta, mu_1, mu_2, Q_0, slew).
        let out = run_case(|s| {
            let c = PumpCampaign::of(s).unwrap().expect("a pump scenario");
            *s = c.run_scenario(
                &draw(&c.plan(), 0, k, Sampling::Corners),
                s.name.clone(),
                s.description.clone(),
            );
        });
        let (a, b, ba, _) = figures(&out);
        assert!(ba, "corner {k}: adaptive unbounded");
        assert!(a[0] < b[0], "corner {k}: ISE adaptive {} PI {}", a[0], b[0]);
        assert!(
            a[2] <= b[2],
            "corner {k}: below P_min adaptive {} PI {}",
            a[2],
            b[2]
        );
        if a[1] >= b[1] {
            worse_max_dev.push(k);
        }
        if a[2] > 0.0 {
            below.push(k);
        }
    }
    // Only corners with faster demand ramps (slew +10 %) reach P_min (never longer than
    // the PI, asserted above): the quieter default (identifier filter 70 1/s, drift
    // learning 1e4) follows the 1.8 dm^3/s ramp's end more slowly than the earlier, busier
    // one, which reached P_min only with a slow pilot valve and more leakage as well.
    let fast_ramp = |k: &u64| k >> 4 & 1 == 1;
    assert!(below.iter().all(fast_ramp), "below P_min: {below:?}");
    println!("worst deviation not lower than the PI's at corners {worse_max_dev:?}");
    assert!(worse_max_dev.len() <= 8, "max dev not lower: {worse_max_dev:?}");
}

/// Issue "fair classical baseline": the search of `tune_cascade_pi`, rerun on a
/// neighbourhood of both shipped tunings (with gain sets that fail each criterion, among
/// them the earlier robust tuning, which holds in every simulated variant but keeps only
/// 25 degrees of phase margin at 15 MPa with demand), picks exactly those tunings.
#[test]
fn the_tuning_search_picks_both_shipped_cascade_pi_tunings() {
    use rhonn::experiment::tuning::{grid, search, worst_margins, MIN_PHASE_MARGIN_DEG};
    use rhonn::experiment::{CascadePiGainsMpa, NOMINAL_OPTIMAL, ROBUST};
    let spec = preset::load_any("control-adaptive").unwrap();
    let g = grid(
        &[0.15, 0.2, 0.75, 1.0],
        &[0.05, 0.07],
        &[0.2, 0.6, 0.8],
        &[4.0, 6.0, 8.0],
    );
    let (scores, optimal, robust) = search(&spec, &g);
    assert_eq!(optimal.unwrap().gains, NOMINAL_OPTIMAL);
    assert_eq!(robust.unwrap().gains, ROBUST);
    // Each criterion rules something out: the grid is not trivially robust.
    assert!(scores.iter().any(|s| s.within_overshoot_limit() && !s.robust()));
    assert!(scores.iter().any(|s| !s.within_overshoot_limit()));
    let r = robust.unwrap();
    assert!(r.lag_5ms.holds(&r.nominal) && r.delay_1.holds(&r.nominal) && r.doubled.holds(&r.nominal));
    let m = r.margins.unwrap();
    assert!(
        m.kept() && m.gain >= 2.0 && m.phase_deg >= MIN_PHASE_MARGIN_DEG,
        "{m:?}"
    );
    // The margins rule out a faster gain set that every simulated variant passes.
    let earlier = CascadePiGainsMpa {
        kp_mm_per_mpa: 0.2,
        ti_s: 0.05,
        setpoint_weight: 0.6,
        stroke_gain: 6.0,
    };
    let e = scores.iter().find(|s| s.gains == earlier).unwrap();
    assert!(e.robust() && e.nominal.iae_mpa_s < r.nominal.iae_mpa_s);
    let m = worst_margins(earlier).unwrap();
    assert!(m.measurable && m.phase_deg < MIN_PHASE_MARGIN_DEG, "{m:?}");
    let o = optimal.unwrap();
    assert!(
        !o.lag_5ms.holds(&o.nominal),
        "the nominal-optimal tuning is fragile"
    );
}

/// The earlier goals, on IAE alone: lower IAE than the nominal-optimal cascade PI on the
/// nominal plant and at least 28 of the 32 corners, lower than the robust one with every
/// lag and the delay, and within 1 % of the set-point at least 60 % of the nominal run.
#[test]
fn adaptive_has_lower_iae_than_both_cascade_pi_tunings_where_the_goals_say() {
    use rhonn::experiment::tuning::robustness_cases;
    let cases = robustness_cases(&preset::load_any("control-adaptive").unwrap()).unwrap();
    assert_eq!(cases.len(), 37);
    let mut corners_won = 0;
    for (name, spec) in &cases {
        let out = run_full(&spec.pump_run().unwrap(), &mut NoRecorder).unwrap();
        let ra = out.summary.figures.regulation.clone().unwrap();
        let c = out.summary.control.as_ref().unwrap();
        assert_eq!(c.baseline.controller, "cascade-pi");
        let robust = c.baseline.figures.regulation.clone().unwrap();
        // The second baseline of the same run: the nominal-optimal tuning.
        let second = c
            .second_baseline
            .as_ref()
            .expect("the shipped scenario's second baseline");
        assert_eq!(second.tuning, Some("nominal-optimal"));
        let opt = second.figures.regulation.clone().unwrap();
        if name == "nominal" {
            assert!(
                ra.iae_mpa_s < opt.iae_mpa_s,
                "nominal: {} vs {}",
                ra.iae_mpa_s,
                opt.iae_mpa_s
            );
            assert!(
                ra.within_1pct_percent >= 60.0,
                "within 1 %: {}",
                ra.within_1pct_percent
            );
        } else if name.starts_with("solenoid") || name.starts_with("transport") {
            assert!(
                ra.iae_mpa_s < robust.iae_mpa_s,
                "{name}: {} vs {}",
                ra.iae_mpa_s,
                robust.iae_mpa_s
            );
        } else {
            corners_won += (ra.iae_mpa_s < opt.iae_mpa_s) as usize;
        }
    }
    // The quieter default (a quarter of the earlier one's valve activity) gives up a few
    // corners on IAE alone (the earlier one won 30 or more); on IAE at no more activity it
    // wins far more often (`every_shipped_adaptive_setting_beats_the_cascade_front`).
    assert!(corners_won >= 28, "{corners_won} of 32 corners");
}

/// The integral action removes the adaptive controller's steady offset: with it the
/// pressure is within 1 % of the set-point for more of the run (default settings: 58 %
/// without, 72 % with; the earlier, busier default: a quarter without, 60 % with).
#[test]
fn integral_action_removes_the_steady_offset() {
    let share = |ki: f64| {
        let mut spec = preset::load_any("control-adaptive").unwrap();
        if let Some(rhonn::experiment::LoopSpec::PumpRhonnAdaptive(knobs)) =
            spec.control.as_mut().map(|c| &mut c.controller)
        {
            knobs.integral_per_s2 = Some(ki);
        }
        let out = run_full(&spec.pump_run().unwrap(), &mut NoRecorder).unwrap();
        out.summary.figures.regulation.unwrap().within_1pct_percent
    };
    let (without, with) = (share(0.0), share(1000.0));
    assert!(
        with > without + 10.0 && with > 65.0,
        "within 1 %: {without} without, {with} with"
    );
}

/// The margins measured on the simulated pump by sine injection are a measurement: the
/// loop gain is above 1 at low frequency and below 1 at high; the peak sensitivity does
/// not depend on the injected amplitude (2.5 and 10 mA agree within 3 %); the phase
/// margin read where |L| = 1 is at least what the peak sensitivity guarantees
/// (2 arcsin(1 / (2 M_s))), at every operating point; and the robust tuning keeps 6 dB
/// and 45 degrees everywhere.
#[test]
fn the_measured_margins_are_consistent_and_the_robust_tuning_keeps_them() {
    use rhonn::experiment::tuning::{
        loop_gain, margins, margins_of_peak, sensitivity_peak, OPERATING_POINTS,
    };
    use rhonn::experiment::ROBUST;
    // Nonsense arguments are errors, not hours of simulation.
    assert!(loop_gain(ROBUST, 10.0, 0.0, 0.0).is_err());
    assert!(sensitivity_peak(ROBUST, f64::NAN, 0.0, 8, 0.005).is_err());
    assert!(sensitivity_peak(ROBUST, 10.0, 0.0, 8, -1.0).is_err());
    assert!(sensitivity_peak(ROBUST, 10.0, 0.0, 0, 0.005).is_err());
    let (low, _) = loop_gain(ROBUST, 10.0, 0.0, 10.0).unwrap();
    let (high, _) = loop_gain(ROBUST, 10.0, 0.0, 400.0).unwrap();
    assert!(low > 1.0 && high < 1.0, "|L(10)| = {low}, |L(400)| = {high}");
    for (p, q) in OPERATING_POINTS {
        let (small, _) = sensitivity_peak(ROBUST, p, q, 24, 0.0025).unwrap();
        let (large, _) = sensitivity_peak(ROBUST, p, q, 24, 0.01).unwrap();
        assert!(
            (small / large - 1.0).abs() < 0.03,
            "{p} MPa, {q} dm^3/s: M_s {small} at 2.5 mA, {large} at 10 mA"
        );
        let (gm, pm) = margins(ROBUST, p, q).unwrap();
        let (_, pm_bound) = margins_of_peak(small.max(large));
        assert!(
            pm >= pm_bound - 1.0,
            "{p} MPa, {q} dm^3/s: phase margin {pm} below {pm_bound}"
        );
        assert!(
            gm >= 2.0 && pm >= 45.0,
            "{p} MPa, {q} dm^3/s: margins {gm}, {pm} deg"
        );
    }
}

/// IAE against the valve's activity (`rhonn::experiment::front`): every shipped adaptive
/// setting's nominal IAE is at least 20 % below the best cascade PI IAE reachable at the
/// same or lower current total variation (1,540 gain sets); the default is within 1 % of
/// the set-point at least 65 % of the run and beats the nominal-optimal cascade PI's IAE at
/// no more current activity on every one of the 37 plants of the robustness study.
#[test]
fn every_shipped_adaptive_setting_beats_the_cascade_front() {
    use rhonn::experiment::front::{
        best_iae_within, cascade_grid, cascade_points, nominal_optimal_points, points, wins,
    };
    use rhonn::experiment::tuning::robustness_cases;
    let spec = preset::load_any("control-adaptive").unwrap();
    let gains = cascade_grid();
    let cascade = cascade_points(&spec, &gains);
    for name in [
        "control-adaptive",
        "control-adaptive-gentle",
        "control-adaptive-fast",
    ] {
        let a = points(
            "rhonn-adaptive",
            vec![(name.into(), preset::load_any(name).unwrap())],
        )
        .remove(0);
        let b = best_iae_within(&cascade, a.current_total_variation_a).expect("a cascade at that activity");
        assert!(
            a.iae_mpa_s <= 0.8 * b.iae_mpa_s,
            "{name}: IAE {} at {} A; best cascade {} at {} A",
            a.iae_mpa_s,
            a.current_total_variation_a,
            b.iae_mpa_s,
            b.current_total_variation_a
        );
        if name == "control-adaptive" {
            assert!(a.within_1pct_percent >= 65.0, "{}", a.within_1pct_percent);
        }
    }
    let cases = robustness_cases(&spec).unwrap();
    let no = nominal_optimal_points(&cases);
    let lag_20 = cases.iter().position(|(n, _)| n == "solenoid lag 20 ms").unwrap();
    let (name, mut without_bank) = cases[lag_20].clone();
    if let Some(rhonn::experiment::LoopSpec::PumpRhonnAdaptive(knobs)) =
        without_bank.control.as_mut().map(|c| &mut c.controller)
    {
        knobs.actuator_memory_s = Some(0.0);
    }
    let a = points("rhonn-adaptive", cases);
    let wins = wins(&a, &no);
    assert_eq!(wins, 37, "{wins} of 37");
    // Behind a 20 ms solenoid lag: at most 40 MPa s, which the stroke loop reaches by
    // identifying the lag online and scheduling its gain on it (without: 44).
    let off = points("rhonn-adaptive", vec![(name, without_bank)]).remove(0);
    assert!(
        a[lag_20].iae_mpa_s <= 40.0 && off.iae_mpa_s > a[lag_20].iae_mpa_s,
        "20 ms lag: IAE {} (without the actuator's identification {})",
        a[lag_20].iae_mpa_s,
        off.iae_mpa_s
    );
}

/// A Monte Carlo campaign over the tolerances (the first 300 runs of `rhonn campaign
/// control-adaptive --runs 1000 --seed 1`): the adaptive controller has the lower IAE at no
/// more current activity than the nominal-optimal cascade PI in at least 95 % of them (all
/// 1,000 of the full campaign; 926 before the stroke loop identified its actuator online).
#[test]
fn monte_carlo_the_adaptive_wins_on_iae_and_activity_in_95_percent_of_runs() {
    use rayon::prelude::*;
    let spec = PumpCampaign::of(&preset::load_any("control-adaptive").unwrap())
        .unwrap()
        .unwrap();
    let names = spec.figure_names();
    let at = |n: &str| {
        names
            .iter()
            .position(|x| x == n)
            .unwrap_or_else(|| panic!("no {n}"))
    };
    let (iae, tv) = (at("iae_mpa_s"), at("current_total_variation_a"));
    let (iae2, tv2) = (
        at("second_baseline_iae_mpa_s"),
        at("second_baseline_current_total_variation_a"),
    );
    let rows: Vec<Vec<f64>> = (0..300u64)
        .into_par_iter()
        .map(|k| spec.run_one(1, k, Sampling::Random, false).0.outcome.unwrap())
        .collect();
    let wins = rows
        .iter()
        .filter(|v| v[iae] < v[iae2] && v[tv] <= v[tv2])
        .count();
    assert!(wins * 100 >= 95 * rows.len(), "{wins} of {}", rows.len());
}

/// `control-adaptive` runs the adaptive controller against both cascade PI tunings in the
/// same run, on identical plants: the second baseline's figures are those of the
/// nominal-optimal cascade run on its own; `trajectory.csv` has all three controllers'
/// pressure and current; the findings compare the adaptive controller with each.
#[test]
fn control_adaptive_compares_with_both_cascade_tunings_in_one_run() {
    use rhonn::experiment::tuning::with_cascade_pi;
    use rhonn::experiment::{Trace, NOMINAL_OPTIMAL};
    let spec = preset::load_any("control-adaptive").unwrap();
    let mut trace = Trace::default();
    let out = run_full(&spec.pump_run().unwrap(), &mut trace).unwrap();
    let c = out.summary.control.as_ref().unwrap();
    let second = c.second_baseline.as_ref().unwrap();
    assert_eq!(
        (second.controller, second.tuning),
        ("cascade-pi", Some("nominal-optimal"))
    );
    let alone = run_full(
        &with_cascade_pi(&spec, NOMINAL_OPTIMAL).pump_run().unwrap(),
        &mut NoRecorder,
    )
    .unwrap();
    let (r2, ra) = (
        second.figures.regulation.clone().unwrap(),
        alone.summary.figures.regulation.unwrap(),
    );
    assert_eq!(
        (r2.iae_mpa_s, r2.current_total_variation_a),
        (ra.iae_mpa_s, ra.current_total_variation_a)
    );
    for col in [
        "p_line",
        "p_line_pi",
        "p_line_pi2",
        "current",
        "current_pi",
        "current_pi2",
    ] {
        let v = trace.column(col).unwrap_or_else(|| panic!("no column {col}"));
        assert_eq!(v.len(), trace.column("t").unwrap().len());
    }
    let adaptive = out.summary.figures.regulation.as_ref().unwrap();
    let robust = c.baseline.figures.regulation.as_ref().unwrap();
    // Nominal plant: the adaptive's IAE is below both tunings', at less current activity
    // than the nominal-optimal one's.
    assert!(adaptive.iae_mpa_s < r2.iae_mpa_s && adaptive.iae_mpa_s < robust.iae_mpa_s);
    assert!(adaptive.current_total_variation_a < r2.current_total_variation_a);
    assert!(c
        .findings
        .iter()
        .any(|f| f.starts_with("IAE") && f.contains("cascade-pi-nominal-optimal")));
}
