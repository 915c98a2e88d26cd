//! What a run produces sample by sample: the [`Recorder`] trait and the in-memory
//! [`Trace`].

/// One output sample (SI).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sample {
    /// Time \[s\].
    pub t: f64,
    /// Line pressure \[Pa\].
    pub p_line: f64,
    /// Pump stroke \[m\].
    pub stroke: f64,
    /// Solenoid current \[A\].
    pub current: f64,
    /// Demanded flow \[m^3/s\].
    pub demand: f64,
    /// Pressure set-point \[Pa\] (regulated runs).
    pub p_ref: Option<f64>,
    /// Measured pressure \[Pa\] (when measured: regulated runs, or noise > 0).
    pub p_meas: Option<f64>,
    /// An identifier's estimates of `[p_line, stroke]` \[Pa, m\] (identified states only).
    pub hat: [Option<f64>; 2],
    /// A frozen model's free-run (parallel) estimates, in the validation runs, which
    /// integrate the series-parallel (`hat`) and the parallel model together.
    pub hat_parallel: [Option<f64>; 2],
    /// The adaptive controller's state at the last control instant.
    pub control: Option<crate::control::CascadeState>,
    /// The PI baseline's plant at the same instant (adaptive runs).
    pub baseline: Option<BaselineSample>,
    /// The second baseline's plant (adaptive runs with a `second_baseline`).
    pub second_baseline: Option<BaselineSample>,
}

/// The baseline's plant in an adaptive run (SI).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BaselineSample {
    /// Line pressure \[Pa\].
    pub p_line: f64,
    /// Stroke \[m\].
    pub stroke: f64,
    /// Current \[A\].
    pub current: f64,
}

/// Receives the output samples of a run, in time order.
pub trait Recorder {
    /// One sample.
    fn record(&mut self, s: &Sample);
    /// Whether to produce samples at all (a summary-only run skips the sampling).
    fn wants_samples(&self) -> bool {
        true
    }
    /// Produce only every `stride()`-th output sample (those with `k % stride == 0`; a
    /// campaign's envelope needs a few hundred points, not every millisecond).
    fn stride(&self) -> u64 {
        1
    }
    /// Whether an identification run should also collect its frozen-weight validation
    /// runs sample by sample (for `validation.csv`).
    fn wants_validation(&self) -> bool {
        self.wants_samples()
    }
}

/// Keeps nothing (a campaign that needs only the summary).
#[derive(Debug, Default, Clone, Copy)]
pub struct NoRecorder;

impl Recorder for NoRecorder {
    #[inline]
    fn record(&mut self, _s: &Sample) {}
    fn wants_samples(&self) -> bool {
        false
    }
}

/// A column of a trace: name, SI unit, values.
#[derive(Debug, Clone, PartialEq)]
pub struct Column {
    /// Name (`p_line`, `stroke`, ...).
    pub name: String,
    /// SI unit (`Pa`, `m`, ...).
    pub unit: &'static str,
    /// Values, one per sample.
    pub values: Vec<f64>,
}

/// All samples of a run in labelled SI columns; the first is `t` \[s\].
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Trace {
    /// The columns, `t` first.
    pub columns: Vec<Column>,
}

impl Trace {
    /// The column called `name`.
    pub fn column(&self, name: &str) -> Option<&[f64]> {
        self.columns
            .iter()
            .find(|c| c.name == name)
            .map(|c| c.values.as_slice())
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.columns.first().map_or(0, |c| c.values.len())
    }

    /// Whether there are no samples.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

impl Recorder for Trace {
    fn record(&mut self, s: &Sample) {
        if self.columns.is_empty() {
            let mut cols = vec![
                ("t", "s"),
                ("p_line", "Pa"),
                ("stroke", "m"),
                ("current", "A"),
                ("demand", "m^3/s"),
            ];
            if s.p_ref.is_some() {
                cols.push(("p_ref", "Pa"));
            }
            if s.p_meas.is_some() {
                cols.push(("p_meas", "Pa"));
            }
            if s.hat[0].is_some() {
                cols.push(("p_line_hat", "Pa"));
            }
            if s.hat[1].is_some() {
                cols.push(("stroke_hat", "m"));
            }
            if s.control.is_some() {
                cols.extend([
                    ("stroke_ref", "m"),
                    ("p_line_model", "Pa"),
                    ("w_norm", "MPa/s"),
                    ("w1_norm", "MPa/(s mm)"),
                    ("w1_distance", "MPa/(s mm)"),
                    ("w1_ball_radius", "MPa/(s mm)"),
                ]);
            }
            if s.baseline.is_some() {
                cols.extend([("p_line_pi", "Pa"), ("stroke_pi", "m"), ("current_pi", "A")]);
            }
            if s.second_baseline.is_some() {
                cols.extend([("p_line_pi2", "Pa"), ("stroke_pi2", "m"), ("current_pi2", "A")]);
            }
            self.columns = cols
                .into_iter()
                .map(|(name, unit)| Column {
                    name: name.into(),
                    unit,
                    values: Vec::new(),
                })
                .collect();
        }
        let vals = [
            Some(s.t),
            Some(s.p_line),
            Some(s.stroke),
            Some(s.current),
            Some(s.demand),
            s.p_ref,
            s.p_meas,
            s.hat[0],
            s.hat[1],
            s.control.map(|c| c.stroke_ref),
            s.control.map(|c| c.p_hat),
            s.control.map(|c| c.w_norm),
            s.control.map(|c| c.w1_norm),
            s.control.map(|c| c.w1_distance),
            s.control.map(|c| c.ball_radius),
            s.baseline.map(|b| b.p_line),
            s.baseline.map(|b| b.stroke),
            s.baseline.map(|b| b.current),
            s.second_baseline.map(|b| b.p_line),
            s.second_baseline.map(|b| b.stroke),
            s.second_baseline.map(|b| b.current),
        ];
        for (col, v) in self.columns.iter_mut().zip(vals.into_iter().flatten()) {
            col.values.push(v);
        }
    }
}
