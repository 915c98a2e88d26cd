//! The README's table of systems rhonn never modelled, over seeds:
//! `cargo run --release -p rhonn-report --example unseen_systems [SEEDS]` (default 5).
//!
//! For each system of `rhonn::sysid::benchmarks` (a Wiener-Hammerstein chain with one
//! input, a bilinear system with two) and each seed j = 0..SEEDS, a training record
//! (seed 10 + inputs + 100 j) and a test record (seed 20 + inputs + 100 j) of 5,000
//! samples; the structure chosen as `rhonn fit` chooses it without `--model` (the same
//! selection, with its default options), trained, then run free on the test record beside
//! its ARX baseline (the selection's best ARX on the folds, as `rhonn fit` keeps it). Seed j = 0 is the pair `crates/cli/tests/fit_predict.rs` checks. Prints one line
//! per run and the median, best and worst per system.

use rhonn::data::Record;
use rhonn::sysid::benchmarks::{bilinear, wiener_hammerstein};
use rhonn::sysid::select::{select, SelectOptions};
use rhonn::sysid::{predict, train_selected};
use std::time::Instant;

fn names(r: &Record) -> (Vec<String>, Vec<String>) {
    let inputs = if r.inputs.len() == 1 {
        vec!["u".to_string()]
    } else {
        vec!["u1".to_string(), "u2".to_string()]
    };
    (inputs, vec!["y".to_string()])
}

/// (chosen structure, model's free-run fit on the test record, its ARX baseline's, the
/// fit's wall time in seconds).
fn one(train_rec: &Record, test_rec: &Record) -> Result<(String, f64, f64, f64), rhonn::Error> {
    let (inputs, outputs) = names(train_rec);
    let start = Instant::now();
    let recs = std::slice::from_ref(train_rec);
    let sel = select(recs, &inputs, &outputs, &SelectOptions::default(), &|_| {})?;
    let name = sel.chosen_name();
    let specs = sel.chosen_specs();
    let (fitted, _) = train_selected(&specs, Some(sel), recs, &inputs, &outputs)?;
    let seconds = start.elapsed().as_secs_f64();
    let p = predict(&fitted, test_rec, None)?;
    let fit = p.figures[0].fit_percent;
    let arx = p.baseline.as_ref().map_or(fit, |(_, f)| f[0].fit_percent);
    Ok((name, fit, arx, seconds))
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

fn main() -> Result<(), rhonn::Error> {
    let seeds: u64 = std::env::args()
        .nth(1)
        .and_then(|s| s.parse().ok())
        .unwrap_or(5)
        .max(1);
    type System = fn(u64, usize) -> Record;
    let systems: [(&str, usize, System); 2] = [
        ("Wiener-Hammerstein, 1 input", 1, wiener_hammerstein),
        ("bilinear, 2 inputs", 2, bilinear),
    ];
    for (label, inputs, make) in systems {
        let (mut fits, mut arxs, mut margins) = (Vec::new(), Vec::new(), Vec::new());
        for j in 0..seeds {
            let i = inputs as u64;
            let (tr, te) = (make(10 + i + 100 * j, 5000), make(20 + i + 100 * j, 5000));
            let (name, fit, arx, s) = one(&tr, &te)?;
            println!(
                "{label}, seeds {} / {}: chose {name}: {fit:.1} % (ARX {arx:.1} %), {s:.2} s",
                10 + i + 100 * j,
                20 + i + 100 * j
            );
            fits.push(fit);
            arxs.push(arx);
            margins.push(fit - arx);
        }
        let worst_margin = margins.iter().copied().fold(f64::INFINITY, f64::min);
        let (lo, hi) = (
            fits.iter().copied().fold(f64::INFINITY, f64::min),
            fits.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        );
        println!(
            "{label}: {seeds} seeds: fit median {:.1} % (worst {lo:.1}, best {hi:.1}); ARX median {:.1} %; model minus ARX at worst {worst_margin:+.1} points",
            median(&mut fits),
            median(&mut arxs)
        );
    }
    Ok(())
}
