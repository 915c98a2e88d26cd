//! The adaptive cascade's online identification of its actuator (`rhonn_core::actuator`),
//! measured: each shipped adaptive setting on the 37 plants of the robustness study (the
//! nominal plant, the 1, 5 and 20 ms solenoid lags, the one-period delay, the 32 tolerance
//! corners) with the identification off (`actuator_memory_s = 0`, the earlier design) and
//! on at several lag scales `lag_scale_s`, each against the nominal-optimal cascade PI:
//! the plants won (lower IAE at no more current total variation), the lags' and the
//! delay's IAE, and the nominal IAE, current total variation and share within 1 %
//! (docs/results.md).
//!
//! `cargo run --release -p rhonn-study --example actuator_study` (about 10 s on 2 cores).
use rayon::prelude::*;
use rhonn::experiment::{preset, LoopSpec, ScenarioSpec};
use rhonn_study::front::{nominal_optimal_points, points, wins};
use rhonn_study::tuning::robustness_cases;

fn with_actuator(spec: &ScenarioSpec, memory_s: f64, lag_scale_s: f64) -> ScenarioSpec {
    let mut s = spec.clone();
    if let Some(LoopSpec::PumpRhonnAdaptive(knobs)) = s.control.as_mut().map(|c| &mut c.controller) {
        knobs.actuator_memory_s = Some(memory_s);
        knobs.lag_scale_s = Some(lag_scale_s);
    }
    s
}

fn main() {
    println!("| setting | actuator_memory_s, lag_scale_s | wins of 37 | IAE lag 1 / 5 / 20 ms, delay [MPa s] | nominal IAE [MPa s] | current TV [A] | within 1 % |");
    println!("|---|---|---|---|---|---|---|");
    for name in [
        "control-adaptive",
        "control-adaptive-gentle",
        "control-adaptive-fast",
    ] {
        let cases = robustness_cases(&preset::load_any(name).unwrap()).unwrap();
        let no = nominal_optimal_points(&cases);
        let settings = [
            (0.0, 0.0),
            (5.0, 0.0),
            (5.0, 0.03),
            (5.0, 0.04),
            (5.0, 0.06),
            (5.0, 0.1),
            (2.0, 0.04),
            (10.0, 0.04),
        ];
        let rows: Vec<String> = settings
            .par_iter()
            .map(|&(m, l)| {
                let a = points("rhonn-adaptive", cases.iter().map(|(n, s)| (n.clone(), with_actuator(s, m, l))).collect());
                let wins = wins(&a, &no);
                format!(
                    "| `{name}` | {m}, {l} | {wins} | {:.1} / {:.1} / {:.1}, {:.1} | {:.2} | {:.0} | {:.1} % |",
                    a[1].iae_mpa_s, a[2].iae_mpa_s, a[3].iae_mpa_s, a[4].iae_mpa_s, a[0].iae_mpa_s,
                    a[0].current_total_variation_a, a[0].within_1pct_percent
                )
            })
            .collect();
        for r in rows {
            println!("{r}");
        }
    }
}
