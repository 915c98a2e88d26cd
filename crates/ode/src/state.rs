//! Storage for a state vector: a fixed-size array on the stack, or (feature `alloc`)
//! a `Vec<f64>` whose size is known only at run time, allocated once per solver.

/// A state vector the solver can work on. Implemented for `[f64; N]` and, with the
/// `alloc` feature, for `Vec<f64>`.
pub trait State: Clone {
    /// A vector of `dim` zeros. For arrays `dim` must equal `N`.
    fn zeros(dim: usize) -> Self;
    /// The components.
    fn as_slice(&self) -> &[f64];
    /// The components, mutable.
    fn as_mut_slice(&mut self) -> &mut [f64];
    /// Number of components.
    fn dim(&self) -> usize {
        self.as_slice().len()
    }
    /// A vector of `dim` copies of `v`.
    fn splat(dim: usize, v: f64) -> Self {
        let mut s = Self::zeros(dim);
        s.as_mut_slice().iter_mut().for_each(|x| *x = v);
        s
    }
}

impl<const N: usize> State for [f64; N] {
    fn zeros(dim: usize) -> Self {
        assert_eq!(dim, N, "state dimension {dim} does not match the array size {N}");
        [0.0; N]
    }
    #[inline(always)]
    fn as_slice(&self) -> &[f64] {
        self
    }
    #[inline(always)]
    fn as_mut_slice(&mut self) -> &mut [f64] {
        self
    }
}

#[cfg(feature = "alloc")]
impl State for alloc::vec::Vec<f64> {
    fn zeros(dim: usize) -> Self {
        alloc::vec![0.0; dim]
    }
    #[inline(always)]
    fn as_slice(&self) -> &[f64] {
        self
    }
    #[inline(always)]
    fn as_mut_slice(&mut self) -> &mut [f64] {
        self
    }
}
