//! What every figure integrated on the solver's dense output shares: the 3-point
//! Gauss-Legendre rule each step is integrated with, and how an error converts to display
//! units at each point.

/// Gauss-Legendre nodes on \[0, 1\] and weights (summing to 1).
pub(super) const GAUSS: [(f64, f64); 3] = [
    (0.112_701_665_379_258_31, 5.0 / 18.0),
    (0.5, 8.0 / 18.0),
    (0.887_298_334_620_741_7, 5.0 / 18.0),
];

/// How a figure on the dense output converts a state's errors at each point: times the
/// display units per SI unit (`Scale(1.0)`: SI as they are). (A value, not a closure: the
/// conversion runs 16 times per interval and inlines.)
#[derive(Debug, Clone, Copy)]
pub(super) struct Scale(pub(super) f64);

impl Scale {
    #[inline(always)]
    pub(super) fn apply(self, v: f64) -> f64 {
        v * self.0
    }
}
