//! Issue 5: RHONN indirect adaptive control. Tests of the theory (an affine RHONN plant
//! with known weights; the projection), and the pump: the adaptive cascade against the
//! PI baseline on the nominal plant, lagged and delayed solenoids, and every corner of
//! the thesis's uncertainty box.

use rhonn::control::AffineNeuron;
use rhonn::experiment::campaign::{draw, Sampling};
use rhonn::experiment::{campaign_plan, drawn_scenario, preset, PlantRunOutput, ScenarioSpec};
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

fn run_case(f: impl Fn(&mut ScenarioSpec)) -> PlantRunOutput {
    let mut spec = preset::load_any("control-adaptive").unwrap();
    f(&mut spec);
    spec.run().unwrap()
}

/// (ISE, settled max deviation, time below P_min after 1 s, bounded) of both controllers.
fn figures(out: &PlantRunOutput) -> ([f64; 3], [f64; 3], bool, bool) {
    let c = out.summary.control.as_ref().expect("a loop");
    let (ra, rb) = (&c[0], &c[1]);
    let f = |r: &rhonn::experiment::LoopFigures| {
        [
            r.ise,
            r.max_abs_deviation_settled,
            r.time_below_floor_after_settle_s.expect("the pump's floor"),
        ]
    };
    (f(ra), f(rb), ra.states_bounded, rb.states_bounded)
}

#[test]
fn nominal_plant_adaptive_beats_the_cascade_pi_in_the_same_run() {
    let mut spec = preset::load_any("control-adaptive").unwrap();
    spec.duration_s = 60.0;
    let out = spec.run().unwrap();
    let trace = &out;
    for col in [
        "p_line",
        "p_line_baseline",
        "current",
        "current_baseline",
        "p_line_ref",
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
    let adaptive = out.summary.control.as_ref().unwrap()[0].adaptive.clone().unwrap();
    assert!(adaptive.w1_distance_max <= adaptive.w1_ball_radius);
    // Better on every figure: ISE, settled deviation, time below P_min.
    assert!(
        a[0] < b[0] && a[1] < b[1] && a[2] <= b[2],
        "adaptive {a:?} PI {b:?}"
    );
    // The two plants saw the same demand and set-point, and differ only by controller.
    let (p, p_pi) = (
        trace.column("p_line").unwrap(),
        trace.column("p_line_baseline").unwrap(),
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
            let plan = campaign_plan(s).unwrap();
            *s = drawn_scenario(s, &draw(&plan, 0, k, Sampling::Corners)).unwrap();
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
        spec.run().unwrap().summary.control.unwrap()[0].within_1pct_percent
    };
    let (without, with) = (share(0.0), share(1000.0));
    assert!(
        with > without + 10.0 && with > 65.0,
        "within 1 %: {without} without, {with} with"
    );
}

/// A Monte Carlo campaign over the tolerances (the first 300 runs of `rhonn campaign
/// control-adaptive --runs 1000 --seed 1`): the adaptive controller has the lower IAE at no
/// more current activity than the nominal-optimal cascade PI in at least 95 % of them (all
/// 1,000 of the full campaign; 926 before the stroke loop identified its actuator online).
#[test]
fn monte_carlo_the_adaptive_wins_on_iae_and_activity_in_95_percent_of_runs() {
    use rayon::prelude::*;
    let spec = preset::load_any("control-adaptive").unwrap();
    let plan = campaign_plan(&spec).unwrap();
    // (IAE, input total variation) of the adaptive controller and of the second baseline.
    let rows: Vec<[f64; 4]> = (0..300u64)
        .into_par_iter()
        .map(|k| {
            let run = drawn_scenario(&spec, &draw(&plan, 1, k, Sampling::Random)).unwrap();
            let c = run.run().unwrap().summary.control.unwrap();
            [
                c[0].iae,
                c[0].input_total_variation,
                c[2].iae,
                c[2].input_total_variation,
            ]
        })
        .collect();
    let (iae, tv, iae2, tv2) = (0, 1, 2, 3);
    let wins = rows
        .iter()
        .filter(|v| v[iae] < v[iae2] && v[tv] <= v[tv2])
        .count();
    assert!(wins * 100 >= 95 * rows.len(), "{wins} of {}", rows.len());
}
