//! `[solver]` on a plant other than the pump: the tanks' control and identification
//! scenarios with the solver's profile, tolerances and largest step set in the file.

use crate::shipped;
use rhonn::experiment::{run_plant_scenario, PlantRunOutput, ScenarioSpec};

/// The shipped tanks control scenario, shortened to 600 s, with `solver` appended.
fn control(solver: &str) -> rhonn::Result<PlantRunOutput> {
    let text = shipped("tanks-control").replace("duration_s = 2400.0", "duration_s = 600.0") + solver;
    run_plant_scenario(&ScenarioSpec::from_toml(&text, "tanks-solver.toml")?, None)
}

fn iae(out: &PlantRunOutput) -> [f64; 2] {
    let [a, b]: [_; 2] = out.summary.control.clone().unwrap().try_into().unwrap();
    [a.iae, b.iae]
}

#[test]
fn a_solver_section_sets_the_tanks_tolerances() {
    let plain = control("").unwrap();
    // The runner's own settings written out give the same run to the bit.
    let mut same = control("\n[solver]\nrtol = 1e-7\natol_si = { h1 = 1e-9, h2 = 1e-9 }\n").unwrap();
    // (The settings echoed differ: one has the section written out.)
    assert!(same.summary.settings.solver.is_some() && plain.summary.settings.solver.is_none());
    same.summary.settings = plain.summary.settings.clone();
    assert_eq!(same, plain);
    // MATLAB's ode45 defaults (RelTol 1e-3, AbsTol 1e-6, MaxStep span/10): another run,
    // within a percent of the tight one.
    let coarse = control("\n[solver]\nprofile = \"ode45\"\n").unwrap();
    assert_ne!(coarse, plain);
    for (c, p) in iae(&coarse).iter().zip(iae(&plain)) {
        assert!((c / p - 1.0).abs() < 0.01, "IAE {c} against {p}");
    }
    // Absolute tolerances per state: at a loose relative tolerance, a loose absolute one
    // moves the run further.
    let rtol = control("\n[solver]\nrtol = 1e-3\n").unwrap();
    let atol = control("\n[solver]\nrtol = 1e-3\natol_si = { h1 = 1e-2, h2 = 1e-2 }\n").unwrap();
    assert_ne!(rtol, plain);
    assert_ne!(atol, rtol);
    // summary.json says the settings each run took and the solver's work over both loops:
    // the loose one fewer steps.
    let (s, p) = (&atol.summary.solver, &plain.summary.solver);
    assert_eq!(
        (s.rtol, s.atol_si["h1"], p.rtol, p.atol_si["h2"]),
        (1e-3, 1e-2, 1e-7, 1e-9)
    );
    assert!(
        s.accepted_steps < p.accepted_steps && s.rhs_evaluations > 0,
        "{s:?} against {p:?}"
    );
    let o = &coarse.summary.solver;
    assert_eq!(o.max_step_s, Some(60.0), "{o:?}"); // ode45: a tenth of the 600 s run
    assert_eq!(p.max_step_s, None);
}

#[test]
fn a_solver_section_sets_an_identification_s_tolerances() {
    let text = shipped("tanks-identify");
    let spec = ScenarioSpec::from_toml(&text, "tanks-identify.toml").unwrap();
    let plain = run_plant_scenario(&spec, None).unwrap();
    let coarse = text + "\n[solver]\nprofile = \"simulink-ode45\"\nrtol = 1e-4\n";
    let coarse = run_plant_scenario(&ScenarioSpec::from_toml(&coarse, "t.toml").unwrap(), None).unwrap();
    assert_ne!(coarse, plain);
    let fit = |o: &PlantRunOutput| o.summary.identification.clone().unwrap()[0].training_fit_percent;
    assert!(
        (fit(&coarse) - fit(&plain)).abs() < 1.0,
        "{} against {}",
        fit(&coarse),
        fit(&plain)
    );
}

#[test]
fn a_bad_solver_setting_names_its_key_and_what_is_allowed() {
    for (solver, want) in [
        (
            "atol_si = { h3 = 1e-9 }",
            "`solver.atol_si.h3` = \"h3\" is not allowed: a state of the tanks: h1, h2",
        ),
        ("atol_si = { h1 = -1.0 }", "a number > 0 (m, the state's SI unit)"),
        ("rtol = 0.5", "`solver.rtol` = 0.5"),
        ("max_step_ms = 1e-9", "`solver.max_step_ms` = 1e-9"),
        ("atol_p_line_pa = 1.0", "unknown field `atol_p_line_pa`"),
    ] {
        let e = control(&format!("\n[solver]\n{solver}\n"))
            .unwrap_err()
            .to_string();
        assert!(e.contains(want), "{solver}: {e}");
    }
}
