//! The learning laws' steps on slices, the one place each is written: the host
//! library's laws (`rhonn::law`), its identifier, `rhonn fit`'s sampled estimators and
//! both adaptive controllers call these.
//!
//! * The gradient law `dw/dt = -g phi e` (Kosmatopoulos et al. 1995; the thesis's eq.
//!   4.7 with phi = z, its filtered-regressor variant with phi = zeta): [`descend`].
//! * Sampled, the normalised step `w -= g phi e / (1 + phi^T phi)` (Ioannou & Sun 1996,
//!   section 4.11), stable for any regressor size: [`normalized_step`].
//! * Projection onto a ball (Ioannou & Sun 1996, section 4.10.3): [`project`].
//! * With a gain matrix: [`Gain`] (borrowed), [`descend_with`], [`normalized_step_with`].
//! * Least squares (Ioannou & Sun 1996, section 4.3.6): the covariance law
//!   [`least_squares_derivative`] and recursive least squares [`least_squares_step`].
//! * The robust modifications of the sigma laws: [`zone`] and [`modify`].

use crate::Real;

/// `sum a_i b_i` over slices.
#[inline]
pub fn dot<T: Real>(a: &[T], b: &[T]) -> T {
    a.iter().zip(b).map(|(x, y)| *x * *y).sum()
}

/// A learning gain, borrowed: `gamma I`, or a row-major `L x L` symmetric positive
/// definite matrix.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Gain<'a, T> {
    /// gamma I.
    Scalar(T),
    /// Row-major L x L.
    Matrix(&'a [T]),
}

impl<T: Real> Gain<'_, T> {
    /// `out = Gain v`.
    #[inline]
    pub fn apply(&self, v: &[T], out: &mut [T]) {
        match self {
            Gain::Scalar(g) => {
                for (o, x) in out.iter_mut().zip(v) {
                    *o = *g * *x;
                }
            }
            Gain::Matrix(m) => {
                let l = v.len();
                for r in 0..l {
                    out[r] = (0..l).map(|c| m[r * l + c] * v[c]).sum();
                }
            }
        }
    }
}

/// `dw = -g phi e` for a scalar gain `g`: the one place this product is written (the
/// identifier's fast paths and the adaptive controllers' neurons call it, so their
/// results stay those of the general law bit for bit).
#[inline(always)]
pub fn descend<T: Real>(g: T, phi: &[T], e: T, dw: &mut [T]) {
    for (d, p) in dw.iter_mut().zip(phi) {
        *d = -(g * *p * e);
    }
}

/// `dw = -Gamma phi e` for any gain (`work` holds `Gamma phi`, at least `phi.len()`).
#[inline]
pub fn descend_with<T: Real>(gain: Gain<'_, T>, phi: &[T], e: T, dw: &mut [T], work: &mut [T]) {
    match gain {
        Gain::Scalar(g) => descend(g, phi, e, dw),
        gain => {
            let q = &mut work[..phi.len()];
            gain.apply(phi, q);
            for (d, q) in dw.iter_mut().zip(q.iter()) {
                *d = -(*q * e);
            }
        }
    }
}

/// The sampled, normalised gradient step for any gain:
/// `w -= Gamma phi e / (1 + phi^T phi)` (`work` as in [`descend_with`]).
#[inline]
pub fn normalized_step_with<T: Real>(gain: Gain<'_, T>, phi: &[T], e: T, w: &mut [T], work: &mut [T]) {
    match gain {
        Gain::Scalar(g) => normalized_step(g, phi, e, w),
        gain => {
            let norm = normalisation(phi);
            let q = &mut work[..phi.len()];
            gain.apply(phi, q);
            for (w, q) in w.iter_mut().zip(q.iter()) {
                *w -= *q * e / norm;
            }
        }
    }
}

/// `q = P phi` for a row-major `L x L` covariance `P`.
#[inline]
fn times<T: Real>(p: &[T], phi: &[T], q: &mut [T]) {
    let l = phi.len();
    for (r, q) in q.iter_mut().enumerate().take(l) {
        *q = dot(&p[r * l..(r + 1) * l], phi);
    }
}

/// The least-squares law `dw/dt = -P phi e`, `dP/dt = -P phi phi^T P`, the covariance
/// held (dP = 0) while `trace P <= floor L` so the law keeps adapting (`work`: `L`).
#[inline]
pub fn least_squares_derivative<T: Real>(
    phi: &[T],
    e: T,
    p: &[T],
    floor: T,
    dw: &mut [T],
    dp: &mut [T],
    work: &mut [T],
) {
    let l = phi.len();
    let q = &mut work[..l];
    times(p, phi, q);
    for k in 0..l {
        dw[k] = -q[k] * e;
    }
    let trace: T = (0..l).map(|k| p[k * l + k]).sum();
    let shrink = trace > floor * T::of(l as f64);
    for r in 0..l {
        for c in 0..l {
            dp[r * l + c] = if shrink { -q[r] * q[c] } else { T::default() };
        }
    }
}

/// Recursive least squares: `q = P phi`, `w -= q e / (1 + phi^T q)`,
/// `P -= q q^T / (1 + phi^T q)` (`work`: `L`).
#[inline]
pub fn least_squares_step<T: Real>(phi: &[T], e: T, w: &mut [T], p: &mut [T], work: &mut [T]) {
    let l = phi.len();
    let q = &mut work[..l];
    // q = P phi, as phi^T P (P is symmetric): rows of P scaled and summed, which runs in
    // independent lanes where a row-by-row dot product waits on each addition.
    q.fill(T::of(0.0));
    for (row, &f) in p.chunks_exact(l).zip(phi) {
        for (qc, &pc) in q.iter_mut().zip(row) {
            *qc += f * pc;
        }
    }
    let den = T::of(1.0) + dot(phi, q);
    for k in 0..l {
        w[k] -= q[k] * (e / den);
    }
    // Row by row with the division hoisted out of the inner loop (the rank-one update
    // is the whole cost of a step: l^2 multiply-adds).
    for (row, &qr) in p.chunks_exact_mut(l).zip(q.iter()) {
        let a = qr / den;
        for (pc, &qc) in row.iter_mut().zip(q.iter()) {
            *pc -= a * qc;
        }
    }
}

/// Where a neuron's weight vector is relative to its radius M.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Zone {
    /// `|w| < M`: the plain gradient law.
    Inside,
    /// `|w| = M`: sliding on the sphere.
    Sphere,
    /// `|w| > M`: the gradient law plus the leakage.
    Outside,
}

/// The zone of a weight with `|w|^2 = r2` and radius `m`, where `g = w^T Gamma phi e`
/// and `wgw = w^T Gamma w` (only evaluated on the surface). Both robust laws decide alike
/// on the surface |w| = M: inside when the gradient points in, sliding on the sphere
/// while the leakage would push back harder than the gradient pushes out, outside
/// otherwise. For the switching law this is its Filippov solution (an event-located
/// solver must slide there, or it chatters), which coincides with the smooth law; off
/// the surface the two laws are the thesis's eq. 4.9 as written.
pub fn zone<T: Real>(r2: T, m: T, sigma: T, on_surface: impl FnOnce() -> (T, T)) -> Zone {
    let m2 = m * m;
    if r2 < m2 * (T::of(1.0) - T::of(1e-9)) {
        Zone::Inside
    } else if r2 > m2 * (T::of(1.0) + T::of(1e-6)) {
        Zone::Outside
    } else {
        let (g, wgw) = on_surface();
        if g > T::default() {
            Zone::Inside
        } else if g >= -sigma * wgw {
            Zone::Sphere
        } else {
            Zone::Outside
        }
    }
}

/// Add the robust term of `zone` to a gradient step `dw = -Gamma phi e` (given), with
/// `work` of the weights' length.
pub fn modify<T: Real>(zone: Zone, gain: Gain<'_, T>, sigma: T, w: &[T], dw: &mut [T], work: &mut [T]) {
    let l = w.len();
    match zone {
        Zone::Inside => {}
        Zone::Outside => {
            gain.apply(w, &mut work[..l]);
            for k in 0..l {
                dw[k] -= sigma * work[k];
            }
        }
        Zone::Sphere => {
            gain.apply(w, &mut work[..l]);
            let g = -dot(w, dw);
            let wgw = dot(w, &work[..l]);
            if wgw > T::default() {
                for k in 0..l {
                    dw[k] += g / wgw * work[k];
                }
            }
        }
    }
}

/// `1 + phi^T phi`, the sampled gradient step's normalisation.
#[inline]
pub fn normalisation<T: Real>(phi: &[T]) -> T {
    T::of(1.0) + phi.iter().map(|p| *p * *p).sum::<T>()
}

/// The sampled, normalised gradient step with a scalar gain:
/// `w -= g phi e / (1 + phi^T phi)`.
#[inline]
pub fn normalized_step<T: Real>(g: T, phi: &[T], e: T, w: &mut [T]) {
    let c = g * e / normalisation(phi);
    for (w, p) in w.iter_mut().zip(phi) {
        *w -= *p * c;
    }
}

/// Project `v` onto the ball of `radius` around `c` (after each step a vector outside
/// it is put back on its surface along the ray from `c`); true when it had to.
#[inline]
pub fn project<T: Real>(v: &mut [T], c: &[T], radius: T) -> bool {
    let d2: T = v.iter().zip(c).map(|(a, b)| (*a - *b) * (*a - *b)).sum();
    if d2 <= radius * radius {
        return false;
    }
    let k = radius / d2.sqrt();
    for (a, b) in v.iter_mut().zip(c) {
        *a = *b + (*a - *b) * k;
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn projection_lands_on_the_sphere_and_leaves_the_inside_alone() {
        let mut v = [3.0, 4.0];
        assert!(project(&mut v, &[0.0, 0.0], 1.0));
        assert!((libm::sqrt(v[0] * v[0] + v[1] * v[1]) - 1.0).abs() < 1e-15);
        let mut inside = [0.3, -0.4];
        assert!(!project(&mut inside, &[0.0, 0.0], 1.0));
        assert_eq!(inside, [0.3, -0.4]);
        let mut u = [2.0, 1.0];
        assert!(project(&mut u, &[1.0, 1.0], 0.5));
        assert_eq!(u, [1.5, 1.0]);
    }

    #[test]
    fn the_sampled_step_shrinks_the_error_and_descend_points_downhill() {
        let phi = [1.0, -2.0, 0.5];
        let target = [0.3, 0.1, -0.4];
        let y: f64 = phi.iter().zip(&target).map(|(a, b)| a * b).sum();
        let mut w = [0.0; 3];
        let mut last = f64::INFINITY;
        for _ in 0..50 {
            let e: f64 = phi.iter().zip(&w).map(|(a, b)| a * b).sum::<f64>() - y;
            assert!(e.abs() < last || e == 0.0, "{e} after {last}");
            last = e.abs();
            normalized_step(0.5, &phi, e, &mut w);
        }
        assert!(last < 1e-6, "{last}");
        let mut dw = [0.0; 3];
        descend(0.5, &phi, 2.0, &mut dw);
        let descent: f64 = dw.iter().zip(&phi).map(|(d, p)| d * p * 2.0).sum();
        assert!(descent < 0.0);
    }
}
