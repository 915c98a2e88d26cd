//! The RHONN identifier's right-hand side on slices, the one place it is written: the
//! host library's identifier (integrated with a plant by the event-locating solver, or
//! sample by sample by the `online` module) and a target's fixed-size identifier
//! (`online_fixed`) evaluate it here.
//!
//! A neuron `i` has the states `[x_i, w_i, law states]` (filtered error: `dx_i = -a_i x_i
//! + w_i^T z`, the regressor phi = z) or `[zeta_i, w_i, law states]` (filtered regressor:
//! `dzeta_i = -a_i zeta_i + z`, `x_i = w_i^T zeta_i`, phi = zeta); the weights follow a
//! [`NeuronLaw`], with the sigma laws' robust term ([`crate::law::modify`]) on top.

use crate::law::{self, dot, Gain, Zone};
use crate::{Real, Sigmoid};

/// How the identifier runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mode {
    /// Weights adapt; z from the measured states.
    Train,
    /// Weights frozen; z from the measured states (one-step tracking).
    SeriesParallel,
    /// Weights frozen; z from the model's own states (free run).
    Parallel,
}

impl Mode {
    /// Name used in summaries.
    pub fn name(self) -> &'static str {
        match self {
            Mode::Train => "training",
            Mode::SeriesParallel => "series-parallel",
            Mode::Parallel => "parallel",
        }
    }
}

/// How a neuron's regressor and model state are formed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Structure {
    /// States \[x_i, w_i, law states\]: `dx_i = -a_i x_i + w_i^T z`, phi = z.
    FilteredError,
    /// States \[zeta_i, w_i, law states\]: `dzeta_i = -a_i zeta_i + z`,
    /// `x_i = w_i^T zeta_i`, phi = zeta.
    FilteredRegressor,
}

/// Robust modification of a gradient law (the sigma laws).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Robust {
    /// None.
    None,
    /// Switching sigma-modification.
    Switching,
    /// Smooth three-case variant.
    Smooth,
}

/// The high-order terms, borrowed: term `k`'s factors are `idx[offsets[k]..offsets[k +
/// 1]]` with exponents `exp[...]` ([`crate::terms::eval`]).
#[derive(Debug, Clone, Copy)]
pub struct Terms<'a> {
    /// `L + 1` offsets into `idx` and `exp`.
    pub offsets: &'a [usize],
    /// Factor indices into y (the sigmoids of the states, then the inputs).
    pub idx: &'a [usize],
    /// Factor exponents.
    pub exp: &'a [i32],
}

impl Terms<'_> {
    /// Number of terms L.
    #[inline]
    pub fn len(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    /// Whether there is no term.
    #[inline]
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// The network, borrowed: `n` neurons, `m` inputs, the sigmoid of the scaled states,
/// the scaled inputs, the terms and the poles.
#[derive(Debug, Clone, Copy)]
pub struct Net<'a, T> {
    /// Neurons (identified states).
    pub n: usize,
    /// Inputs.
    pub m: usize,
    /// The sigmoid.
    pub sigmoid: Sigmoid,
    /// The state `i` enters the sigmoid as `chi_i / state_scale[i]`.
    pub state_scale: &'a [T],
    /// The input `j` enters as `u_j / input_scale[j]`.
    pub input_scale: &'a [T],
    /// The terms.
    pub terms: Terms<'a>,
    /// Poles a_i \[1/s\].
    pub a: &'a [T],
}

impl<T: Real> Net<'_, T> {
    /// `y` (sigmoids of the scaled states `chi`, scaled inputs `u`) and the terms `z`.
    #[inline]
    pub fn regressor(&self, chi: &[T], u: &[T], y: &mut [T], z: &mut [T]) {
        for i in 0..self.n {
            y[i] = self.sigmoid.eval_in(self.scaled_state(i, chi[i]));
        }
        for j in 0..self.m {
            y[self.n + j] = u[j] / self.input_scale[j];
        }
        let t = &self.terms;
        crate::terms::eval(t.offsets, t.idx, t.exp, &y[..self.n + self.m], z);
    }

    /// `v / state_scale[i]`, without the division for a unit scale (the same result,
    /// faster).
    #[inline(always)]
    pub fn scaled_state(&self, i: usize, v: T) -> T {
        let s = self.state_scale[i];
        if s == T::of(1.0) {
            v
        } else {
            v / s
        }
    }

    /// Terms per neuron L.
    #[inline]
    pub fn n_terms(&self) -> usize {
        self.terms.len()
    }
}

/// A learning law as the identifier calls it, neuron by neuron (the host library's laws
/// implement it; [`ScalarGradient`] is a fixed-size one for targets).
pub trait NeuronLaw<T: Real> {
    /// States per neuron besides the weights, for `l` regressor terms.
    fn law_states(&self, _l: usize) -> usize {
        0
    }
    /// Continuous time: `dw/dt` and the law states' derivative, from the regressor `phi`
    /// and the error `e = estimate - measurement` (`work`: scratch of `phi`'s length).
    #[allow(clippy::too_many_arguments)]
    fn derivative(
        &self,
        neuron: usize,
        phi: &[T],
        e: T,
        states: &[T],
        dw: &mut [T],
        dstates: &mut [T],
        work: &mut [T],
    );
    /// The neuron's gain, for a gradient law (the sigma laws need it), or None.
    fn gain(&self, neuron: usize) -> Option<Gain<'_, T>>;
    /// A bound on the size of the neuron's gain (a scalar gain, the sum of a gain
    /// matrix's absolute entries, the trace of a covariance in `states`): with
    /// `|z|^2` it bounds the weights' fastest motion, `sqrt(rate |z|^2)`.
    fn rate(&self, neuron: usize, states: &[T], l: usize) -> T;
}

/// The gradient law `dw_i = -g_i phi e_i` with one scalar gain per neuron (at most `C`
/// neurons).
#[derive(Debug, Clone, Copy)]
pub struct ScalarGradient<T, const C: usize>(pub [T; C]);

impl<T: Real, const C: usize> NeuronLaw<T> for ScalarGradient<T, C> {
    #[inline]
    fn derivative(&self, i: usize, phi: &[T], e: T, _s: &[T], dw: &mut [T], _ds: &mut [T], _work: &mut [T]) {
        law::descend(self.0[i], phi, e, dw)
    }
    fn gain(&self, i: usize) -> Option<Gain<'_, T>> {
        Some(Gain::Scalar(self.0[i]))
    }
    fn rate(&self, i: usize, _s: &[T], _l: usize) -> T {
        self.0[i]
    }
}

/// Work space of one evaluation, borrowed: `xhat` (n), `y` (n + m), `z`, `q`, `r` (L).
#[derive(Debug)]
pub struct Work<'a, T> {
    /// The model's estimates.
    pub xhat: &'a mut [T],
    /// Sigmoids of the states and the scaled inputs.
    pub y: &'a mut [T],
    /// The regressor (left there by the last evaluation).
    pub z: &'a mut [T],
    /// A law's work.
    pub q: &'a mut [T],
    /// The robust term's work.
    pub r: &'a mut [T],
}

/// A network, its law and its mode, borrowed; knows the layout of its states (`n`
/// blocks of [`Ident::block`]).
#[derive(Debug, Clone, Copy)]
pub struct Ident<'a, T, L> {
    /// Structure.
    pub net: Net<'a, T>,
    /// The weights' law.
    pub law: &'a L,
    /// How the regressor is formed.
    pub structure: Structure,
    /// Robust modification (gradient laws).
    pub robust: Robust,
    /// Radii M_i (robust laws).
    pub radius: &'a [T],
    /// Leakages sigma_i (robust laws).
    pub sigma: &'a [T],
    /// Mode.
    pub mode: Mode,
}

impl<T: Real, L: NeuronLaw<T>> Ident<'_, T, L> {
    /// States per neuron.
    #[inline]
    pub fn block(&self) -> usize {
        let l = self.net.n_terms();
        self.w_off() + l + self.law.law_states(l)
    }

    /// Number of identifier states.
    #[inline]
    pub fn dim(&self) -> usize {
        self.net.n * self.block()
    }

    /// Offset of neuron i's weights in its block (after x_i or zeta_i).
    #[inline]
    pub fn w_off(&self) -> usize {
        match self.structure {
            Structure::FilteredError => 1,
            Structure::FilteredRegressor => self.net.n_terms(),
        }
    }

    /// The model's estimates x_hat (one per neuron) from the identifier state.
    #[inline]
    pub fn outputs(&self, s: &[T], xhat: &mut [T]) {
        let (l, b) = (self.net.n_terms(), self.block());
        for (i, xh) in xhat.iter_mut().enumerate().take(self.net.n) {
            let blk = &s[i * b..(i + 1) * b];
            *xh = match self.structure {
                Structure::FilteredError => blk[0],
                Structure::FilteredRegressor => dot(&blk[..l], &blk[l..2 * l]),
            };
        }
    }

    /// Neuron i's weights in the state `s`.
    #[inline]
    pub fn weights<'s>(&self, i: usize, s: &'s [T]) -> &'s [T] {
        let (l, b, wo) = (self.net.n_terms(), self.block(), self.w_off());
        &s[i * b + wo..i * b + wo + l]
    }

    /// `|w_i|^2`.
    #[inline]
    pub fn norm2(&self, i: usize, s: &[T]) -> T {
        let w = self.weights(i, s);
        dot(w, w)
    }

    /// The derivative of the identifier state `s` given the measured states `chi`, the
    /// inputs `u` and each neuron's [`Zone`] (no allocation). With `same_regressor`, the
    /// regressor z of the previous evaluation (left in `work.z`) is used again (valid when
    /// z did not change: z from held measurements and held inputs, not in a free run),
    /// which saves its sigmoids and products.
    #[allow(clippy::too_many_arguments)]
    pub fn rhs_general(
        &self,
        chi: &[T],
        u: &[T],
        s: &[T],
        ds: &mut [T],
        zones: &[Zone],
        work: &mut Work<'_, T>,
        same_regressor: bool,
    ) {
        let (n, l, b) = (self.net.n, self.net.n_terms(), self.block());
        self.outputs(s, &mut work.xhat[..n]);
        if !same_regressor || self.mode == Mode::Parallel {
            let src: &[T] = if self.mode == Mode::Parallel {
                &work.xhat[..n]
            } else {
                chi
            };
            self.net.regressor(src, u, work.y, work.z);
        }
        let z = &work.z[..l];
        let train = self.mode == Mode::Train;
        for i in 0..n {
            let blk = &s[i * b..(i + 1) * b];
            let dblk = &mut ds[i * b..(i + 1) * b];
            let a = self.net.a[i];
            let e = work.xhat[i] - chi[i];
            let wo = self.w_off();
            let (lead, rest) = dblk.split_at_mut(wo);
            let (dw, dlaw) = rest.split_at_mut(l);
            let phi = match self.structure {
                Structure::FilteredError => {
                    lead[0] = -a * blk[0] + dot(&blk[1..1 + l], z);
                    z
                }
                Structure::FilteredRegressor => {
                    for k in 0..l {
                        lead[k] = -a * blk[k] + z[k];
                    }
                    &blk[..l]
                }
            };
            if !train {
                dw.iter_mut().for_each(|v| *v = T::default());
                dlaw.iter_mut().for_each(|v| *v = T::default());
                continue;
            }
            let w = &blk[wo..wo + l];
            self.law
                .derivative(i, phi, e, &blk[wo + l..], dw, dlaw, &mut work.q[..l]);
            if let (Robust::Switching | Robust::Smooth, Some(gain)) = (self.robust, self.law.gain(i)) {
                law::modify(zones[i], gain, self.sigma[i], w, dw, &mut work.r[..l]);
            }
        }
    }

    /// `w^T Gamma z e` and `w^T Gamma w` for neuron i (a filtered-error law's).
    pub fn robust_terms(&self, i: usize, chi: &[T], u: &[T], s: &[T], work: &mut Work<'_, T>) -> (T, T) {
        let (n, l, b) = (self.net.n, self.net.n_terms(), self.block());
        self.outputs(s, &mut work.xhat[..n]);
        self.net.regressor(chi, u, work.y, work.z);
        let w = &s[i * b + 1..i * b + 1 + l];
        let e = work.xhat[i] - chi[i];
        let gain = self.law.gain(i).unwrap_or(Gain::Scalar(T::of(1.0)));
        gain.apply(&work.z[..l], &mut work.q[..l]);
        gain.apply(w, &mut work.r[..l]);
        (dot(w, &work.q[..l]) * e, dot(w, &work.r[..l]))
    }

    /// Choose each neuron's zone at the start of an interval (robust laws in training;
    /// otherwise the zones stay).
    pub fn update_zones(&self, chi: &[T], u: &[T], s: &[T], zones: &mut [Zone], work: &mut Work<'_, T>) {
        if self.robust == Robust::None || self.mode != Mode::Train {
            return;
        }
        for (i, zone) in zones.iter_mut().enumerate().take(self.net.n) {
            let r2 = self.norm2(i, s);
            let (m, sig) = (self.radius[i], self.sigma[i]);
            *zone = law::zone(r2, m, sig, || self.robust_terms(i, chi, u, s, work));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_filtered_error_neuron_descends_its_error_and_a_frozen_one_keeps_its_weights() {
        // One neuron, one input, terms z = [s(chi), u]; chi = 0.5, u = 2, x_hat = 1.
        let (offsets, idx, exp) = ([0, 1, 2], [0, 1], [1, 1]);
        let net = Net {
            n: 1,
            m: 1,
            sigmoid: Sigmoid::TANH,
            state_scale: &[1.0],
            input_scale: &[1.0],
            terms: Terms {
                offsets: &offsets,
                idx: &idx,
                exp: &exp,
            },
            a: &[3.0],
        };
        let mut id = Ident {
            net,
            law: &ScalarGradient([0.5]),
            structure: Structure::FilteredError,
            robust: Robust::None,
            radius: &[],
            sigma: &[],
            mode: Mode::Train,
        };
        let s = [1.0, 0.2, -0.1];
        let (mut xhat, mut y, mut z, mut q, mut r) = ([0.0; 1], [0.0; 2], [0.0; 2], [0.0; 2], [0.0; 2]);
        let mut work = Work {
            xhat: &mut xhat,
            y: &mut y,
            z: &mut z,
            q: &mut q,
            r: &mut r,
        };
        let mut ds = [0.0; 3];
        id.rhs_general(&[0.5], &[2.0], &s, &mut ds, &[Zone::Inside], &mut work, false);
        let z0 = libm::tanh(0.5);
        assert!((ds[0] - (-3.0 + 0.2 * z0 - 0.2)).abs() < 1e-15, "{ds:?}");
        // e = 0.5: dw = -0.5 z e
        assert!(
            (ds[1] + 0.25 * z0).abs() < 1e-15 && (ds[2] + 0.5).abs() < 1e-15,
            "{ds:?}"
        );
        id.mode = Mode::SeriesParallel;
        id.rhs_general(&[0.5], &[2.0], &s, &mut ds, &[Zone::Inside], &mut work, true);
        assert_eq!(&ds[1..], &[0.0, 0.0]);
    }
}
