//! The recurrent high-order neural network (pump-model.md section 2, thesis chapter 4):
//! sigmoids of the states, external inputs, and high-order terms `z_k = prod y_j^d_j`.

use crate::error::{invalid, Result};

/// Most inputs `y` (sigmoids of states plus external inputs) a network may have.
pub const MAX_Y: usize = 64;
/// Most high-order terms `L` a network may have (scratch vectors live on the stack).
pub const MAX_TERMS: usize = 256;

/// `s(v) = a / (1 + exp(-b v)) - c` (in `rhonn_core`: the same on a microcontroller).
pub use rhonn_core::Sigmoid;

/// High-order terms: term `k` is `prod_{j in I_k} y_j^{d_j(k)}`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Terms {
    offsets: Vec<usize>,
    idx: Vec<usize>,
    exp: Vec<i32>,
    /// Every term is one factor to the first power (z_k = y_{idx_k}), as in the thesis.
    plain: bool,
}

impl Terms {
    /// From explicit lists of `(y index, exponent)` per term; `n_y` is the length of `y`.
    pub fn from_lists(lists: &[Vec<[usize; 2]>], n_y: usize, field: &str) -> Result<Self> {
        if lists.is_empty() || lists.len() > MAX_TERMS {
            return Err(invalid(
                field,
                lists.len(),
                format!("between 1 and {MAX_TERMS} terms"),
            ));
        }
        let mut t = Terms {
            offsets: vec![0],
            ..Default::default()
        };
        for (k, term) in lists.iter().enumerate() {
            if term.is_empty() {
                return Err(invalid(
                    format!("{field}[{k}]"),
                    "[]",
                    "at least one [index, exponent] factor",
                ));
            }
            for (f, &[j, d]) in term.iter().enumerate() {
                if j >= n_y {
                    return Err(invalid(
                        format!("{field}[{k}][{f}][0]"),
                        j,
                        format!(
                            "an index of y in [0, {}) (sigmoids of the states, then the inputs)",
                            n_y
                        ),
                    ));
                }
                if !(1..=8).contains(&d) {
                    return Err(invalid(
                        format!("{field}[{k}][{f}][1]"),
                        d,
                        "an exponent in [1, 8]",
                    ));
                }
                t.idx.push(j);
                t.exp.push(d as i32);
            }
            t.offsets.push(t.idx.len());
        }
        t.set_plain();
        Ok(t)
    }

    fn set_plain(&mut self) {
        self.plain = self.idx.len() == self.len() && self.exp.iter().all(|&d| d == 1);
    }

    /// When every term is one factor to the first power (z_k = y_{j_k}), the indices j_k.
    #[inline]
    pub fn plain_indices(&self) -> Option<&[usize]> {
        self.plain.then_some(&self.idx[..])
    }

    /// Every monomial of `y` (length `n_y`) of total degree 1 to `degree` with at most
    /// `max_factors` distinct factors.
    pub fn monomials(n_y: usize, degree: usize, max_factors: usize) -> Self {
        let mut t = Terms {
            offsets: vec![0],
            ..Default::default()
        };
        rhonn_core::terms::for_each_monomial(degree, max_factors, &mut vec![0; n_y], |e| {
            for (j, &d) in e.iter().enumerate() {
                if d > 0 {
                    t.idx.push(j);
                    t.exp.push(d as i32);
                }
            }
            t.offsets.push(t.idx.len());
        });
        t.set_plain();
        t
    }

    /// No terms.
    pub fn empty() -> Self {
        Terms {
            offsets: vec![0],
            ..Default::default()
        }
    }

    /// Number of terms L.
    pub fn len(&self) -> usize {
        self.offsets.len().saturating_sub(1)
    }

    /// Whether there are no terms.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// `z` from `y` (no allocation).
    #[inline]
    pub fn eval(&self, y: &[f64], z: &mut [f64]) {
        rhonn_core::terms::eval(&self.offsets, &self.idx, &self.exp, y, z)
    }

    /// The terms borrowed as `rhonn_core`'s identifier evaluates them.
    #[inline(always)]
    pub fn view(&self) -> rhonn_core::ident::Terms<'_> {
        rhonn_core::ident::Terms {
            offsets: &self.offsets,
            idx: &self.idx,
            exp: &self.exp,
        }
    }

    /// Term `k` as `(index, exponent)` factors.
    pub fn factors(&self, k: usize) -> Vec<[usize; 2]> {
        (self.offsets[k]..self.offsets[k + 1])
            .map(|f| [self.idx[f], self.exp[f] as usize])
            .collect()
    }
}

/// A RHONN's structure: `n` neurons (identified states), `m` external inputs, the
/// sigmoid, per-state scaling, the terms and the neurons' poles `a_i > 0`.
///
/// `y = [s(chi_1 / scale_1) .. s(chi_n / scale_n), u_1 / uscale_1 .. u_m / uscale_m]`;
/// `dx_i/dt = -a_i x_i + w_i^T z(y)`.
#[derive(Debug, Clone, PartialEq)]
pub struct Network {
    /// Number of neurons.
    pub n: usize,
    /// Number of external inputs.
    pub m: usize,
    /// Sigmoid.
    pub sigmoid: Sigmoid,
    /// Each state is divided by this before the sigmoid (1 = raw SI, as the thesis).
    pub state_scale: Vec<f64>,
    /// Each input is divided by this.
    pub input_scale: Vec<f64>,
    /// The terms.
    pub terms: Terms,
    /// Poles a_i > 0.
    pub a: Vec<f64>,
}

impl Network {
    /// `y` and `z` for states `chi` and inputs `u`. `y` and `z` are caller scratch.
    #[inline]
    pub fn regressor(&self, chi: &[f64], u: &[f64], y: &mut [f64], z: &mut [f64]) {
        self.view().regressor(chi, u, y, z)
    }

    /// The network borrowed as `rhonn_core`'s identifier evaluates it.
    #[inline(always)]
    pub fn view(&self) -> rhonn_core::ident::Net<'_, f64> {
        rhonn_core::ident::Net {
            n: self.n,
            m: self.m,
            sigmoid: self.sigmoid,
            state_scale: &self.state_scale,
            input_scale: &self.input_scale,
            terms: self.terms.view(),
            a: &self.a,
        }
    }

    /// State `i`'s value `v` divided by its scale. A scale of 1 (raw SI states, the
    /// thesis's) skips the division: the same result, without a division's latency in
    /// every evaluation's chain.
    #[inline(always)]
    pub fn scaled_state(&self, i: usize, v: f64) -> f64 {
        self.view().scaled_state(i, v)
    }

    /// Number of terms L.
    pub fn n_terms(&self) -> usize {
        self.terms.len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_unit_scale_skips_the_division_with_the_same_result() {
        let net = Network {
            n: 2,
            m: 0,
            sigmoid: Sigmoid::LOGISTIC,
            state_scale: vec![1.0, 3.0],
            input_scale: vec![],
            terms: Terms::monomials(2, 1, 1),
            a: vec![1.0, 1.0],
        };
        for v in [0.1, -2.5e6, 7.3e-4, -0.0, f64::INFINITY] {
            assert_eq!(net.scaled_state(0, v).to_bits(), (v / 1.0).to_bits());
            assert_eq!(net.scaled_state(1, v).to_bits(), (v / 3.0).to_bits());
        }
    }

    #[test]
    fn sigmoid_presets() {
        assert_eq!(Sigmoid::LOGISTIC.eval(0.0), 0.5);
        assert!((Sigmoid::TANH.eval(0.3) - 0.3f64.tanh()).abs() < 1e-15);
    }

    #[test]
    fn monomials_up_to_degree_two_of_three_inputs() {
        let t = Terms::monomials(3, 2, 2);
        // 3 linear + 3 squares + 3 cross products
        assert_eq!(t.len(), 9);
        let mut z = vec![0.0; 9];
        t.eval(&[2.0, 3.0, 5.0], &mut z);
        let mut s = z.clone();
        s.sort_by(f64::total_cmp);
        assert_eq!(s, vec![2.0, 3.0, 4.0, 5.0, 6.0, 9.0, 10.0, 15.0, 25.0]);
        assert_eq!(Terms::monomials(3, 2, 1).len(), 6);
    }

    #[test]
    fn explicit_terms_are_checked() {
        let t = Terms::from_lists(&[vec![[0, 1]], vec![[0, 1], [1, 2]]], 2, "identifier.terms").unwrap();
        let mut z = [0.0; 2];
        t.eval(&[2.0, 3.0], &mut z);
        assert_eq!(z, [2.0, 18.0]);
        let e = Terms::from_lists(&[vec![[2, 1]]], 2, "identifier.terms")
            .unwrap_err()
            .to_string();
        assert!(e.contains("`identifier.terms[0][0][0]` = 2"), "{e}");
    }
}
