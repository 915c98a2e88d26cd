//! How the controllers of `scenarios/tanks-control.toml` were tuned: a grid search for
//! the lowest IAE on the scenario's nominal plant and set-points, for the RHONN adaptive
//! cascade and for the PI cascade with the same sensors. Run by hand (it prints the
//! best of each): `cargo test --release -p rhonn --test integration tanks_tuning -- --ignored --nocapture`.
//! And the lowest IAE any causal controller can reach there (a test).

use rhonn::control::{Cascade, Controller, IndirectSettings, Pi, RhonnIndirect};
use rhonn::experiment::closed_loop::closed_loop;
use rhonn::plant::{Input, Tanks, TanksParams};
use rhonn::signal::{PiecewiseLinear, Signal};

/// The scenario's set-points (SI): 100 mm, then 180, 120, 220 mm at 600, 1200, 1800 s.
fn setpoint() -> Signal {
    let pts = vec![
        (0.0, 0.1),
        (600.0, 0.1),
        (600.0, 0.18),
        (1200.0, 0.18),
        (1200.0, 0.12),
        (1800.0, 0.12),
        (1800.0, 0.22),
    ];
    Signal::piecewise(PiecewiseLinear::new(pts), f64::MIN, f64::MAX)
}

fn iae(ctl: &mut dyn Controller) -> f64 {
    let tanks = Tanks::new(TanksParams::default(), Input::Held(0.0));
    closed_loop(tanks, &[0.05, 0.05], ctl, 0, &setpoint(), 1.0, 2400.0).map_or(f64::INFINITY, |r| r.iae)
}

fn inner(kp_v_per_m: f64, ti_s: f64) -> Box<dyn Controller> {
    Box::new(Pi::new(kp_v_per_m, ti_s, 1.0, 0.0, 0.0, 10.0))
}

const INNER_KP: [f64; 7] = [25.0, 50.0, 100.0, 200.0, 400.0, 800.0, 1600.0];
const INNER_TI: [f64; 5] = [5.0, 10.0, 20.0, 50.0, 1e9];

#[test]
#[ignore]
fn grid_search_both_cascades() {
    let mut best = (f64::INFINITY, [0.0; 4]);
    for ikp in INNER_KP {
        for iti in INNER_TI {
            for lam in [0.05, 0.08, 0.12, 0.2, 0.3, 0.5] {
                for ys in [0.02, 0.05, 0.1] {
                    let o = RhonnIndirect::new(
                        IndirectSettings::for_pole(lam, ys),
                        1,
                        (0.0, 0.29),
                        1.0,
                        0.01,
                        0.05,
                    );
                    let v = iae(&mut Cascade::new("a", Box::new(o), inner(ikp, iti)));
                    if v < best.0 {
                        best = (v, [ikp, iti, lam, ys]);
                    }
                }
            }
        }
    }
    eprintln!(
        "RHONN cascade: IAE {:.4} m s at inner kp {} V/m, ti {} s, lambda {} 1/s, y_scale {} m",
        best.0, best.1[0], best.1[1], best.1[2], best.1[3]
    );
    let mut best = (f64::INFINITY, [0.0; 4]);
    for ikp in INNER_KP {
        for iti in INNER_TI {
            for okp in [4.0, 8.0, 16.0, 32.0, 64.0] {
                for oti in [10.0, 20.0, 30.0, 60.0, 120.0] {
                    let mut o = Pi::new(okp, oti, 1.0, 0.0, 0.0, 0.29);
                    o.measured = [1];
                    let v = iae(&mut Cascade::new("b", Box::new(o), inner(ikp, iti)));
                    if v < best.0 {
                        best = (v, [ikp, iti, okp, oti]);
                    }
                }
            }
        }
    }
    eprintln!(
        "PI cascade: IAE {:.4} m s at inner kp {} V/m, ti {} s, outer kp {}, ti {} s",
        best.0, best.1[0], best.1[1], best.1[2], best.1[3]
    );
    assert!(best.0.is_finite());
}

/// A constant input: full pump voltage or none.
struct Held([usize; 1], f64);

impl Controller for Held {
    fn name(&self) -> &'static str {
        "held"
    }
    fn measurements(&self) -> &[usize] {
        &self.0
    }
    fn control(&mut self, _t: f64, _measured: &[f64], _setpoint: f64) -> f64 {
        self.1
    }
}

/// The ceiling of issue 36's tanks goal (the adaptive cascade's IAE at most 0.8 x the PI
/// cascade's): the time-optimal answer to each set-point step (full pump voltage up, none
/// down: on this cooperative plant no input raises or lowers the lower level faster), from
/// the steady state the previous set-point holds (as any controller that tracked it does,
/// not knowing when the next step comes; the first from the scenario's initial levels),
/// counted only until the level first reaches the new set-point, already has an error area
/// above 0.8 x the shipped PI cascade's IAE. No causal controller meets the goal on the
/// nominal plant; the PI is within a fifth of the bound.
#[test]
fn the_time_optimal_bound_is_above_0_8_of_the_pi_cascade_iae() {
    let steps = [(0.05, 0.10), (0.10, 0.18), (0.18, 0.12), (0.12, 0.22)];
    let mut bound_m_s = 0.0;
    for (from, to) in steps {
        let up = to > from;
        let mut held = Held([1], if up { 10.0 } else { 0.0 });
        let tanks = Tanks::new(TanksParams::default(), Input::Held(0.0));
        let run = closed_loop(
            tanks,
            &[from, from],
            &mut held,
            0,
            &Signal::constant(to),
            0.01,
            600.0,
        )
        .unwrap();
        for k in 1..run.t.len() {
            let e = if up { to - run.y[k - 1] } else { run.y[k - 1] - to };
            if e <= 0.0 {
                break;
            }
            bound_m_s += e * (run.t[k] - run.t[k - 1]);
        }
    }
    let mut outer = Pi::new(8.0, 30.0, 1.0, 0.0, 0.0, 0.29);
    outer.measured = [1];
    let pi = iae(&mut Cascade::new("pi", Box::new(outer), inner(200.0, 10.0)));
    println!("time-optimal bound {bound_m_s} m s, PI cascade {pi} m s");
    // Measured: 9.53 against 11.04 m s (0.86 x).
    assert!(
        bound_m_s > 0.8 * pi && bound_m_s < pi,
        "bound {bound_m_s} m s, PI {pi} m s"
    );
}
