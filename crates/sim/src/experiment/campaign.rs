//! Monte Carlo campaigns over a plant's parameter tolerances (the pump's: beta, mu_1,
//! mu_2 +-20 %, Q_0 +-10 %, demand slew +-10 %): each run's draw depends only on the
//! campaign's seed and the run's index ([`draw`]), so a campaign gives the same rows
//! whatever the thread count and however it is sharded. A scenario's `[campaign]` section
//! overrides a parameter's distribution (uniform, truncated normal, fixed) and range.
//! Here: the plan and the draw, and the statistics of the runs' figures and traces;
//! `rhonn campaign` (the report crate) runs the draws and adds the files, the resume and
//! the merge.

use serde::Serialize;

pub use super::campaign_plan::*;

/// Type-7 quantile (linear interpolation between order statistics, numpy's default) of
/// sorted `v`; NaN when `v` is empty.
pub fn quantile_sorted(v: &[f64], p: f64) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    let h = p * (v.len() - 1) as f64;
    let (lo, hi) = (h.floor() as usize, h.ceil() as usize);
    v[lo] + (h - lo as f64) * (v[hi] - v[lo])
}

/// The envelope of several traces on one grid: per point min, 5 % quantile, median,
/// 95 % quantile, max.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Envelope {
    /// Smallest value per point.
    pub min: Vec<f64>,
    /// 5 % quantile per point.
    pub q05: Vec<f64>,
    /// Median per point.
    pub median: Vec<f64>,
    /// 95 % quantile per point.
    pub q95: Vec<f64>,
    /// Largest value per point.
    pub max: Vec<f64>,
}

impl Envelope {
    /// The envelope of `traces` (each as long as the grid; shorter ones count where they
    /// have values).
    pub fn of(traces: &[&[f64]], points: usize) -> Envelope {
        let mut e = Envelope::default();
        let mut col = Vec::with_capacity(traces.len());
        for k in 0..points {
            col.clear();
            col.extend(
                traces
                    .iter()
                    .filter_map(|t| t.get(k))
                    .copied()
                    .filter(|x| x.is_finite()),
            );
            col.sort_by(f64::total_cmp);
            e.min.push(quantile_sorted(&col, 0.0));
            e.q05.push(quantile_sorted(&col, 0.05));
            e.median.push(quantile_sorted(&col, 0.5));
            e.q95.push(quantile_sorted(&col, 0.95));
            e.max.push(quantile_sorted(&col, 1.0));
        }
        e
    }
}

/// Distribution of one figure over the successful runs.
#[derive(Debug, Clone, PartialEq, Serialize, schemars::JsonSchema)]
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

/// One figure's statistics over the values of the runs that finished, in any order
/// (the non-finite ones are left out; quantiles by [`quantile_sorted`], the mean summed
/// in ascending order: the same figures whatever order the runs came in).
pub fn figure_stats(name: &str, mut v: Vec<f64>) -> FigureStats {
    v.retain(|x| x.is_finite());
    v.sort_by(f64::total_cmp);
    let q = |p: f64| quantile_sorted(&v, p);
    FigureStats {
        figure: name.to_string(),
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
}

#[cfg(test)]
#[path = "campaign_tests.rs"]
mod tests;
