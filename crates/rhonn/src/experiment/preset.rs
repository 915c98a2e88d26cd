//! The scenarios shipped with rhonn (the TOML files in the repository's `scenarios/`
//! folder, compiled in), and loading a scenario by name or path.

use super::plant_scenario::{is_plant_scenario, PlantScenarioSpec};
use super::pump_settings::ScenarioSpec;
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
        let former = former_pump_keys(text);
        if !former.is_empty() {
            return Err(Error::Parse {
                source_name: source.to_string(),
                message: format!("{} and no `kind` in [plant]: the pump's former scenario format, now written in the one format every plant uses (`[plant] kind = \"pump\"`; the keys' mapping: docs/reference/scenarios.md, \"The pump\")", former.join(", ")),
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

/// The keys of the pump's former scenario format in `text` (a TOML text without
/// `[plant] kind`), as `key` or `[section]`; empty for any other text, whose errors the
/// one format's reader gives.
fn former_pump_keys(text: &str) -> Vec<String> {
    let Ok(t) = toml::from_str::<toml::Table>(text) else {
        return Vec::new();
    };
    if is_plant_scenario(text) {
        return Vec::new();
    }
    [
        "output_interval_ms",
        "controller",
        "current_a",
        "demand_dm3_s",
        "initial",
    ]
    .iter()
    .filter(|k| t.contains_key(**k))
    .map(|k| match t[*k].is_table() {
        true => format!("`[{k}]`"),
        false => format!("`{k}`"),
    })
    .collect()
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
        return crate::error::read_text(path).map_err(|e| Error::Io {
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

/// A scenario given as TOML `text` (`name_or_path` names it in errors), or without a
/// text by name or path (see [`load_any`]): Python's `rhonn.run(name, toml_text)`.
pub fn load_or_parse(name_or_path: &str, text: Option<&str>) -> Result<AnyScenario> {
    match text {
        Some(text) => AnyScenario::parse(text, name_or_path),
        None => load_any(name_or_path),
    }
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

    #[test]
    fn the_pumps_former_format_is_refused_with_the_way_out() {
        let old = "name = \"x\"\nduration_s = 1.0\noutput_interval_ms = 1.0\n[current_a]\nkind = \"constant\"\nvalue = 0.1\n";
        let e = AnyScenario::parse(old, "old.toml").unwrap_err().to_string();
        assert!(
            e.contains("old.toml")
                && e.contains("`output_interval_ms`, `[current_a]`")
                && e.contains("scenarios.md"),
            "{e}"
        );
        // Any other text without a kind: the reader's own error, with its line.
        let e = AnyScenario::parse("name = \"x\"\nduration_s = 1.0\n[plant]\n", "t.toml")
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 3") && e.contains("missing field `kind`"), "{e}");
    }
}
