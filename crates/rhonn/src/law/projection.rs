//! Projection onto a ball: after each step a weight vector outside the ball of radius
//! `r` around `c` is put back on its surface along the ray from `c` (Ioannou & Sun 1996,
//! section 4.10.3). The adaptive controller keeps its input-gain weights in a ball
//! around their identified values this way, so the identified gain never reaches zero.

/// Project `v` onto the ball of `radius` around `c`; true when it had to.
#[inline]
pub fn project(v: &mut [f64], c: &[f64], radius: f64) -> bool {
    let d2: f64 = v.iter().zip(c).map(|(a, b)| (a - b) * (a - b)).sum();
    if d2 <= radius * radius {
        return false;
    }
    let k = radius / d2.sqrt();
    for (a, b) in v.iter_mut().zip(c) {
        *a = b + (*a - b) * k;
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn projection_lands_on_the_sphere_and_leaves_the_inside_alone() {
        let mut v = [3.0, 4.0];
        assert!(project(&mut v, &[0.0, 0.0], 1.0));
        assert!(((v[0] * v[0] + v[1] * v[1]).sqrt() - 1.0).abs() < 1e-15);
        let mut inside = [0.3, -0.4];
        assert!(!project(&mut inside, &[0.0, 0.0], 1.0));
        assert_eq!(inside, [0.3, -0.4]);
        let mut u = [2.0, 1.0];
        assert!(project(&mut u, &[1.0, 1.0], 0.5));
        assert_eq!(u, [1.5, 1.0]);
    }
}
