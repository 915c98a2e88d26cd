//! The robust modifications of the gradient law that keep weights bounded without
//! persistent excitation (thesis eq. 4.9 and the three-case law after it; Ioannou &
//! Sun 1996, section 8.4):
//! - *sigma-switching*: a leakage `-sigma_i Gamma_i w_i` while `|w_i| > M_i`;
//! - *smooth sigma*: on the sphere `|w_i| = M_i` the weight slides on it while
//!   `-sigma w^T Gamma w <= w^T Gamma phi e <= 0`.
//!
//! A neuron's weight is in one of three [`Zone`]s; the identifier locates the crossings
//! of `|w_i| = M_i` as solver events and decides the zone at each with [`zone`].

use super::gain::Gain;

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
pub fn zone(r2: f64, m: f64, sigma: f64, on_surface: impl FnOnce() -> (f64, f64)) -> Zone {
    let m2 = m * m;
    if r2 < m2 * (1.0 - 1e-9) {
        Zone::Inside
    } else if r2 > m2 * (1.0 + 1e-6) {
        Zone::Outside
    } else {
        let (g, wgw) = on_surface();
        if g > 0.0 {
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
pub fn modify(zone: Zone, gain: &Gain, sigma: f64, w: &[f64], dw: &mut [f64], work: &mut [f64]) {
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
            // w^T Gamma phi e = -w^T dw while dw is the plain gradient step.
            let g = -super::dot(w, dw);
            let wgw = super::dot(w, &work[..l]);
            if wgw > 0.0 {
                for k in 0..l {
                    dw[k] += g / wgw * work[k];
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn on_the_sphere_the_step_is_tangent_and_outside_it_points_back() {
        let gain = Gain::Scalar(2.0);
        let w = [0.6, 0.8];
        let mut dw = [-1.0, -0.5]; // an outward gradient step would be w . dw > 0; this one points in
        let mut work = [0.0; 2];
        let plain = dw;
        modify(Zone::Sphere, &gain, 0.1, &w, &mut dw, &mut work);
        assert!(crate::law::dot(&w, &dw).abs() < 1e-12, "{dw:?}");
        let mut out = plain;
        modify(Zone::Outside, &gain, 0.1, &w, &mut out, &mut work);
        assert!(crate::law::dot(&w, &out) < crate::law::dot(&w, &plain));
        assert_eq!(zone(0.5, 1.0, 0.1, || unreachable!()), Zone::Inside);
        assert_eq!(zone(2.0, 1.0, 0.1, || unreachable!()), Zone::Outside);
        assert_eq!(zone(1.0, 1.0, 0.1, || (1.0, 1.0)), Zone::Inside);
        assert_eq!(zone(1.0, 1.0, 0.1, || (-0.05, 1.0)), Zone::Sphere);
        assert_eq!(zone(1.0, 1.0, 0.1, || (-0.5, 1.0)), Zone::Outside);
    }
}
