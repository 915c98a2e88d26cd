//! A general online identifier in fixed-size arrays, for a target without an allocator:
//! [`FixedOnline`] owns every buffer (capacity `S` for a buffer per signal, `C` for the
//! state, the terms and their factors) and runs the update of
//! [`crate::online`], the same code the host library's `OnlineIdentifier` runs.
//!
//! Its structure is the host's `rhonn identify` default: one neuron per output, the
//! regressor every monomial up to `degree` (at most `max_factors` distinct factors) of
//! tanh of the normalised outputs (unless `output_terms` is off), the normalised inputs
//! and their first-order filters, plus a constant ([`online_terms`]); the filtered-error
//! law with the scalar gain `gain / (T L)` ([`crate::ident::ScalarGradient`]), or its
//! sigma-modified variants with a radius per neuron.
//!
//! ```
//! use rhonn_core::online::{InputHold, Scaling};
//! use rhonn_core::online_fixed::{FixedOnline, FixedSpec};
//! // y' = -y + u + 0.5 u tanh(y), sampled every 50 ms, the input switching every second.
//! let mut id = FixedOnline::<f32, 8, 16>::empty();
//! id.configure(&FixedSpec {
//!     filters_s: &[],
//!     degree: 2,
//!     max_factors: 2,
//!     output_terms: true,
//!     a_per_s: Some(1.0),
//!     gain: 0.5,
//!     dead_zone: &[0.0],
//!     hold: InputHold::Hold,
//!     period_s: 0.05,
//!     scaling: Scaling { y_offset: &[0.0], y_scale: &[1.0], u_offset: &[0.0], u_scale: &[1.0], y_bounds: None },
//!     robust: None,
//! })
//! .unwrap();
//! let (mut y, mut u, mut seed) = (0.0f32, 0.0f32, 7u32);
//! let (mut early, mut late) = (0.0, 0.0);
//! for k in 0..20_000 {
//!     if k % 20 == 0 {
//!         seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
//!         u = (seed >> 8) as f32 / (1u32 << 24) as f32 * 2.0 - 1.0;
//!     }
//!     let y_hat = id.update(k as f32 * 0.05, &[u], &[y]).unwrap()[0]; // before seeing y
//!     let e2 = (y_hat - y) * (y_hat - y);
//!     if k < 400 { early += e2 } else if k >= 19_600 { late += e2 }
//!     for _ in 0..50 {
//!         y += 0.001 * (-y + u + 0.5 * u * libm::tanhf(y));
//!     }
//! }
//! assert!(late < 0.2 * early, "the estimate error shrinks: {early} -> {late}");
//! ```

use crate::ident::{Ident, Mode, Net, Robust, ScalarGradient, Structure, Terms, Work};
use crate::law::Zone;
use crate::online::{Buffers, InputHold, Online, Scaling, Settings, Status, UpdateError};
use crate::{Real, Sigmoid};

/// The terms of an online identifier of `ny` outputs from `nu` inputs with `nf` filters
/// each (the network's inputs are `nu (1 + nf)` signals and a constant 1, after the
/// `ny` outputs' sigmoids): every monomial of degree 1 to `degree` of the outputs
/// (with `output_terms`), the inputs and the filters, then the constant term.
/// `factor(Some((index, exponent)))` for each factor, `factor(None)` at each term's end;
/// `cur`: scratch, one entry per signal (`ny + nu (1 + nf)`, or without the outputs).
pub fn online_terms(
    (ny, nu, nf): (usize, usize, usize),
    output_terms: bool,
    degree: usize,
    max_factors: usize,
    cur: &mut [usize],
    mut factor: impl FnMut(Option<(usize, i32)>),
) {
    let first = if output_terms { 0 } else { ny };
    let m = nu * (1 + nf) + 1;
    let signals = ny + m - 1 - first;
    // The constant takes no part in products, which it would only duplicate.
    crate::terms::for_each_monomial(degree, max_factors, &mut cur[..signals], |e| {
        for (j, &d) in e.iter().enumerate() {
            if d > 0 {
                factor(Some((j + first, d as i32)));
            }
        }
        factor(None);
    });
    factor(Some((ny + m - 1, 1)));
    factor(None);
}

/// What a [`FixedOnline`] is built from (the host's `OnlineSpec` keys, and the scaling).
#[derive(Debug, Clone, Copy)]
pub struct FixedSpec<'a, T> {
    /// Time constants \[s\] of each input's filters.
    pub filters_s: &'a [T],
    /// Degree of the terms (1 to 4).
    pub degree: usize,
    /// Most distinct factors per term.
    pub max_factors: usize,
    /// Whether the outputs' sigmoids enter the terms.
    pub output_terms: bool,
    /// The neuron pole a \[1/s\] (none: 1 / (10 T)).
    pub a_per_s: Option<T>,
    /// The law's step: gamma = gain / (T L).
    pub gain: T,
    /// Errors below this (output units), one per output, do not adapt.
    pub dead_zone: &'a [T],
    /// Inputs held or linear between samples.
    pub hold: InputHold,
    /// The sample time T \[s\].
    pub period_s: T,
    /// Offsets and scales (their lengths give the outputs and the inputs).
    pub scaling: Scaling<'a, T>,
    /// The sigma laws' modification, with a radius and a leakage per output (none: the
    /// plain filtered-error law).
    pub robust: Option<(Robust, &'a [T], &'a [T])>,
}

/// Why a [`FixedSpec`] cannot be built.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SpecError {
    /// A buffer would need this many entries, more than its capacity (`S` for the
    /// signals, outputs and network inputs; `C` for the state, terms and factors).
    Capacity(usize),
    /// The named field is refused: no output or no input (`scaling`), a degree outside 1
    /// to 4, `max_factors` outside 1 to the degree, lists of the wrong length, or a scale,
    /// sample time, gain, pole, filter or radius that is not a finite number > 0.
    Invalid(&'static str),
}

/// A general online identifier in arrays of capacities `S` (at least the outputs plus the
/// network's inputs, `ny + nu (1 + filters) + 1`) and `C` (at least the state `ny (1 +
/// L)`, the terms plus one and their factors): see the module docs.
#[derive(Debug, Clone)]
pub struct FixedOnline<T, const S: usize, const C: usize> {
    ny: usize,
    nu: usize,
    m: usize,
    l: usize,
    nf: usize,
    factors: usize,
    offsets: [usize; C],
    idx: [usize; C],
    exp: [i32; C],
    a: [T; S],
    ones: [T; S],
    gains: ScalarGradient<T, S>,
    robust: Robust,
    radius: [T; S],
    sigma: [T; S],
    zones: [Zone; S],
    scaling: [[T; S]; 4],
    bounds: Option<[[T; 2]; S]>,
    filters_s: [T; S],
    dead_zone: [T; S],
    hold: InputHold,
    period_s: T,
    state: [T; C],
    k: [T; C],
    acc: [T; C],
    tmp: [T; C],
    /// y_last, u_last, yn, u_now, u_mid, y_hat, xhat, y.
    sig: [[T; S]; 8],
    /// z, q, r.
    terms: [[T; C]; 3],
    status: Status<T>,
}

fn positive<T: Real>(v: &[T]) -> bool {
    v.iter().all(|x| x.to_f64().is_finite() && *x > T::default())
}

impl<T: Real, const S: usize, const C: usize> FixedOnline<T, S, C> {
    /// Build from `spec`; every buffer must fit.
    pub fn new(spec: &FixedSpec<'_, T>) -> Result<Self, SpecError> {
        let mut id = Self::empty();
        id.configure(spec)?;
        Ok(id)
    }

    /// An identifier of nothing yet, to [`FixedOnline::configure`] where it lives (a
    /// target then holds one copy, not the several that moving a returned value can
    /// leave on its stack).
    pub fn empty() -> Self {
        FixedOnline {
            ny: 0,
            nu: 0,
            m: 0,
            l: 0,
            nf: 0,
            factors: 0,
            offsets: [0; C],
            idx: [0; C],
            exp: [0; C],
            a: [T::default(); S],
            ones: [T::of(1.0); S],
            gains: ScalarGradient([T::default(); S]),
            robust: Robust::None,
            radius: [T::default(); S],
            sigma: [T::default(); S],
            zones: [Zone::Inside; S],
            scaling: [[T::default(); S]; 4],
            bounds: None,
            filters_s: [T::default(); S],
            dead_zone: [T::default(); S],
            hold: InputHold::Hold,
            period_s: T::default(),
            state: [T::default(); C],
            k: [T::default(); C],
            acc: [T::default(); C],
            tmp: [T::default(); C],
            sig: [[T::default(); S]; 8],
            terms: [[T::default(); C]; 3],
            status: Status::default(),
        }
    }

    /// Set up for `spec` in place, from the start (weights 0, no last sample); on an
    /// error the identifier is left empty.
    pub fn configure(&mut self, spec: &FixedSpec<'_, T>) -> Result<(), SpecError> {
        let r = self.configure_checked(spec);
        if r.is_err() {
            self.ny = 0;
        }
        r
    }

    fn configure_checked(&mut self, spec: &FixedSpec<'_, T>) -> Result<(), SpecError> {
        let sc = &spec.scaling;
        let (ny, nu, nf) = (sc.y_scale.len(), sc.u_scale.len(), spec.filters_s.len());
        let checks = [
            (ny > 0 && nu > 0, "scaling (no output or no input)"),
            (
                sc.y_offset.len() == ny && sc.u_offset.len() == nu,
                "scaling offsets",
            ),
            (positive(sc.y_scale) && positive(sc.u_scale), "scaling scales"),
            (
                sc.y_bounds
                    .is_none_or(|b| b.len() == ny && b.iter().all(|[lo, hi]| lo < hi)),
                "scaling.y_bounds",
            ),
            (spec.dead_zone.len() == ny, "dead_zone"),
            (
                spec.robust
                    .is_none_or(|(_, m, s)| m.len() == ny && s.len() == ny && positive(m) && positive(s)),
                "robust (radius, leakage)",
            ),
            ((1..=4).contains(&spec.degree), "degree"),
            ((1..=spec.degree).contains(&spec.max_factors), "max_factors"),
            (positive(&[spec.period_s]), "period_s"),
            (positive(&[spec.gain]), "gain"),
            (positive(&[spec.a_per_s.unwrap_or(T::of(1.0))]), "a_per_s"),
            (positive(spec.filters_s), "filters_s"),
        ];
        if let Some((_, field)) = checks.iter().find(|(ok, _)| !ok) {
            return Err(SpecError::Invalid(field));
        }
        let m = nu * (1 + nf) + 1;
        let id = self;
        (id.ny, id.nu, id.m, id.nf, id.hold, id.period_s) = (ny, nu, m, nf, spec.hold, spec.period_s);
        id.robust = spec.robust.map_or(Robust::None, |r| r.0);
        id.zones = [Zone::Inside; S];
        id.state = [T::default(); C];
        id.status = Status::default();
        id.bounds = None;
        if ny + m > S {
            return Err(SpecError::Capacity(ny + m));
        }
        id.build_terms(spec)?;
        let (l, dim) = (id.l, ny * (1 + id.l));
        let need = [dim, id.factors, l + 1].into_iter().max().unwrap_or(0);
        if need > C {
            return Err(SpecError::Capacity(need));
        }
        let a = spec.a_per_s.unwrap_or(T::of(0.1) / spec.period_s);
        let gamma = spec.gain / (spec.period_s * T::of(l as f64));
        for i in 0..ny {
            id.a[i] = a;
            id.gains.0[i] = gamma;
            id.dead_zone[i] = spec.dead_zone[i] / sc.y_scale[i];
            if let Some((_, r, s)) = spec.robust {
                (id.radius[i], id.sigma[i]) = (r[i], s[i]);
            }
        }
        for (dst, src) in id
            .scaling
            .iter_mut()
            .zip([sc.y_offset, sc.y_scale, sc.u_offset, sc.u_scale])
        {
            dst[..src.len()].copy_from_slice(src);
        }
        if let Some(b) = sc.y_bounds {
            let mut bounds = [[T::default(); 2]; S];
            bounds[..ny].copy_from_slice(b);
            id.bounds = Some(bounds);
        }
        id.filters_s[..nf].copy_from_slice(spec.filters_s);
        Ok(())
    }

    /// The terms into `offsets`, `idx`, `exp` (an error past the capacity).
    fn build_terms(&mut self, spec: &FixedSpec<'_, T>) -> Result<(), SpecError> {
        let signals = self.ny + self.m - 1;
        let (mut l, mut f, mut over) = (0, 0, 0);
        let mut cur = [0usize; S];
        let dims = (self.ny, self.nu, self.nf);
        online_terms(
            dims,
            spec.output_terms,
            spec.degree,
            spec.max_factors,
            &mut cur[..signals],
            |x| match x {
                Some((j, d)) => {
                    if f < C {
                        (self.idx[f], self.exp[f]) = (j, d);
                    }
                    f += 1;
                }
                None => {
                    l += 1;
                    if l < C {
                        self.offsets[l] = f;
                    } else {
                        over = over.max(l + 1);
                    }
                }
            },
        );
        (self.l, self.factors) = (l, f);
        match over.max(f) {
            n if n > C => Err(SpecError::Capacity(n)),
            _ => Ok(()),
        }
    }

    /// Take the sample `(t, u, y)` and return the estimate of `y(t)` made before seeing
    /// `y` (see [`Online::update`]).
    pub fn update(&mut self, t: T, u: &[T], y: &[T]) -> Result<&[T], UpdateError<T>> {
        self.online().update(t, u, y)?;
        Ok(&self.sig[5][..self.ny])
    }

    /// Stop (`true`) or resume adapting the weights.
    pub fn freeze(&mut self, frozen: bool) {
        self.status.frozen = frozen;
    }

    /// Run free (`true`) or series-parallel.
    pub fn set_free_run(&mut self, free: bool) {
        self.status.free_run = free;
    }

    /// Forget the last sample (a new record starts); the weights stay.
    pub fn reset(&mut self) {
        self.status.t_last = None;
    }

    /// Neuron i's weights (none for a neuron it does not have).
    pub fn weights(&self, i: usize) -> &[T] {
        let b = 1 + self.l;
        if i < self.ny {
            &self.state[i * b + 1..(i + 1) * b]
        } else {
            &[]
        }
    }

    /// Terms per neuron L.
    pub fn n_terms(&self) -> usize {
        self.l
    }

    /// The identifier borrowed as [`Online`] runs it.
    fn online(&mut self) -> Online<'_, T, ScalarGradient<T, S>> {
        let (ny, nu, m, l) = (self.ny, self.nu, self.m, self.l);
        let dim = ny * (1 + l);
        let net = Net {
            n: ny,
            m,
            sigmoid: Sigmoid::TANH,
            state_scale: &self.ones[..ny],
            input_scale: &self.ones[..m],
            terms: Terms {
                offsets: &self.offsets[..l + 1],
                idx: &self.idx[..self.factors],
                exp: &self.exp[..self.factors],
            },
            a: &self.a[..ny],
        };
        let [y_off, y_sc, u_off, u_sc] = &self.scaling;
        let [y_last, u_last, yn, u_now, u_mid, y_hat, xhat, y] = &mut self.sig;
        let [z, q, r] = &mut self.terms;
        Online {
            ident: Ident {
                net,
                law: &self.gains,
                structure: Structure::FilteredError,
                robust: self.robust,
                radius: &self.radius[..ny],
                sigma: &self.sigma[..ny],
                mode: Mode::Train,
            },
            zones: &mut self.zones[..ny],
            settings: Settings {
                scaling: Scaling {
                    y_offset: &y_off[..ny],
                    y_scale: &y_sc[..ny],
                    u_offset: &u_off[..nu],
                    u_scale: &u_sc[..nu],
                    y_bounds: self.bounds.as_ref().map(|b| &b[..ny]),
                },
                hold: self.hold,
                filters_s: &self.filters_s[..self.nf],
                dead_zone: &self.dead_zone[..ny],
                period_s: self.period_s,
            },
            buf: Buffers {
                state: &mut self.state[..dim],
                k: &mut self.k[..dim],
                acc: &mut self.acc[..dim],
                tmp: &mut self.tmp[..dim],
                y_last: &mut y_last[..ny],
                u_last: &mut u_last[..m],
                yn: &mut yn[..ny],
                u_now: &mut u_now[..m],
                u_mid: &mut u_mid[..m],
                y_hat: &mut y_hat[..ny],
                work: Work {
                    xhat: &mut xhat[..ny],
                    y: &mut y[..ny + m],
                    z: &mut z[..l],
                    q: &mut q[..l],
                    r: &mut r[..l],
                },
            },
            status: &mut self.status,
        }
    }
}
