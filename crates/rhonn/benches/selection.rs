//! The default selections' speed on several outputs: `cargo bench -p rhonn --bench
//! selection` prints a table (wall time of `rhonn fit`'s default selection, the candidates
//! the work budget let run, the choice; then of `rhonn identify`'s online bank, a bank per
//! output beside the joint one, and its choice). The records are systems of the unseen-systems
//! corpus (`rhonn::corpus`, seed 100 on) side by side: each output its own system, each
//! input its own excitation. Timed once each: the selection is deterministic, its time is
//! what varies with the machine.

use rhonn::data::Record;
use rhonn::ident::bank::select_per_output;
use rhonn::sysid::select::{select, SelectOptions};
use std::time::Instant;

/// `records` records of `len` samples with `k` inputs and `k` outputs.
fn side_by_side(k: usize, records: usize, len: usize) -> Vec<Record> {
    // Saturation, dead zone, Wiener, Hammerstein, bilinear, input delay: one input, one
    // output, 2,000 training samples each.
    let family = [2usize, 3, 6, 7, 8, 9];
    (0..records)
        .map(|r| {
            let sys: Vec<_> = (0..k)
                .map(|j| rhonn::corpus::system(100 + r as u64, family[j]))
                .collect();
            Record {
                source: format!("record {r}"),
                t: sys[0].train[0].t[..len].to_vec(),
                inputs: sys.iter().map(|s| s.train[0].inputs[0][..len].to_vec()).collect(),
                outputs: sys
                    .iter()
                    .map(|s| s.train[0].outputs[0][..len].to_vec())
                    .collect(),
            }
        })
        .collect()
}

fn main() {
    println!("| inputs x outputs | records x samples | selection [s] | candidates run | chosen | online bank [s] | online choice |");
    println!("|---|---|---|---|---|---|---|");
    for (k, records, len) in [(4, 4, 1800), (6, 66, 605)] {
        let recs = side_by_side(k, records, len);
        let names = |p: &str| (1..=k).map(|j| format!("{p}{j}")).collect::<Vec<_>>();
        let start = Instant::now();
        let sel = select(
            &recs,
            &names("u"),
            &names("y"),
            &SelectOptions::default(),
            &|_| {},
        )
        .expect("the selection runs");
        let fit_s = start.elapsed().as_secs_f64();
        let ran = sel.candidates.iter().filter(|c| c.score.is_some()).count();
        let start = Instant::now();
        let online = select_per_output(&recs, &names("y")).expect("the online bank runs");
        println!(
            "| {k} x {k} | {records} x {len} | {fit_s:.1} | {ran} of {} | {} | {:.1} | {} |",
            sel.candidates.len(),
            sel.chosen_name(),
            start.elapsed().as_secs_f64(),
            online.chosen_name()
        );
    }
}
