//! Monte Carlo campaigns over the thesis's parameter tolerances (beta, mu_1, mu_2 +-20 %,
//! Q_0 +-10 %, demand slew +-10 %): each run's draw depends only on the campaign's seed
//! and the run's index, so a campaign gives the same rows whatever the thread count and
//! however it is sharded. `rhonn campaign` adds the files, the resume and the merge.

use super::run::{run_full, Summary};
use super::scenario::ScenarioSpec;
use super::trace::NoRecorder;
use crate::signal::SignalSpec;
use rand::{Rng, SeedableRng};
use serde::Serialize;

/// An uncertain parameter of the thesis and its relative tolerance.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Tolerance {
    /// Name as in `runs.csv` (the scenario's `[plant]` key it scales).
    pub name: &'static str,
    /// Relative half-width (0.2 = +-20 %).
    pub relative: f64,
}

/// The thesis's stated tolerances (SPEC.md table): beta +-20 %, mu_1 and mu_2 +-20 %,
/// Q_0 +-10 %, load flow slew rate +-10 %.
pub const TOLERANCES: [Tolerance; 5] = [
    Tolerance {
        name: "beta_mpa",
        relative: 0.2,
    },
    Tolerance {
        name: "mu_1",
        relative: 0.2,
    },
    Tolerance {
        name: "mu_2",
        relative: 0.2,
    },
    Tolerance {
        name: "q_0_dm3_s",
        relative: 0.1,
    },
    Tolerance {
        name: "qdot_max_dm3_s2",
        relative: 0.1,
    },
];

/// How the runs' parameters are drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Sampling {
    /// Each factor uniform in `[1 - tol, 1 + tol]`.
    Uniform,
    /// Every corner of the box (2^5 = 32 runs; run k's bit j picks the sign of factor j).
    Corners,
}

/// The seed of run `index` of a campaign seeded `seed` (SplitMix64 of both): a run's
/// draw depends on nothing else.
pub fn run_seed(seed: u64, index: u64) -> u64 {
    let mut z = seed
        ^ index
            .wrapping_mul(0x9e37_79b9_7f4a_7c15)
            .wrapping_add(0x6a09_e667_f3bc_c909);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The multiplying factors of run `index` (one per [`TOLERANCES`] entry).
pub fn draw(seed: u64, index: u64, sampling: Sampling) -> [f64; 5] {
    let mut f = [1.0; 5];
    match sampling {
        Sampling::Uniform => {
            let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(run_seed(seed, index));
            for (fi, t) in f.iter_mut().zip(&TOLERANCES) {
                *fi = 1.0 + t.relative * rng.gen_range(-1.0..=1.0);
            }
        }
        Sampling::Corners => {
            for (j, (fi, t)) in f.iter_mut().zip(&TOLERANCES).enumerate() {
                let sign = if index >> j & 1 == 1 { 1.0 } else { -1.0 };
                *fi = 1.0 + sign * t.relative;
            }
        }
    }
    f
}

/// The scenario of one run: the plant's parameters scaled by `factors`; the slew factor
/// scales both the plant's Qdot_max and the demand trapezoids' slew. The noise and PRBS
/// seeds are the scenario's, so runs differ only by their parameters.
pub fn apply(spec: &ScenarioSpec, factors: &[f64; 5]) -> ScenarioSpec {
    let mut s = spec.clone();
    s.plant.beta_mpa *= factors[0];
    s.plant.mu_1 *= factors[1];
    s.plant.mu_2 *= factors[2];
    s.plant.q_0_dm3_s *= factors[3];
    s.plant.qdot_max_dm3_s2 *= factors[4];
    if let Some(SignalSpec::Trapezoids { slew_per_s, .. }) = s.demand_dm3_s.as_mut() {
        *slew_per_s *= factors[4];
    }
    s
}

/// The names of the figures a run of `spec` reports, in `runs.csv` order.
pub fn figure_names(spec: &ScenarioSpec) -> Vec<String> {
    let mut v: Vec<String> = [
        "p_line_min_mpa",
        "p_line_max_mpa",
        "final_p_line_mpa",
        "stroke_max_mm",
        "time_below_p_min_after_1s_s",
    ]
    .map(String::from)
    .to_vec();
    if spec.controller.is_some() {
        v.extend(
            [
                "ise_mpa2_s",
                "max_abs_deviation_settled_mpa",
                "time_current_saturated_s",
            ]
            .map(String::from),
        );
    }
    if matches!(
        spec.controller,
        Some(super::scenario::ControllerSpec::RhonnAdaptive { .. })
    ) {
        v.extend(
            [
                "pi_ise_mpa2_s",
                "pi_max_abs_deviation_settled_mpa",
                "pi_time_below_p_min_after_1s_s",
                "w_norm_max",
                "w1_distance_max",
            ]
            .map(String::from),
        );
    }
    if let Some(id) = &spec.identifier {
        for s in &id.states {
            v.push(format!("{s}_training_fit_percent"));
            v.push(format!("{s}_training_rms_error"));
        }
    }
    v
}

/// The figures of a run, in [`figure_names`] order.
pub fn figure_values(summary: &Summary) -> Vec<f64> {
    let f = &summary.figures;
    let mut v = vec![
        f.p_line_min_mpa,
        f.p_line_max_mpa,
        f.final_p_line_mpa,
        f.stroke_max_mm,
        f.time_below_p_min_after_1s_s,
    ];
    if let Some(r) = &f.regulation {
        v.extend([
            r.ise_mpa2_s,
            r.max_abs_deviation_settled_mpa,
            r.time_current_saturated_s,
        ]);
    }
    if let Some(c) = &summary.control {
        let b = &c.baseline.figures;
        let rb = b.regulation.as_ref();
        v.extend([
            rb.map_or(f64::NAN, |r| r.ise_mpa2_s),
            rb.map_or(f64::NAN, |r| r.max_abs_deviation_settled_mpa),
            b.time_below_p_min_after_1s_s,
            c.adaptive.w_norm_max,
            c.adaptive.w1_distance_max,
        ]);
    }
    if let Some(id) = &summary.identification {
        for s in &id.training {
            v.push(s.fit_percent);
            v.push(s.rms_error);
        }
    }
    v
}

/// One run's row: its index, factors, and figures or the reason it failed.
#[derive(Debug, Clone, PartialEq)]
pub struct RunRow {
    /// Run index.
    pub index: u64,
    /// The drawn factors.
    pub factors: [f64; 5],
    /// Figures, or the error's message.
    pub outcome: Result<Vec<f64>, String>,
}

/// Run index `index` of a campaign over `spec`.
pub fn run_one(spec: &ScenarioSpec, seed: u64, index: u64, sampling: Sampling) -> RunRow {
    let factors = draw(seed, index, sampling);
    let outcome = apply(spec, &factors)
        .check()
        .and_then(|sc| run_full(&sc, &mut NoRecorder))
        .map(|o| figure_values(&o.summary))
        .map_err(|e| e.to_string());
    RunRow {
        index,
        factors,
        outcome,
    }
}

/// Distribution of one figure over the successful runs.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FigureStats {
    /// Figure name.
    pub figure: String,
    /// Smallest value.
    pub min: f64,
    /// 5 % quantile.
    pub q05: f64,
    /// Median.
    pub median: f64,
    /// 95 % quantile.
    pub q95: f64,
    /// Largest value.
    pub max: f64,
    /// Mean.
    pub mean: f64,
}

/// Per figure statistics over `rows` (failed runs left out; NaN values left out).
pub fn statistics(names: &[String], rows: &[RunRow]) -> Vec<FigureStats> {
    names
        .iter()
        .enumerate()
        .map(|(k, name)| {
            let mut v: Vec<f64> = rows
                .iter()
                .filter_map(|r| r.outcome.as_ref().ok().map(|f| f[k]))
                .filter(|x| x.is_finite())
                .collect();
            v.sort_by(f64::total_cmp);
            let q = |p: f64| {
                if v.is_empty() {
                    return f64::NAN;
                }
                // Linear interpolation between order statistics (type 7, as numpy's default).
                let h = p * (v.len() - 1) as f64;
                let (lo, hi) = (h.floor() as usize, h.ceil() as usize);
                v[lo] + (h - lo as f64) * (v[hi] - v[lo])
            };
            FigureStats {
                figure: name.clone(),
                min: q(0.0),
                q05: q(0.05),
                median: q(0.5),
                q95: q(0.95),
                max: q(1.0),
                mean: if v.is_empty() {
                    f64::NAN
                } else {
                    v.iter().sum::<f64>() / v.len() as f64
                },
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_draw_depends_only_on_seed_and_index_and_stays_in_the_box() {
        for i in 0..200 {
            let a = draw(7, i, Sampling::Uniform);
            assert_eq!(a, draw(7, i, Sampling::Uniform));
            for (f, t) in a.iter().zip(&TOLERANCES) {
                assert!((f - 1.0).abs() <= t.relative + 1e-15);
            }
        }
        assert_ne!(draw(7, 0, Sampling::Uniform), draw(8, 0, Sampling::Uniform));
        assert_ne!(draw(7, 0, Sampling::Uniform), draw(7, 1, Sampling::Uniform));
        let c = draw(0, 0b10110, Sampling::Corners);
        assert_eq!(c, [0.8, 1.2, 1.2, 0.9, 1.1]);
    }

    #[test]
    fn quantiles_as_numpy() {
        let names = vec!["x".to_string()];
        let rows: Vec<RunRow> = (0..5)
            .map(|k| RunRow {
                index: k,
                factors: [1.0; 5],
                outcome: Ok(vec![k as f64]),
            })
            .chain(std::iter::once(RunRow {
                index: 9,
                factors: [1.0; 5],
                outcome: Err("failed".into()),
            }))
            .collect();
        let s = &statistics(&names, &rows)[0];
        // numpy.quantile([0, 1, 2, 3, 4], [0.05, 0.5, 0.95]) = [0.2, 2.0, 3.8]
        assert!((s.q05 - 0.2).abs() < 1e-12 && s.median == 2.0 && (s.q95 - 3.8).abs() < 1e-12);
        assert_eq!((s.min, s.max, s.mean), (0.0, 4.0, 2.0));
    }
}
