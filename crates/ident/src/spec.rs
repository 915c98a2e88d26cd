//! The `[identifier]` section of a scenario.

use super::identified::MAX_SIGNALS;
use super::{Identifier, Mode};
use crate::error::{invalid, Result};
use crate::law::LawSpec;
use crate::net::{Network, Sigmoid, Terms, MAX_TERMS, MAX_Y};
use crate::plant::{Plant, SignalRef};
use rhonn_ode::DEFAULT_MAX_STEPS;
use serde::{Deserialize, Serialize};

/// A sigmoid by name (`"logistic"`, `"tanh"`) or by its parameters `{a, b, c}`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum SigmoidSpec {
    /// A preset.
    Named(String),
    /// `a / (1 + exp(-b v)) - c`.
    Custom(Sigmoid),
}

/// A RHONN identifier as a scenario writes it. The network works on SI values divided
/// by the scales (1 = the raw SI states, as the thesis does).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct IdentifierSpec {
    /// Identified states, one neuron each: `p_line`, `stroke`.
    pub states: Vec<String>,
    /// External inputs in y: `current`, `demand`.
    #[serde(default)]
    pub inputs: Vec<String>,
    /// Sigmoid (default logistic).
    #[serde(default = "default_sigmoid")]
    pub sigmoid: SigmoidSpec,
    /// Divisor of each state before its sigmoid (default 1).
    #[serde(default)]
    pub state_scale: Option<Vec<f64>>,
    /// Divisor of each input (default 1).
    #[serde(default)]
    pub input_scale: Option<Vec<f64>>,
    /// Terms by hand: each a list of `[y index, exponent]`, y = \[s(states)..., inputs...\].
    #[serde(default)]
    pub terms: Option<Vec<Vec<[usize; 2]>>>,
    /// Or every monomial of y up to this degree ...
    #[serde(default)]
    pub degree: Option<usize>,
    /// ... with at most this many distinct factors (default: the degree).
    #[serde(default)]
    pub max_factors: Option<usize>,
    /// Poles a_i > 0, one per neuron.
    pub a: Vec<f64>,
    /// The model's initial states \[SI\] (default 0).
    #[serde(default)]
    pub initial_si: Option<Vec<f64>>,
    /// Training epochs over the same data (default 1).
    #[serde(default = "one")]
    pub epochs: usize,
    /// The learning law.
    pub law: LawSpec,
    /// Validate with frozen weights after training (default true).
    #[serde(default = "yes")]
    pub validate: bool,
}

fn yes() -> bool {
    true
}

/// Names to the pump's signals: each one of `known`, each at most once; errors name
/// `field[k]`.
fn signals(
    names: &[String],
    field: &str,
    known: &[(&str, SignalRef)],
    allowed: &str,
    once: &str,
) -> Result<Vec<SignalRef>> {
    let mut out = Vec::new();
    for (k, s) in names.iter().enumerate() {
        let Some(&(_, sig)) = known.iter().find(|(n, _)| n == s) else {
            return Err(invalid(format!("{field}[{k}]"), format!("{s:?}"), allowed));
        };
        if out.contains(&sig) {
            return Err(invalid(format!("{field}[{k}]"), format!("{s:?}"), once));
        }
        out.push(sig);
    }
    Ok(out)
}

fn default_sigmoid() -> SigmoidSpec {
    SigmoidSpec::Named("logistic".into())
}

fn one() -> usize {
    1
}

/// A checked identifier set-up.
#[derive(Debug, Clone, PartialEq)]
pub struct IdentSettings {
    /// The identifier (mode `Train`).
    pub ident: Identifier,
    /// Identified states.
    pub states: Vec<SignalRef>,
    /// Inputs.
    pub inputs: Vec<SignalRef>,
    /// Initial model states \[SI\].
    pub xhat0: Vec<f64>,
    /// Epochs.
    pub epochs: usize,
    /// Validate after training.
    pub validate: bool,
}

impl IdentifierSpec {
    /// Validate for the pump: neurons for `p_line` and `stroke`, inputs `current` and
    /// `demand`.
    pub fn check(&self) -> Result<IdentSettings> {
        let pump = crate::plant::pump::PumpSystem::new(
            crate::plant::PumpParams::default(),
            crate::plant::Input::Held(0.0),
            crate::plant::Input::Held(0.0),
        );
        self.check_for(&pump)
    }

    /// Validate for `plant`: each identified state is one of the plant's measured states
    /// (the identifier reads it, series-parallel), each input one of its inputs.
    pub fn check_for<P: Plant>(&self, plant: &P) -> Result<IdentSettings> {
        let f = "identifier";
        let n = self.states.len();
        let measured: Vec<(&str, SignalRef)> = plant
            .measured()
            .iter()
            .map(|&i| (plant.states()[i].name, SignalRef::State(i)))
            .collect();
        let inputs_known: Vec<(&str, SignalRef)> = plant
            .inputs()
            .iter()
            .enumerate()
            .map(|(k, q)| (q.name, SignalRef::Input(k)))
            .collect();
        let quoted = |v: &[(&str, SignalRef)], sep: &str| {
            v.iter()
                .map(|(n, _)| format!("{n:?}"))
                .collect::<Vec<_>>()
                .join(sep)
        };
        let most = measured.len().min(MAX_SIGNALS);
        if n == 0 || n > most {
            let count = if most == 2 {
                "1 or 2".to_string()
            } else {
                format!("1 to {most}")
            };
            return Err(invalid(
                format!("{f}.states"),
                format!("{:?}", self.states),
                format!("{count} of {}", quoted(&measured, ", ")),
            ));
        }
        let states = signals(
            &self.states,
            &format!("{f}.states"),
            &measured,
            &quoted(&measured, " or "),
            "each state once",
        )?;
        let inputs = signals(
            &self.inputs,
            &format!("{f}.inputs"),
            &inputs_known,
            &quoted(&inputs_known, " or "),
            "each input once",
        )?;
        let m = inputs.len();
        if m > MAX_SIGNALS || n + m > MAX_Y {
            return Err(invalid(
                format!("{f}.inputs"),
                m,
                format!("at most {MAX_SIGNALS} inputs"),
            ));
        }
        let sigmoid = self.check_sigmoid()?;
        let state_scale = check_scale(&self.state_scale, n, "state_scale")?;
        let input_scale = check_scale(&self.input_scale, m, "input_scale")?;
        let terms = self.check_terms(n + m)?;
        self.check_poles(n)?;
        let xhat0 = match &self.initial_si {
            None => vec![0.0; n],
            Some(v) if v.len() == n && v.iter().all(|x| x.is_finite()) => v.clone(),
            Some(v) => {
                return Err(invalid(
                    format!("{f}.initial_si"),
                    format!("{v:?}"),
                    format!("{n} finite values"),
                ))
            }
        };
        if !(1..=10_000).contains(&self.epochs) {
            return Err(invalid(
                format!("{f}.epochs"),
                self.epochs,
                "an integer in [1, 10000]",
            ));
        }
        let l = terms.len();
        let law = self.law.check(n, l, &format!("{f}.law"))?;
        let net = Network {
            n,
            m,
            sigmoid,
            state_scale,
            input_scale,
            terms,
            a: self.a.clone(),
        };
        Ok(IdentSettings {
            ident: Identifier::new(net, law, Mode::Train),
            states,
            inputs,
            xhat0,
            epochs: self.epochs,
            validate: self.validate,
        })
    }

    /// The sigmoid: a named one or {a, b, c}.
    fn check_sigmoid(&self) -> Result<Sigmoid> {
        let f = "identifier";
        Ok(match &self.sigmoid {
            SigmoidSpec::Named(s) if s == "logistic" => Sigmoid::LOGISTIC,
            SigmoidSpec::Named(s) if s == "tanh" => Sigmoid::TANH,
            SigmoidSpec::Named(s) => {
                return Err(invalid(
                    format!("{f}.sigmoid"),
                    format!("{s:?}"),
                    "\"logistic\", \"tanh\" or {a, b, c}",
                ))
            }
            SigmoidSpec::Custom(s) => {
                if !(s.a.is_finite() && s.a != 0.0 && s.b.is_finite() && s.b != 0.0 && s.c.is_finite()) {
                    return Err(invalid(
                        format!("{f}.sigmoid"),
                        format!("{s:?}"),
                        "finite a and b, not zero, finite c",
                    ));
                }
                *s
            }
        })
    }

    /// The high-order terms over `nm` signals: listed, or all monomials up to a degree.
    fn check_terms(&self, nm: usize) -> Result<Terms> {
        let f = "identifier";
        Ok(match (&self.terms, self.degree) {
            (Some(t), None) => Terms::from_lists(t, nm, &format!("{f}.terms"))?,
            (None, Some(d)) => {
                if !(1..=6).contains(&d) {
                    return Err(invalid(format!("{f}.degree"), d, "an integer in [1, 6]"));
                }
                let mf = self.max_factors.unwrap_or(d);
                if !(1..=d).contains(&mf) {
                    return Err(invalid(
                        format!("{f}.max_factors"),
                        mf,
                        format!("an integer in [1, {d}]"),
                    ));
                }
                let t = Terms::monomials(nm, d, mf);
                if t.len() > MAX_TERMS {
                    return Err(invalid(
                        format!("{f}.degree"),
                        d,
                        format!(
                            "a degree giving at most {MAX_TERMS} terms (this gives {})",
                            t.len()
                        ),
                    ));
                }
                t
            }
            _ => {
                return Err(invalid(
                    format!("{f}.terms"),
                    "both or neither of terms and degree",
                    "exactly one of `terms` and `degree`",
                ))
            }
        })
    }

    /// Whether the neurons' poles can be integrated over a run of `duration_s` (`field`
    /// names that duration in an error): an explicit Dormand-Prince step is stable for
    /// `h a <= 3.3`, so a pole `a` needs at least `a duration_s / 3.3` steps, and a run may
    /// take [`DEFAULT_MAX_STEPS`]; beyond it the run would step for tens of seconds and fail.
    pub fn check_pole_speed(&self, duration_s: f64, field: &str) -> Result<()> {
        let most = 3.3 * DEFAULT_MAX_STEPS as f64 / duration_s;
        for (k, a) in self.a.iter().enumerate() {
            if *a > most {
                return Err(invalid(
                    format!("identifier.a[{k}]"),
                    a,
                    format!(
                        "at most {} 1/s for a run of {field} = {duration_s} s: a faster neuron needs more than the \
                         {} steps a run may take (a pole of a 1/s wants steps below 3.3/a s)",
                        crate::metrics::sig(most, 3),
                        crate::metrics::sig(DEFAULT_MAX_STEPS as f64, 3)
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The neurons' poles a_i > 0, one per state.
    fn check_poles(&self, n: usize) -> Result<()> {
        let f = "identifier";
        if self.a.len() != n {
            return Err(invalid(
                format!("{f}.a"),
                format!("{} values", self.a.len()),
                format!("one per state ({n})"),
            ));
        }
        for (k, a) in self.a.iter().enumerate() {
            if !(a.is_finite() && *a > 0.0) {
                return Err(invalid(
                    format!("{f}.a[{k}]"),
                    a,
                    "a number > 0 (a stable neuron)",
                ));
            }
        }
        Ok(())
    }
}

/// Per-signal scales: 1 by default, else `len` numbers > 0.
fn check_scale(v: &Option<Vec<f64>>, len: usize, name: &str) -> Result<Vec<f64>> {
    let f = "identifier";
    match v {
        None => Ok(vec![1.0; len]),
        Some(v) if v.len() != len => Err(invalid(
            format!("{f}.{name}"),
            format!("{} values", v.len()),
            format!("{len} values"),
        )),
        Some(v) => {
            for (k, x) in v.iter().enumerate() {
                if !(x.is_finite() && *x > 0.0) {
                    return Err(invalid(format!("{f}.{name}[{k}]"), x, "a number > 0"));
                }
            }
            Ok(v.clone())
        }
    }
}
