//! The part of rhonn that runs on a microcontroller: `#![no_std]`, no allocation,
//! fixed-size (const generic) states, `libm` for the maths.
//!
//! The host library (`rhonn`) uses these very functions and types for the same work (the
//! sigmoid, the learning laws' steps, the identifier's right-hand side and the online
//! identifier's update, the PI, the RHONN adaptive controller, the pump's equations), so
//! a controller or identifier designed and tested on the desktop is, bit for bit, the
//! one that runs on the target (`embedded/` runs them on an emulated Cortex-M4F and
//! compares every printed value with the host).
//!
//! One exception, by choice: with the `std` feature (the host library turns it on) the
//! sigmoid's `exp` is the platform's, faster than `libm`'s (thesis-ch5 4 % faster, and its
//! figures unchanged); results then agree with the target's within an ulp per `exp`.
//! Built without `std` (as `embedded/` does for its host reference) every result is the
//! target's bit for bit.
//!
//! The controller, the laws and the identifier are generic over [`Real`] (`f64`, or `f32` for a
//! single-precision FPU such as a Cortex-M4F's); the host library uses `f64`.
//!
//! Modules: [`sigmoid`] (`s(v) = a / (1 + exp(-b v)) - c`), [`terms`] (the high-order
//! terms `z_k = prod y_j^d_j`), [`law`] (the gradient step
//! `-g phi e`, its normalised sampled form, projection onto a ball), [`pi`] (PI with
//! anti-windup), [`adaptive`] (the affine RHONN neuron and the pump's RHONN adaptive
//! cascade), [`pump`] (the pump's pilot valve and line equations, and a fixed-step
//! discretisation for a plant on the target), [`ident`] (the identifier's right-hand
//! side for any structure and law), [`online`] (the online identifier's sample-by-sample
//! update on borrowed buffers), [`online_fixed`] (a general online identifier in
//! fixed-size arrays).
#![no_std]
#![deny(missing_docs)]

#[cfg(feature = "std")]
extern crate std;

pub mod actuator;
pub mod adaptive;
pub mod ident;
pub mod law;
pub mod online;
pub mod online_fixed;
pub mod pi;
pub mod pump;
pub mod real;
pub mod sigmoid;
pub mod terms;

pub use real::Real;
pub use sigmoid::Sigmoid;

/// `e^x`: the platform's with `std`, `libm`'s without (see the crate docs).
#[inline(always)]
pub fn exp(x: f64) -> f64 {
    #[cfg(feature = "std")]
    {
        x.exp()
    }
    #[cfg(not(feature = "std"))]
    {
        libm::exp(x)
    }
}

/// `sum a_i b_i` over fixed-size arrays.
#[inline]
pub fn dot<T: Real, const N: usize>(a: &[T; N], b: &[T; N]) -> T {
    a.iter().zip(b).map(|(x, y)| *x * *y).sum()
}

/// The guide's example of the online identifier on a target (docs/guides/embedded.md),
/// compiled and run by `cargo test --doc`.
#[cfg(doctest)]
#[doc = include_str!("../../../docs/guides/embedded.md")]
struct EmbeddedGuide;
