use rhonn::control::*;
use rhonn::experiment::any_plant::closed_loop;
use rhonn::plant::{Input, Tanks, TanksParams};
use rhonn::signal::{PiecewiseLinear, Signal};

fn sp() -> Signal {
    Signal::piecewise(
        PiecewiseLinear::new(vec![
            (0.0, 0.1),
            (600.0, 0.1),
            (601.0, 0.18),
            (1200.0, 0.18),
            (1201.0, 0.12),
            (1800.0, 0.12),
            (1801.0, 0.22),
        ]),
        f64::MIN,
        f64::MAX,
    )
}
fn run(ctl: &mut dyn Controller) -> (f64, f64) {
    let tanks = Tanks::new(TanksParams::default(), Input::Held(0.0));
    match closed_loop(tanks, &[0.05, 0.05], ctl, 0, &sp(), 1.0, 2400.0) {
        Ok(r) => (r.iae, r.final_error()),
        Err(_) => (f64::INFINITY, 0.0),
    }
}
fn inner(kp: f64, ti: f64) -> Pi {
    Pi::new(kp, ti, 1.0, 0.0, 0.0, 10.0)
}

#[test]
#[ignore]
fn scratch() {
    let mut best = (f64::INFINITY, vec![]);
    for &ikp in &[25.0, 50.0, 100.0, 200.0, 400.0, 800.0, 1600.0] {
        for &iti in &[5.0, 10.0, 20.0, 50.0, 1e9] {
            for &lam in &[0.05, 0.08, 0.12, 0.2, 0.3, 0.5] {
                for &ys in &[0.02, 0.05, 0.1] {
                    let o = RhonnIndirect::new(
                        IndirectSettings::for_pole(lam, ys),
                        1,
                        (0.0, 0.29),
                        1.0,
                        0.01,
                        0.05,
                    );
                    let mut c = Cascade::new("a", Box::new(o), Box::new(inner(ikp, iti)));
                    let (iae, _) = run(&mut c);
                    if iae < best.0 {
                        best = (iae, vec![ikp, iti, lam, ys]);
                    }
                }
            }
        }
    }
    eprintln!("rhonn-cascade best IAE {:.3} at {:?}", best.0, best.1);
    let mut best = (f64::INFINITY, vec![]);
    for &ikp in &[25.0, 50.0, 100.0, 200.0, 400.0, 800.0, 1600.0] {
        for &iti in &[5.0, 10.0, 20.0, 50.0, 1e9] {
            for &okp in &[4.0, 8.0, 16.0, 32.0, 64.0] {
                for &oti in &[10.0, 20.0, 30.0, 60.0, 120.0] {
                    let mut o = Pi::new(okp, oti, 1.0, 0.0, 0.0, 0.29);
                    o.measured = [1];
                    let mut c = Cascade::new("b", Box::new(o), Box::new(inner(ikp, iti)));
                    let (iae, _) = run(&mut c);
                    if iae < best.0 {
                        best = (iae, vec![ikp, iti, okp, oti]);
                    }
                }
            }
        }
    }
    eprintln!("pi-cascade best IAE {:.3} at {:?}", best.0, best.1);
    let mut best = (f64::INFINITY, vec![]);
    for &kp in &[80.0, 160.0, 320.0, 640.0, 1280.0] {
        for &ti in &[20.0, 40.0, 80.0, 160.0, 320.0, 640.0] {
            let mut p = Pi::new(kp, ti, 1.0, 0.0, 0.0, 10.0);
            p.measured = [1];
            let (iae, _) = run(&mut p);
            if iae < best.0 {
                best = (iae, vec![kp, ti]);
            }
        }
    }
    eprintln!("pi best IAE {:.3} at {:?}", best.0, best.1);
}
