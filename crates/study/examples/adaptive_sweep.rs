//! A random search of the RHONN adaptive controller's settings (lambda, stroke gain g,
//! lead, filter pole, the drift and gain weights' learning rates, integral action,
//! identification time; N draws from a grid, seeded) over the 37 plants of the robustness
//! study, each against the nominal-optimal cascade PI: per setting, the plants won (lower
//! IAE at no more current total variation), the 20 ms solenoid lag's IAE, and the nominal
//! IAE, current total variation and share within 1 %. It measures the trade-off between
//! winning every plant and the 20 ms lag (docs/results.md).
//!
//! `cargo run --release -p rhonn-study --example adaptive_sweep -- [N] [SEED]` (300 draws:
//! about 90 s on 2 cores).
use rayon::prelude::*;
use rhonn::experiment::{preset, LoopSpec, ScenarioSpec};
use rhonn_study::front::{nominal_optimal_points, points, wins};
use rhonn_study::tuning::robustness_cases;

fn set(spec: &ScenarioSpec, k: &[f64; 8]) -> ScenarioSpec {
    let mut s = spec.clone();
    if let Some(LoopSpec::PumpRhonnAdaptive(knobs)) = s.control.as_mut().map(|c| &mut c.controller) {
        knobs.lambda_per_s = Some(k[0]);
        knobs.stroke_gain = Some(k[1]);
        knobs.lead_s = Some(k[2]);
        knobs.observer_pole_per_s = Some(k[3]);
        knobs.gamma_w = Some(k[4]);
        knobs.gamma_w1 = Some(k[5]);
        knobs.integral_per_s2 = Some(k[6]);
        knobs.identification_s = Some(k[7]);
    }
    s
}

fn main() {
    let spec = preset::load_any("control-adaptive").unwrap();
    let cases = robustness_cases(&spec).unwrap();
    let no = nominal_optimal_points(&cases);
    let n: usize = std::env::args().nth(1).map_or(200, |a| a.parse().unwrap());
    let seed: u64 = std::env::args().nth(2).map_or(1, |a| a.parse().unwrap());
    let grid: Vec<[f64; 8]> = (0..n as u64)
        .map(|i| {
            let mut x = (seed * 1_000_003 + i).wrapping_mul(0x9e37_79b9_7f4a_7c15);
            let mut r = || {
                x ^= x << 13;
                x ^= x >> 7;
                x ^= x << 17;
                (x % 10_000) as f64 / 10_000.0
            };
            let pick = |v: &[f64], r: f64| v[((r * v.len() as f64) as usize).min(v.len() - 1)];
            [
                pick(&[70.0, 80.0, 90.0, 100.0, 110.0, 120.0], r()),
                pick(&[2.0, 2.5, 3.0, 3.5, 4.0], r()),
                pick(&[0.04, 0.05, 0.06, 0.07], r()),
                pick(&[50.0, 60.0, 70.0, 80.0], r()),
                pick(&[7e3, 1e4, 1.3e4], r()),
                pick(&[5.0, 10.0, 20.0, 40.0], r()),
                pick(&[500.0, 750.0, 1000.0, 1500.0, 2000.0], r()),
                pick(&[1.0, 2.0, 3.0], r()),
            ]
        })
        .collect();
    let res: Vec<String> = grid
        .par_iter()
        .map(|k| {
            let a = points(
                "rhonn-adaptive",
                cases.iter().map(|(n, s)| (n.clone(), set(s, k))).collect(),
            );
            let wins = wins(&a, &no);
            format!(
                "{wins} lag20 {:.1} nominal {:.2} tv {:.0} within {:.1} k {:?}",
                a[3].iae_mpa_s, a[0].iae_mpa_s, a[0].current_total_variation_a, a[0].within_1pct_percent, k
            )
        })
        .collect();
    for r in res {
        println!("{r}");
    }
}
