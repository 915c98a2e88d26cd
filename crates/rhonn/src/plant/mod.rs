//! The plant: a solenoid-controlled variable-displacement pump feeding a hydraulic
//! line (SPEC.md section 1).

mod params;
mod pump;

pub use params::{PumpParams, PumpParamsSpec};
pub use pump::{Input, PumpSystem, CURRENT_EFF, PLANT_DIM, PUMP_EVENTS, P_LINE, STROKE};
