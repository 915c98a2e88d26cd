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
pub use rhonn_core::law::{zone, Zone};

/// Add the robust term of `zone` to a gradient step `dw = -Gamma phi e` (given), with
/// `work` of the weights' length (`rhonn_core::law::modify`).
pub fn modify(zone: Zone, gain: &Gain, sigma: f64, w: &[f64], dw: &mut [f64], work: &mut [f64]) {
    rhonn_core::law::modify(zone, gain.as_core(), sigma, w, dw, work)
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
