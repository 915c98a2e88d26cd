//! The online identifier's cascade structure (`structure = "cascade"`): `rhonn fit`'s
//! continuous-time cascade (`crate::models::cascade`: a chain of limited-integrator
//! neurons with power-law outflows, the first ones hidden, the last one measured)
//! learned one sample at a time.
//!
//! Its parameters (in `rhonn fit`'s unconstrained coordinates: logarithms of the rates,
//! shares and bounds, the exponents through a logistic onto their range) and its levels
//! are the state of an extended Kalman filter: each sample the levels move by the
//! chain's equations (RK4, input held), the parameters stay (no random walk), and the
//! measured output corrects both through their joint covariance. This is the recursive
//! prediction-error method in its Gauss-Newton form (Ljung & Söderström, Theory and
//! Practice of Recursive Identification, MIT Press 1983, section 3.8), and the way
//! Sanchez, Alanis & Loukianov train their discrete-time RHONNs online. The hidden level
//! needs no stand-in: the filter estimates it with the parameters.
//!
//! Why it keeps a hidden neuron stable: the coordinates map onto positive rates and
//! bounds and exponents within their range, so every parameter value the filter reaches
//! is a chain of tanks that drains and stays within its bounds; no estimate can make the
//! frozen model diverge.
//!
//! One filter from one start finds one basin, as one start of `rhonn fit`'s does, so
//! `starts` filters run side by side from `rhonn fit`'s seeded random starts. Each also
//! runs its own free run (levels moved by its current parameters alone, from its
//! filtered levels `settle` samples into each record), and the estimate, the weights and
//! the frozen model are those of the filter whose free run has followed the
//! measurements best this pass. A filter whose numbers stop being finite drops out.

use super::engine::{EngineState, OnlineEngine};
use super::online_spec::{CascadeOnlineSpec, OnlineSpec, Scaling};
use crate::error::{invalid, Error, Result};
use crate::models::cascade::{n_params, random_start, Coords, Params};
use nalgebra::{DMatrix, DVector};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// One filter: its parameter coordinates, levels, their joint covariance, and its own
/// free run with the squared errors it made this pass.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Member {
    th: Vec<f64>,
    x: Vec<f64>,
    p: DMatrix<f64>,
    shadow: Vec<f64>,
    sq: f64,
    count: usize,
    alive: bool,
    /// The output it estimated for the latest sample before seeing it (normalised).
    prior: f64,
    /// The parameters it was given (a stored model's), used until it learns: its
    /// coordinates (logarithms, logits) do not always map back to the very same numbers,
    /// and a model read from its file runs as the one that wrote it, bit for bit.
    exact: Option<Params>,
}

/// The cascade engine with its scaling and the checks of a sample.
#[derive(Debug, Clone)]
pub(super) struct CascadeOnline {
    set: CascadeOnlineSpec,
    co: Coords,
    pub(super) scaling: Scaling,
    period_s: f64,
    members: Vec<Member>,
    best: usize,
    seen: usize,
    /// Whether any sample has been taken.
    started: bool,
    t_last: Option<f64>,
    pub(super) frozen: bool,
    pub(super) free_run: bool,
    u_last: Vec<f64>,
    un: Vec<f64>,
    pub(super) out: Vec<f64>,
    work: Vec<f64>,
}

/// What [`CascadeOnline`] saves around a K-step-ahead prediction.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct CascadeSnapshot {
    members: Vec<Member>,
    best: usize,
    seen: usize,
    t_last: Option<f64>,
    u_last: Vec<f64>,
}

/// The normalised output range the starts are drawn for: the data's own range when
/// `y_bounds` is the identification data's range widened by `margin` on each side
/// (as `rhonn identify` sets it), else two standard deviations about the mean.
fn output_range(scaling: &Scaling, margin: f64) -> (f64, f64) {
    match &scaling.y_bounds {
        Some(b) if margin >= 0.0 => {
            let [lo, hi] = b[0];
            let range = (hi - lo) / (1.0 + 2.0 * margin);
            let (m, s) = (scaling.y_offset[0], scaling.y_scale[0]);
            ((lo + margin * range - m) / s, (hi - margin * range - m) / s)
        }
        _ => (-2.0, 2.0),
    }
}

impl CascadeOnline {
    pub(super) fn new(
        spec: &OnlineSpec,
        ny: usize,
        nu: usize,
        period_s: f64,
        scaling: Scaling,
    ) -> Result<Self> {
        if ny != 1 {
            return Err(invalid(
                "outputs",
                ny,
                "one output with `structure = \"cascade\"` (the last neuron of the chain)",
            ));
        }
        let set = spec.cascade.clone().unwrap_or_default();
        let co = Coords {
            n: set.neurons,
            ni: nu,
            free_exp: set.free_exponents,
        };
        let (ymin, ymax) = output_range(&scaling, spec.output_margin);
        let members = (0..set.starts)
            .map(|s| {
                let mut rng = ChaCha8Rng::seed_from_u64(set.seed.wrapping_add(s as u64));
                Member::new(&set, co, random_start(co, ymin, ymax, 0, &mut rng))
            })
            .collect();
        Ok(CascadeOnline {
            co,
            period_s,
            members,
            best: 0,
            seen: 0,
            started: false,
            t_last: None,
            frozen: false,
            free_run: false,
            u_last: vec![0.0; nu],
            un: vec![0.0; nu],
            out: vec![0.0; 1],
            work: vec![0.0; 5 * set.neurons],
            scaling,
            set,
        })
    }

    /// Take the sample `(t, u, y)`: the estimate of `y(t)` from the samples before it
    /// (the measurement itself at a record's first sample), then learn from `y`.
    pub(super) fn update(&mut self, t: f64, u: &[f64], y: &[f64]) -> Result<&[f64]> {
        self.check_sample(t, u, y)?;
        let s = &self.scaling;
        for (j, v) in u.iter().enumerate() {
            // Not centred: the first neuron's inflow is proportional to the inputs.
            self.un[j] = v / s.u_scale[j];
        }
        let yn = if y[0].is_finite() {
            (y[0] - s.y_offset[0]) / s.y_scale[0]
        } else {
            f64::NAN
        };
        let settling = self.seen < self.set.settle;
        let measure = yn.is_finite() && (!self.free_run || settling);
        let learn = measure && !self.frozen && !self.free_run;
        // Frozen (or free) parameters are known: the filters then estimate the levels only.
        let learn_params = !self.frozen && !self.free_run;
        let h = self.t_last.map_or(1.0, |tl| (t - tl) / self.period_s);
        let (co, set, first, best) = (self.co, &self.set, self.seen == 0, self.best);
        // Frozen, only the chosen filter matters (the others wait, their levels as they were).
        let running = |i: usize, m: &Member| m.alive && (learn_params || i == best);
        for (_, m) in self
            .members
            .iter_mut()
            .enumerate()
            .filter(|(i, m)| running(*i, m))
        {
            if first {
                m.start_record(co, yn);
            } else {
                m.predict(co, set, &self.u_last, h, !learn_params, &mut self.work);
            }
            m.prior = m.params(co).output(&m.x);
            if m.alive && !first && measure {
                m.correct(co, yn, set.measurement_var, learn);
            }
            m.follow(co, yn, settling, set, &self.u_last, h, &mut self.work);
        }
        // A frozen model is the filter chosen while it learned.
        if learn_params || !self.members[self.best].alive {
            self.choose_best(t)?;
        }
        self.out[0] = if first {
            y[0]
        } else {
            self.members[self.best].prior * self.scaling.y_scale[0] + self.scaling.y_offset[0]
        };
        self.u_last.copy_from_slice(&self.un);
        self.seen += 1;
        self.started = true;
        self.t_last = Some(t);
        Ok(&self.out)
    }

    fn check_sample(&self, t: f64, u: &[f64], y: &[f64]) -> Result<()> {
        let s = &self.scaling;
        if u.len() != s.u_scale.len() || y.len() != 1 {
            return Err(invalid(
                "update",
                format!("{} inputs and {} outputs", u.len(), y.len()),
                format!("{} inputs and 1 output", s.u_scale.len()),
            ));
        }
        let measured_needed = !self.free_run || self.seen < self.set.settle;
        super::engine::check_sample_finite(t, u, &y[..1], measured_needed)?;
        if let Some(t_last) = self.t_last.filter(|tl| t <= *tl) {
            return Err(invalid(
                "t",
                t,
                format!("a time after the previous sample's, {t_last} s"),
            ));
        }
        Ok(())
    }

    /// The filter whose free run has followed the measurements best this pass (the
    /// current one until a free run has counted errors); an error when every filter
    /// has dropped out.
    fn choose_best(&mut self, t: f64) -> Result<()> {
        let score = |m: &Member| {
            if !m.alive {
                f64::INFINITY
            } else if m.count == 0 {
                f64::MAX
            } else {
                m.sq / m.count as f64
            }
        };
        if !self.members[self.best].alive || self.members.iter().any(|m| m.count > 0) {
            let (i, best) = self
                .members
                .iter()
                .enumerate()
                .map(|(i, m)| (i, score(m)))
                .min_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)))
                .expect("at least one start");
            if best.is_infinite() {
                let m = &self.members[self.best];
                return Err(Error::NotFinite {
                    what: format!(
                        "every filter of the online cascade at t = {t} s (levels {:?}, parameter coordinates {:?})",
                        m.x, m.th
                    ),
                    cause: "the data or the settings: lower model.cascade.parameter_var or pass_var, or raise measurement_var".into(),
                });
            }
            self.best = i;
        }
        Ok(())
    }

    /// A new pass over the recordings: every filter's parameter variances grow by
    /// `pass_var` (so that it learns again; not before the first sample) and the free
    /// runs' errors start over.
    pub(super) fn new_pass(&mut self) {
        let n = self.co.n;
        // Before the first sample the filters start afresh anyway.
        let widen = if self.started { self.set.pass_var } else { 0.0 };
        for m in &mut self.members {
            for i in n..m.p.nrows() {
                m.p[(i, i)] += widen;
            }
            m.sq = 0.0;
            m.count = 0;
        }
    }

    /// Forget the last samples (a new record starts); the parameters stay.
    pub(super) fn reset(&mut self) {
        self.seen = 0;
        self.t_last = None;
    }

    /// Put the measured neuron's level at the output `y` (output units), in every filter
    /// and free run.
    pub(super) fn set_estimate(&mut self, y: &[f64]) {
        let yn = (y[0] - self.scaling.y_offset[0]) / self.scaling.y_scale[0];
        for m in self.members.iter_mut().filter(|m| m.alive) {
            let p = m.params(self.co);
            let n = m.x.len();
            m.x[n - 1] = p.measured_level(yn);
            m.shadow[n - 1] = m.x[n - 1];
        }
    }

    /// The best filter's parameters as `model.json` stores a cascade's (normalised units:
    /// `b` per input, `k`, `alpha`, `g`, `o`, `xmax` per neuron, `c`), as one vector.
    pub(super) fn weights(&self) -> Vec<Vec<f64>> {
        vec![self.members[self.best].params(self.co).stored()]
    }

    /// One filter with these parameters (checked by the caller's [`Self::check_weights`]).
    pub(super) fn set_weights(&mut self, w: &[Vec<f64>]) {
        let p = Params::from_stored(self.co.n, self.co.ni, &w[0]);
        let mut m = Member::new(&self.set, self.co, self.co.coords(&p));
        m.exact = Some(p);
        self.members = vec![m];
        self.best = 0;
    }

    /// Check stored parameters: a valid cascade.
    pub(super) fn check_weights(&self, w: &[Vec<f64>]) -> Result<()> {
        Params::from_stored(self.co.n, self.co.ni, &w[0]).check()
    }

    pub(super) fn n_terms(&self) -> usize {
        n_params(self.co.n, self.co.ni)
    }

    /// The stored parameters' names: `b[u]`, `k1`, `alpha1`, `g1`, `o1`, `xmax1`, `c`.
    pub(super) fn term_names(&self, inputs: &[String]) -> Vec<String> {
        let n = self.co.n;
        let mut names: Vec<String> = inputs.iter().map(|u| format!("b[{u}]")).collect();
        for (key, count) in [("k", n), ("alpha", n), ("g", n - 1), ("o", n - 1), ("xmax", n)] {
            names.extend((1..=count).map(|i| format!("{key}{i}")));
        }
        names.push("c".into());
        names
    }

    pub(super) fn snapshot(&self) -> CascadeSnapshot {
        CascadeSnapshot {
            members: self.members.clone(),
            best: self.best,
            seen: self.seen,
            t_last: self.t_last,
            u_last: self.u_last.clone(),
        }
    }

    pub(super) fn restore(&mut self, s: &CascadeSnapshot) {
        self.members.clone_from(&s.members);
        self.best = s.best;
        self.seen = s.seen;
        self.t_last = s.t_last;
        self.u_last.clone_from(&s.u_last);
    }
}

impl Member {
    fn new(set: &CascadeOnlineSpec, co: Coords, th: Vec<f64>) -> Self {
        let (n, np) = (co.n, th.len());
        let mut p = DMatrix::zeros(n + np, n + np);
        for i in 0..n + np {
            p[(i, i)] = if i < n { 1.0 } else { set.parameter_var };
        }
        Member {
            th,
            x: vec![0.0; n],
            p,
            shadow: vec![0.0; n],
            sq: 0.0,
            count: 0,
            alive: true,
            prior: 0.0,
            exact: None,
        }
    }

    /// Its parameters: the exact ones it was given, or those of its coordinates.
    fn params(&self, co: Coords) -> Params {
        self.exact.clone().unwrap_or_else(|| co.params(&self.th))
    }

    /// A record starts at the measured output `yn`: the measured level there, the hidden
    /// ones in balance with it, the levels' covariance wide and apart from the
    /// parameters'.
    fn start_record(&mut self, co: Coords, yn: f64) {
        let p = self.params(co);
        p.balanced_levels(p.measured_level(yn), &mut self.x);
        let n = co.n;
        for i in 0..self.p.nrows() {
            for j in 0..self.p.ncols() {
                if (i < n || j < n) && i != j {
                    self.p[(i, j)] = 0.0;
                }
            }
        }
        for i in 0..n {
            self.p[(i, i)] = 1.0;
        }
        self.shadow.copy_from_slice(&self.x);
    }

    /// Move the levels `h` samples with the inputs `u` held and the covariance with
    /// them: `P <- J P J^T + Q`, `J` the step's Jacobian by forward differences. With
    /// `levels_only` the parameters are taken as known: the levels' block alone moves and
    /// their covariance with the parameters is dropped.
    fn predict(
        &mut self,
        co: Coords,
        set: &CascadeOnlineSpec,
        u: &[f64],
        h: f64,
        levels_only: bool,
        work: &mut [f64],
    ) {
        let n = co.n;
        let d = if levels_only { n } else { self.p.nrows() };
        let step = |p: &Params, x: &[f64], work: &mut [f64]| {
            let mut x = x.to_vec();
            p.step(p.inflow(u), &mut x, h, set.substeps, work);
            x
        };
        // The parameters once for the step and the levels' columns; a parameter's column
        // needs its own.
        let base = self.params(co);
        let f0 = step(&base, &self.x, work);
        let mut jac = DMatrix::<f64>::identity(d, d);
        for c in 0..d {
            let fc;
            let dz;
            if c < n {
                let mut x = self.x.clone();
                dz = 1e-6 * x[c].abs().max(1.0);
                x[c] += dz;
                fc = step(&base, &x, work);
            } else {
                let mut th = self.th.clone();
                dz = 1e-6 * th[c - n].abs().max(1.0);
                th[c - n] += dz;
                fc = step(&co.params(&th), &self.x, work);
            }
            for r in 0..n {
                jac[(r, c)] = (fc[r] - f0[r]) / dz;
            }
        }
        self.x = f0;
        let mut p = &jac * self.p.view((0, 0), (d, d)) * jac.transpose();
        for i in 0..n {
            p[(i, i)] += set.level_var * h;
        }
        self.p.view_mut((0, 0), (d, d)).copy_from(&p);
        if levels_only {
            let all = self.p.nrows();
            self.p.view_mut((0, n), (n, all - n)).fill(0.0);
            self.p.view_mut((n, 0), (all - n, n)).fill(0.0);
        }
        if !(self.x.iter().all(|v| v.is_finite()) && self.p.iter().all(|v| v.is_finite())) {
            self.alive = false;
        }
    }

    /// Correct with the measured output `yn` (normalised): the levels always, the
    /// parameters when `learn` (Joseph form: stays symmetric and positive).
    fn correct(&mut self, co: Coords, yn: f64, r: f64, learn: bool) {
        let (n, d) = (co.n, self.p.nrows());
        let (a, c) = (n - 1, d - 1);
        let params = self.params(co);
        let e = yn - params.output(&self.x);
        // The output is the last level plus the offset `c` (the last coordinate); with the
        // parameters known (not learning) the offset carries no uncertainty.
        let hc = if learn { 1.0 } else { 0.0 };
        let s = self.p[(a, a)] + hc * (2.0 * self.p[(a, c)] + self.p[(c, c)]) + r;
        if !(s.is_finite() && s > 0.0) {
            self.alive = false;
            return;
        }
        let mut k = DVector::<f64>::zeros(d);
        for i in 0..d {
            if i < n || learn {
                k[i] = (self.p[(i, a)] + hc * self.p[(i, c)]) / s;
            }
        }
        let mut ikh = DMatrix::<f64>::identity(d, d);
        for i in 0..d {
            ikh[(i, a)] -= k[i];
            ikh[(i, c)] -= hc * k[i];
        }
        self.p = &ikh * &self.p * ikh.transpose() + &k * k.transpose() * r;
        for i in 0..n {
            self.x[i] += k[i] * e;
        }
        for i in n..d {
            self.th[i - n] += k[i] * e;
        }
        if learn {
            // The coordinates moved: the given parameters are no longer its.
            self.exact = None;
        }
        let params = self.params(co);
        for (i, x) in self.x.iter_mut().enumerate() {
            *x = x.clamp(0.0, params.level_bound(i));
        }
        if !(self.th.iter().all(|v| v.is_finite()) && self.p.iter().all(|v| v.is_finite())) {
            self.alive = false;
        }
    }

    /// The member's own free run: it starts from the filtered levels `settle` samples
    /// into a record and then moves by the parameters alone; its squared errors count.
    #[allow(clippy::too_many_arguments)]
    fn follow(
        &mut self,
        co: Coords,
        yn: f64,
        settling: bool,
        set: &CascadeOnlineSpec,
        u: &[f64],
        h: f64,
        work: &mut [f64],
    ) {
        if !self.alive {
            return;
        }
        if settling {
            self.shadow.copy_from_slice(&self.x);
            return;
        }
        let p = self.params(co);
        p.step(p.inflow(u), &mut self.shadow, h, set.substeps, work);
        if yn.is_finite() {
            let e = p.output(&self.shadow) - yn;
            if e.is_finite() {
                self.sq += e * e;
                self.count += 1;
            } else {
                self.alive = false;
            }
        }
    }
}

impl OnlineEngine for CascadeOnline {
    fn update(&mut self, t: f64, u: &[f64], y: &[f64]) -> Result<&[f64]> {
        CascadeOnline::update(self, t, u, y)
    }
    fn estimate(&self) -> &[f64] {
        &self.out
    }
    fn freeze(&mut self, frozen: bool) {
        self.frozen = frozen;
    }
    fn set_free_run(&mut self, free: bool) {
        self.free_run = free;
    }
    fn reset(&mut self) {
        CascadeOnline::reset(self)
    }
    fn new_pass(&mut self) {
        CascadeOnline::new_pass(self)
    }
    fn set_estimate(&mut self, y: &[f64]) {
        CascadeOnline::set_estimate(self, y)
    }
    fn weights(&self) -> Vec<Vec<f64>> {
        CascadeOnline::weights(self)
    }
    fn set_weights(&mut self, w: &[Vec<f64>]) {
        CascadeOnline::set_weights(self, w)
    }
    fn term_names(&self, _outputs: &[String], inputs: &[String]) -> Vec<String> {
        CascadeOnline::term_names(self, inputs)
    }
    fn n_terms(&self) -> usize {
        CascadeOnline::n_terms(self)
    }
    fn scaling(&self) -> &Scaling {
        &self.scaling
    }
    fn set_y_bounds(&mut self, b: Vec<[f64; 2]>) {
        self.scaling.y_bounds = Some(b);
    }
    fn snapshot(&self) -> Box<dyn EngineState> {
        Box::new(CascadeOnline::snapshot(self))
    }
    fn restore(&mut self, s: &dyn EngineState) {
        if let Some(s) = s.as_any().downcast_ref::<CascadeSnapshot>() {
            CascadeOnline::restore(self, s);
        }
    }
    fn check_weights(&self, w: &[Vec<f64>]) -> Result<()> {
        CascadeOnline::check_weights(self, w)
    }
    fn box_clone(&self) -> Box<dyn OnlineEngine> {
        Box::new(self.clone())
    }
}
