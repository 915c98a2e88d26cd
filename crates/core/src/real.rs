//! The number type of the controller's arithmetic: `f64` on the host and on targets with
//! a double-precision FPU, `f32` on microcontrollers whose FPU is single precision (a
//! Cortex-M4F does an `f64` operation in software, some 50 times slower).
//!
//! Written by hand rather than with `num-traits`: the code needs these few operations
//! only, each the same function as the type's own (`f64::clamp`, `libm::expf`, ...), so
//! the `f64` path stays bit for bit what it was before it became generic.

use core::fmt::Debug;
use core::iter::Sum;
use core::ops::{Add, AddAssign, Div, Mul, MulAssign, Neg, Sub, SubAssign};

/// A floating-point type the controller and the laws compute in.
pub trait Real:
    Copy
    + Debug
    + Default
    + PartialEq
    + PartialOrd
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign
    + Sum
{
    /// The nearest value to `x`.
    fn of(x: f64) -> Self;
    /// As `f64` (exact).
    fn to_f64(self) -> f64;
    /// `e^self`.
    fn exp(self) -> Self;
    /// Square root.
    fn sqrt(self) -> Self;
    /// Absolute value.
    fn abs(self) -> Self;
    /// The larger (the type's `max`).
    fn max(self, other: Self) -> Self;
    /// The smaller (the type's `min`).
    fn min(self, other: Self) -> Self;
    /// Clamped to `[lo, hi]` (the type's `clamp`).
    fn clamp(self, lo: Self, hi: Self) -> Self;
    /// The bits, for comparing values exactly.
    fn bits(self) -> u64;
    /// `self^n`: the platform's `powi` for `f64` with the `std` feature (the host
    /// library), [`powi_by_squaring`] otherwise.
    fn powi(self, n: i32) -> Self;
    /// Neither infinite nor NaN.
    fn is_finite(self) -> bool;
    /// The smallest integer not below (libm's `ceil`).
    fn ceil(self) -> Self;
    /// The nearest value to `n` (the type's `as` conversion).
    fn of_usize(n: usize) -> Self;
    /// Truncated to an integer, saturating, NaN to 0 (the type's `as` conversion).
    fn to_usize(self) -> usize;
}

/// `x^n` by squaring and multiplying, as compiler-builtins' `__powidf2` (the platform's
/// `powi` on targets without a math library) does.
#[inline]
pub fn powi_by_squaring<T: Real>(x: T, n: i32) -> T {
    let (mut a, mut b, mut r) = (x, n.unsigned_abs(), T::of(1.0));
    loop {
        if b & 1 != 0 {
            r *= a;
        }
        b /= 2;
        if b == 0 {
            break;
        }
        a *= a;
    }
    if n < 0 {
        T::of(1.0) / r
    } else {
        r
    }
}

impl Real for f64 {
    #[inline(always)]
    fn of(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn to_f64(self) -> f64 {
        self
    }
    #[inline(always)]
    fn exp(self) -> Self {
        crate::exp(self)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        libm::sqrt(self)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        libm::fabs(self)
    }
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        f64::max(self, other)
    }
    #[inline(always)]
    fn min(self, other: Self) -> Self {
        f64::min(self, other)
    }
    #[inline(always)]
    fn clamp(self, lo: Self, hi: Self) -> Self {
        f64::clamp(self, lo, hi)
    }
    #[inline(always)]
    fn bits(self) -> u64 {
        self.to_bits()
    }
    #[inline(always)]
    fn powi(self, n: i32) -> Self {
        #[cfg(feature = "std")]
        {
            f64::powi(self, n)
        }
        #[cfg(not(feature = "std"))]
        {
            powi_by_squaring(self, n)
        }
    }
    #[inline(always)]
    fn is_finite(self) -> bool {
        f64::is_finite(self)
    }
    #[inline(always)]
    fn ceil(self) -> Self {
        libm::ceil(self)
    }
    #[inline(always)]
    fn of_usize(n: usize) -> Self {
        n as f64
    }
    #[inline(always)]
    fn to_usize(self) -> usize {
        self as usize
    }
}

impl Real for f32 {
    #[inline(always)]
    fn of(x: f64) -> Self {
        x as f32
    }
    #[inline(always)]
    fn to_f64(self) -> f64 {
        self as f64
    }
    #[inline(always)]
    fn exp(self) -> Self {
        libm::expf(self)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        libm::sqrtf(self)
    }
    #[inline(always)]
    fn abs(self) -> Self {
        libm::fabsf(self)
    }
    #[inline(always)]
    fn max(self, other: Self) -> Self {
        f32::max(self, other)
    }
    #[inline(always)]
    fn min(self, other: Self) -> Self {
        f32::min(self, other)
    }
    #[inline(always)]
    fn clamp(self, lo: Self, hi: Self) -> Self {
        f32::clamp(self, lo, hi)
    }
    #[inline(always)]
    fn bits(self) -> u64 {
        self.to_bits() as u64
    }
    #[inline(always)]
    fn powi(self, n: i32) -> Self {
        powi_by_squaring(self, n)
    }
    #[inline(always)]
    fn is_finite(self) -> bool {
        f32::is_finite(self)
    }
    #[inline(always)]
    fn ceil(self) -> Self {
        libm::ceilf(self)
    }
    #[inline(always)]
    fn of_usize(n: usize) -> Self {
        n as f32
    }
    #[inline(always)]
    fn to_usize(self) -> usize {
        self as usize
    }
}
