//! A cascade's training residuals, and the Jacobian columns of its hidden initial
//! states computed from one record's free run (`cascade.rs` trains with them).

use super::{logistic, simulate, Coords, Params};

/// The training residuals of a cascade: every record's free run (from its hidden initial
/// states, coordinates after the model's) minus its output, normalised, record after
/// record.
pub(crate) struct FreeRuns<'a> {
    co: Coords,
    data: &'a [(Vec<Vec<f64>>, Vec<f64>)],
    /// Where each record's residuals start.
    starts_at: Vec<usize>,
}

impl<'a> FreeRuns<'a> {
    /// The residuals of the records `data` (normalised inputs and output).
    pub(crate) fn new(co: Coords, data: &'a [(Vec<Vec<f64>>, Vec<f64>)]) -> FreeRuns<'a> {
        let starts_at = data
            .iter()
            .scan(0, |at, (_, y)| {
                let s = *at;
                *at += y.len() - 1;
                Some(s)
            })
            .collect();
        FreeRuns { co, data, starts_at }
    }

    /// Record `q`'s residuals at coordinates `th` into `buf`, its first sample's (zero: the
    /// free run starts at the measurement) included (false: not simulated).
    fn record(&self, p: &Params, th: &[f64], q: usize, buf: &mut Vec<f64>) -> bool {
        let (n, nm) = (self.co.n, self.co.n_model());
        let (u, y) = &self.data[q];
        let hidden: Vec<f64> = (0..n - 1)
            .map(|i| p.xmax[i] * logistic(th[nm + q * (n - 1) + i]))
            .collect();
        if simulate(p, u, &hidden, y[0], y.len(), buf).is_err() {
            return false;
        }
        for (a, b) in buf.iter_mut().zip(y) {
            *a -= b;
        }
        true
    }

    /// Every record's residuals at `th` into `out` (false: a record not simulated).
    pub(crate) fn all(&self, th: &[f64], out: &mut Vec<f64>) -> bool {
        let p = self.co.params(th);
        out.clear();
        let mut buf = Vec::new();
        for q in 0..self.data.len() {
            if !self.record(&p, th, q, &mut buf) {
                return false;
            }
            out.extend_from_slice(&buf[1..]);
        }
        true
    }

    /// The residuals at `th`, which differs from the point of the residuals `r0` in
    /// coordinate `c` alone: a hidden initial state moves its own record's free run only,
    /// so that record is simulated and the others' residuals kept (the same bits as
    /// [`FreeRuns::all`]: a record's simulation depends on the weights and its own
    /// states). On several records this spares most of the Jacobian's simulations of
    /// the hidden states (the coupled drives' fit 11 % faster).
    pub(crate) fn column(&self, th: &[f64], c: usize, r0: &[f64], out: &mut Vec<f64>) -> bool {
        let nm = self.co.n_model();
        if c < nm {
            return self.all(th, out);
        }
        let q = (c - nm) / (self.co.n - 1);
        let mut buf = Vec::new();
        if !self.record(&self.co.params(th), th, q, &mut buf) {
            return false;
        }
        out.clear();
        out.extend_from_slice(r0);
        out[self.starts_at[q]..self.starts_at[q] + buf.len() - 1].copy_from_slice(&buf[1..]);
        true
    }
}
