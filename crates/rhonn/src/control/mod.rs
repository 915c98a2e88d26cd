//! Controllers of the line pressure, sampled every control period with zero-order hold.

pub mod adaptive;
mod pi;
pub use adaptive::{AffineNeuron, CascadeSettings, CascadeState, RhonnCascade};
pub use pi::Pi;
