//! Whole runs of the shipped scenarios without I/O, and one step of the discrete
//! identifier. The right-hand-side evaluation count of each run is printed once, to go
//! beside the time in the README.

use criterion::{criterion_group, criterion_main, Criterion};
use rhonn::experiment::preset;
use rhonn::ident::{DiscreteIdentifier, Identifier, Mode};
use rhonn::law::{GainSpec, LawSpec};
use rhonn::net::{Network, Sigmoid, Terms};
use std::hint::black_box;

fn bench_runs(c: &mut Criterion) {
    for name in ["thesis-ch3", "regulated-pi"] {
        let spec = preset::load_any(name).unwrap();
        let s = spec.run_summary().unwrap();
        eprintln!(
            "{name}: {} rhs evaluations, {} accepted / {} rejected steps, {} events",
            s.solver.rhs_evaluations, s.solver.accepted_steps, s.solver.rejected_steps, s.solver.events
        );
        c.bench_function(&format!("{name} (summary only)"), |b| {
            b.iter(|| black_box(&spec).run_summary().unwrap())
        });
        c.bench_function(&format!("{name} (trajectory at its output interval)"), |b| {
            b.iter(|| black_box(&spec).run().unwrap())
        });
    }
    // thesis-ch5: the training run (plant + identifier, 40 s), then the whole job with
    // the two frozen-weight validation runs.
    let mut train = preset::load_any("thesis-ch5").unwrap();
    train.identifier.as_mut().unwrap().validate = false;
    let full = preset::load_any("thesis-ch5").unwrap();
    for (label, spec) in [
        ("thesis-ch5 training", &train),
        ("thesis-ch5 training + 2 validations", &full),
    ] {
        let s = spec.run_summary().unwrap();
        eprintln!(
            "{label}: {} rhs evaluations, {} events",
            s.solver.rhs_evaluations, s.solver.events
        );
        c.bench_function(label, |b| b.iter(|| black_box(spec).run_summary().unwrap()));
    }
}

fn bench_discrete_step(c: &mut Criterion) {
    // 2 neurons, 2 inputs, 10 terms: 4 linear, 4 squares, 2 cross products.
    let lists: Vec<Vec<[usize; 2]>> = vec![
        vec![[0, 1]],
        vec![[1, 1]],
        vec![[2, 1]],
        vec![[3, 1]],
        vec![[0, 2]],
        vec![[1, 2]],
        vec![[2, 2]],
        vec![[3, 2]],
        vec![[0, 1], [2, 1]],
        vec![[1, 1], [3, 1]],
    ];
    let net = Network {
        n: 2,
        m: 2,
        sigmoid: Sigmoid::LOGISTIC,
        state_scale: vec![10e6, 10e-3],
        input_scale: vec![0.8, 2e-3],
        terms: Terms::from_lists(&lists, 4, "terms").unwrap(),
        a: vec![120.0, 41.0],
    };
    for (label, law) in [
        (
            "filtered-error",
            LawSpec::FilteredError {
                gamma: vec![GainSpec::Scalar(1e4), GainSpec::Scalar(30.0)],
            },
        ),
        (
            "filtered-regressor-ls",
            LawSpec::FilteredRegressorLs {
                p0: vec![10.0, 10.0],
                floor: None,
            },
        ),
    ] {
        let law = law.check(2, 10, "law").unwrap();
        let ident = Identifier::new(net.clone(), law, Mode::Train);
        let s0 = ident.initial_state(&[0.0, 0.0], None);
        let mut d = DiscreteIdentifier::new(ident, s0, 0.005);
        let mut k = 0u64;
        c.bench_function(
            &format!("discrete identifier step, 2 neurons, 10 terms, {label}"),
            |b| {
                b.iter(|| {
                    k += 1;
                    let t = k as f64 * 0.005;
                    d.step(black_box(&[10e6 + 1e5 * t.sin(), 8e-3]), black_box(&[0.4, 1e-3]));
                })
            },
        );
    }
}

fn bench_sysid(c: &mut Criterion) {
    use rhonn::data::Record;
    use rhonn::sysid::{fit, ModelSpec};
    // 1,000 samples of a nonlinear first-order system under a random staircase input.
    let n = 1000;
    let mut s = 1u64;
    let (mut u, mut y) = (vec![0.0; n], vec![0.0; n]);
    let mut level = 0.0;
    for k in 0..n {
        if k % 9 == 0 {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            level = ((s >> 33) as f64 / (1u64 << 31) as f64) * 2.0 - 1.0;
        }
        u[k] = level;
        if k > 0 {
            y[k] = 0.6 * y[k - 1] + 0.3 * u[k - 1] + 0.3 * y[k - 1].tanh() * u[k - 1];
        }
    }
    let r = Record {
        source: "bench".into(),
        t: (0..n).map(|k| k as f64).collect(),
        inputs: vec![u],
        outputs: vec![y],
    };
    let (i, o) = (vec!["u".to_string()], vec!["y".to_string()]);
    let spec = ModelSpec {
        na: 3,
        nb: 2,
        nk: 1,
        ..Default::default()
    };
    c.bench_function("fit rhonn na 3 nb 2 degree 2 (26 features), 1,000 samples", |b| {
        b.iter(|| fit(black_box(&spec), std::slice::from_ref(&r), &i, &o).unwrap())
    });
    let m = fit(&spec, std::slice::from_ref(&r), &i, &o).unwrap();
    c.bench_function("predict free run, 1,000 samples", |b| {
        b.iter(|| m.predict(black_box(&r), None).unwrap())
    });
    c.bench_function("predict 10 steps ahead, 1,000 samples", |b| {
        b.iter(|| m.predict(black_box(&r), Some(10)).unwrap())
    });
    // A `cascade` model (continuous-time RHONN, two neurons, one hidden) on 1,000
    // samples (4 s each) of two tanks with square-root outflows, the upper one
    // overflowing at 10 V.
    let mut x = (3.0f64, 2.0f64);
    let mut yt = vec![0.0; n];
    let ut: Vec<f64> = (0..n)
        .map(|k| 0.5 + 5.0 * ((k / 40) as f64 * 0.618).fract())
        .collect();
    for k in 0..n {
        yt[k] = x.1;
        for _ in 0..100 {
            let d1 = 0.08 * ut[k] - 0.06 * x.0.sqrt();
            let over = if x.0 >= 10.0 { d1.max(0.0) } else { 0.0 };
            let d2 = 0.05 * x.0.sqrt() - 0.05 * x.1.sqrt() + 0.4 * over;
            x = ((x.0 + 0.04 * d1).clamp(0.0, 10.0), (x.1 + 0.04 * d2).max(0.0));
        }
    }
    let tanks = Record {
        source: "tanks".into(),
        t: (0..n).map(|k| 4.0 * k as f64).collect(),
        inputs: vec![ut],
        outputs: vec![yt],
    };
    let cspec = ModelSpec {
        kind: rhonn::sysid::Kind::Cascade,
        epochs: 50,
        ..Default::default()
    };
    let mut g = c.benchmark_group("cascade");
    g.sample_size(10);
    g.bench_function("fit cascade, 16 starts x 50 iterations, 1,000 samples", |b| {
        b.iter(|| fit(black_box(&cspec), std::slice::from_ref(&tanks), &i, &o).unwrap())
    });
    let cm = fit(&cspec, std::slice::from_ref(&tanks), &i, &o).unwrap();
    g.bench_function("predict cascade free run (settle + run), 1,000 samples", |b| {
        b.iter(|| cm.predict(black_box(&tanks), None).unwrap())
    });
    g.bench_function(
        "predict cascade 10 steps ahead (settled at every sample), 1,000 samples",
        |b| b.iter(|| cm.predict(black_box(&tanks), Some(10)).unwrap()),
    );
    g.finish();
}

/// One control period of the adaptive cascade: the identifier's update over the last
/// period (RK4, 2 substeps, projection) and the control law; and the whole
/// control-adaptive run (adaptive and PI plants, 60 s).
fn bench_control(c: &mut Criterion) {
    use rhonn::control::{CascadeSettings, RhonnCascade};
    let mut ctl = RhonnCascade::new(
        CascadeSettings::default(),
        1300.0,
        28.0,
        0.8,
        0.024,
        25e6,
        5e-3,
        411.0,
        10e6,
    );
    let mut k = 0u64;
    c.bench_function(
        "control-adaptive: one control period (identifier update + control law)",
        |b| {
            b.iter(|| {
                k += 1;
                let t = 2.0 + k as f64 * 5e-3;
                // A pressure and stroke that move, so that nothing is constant-folded.
                let p = 10e6 + 2e5 * (k as f64 * 0.37).sin();
                let x = 8e-3 + 1e-4 * (k as f64 * 0.11).cos();
                black_box(ctl.update(black_box(t), black_box(p), black_box(x), black_box(10e6)))
            })
        },
    );
    let spec = preset::load_any("control-adaptive").unwrap();
    let s = spec.run_summary().unwrap();
    eprintln!(
        "control-adaptive: {} rhs evaluations (its three plants)",
        s.solver.rhs_evaluations
    );
    c.bench_function("control-adaptive (its three loops' plants, summary only)", |b| {
        b.iter(|| black_box(&spec).run_summary().unwrap())
    });
}

/// One `OnlineIdentifier::update` (2 outputs, 1 input, degree 2: 10 terms per neuron,
/// 20 weights), and the 60 s pump-identify record (12,001 samples) identified online.
fn bench_online(c: &mut Criterion) {
    use rhonn::ident::{identify_records, OnlineIdentifier, OnlineSpec, Scaling};
    let spec = OnlineSpec::default();
    let mut id = OnlineIdentifier::new(&spec, 2, 1, 0.01, Scaling::identity(2, 1)).unwrap();
    assert_eq!(id.n_terms(), 10);
    let mut k = 0u64;
    c.bench_function("online identifier: one update, 2 outputs, 20 weights", |b| {
        b.iter(|| {
            k += 1;
            let t = k as f64 * 0.01;
            let u = (t * 3.0).sin();
            black_box(id.update(t, &[u], &[0.5 * u, (t * 0.7).cos()]).unwrap()[0])
        })
    });
    let rec = [pump_identify_record()];
    let outputs = ["p_meas".to_string()];
    c.bench_function("online identification of the 60 s pump-identify record", |b| {
        b.iter(|| {
            identify_records(black_box(&spec), &rec, &outputs)
                .unwrap()
                .figures[0]
                .rms_error_last_half
        })
    });
    // The lagged structure of models/pump-online-lagged.toml: one update (recursive least
    // squares over its weights), and the same record.
    let lagged: OnlineSpec = toml::from_str(include_str!("../../../models/pump-online-lagged.toml")).unwrap();
    let mut id = OnlineIdentifier::new(&lagged, 1, 2, 0.005, Scaling::identity(1, 2)).unwrap();
    let n = id.n_terms();
    let mut k = 0u64;
    c.bench_function(
        &format!("online identifier, lagged: one update, {n} weights"),
        |b| {
            b.iter(|| {
                k += 1;
                let t = k as f64 * 0.005;
                let u = (t * 3.0).sin();
                black_box(id.update(t, &[u, (t * 0.3).cos()], &[0.5 * u]).unwrap()[0])
            })
        },
    );
    c.bench_function(
        "online identification, lagged, of the 60 s pump-identify record",
        |b| {
            b.iter(|| {
                identify_records(black_box(&lagged), &rec, &outputs)
                    .unwrap()
                    .figures[0]
                    .rms_error_last_half
            })
        },
    );
}

/// The cascade structure of models/tanks-online-cascade.toml: one update (32 extended
/// Kalman filters, 10 parameters and 2 levels each), and its 8 passes over the
/// cascaded tanks' estimation record (1,024 samples).
fn bench_online_cascade(c: &mut Criterion) {
    use rhonn::ident::{identify_records, OnlineIdentifier, OnlineSpec, Scaling};
    let spec: OnlineSpec = toml::from_str(include_str!("../../../models/tanks-online-cascade.toml")).unwrap();
    let text = include_str!("../../../data/cascaded-tanks/estimation.csv");
    let rows: Vec<Vec<f64>> = text
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|v| v.trim().parse().unwrap()).collect())
        .collect();
    let col = |j: usize| rows.iter().map(|r| r[j]).collect::<Vec<f64>>();
    let rec = [rhonn::data::Record {
        source: "estimation.csv".into(),
        t: col(0),
        inputs: vec![col(1)],
        outputs: vec![col(2)],
    }];
    let scaling = Scaling::of(&[&rec[0].outputs[0]], &[&rec[0].inputs[0]]);
    let mut id = OnlineIdentifier::new(&spec, 1, 1, 4.0, scaling).unwrap();
    let mut k = 0usize;
    c.bench_function("online identifier, cascade: one update, 32 filters", |b| {
        b.iter(|| {
            let j = k % rows.len();
            if j == 0 {
                id.reset();
            }
            k += 1;
            black_box(id.update(rows[j][0], &[rows[j][1]], &[rows[j][2]]).unwrap()[0])
        })
    });
    let outputs = ["y".to_string()];
    c.bench_function(
        "online identification, cascade, 8 passes over the tanks' estimation record",
        |b| {
            b.iter(|| {
                identify_records(black_box(&spec), &rec, &outputs)
                    .unwrap()
                    .figures[0]
                    .rms_error_last_half
            })
        },
    );
}

/// The online selection's bank (`rhonn identify` without `--model`) on a 20,000-sample
/// record of one input and one output (a Wiener-Hammerstein-like chain: a first-order
/// filter, a static tanh, another filter): the whole bank in one pass, divide by 20,000 for
/// the time per sample.
fn bench_online_bank(c: &mut Criterion) {
    use rhonn::ident::bank::{default_candidates, select};
    let n = 20_000;
    let (mut a, mut b, mut u) = (0.0_f64, 0.0_f64, 0.0_f64);
    let (mut t, mut us, mut ys) = (vec![], vec![], vec![]);
    let mut state = 12345u64;
    for k in 0..n {
        if k % 7 == 0 {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            u = (state >> 33) as f64 / (1u64 << 31) as f64 * 2.0 - 1.0;
        }
        t.push(k as f64 * 1e-3);
        us.push(u);
        ys.push(b);
        a = 0.9 * a + 0.1 * u;
        b = 0.8 * b + 0.2 * (2.0 * a).tanh();
    }
    let rec = [rhonn::data::Record {
        source: "wh.csv".into(),
        t,
        inputs: vec![us],
        outputs: vec![ys],
    }];
    let outputs = ["y".to_string()];
    let mut g = c.benchmark_group("online selection");
    g.sample_size(10);
    g.bench_function(
        "the default bank (14 candidates, the block structures in it), one pass over 20,000 samples, 1 in 1 out",
        |bch| {
            bch.iter(|| {
                select(default_candidates(1, 1, n), black_box(&rec), &outputs)
                    .unwrap()
                    .chosen
            })
        },
    );
    // Beside it, the bank without its two Wiener-Hammerstein block structures (each fitted
    // on the 10,000-sample warm-up): their cost, in the same run (the budgets: the
    // bank 20 us a sample, with the block structure 50 us).
    g.bench_function(
        "the default bank without its two block structures (12 candidates), one pass over 20,000 samples",
        |bch| {
            bch.iter(|| {
                let without = default_candidates(1, 1, n)
                    .into_iter()
                    .filter(|c| !c.name.starts_with("wiener-hammerstein"))
                    .collect();
                select(without, black_box(&rec), &outputs).unwrap().chosen
            })
        },
    );
    // The same bank fed one sample at a time on one thread (`OnlineBank`, Python's
    // `OnlineIdentifier()` without a model): the cost of a sample in a user's own loop.
    g.bench_function(
        "the default bank in a loop (OnlineBank::update, one thread), 20,000 samples, 1 in 1 out",
        |bch| {
            use rhonn::ident::bank::{BankSettings, OnlineBank};
            let r = &rec[0];
            bch.iter(|| {
                let mut bank = OnlineBank::new(
                    default_candidates(1, 1, n),
                    1,
                    1,
                    1e-3,
                    BankSettings::for_stream(n),
                )
                .unwrap();
                for k in 0..n {
                    black_box(
                        bank.update(r.t[k], &[r.inputs[0][k]], &[r.outputs[0][k]])
                            .unwrap(),
                    );
                }
                bank.settings().window
            })
        },
    );
    g.finish();
}

/// The pump-identify record (current and demand in, measured pressure out), simulated.
fn pump_identify_record() -> rhonn::data::Record {
    let out = preset::load_any("pump-identify").unwrap().run().unwrap();
    let col = |n: &str| out.column(n).unwrap().to_vec();
    rhonn::data::Record {
        source: "pump-identify".into(),
        t: col("t"),
        inputs: vec![col("current"), col("demand")],
        outputs: vec![col("p_line_measured")],
    }
}

/// The grey-box pump model of models/pump.toml on the 60 s pump-identify record
/// (12,001 samples): its training (every stage of the continuation) and a 10-step-ahead
/// prediction (the filter over the record and 12,000 ten-sample simulations).
fn bench_pump_grey(c: &mut Criterion) {
    use rhonn::sysid::{fit, parse_spec_file};
    let rec = [pump_identify_record()];
    let spec = parse_spec_file(include_str!("../../../models/pump.toml"))
        .unwrap()
        .remove(0);
    let (i, o) = (
        vec!["current".to_string(), "demand".to_string()],
        vec!["p_meas".to_string()],
    );
    let mut g = c.benchmark_group("pump grey box");
    g.sample_size(10);
    g.bench_function("fit models/pump.toml on the 60 s pump-identify record", |b| {
        b.iter(|| fit(black_box(&spec), &rec, &i, &o).unwrap())
    });
    let m = fit(&spec, &rec, &i, &o).unwrap();
    g.bench_function("predict 10 steps ahead, 60 s record", |b| {
        b.iter(|| m.predict(black_box(&rec[0]), Some(10)).unwrap())
    });
    g.finish();
}

criterion_group!(
    benches,
    bench_pump_grey,
    bench_online,
    bench_online_cascade,
    bench_online_bank,
    bench_runs,
    bench_discrete_step,
    bench_sysid,
    bench_control
);
criterion_main!(benches);
