//! The rules of a fit's structure arguments, in one place for both doors (`rhonn fit` and
//! Python's `rhonn.fit`): whether the structure is selected, judged how and within what
//! budget. Each rule names the arguments in the door's own words ([`Door`]); the library
//! below names its fields by its own (`select_steps_ahead`, `budget`), which the command
//! line renames to its flags ([`Door::rename`]).

use rhonn::sysid::select::SelectOptions;
use rhonn_report::{Error, Result};

/// How a door spells the fit's arguments in messages.
#[derive(Debug, Clone, Copy)]
pub struct Door {
    /// The structure's mode, and its two values.
    pub select: &'static str,
    /// `select` set to auto.
    pub auto: &'static str,
    /// `select` set to none.
    pub none: &'static str,
    /// How many samples ahead the selection judges.
    pub steps_ahead: &'static str,
    /// The work budget's factor.
    pub budget: &'static str,
    /// The model spec.
    pub model: &'static str,
    /// The output columns.
    pub outputs: &'static str,
    /// The input and output columns together (`--inputs and --outputs`).
    pub inputs_and_outputs: &'static str,
    /// The training records.
    pub data: &'static str,
    /// The option that resamples the data (None: the door fits the samples as given).
    pub resample: Option<&'static str>,
    /// What to do when the times are milliseconds, given the sample time in seconds.
    pub milliseconds: fn(f64) -> String,
}

/// `rhonn fit`'s flags.
pub const COMMAND_LINE: Door = Door {
    select: "--select",
    auto: "--select auto",
    none: "--select none",
    steps_ahead: "--select-steps-ahead",
    budget: "--budget",
    model: "--model",
    outputs: "--outputs",
    inputs_and_outputs: "--inputs and --outputs",
    data: "--data",
    resample: Some("--resample"),
    milliseconds: |_| "give `t` in seconds (divide it by 1,000)".to_string(),
};

/// Python's `rhonn.fit` keyword arguments (the library's own field names).
pub const PYTHON: Door = Door {
    select: "select",
    auto: "select=\"auto\"",
    none: "select=\"none\"",
    steps_ahead: "select_steps_ahead",
    budget: "budget",
    model: "model",
    outputs: "outputs",
    inputs_and_outputs: "u and y",
    data: "u and y",
    resample: None,
    milliseconds: |s| format!("pass dt={s}"),
};

impl Door {
    /// A warning on the data with its advice in this door's terms.
    pub fn data_warning(&self, w: &rhonn::sysid::DataWarning) -> String {
        let resample = |s: f64| {
            match self.resample {
            Some(flag) => format!("Resample to a longer sample time, e.g. `{flag} {s}`"),
            None => format!(
                "Resample the recordings to a longer sample time before fitting (they are fitted as given), e.g. to about {s} s by averaging blocks of samples"
            ),
        }
        };
        w.worded(&resample, &self.milliseconds)
    }

    /// A library error with its field named as this door names it (the library's
    /// `select_steps_ahead` is the command line's `--select-steps-ahead`).
    pub fn rename(&self, e: rhonn::Error) -> rhonn::Error {
        e.with_field_named("select_steps_ahead", self.steps_ahead)
            .with_field_named("budget", self.budget)
            .with_field_named("select", self.select)
            .with_field_named("outputs", self.outputs)
            .with_field_named("inputs and outputs", self.inputs_and_outputs)
            .with_field_named("data", self.data)
    }
}

/// A fit's structure arguments as a door received them.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FitArgs<'a> {
    /// A model spec was given.
    pub model_given: bool,
    /// `auto`, `none`, or not given (auto without a model, none with one).
    pub select: Option<&'a str>,
    /// Judge the selection K samples ahead (not given: the free run).
    pub select_steps_ahead: Option<i128>,
    /// The work budget as a multiple of the default (not given: 1).
    pub budget: Option<f64>,
}

/// The message when a selection and a model both name the structure.
pub fn both_name_the_structure(door: &Door) -> String {
    format!(
        "{} and {} both name the structure: give one ({} keeps {}'s)",
        door.auto, door.model, door.none, door.model
    )
}

impl<'a> FitArgs<'a> {
    /// The arguments as given (`select`, `select_steps_ahead`, `budget`); whether a model
    /// is given is the caller's to set (`fit_in_memory` sets it from its spec).
    pub fn given(select: Option<&'a str>, select_steps_ahead: Option<i128>, budget: Option<f64>) -> Self {
        FitArgs {
            model_given: false,
            select,
            select_steps_ahead,
            budget,
        }
    }

    /// The selection's options (None: no selection, the structure of the model or the
    /// default one), or what is wrong, in `door`'s words.
    pub fn selection(&self, door: &Door) -> Result<Option<SelectOptions>> {
        let bad = |m: String| Err(Error::Input(m));
        let auto = match self.select {
            Some("auto") => true,
            Some("none") => false,
            None => !self.model_given,
            Some(other) => {
                return bad(format!(
                    "{} {other:?} is not allowed: give auto or none (or leave it out: auto without {}, none with it)",
                    door.select, door.model
                ))
            }
        };
        if auto && self.model_given && self.select.is_some() {
            return bad(both_name_the_structure(door));
        }
        if !auto && (self.select_steps_ahead.is_some() || self.budget.is_some()) {
            return bad(format!(
                "{} and {} apply to the selection only ({}, the default without {})",
                door.steps_ahead, door.budget, door.auto, door.model
            ));
        }
        let steps = match self.select_steps_ahead {
            Some(k) if k < 1 => {
                return bad(format!(
                    "{} {k} is not allowed: give K >= 1, or leave it out to judge the free run",
                    door.steps_ahead
                ))
            }
            // As given (a count the machine cannot hold is one too many for any record).
            k => k.map(|k| usize::try_from(k).unwrap_or(usize::MAX)),
        };
        if let Some(b) = self.budget.filter(|b| !(b.is_finite() && *b > 0.0 && *b <= 1e6)) {
            return bad(format!(
                "{} {b} is not allowed: give a multiple of the default work budget in (0, 1e6]",
                door.budget
            ));
        }
        Ok(auto.then(|| SelectOptions::judged(steps, self.budget)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err(a: FitArgs, door: &Door) -> String {
        a.selection(door).unwrap_err().to_string()
    }

    #[test]
    fn each_rule_holds_at_both_doors_in_their_own_words() {
        let none = FitArgs::default();
        // Without a model the structure is selected; with one it is the model's.
        assert_eq!(none.selection(&PYTHON).unwrap(), Some(SelectOptions::default()));
        let model = FitArgs {
            model_given: true,
            ..none
        };
        assert_eq!(model.selection(&COMMAND_LINE).unwrap(), None);
        assert_eq!(
            FitArgs {
                select: Some("none"),
                ..model
            }
            .selection(&PYTHON)
            .unwrap(),
            None
        );
        let judged = FitArgs {
            select_steps_ahead: Some(5),
            budget: Some(2.0),
            ..none
        };
        assert_eq!(
            judged.selection(&PYTHON).unwrap(),
            Some(SelectOptions::judged(Some(5), Some(2.0)))
        );
        for (door, words) in [
            (
                &COMMAND_LINE,
                [
                    "--select auto and --model",
                    "--select-steps-ahead and --budget",
                    "--select-steps-ahead 0",
                    "--budget inf",
                    "--select \"best\"",
                ],
            ),
            (
                &PYTHON,
                [
                    "select=\"auto\" and model",
                    "select_steps_ahead and budget",
                    "select_steps_ahead 0",
                    "budget inf",
                    "select \"best\"",
                ],
            ),
        ] {
            let auto_and_model = FitArgs {
                select: Some("auto"),
                ..model
            };
            assert!(
                err(auto_and_model, door).starts_with(words[0]),
                "{}",
                err(auto_and_model, door)
            );
            let budget_without_selection = FitArgs {
                budget: Some(2.0),
                ..model
            };
            assert!(err(budget_without_selection, door).starts_with(words[1]));
            let zero = FitArgs {
                select_steps_ahead: Some(0),
                ..none
            };
            assert!(err(zero, door).starts_with(words[2]));
            let inf = FitArgs {
                budget: Some(f64::INFINITY),
                ..none
            };
            assert!(err(inf, door).starts_with(words[3]));
            let best = FitArgs {
                select: Some("best"),
                ..none
            };
            assert!(err(best, door).starts_with(words[4]), "{}", err(best, door));
        }
        for bad in [-1i128, 0] {
            let a = FitArgs {
                select_steps_ahead: Some(bad),
                ..none
            };
            assert!(a.selection(&PYTHON).is_err());
        }
        for b in [f64::NAN, 0.0, -1.0, 1.1e6] {
            let a = FitArgs {
                budget: Some(b),
                ..none
            };
            assert!(a.selection(&COMMAND_LINE).is_err(), "{b}");
        }
    }

    #[test]
    fn the_command_line_renames_the_library_s_fields_to_its_flags() {
        let e = rhonn::Error::Invalid {
            value: rhonn::error::InvalidValue {
                field: "select_steps_ahead".into(),
                value: "9".into(),
                allowed: "fewer".into(),
            },
            scenario: None,
        };
        assert!(COMMAND_LINE
            .rename(e.clone())
            .to_string()
            .contains("`--select-steps-ahead` = 9"));
        assert!(PYTHON.rename(e).to_string().contains("`select_steps_ahead` = 9"));
        // The library names its fields, never a door's flags: a block structure's columns.
        let data = rhonn::data::Record {
            source: "x".into(),
            t: (0..50).map(f64::from).collect(),
            inputs: vec![(0..50).map(|k| f64::from(k).sin()).collect(); 2],
            outputs: vec![(0..50).map(|k| f64::from(k).cos()).collect()],
        };
        let spec: rhonn::sysid::ModelSpec = toml::from_str("kind = \"wiener-hammerstein\"").unwrap();
        let e = rhonn::sysid::fit(&spec, &[data], &["u1".into(), "u2".into()], &["y".into()]).unwrap_err();
        assert!(!e.to_string().contains("--"), "{e}");
        let cli = COMMAND_LINE.rename(e.clone()).to_string();
        assert!(
            cli.contains("`--inputs and --outputs` = 2 inputs, 1 outputs"),
            "{cli}"
        );
        assert!(PYTHON.rename(e).to_string().contains("`u and y` = 2 inputs"));
    }
}
