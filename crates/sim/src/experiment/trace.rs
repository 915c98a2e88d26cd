//! A labelled table of samples in SI columns ([`Trace`]): what a prediction or an online
//! identification writes as CSV.

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
