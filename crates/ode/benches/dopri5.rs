//! The integrator on its own: a harmonic oscillator over ten periods, and a limited
//! integrator that hits and leaves its bounds.

use criterion::{criterion_group, criterion_main, Criterion};
use rhonn_ode::{Dopri5, Options, StepResult, System};
use std::hint::black_box;

struct Oscillator;
impl System for Oscillator {
    type State = [f64; 2];
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&self, _t: f64, x: &[f64], dx: &mut [f64]) {
        dx[0] = x[1];
        dx[1] = -x[0];
    }
}

struct Saturating;
impl System for Saturating {
    type State = [f64; 1];
    fn dim(&self) -> usize {
        1
    }
    fn rhs(&self, t: f64, _x: &[f64], dx: &mut [f64]) {
        dx[0] = t.cos();
    }
    fn bounds(&self, _i: usize) -> (f64, f64) {
        (-0.5, 0.5)
    }
}

fn solve<S: System>(sys: S, x0: S::State, t_end: f64, opts: Options<S::State>) -> f64 {
    let mut s = Dopri5::new(sys, 0.0, x0, opts).unwrap();
    while !matches!(s.step(t_end).unwrap(), StepResult::Reached { .. }) {}
    s.state()[0]
}

fn bench(c: &mut Criterion) {
    let t_end = 20.0 * std::f64::consts::PI;
    c.bench_function("oscillator 10 periods rtol 1e-6", |b| {
        b.iter(|| {
            solve(
                Oscillator,
                black_box([1.0, 0.0]),
                t_end,
                Options::uniform(2, 1e-6, 1e-9),
            )
        })
    });
    c.bench_function("limited integrator 10 periods (40 events)", |b| {
        b.iter(|| {
            let mut o = Options::uniform(1, 1e-6, 1e-9);
            o.h_max_s = 0.2;
            solve(Saturating, black_box([0.0]), t_end, o)
        })
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
