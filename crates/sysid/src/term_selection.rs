//! Which high-order terms a lagged `rhonn` keeps under `max_terms = N` with `term_selection
//! = "error-reduction"`: orthogonal forward regression by the error reduction ratio (the
//! FROLS of Billings, Chen and Korenberg, as SysIdentPy implements it), restricted to the
//! high-order terms: the linear regressors and the bias are always in, and each step adds
//! the term that explains the largest share of the outputs' energy among what the terms
//! already in do not explain. Written here because no crate of the workspace offers a
//! forward regression over given columns; nalgebra's QR needs the whole matrix at once.

/// `u . v`.
fn dot(u: &[f64], v: &[f64]) -> f64 {
    u.iter().zip(v).map(|(a, b)| a * b).sum()
}

/// `v` minus its projections on the orthonormal vectors `basis` (modified Gram-Schmidt).
fn orthogonalise(v: &mut [f64], basis: &[Vec<f64>]) {
    for q in basis {
        let d = dot(q, v);
        for (a, b) in v.iter_mut().zip(q) {
            *a -= d * b;
        }
    }
}

/// A column whose part orthogonal to the columns in keeps less than this share of its
/// norm is taken as dependent on them (it would explain nothing new).
const DEPENDENT: f64 = 1e-10;

/// The columns of `rows` among `candidates` chosen by error reduction ratio, at most
/// `keep`, in the order chosen; the columns `fixed` are in from the start. The ratio of
/// a column `w` (orthogonalised against those in) is the sum over the outputs `y` of
/// `(w . y)^2 / (w . w  y . y)`. Ties go to the earlier candidate; a column dependent on
/// those in is never chosen, so fewer than `keep` may come back.
pub(super) fn by_error_reduction(
    rows: &[Vec<f64>],
    targets: &[Vec<f64>],
    fixed: &[usize],
    candidates: &[usize],
    keep: usize,
) -> Vec<usize> {
    let column = |j: usize| -> Vec<f64> { rows.iter().map(|r| r[j]).collect() };
    let mut basis: Vec<Vec<f64>> = Vec::new();
    let add = |mut v: Vec<f64>, norm0: f64, basis: &mut Vec<Vec<f64>>| -> bool {
        orthogonalise(&mut v, basis);
        let nn = dot(&v, &v);
        if !(nn > DEPENDENT * norm0 && nn > 0.0) {
            return false;
        }
        let s = nn.sqrt();
        v.iter_mut().for_each(|a| *a /= s);
        basis.push(v);
        true
    };
    for &j in fixed {
        let v = column(j);
        let n0 = dot(&v, &v);
        add(v, n0, &mut basis);
    }
    let energy: Vec<f64> = targets.iter().map(|y| dot(y, y).max(f64::MIN_POSITIVE)).collect();
    // Each candidate as its part orthogonal to the columns in, and its own norm.
    let mut left: Vec<(usize, Vec<f64>, f64)> = candidates
        .iter()
        .map(|&j| {
            let mut v = column(j);
            let n0 = dot(&v, &v);
            orthogonalise(&mut v, &basis);
            (j, v, n0)
        })
        .collect();
    let mut chosen = Vec::new();
    while chosen.len() < keep {
        let mut best: Option<(usize, f64)> = None;
        for (q, (_, w, n0)) in left.iter().enumerate() {
            let ww = dot(w, w);
            if !(ww > DEPENDENT * n0 && ww > 0.0) {
                continue;
            }
            let ratio: f64 = targets
                .iter()
                .zip(&energy)
                .map(|(y, e)| dot(w, y).powi(2) / (ww * e))
                .sum();
            if best.is_none_or(|(_, b)| ratio > b) {
                best = Some((q, ratio));
            }
        }
        let Some((q, _)) = best else { break };
        let (j, w, n0) = left.remove(q);
        chosen.push(j);
        let start = basis.len();
        add(w, n0, &mut basis);
        let new = &basis[start..];
        for (_, v, _) in &mut left {
            orthogonalise(v, new);
        }
    }
    chosen
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_column_that_explains_what_is_left_comes_first_and_a_dependent_one_never() {
        // Columns: 0 the bias (fixed), 1 a ramp (fixed), 2 the ramp again (dependent on
        // the fixed ones), 3 a square wave, 4 a small sine; y = 1 + ramp + 2 square +
        // 0.1 sine. The square explains the most of what the fixed columns leave, then
        // the sine; the copy of the ramp explains nothing new and is never chosen.
        let rows: Vec<Vec<f64>> = (0..200)
            .map(|k| {
                let t = k as f64 / 200.0;
                let sq = if (k / 10) % 2 == 0 { 1.0 } else { -1.0 };
                vec![1.0, t, t, sq, (0.37 * k as f64).sin()]
            })
            .collect();
        let y: Vec<f64> = rows
            .iter()
            .map(|r| 1.0 + r[1] + 2.0 * r[3] + 0.1 * r[4])
            .collect();
        let chosen = by_error_reduction(&rows, std::slice::from_ref(&y), &[0, 1], &[2, 3, 4], 3);
        assert_eq!(chosen, vec![3, 4]);
        assert_eq!(by_error_reduction(&rows, &[y], &[0, 1], &[2, 3, 4], 1), vec![3]);
    }
}
