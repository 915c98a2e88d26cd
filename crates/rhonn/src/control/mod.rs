//! Controllers of the line pressure, sampled every control period with zero-order hold.

mod pi;
pub use pi::Pi;
