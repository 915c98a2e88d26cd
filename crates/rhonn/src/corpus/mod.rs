//! The unseen-systems corpus: simulated systems of many families, drawn from a seed given
//! at run time, each with training records and test records (whose input may differ in
//! kind from training: trained on a multisine, tested on steps), to judge rhonn's
//! defaults on data nobody tuned them on. [`generate`] draws the systems; [`judge`] fits
//! the default model and the ARX of lags by cross-validation on a system's training
//! records and scores both in free run on its test records; [`summarise`] gives the median
//! and the worst of rhonn's ratio to the ARX (`rhonn corpus`).
//!
//! A default is judged on a seed it was not designed with: every seed draws new
//! parameters, excitations and noise for every family.

mod inputs;
mod plants;

pub use inputs::{signal, InputKind};
pub use plants::Family;

use crate::data::Record;
use crate::error::Result;
use crate::ident::{bank::BankSelection, OnlineModel};
use crate::sysid::{self, select::SelectOptions, FitStructure};
use plants::{ClosedLoop, Drawn};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use serde::Serialize;

/// The fewest systems a corpus run draws by default.
pub const DEFAULT_SYSTEMS: usize = 40;

/// One system of the corpus.
#[derive(Debug, Clone)]
pub struct System {
    /// `sNN-family`.
    pub name: String,
    /// Its family.
    pub family: Family,
    /// Its parameters in words.
    pub about: String,
    /// How its training records were excited.
    pub train_input: InputKind,
    /// How its test records were excited.
    pub test_input: InputKind,
    /// Input columns.
    pub inputs: Vec<String>,
    /// Output columns.
    pub outputs: Vec<String>,
    /// Training records.
    pub train: Vec<Record>,
    /// Test records.
    pub tests: Vec<Record>,
}

/// The seed of system `index` of a corpus seeded `seed` (SplitMix64 of both).
fn system_seed(seed: u64, index: usize) -> u64 {
    let mut z = seed ^ (index as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// `count` systems of the corpus seeded `seed`, cycling through every family.
pub fn generate(seed: u64, count: usize) -> Vec<System> {
    (0..count).map(|i| system(seed, i)).collect()
}

/// System `index` of the corpus seeded `seed`: family `index` mod 13; every other draw of
/// a family is tested on an input of another kind than it was trained on.
pub fn system(seed: u64, index: usize) -> System {
    let family = Family::ALL[index % Family::ALL.len()];
    let mut rng = ChaCha8Rng::seed_from_u64(system_seed(seed, index));
    let train_input = if rng.gen_bool(0.5) {
        InputKind::Multisine
    } else {
        InputKind::FilteredNoise
    };
    let test_input = if (index / Family::ALL.len()).is_multiple_of(2) {
        if rng.gen_bool(0.5) {
            InputKind::Steps
        } else {
            InputKind::Pulses
        }
    } else {
        train_input
    };
    let (n_train, n_test) = match family {
        Family::ShortRecord => (rng.gen_range(150..=300), 1500),
        Family::ClosedLoopIntegrator => (5000, 5000),
        Family::FastSampling => (4000, 3000),
        _ => (2000, 1500),
    };
    let name = format!("s{index:02}-{}", family.name().replace(' ', "-"));
    let kinds = [(train_input, n_train, "train"), (test_input, n_test, "test")];
    let (about, inputs, outputs, mut records) = if family == Family::ClosedLoopIntegrator {
        closed_loop_records(&name, &kinds, &mut rng)
    } else {
        open_loop_records(&name, family, &kinds, &mut rng)
    };
    let tests = records.split_off(1);
    System {
        name,
        family,
        about,
        train_input,
        test_input,
        inputs,
        outputs,
        train: records,
        tests,
    }
}

type Drawn4 = (String, Vec<String>, Vec<String>, Vec<Record>);

fn columns(prefix: &str, n: usize) -> Vec<String> {
    if n == 1 {
        vec![prefix.to_string()]
    } else {
        (1..=n).map(|i| format!("{prefix}{i}")).collect()
    }
}

fn gauss(n: usize, sd: f64, rng: &mut ChaCha8Rng) -> Vec<f64> {
    (0..n)
        .map(|_| sd * <StandardNormal as Distribution<f64>>::sample(&StandardNormal, rng))
        .collect()
}

fn std_dev(v: &[f64]) -> f64 {
    let m = v.iter().sum::<f64>() / v.len().max(1) as f64;
    (v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / v.len().max(1) as f64).sqrt()
}

/// The records of an open-loop system: train first, then test; measurement noise of 1 %
/// to 5 % of the training output's spread, the same in every record; inputs and outputs
/// in scales from 0.01 to 100.
fn open_loop_records(
    name: &str,
    family: Family,
    kinds: &[(InputKind, usize, &str)],
    rng: &mut ChaCha8Rng,
) -> Drawn4 {
    let Drawn {
        plant,
        inputs,
        band,
        about,
        delay,
    } = plants::draw(family, rng);
    let noise_share = rng.gen_range(0.01..0.05);
    let in_scale: Vec<f64> = (0..inputs)
        .map(|_| 10f64.powf(rng.gen_range(-1.0..2.0)))
        .collect();
    let out_scale: Vec<f64> = (0..plant.outputs)
        .map(|_| 10f64.powf(rng.gen_range(-2.0..2.0)))
        .collect();
    let mut noise_sd: Option<Vec<f64>> = None;
    let mut records = Vec::new();
    for &(kind, n, what) in kinds {
        let u: Vec<Vec<f64>> = (0..inputs).map(|_| signal(kind, n, band, 1.0, rng)).collect();
        let held: Vec<Vec<f64>> = u
            .iter()
            .map(|c| {
                (0..n)
                    .map(|k| if k >= delay { c[k - delay] } else { 0.0 })
                    .collect()
            })
            .collect();
        let mut y = plant.run(&held);
        if family == Family::SlowDrift {
            let sd = std_dev(&y[0]);
            let period = rng.gen_range(2.0..5.0) * n as f64;
            let phase = rng.gen_range(0.0..std::f64::consts::TAU);
            for (k, v) in y[0].iter_mut().enumerate() {
                *v += 0.5 * sd * (std::f64::consts::TAU * k as f64 / period + phase).sin();
            }
        }
        let sd = noise_sd.get_or_insert_with(|| y.iter().map(|c| noise_share * std_dev(c)).collect());
        for (c, s) in y.iter_mut().zip(sd.iter()) {
            for (v, e) in c.iter_mut().zip(gauss(n, *s, rng)) {
                *v += e;
            }
        }
        records.push(Record {
            source: format!("{name} {what}"),
            t: (0..n).map(|k| k as f64 * plant.dt).collect(),
            inputs: u
                .into_iter()
                .zip(&in_scale)
                .map(|(c, s)| c.into_iter().map(|v| v * s).collect())
                .collect(),
            outputs: y
                .into_iter()
                .zip(&out_scale)
                .map(|(c, s)| c.into_iter().map(|v| v * s).collect())
                .collect(),
        });
    }
    let about = format!("{about}, noise {:.1} %", 100.0 * noise_share);
    (about, columns("u", inputs), columns("y", plant.outputs), records)
}

/// The records of the closed-loop integrator: the PD loop follows a reference of the
/// record's kind (0.2 m RMS); a dither on the force and 0.2 mm of position noise.
fn closed_loop_records(name: &str, kinds: &[(InputKind, usize, &str)], rng: &mut ChaCha8Rng) -> Drawn4 {
    let sys = ClosedLoop::draw(rng);
    let band = 0.5 * sys.wc * sys.dt;
    let mut records = Vec::new();
    for &(kind, n, what) in kinds {
        let r = signal(kind, n, band, 0.2, rng);
        let dither = gauss(n, 0.01 * sys.m * sys.wc * sys.wc, rng);
        let noise = gauss(n, 2e-4, rng);
        let (force, pos) = sys.run(&r, &dither, &noise);
        records.push(Record {
            source: format!("{name} {what}"),
            t: (0..n).map(|k| k as f64 * sys.dt).collect(),
            inputs: vec![force],
            outputs: vec![pos],
        });
    }
    (
        sys.about(),
        vec!["force".into()],
        vec!["position".into()],
        records,
    )
}

/// One output of one system: both models' free-run RMS errors on the test records, and
/// the spread of the output there (the error of predicting the test mean).
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct OutputScore {
    /// The output's column.
    pub output: String,
    /// rhonn fit's default model.
    pub fit_rmse: f64,
    /// The ARX of lags by cross-validation on train.
    pub arx_rmse: f64,
    /// The output's standard deviation over the samples scored.
    pub test_std: f64,
    /// `fit_rmse / arx_rmse`.
    pub ratio: f64,
    /// Whether the selection said that nothing it tried beat this output's training mean
    /// on the folds (`model.json`'s `no_better_than_mean`).
    pub flagged_no_better_than_mean: bool,
    /// rhonn identify's default online model (the bank, frozen after its passes), scored
    /// from the later of its first prediction and the two models' (None: it failed).
    pub online_rmse: Option<f64>,
    /// `online_rmse` over the ARX's on the same samples.
    pub online_ratio: Option<f64>,
}

/// What [`judge`] found on one system.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct Judged {
    /// The system's name, family, parameters and inputs.
    pub system: String,
    /// See `system`.
    pub family: Family,
    /// See `system`.
    pub about: String,
    /// See `system`.
    pub train_input: InputKind,
    /// See `system`.
    pub test_input: InputKind,
    /// Samples of training.
    pub train_samples: usize,
    /// The default's chosen structure and the ARX's.
    pub fit_structure: String,
    /// See `fit_structure`.
    pub arx_structure: String,
    /// Per output (empty when a fit failed).
    pub outputs: Vec<OutputScore>,
    /// The online model's structure (`rhonn identify`'s default), or why it failed.
    pub online_structure: String,
    /// What the default fit warned of (its selection's and the data's warnings).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub fit_warnings: Vec<String>,
    /// Why it has no scores.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub failed: Option<String>,
}

/// What judging a system trained, for `rhonn corpus --out` to write beside its records:
/// each model runs with `rhonn predict`, each selection says why its model was chosen.
#[derive(Debug, Clone)]
pub struct Trained {
    /// rhonn fit's default model.
    pub fitted: sysid::FittedModel,
    /// Its selection (every candidate's scores on the folds).
    pub selection: Option<sysid::select::Selection>,
    /// rhonn identify's default online model, frozen after the training records, and its
    /// bank's selection (None: the online default failed; the row says why).
    pub online: Option<(OnlineModel, BankSelection)>,
}

/// Fit rhonn's default (`opts`) and the ARX of lags by cross-validation on `sys`'s
/// training records and score both in free run on its test records, each from the later
/// of the two models' first predictions. A fit that fails is a row with its error (and
/// nothing trained).
pub fn judge(
    sys: &System,
    opts: &SelectOptions,
    progress: &(dyn Fn(&str) + Sync),
) -> (Judged, Option<Trained>) {
    let mut j = Judged {
        system: sys.name.clone(),
        family: sys.family,
        about: sys.about.clone(),
        train_input: sys.train_input,
        test_input: sys.test_input,
        train_samples: sys.train.iter().map(Record::len).sum(),
        fit_structure: String::new(),
        arx_structure: String::new(),
        online_structure: String::new(),
        outputs: Vec::new(),
        fit_warnings: Vec::new(),
        failed: None,
    };
    match judge_into(sys, opts, progress, &mut j) {
        Ok(t) => (j, Some(t)),
        Err(e) => {
            j.failed = Some(e.to_string());
            j.outputs.clear();
            (j, None)
        }
    }
}

fn judge_into(
    sys: &System,
    opts: &SelectOptions,
    progress: &(dyn Fn(&str) + Sync),
    j: &mut Judged,
) -> Result<Trained> {
    let (ins, outs) = (&sys.inputs, &sys.outputs);
    let run = sysid::fit_records(FitStructure::Select(opts), &sys.train, ins, outs, progress)?;
    if let Some(sel) = &run.summary.selection {
        j.fit_structure = sel.chosen_name();
    }
    j.fit_warnings = run.selection_warnings.clone();
    j.fit_warnings
        .extend(run.data_warnings.iter().map(ToString::to_string));
    let flagged = run.fitted.no_better_than_mean.clone();
    let (arx, arx_sel) = sysid::best_arx(&sys.train, ins, outs)?;
    j.arx_structure = arx_sel.candidates[arx_sel.best_arx].name.clone();
    let mut sq = vec![[0.0f64; 2]; outs.len()];
    let mut scored: Vec<Vec<f64>> = vec![Vec::new(); outs.len()];
    for r in &sys.tests {
        let f = sysid::predict(&run.fitted, r, None)?;
        let a = sysid::predict(&arx, r, None)?;
        let from = f.first.max(a.first);
        for (o, y) in r.outputs.iter().enumerate() {
            for k in from..y.len() {
                sq[o][0] += (f.outputs[o][k] - y[k]).powi(2);
                sq[o][1] += (a.outputs[o][k] - y[k]).powi(2);
                scored[o].push(y[k]);
            }
        }
    }
    let (online_scores, online) = match online_scores(sys, &arx) {
        Ok((model, sel, scores)) => {
            j.online_structure = sel.chosen_name();
            (scores, Some((model, sel)))
        }
        Err(e) => {
            j.online_structure = format!("failed: {e}");
            (Vec::new(), None)
        }
    };
    j.outputs = outs
        .iter()
        .zip(sq)
        .zip(scored)
        .enumerate()
        .map(|(o, ((name, [f, a]), y))| {
            let n = y.len().max(1) as f64;
            let (fit_rmse, arx_rmse) = ((f / n).sqrt(), (a / n).sqrt());
            let on = online_scores.get(o).copied();
            OutputScore {
                output: name.clone(),
                fit_rmse,
                arx_rmse,
                test_std: std_dev(&y),
                ratio: fit_rmse / arx_rmse,
                flagged_no_better_than_mean: flagged.contains(name),
                online_rmse: on.map(|(m, _)| m),
                online_ratio: on.map(|(m, a)| m / a),
            }
        })
        .collect();
    Ok(Trained {
        selection: run.summary.selection.clone(),
        fitted: run.fitted,
        online,
    })
}

/// One output's RMS errors on the test records: the model's and the ARX's.
type RmsPair = (f64, f64);

/// rhonn identify's default on `sys` (trained on its training records, frozen), run free on
/// its test records: the model, its bank's selection and, per output, its RMS error and the
/// ARX's over the same samples (from the later of the two models' first predictions).
fn online_scores(
    sys: &System,
    arx: &sysid::FittedModel,
) -> Result<(OnlineModel, BankSelection, Vec<RmsPair>)> {
    let (ins, outs) = (&sys.inputs, &sys.outputs);
    let (model, sel) = crate::identification::online_default(&sys.train, ins, outs)?;
    let lag = crate::ident::outputs_read_in_free_run(&model.model);
    let mut id = model.identifier()?;
    let mut sq = vec![[0.0f64; 2]; outs.len()];
    let mut n = vec![0usize; outs.len()];
    for r in &sys.tests {
        let on = crate::ident::predict_records(&mut id, std::slice::from_ref(r), None)?.remove(0);
        let a = sysid::predict(arx, r, None)?;
        for (o, y) in r.outputs.iter().enumerate() {
            for k in lag.max(a.first)..y.len() {
                sq[o][0] += (on[k][o] - y[k]).powi(2);
                sq[o][1] += (a.outputs[o][k] - y[k]).powi(2);
                n[o] += 1;
            }
        }
    }
    let scores = sq
        .iter()
        .zip(&n)
        .map(|([m, a], &n)| {
            let n = n.max(1) as f64;
            ((m / n).sqrt(), (a / n).sqrt())
        })
        .collect();
    Ok((model, sel, scores))
}

/// The corpus's verdict on rhonn's default against the ARX, over every system's outputs.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
pub struct Summary {
    /// System outputs scored (a failed system counts none).
    pub scored: usize,
    /// Systems whose fit failed.
    pub failed: usize,
    /// The median of rhonn's free-run RMS error over the ARX's.
    pub median_ratio: f64,
    /// The largest, and the system and output it belongs to.
    pub worst_ratio: f64,
    /// See `worst_ratio`.
    pub worst: String,
    /// Outputs where rhonn is at most 1.01 x the ARX.
    pub at_most_arx: usize,
    /// Outputs where rhonn is above the test's standard deviation while the ARX is below.
    pub above_std_where_arx_below: usize,
    /// The same for rhonn identify's default online model: the median of its ratio to the
    /// ARX, the largest and where, and the outputs at most 1.01 x the ARX (of those it
    /// scored).
    pub online_median_ratio: f64,
    /// See `online_median_ratio`.
    pub online_worst_ratio: f64,
    /// See `online_median_ratio`.
    pub online_worst: String,
    /// See `online_median_ratio`.
    pub online_at_most_arx: usize,
}

/// The ratios `of` each output gives (where it gives one), sorted, each with its system
/// and output.
fn sorted_ratios(rows: &[Judged], of: impl Fn(&OutputScore) -> Option<f64>) -> Vec<(f64, String)> {
    let mut ratios: Vec<(f64, String)> = rows
        .iter()
        .flat_map(|j| {
            j.outputs
                .iter()
                .filter_map(|o| Some((of(o)?, format!("{} {}", j.system, o.output))))
                .collect::<Vec<_>>()
        })
        .collect();
    ratios.sort_by(|a, b| a.0.total_cmp(&b.0));
    ratios
}

/// The median of sorted ratios (NaN for none).
fn median(ratios: &[(f64, String)]) -> f64 {
    let n = ratios.len();
    match n {
        0 => f64::NAN,
        _ if n % 2 == 1 => ratios[n / 2].0,
        _ => 0.5 * (ratios[n / 2 - 1].0 + ratios[n / 2].0),
    }
}

/// The median and the worst over `rows`.
pub fn summarise(rows: &[Judged]) -> Summary {
    let ratios = sorted_ratios(rows, |o| Some(o.ratio));
    let online = sorted_ratios(rows, |o| o.online_ratio);
    let outs = || rows.iter().flat_map(|j| &j.outputs);
    Summary {
        scored: ratios.len(),
        failed: rows.iter().filter(|j| j.failed.is_some()).count(),
        median_ratio: median(&ratios),
        worst_ratio: ratios.last().map_or(f64::NAN, |r| r.0),
        worst: ratios.last().map_or(String::new(), |r| r.1.clone()),
        at_most_arx: outs().filter(|o| o.ratio <= 1.01).count(),
        above_std_where_arx_below: outs()
            .filter(|o| o.fit_rmse > o.test_std && o.arx_rmse < o.test_std)
            .count(),
        online_median_ratio: median(&online),
        online_worst_ratio: online.last().map_or(f64::NAN, |r| r.0),
        online_worst: online.last().map_or(String::new(), |r| r.1.clone()),
        online_at_most_arx: online.iter().filter(|r| r.0 <= 1.01).count(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_family_draws_finite_records_the_same_on_every_call() {
        let a = generate(7, Family::ALL.len());
        let b = generate(7, Family::ALL.len());
        for (x, y) in a.iter().zip(&b) {
            assert_eq!(x.train, y.train, "{}", x.name);
            for r in x.train.iter().chain(&x.tests) {
                for c in r.inputs.iter().chain(&r.outputs) {
                    assert!(c.iter().all(|v| v.is_finite()), "{}: not finite", x.name);
                    assert!(std_dev(c) > 0.0, "{}: a constant column", x.name);
                }
            }
        }
        let c = generate(8, 1);
        assert_ne!(a[0].train, c[0].train, "another seed, another system");
    }
}
