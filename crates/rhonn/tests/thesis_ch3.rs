//! `thesis-ch3` against an independent high-accuracy reference: scipy's DOP853 at
//! rtol 1e-12 with its own event handling, written from pump-model.md alone
//! (`tools/reference/pump_reference.py`, output committed in `tests/data`).

use rhonn::experiment::{preset, PlantRunOutput};

fn reference() -> Vec<[f64; 3]> {
    let text = include_str!("data/thesis_ch3_reference.csv");
    text.lines()
        .skip(1)
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|c| c.parse().unwrap()).collect();
            [v[0], v[1], v[2]]
        })
        .collect()
}

fn simulate() -> PlantRunOutput {
    preset::load_any("thesis-ch3").unwrap().run().unwrap()
}

#[test]
fn agrees_with_the_independent_reference_at_every_millisecond() {
    let trace = simulate();
    let r = reference();
    let t = trace.column("t").unwrap();
    let p = trace.column("p_line").unwrap();
    let x = trace.column("stroke").unwrap();
    assert_eq!(t.len(), r.len());
    let mut worst_x: f64 = 0.0;
    let mut p_off = 0;
    let mut worst_p: f64 = 0.0;
    for k in 0..r.len() {
        assert!((t[k] - r[k][0]).abs() < 1e-9);
        worst_x = worst_x.max((x[k] - r[k][2]).abs());
        let dp = (p[k] - r[k][1]).abs();
        worst_p = worst_p.max(dp);
        if dp > 0.1e6 {
            p_off += 1;
        }
    }
    // Stroke within 0.01 mm at every millisecond.
    assert!(worst_x < 0.01e-3, "worst stroke difference {} mm", worst_x * 1e3);
    // Line pressure within 0.1 MPa on more than 99.5 % of the samples.
    let frac = 1.0 - p_off as f64 / r.len() as f64;
    assert!(
        frac > 0.995,
        "{frac} within 0.1 MPa (worst {} MPa)",
        worst_p / 1e6
    );
    eprintln!(
        "worst stroke difference {:.3e} mm, worst pressure difference {:.3e} MPa, {} samples off by > 0.1 MPa",
        worst_x * 1e3,
        worst_p / 1e6,
        p_off
    );
}

#[test]
fn tells_the_story_of_the_thesis() {
    let trace = simulate();
    let s = &trace.summary;
    let t = trace.column("t").unwrap();
    let p = trace.column("p_line").unwrap();
    let x = trace.column("stroke").unwrap();
    let at = |time: f64| ((time * 1000.0).round()) as usize;
    // The pressure first falls (lubricating flow, no pump flow) ...
    assert!(p[at(0.5)] < 0.5e6, "{}", p[at(0.5)]);
    // ... rises once the pump flow exceeds Q_0, and is held at P_max while the stroke is large ...
    assert!(p[at(2.0)] == 25e6 && p[at(20.0)] == 25e6 && p[at(38.0)] == 25e6);
    // ... and falls on the down-stroke.
    assert!(p[at(39.5)] < 5e6);
    // The stroke follows phi I / K_a with a lag and holds 17.23 mm at 0.8 A.
    assert!((x[at(20.0)] * 1e3 - 17.23).abs() < 0.005);
    let lag = {
        // time for the stroke to reach the steady stroke of the current at t = 10 s
        let x_ss = 28.0 * (0.8 * 10.0 / 15.0) / 1300.0;
        let k = x.iter().position(|&v| v >= x_ss).unwrap();
        t[k] - 10.0
    };
    assert!((0.03..0.3).contains(&lag), "lag {lag} s");
    // Time below P_min agrees with the reference's samples (1 ms resolution).
    let r = reference();
    let below_ref = r.windows(2).filter(|w| w[0][1] < 1e6).count() as f64 * 1e-3;
    let below = s.floor.as_ref().unwrap().time_below_s;
    assert!((below - below_ref).abs() < 0.01, "{below} vs {below_ref}");
    let p_line = &s.open_loop.as_ref().unwrap()[0];
    assert_eq!((p_line.state, p_line.max_value), ("p_line", 25.0));
    assert!(s.solver.events >= 4);
}

#[test]
fn ode45_compatible_profile_is_coarser_and_cheaper_but_close() {
    let mut spec = preset::load_any("thesis-ch3").unwrap();
    spec.solver = Some(rhonn::experiment::SolverSpec {
        profile: rhonn::experiment::ProfileSpec::Ode45,
        ..Default::default()
    });
    let trace = spec.run().unwrap();
    let s = &trace.summary;
    assert_eq!(s.solver.rtol, 1e-3);
    assert_eq!(s.solver.max_step_s, Some(4.0));
    let fine = simulate().summary;
    assert!(s.solver.rhs_evaluations < fine.solver.rhs_evaluations);
    let r = reference();
    let x = trace.column("stroke").unwrap();
    let worst = r.iter().zip(x).map(|(r, x)| (r[2] - x).abs()).fold(0.0, f64::max);
    // RelTol 1e-3 on a 17 mm stroke: a few hundredths of a millimetre.
    assert!(worst < 0.05e-3 && worst > 1e-6, "{} mm", worst * 1e3);
    assert_eq!(s.solver.events, fine.solver.events);
}
