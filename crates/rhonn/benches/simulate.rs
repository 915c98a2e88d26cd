//! Whole runs of the shipped scenarios, without I/O. The right-hand-side evaluation
//! count of each run is printed once, to go beside the time in the README.

use criterion::{criterion_group, criterion_main, Criterion};
use rhonn::experiment::{preset, run, NoRecorder, Trace};
use std::hint::black_box;

fn bench_runs(c: &mut Criterion) {
    for name in ["thesis-ch3", "regulated-pi"] {
        let sc = preset::load(name).unwrap().check().unwrap();
        let s = run(&sc, &mut NoRecorder).unwrap();
        eprintln!(
            "{name}: {} rhs evaluations, {} accepted / {} rejected steps, {} events",
            s.solver.rhs_evaluations, s.solver.accepted_steps, s.solver.rejected_steps, s.solver.events
        );
        c.bench_function(&format!("{name} (summary only)"), |b| {
            b.iter(|| run(black_box(&sc), &mut NoRecorder).unwrap())
        });
        c.bench_function(&format!("{name} (trace at 1 ms)"), |b| {
            b.iter(|| {
                let mut t = Trace::default();
                run(black_box(&sc), &mut t).unwrap();
                t
            })
        });
    }
}

criterion_group!(benches, bench_runs);
criterion_main!(benches);
