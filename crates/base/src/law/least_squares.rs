//! Least squares: each neuron carries a covariance `P_i` (L x L) that shapes its step,
//! `dw_i/dt = -P_i phi e_i`, `dP_i/dt = -P_i phi phi^T P_i` (Ioannou & Sun 1996, section
//! 4.3.6; the thesis's filtered-regressor least squares with phi = zeta). The covariance
//! is bounded below: it stops shrinking while `trace P_i < floor_i L`, so the law keeps
//! adapting. Sampled, recursive least squares:
//! `q = P phi`, `w -= q e / (1 + phi^T q)`, `P -= q q^T / (1 + phi^T q)`; a reset
//! ([`LearningLaw::init`]) puts `P_i` back to `p0_i I` (`rhonn fit` resets it each epoch).

use super::LearningLaw;

/// Least squares, per neuron `P_i(0) = p0_i I` and its floor.
#[derive(Debug, Clone, PartialEq)]
pub struct LeastSquares {
    /// `P_i(0) = p0_i I`.
    pub p0: Vec<f64>,
    /// The covariance stops shrinking while `trace P_i < floor_i L`.
    pub floor: Vec<f64>,
}

/// `q = P phi` for a row-major L x L `P`.
impl LearningLaw for LeastSquares {
    fn name(&self) -> &'static str {
        "least-squares"
    }

    /// The covariance's trace.
    fn rate(&self, _neuron: usize, states: &[f64], l: usize) -> f64 {
        (0..l).map(|k| states[k * l + k]).sum::<f64>()
    }

    fn law_states(&self, l: usize) -> usize {
        l * l
    }

    fn init(&self, neuron: usize, l: usize, states: &mut [f64]) {
        states.iter_mut().for_each(|v| *v = 0.0);
        for k in 0..l {
            states[k * l + k] = self.p0[neuron];
        }
    }

    fn derivative(
        &self,
        neuron: usize,
        phi: &[f64],
        e: f64,
        p: &[f64],
        dw: &mut [f64],
        dp: &mut [f64],
        work: &mut [f64],
    ) {
        rhonn_core::law::least_squares_derivative(phi, e, p, self.floor[neuron], dw, dp, work)
    }

    fn update(&self, _neuron: usize, phi: &[f64], e: f64, w: &mut [f64], p: &mut [f64], work: &mut [f64]) {
        rhonn_core::law::least_squares_step(phi, e, w, p, work)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recursive_least_squares_recovers_a_linear_map_and_the_covariance_shrinks() {
        let law = LeastSquares {
            p0: vec![1e3],
            floor: vec![0.0],
        };
        let truth = [0.7, -1.2];
        let mut w = [0.0; 2];
        let mut p = [0.0; 4];
        law.init(0, 2, &mut p);
        assert_eq!(p, [1e3, 0.0, 0.0, 1e3]);
        let mut work = [0.0; 2];
        for k in 0..20 {
            let phi = [(k as f64 * 0.7).sin(), (k as f64 * 1.3).cos()];
            let e = crate::law::dot(&w, &phi) - crate::law::dot(&truth, &phi);
            law.update(0, &phi, e, &mut w, &mut p, &mut work);
        }
        assert!((w[0] - 0.7).abs() < 1e-3 && (w[1] + 1.2).abs() < 1e-3, "{w:?}");
        assert!(p[0] + p[3] < 1.0, "{p:?}");
        // At the floor the continuous covariance stops shrinking.
        let floored = LeastSquares {
            p0: vec![1.0],
            floor: vec![1.0],
        };
        let (mut dw, mut dp) = ([0.0; 2], [1.0; 4]);
        floored.derivative(
            0,
            &[1.0, 1.0],
            1.0,
            &[1.0, 0.0, 0.0, 1.0],
            &mut dw,
            &mut dp,
            &mut work,
        );
        assert_eq!(dp, [0.0; 4]);
        assert_eq!(dw, [-1.0, -1.0]);
    }
}
