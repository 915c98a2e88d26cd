//! The `ode_solvers` crate's Dopri5 as an independent oracle on smooth problems.
#![allow(clippy::excessive_precision)]

use ode_solvers::{Vector2, Vector4};
use rhonn_ode::{Dopri5, Options, StepResult, System};

struct VdP(f64);
impl System for VdP {
    type State = [f64; 2];
    fn dim(&self) -> usize {
        2
    }
    fn rhs(&self, _t: f64, x: &[f64], dx: &mut [f64]) {
        dx[0] = x[1];
        dx[1] = self.0 * (1.0 - x[0] * x[0]) * x[1] - x[0];
    }
}
impl ode_solvers::System<f64, Vector2<f64>> for VdP {
    fn system(&self, _t: f64, y: &Vector2<f64>, dy: &mut Vector2<f64>) {
        dy[0] = y[1];
        dy[1] = self.0 * (1.0 - y[0] * y[0]) * y[1] - y[0];
    }
}

/// The restricted three-body Arenstorf orbit (Hairer, Norsett, Wanner I, II.0).
struct Arenstorf;
const MU: f64 = 0.012277471;
fn arenstorf(y: &[f64], dy: &mut [f64]) {
    let mu1 = 1.0 - MU;
    let d1 = ((y[0] + MU).powi(2) + y[1].powi(2)).powf(1.5);
    let d2 = ((y[0] - mu1).powi(2) + y[1].powi(2)).powf(1.5);
    dy[0] = y[2];
    dy[1] = y[3];
    dy[2] = y[0] + 2.0 * y[3] - mu1 * (y[0] + MU) / d1 - MU * (y[0] - mu1) / d2;
    dy[3] = y[1] - 2.0 * y[2] - mu1 * y[1] / d1 - MU * y[1] / d2;
}
impl System for Arenstorf {
    type State = [f64; 4];
    fn dim(&self) -> usize {
        4
    }
    fn rhs(&self, _t: f64, x: &[f64], dx: &mut [f64]) {
        arenstorf(x, dx);
    }
}
impl ode_solvers::System<f64, Vector4<f64>> for Arenstorf {
    fn system(&self, _t: f64, y: &Vector4<f64>, dy: &mut Vector4<f64>) {
        let mut d = [0.0; 4];
        arenstorf(y.as_slice(), &mut d);
        for i in 0..4 {
            dy[i] = d[i];
        }
    }
}

fn ours<S: System>(sys: S, x0: S::State, t_end: f64, tol: f64) -> (Vec<f64>, u64) {
    let dim = sys.dim();
    let mut s = Dopri5::new(sys, 0.0, x0, Options::uniform(dim, tol, tol)).unwrap();
    while !matches!(s.step(t_end).unwrap(), StepResult::Reached { .. }) {}
    (s.state().to_vec(), s.stats().rhs_evaluations)
}

#[test]
fn van_der_pol_agrees_with_ode_solvers() {
    let (x, _) = ours(VdP(1.0), [2.0, 0.0], 10.0, 1e-10);
    let mut o = ode_solvers::Dopri5::new(VdP(1.0), 0.0, 10.0, 10.0, Vector2::new(2.0, 0.0), 1e-10, 1e-10);
    o.set_output(ode_solvers::OutputType::Sparse);
    o.integrate().unwrap();
    let y = o.y_out().last().unwrap();
    assert!(
        (x[0] - y[0]).abs() < 1e-7 && (x[1] - y[1]).abs() < 1e-7,
        "{x:?} vs {y:?}"
    );
}

#[test]
fn arenstorf_orbit_closes_and_agrees_with_ode_solvers() {
    let t_end = 17.0652165601579625588917206249;
    let y0 = [0.994, 0.0, 0.0, -2.00158510637908252240537862224];
    let (x, n_ours) = ours(Arenstorf, y0, t_end, 1e-10);
    let mut o = ode_solvers::Dopri5::new(
        Arenstorf,
        0.0,
        t_end,
        t_end,
        Vector4::from_row_slice(&y0),
        1e-10,
        1e-10,
    );
    o.set_output(ode_solvers::OutputType::Sparse);
    let st = o.integrate().unwrap();
    let y = o.y_out().last().unwrap();
    for i in 0..2 {
        assert!((x[i] - y[i]).abs() < 1e-5, "{x:?} vs {y:?}");
        // The orbit is periodic: it returns to its start.
        assert!((x[i] - y0[i]).abs() < 1e-4, "{x:?}");
    }
    // Same method, comparable work (within a factor of 1.5).
    let n_theirs = st.num_eval as f64;
    let ratio = n_ours as f64 / n_theirs;
    assert!((0.66..1.5).contains(&ratio), "{n_ours} vs {n_theirs}");
}
