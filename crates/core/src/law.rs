//! The learning laws' steps on slices, the one place each is written: the host
//! library's laws (`rhonn::law`), its identifier, `rhonn fit`'s sampled estimators and
//! both adaptive controllers call these.
//!
//! * The gradient law `dw/dt = -g phi e` (Kosmatopoulos et al. 1995; the thesis's eq.
//!   4.7 with phi = z, its filtered-regressor variant with phi = zeta): [`descend`].
//! * Sampled, the normalised step `w -= g phi e / (1 + phi^T phi)` (Ioannou & Sun 1996,
//!   section 4.11), stable for any regressor size: [`normalized_step`].
//! * Projection onto a ball (Ioannou & Sun 1996, section 4.10.3): [`project`].

use crate::Real;

/// `dw = -g phi e` for a scalar gain `g`: the one place this product is written (the
/// identifier's fast paths and the adaptive controllers' neurons call it, so their
/// results stay those of the general law bit for bit).
#[inline(always)]
pub fn descend<T: Real>(g: T, phi: &[T], e: T, dw: &mut [T]) {
    for (d, p) in dw.iter_mut().zip(phi) {
        *d = -(g * *p * e);
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
