//! The sign-error law, `dw_i/dt = -gamma_i phi sign(e_i)` (sampled: `w_i -= gamma_i phi
//! sign(e_i) / (1 + phi^T phi)`), built in tests only: the small law that shows adding a
//! law is this file, a [`super::Rule`] variant with its arm in `Rule::law`, and a
//! [`super::LawSpec`] variant with its arm in `LawSpec::check` (`kind =
//! "test-sign-error"`), as docs/ARCHITECTURE.md counts.

use super::LearningLaw;

/// The sign-error law, one scalar gain per neuron.
#[derive(Debug, Clone, PartialEq)]
pub struct SignError {
    /// Gain per neuron.
    pub gamma: Vec<f64>,
}

impl LearningLaw for SignError {
    fn name(&self) -> &'static str {
        "test-sign-error"
    }
    fn rate(&self, neuron: usize, _states: &[f64], _l: usize) -> f64 {
        self.gamma[neuron]
    }
    fn derivative(
        &self,
        neuron: usize,
        phi: &[f64],
        e: f64,
        _states: &[f64],
        dw: &mut [f64],
        _dstates: &mut [f64],
        _work: &mut [f64],
    ) {
        for (d, p) in dw.iter_mut().zip(phi) {
            *d = -self.gamma[neuron] * p * e.signum();
        }
    }
    fn update(
        &self,
        neuron: usize,
        phi: &[f64],
        e: f64,
        w: &mut [f64],
        _states: &mut [f64],
        _work: &mut [f64],
    ) {
        let norm = 1.0 + super::dot(phi, phi);
        for (w, p) in w.iter_mut().zip(phi) {
            *w -= self.gamma[neuron] * p * e.signum() / norm;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::{LawSpec, LearningLaw, Structure};

    /// Written in a scenario's TOML form, checked into a law like any other, and used
    /// through the registry's `Rule`: its sampled steps bring a regression's error down.
    #[test]
    fn a_law_added_by_its_file_and_its_registrations_learns() {
        let spec: LawSpec = toml::from_str("kind = \"test-sign-error\"\ngamma = [0.02]").unwrap();
        let law = spec.check(1, 3, "identifier.law").unwrap();
        assert_eq!(
            (law.name, law.structure),
            ("test-sign-error", Structure::FilteredError)
        );
        assert_eq!(law.rule.name(), "test-sign-error");
        let e = toml::from_str::<LawSpec>("kind = \"test-sign-error\"\ngamma = [-1.0]")
            .unwrap()
            .check(1, 3, "identifier.law")
            .unwrap_err()
            .to_string();
        assert!(e.contains("identifier.law.gamma[0]"), "{e}");
        let target = [0.3, 0.1, -0.4];
        let mut w = [0.0; 3];
        let error = |w: &[f64], k: usize| {
            let phi = [1.0, (k as f64 * 0.7).sin(), (k as f64 * 0.3).cos()];
            let e: f64 = phi
                .iter()
                .zip(w.iter().zip(&target))
                .map(|(p, (a, b))| p * (a - b))
                .sum();
            (phi, e)
        };
        let rms = |w: &[f64]| (0..100).map(|k| error(w, k).1.powi(2)).sum::<f64>().sqrt();
        let before = rms(&w);
        for k in 0..20_000 {
            let (phi, e) = error(&w, k);
            law.rule.update(0, &phi, e, &mut w, &mut [], &mut [0.0; 3]);
        }
        assert!(rms(&w) < 0.05 * before, "{} against {before}", rms(&w));
    }
}
