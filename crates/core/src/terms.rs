//! The RHONN's high-order terms `z_k = prod_{j in I_k} y_j^{d_j(k)}` (pump-model.md
//! section 2, thesis chapter 4), on slices: term `k`'s factors are
//! `idx[offsets[k]..offsets[k + 1]]` with exponents `exp[...]` (the host library's
//! `Terms` holds them in vectors; a target, in arrays). Powers above 2 use [`Real::powi`].

use crate::Real;

/// Evaluate every term: `z[k] = prod y[idx[f]]^exp[f]` over `f` in
/// `offsets[k]..offsets[k + 1]`.
#[inline]
pub fn eval<T: Real>(offsets: &[usize], idx: &[usize], exp: &[i32], y: &[T], z: &mut [T]) {
    // Iterators rather than indices: no bounds check per factor; the same products in
    // the same order.
    for (zk, w) in z.iter_mut().zip(offsets.windows(2)) {
        let mut v = T::of(1.0);
        for (j, d) in idx[w[0]..w[1]].iter().zip(&exp[w[0]..w[1]]) {
            let yj = y[*j];
            v *= match *d {
                1 => yj,
                2 => yj * yj,
                d => yj.powi(d),
            };
        }
        *zk = v;
    }
}

/// Every monomial of `cur.len()` signals up to `degree`, with at most `max_factors`
/// distinct factors, in graded order (by degree; within a degree, exponent vectors in
/// ascending lexicographic order): `term(exponents)` for each, one exponent per signal.
/// No allocation: `cur` is the caller's.
pub fn for_each_monomial(
    degree: usize,
    max_factors: usize,
    cur: &mut [usize],
    mut term: impl FnMut(&[usize]),
) {
    let n = cur.len();
    if n == 0 {
        return;
    }
    for deg in 1..=degree {
        cur.iter_mut().for_each(|d| *d = 0);
        cur[n - 1] = deg;
        loop {
            if cur.iter().filter(|d| **d > 0).count() <= max_factors {
                term(cur);
            }
            // The next vector of the same degree: raise the rightmost entry that has
            // something after it, and put all that is left in the last entry.
            let mut rest = cur[n - 1];
            let mut next = false;
            for i in (0..n - 1).rev() {
                if rest > 0 {
                    cur[i] += 1;
                    cur[i + 1..].iter_mut().for_each(|d| *d = 0);
                    cur[n - 1] = rest - 1;
                    next = true;
                    break;
                }
                rest += cur[i];
            }
            if !next {
                break;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn products_and_powers() {
        // z_0 = y_0, z_1 = y_0 y_1^2, z_2 = y_1^3, z_3 = y_0^-2
        let (offsets, idx, exp) = ([0, 1, 3, 4, 5], [0, 0, 1, 1, 0], [1, 1, 2, 3, -2]);
        let y = [2.0, 3.0];
        let mut z = [0.0; 4];
        eval(&offsets, &idx, &exp, &y, &mut z);
        assert_eq!(z, [2.0, 18.0, 27.0, 0.25]);
        assert_eq!(1.5f32.powi(4), 5.0625);
        assert_eq!(crate::real::powi_by_squaring(2.0f64, -3), 0.125);
    }

    #[test]
    fn monomials_in_graded_order() {
        let mut seen = [[0usize; 3]; 16];
        let mut k = 0;
        for_each_monomial(2, 2, &mut [0; 3], |e| {
            seen[k].copy_from_slice(e);
            k += 1;
        });
        // 3 of degree 1, then the 6 of degree 2 (none has more than 2 factors).
        assert_eq!(k, 9);
        assert_eq!(
            &seen[..9],
            &[
                [0, 0, 1],
                [0, 1, 0],
                [1, 0, 0],
                [0, 0, 2],
                [0, 1, 1],
                [0, 2, 0],
                [1, 0, 1],
                [1, 1, 0],
                [2, 0, 0]
            ]
        );
        let mut n = 0;
        for_each_monomial(3, 1, &mut [0; 3], |_| n += 1);
        assert_eq!(n, 9, "pure powers only");
    }
}
