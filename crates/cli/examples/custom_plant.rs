//! Your own plant, run and written as the shipped ones are: an electric oven whose heating
//! element (`element`, its rise above ambient) warms the chamber (`chamber`), which loses heat
//! by convection and radiation. Two experiments from TOML, each written by the writers of
//! `rhonn run` (trajectory.csv, summary.json, plots, report.html):
//! - online identification of the chamber by a RHONN, then its frozen model on unseen inputs;
//! - a cascade (an outer PI on the chamber sets the element's set-point, an inner loop on the
//!   element drives the heater): a RHONN indirect adaptive inner loop against an inner PI.
//!
//! `cargo run --release --example custom_plant [OUT]` writes OUT/custom-plant-identify and
//! OUT/custom-plant-cascade (default OUT: `out`).
use rhonn::experiment::{run_plant_scenario_on, ScenarioSpec};
use rhonn::plant::{Input, Plant, Quantity};
use std::path::Path;

#[derive(Debug, Clone)]
pub struct Oven(pub Input);
const T_A: f64 = 293.0; // ambient [K]
const STATES: [Quantity; 2] = [
    Quantity::si("element", "K", "heating element's temperature above ambient"),
    Quantity::si("chamber", "K", "chamber's temperature above ambient"),
];
const HEATER: [Quantity; 1] = [Quantity::si("heater", "1", "heater command, 0 to 1")];

#[rustfmt::skip] // one line per method: the whole plant reads at a glance
impl rhonn_ode::System for Oven {
    type State = [f64; 2];
    fn dim(&self) -> usize { 2 }
    fn rhs(&self, t: f64, x: &[f64], dx: &mut [f64]) {
        let (c_e, c_c, p, g, h, k_r) = (500.0, 1000.0, 5000.0, 10.0, 1.0, 5.67e-9); // J/K, J/K, W, W/K, W/K, W/K^4
        let to_chamber = g * (x[0] - x[1]);
        let loss = h * x[1] + k_r * ((x[1] + T_A).powi(4) - T_A.powi(4));
        dx[0] = (p * self.input_at(t, 0) - to_chamber) / c_e;
        dx[1] = (to_chamber - loss) / c_c;
    }
    fn next_breakpoint(&self, t: f64) -> f64 { self.0.next_breakpoint(t) }
}

#[rustfmt::skip]
impl Plant for Oven {
    fn name(&self) -> &'static str { "oven" }
    fn states(&self) -> &'static [Quantity] { &STATES }
    fn inputs(&self) -> &'static [Quantity] { &HEATER }
    fn measured(&self) -> &'static [usize] { &[0, 1] } // both temperatures have a sensor
    fn input_at(&self, t: f64, _k: usize) -> f64 { self.0.at(t).clamp(0.0, 1.0) }
    fn hold_input(&mut self, _k: usize, v: f64) { self.0 = Input::Held(v); }
    fn set_input(&mut self, _k: usize, i: Input) -> rhonn::Result<()> { self.0 = i; Ok(()) }
    // Optional: how long after a set-point step the chamber counts as settled (the figures'
    // settled deviation and overshoot window): three of the 80 s closed loop's time constants.
    fn settle_s(&self) -> f64 { 240.0 }
}

/// Online identification of the chamber from the heater, then the frozen model on heater
/// steps it has not seen.
pub const IDENTIFY: &str = r#"
name = "custom-plant-identify"
duration_s = 6000.0
plant = { kind = "oven" }
input.heater = { kind = "steps", initial = 0.6, steps = [[600.0, 0.2], [1200.0, 0.9], [1800.0, 0.4], [2400.0, 0.7], [3000.0, 0.1], [3600.0, 0.8], [4200.0, 0.3], [4800.0, 1.0], [5400.0, 0.5]] }
identifier = { states = ["element", "chamber"], inputs = ["heater"], state_scale = [300.0, 150.0], degree = 2, a = [0.01, 0.01], law = { kind = "filtered-regressor-ls", p0 = [100.0, 100.0] } }
validation = { duration_s = 2100.0, input.heater = { kind = "steps", initial = 0.3, steps = [[700.0, 0.8], [1400.0, 0.5]] } }
"#;

/// The cascade: an outer PI on the chamber sets the element's set-point (within [0, 900] K;
/// by IMC on the chamber seen from the element, gain about 0.4 and time constant 33 s, for a
/// 80 s closed loop); the inner loop drives the heater: RHONN indirect adaptive control of
/// the element (a first-order, input-affine state; pole 0.2 1/s; its gain guess 0.1 = P /
/// (C_e 100 K) per second) against an inner PI tuned by IMC (gain 500 K, time constant 50 s,
/// 10 s closed loop).
pub const CASCADE: &str = r#"
name = "custom-plant-cascade"
duration_s = 2400.0
plant = { kind = "oven" }

[control]
input = "heater"
input_range = [0.0, 1.0]
output = "chamber"
setpoint = { kind = "steps", initial = 150.0, steps = [[600.0, 300.0], [1200.0, 400.0], [1800.0, 250.0]] }
period_s = 1.0
controller = { kind = "cascade", inner_range = [0.0, 900.0], outer = { kind = "pi", state = "chamber", kp = 1.0, ti_s = 33.0 }, inner = { kind = "rhonn-indirect", state = "element", lambda_per_s = 0.2, y_scale = 100.0, gain0 = 0.1 } }
baseline = { kind = "cascade", inner_range = [0.0, 900.0], outer = { kind = "pi", state = "chamber", kp = 1.0, ti_s = 33.0 }, inner = { kind = "pi", state = "element", kp = 0.01, ti_s = 50.0 } }
"#;

/// Run both experiments on the oven and write each into `out/<name>` as `rhonn run` writes a
/// shipped plant's run; returns the files written.
pub fn run(out: &Path) -> Result<Vec<std::path::PathBuf>, Box<dyn std::error::Error>> {
    let mut files = Vec::new();
    for (text, source) in [(IDENTIFY, "IDENTIFY"), (CASCADE, "CASCADE")] {
        let spec = ScenarioSpec::from_toml(text, source)?;
        let output = run_plant_scenario_on(&Oven(Input::Held(0.0)), &spec)?;
        for f in &output.summary.findings {
            println!("{}: {f}", spec.name);
        }
        files.extend(rhonn_app::save_plant_run(&out.join(&spec.name), &output)?.files);
    }
    Ok(files)
}

#[allow(dead_code)] // a test includes this file as a module and calls `run`
fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args().nth(1).unwrap_or_else(|| "out".into());
    for f in run(Path::new(&out))? {
        println!("  wrote {}", f.display());
    }
    Ok(())
}
