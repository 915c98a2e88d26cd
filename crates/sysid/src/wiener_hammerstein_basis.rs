//! The polynomial's basis of G1's output, kept for the G1 that most residual evaluations of
//! one Levenberg-Marquardt share.
//!
//! Each column of the Jacobian is a full free run with one parameter moved; the columns of
//! c, G2 and the bias (most of them: 23 of 36 for 6 poles and degree 15) leave G1 as it is,
//! so its output through the Hermite basis is the same for all of them. The basis is kept
//! for a G1 asked for a second time (the unmoved one) and reused; a G1 seen once (a moved
//! one) goes straight to G2's input without its basis stored. Both give bit for bit what
//! `Params::inner` computes: the same operations on the same values. Written by hand: it is
//! a memo of one function of this module, keyed by the filter's coefficients' bits.

use super::Params;
use std::sync::{Arc, Mutex};

/// Bases kept at most (the unmoved G1 of the current and of the previous iteration).
const KEPT: usize = 2;
/// G1s seen once remembered at most (the moved ones of an iteration's columns).
const SEEN: usize = 64;

/// One G1's basis per record: `d` values per sample, sample after sample.
pub(super) type Bases = Arc<Vec<Vec<f64>>>;

#[derive(Default)]
struct Memo {
    kept: Vec<(Vec<u64>, Bases)>,
    seen: Vec<Vec<u64>>,
}

/// The memo of one refinement (one data set, one delay, one x range).
#[derive(Default)]
pub(super) struct BasisCache {
    memo: Mutex<Memo>,
}

fn key(p: &Params) -> Vec<u64> {
    let mut k: Vec<u64> = p.g1.b.iter().chain(&p.g1.a).map(|v| v.to_bits()).collect();
    k.extend([p.x_range.0.to_bits(), p.x_range.1.to_bits(), p.c.len() as u64]);
    k
}

impl BasisCache {
    /// G2's input (`Params::inner`) of `p` on every record's normalised input `data[i].0`
    /// at delay `nk`, from the kept basis of its G1 when there is one.
    pub(super) fn inner(&self, p: &Params, nk: usize, data: &[(Vec<f64>, Vec<f64>)]) -> Vec<Vec<f64>> {
        match self.bases(p, nk, data) {
            Some(b) => b.iter().map(|basis| p.combine(basis)).collect(),
            None => data.iter().map(|(u, _)| p.inner(u, nk)).collect(),
        }
    }

    /// `p`'s basis on every record when its G1 is kept or asked for a second time (then
    /// kept); None for a G1 seen once.
    fn bases(&self, p: &Params, nk: usize, data: &[(Vec<f64>, Vec<f64>)]) -> Option<Bases> {
        let k = key(p);
        let keep = {
            let mut m = self.memo.lock().unwrap_or_else(|e| e.into_inner());
            if let Some((_, b)) = m.kept.iter().find(|(kk, _)| *kk == k) {
                return Some(Arc::clone(b));
            }
            let twice = m.seen.contains(&k);
            if !twice {
                if m.seen.len() == SEEN {
                    m.seen.remove(0);
                }
                m.seen.push(k.clone());
            }
            twice
        };
        if !keep {
            return None;
        }
        let b: Bases = Arc::new(data.iter().map(|(u, _)| p.basis(u, nk)).collect());
        let mut m = self.memo.lock().unwrap_or_else(|e| e.into_inner());
        if !m.kept.iter().any(|(kk, _)| *kk == k) {
            if m.kept.len() == KEPT {
                m.kept.remove(0);
            }
            m.kept.push((k, Arc::clone(&b)));
        }
        Some(b)
    }
}

#[cfg(test)]
mod tests {
    use super::super::{Filter, Params};
    use super::*;

    fn params(b0: f64) -> Params {
        Params {
            g1: Filter {
                b: vec![b0, 0.2],
                a: vec![-0.5],
            },
            c: vec![0.3, -0.1, 0.05],
            g2: Filter {
                b: vec![1.0],
                a: vec![],
            },
            bias: 0.0,
            x_range: (f64::NEG_INFINITY, f64::INFINITY),
        }
    }

    #[test]
    fn a_g1_asked_for_twice_is_kept_and_its_basis_is_the_direct_one() {
        let data = vec![(
            (0..50).map(|k| (k as f64 * 0.3).sin()).collect::<Vec<_>>(),
            vec![0.0; 50],
        )];
        let cache = BasisCache::default();
        let (p, moved) = (params(1.0), params(1.0 + 1e-6));
        assert!(cache.bases(&p, 1, &data).is_none(), "not kept when seen once");
        assert!(cache.bases(&moved, 1, &data).is_none());
        let second = cache.bases(&p, 1, &data).unwrap();
        let third = cache.bases(&p, 1, &data).unwrap();
        assert!(Arc::ptr_eq(&second, &third), "kept after the second request");
        assert_eq!(*second, vec![p.basis(&data[0].0, 1)]);
        let again = cache.bases(&moved, 1, &data).unwrap();
        assert_eq!(*again, vec![moved.basis(&data[0].0, 1)]);
        // The values through the kept basis and straight through `inner` are the same
        // bits: a G1 seen once, and a kept one.
        let direct = vec![p.inner(&data[0].0, 1)];
        assert_eq!(p.combine(&third[0]), direct[0]);
        let fresh = BasisCache::default();
        let bits = |v: &[Vec<f64>]| v[0].iter().map(|x| x.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(&fresh.inner(&p, 1, &data)), bits(&direct));
        assert_eq!(bits(&cache.inner(&p, 1, &data)), bits(&direct));
    }
}
