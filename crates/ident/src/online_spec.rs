//! The online identifier's settings (`rhonn identify --model SPEC.toml`, the Python
//! `OnlineIdentifier`'s `model`) and the scaling of its signals, with their checks.

use crate::error::{invalid, Result};
use crate::law::LawSpec;
use crate::models::Activation;
use serde::{Deserialize, Serialize};

/// How inputs move between two samples (`hold` or `linear`): the core's.
pub use rhonn_core::online::InputHold;

/// An online identifier's structure and law, as `rhonn identify --model SPEC.toml`
/// writes it. Every field has a default.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct OnlineSpec {
    /// `continuous` (default: the thesis's continuous-time neurons, series-parallel, input
    /// filters for hidden states) or `lagged` (a discrete-time RHONN of lagged
    /// measurements, `rhonn fit`'s `rhonn` structure, learned per sample; see `lags`).
    #[serde(skip_serializing_if = "OnlineStructure::is_continuous")]
    pub structure: OnlineStructure,
    /// The lags of the `lagged` structure.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lags: Option<LagSpec>,
    /// The settings of the `cascade` structure.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cascade: Option<CascadeOnlineSpec>,
    /// The settings of the `per-output` structure: the joint structure and the outputs
    /// with a structure of their own.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub per_output: Option<super::PerOutputSpec>,
    /// The settings of the `wiener-hammerstein` structure.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub block: Option<BlockOnlineSpec>,
    /// Learning law (a `[law]` table as in scenarios); default `filtered-error` with
    /// `gamma = gain / (T L)` per neuron (T the sample time, L the number of terms).
    pub law: Option<LawSpec>,
    /// Step size of the default law (default 0.5; ignored with a `law`).
    pub gain: f64,
    /// Degree of the high-order terms (default 2).
    pub degree: usize,
    /// Most distinct factors per term (default 2).
    pub max_factors: usize,
    /// What the high-order terms of the `lagged` structure take of each lagged output
    /// (default `tanh`; `identity`: the lags themselves, a polynomial NARX), as `rhonn
    /// fit`'s `activation`.
    #[serde(skip_serializing_if = "Activation::is_tanh")]
    pub activation: Activation,
    /// Neuron pole a \[1/s\] (default 1 / (10 T)).
    pub a_per_s: Option<f64>,
    /// Time constants \[s\] of the input filters standing in for unmeasured states
    /// (default none).
    pub filters_s: Vec<f64>,
    /// `hold` (default) or `linear`.
    pub inputs: InputHold,
    /// Passes over the recordings, weights carried (default 1).
    pub epochs: usize,
    /// Freeze the weights this many seconds into each pass (default never).
    pub freeze_after_s: Option<f64>,
    /// Errors below this, in each output's own units, do not adapt (default 0).
    pub dead_zone: f64,
    /// `rhonn identify` holds each estimate within the identification data's range
    /// widened by this fraction of it on each side (default 0.1; negative: unbounded).
    pub output_margin: f64,
    /// Whether the measured outputs enter the regressor (default true). Without them
    /// the regressor depends on the inputs and their filters only, so the model learned
    /// online (series-parallel) is the very model that runs free.
    pub output_terms: bool,
}

impl Default for OnlineSpec {
    fn default() -> Self {
        OnlineSpec {
            structure: OnlineStructure::Continuous,
            lags: None,
            cascade: None,
            per_output: None,
            block: None,
            law: None,
            gain: 0.5,
            degree: 2,
            max_factors: 2,
            activation: Activation::Tanh,
            a_per_s: None,
            filters_s: Vec::new(),
            inputs: InputHold::Hold,
            epochs: 1,
            freeze_after_s: None,
            dead_zone: 0.0,
            output_margin: 0.1,
            output_terms: true,
        }
    }
}

/// The online identifier's structure.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum OnlineStructure {
    /// Continuous-time neurons between samples (the thesis's identifier).
    #[default]
    Continuous,
    /// A discrete-time RHONN of lagged measurements.
    Lagged,
    /// `rhonn fit`'s continuous-time cascade with hidden neurons, its parameters and
    /// hidden levels estimated together by extended Kalman filters from several starts.
    Cascade,
    /// A joint structure of every output and, for some outputs, a structure of their own
    /// (`per_output`): what `rhonn identify` chooses when outputs differ.
    PerOutput,
    /// `rhonn fit`'s Wiener-Hammerstein block structure (one input, one output; Wiener and
    /// Hammerstein models are among its splits), fitted on the stream's first `block.window`
    /// samples, then its polynomial learned by recursive least squares (`block`).
    WienerHammerstein,
}

impl OnlineStructure {
    fn is_continuous(&self) -> bool {
        *self == OnlineStructure::Continuous
    }
}

/// The lags of the `lagged` structure, as `rhonn fit`'s spec names them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct LagSpec {
    /// Output lags `output_lag_start .. output_lag_start + na - 1` (default 2).
    pub na: usize,
    /// Input lags `nk .. nk + nb - 1` (default 2).
    pub nb: usize,
    /// Input delay in samples (default 1).
    pub nk: usize,
    /// First output lag (default 1; K: a direct K-step-ahead predictor).
    pub output_lag_start: usize,
    /// The high-order terms take only the first this-many lags of each signal (default
    /// every lag).
    pub nonlinear_lags: Option<usize>,
}

/// The `cascade` structure's settings (`cascade = { ... }`): normalised units (levels
/// in output standard deviations, time in samples), as `rhonn fit`'s `cascade`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct CascadeOnlineSpec {
    /// Neurons in the chain, the last one measured (default 2).
    pub neurons: usize,
    /// Whether the exponents are learned (default true; else 1/2, Torricelli).
    pub free_exponents: bool,
    /// Filters run side by side from seeded random starts (default 32); the estimate is
    /// the one whose own free run has followed the measurements best this pass.
    pub starts: usize,
    /// Seed of the starts (default 1).
    pub seed: u64,
    /// Samples after each record's start whose measurements settle the hidden levels of a
    /// free run (default 5), as `rhonn fit`'s `settle`.
    pub settle: usize,
    /// Measurement noise variance the filters assume (default 1e-2, output variances).
    pub measurement_var: f64,
    /// Process noise variance per sample on each level (default 1e-6).
    pub level_var: f64,
    /// Initial variance of each parameter coordinate (logarithms of rates, shares and
    /// bounds; default 1).
    pub parameter_var: f64,
    /// Added to each parameter coordinate's variance at every new pass (default 1e-3):
    /// without it the filters' gains fall to zero within the first pass.
    pub pass_var: f64,
    /// RK4 substeps per sample (default 4).
    pub substeps: usize,
}

/// The online block structure's highest polynomial degree (offline 40): at degree 20 its
/// recursive least squares, started from the inverse of a window's information matrix, did
/// not settle over repeated passes of a noisy record (docs/results.md).
pub const MAX_BLOCK_DEGREE: usize = 15;

/// The `wiener-hammerstein` structure's settings (`block = { ... }`), as `rhonn fit`'s
/// `kind = "wiener-hammerstein"` (`na` poles, `nb` = poles + 1, `degree`, `epochs`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct BlockOnlineSpec {
    /// Poles of the best linear approximation, split between the two filters (default 6).
    pub poles: usize,
    /// Degree of the static polynomial (default 15, at most [`MAX_BLOCK_DEGREE`]).
    pub degree: usize,
    /// Input delay in samples (default 0).
    pub nk: usize,
    /// Levenberg-Marquardt iterations of the fit (default 50).
    pub iterations: usize,
    /// Samples learned before the block structure is fitted on them (default 5,000; the
    /// bank: its warm-up, at most 50,000). Until then the estimate is the last measured
    /// output; after it, only the polynomial and the offset learn.
    pub window: usize,
    /// Times the block structure is fitted again from scratch, each on the latest `window`
    /// samples once that many more have been learned (default 0, as in the bank, where
    /// fitting again was measured and not kept). The memory held stays one window.
    pub refits: usize,
}

impl Default for BlockOnlineSpec {
    fn default() -> Self {
        BlockOnlineSpec {
            poles: 6,
            degree: 15,
            nk: 0,
            iterations: 50,
            window: 5_000,
            refits: 0,
        }
    }
}

impl BlockOnlineSpec {
    /// Each setting within its range (errors name the key).
    pub(super) fn check(&self) -> Result<()> {
        let ranges = [
            ("poles", self.poles, 1, 20),
            ("degree", self.degree, 1, MAX_BLOCK_DEGREE),
            ("nk", self.nk, 0, 100),
            ("iterations", self.iterations, 1, 10_000),
            ("window", self.window, 20, 10_000_000),
            ("refits", self.refits, 0, 1_000),
        ];
        for (key, v, lo, hi) in ranges {
            if !(lo..=hi).contains(&v) {
                return Err(invalid(
                    format!("model.block.{key}"),
                    v,
                    format!("an integer in [{lo}, {hi}]"),
                ));
            }
        }
        Ok(())
    }
}

impl Default for CascadeOnlineSpec {
    fn default() -> Self {
        CascadeOnlineSpec {
            neurons: 2,
            free_exponents: true,
            starts: 32,
            seed: 1,
            settle: 5,
            measurement_var: 1e-2,
            level_var: 1e-6,
            parameter_var: 1.0,
            pass_var: 1e-3,
            substeps: 4,
        }
    }
}

impl CascadeOnlineSpec {
    /// Check every setting (errors name the key).
    pub(super) fn check(&self) -> Result<()> {
        if !(2..=4).contains(&self.neurons) {
            return Err(invalid(
                "model.cascade.neurons",
                self.neurons,
                "an integer in [2, 4]",
            ));
        }
        if !(1..=256).contains(&self.starts) {
            return Err(invalid(
                "model.cascade.starts",
                self.starts,
                "an integer in [1, 256]",
            ));
        }
        if !(1..=1000).contains(&self.settle) {
            return Err(invalid(
                "model.cascade.settle",
                self.settle,
                "an integer in [1, 1000]",
            ));
        }
        if !(1..=100).contains(&self.substeps) {
            return Err(invalid(
                "model.cascade.substeps",
                self.substeps,
                "an integer in [1, 100]",
            ));
        }
        for (key, v, zero_ok) in [
            ("measurement_var", self.measurement_var, false),
            ("level_var", self.level_var, true),
            ("parameter_var", self.parameter_var, false),
            ("pass_var", self.pass_var, true),
        ] {
            if !(v.is_finite() && (v > 0.0 || (zero_ok && v == 0.0))) {
                return Err(invalid(
                    format!("model.cascade.{key}"),
                    v,
                    if zero_ok {
                        "a finite number >= 0"
                    } else {
                        "a finite number > 0"
                    },
                ));
            }
        }
        Ok(())
    }
}

impl Default for LagSpec {
    fn default() -> Self {
        LagSpec {
            na: 2,
            nb: 2,
            nk: 1,
            output_lag_start: 1,
            nonlinear_lags: None,
        }
    }
}

/// Offsets and scales of the outputs and the inputs: the identifier sees
/// `(signal - offset) / scale`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Scaling {
    /// Per output.
    pub y_offset: Vec<f64>,
    /// Per output, > 0.
    pub y_scale: Vec<f64>,
    /// Per input.
    pub u_offset: Vec<f64>,
    /// Per input, > 0.
    pub u_scale: Vec<f64>,
    /// Per output, the range the model's estimate is held in (output units), like a
    /// limited integrator; none: unbounded.
    #[serde(default)]
    pub y_bounds: Option<Vec<[f64; 2]>>,
}

impl Scaling {
    /// No scaling for `ny` outputs and `nu` inputs.
    pub fn identity(ny: usize, nu: usize) -> Self {
        Scaling {
            y_offset: vec![0.0; ny],
            y_scale: vec![1.0; ny],
            u_offset: vec![0.0; nu],
            u_scale: vec![1.0; nu],
            y_bounds: None,
        }
    }

    /// Mean and standard deviation of each column (a constant column gets scale 1).
    pub fn of(outputs: &[&[f64]], inputs: &[&[f64]]) -> Self {
        let ms = |c: &&[f64]| crate::metrics::mean_std(&[*c]);
        let (y_offset, y_scale) = outputs.iter().map(ms).unzip();
        let (u_offset, u_scale) = inputs.iter().map(ms).unzip();
        Scaling {
            y_offset,
            y_scale,
            u_offset,
            u_scale,
            y_bounds: None,
        }
    }
}

/// Check a spec against the signals it will see (every error names the key).
pub(super) fn check_spec(spec: &OnlineSpec, ny: usize, nu: usize, period_s: f64, s: &Scaling) -> Result<()> {
    if ny == 0 || nu == 0 {
        return Err(invalid(
            "outputs and inputs",
            format!("{ny} and {nu}"),
            "at least one of each",
        ));
    }
    if !(period_s.is_finite() && (1e-9..=1e9).contains(&period_s)) {
        return Err(invalid(
            "sample time",
            period_s,
            "a number of seconds in [1e-9, 1e9]",
        ));
    }
    if !(1..=4).contains(&spec.degree) {
        return Err(invalid("model.degree", spec.degree, "an integer in [1, 4]"));
    }
    if spec.activation != Activation::Tanh && spec.structure != OnlineStructure::Lagged {
        return Err(invalid(
            "model.activation",
            "identity",
            "tanh, or identity with structure = \"lagged\"",
        ));
    }
    if !(1..=spec.degree).contains(&spec.max_factors) {
        return Err(invalid(
            "model.max_factors",
            spec.max_factors,
            format!("an integer in [1, {}]", spec.degree),
        ));
    }
    if !(spec.gain.is_finite() && spec.gain > 0.0) {
        return Err(invalid("model.gain", spec.gain, "a finite number > 0"));
    }
    if let Some(a) = spec.a_per_s {
        if !(a.is_finite() && a > 0.0) {
            return Err(invalid(
                "model.a_per_s",
                a,
                "a finite number > 0 (a stable neuron)",
            ));
        }
    }
    for (k, tau) in spec.filters_s.iter().enumerate() {
        if !(tau.is_finite() && *tau > 0.0) {
            return Err(invalid(
                format!("model.filters_s[{k}]"),
                tau,
                "a time constant > 0 s",
            ));
        }
    }
    if !(1..=10_000).contains(&spec.epochs) {
        return Err(invalid("model.epochs", spec.epochs, "an integer in [1, 10000]"));
    }
    if let Some(f) = spec.freeze_after_s {
        if !(f.is_finite() && f >= 0.0) {
            return Err(invalid("model.freeze_after_s", f, "a time >= 0 s"));
        }
    }
    if !(spec.dead_zone.is_finite() && spec.dead_zone >= 0.0) {
        return Err(invalid("model.dead_zone", spec.dead_zone, "a finite number >= 0"));
    }
    check_scaling(s, ny, nu)?;
    check_tables(spec, ny)?;
    if spec.structure == OnlineStructure::Lagged {
        let continuous_only = [
            ("a_per_s", spec.a_per_s.is_some()),
            ("inputs", spec.inputs != InputHold::Hold),
            ("output_terms", !spec.output_terms),
        ];
        if let Some((key, _)) = continuous_only.iter().find(|(_, set)| *set) {
            return Err(invalid(
                format!("model.{key}"),
                "set",
                "not with `structure = \"lagged\"` (a setting of the continuous-time neurons)",
            ));
        }
    }
    if !spec.output_margin.is_finite() {
        return Err(invalid(
            "model.output_margin",
            spec.output_margin,
            "a finite number (negative: unbounded)",
        ));
    }
    Ok(())
}

/// Each structure's own table (`lags`, `cascade`, `per_output`) only with that structure,
/// and checked.
fn check_tables(spec: &OnlineSpec, ny: usize) -> Result<()> {
    let only = |key: &str, structure: &str| {
        Err(invalid(
            format!("model.{key}"),
            "a table",
            format!("only with `structure = \"{structure}\"`"),
        ))
    };
    if spec.structure != OnlineStructure::Lagged && spec.lags.is_some() {
        return only("lags", "lagged");
    }
    if spec.structure != OnlineStructure::Cascade && spec.cascade.is_some() {
        return only("cascade", "cascade");
    }
    if spec.structure != OnlineStructure::WienerHammerstein && spec.block.is_some() {
        return only("block", "wiener-hammerstein");
    }
    if spec.structure == OnlineStructure::Cascade {
        check_cascade(spec)?;
    }
    if spec.structure == OnlineStructure::WienerHammerstein {
        spec.block.clone().unwrap_or_default().check()?;
        check_others(
            spec,
            "wiener-hammerstein",
            "its fit and recursive least squares learn; its settings are the `block` table's",
        )?;
    }
    match (spec.structure == OnlineStructure::PerOutput, &spec.per_output) {
        (true, Some(p)) => p.check(ny),
        (true, None) => Err(invalid(
            "model.per_output",
            "absent",
            "a `per_output` table with `structure = \"per-output\"`",
        )),
        (false, Some(_)) => only("per_output", "per-output"),
        (false, None) => Ok(()),
    }
}

/// Offsets and scales within what the arithmetic can carry: every value finite, offsets
/// of magnitude at most 1e150 and scales in [1e-150, 1e150] (a scale of 5e-324 or 1e308
/// makes every prediction NaN or infinite), bounds finite with low < high. Errors name
/// the field and its index.
fn check_scaling(s: &Scaling, ny: usize, nu: usize) -> Result<()> {
    const BIG: f64 = 1e150;
    let fields: [(&str, &[f64], usize, bool); 4] = [
        ("y_offset", &s.y_offset, ny, false),
        ("y_scale", &s.y_scale, ny, true),
        ("u_offset", &s.u_offset, nu, false),
        ("u_scale", &s.u_scale, nu, true),
    ];
    for (name, v, n, scale) in fields {
        if v.len() != n {
            return Err(invalid(
                format!("scaling.{name}"),
                format!("{} values", v.len()),
                format!(
                    "{n} (one per {})",
                    if name.starts_with('y') { "output" } else { "input" }
                ),
            ));
        }
        for (k, x) in v.iter().enumerate() {
            let ok = if scale {
                x.is_finite() && (1.0 / BIG..=BIG).contains(x)
            } else {
                x.is_finite() && x.abs() <= BIG
            };
            if !ok {
                let allowed = if scale {
                    "a scale in [1e-150, 1e150]"
                } else {
                    "a finite offset of magnitude at most 1e150"
                };
                return Err(invalid(format!("scaling.{name}[{k}]"), x, allowed));
            }
        }
    }
    if let Some(b) = &s.y_bounds {
        if b.len() != ny {
            return Err(invalid(
                "scaling.y_bounds",
                format!("{} pairs", b.len()),
                format!("{ny} (one per output)"),
            ));
        }
        for (k, [lo, hi]) in b.iter().enumerate() {
            if !(lo.is_finite() && hi.is_finite() && lo < hi && lo.abs() <= BIG && hi.abs() <= BIG) {
                return Err(invalid(
                    format!("scaling.y_bounds[{k}]"),
                    format!("[{lo}, {hi}]"),
                    "finite [low, high] with low < high, of magnitude at most 1e150",
                ));
            }
        }
    }
    Ok(())
}

/// The `cascade` structure's own checks: its settings, and no key of the other
/// structures (it learns by its filters, not by a `law`).
fn check_cascade(spec: &OnlineSpec) -> Result<()> {
    spec.cascade.clone().unwrap_or_default().check()?;
    check_others(
        spec,
        "cascade",
        "its extended Kalman filters learn; its settings are the `cascade` table's",
    )
}

/// No key of the other structures with `structure` (which learns its own way, `why`).
fn check_others(spec: &OnlineSpec, structure: &str, why: &str) -> Result<()> {
    let d = OnlineSpec::default();
    let others = [
        ("law", spec.law.is_some()),
        ("a_per_s", spec.a_per_s.is_some()),
        ("filters_s", !spec.filters_s.is_empty()),
        ("inputs", spec.inputs != InputHold::Hold),
        ("output_terms", !spec.output_terms),
        ("degree", spec.degree != d.degree),
        ("max_factors", spec.max_factors != d.max_factors),
        ("gain", spec.gain != d.gain),
        ("dead_zone", spec.dead_zone != d.dead_zone),
    ];
    if let Some((key, _)) = others.iter().find(|(_, set)| *set) {
        return Err(invalid(
            format!("model.{key}"),
            "set",
            format!("not with `structure = \"{structure}\"` ({why})"),
        ));
    }
    Ok(())
}
