//! A live stream's cost per sample (`rhonn identify --stream`: `ident::Stream::push`, one
//! sample at a time, the bank choosing online) beside the same record identified from a
//! file (`identification::identify`, which the bank runs over in one pass), in one run:
//! 20,000 samples of one input and one output (no cascade candidate: over 5,000 samples).
//!
//! `cargo bench -p rhonn --bench stream`

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use rhonn::data::Record;
use rhonn::ident::Stream;
use rhonn::identification::{identify, IdentifyPlan};

/// A first-order system whose gain depends on its output, driven by held random levels.
fn record(n: usize) -> Record {
    let mut s = 11u64;
    let (mut u, mut y) = (Vec::with_capacity(n), Vec::with_capacity(n));
    let (mut level, mut x) = (0.0f64, 0.0f64);
    for k in 0..n {
        if k % 20 == 0 {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            level = (s >> 33) as f64 / (1u64 << 31) as f64 * 2.0 - 1.0;
        }
        u.push(level);
        y.push(x);
        x = 0.8 * x + 0.4 * level + 0.1 * x.tanh() * level;
    }
    Record {
        source: "bench".into(),
        t: (0..n).map(|k| k as f64 * 0.01).collect(),
        inputs: vec![u],
        outputs: vec![y],
    }
}

fn bench_stream(c: &mut Criterion) {
    let r = record(20_000);
    let (i, o) = (vec!["u".to_string()], vec!["y".to_string()]);
    let mut g = c.benchmark_group("online identification of 20,000 samples");
    g.sample_size(10);
    g.bench_function("stream: push one sample at a time, then freeze", |b| {
        b.iter(|| {
            let mut s = Stream::new(i.clone(), o.clone(), None, Some(r.len())).unwrap();
            for k in 0..r.len() {
                black_box(s.push(r.t[k], &[r.inputs[0][k]], &[r.outputs[0][k]]).unwrap());
            }
            black_box(s.finish().unwrap())
        })
    });
    let plan = IdentifyPlan {
        inputs: i.clone(),
        outputs: o.clone(),
        given: None,
        epochs: None,
        steps_ahead: None,
        units: Default::default(),
    };
    g.bench_function("file: identify the record (identify --data)", |b| {
        b.iter(|| black_box(identify(std::slice::from_ref(&r), &[], &plan).unwrap()))
    });
    g.finish();
}

criterion_group!(benches, bench_stream);
criterion_main!(benches);
