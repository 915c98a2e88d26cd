//! The grey-box pump's sampled step and its extended Kalman filter.
//!
//! The state is `[P_l, x, b]`: the line pressure, the stroke (both limited integrators, as
//! in the plant) and `b`, an unmodelled flow into the line (a random walk: what the
//! equations miss, such as a leakage that is not `Q_0`, lands there instead of in a wrong
//! stroke). The filter works in MPa, mm and dm^3/s so that its covariance is well
//! conditioned; the equations run in SI (`rhonn_core::pump::PumpEquations`, the same
//! code as the plant's).

use nalgebra::{Matrix3, Vector3};
use rhonn_core::pump::PumpEquations;

/// Display units of the filter's state: Pa per MPa, m per mm, m^3/s per dm^3/s.
const SCALE: [f64; 3] = [1e6, 1e-3, 1e-3];

/// The pump's equations stepped over one sample.
#[derive(Debug, Clone, Copy)]
pub struct GreyPump {
    /// The equations' coefficients.
    pub eq: PumpEquations,
    /// Pressure bound \[Pa\].
    pub p_max: f64,
    /// Stroke bound \[m\].
    pub x_max: f64,
    /// Sample interval \[s\].
    pub dt: f64,
    /// RK4 substeps per sample.
    pub substeps: usize,
    /// Demand linear between samples (else held, as the current always is).
    pub interpolate_demand: bool,
}

impl GreyPump {
    /// Advance `z = [P_l Pa, x m, b m^3/s]` by one sample with the current `i` \[A\] held
    /// and the demand going from `q0` to `q1` \[m^3/s\] (or held at `q0`). Classical RK4
    /// with every stage's state held in range and no motion beyond a bound (limited
    /// integrators), the pilot valve's branch chosen at each substep's start, as
    /// `rhonn_core::pump::DiscretePump` does.
    pub fn step(&self, z: [f64; 3], i: f64, q0: f64, q1: f64) -> [f64; 3] {
        let n = self.substeps.max(1);
        let h = self.dt / n as f64;
        let dq = if self.interpolate_demand { q1 - q0 } else { 0.0 };
        let (mut p, mut x) = (z[0], z[1]);
        let b = z[2];
        for s in 0..n {
            let neg = self.eq.pilot(p, x, i, false).s < 0.0;
            let f = |p: f64, x: f64, tau: f64| {
                let (p, x) = (p.clamp(0.0, self.p_max), x.clamp(0.0, self.x_max));
                let q = q0 + dq * tau - b;
                let (dp, dx) = self.eq.derivative(p, x, i, q, neg);
                let held = |v: f64, d: f64, hi: f64| {
                    if (v <= 0.0 && d < 0.0) || (v >= hi && d > 0.0) {
                        0.0
                    } else {
                        d
                    }
                };
                (held(p, dp, self.p_max), held(x, dx, self.x_max))
            };
            let t0 = s as f64 / n as f64;
            let th = (s as f64 + 0.5) / n as f64;
            let t1 = (s + 1) as f64 / n as f64;
            let k1 = f(p, x, t0);
            let k2 = f(p + 0.5 * h * k1.0, x + 0.5 * h * k1.1, th);
            let k3 = f(p + 0.5 * h * k2.0, x + 0.5 * h * k2.1, th);
            let k4 = f(p + h * k3.0, x + h * k3.1, t1);
            p = (p + h / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0)).clamp(0.0, self.p_max);
            x = (x + h / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1)).clamp(0.0, self.x_max);
        }
        [p, x, b]
    }

    /// [`GreyPump::step`] on a state in display units (MPa, mm, dm^3/s).
    fn step_scaled(&self, z: &Vector3<f64>, i: f64, q0: f64, q1: f64) -> Vector3<f64> {
        let si = [z[0] * SCALE[0], z[1] * SCALE[1], z[2] * SCALE[2]];
        let o = self.step(si, i, q0, q1);
        Vector3::new(o[0] / SCALE[0], o[1] / SCALE[1], o[2] / SCALE[2])
    }

    /// The stroke whose pump flow meets the demand `q` and the leakage, within its
    /// range \[m\].
    pub fn balanced_stroke(&self, q: f64) -> f64 {
        ((q + self.eq.q_0) / (self.eq.k_l * self.eq.omega)).clamp(0.0, self.x_max)
    }
}

/// Settings of the state estimator, display units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Noise {
    /// Process noise densities per sqrt(s): pressure \[MPa\], stroke \[mm\], unmodelled
    /// flow \[dm^3/s\].
    pub process: [f64; 3],
    /// Measurement noise standard deviation \[MPa\].
    pub measurement_mpa: f64,
}

/// An extended Kalman filter of the grey-box pump on a measured pressure.
#[derive(Debug, Clone)]
pub struct Ekf<'a> {
    pump: &'a GreyPump,
    /// The estimate (MPa, mm, dm^3/s).
    pub z: Vector3<f64>,
    /// Its covariance.
    pub cov: Matrix3<f64>,
    qd: Matrix3<f64>,
    r: f64,
}

impl<'a> Ekf<'a> {
    /// Start at the measured pressure `y0` \[Pa\], the stroke whose pump flow meets the
    /// demand `q0` \[m^3/s\] and the leakage (a line in balance) and no unmodelled flow,
    /// with a covariance as wide as the stroke's range.
    pub fn new(pump: &'a GreyPump, noise: Noise, y0: f64, q0: f64) -> Self {
        let r = noise.measurement_mpa.powi(2);
        let qd = Matrix3::from_diagonal(&Vector3::new(
            noise.process[0].powi(2) * pump.dt,
            noise.process[1].powi(2) * pump.dt,
            noise.process[2].powi(2) * pump.dt,
        ));
        Ekf {
            pump,
            z: Vector3::new(y0 / SCALE[0], pump.balanced_stroke(q0) / SCALE[1], 0.0),
            cov: Matrix3::from_diagonal(&Vector3::new(
                r.max(1e-4),
                (0.5 * pump.x_max / SCALE[1]).powi(2),
                // No unmodelled flow without process noise on it: the state is off.
                if noise.process[2] > 0.0 { 0.01 } else { 0.0 },
            )),
            qd,
            r,
        }
    }

    /// Predict one sample ahead; returns the predicted pressure's variance \[MPa^2\].
    pub fn predict(&mut self, i: f64, q0: f64, q1: f64) -> f64 {
        let f0 = self.pump.step_scaled(&self.z, i, q0, q1);
        // The step map's Jacobian by forward differences (display units, so one step
        // size fits every state).
        let mut jac = Matrix3::zeros();
        for c in 0..3 {
            let h = if c == 2 { 1e-5 } else { 1e-4 };
            let mut zc = self.z;
            zc[c] += h;
            let fc = self.pump.step_scaled(&zc, i, q0, q1);
            jac.set_column(c, &((fc - f0) / h));
        }
        self.z = f0;
        self.cov = jac * self.cov * jac.transpose() + self.qd;
        self.cov[(0, 0)]
    }

    /// Update with a measured pressure `y` \[Pa\]; returns the innovation \[MPa\].
    pub fn update(&mut self, y: f64) -> f64 {
        let e = y / SCALE[0] - self.z[0];
        let s = self.cov[(0, 0)] + self.r;
        let k: Vector3<f64> = self.cov.column(0) / s;
        self.z += k * e;
        // Joseph form: stays symmetric and positive definite.
        let mut a = Matrix3::identity();
        a.set_column(0, &(Vector3::new(1.0, 0.0, 0.0) - k));
        self.cov = a * self.cov * a.transpose() + k * k.transpose() * self.r;
        self.z[0] = self.z[0].clamp(0.0, self.pump.p_max / SCALE[0]);
        self.z[1] = self.z[1].clamp(0.0, self.pump.x_max / SCALE[1]);
        e
    }

    /// The estimate in SI: `[P_l Pa, x m, b m^3/s]`.
    pub fn state(&self) -> [f64; 3] {
        [self.z[0] * SCALE[0], self.z[1] * SCALE[1], self.z[2] * SCALE[2]]
    }
}

/// What filtering a record gives: the estimate after each sample's measurement (SI), the
/// innovations \[MPa\] and the predicted pressure variances \[MPa^2\].
#[derive(Debug, Clone, Default)]
pub struct Filtered {
    /// The estimates (SI).
    pub states: Vec<[f64; 3]>,
    /// The innovations \[MPa\].
    pub innovations: Vec<f64>,
    /// The predicted pressure variances \[MPa^2\].
    pub predicted_var: Vec<f64>,
}

/// Filter the record `(i, q, y)` (current \[A\], demand \[m^3/s\], pressure \[Pa\]),
/// sample by sample, up to `n` samples.
pub fn filter(pump: &GreyPump, noise: Noise, i: &[f64], q: &[f64], y: &[f64], n: usize) -> Filtered {
    let n = n.min(y.len());
    let mut out = Filtered {
        states: Vec::with_capacity(n),
        innovations: Vec::with_capacity(n),
        predicted_var: Vec::with_capacity(n),
    };
    if n == 0 {
        return out;
    }
    let mut ekf = Ekf::new(pump, noise, y[0], q[0]);
    out.states.push(ekf.state());
    out.innovations.push(0.0);
    out.predicted_var.push(ekf.cov[(0, 0)]);
    for k in 1..n {
        let v = ekf.predict(i[k - 1], q[k - 1], q[k]);
        out.predicted_var.push(v);
        out.innovations.push(ekf.update(y[k]));
        out.states.push(ekf.state());
    }
    out
}

/// The measurement noise standard deviation \[MPa\] of a record, by covariance matching:
/// filter with a guess, set the variance to the innovations' mean square less the
/// filter's own predicted variance, three times. The first fifth of the record (the
/// filter's transient) is left out.
pub fn measurement_noise(pump: &GreyPump, process: [f64; 3], i: &[f64], q: &[f64], y: &[f64]) -> f64 {
    let mut sd = 0.05;
    let skip = (y.len() / 5).max(20.min(y.len() / 2));
    for _ in 0..3 {
        let f = filter(
            pump,
            Noise {
                process,
                measurement_mpa: sd,
            },
            i,
            q,
            y,
            y.len(),
        );
        let n = (f.innovations.len() - skip).max(1) as f64;
        let e2 = f.innovations[skip..].iter().map(|e| e * e).sum::<f64>() / n;
        let pv = f.predicted_var[skip..].iter().sum::<f64>() / n;
        let v = e2 - pv;
        sd = if v.is_finite() { v.max(1e-6).sqrt() } else { sd };
    }
    sd
}
