//! The adaptive cascade against the PI baseline on the nominal plant, the lagged and
//! delayed solenoids, and every corner of the thesis's uncertainty box (beta, mu_1,
//! mu_2 +-20 %, Q_0 +-10 %, demand slew +-10 %); controllers tuned once, on the
//! nominal plant. `cargo run --release -p rhonn --example control_robustness`

use rhonn::experiment::campaign::{apply, base_values, draw, Plan, Sampling};
use rhonn::experiment::{preset, run_full, NoRecorder, ScenarioSpec};

/// A plant of the study: its name and how it changes the scenario.
type Case = (String, Box<dyn Fn(&mut ScenarioSpec)>);

/// The plants of the robustness study.
pub fn cases() -> Vec<Case> {
    let nominal = preset::load("control-adaptive").expect("a shipped preset");
    let (plan, base) = (
        Plan::of(&nominal).expect("the preset's plan"),
        base_values(&nominal),
    );
    let mut v: Vec<Case> = vec![("nominal".into(), Box::new(|_| {}))];
    for lag in [1.0, 5.0, 20.0] {
        v.push((
            format!("solenoid lag {lag} ms"),
            Box::new(move |s| s.plant.solenoid_lag_ms = lag),
        ));
    }
    v.push((
        "transport delay 1 period".into(),
        Box::new(|s| s.plant.transport_delay_periods = 1),
    ));
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
            Box::new(move |s| *s = apply(s, &f)),
        ));
    }
    v
}

fn main() -> Result<(), rhonn::Error> {
    println!(
        "| plant | adaptive ISE | PI ISE | adaptive max dev | PI max dev | adaptive below P_min | PI below P_min | adaptive better |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for (name, f) in cases() {
        let mut spec = preset::load("control-adaptive")?;
        f(&mut spec);
        let sc = spec.check()?;
        let out = run_full(&sc, &mut NoRecorder)?;
        let fa = &out.summary.figures;
        let c = out.summary.control.as_ref().expect("an adaptive run");
        let fb = &c.baseline.figures;
        let (ra, rb) = (fa.regulation.as_ref().unwrap(), fb.regulation.as_ref().unwrap());
        println!(
            "| {name} | {:.1} | {:.1} | {:.2} | {:.2} | {:.3} | {:.3} | {} |",
            ra.ise_mpa2_s,
            rb.ise_mpa2_s,
            ra.max_abs_deviation_settled_mpa,
            rb.max_abs_deviation_settled_mpa,
            fa.time_below_p_min_after_1s_s,
            fb.time_below_p_min_after_1s_s,
            if c.adaptive_better(fa) { "yes" } else { "**no**" }
        );
    }
    Ok(())
}
