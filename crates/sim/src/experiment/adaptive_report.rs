//! What an adaptive controller's run reports of its weights, on any plant: read from the
//! controller's [`AdaptiveView`] at each control instant.

use crate::control::AdaptiveView;
use serde::Serialize;

/// What a run of the adaptive controller reports of its weights.
#[derive(Debug, Clone, PartialEq, Serialize, Default, schemars::JsonSchema)]
pub struct AdaptiveReport {
    /// Largest |W| over the run (the neuron's units; the pump's: MPa/s).
    pub w_norm_max: f64,
    /// |W| at the end.
    pub w_norm_final: f64,
    /// Largest |W_1 - centre| after the identification phase (the neuron's units; the
    /// pump's: MPa/(s mm)).
    pub w1_distance_max: f64,
    /// Radius of W_1's ball.
    pub w1_ball_radius: f64,
    /// W_1 at the end.
    pub w1_final: Vec<f64>,
    /// Identifier substeps that ended with a projection.
    pub projections: u64,
    /// Radius of W's ball (around 0).
    pub w_bound: f64,
    /// The actuator's lag identified online, at the end \[ms\] (a one-period delay reads
    /// as one period); absent when the controller does not identify it.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub actuator_lag_ms: Option<f64>,
    /// The pilot valve's flow against the nominal one, identified online, at the end.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pilot_flow_ratio: Option<f64>,
}

impl AdaptiveReport {
    /// Take the view `v` of one control instant.
    pub(super) fn add(&mut self, v: &AdaptiveView) {
        self.w_norm_max = self.w_norm_max.max(v.w_norm);
        self.w_norm_final = v.w_norm;
        if !v.identifying {
            self.w1_distance_max = self.w1_distance_max.max(v.w1_distance);
        }
        self.w1_ball_radius = v.ball_radius;
        self.w_bound = v.w_bound;
        self.w1_final = v.w1.to_vec();
        self.projections = v.projections;
        self.actuator_lag_ms = v.actuator.map(|(lag_s, _)| lag_s * 1e3);
        self.pilot_flow_ratio = v.actuator.map(|(_, ratio)| ratio);
    }

    /// Whether every weight stayed inside its projection ball.
    pub fn within_balls(&self) -> bool {
        self.w1_distance_max <= self.w1_ball_radius * (1.0 + 1e-9) && self.w_norm_max <= self.w_bound
    }
}
