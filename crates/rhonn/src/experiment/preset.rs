//! The scenarios shipped with rhonn (the TOML files in the repository's `scenarios/`
//! folder, compiled in), and loading a scenario by name or path.

use super::plant_scenario::{is_plant_scenario, PlantScenarioSpec};
use super::scenario::ScenarioSpec;
use crate::error::{Error, Result};
use std::path::Path;

/// `(name, TOML text)` of every shipped scenario.
pub const SHIPPED: &[(&str, &str)] = &[
    (
        "thesis-ch3",
        include_str!("../../../../scenarios/thesis-ch3.toml"),
    ),
    (
        "regulated-pi",
        include_str!("../../../../scenarios/regulated-pi.toml"),
    ),
    (
        "thesis-ch5",
        include_str!("../../../../scenarios/thesis-ch5.toml"),
    ),
    (
        "pump-identify",
        include_str!("../../../../scenarios/pump-identify.toml"),
    ),
    (
        "pump-validate",
        include_str!("../../../../scenarios/pump-validate.toml"),
    ),
    (
        "control-adaptive",
        include_str!("../../../../scenarios/control-adaptive.toml"),
    ),
    (
        "control-adaptive-gentle",
        include_str!("../../../../scenarios/control-adaptive-gentle.toml"),
    ),
    (
        "control-adaptive-fast",
        include_str!("../../../../scenarios/control-adaptive-fast.toml"),
    ),
    (
        "tanks-identify",
        include_str!("../../../../scenarios/tanks-identify.toml"),
    ),
    (
        "tanks-control",
        include_str!("../../../../scenarios/tanks-control.toml"),
    ),
];

/// A scenario of the one format: the pump's lowered to its own runner's settings, any
/// other plant's as written.
#[derive(Debug, Clone, PartialEq)]
pub enum AnyScenario {
    /// The pump's (`[plant] kind = "pump"`), lowered.
    Pump(Box<ScenarioSpec>),
    /// Any other plant's (`[plant] kind = "tanks"`, ...).
    Plant(Box<PlantScenarioSpec>),
}

impl AnyScenario {
    /// Its name.
    pub fn name(&self) -> &str {
        match self {
            AnyScenario::Pump(s) => &s.name,
            AnyScenario::Plant(s) => &s.name,
        }
    }
    /// Its one-line description.
    pub fn description(&self) -> &str {
        match self {
            AnyScenario::Pump(s) => &s.description,
            AnyScenario::Plant(s) => &s.description,
        }
    }
    /// A scenario from its TOML text; `source` names it in errors. The pump's
    /// (`[plant] kind = "pump"`) is lowered to its own runner's settings and checked.
    pub fn parse(text: &str, source: &str) -> Result<Self> {
        if toml::from_str::<toml::Table>(text).is_ok() && !is_plant_scenario(text) {
            return Err(Error::Parse {
                source_name: source.to_string(),
                message: "no `kind` in a [plant] section: every scenario names its plant (`[plant] kind = \"pump\"`, \"tanks\" or a registered kind). The pump's former format (`output_interval_ms`, `[controller]`, `[current_a]`) is now written in the one format: see docs/reference/scenarios.md, \"The pump\"".into(),
            });
        }
        let spec = PlantScenarioSpec::from_toml(text, source)?;
        if spec.plant.kind == "pump" {
            let lowered = super::pump_scenario::lower_checked(&spec)?;
            Ok(AnyScenario::Pump(Box::new(lowered)))
        } else {
            Ok(AnyScenario::Plant(Box::new(spec)))
        }
    }
}

/// Names and one-line descriptions of the shipped scenarios.
pub fn list() -> Vec<(&'static str, String)> {
    SHIPPED
        .iter()
        .map(|(name, text)| {
            let spec = AnyScenario::parse(text, name).expect("shipped scenarios parse");
            (*name, spec.description().to_string())
        })
        .collect()
}

/// The text of a shipped scenario by name, or of a TOML file by path. A name with a `/`
/// or ending in `.toml` is always a path; otherwise a shipped name wins over a file of
/// that name.
fn text_of(name_or_path: &str) -> Result<String> {
    let looks_like_path = name_or_path.contains('/') || name_or_path.ends_with(".toml");
    if !looks_like_path {
        if let Some((_, text)) = SHIPPED.iter().find(|(n, _)| *n == name_or_path) {
            return Ok(text.to_string());
        }
    }
    let path = Path::new(name_or_path);
    if path.is_file() || looks_like_path || path.exists() {
        return std::fs::read_to_string(path).map_err(|e| Error::Io {
            path: name_or_path.to_string(),
            message: crate::error::path_problem(path, &e),
        });
    }
    Err(Error::UnknownScenario {
        name: name_or_path.to_string(),
        known: SHIPPED.iter().map(|(n, _)| *n).collect::<Vec<_>>().join(", "),
    })
}

/// A scenario of any plant by name or path (see [`load`]).
pub fn load_any(name_or_path: &str) -> Result<AnyScenario> {
    AnyScenario::parse(&text_of(name_or_path)?, name_or_path)
}

/// A pump scenario by name or path; a scenario of another plant is an error saying so.
pub fn load(name_or_path: &str) -> Result<ScenarioSpec> {
    match load_any(name_or_path)? {
        AnyScenario::Pump(s) => Ok(*s),
        AnyScenario::Plant(s) => Err(crate::error::invalid(
            "plant.kind",
            format!("\"{}\" (scenario `{}`)", s.plant.kind, s.name),
            "the pump here: this call runs pump scenarios (use `load_any`)",
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_shipped_scenario_parses_and_checks() {
        for (name, _) in SHIPPED {
            match load_any(name).unwrap() {
                AnyScenario::Pump(spec) => {
                    assert_eq!(spec.name, *name);
                    spec.check().unwrap();
                    assert!(!spec.description.is_empty());
                }
                AnyScenario::Plant(spec) => {
                    assert_eq!(spec.name, *name);
                    spec.check_common().unwrap();
                    assert!(!spec.description.is_empty());
                }
            }
        }
    }

    #[test]
    fn unknown_names_list_the_shipped_ones() {
        let e = load("thesis-ch9").unwrap_err().to_string();
        assert_eq!(
            e,
            "unknown scenario `thesis-ch9`: not a file, and not one of the shipped scenarios (thesis-ch3, regulated-pi, thesis-ch5, pump-identify, pump-validate, control-adaptive, control-adaptive-gentle, control-adaptive-fast, tanks-identify, tanks-control)"
        );
        assert!(load("nope/x.toml")
            .unwrap_err()
            .to_string()
            .contains("its folder nope does not exist"));
    }

    #[test]
    fn unknown_keys_are_errors() {
        let text = SHIPPED[0].1.replace("duration_s", "duration_s = 1.0\ndurtion_s");
        let e = AnyScenario::parse(&text, "x.toml").unwrap_err().to_string();
        assert!(
            e.contains("x.toml") && e.contains("unknown field `durtion_s`"),
            "{e}"
        );
    }
}
