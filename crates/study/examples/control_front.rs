//! The pump's tracking against its valve's activity (`rhonn::experiment::front`): the
//! cascade PI over a grid of 1,540 gain sets, the RHONN adaptive controller's default over
//! its closed-loop pole, and the three shipped adaptive settings (`control-adaptive`,
//! `-gentle`, `-fast`), each run on `control-adaptive`'s nominal plant (its set-points,
//! demand, noise and seed), scored by IAE and by the solenoid current's total variation.
//! Then each shipped setting on the 36 other plants of the robustness study (1, 5, 20 ms
//! solenoid lags, a one-period delay, the 32 tolerance corners) against the nominal-optimal
//! cascade PI.
//!
//! `cargo run --release -p rhonn-study --example control_front [OUT]` (about 10 s on 2
//! cores) prints both tables and writes OUT/front.csv and OUT/front.svg (default OUT:
//! out/control-front).
use rhonn::experiment::preset;
use rhonn_study::front::{
    adaptive_points, best_iae_within, cascade_grid, cascade_points, nominal_optimal_points, points, wins,
    FrontPoint,
};
use rhonn_study::tuning::robustness_cases;

const SHIPPED: [&str; 3] = [
    "control-adaptive-gentle",
    "control-adaptive",
    "control-adaptive-fast",
];

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::path::PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "out/control-front".into()),
    );
    let spec = preset::load_any("control-adaptive")?;
    let gains = cascade_grid();
    let cascade = cascade_points(&spec, &gains);
    let mut adaptive = adaptive_points(&spec, &[40.0, 50.0, 70.0, 100.0, 140.0, 200.0]);
    let shipped: Vec<(String, FrontPoint)> = SHIPPED
        .iter()
        .map(|n| {
            Ok((
                n.to_string(),
                points("rhonn-adaptive", vec![(n.to_string(), preset::load_any(n)?)]).remove(0),
            ))
        })
        .collect::<Result<_, rhonn::Error>>()?;
    adaptive.extend(shipped.iter().map(|(_, p)| p.clone()));
    println!("nominal plant: each shipped adaptive setting against the best cascade PI at the same or less current activity");
    println!("setting | IAE [MPa s] | current TV [A] | within 1 % | best cascade IAE at <= TV (its TV) | its gains | IAE ratio");
    for (name, a) in &shipped {
        let b = best_iae_within(&cascade, a.current_total_variation_a);
        println!(
            "{name} | {:.3} | {:.1} | {:.1} % | {} | {} | {}",
            a.iae_mpa_s,
            a.current_total_variation_a,
            a.within_1pct_percent,
            b.map_or("none".into(), |b| format!(
                "{:.3} ({:.1})",
                b.iae_mpa_s, b.current_total_variation_a
            )),
            b.map_or("", |b| b.setting.as_str()),
            b.map_or("none".into(), |b| format!("{:.3}", a.iae_mpa_s / b.iae_mpa_s)),
        );
    }
    let cases = robustness_cases(&spec)?;
    let no = nominal_optimal_points(&cases);
    println!("the 37 plants of the robustness study: wins = lower IAE at no more current total variation than the nominal-optimal cascade PI");
    for name in SHIPPED {
        let shipped_spec = preset::load_any(name)?;
        let cases = robustness_cases(&shipped_spec)?;
        let a = points("rhonn-adaptive", cases);
        let wins = wins(&a, &no);
        let lost: Vec<String> = a
            .iter()
            .zip(&no)
            .filter(|(a, n)| !a.beats(n))
            .map(|(a, n)| {
                format!(
                    "{}: IAE {:.1} vs {:.1}, TV {:.0} vs {:.0}",
                    a.setting,
                    a.iae_mpa_s,
                    n.iae_mpa_s,
                    a.current_total_variation_a,
                    n.current_total_variation_a
                )
            })
            .collect();
        println!(
            "{name}: wins {wins} of {}; 20 ms lag IAE {:.1} MPa s",
            a.len(),
            a[3].iae_mpa_s
        );
        for l in lost {
            println!("  not won: {l}");
        }
    }
    for f in rhonn_study::front_plot::write_front(&out, &cascade, &adaptive, &shipped)? {
        println!("  wrote {}", f.display());
    }
    Ok(())
}
