//! The gradient law: each neuron's weights descend the squared error along its
//! regressor, `dw_i/dt = -Gamma_i phi e_i` (Kosmatopoulos et al. 1995; the thesis's
//! eq. 4.7 with phi = z, its filtered-regressor variant with phi = zeta). Sampled, the
//! normalised step `w_i -= Gamma_i phi e_i / (1 + phi^T phi)` (Ioannou & Sun 1996,
//! section 4.11), which stays stable for any regressor size.
//!
//! Used by the online identifier (filtered-error and filtered-regressor laws), by the
//! adaptive controller's neurons ([`descend`]) and by `rhonn fit --model` with
//! `law = "gradient"`.

use super::gain::Gain;
use super::LearningLaw;

pub use rhonn_core::law::descend;
use rhonn_core::law::{descend_with, normalized_step_with};

/// The gradient law, one gain per neuron.
#[derive(Debug, Clone, PartialEq)]
pub struct Gradient {
    /// Gain per neuron.
    pub gamma: Vec<Gain>,
}

impl Gradient {
    /// The same scalar gain `g` for `n` neurons.
    pub fn scalar(g: f64, n: usize) -> Self {
        Gradient {
            gamma: vec![Gain::Scalar(g); n],
        }
    }
}

impl LearningLaw for Gradient {
    fn name(&self) -> &'static str {
        "gradient"
    }

    fn gain(&self, neuron: usize) -> Option<&Gain> {
        self.gamma.get(neuron)
    }

    fn scalar_gains(&self) -> Option<Vec<f64>> {
        self.gamma
            .iter()
            .map(|g| match g {
                Gain::Scalar(s) => Some(*s),
                Gain::Matrix(_) => None,
            })
            .collect()
    }

    /// The gain itself (a matrix's: the sum of its entries' magnitudes).
    fn rate(&self, neuron: usize, _states: &[f64], _l: usize) -> f64 {
        match &self.gamma[neuron] {
            Gain::Scalar(v) => *v,
            Gain::Matrix(m) => m.iter().map(|v| v.abs()).sum::<f64>(),
        }
    }

    fn derivative(
        &self,
        neuron: usize,
        phi: &[f64],
        e: f64,
        _states: &[f64],
        dw: &mut [f64],
        _dstates: &mut [f64],
        work: &mut [f64],
    ) {
        descend_with(self.gamma[neuron].as_core(), phi, e, dw, work)
    }

    fn update(
        &self,
        neuron: usize,
        phi: &[f64],
        e: f64,
        w: &mut [f64],
        _states: &mut [f64],
        work: &mut [f64],
    ) {
        normalized_step_with(self.gamma[neuron].as_core(), phi, e, w, work)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sampled_step_shrinks_the_error_and_the_flow_points_downhill() {
        let law = Gradient::scalar(0.5, 1);
        let phi = [1.0, -2.0, 0.5];
        let target = [0.3, 0.1, -0.4];
        let y: f64 = phi.iter().zip(&target).map(|(a, b)| a * b).sum();
        let mut w = [0.0; 3];
        let mut work = [0.0; 3];
        let mut last = f64::INFINITY;
        for _ in 0..50 {
            let e: f64 = phi.iter().zip(&w).map(|(a, b)| a * b).sum::<f64>() - y;
            assert!(e.abs() < last || e == 0.0, "{e} after {last}");
            last = e.abs();
            law.update(0, &phi, e, &mut w, &mut [], &mut work);
        }
        assert!(last < 1e-6, "{last}");
        // Continuous time: dw . (de/dw) = -g |phi|^2 e^2 < 0.
        let mut dw = [0.0; 3];
        law.derivative(0, &phi, 2.0, &[], &mut dw, &mut [], &mut work);
        let descent: f64 = dw.iter().zip(&phi).map(|(d, p)| d * p * 2.0).sum();
        assert!(descent < 0.0);
        // A matrix gain equal to g I gives the scalar law's numbers.
        let m = Gradient {
            gamma: vec![Gain::Matrix(vec![0.5, 0.0, 0.0, 0.0, 0.5, 0.0, 0.0, 0.0, 0.5])],
        };
        let mut dm = [0.0; 3];
        m.derivative(0, &phi, 2.0, &[], &mut dm, &mut [], &mut work);
        assert_eq!(dm, dw);
    }
}
