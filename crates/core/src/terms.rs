//! The RHONN's high-order terms `z_k = prod_{j in I_k} y_j^{d_j(k)}` (pump-model.md
//! section 2, thesis chapter 4), on slices: term `k`'s factors are
//! `idx[offsets[k]..offsets[k + 1]]` with exponents `exp[...]` (the host library's
//! `Terms` holds them in vectors; a target, in arrays). Powers above 2 use [`Real::powi`].

use crate::Real;

/// Evaluate every term: `z[k] = prod y[idx[f]]^exp[f]` over `f` in
/// `offsets[k]..offsets[k + 1]`.
#[inline]
pub fn eval<T: Real>(offsets: &[usize], idx: &[usize], exp: &[i32], y: &[T], z: &mut [T]) {
    for k in 0..offsets.len().saturating_sub(1) {
        let mut v = T::of(1.0);
        for f in offsets[k]..offsets[k + 1] {
            let yj = y[idx[f]];
            v *= match exp[f] {
                1 => yj,
                2 => yj * yj,
                d => yj.powi(d),
            };
        }
        z[k] = v;
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
}
