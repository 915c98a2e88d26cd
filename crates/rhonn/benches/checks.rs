//! The data checks that run before every fit (`rhonn::sysid::data_warnings`), on a drifting
//! record whose autocorrelation never falls (the worst case of the decorrelation lag):
//! a million rows must be checked in well under the fit's own time (issue 56 asks under
//! 2 s). Beside it, at 20,000 rows, the FFT lag against one exact sum per lag (the method
//! before, O(n * lag)), in one run.
//!
//! `cargo bench -p rhonn --bench checks`

use criterion::{black_box, criterion_group, criterion_main, Criterion};
use rhonn::data::Record;

fn drifting(n: usize) -> Record {
    let mut s = 7u64;
    let (mut u, mut y) = (Vec::with_capacity(n), Vec::with_capacity(n));
    for k in 0..n {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let r = (s >> 33) as f64 / (1u64 << 31) as f64 - 0.5;
        u.push(r);
        y.push(k as f64 * 1e-6 + 1e-3 * r);
    }
    Record {
        source: "drift".into(),
        t: (0..n).map(|k| k as f64 * 1e-3).collect(),
        inputs: vec![u],
        outputs: vec![y],
    }
}

/// The lag by one exact sum per lag (the method before the FFT).
fn by_sums(y: &[f64]) -> Option<usize> {
    let n = y.len();
    let mean = y.iter().sum::<f64>() / n as f64;
    let d: Vec<f64> = y.iter().map(|v| v - mean).collect();
    let c0: f64 = d.iter().map(|v| v * v).sum();
    let target = (-1.0f64).exp() * c0;
    (1..n / 2).find(|&k| d[..n - k].iter().zip(&d[k..]).map(|(a, b)| a * b).sum::<f64>() < target)
}

fn bench_checks(c: &mut Criterion) {
    let (i, o) = (vec!["u".to_string()], vec!["y".to_string()]);
    let mut g = c.benchmark_group("data checks");
    g.sample_size(10);
    let big = drifting(1_000_000);
    g.bench_function("data_warnings, 1,000,000 drifting rows", |b| {
        b.iter(|| rhonn::sysid::data_warnings(black_box(std::slice::from_ref(&big)), &i, &o, 8, 1e-3))
    });
    let small = drifting(20_000);
    g.bench_function("decorrelation lag by FFT, 20,000 drifting rows", |b| {
        b.iter(|| rhonn::sysid::decorrelation_lag(black_box(&small.outputs[0])))
    });
    g.bench_function(
        "decorrelation lag by one sum per lag (before), 20,000 drifting rows",
        |b| b.iter(|| by_sums(black_box(&small.outputs[0]))),
    );
    g.finish();
}

criterion_group!(benches, bench_checks);
criterion_main!(benches);
