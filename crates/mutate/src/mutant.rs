//! One mutated file, what the TOML, JSON and CSV mutations (`mutation`, `csv_mutation`)
//! each return.

/// One mutated file.
#[derive(Debug, Clone)]
pub struct Mutant {
    /// The mutated text.
    pub text: String,
    /// What was changed, for the report.
    pub what: String,
    /// An error about this change names at least one of these (lower case).
    pub names: Vec<String>,
}
