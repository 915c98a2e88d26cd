//! RHONN indirect adaptive control of the pump (pump-model.md section 4, thesis 4.5.2):
//! the affine neuron, the cascade and its settings live in `rhonn_core::adaptive` (the
//! very code that runs on a microcontroller, see `embedded/`); here they become a
//! [`Controller`] of the library's runs.

use super::{AdaptiveView, Controller};
use crate::plant::{P_LINE, STROKE};
pub use rhonn_core::adaptive::{
    AffineNeuron, CascadeSettings, CascadeState, RhonnCascade, INTEGRAL_BAND_MPA, L_DRIFT, L_GAIN,
};

impl AdaptiveView {
    /// The view of a controller built on `neuron`.
    pub fn of(
        neuron: &AffineNeuron<L_DRIFT, L_GAIN>,
        model_output: f64,
        inner_reference: Option<f64>,
        identifying: bool,
        projections: u64,
    ) -> Self {
        AdaptiveView {
            model_output,
            inner_reference,
            w_norm: neuron.w_norm(),
            w1_norm: neuron.w1_norm(),
            identifying,
            w1_distance: neuron.w1_distance(),
            ball_radius: neuron.radius,
            w_bound: neuron.w_bound,
            w1: neuron.w1,
            projections,
        }
    }
}

impl Controller for RhonnCascade {
    fn name(&self) -> &'static str {
        "rhonn-adaptive"
    }
    fn measurements(&self) -> &[usize] {
        &[P_LINE, STROKE]
    }
    fn control(&mut self, t: f64, measured: &[f64], setpoint: f64) -> f64 {
        self.update(t, measured[0], measured[1], setpoint)
    }
    fn adaptive(&self, t: f64) -> Option<AdaptiveView> {
        let identifying = t < self.settings.identification_s;
        Some(AdaptiveView::of(
            &self.neuron,
            self.neuron.xh * 1e6,
            Some(self.state().stroke_ref),
            identifying,
            self.projections(),
        ))
    }
}
