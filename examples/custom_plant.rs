//! Your own plant: an electric oven losing heat by convection and radiation, `C dT/dt = P u - h (T - T_a)
//! - k_r (T^4 - T_a^4)`, heater u in [0, 1], state `x = T - T_a`. Identified online by a RHONN, then
//! controlled, RHONN indirect adaptive vs a PI: `cargo run --release --example custom_plant`
use rhonn::control::{IndirectSettings, Pi, RhonnIndirect};
use rhonn::experiment::any_plant::{closed_loop, identify};
use rhonn::ident::IdentifierSpec;
use rhonn::plant::{Input, Plant, Quantity};
use rhonn::signal::{PiecewiseLinear, Signal};

#[derive(Debug, Clone)]
struct Oven(Input);
const T_A: f64 = 293.0; // ambient [K]
const RISE: [Quantity; 1] = [Quantity::si("rise", "K", "temperature above ambient")];
const HEATER: [Quantity; 1] = [Quantity::si("heater", "1", "heater command")];

#[rustfmt::skip] // one line per method: the whole plant reads at a glance
impl rhonn_ode::System for Oven {
    type State = [f64; 1];
    fn dim(&self) -> usize { 1 }
    fn rhs(&self, t: f64, x: &[f64], dx: &mut [f64]) {
        let (c, p, h, k_r) = (2000.0, 2000.0, 1.0, 5.67e-9); // J/K, W, W/K, W/K^4
        let loss = h * x[0] + k_r * ((x[0] + T_A).powi(4) - T_A.powi(4));
        dx[0] = (p * self.input_at(t, 0) - loss) / c;
    }
    fn next_breakpoint(&self, t: f64) -> f64 { self.0.next_breakpoint(t) }
}

#[rustfmt::skip]
impl Plant for Oven {
    fn states(&self) -> &'static [Quantity] { &RISE }
    fn inputs(&self) -> &'static [Quantity] { &HEATER }
    fn input_at(&self, t: f64, _k: usize) -> f64 { self.0.at(t).clamp(0.0, 1.0) }
    fn hold_input(&mut self, _k: usize, v: f64) { self.0 = Input::Held(v); }
}

/// Levels held for `hold_s` each, 5 s ramps between.
#[rustfmt::skip]
fn steps(levels: &[f64], hold_s: f64) -> Signal {
    let t = |k: usize| k as f64 * (hold_s + 5.0);
    let pts = levels.iter().enumerate().flat_map(|(k, &v)| [(t(k), v), (t(k) + hold_s, v)]);
    Signal::piecewise(PiecewiseLinear::new(pts.collect()), f64::MIN, f64::MAX)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let spec: IdentifierSpec = toml::from_str(
        r#"states = ["rise"]
        inputs = ["heater"]
        state_scale = [150.0]
        degree = 2
        a = [0.01]
        law = { kind = "filtered-regressor-ls", p0 = [100.0] }"#,
    )?;
    let levels = [0.6, 0.2, 0.9, 0.4, 0.7, 0.1, 0.8, 0.3, 1.0, 0.5];
    let train = Oven(Input::Signal(steps(&levels, 595.0)));
    let is = spec.check_for(&train)?;
    let online = identify(train, &[0.0], &is, 6000.0, 1.0, None)?;
    let unseen = Oven(Input::Signal(steps(&[0.3, 0.8, 0.5], 695.0)));
    let free = identify(unseen, &[0.0], &is, 2100.0, 1.0, Some(&online.weights))?;
    let fit_on = online.fit_percent_after(3000.0)[0];
    let fit_free = free.fit_percent_after(0.0)[0];
    println!("identification: fit {fit_on:.1} % online (last half), {fit_free:.1} % free run, unseen input");
    let setpoint = steps(&[150.0, 300.0, 400.0, 250.0], 595.0);
    // Pole 0.02 1/s, the neuron sees the rise in 100 K; the PI by IMC on the plant linearised
    // at 307 K rise (gain 339 K, time constant 340 s) for the same closed-loop time constant.
    let settings = IndirectSettings::for_pole(0.02, 100.0);
    let mut pi = Pi::new(340.0 * settings.lambda_per_s / 339.0, 340.0, 1.0, 0.0, 0.0, 1.0);
    let mut adaptive = RhonnIndirect::new(settings, 0, (0.0, 1.0), 1.0, 0.01, 0.0);
    for ctl in [&mut adaptive as &mut dyn rhonn::control::Controller, &mut pi] {
        let run = closed_loop(Oven(Input::Held(0.0)), &[0.0], ctl, 0, &setpoint, 1.0, 2400.0)?;
        let (c, e) = (run.controller, run.final_error());
        println!(
            "control ({c}): IAE {:.0} K s, ISE {:.0} K^2 s, final error {e:.2} K",
            run.iae, run.ise
        );
    }
    Ok(())
}
