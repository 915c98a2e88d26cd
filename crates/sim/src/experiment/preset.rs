//! The scenarios shipped with rhonn (the TOML files in the repository's `scenarios/`
//! folder, compiled in), and loading a scenario by name or path.

use super::scenario::{is_plant_scenario, ScenarioSpec};
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
    (
        "tanks-simulate",
        include_str!("../../../../scenarios/tanks-simulate.toml"),
    ),
];

/// A scenario from its TOML text in the one format (`source` names it in errors): the
/// one scenario type of every plant. The checks that need no plant run here; the
/// plant's own at the run (before anything is written).
pub fn parse(text: &str, source: &str) -> Result<ScenarioSpec> {
    let former = former_pump_keys(text);
    if !former.is_empty() {
        return Err(Error::Parse {
            source_name: source.to_string(),
            message: format!("{} and no `kind` in [plant]: the pump's former scenario format, now written in the one format every plant uses (`[plant] kind = \"pump\"`; the keys' mapping: docs/reference/scenarios.md, \"The pump\")", former.join(", ")),
        });
    }
    let spec = ScenarioSpec::from_toml(text, source)?;
    spec.check_common()?;
    Ok(spec)
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
            let spec = parse(text, name).expect("shipped scenarios parse");
            (*name, spec.description)
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

/// A scenario of any plant, the pump's too: a shipped scenario by name, or a TOML file
/// by path (a name with a `/` or ending in `.toml` is always a path; otherwise a shipped
/// name wins over a file of that name).
pub fn load_any(name_or_path: &str) -> Result<ScenarioSpec> {
    parse(&text_of(name_or_path)?, name_or_path)
}

/// A scenario given as TOML `text` (`name_or_path` names it in errors), or without a
/// text by name or path (see [`load_any`]): Python's `rhonn.run(name, toml_text)`.
pub fn load_or_parse(name_or_path: &str, text: Option<&str>) -> Result<ScenarioSpec> {
    match text {
        Some(text) => parse(text, name_or_path),
        None => load_any(name_or_path),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_shipped_scenario_parses_and_checks() {
        for (name, _) in SHIPPED {
            let spec = load_any(name).unwrap();
            assert_eq!(spec.name, *name);
            assert!(!spec.description.is_empty());
            spec.check_common().unwrap();
            spec.run_summary().unwrap();
        }
    }

    #[test]
    fn unknown_names_list_the_shipped_ones() {
        let e = load_any("thesis-ch9").unwrap_err().to_string();
        assert_eq!(
            e,
            "unknown scenario `thesis-ch9`: not a file, and not one of the shipped scenarios (thesis-ch3, regulated-pi, thesis-ch5, pump-identify, pump-validate, control-adaptive, control-adaptive-gentle, control-adaptive-fast, tanks-identify, tanks-control, tanks-simulate)"
        );
        assert!(load_any("nope/x.toml")
            .unwrap_err()
            .to_string()
            .contains("its folder nope does not exist"));
    }

    #[test]
    fn unknown_keys_are_errors() {
        let text = SHIPPED[0].1.replace("duration_s", "duration_s = 1.0\ndurtion_s");
        let e = parse(&text, "x.toml").unwrap_err().to_string();
        assert!(
            e.contains("x.toml") && e.contains("unknown field `durtion_s`"),
            "{e}"
        );
    }

    #[test]
    fn the_pumps_former_format_is_refused_with_the_way_out() {
        let old = "name = \"x\"\nduration_s = 1.0\noutput_interval_ms = 1.0\n[current_a]\nkind = \"constant\"\nvalue = 0.1\n";
        let e = parse(old, "old.toml").unwrap_err().to_string();
        assert!(
            e.contains("old.toml")
                && e.contains("`output_interval_ms`, `[current_a]`")
                && e.contains("scenarios.md"),
            "{e}"
        );
        // Any other text without a kind: the reader's own error, with its line.
        let e = parse("name = \"x\"\nduration_s = 1.0\n[plant]\n", "t.toml")
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 3") && e.contains("missing field `kind`"), "{e}");
    }
}
