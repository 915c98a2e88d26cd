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

/// Column-name suffixes (after the last `_`) that name one unit, and the unit printed. Case
/// matters where a letter means two things (`_m` metres; `_M` nothing), and only suffixes a
/// signal's name would not end in otherwise are listed (not `_v`, `_x`, `_p`).
const SUFFIXES: [(&str, &str); 27] = [
    ("V", "V"),
    ("mV", "mV"),
    ("kV", "kV"),
    ("A", "A"),
    ("mA", "mA"),
    ("m", "m"),
    ("mm", "mm"),
    ("cm", "cm"),
    ("um", "µm"),
    ("s", "s"),
    ("ms", "ms"),
    ("pa", "Pa"),
    ("Pa", "Pa"),
    ("kpa", "kPa"),
    ("kPa", "kPa"),
    ("mpa", "MPa"),
    ("MPa", "MPa"),
    ("bar", "bar"),
    ("N", "N"),
    ("Nm", "N m"),
    ("W", "W"),
    ("kW", "kW"),
    ("K", "K"),
    ("degC", "degC"),
    ("rad", "rad"),
    ("deg", "deg"),
    ("Hz", "Hz"),
];

/// The unit a column's name ends in, when its suffix names one unambiguously
/// (`y_outlet_temp_V` in V, `p_line_pa` in Pa, `x_mm` in mm); None for any other name
/// (`y`, `speed_v`, a suffix with no stem such as `_V`).
pub fn from_column_name(name: &str) -> Option<&'static str> {
    let (stem, suffix) = name.rsplit_once('_')?;
    if stem.is_empty() {
        return None;
    }
    SUFFIXES.iter().find(|(s, _)| *s == suffix).map(|(_, u)| *u)
}

#[cfg(test)]
mod tests {
    use super::from_column_name;

    #[test]
    fn a_columns_unit_is_read_from_an_unambiguous_suffix_only() {
        assert_eq!(from_column_name("y_outlet_temp_V"), Some("V"));
        assert_eq!(from_column_name("p_line_pa"), Some("Pa"));
        assert_eq!(from_column_name("p_meas_mpa"), Some("MPa"));
        assert_eq!(from_column_name("x_um"), Some("µm"));
        for none in ["y", "u", "speed_v", "_V", "y_M", "y_", "p_meas", "tank_level"] {
            assert_eq!(from_column_name(none), None, "{none}");
        }
    }
}
