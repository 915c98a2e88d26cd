//! Known-answer problems: closed-form solutions, convergence order, event times,
//! limited integrators, breakpoints, and the errors a user can cause.
#![allow(clippy::field_reassign_with_default)]

use rhonn_ode::{Direction, Dopri5, Error, EventAction, EventKind, Options, Profile, StepResult, System};
use std::f64::consts::PI;

/// dx/dt = -x.
struct Decay;
impl System for Decay {
    type State = [f64; 1];
    fn dim(&self) -> usize {
        1
    }
    fn rhs(&self, _t: f64, x: &[f64], dx: &mut [f64]) {
        dx[0] = -x[0];
    }
}

/// x'' = -x as a first-order system.
struct Oscillator;
impl System for Oscillator {
    type State = [f64; 2];
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&self, _t: f64, x: &[f64], dx: &mut [f64]) {
        dx[0] = x[1];
        dx[1] = -x[0];
    }
}

fn run_to<S: System>(s: &mut Dopri5<S>, t_end: f64) {
    while !matches!(s.step(t_end).unwrap(), StepResult::Reached { .. }) {}
}

/// Fixed step h: tolerances so loose that no step is rejected.
fn fixed(h: f64, dim: usize) -> Options<Vec<f64>> {
    let mut o = Options::uniform(dim, 0.5, 1e30);
    o.h_init_s = Some(h);
    o.h_max_s = h;
    o
}

struct VecOsc;
impl System for VecOsc {
    type State = Vec<f64>;
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&self, _t: f64, x: &[f64], dx: &mut [f64]) {
        dx[0] = x[1];
        dx[1] = -x[0];
    }
}

#[test]
fn decay_matches_closed_form() {
    let mut s = Dopri5::new(Decay, 0.0, [1.0], Options::uniform(1, 1e-10, 1e-12)).unwrap();
    run_to(&mut s, 5.0);
    assert!((s.state()[0] - (-5.0f64).exp()).abs() < 1e-11, "{}", s.state()[0]);
    assert_eq!(s.t(), 5.0);
}

#[test]
fn global_error_is_fifth_order() {
    let err = |h: f64| {
        let mut s = Dopri5::new(VecOsc, 0.0, vec![1.0, 0.0], fixed(h, 2)).unwrap();
        run_to(&mut s, 2.0);
        assert_eq!(s.stats().rejected_steps, 0);
        ((s.state()[0] - 2.0f64.cos()).powi(2) + (s.state()[1] + 2.0f64.sin()).powi(2)).sqrt()
    };
    let (e1, e2) = (err(0.1), err(0.05));
    let order = (e1 / e2).log2();
    assert!(
        (4.7..5.5).contains(&order),
        "observed order {order} ({e1:e} -> {e2:e})"
    );
}

#[test]
fn dense_output_is_fourth_order_between_steps() {
    // Maximum interpolation error over many points inside the steps.
    let err = |h: f64| {
        let mut s = Dopri5::new(VecOsc, 0.0, vec![1.0, 0.0], fixed(h, 2)).unwrap();
        let mut worst: f64 = 0.0;
        let mut out = [0.0; 2];
        loop {
            let r = s.step(2.0).unwrap();
            for k in 1..10 {
                let t = s.t_prev() + (s.t() - s.t_prev()) * k as f64 / 10.0;
                s.interpolate(t, &mut out);
                worst = worst.max((out[0] - t.cos()).abs());
            }
            if matches!(r, StepResult::Reached { .. }) {
                break;
            }
        }
        worst
    };
    let (e1, e2) = (err(0.2), err(0.1));
    let order = (e1 / e2).log2();
    assert!(order > 3.7, "dense output order {order} ({e1:e} -> {e2:e})");
    assert!(e2 < 1e-6, "{e2:e}");
}

#[test]
fn oscillator_with_tight_tolerance_over_ten_periods() {
    let mut s = Dopri5::new(Oscillator, 0.0, [1.0, 0.0], Options::uniform(2, 1e-10, 1e-12)).unwrap();
    run_to(&mut s, 20.0 * PI);
    assert!((s.state()[0] - 1.0).abs() < 1e-8);
    assert!(s.state()[1].abs() < 1e-8);
}

/// A ball dropped from 10 m, restitution 0.8: the bounce times are known.
struct Ball {
    bounces: Vec<f64>,
}
impl System for Ball {
    type State = [f64; 2];
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&self, _t: f64, x: &[f64], dx: &mut [f64]) {
        dx[0] = x[1];
        dx[1] = -9.81;
    }
    fn n_events(&self) -> usize {
        1
    }
    fn events(&self, _t: f64, x: &[f64], g: &mut [f64]) {
        g[0] = x[0];
    }
    fn event_direction(&self, _j: usize) -> Direction {
        Direction::Falling
    }
    fn on_event(&mut self, _j: usize, t: f64, x: &mut [f64]) -> EventAction {
        self.bounces.push(t);
        x[0] = 0.0;
        x[1] *= -0.8;
        if self.bounces.len() == 5 {
            EventAction::Stop
        } else {
            EventAction::Continue
        }
    }
}

#[test]
fn bouncing_ball_event_times_within_1e9_s() {
    let mut s = Dopri5::new(
        Ball { bounces: vec![] },
        0.0,
        [10.0, 0.0],
        Options::uniform(2, 1e-10, 1e-10),
    )
    .unwrap();
    let r = s.solve_to(100.0, |_, _| {}).unwrap();
    assert!(matches!(
        r,
        StepResult::Stopped {
            kind: EventKind::User(0),
            ..
        }
    ));
    let g: f64 = 9.81;
    let mut t = (2.0 * 10.0 / g).sqrt();
    let mut v = g * t;
    for (k, &tk) in s.system().bounces.iter().enumerate() {
        assert!((tk - t).abs() < 1e-9, "bounce {k}: {tk} vs {t}");
        v *= 0.8;
        t += 2.0 * v / g;
    }
    assert_eq!(s.stats().events, 5);
}

/// dx/dt = cos t, limited to \[-0.5, 0.5\].
struct Saturating;
impl System for Saturating {
    type State = [f64; 1];
    fn dim(&self) -> usize {
        1
    }
    fn rhs(&self, t: f64, _x: &[f64], dx: &mut [f64]) {
        dx[0] = t.cos();
    }
    fn bounds(&self, _i: usize) -> (f64, f64) {
        (-0.5, 0.5)
    }
}

#[test]
fn limited_integrator_holds_and_releases_at_the_right_times() {
    // While the state is held its derivative is zero and nothing limits the step but
    // h_max: an event function checked at step ends cannot see a sign change that
    // comes and goes within one step.
    let mut opts = Options::uniform(1, 1e-9, 1e-12);
    opts.h_max_s = 0.2;
    let mut s = Dopri5::new(Saturating, 0.0, [0.0], opts).unwrap();
    let mut events = vec![];
    let mut worst: f64 = 0.0;
    let mut out = [0.0];
    // Closed form: sin t until pi/6, held at 0.5 until pi/2, then sin t - 0.5 until pi,
    // held at -0.5 until 3pi/2, then sin t + 0.5 ... (period 2pi from pi/2 on).
    let exact = |t: f64| -> f64 {
        if t <= PI / 6.0 {
            t.sin()
        } else if t <= PI / 2.0 {
            0.5
        } else {
            let tau = (t - PI / 2.0).rem_euclid(2.0 * PI) + PI / 2.0;
            if tau <= PI {
                tau.sin() - 0.5
            } else if tau <= 1.5 * PI {
                -0.5
            } else if tau <= 2.0 * PI {
                tau.sin() + 0.5
            } else {
                0.5
            }
        }
    };
    s.solve_to(4.0 * PI, |s, r| {
        if let StepResult::Event { t, kind } = r {
            events.push((t, kind));
        }
        for k in 0..=4 {
            let t = s.t_prev() + (s.t() - s.t_prev()) * k as f64 / 4.0;
            s.interpolate(t, &mut out);
            worst = worst.max((out[0] - exact(t)).abs());
        }
    })
    .unwrap();
    let expected = [
        (PI / 6.0, EventKind::Upper(0)),
        (PI / 2.0, EventKind::Released(0)),
        (PI, EventKind::Lower(0)),
        (1.5 * PI, EventKind::Released(0)),
        (2.0 * PI, EventKind::Upper(0)),
        (2.5 * PI, EventKind::Released(0)),
        (3.0 * PI, EventKind::Lower(0)),
        (3.5 * PI, EventKind::Released(0)),
    ];
    assert_eq!(events.len(), expected.len(), "{events:?}");
    for ((t, k), (te, ke)) in events.iter().zip(expected) {
        assert_eq!(*k, ke);
        assert!((t - te).abs() < 1e-9, "{k:?} at {t} vs {te}");
    }
    assert!(worst < 1e-7, "max error {worst:e}");
    // It ends on the upward run from the lower bound, 0.5 + sin(4pi) = 0.5: the bound.
    assert!((s.state()[0] - 0.5).abs() < 1e-7);
}

#[test]
fn state_starting_on_a_bound_with_zero_derivative_is_released_when_it_turns_inward() {
    // dx/dt = t, x in [0, 1], x(0) = 0: held at t = 0 (derivative 0), then released.
    struct Ramp;
    impl System for Ramp {
        type State = [f64; 1];
        fn dim(&self) -> usize {
            1
        }
        fn rhs(&self, t: f64, _x: &[f64], dx: &mut [f64]) {
            dx[0] = t;
        }
        fn bounds(&self, _i: usize) -> (f64, f64) {
            (0.0, 1.0)
        }
    }
    let mut s = Dopri5::new(Ramp, 0.0, [0.0], Options::default()).unwrap();
    run_to(&mut s, 1.0);
    assert!((s.state()[0] - 0.5).abs() < 1e-8, "{}", s.state()[0]);
}

/// dx/dt = u(t), u a unit step at t = 1 that the system selects per segment.
struct StepInput {
    on: bool,
}
impl System for StepInput {
    type State = [f64; 1];
    fn dim(&self) -> usize {
        1
    }
    fn rhs(&self, _t: f64, _x: &[f64], dx: &mut [f64]) {
        dx[0] = if self.on { 1.0 } else { 0.0 };
    }
    fn update_modes(&mut self, t: f64, _x: &[f64]) {
        self.on = t >= 1.0;
    }
    fn next_breakpoint(&self, t: f64) -> f64 {
        if t < 1.0 {
            1.0
        } else {
            f64::INFINITY
        }
    }
}

#[test]
fn steps_land_on_breakpoints_and_jumps_cost_no_rejections() {
    let mut s = Dopri5::new(StepInput { on: false }, 0.0, [0.0], Options::default()).unwrap();
    let mut landed = false;
    s.solve_to(3.0, |_, r| landed |= r == StepResult::Breakpoint { t: 1.0 })
        .unwrap();
    assert!(landed);
    assert!((s.state()[0] - 2.0).abs() < 1e-12);
    assert_eq!(s.stats().rejected_steps, 0);
    assert_eq!(s.stats().breakpoints, 2);
}

#[test]
fn ode45_profile_meets_its_tolerance() {
    let mut s = Dopri5::new(Oscillator, 0.0, [1.0, 0.0], Options::ode45(2, 10.0)).unwrap();
    assert_eq!(s.options().profile, Profile::Ode45);
    run_to(&mut s, 10.0);
    let e = (s.state()[0] - 10.0f64.cos()).abs();
    assert!(e < 1e-2 && e > 1e-9, "{e:e}");
    // Coarse tolerances: a handful of steps, never longer than MaxStep = 1 s.
    assert!(
        s.stats().accepted_steps >= 10 && s.stats().accepted_steps < 60,
        "{}",
        s.stats()
    );
}

#[test]
fn nan_in_the_right_hand_side_is_an_error_with_time_and_state() {
    struct Blow;
    impl System for Blow {
        type State = [f64; 1];
        fn dim(&self) -> usize {
            1
        }
        fn rhs(&self, t: f64, x: &[f64], dx: &mut [f64]) {
            dx[0] = if t > 0.5 { f64::NAN } else { x[0] };
        }
    }
    let mut s = Dopri5::new(Blow, 0.0, [1.0], Options::default()).unwrap();
    let e = s.solve_to(1.0, |_, _| {}).unwrap_err();
    match e {
        Error::NonFinite { t, state } => {
            assert!(t > 0.4 && t <= 0.5, "{t}");
            assert!(state.values()[0] > 1.0);
        }
        other => panic!("{other}"),
    }
}

#[test]
fn finite_time_blow_up_underflows_the_step() {
    // dx/dt = x^2, x(0) = 1 blows up at t = 1.
    struct Blow;
    impl System for Blow {
        type State = [f64; 1];
        fn dim(&self) -> usize {
            1
        }
        fn rhs(&self, _t: f64, x: &[f64], dx: &mut [f64]) {
            dx[0] = x[0] * x[0];
        }
    }
    let mut opts = Options::default();
    opts.h_min_s = 1e-10;
    let mut s = Dopri5::new(Blow, 0.0, [1.0], opts).unwrap();
    let e = s.solve_to(2.0, |_, _| {}).unwrap_err();
    assert!(
        matches!(e, Error::StepSizeUnderflow { t, .. } | Error::NonFinite { t, .. } if (t - 1.0).abs() < 1e-3),
        "{e}"
    );
}

#[test]
fn bad_options_name_the_field_and_the_range() {
    let mut o = Options::<[f64; 1]>::default();
    o.rtol = [-1.0];
    let e = Dopri5::new(Decay, 0.0, [1.0], o).err().unwrap();
    assert_eq!(
        e.to_string(),
        "solver option `rtol` = -1e0 is not allowed: a number in [1e-14, 1)"
    );
    let mut o = Options::<[f64; 1]>::default();
    o.h_max_s = 0.0;
    let e = Dopri5::new(Decay, 0.0, [1.0], o).err().unwrap();
    assert!(e.to_string().contains("h_max_s"));
    let e = Dopri5::new(Saturating, 0.0, [0.7], Options::default())
        .err()
        .unwrap();
    assert!(e.to_string().contains("outside the limits"), "{e}");
}

#[test]
fn solver_and_options_are_send_sync_clone_where_campaigns_need_it() {
    fn check<T: Send + Sync + Clone>() {}
    check::<Options<[f64; 2]>>();
    check::<Options<Vec<f64>>>();
    check::<Error>();
    fn send<T: Send>() {}
    send::<Dopri5<Oscillator>>();
}

/// Two breakpoints a rounding error apart (6.8 as k * 5 / 1000, and 6.4 + 0.4).
struct NearBreakpoints;
impl System for NearBreakpoints {
    type State = [f64; 1];
    fn dim(&self) -> usize {
        1
    }
    fn rhs(&self, t: f64, _x: &[f64], dx: &mut [f64]) {
        dx[0] = t.sin();
    }
    fn next_breakpoint(&self, t: f64) -> f64 {
        let b = 6.4 + 0.4;
        if t < b {
            b
        } else {
            f64::INFINITY
        }
    }
}

#[test]
fn a_breakpoint_a_rounding_error_after_the_stop_time_is_no_step_underflow() {
    let mut s = Dopri5::new(NearBreakpoints, 0.0, [0.0], Options::default()).unwrap();
    let stop = 1360.0 * 5.0 / 1000.0;
    assert!(stop < 6.4 + 0.4);
    s.solve_to(stop, |_, _| {}).unwrap();
    s.solve_to(10.0, |_, _| {}).unwrap();
    assert!((s.state()[0] - (1.0 - 10.0f64.cos())).abs() < 1e-6);
}

/// Free, limited to \[-0.5, 0.5\], free, limited to \[-0.25, 0.25\]: the limited ones
/// are `dx/dt = cos t`, the free ones decay.
struct TwoLimited;
impl System for TwoLimited {
    type State = [f64; 4];
    fn dim(&self) -> usize {
        4
    }
    fn rhs(&self, t: f64, x: &[f64], dx: &mut [f64]) {
        dx[0] = -x[0];
        dx[1] = t.cos();
        dx[2] = -2.0 * x[2];
        dx[3] = t.cos();
    }
    fn bounds(&self, i: usize) -> (f64, f64) {
        match i {
            1 => (-0.5, 0.5),
            3 => (-0.25, 0.25),
            _ => (f64::NEG_INFINITY, f64::INFINITY),
        }
    }
}

#[test]
fn limited_states_among_free_ones_are_each_held_at_their_own_bounds() {
    let mut opts = Options::uniform(4, 1e-9, 1e-12);
    opts.h_max_s = 0.2;
    let mut s = Dopri5::new(TwoLimited, 0.0, [1.0, 0.0, 1.0, 0.0], opts).unwrap();
    let mut events = vec![];
    let mut dense_checked = 0;
    s.solve_to(3.0, |s, r| {
        if let StepResult::Event { t, kind } = r {
            events.push((t, kind));
        }
        // One component's dense polynomial gives what dense_at gives, bit for bit.
        for i in 0..4 {
            let c = s.dense_component(i);
            for th in [0.0, 0.3, 0.77, s.step_fraction()] {
                assert_eq!(c.at(th).to_bits(), s.dense_at(th, i).to_bits());
                dense_checked += 1;
            }
        }
    })
    .unwrap();
    let expected = [
        (0.25f64.asin(), EventKind::Upper(3)),
        (PI / 6.0, EventKind::Upper(1)),
        // Both held states turn inward at pi/2: one release is located, the restart
        // after it frees the other (its unclamped derivative already points inward).
        (PI / 2.0, EventKind::Released(3)),
        (5.0 * PI / 6.0, EventKind::Lower(3)),
    ];
    assert_eq!(events.len(), expected.len(), "{events:?}");
    for ((t, k), (te, ke)) in events.iter().zip(expected) {
        assert_eq!(*k, ke);
        assert!((t - te).abs() < 1e-8, "{k:?} at {t} vs {te}");
    }
    // At 3 s: the first limited state runs sin t - 1/2 since its release, the second
    // is held at its lower bound; the free ones decayed untouched by the others' holds.
    let x = s.state();
    assert!((x[0] - (-3.0f64).exp()).abs() < 1e-8, "{}", x[0]);
    assert!((x[1] - (3.0f64.sin() - 0.5)).abs() < 1e-8, "{}", x[1]);
    assert!((x[2] - (-6.0f64).exp()).abs() < 1e-8, "{}", x[2]);
    assert_eq!(x[3], -0.25);
    assert!(dense_checked > 40);
}
