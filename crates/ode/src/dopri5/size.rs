//! Step-size control after a step (ode45's I-controller or Hairer's PI, per the
//! profile) and the dense output of an accepted step.

use super::*;

impl<Sys: System> Dopri5<Sys> {
    /// Step size after an accepted step.
    pub(super) fn accept_size(&mut self, h: f64, err: f64, rejected: bool) {
        self.h = match self.opts.profile {
            Profile::Hairer => {
                const BETA: f64 = 0.04;
                const SAFE: f64 = 0.9;
                let expo1 = 0.2 - BETA * 0.75;
                let fac11 = powf(err, expo1);
                let mut fac = fac11 / self.facold_beta;
                fac = (1.0 / 10.0f64).max((1.0 / 0.2f64).min(fac / SAFE));
                self.facold = err.max(1e-4);
                self.facold_beta = powf(self.facold, BETA);
                let hn = h / fac;
                if rejected {
                    hn.min(h)
                } else {
                    hn
                }
            }
            Profile::Ode45 => {
                if rejected {
                    h
                } else {
                    let temp = 1.25 * powf(err, 0.2);
                    if temp > 0.2 {
                        h / temp
                    } else {
                        5.0 * h
                    }
                }
            }
        };
    }

    /// Step size after a rejected step.
    pub(super) fn reject_size(&self, h: f64, err: f64, rejections: u32) -> f64 {
        match self.opts.profile {
            Profile::Hairer => {
                let fac11 = powf(err, 0.2 - 0.04 * 0.75);
                h / (1.0 / 0.2f64).min(fac11 / 0.9)
            }
            Profile::Ode45 => {
                if rejections == 1 {
                    h * (0.1f64).max(0.8 * powf(1.0 / err, 0.2))
                } else {
                    0.5 * h
                }
            }
        }
    }

    /// Coefficients of the continuous extension of the accepted step of size `h`.
    pub(super) fn build_dense(&mut self, h: f64) {
        let n = self.x.dim();
        let x = self.x.as_slice();
        let xn = self.x_new.as_slice();
        let [k1, _k2, k3, k4, k5, k6, k7] = &self.k;
        let (k1, k3, k4, k5, k6, k7) = (
            k1.as_slice(),
            k3.as_slice(),
            k4.as_slice(),
            k5.as_slice(),
            k6.as_slice(),
            k7.as_slice(),
        );
        let [r1, r2, r3, r4, r5] = &mut self.dense;
        let (r1, r2, r3, r4, r5) = (
            r1.as_mut_slice(),
            r2.as_mut_slice(),
            r3.as_mut_slice(),
            r4.as_mut_slice(),
            r5.as_mut_slice(),
        );
        for i in 0..n {
            let dy = xn[i] - x[i];
            let bspl = h * k1[i] - dy;
            r1[i] = x[i];
            r2[i] = dy;
            r3[i] = bspl;
            r4[i] = dy - h * k7[i] - bspl;
            r5[i] = h * (D1 * k1[i] + D3 * k3[i] + D4 * k4[i] + D5 * k5[i] + D6 * k6[i] + D7 * k7[i]);
        }
    }
}
