//! Unit conversions. The code works in SI; people read MPa, mm and dm^3/s.

/// Pascal per megapascal.
pub const PA_PER_MPA: f64 = 1e6;
/// Metre per millimetre.
pub const M_PER_MM: f64 = 1e-3;
/// Cubic metre per cubic decimetre (litre).
pub const M3_PER_DM3: f64 = 1e-3;
/// Square metre per square decimetre.
pub const M2_PER_DM2: f64 = 1e-2;
/// Second per millisecond.
pub const S_PER_MS: f64 = 1e-3;

/// Pa -> MPa.
pub fn mpa(p_pa: f64) -> f64 {
    p_pa / PA_PER_MPA
}
/// m -> mm.
pub fn mm(x_m: f64) -> f64 {
    x_m / M_PER_MM
}
/// m^3/s -> dm^3/s.
pub fn dm3_s(q_m3_s: f64) -> f64 {
    q_m3_s / M3_PER_DM3
}
