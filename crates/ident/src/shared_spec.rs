//! One spec for `rhonn fit` and `rhonn identify` where their model kinds overlap: a `fit`
//! spec of an ARX, a lagged RHONN, a cascade or a Wiener-Hammerstein block structure given
//! to `identify` is read as the online structure of the same model (and an `identify` spec
//! of the lagged, cascade or wiener-hammerstein structure given to `fit`, as the offline
//! one); a key with no counterpart is named, with its
//! value, in the error. The translation is key by key on the TOML table, so only keys
//! written in the file count (a default is never a difference).

use super::online_spec::OnlineSpec;
use crate::models::ModelSpec;
use toml::{Table, Value};

/// `rhonn fit`'s keys and where they go in an online spec (`None`: nowhere).
const FIT_TO_ONLINE: &[(&str, Option<&str>)] = &[
    ("na", Some("lags.na")),
    ("nb", Some("lags.nb")),
    ("nk", Some("lags.nk")),
    ("output_lag_start", Some("lags.output_lag_start")),
    ("nonlinear_lags", Some("lags.nonlinear_lags")),
    ("degree", Some("degree")),
    ("max_factors", Some("max_factors")),
    ("activation", Some("activation")),
    ("input_filters_s", Some("filters_s")),
    ("epochs", Some("epochs")),
    ("output_margin", Some("output_margin")),
    ("neurons", Some("cascade.neurons")),
    ("free_exponents", Some("cascade.free_exponents")),
    ("starts", Some("cascade.starts")),
    ("settle", Some("cascade.settle")),
    ("seed", Some("cascade.seed")),
    ("law", None),
    ("ridge", None),
    ("gain", None),
    ("horizon", None),
    ("max_terms", None),
    ("term_selection", None),
    ("nonlinear_in", None),
    ("pump", None),
];

/// Put `v` at the dotted `path` of `t`.
fn put(t: &mut Table, path: &str, v: Value) {
    match path.split_once('.') {
        None => {
            t.insert(path.into(), v);
        }
        Some((head, rest)) => {
            let sub = t
                .entry(head.to_string())
                .or_insert_with(|| Value::Table(Table::new()));
            if let Value::Table(s) = sub {
                put(s, rest, v);
            }
        }
    }
}

/// Keys without a counterpart, as `key = value` for an error.
fn listed(keys: &[(String, Value)]) -> String {
    keys.iter()
        .map(|(k, v)| format!("{k} = {v}"))
        .collect::<Vec<_>>()
        .join(", ")
}

/// A `rhonn fit` spec (TOML text, one model) as the online spec of the same structure:
/// `arx` is the lagged structure of degree 1, `rhonn` the lagged structure, `cascade`
/// the cascade. None: not a `fit` spec; Err: why not, naming each key that has no
/// online counterpart.
pub fn online_from_fit(text: &str) -> Option<Result<OnlineSpec, String>> {
    let fit: Table = toml::from_str(text).ok()?;
    let spec = toml::from_str::<ModelSpec>(text).ok()?;
    if spec.kind == crate::models::Kind::WienerHammerstein {
        return Some(block_to_online(&fit, &spec));
    }
    Some(fit_table_to_online(&fit))
}

/// A `rhonn fit` Wiener-Hammerstein spec as the online structure of the same block
/// structure, every setting carried with `rhonn fit`'s value (its defaults too: the
/// online structure's differ): `na` poles, `nk`, `degree`, `epochs` (the fit's
/// iterations), `output_margin`. The online structure's numerator has `na + 1`
/// coefficients, so another `nb` is named; so is any other key.
fn block_to_online(fit: &Table, spec: &ModelSpec) -> Result<OnlineSpec, String> {
    let carried = ["na", "nk", "degree", "epochs", "output_margin"];
    let missing: Vec<(String, Value)> = fit
        .iter()
        .filter(|(k, v)| match k.as_str() {
            "kind" => false,
            "nb" => v.as_integer() != Some(spec.na as i64 + 1),
            "law" => v.as_str() != Some("simulation-error"),
            k => !carried.contains(&k),
        })
        .map(|(k, v)| (k.clone(), v.clone()))
        .collect();
    if !missing.is_empty() {
        return Err(format!(
            "a `rhonn fit` spec (kind = \"wiener-hammerstein\") whose keys {} have no counterpart in online identification (its structure has nb = na + 1 and learns by its fit on a window, then recursive least squares): remove them, or write the online spec (structure = \"wiener-hammerstein\")",
            listed(&missing)
        ));
    }
    Ok(OnlineSpec {
        structure: super::online_spec::OnlineStructure::WienerHammerstein,
        block: Some(super::online_spec::BlockOnlineSpec {
            poles: spec.na,
            nk: spec.nk,
            degree: spec.degree,
            iterations: spec.epochs,
            ..Default::default()
        }),
        output_margin: spec.output_margin,
        ..OnlineSpec::default()
    })
}

/// An online `wiener-hammerstein` spec as `rhonn fit`'s: `block.poles` as `na` (and
/// `nb` = `na` + 1), `block.nk`, `block.degree`, `block.iterations` as `epochs`,
/// `output_margin`; `block.window` and the keys of learning online are named.
fn block_to_fit(on: &Table, spec: &OnlineSpec) -> Result<ModelSpec, String> {
    let block_keys = ["poles", "nk", "degree", "iterations"];
    let mut missing: Vec<(String, Value)> = Vec::new();
    for (k, v) in on {
        match (k.as_str(), v.as_table()) {
            ("structure" | "output_margin", _) => {}
            ("block", Some(t)) => missing.extend(
                t.iter()
                    .filter(|(sk, _)| !block_keys.contains(&sk.as_str()))
                    .map(|(sk, sv)| (format!("block.{sk}"), sv.clone())),
            ),
            _ => missing.push((k.clone(), v.clone())),
        }
    }
    if !missing.is_empty() {
        return Err(format!(
            "an online spec (structure = \"wiener-hammerstein\") whose keys {} have no counterpart in `rhonn fit`: remove them, or write the fit spec (kind = \"wiener-hammerstein\")",
            listed(&missing)
        ));
    }
    let b = spec.block.clone().unwrap_or_default();
    Ok(ModelSpec {
        kind: crate::models::Kind::WienerHammerstein,
        na: b.poles,
        nb: b.poles + 1,
        nk: b.nk,
        degree: b.degree,
        epochs: b.iterations,
        law: crate::models::Estimator::SimulationError,
        output_margin: spec.output_margin,
        ..ModelSpec::default()
    })
}

fn fit_table_to_online(fit: &Table) -> Result<OnlineSpec, String> {
    let kind = fit.get("kind").and_then(Value::as_str).unwrap_or("rhonn");
    let mut out = Table::new();
    let mut missing = Vec::new();
    match kind {
        "arx" => {
            out.insert("structure".into(), "lagged".into());
            out.insert("degree".into(), 1.into());
            out.insert("max_factors".into(), 1.into());
            put(&mut out, "lags.na", 2.into());
        }
        "rhonn" => {
            out.insert("structure".into(), "lagged".into());
            put(&mut out, "lags.na", 2.into());
        }
        "cascade" => {
            out.insert("structure".into(), "cascade".into());
            out.insert("cascade".into(), Value::Table(Table::new()));
        }
        other => {
            return Err(format!(
            "kind = \"{other}\" has no online counterpart (online: arx, rhonn, cascade, wiener-hammerstein)"
        ))
        }
    }
    let ignored_by_arx = ["degree", "max_factors", "nonlinear_lags"];
    for (k, v) in fit.iter().filter(|(k, _)| *k != "kind") {
        if kind == "arx" && ignored_by_arx.contains(&k.as_str()) {
            continue;
        }
        match FIT_TO_ONLINE.iter().find(|(f, _)| f == k) {
            Some((_, Some(to))) if kind == "cascade" || !to.starts_with("cascade.") => {
                put(&mut out, to, v.clone())
            }
            _ => missing.push((k.clone(), v.clone())),
        }
    }
    if !missing.is_empty() {
        return Err(format!(
            "a `rhonn fit` spec (kind = \"{kind}\") whose keys {} have no counterpart in online identification (it learns by recursive least squares, sample by sample): remove them, or write the online spec (structure = \"lagged\" or \"cascade\")",
            listed(&missing)
        ));
    }
    out.try_into::<OnlineSpec>().map_err(|e| e.to_string())
}

/// An online spec of the lagged or cascade structure (TOML text) as the `rhonn fit` spec
/// of the same model. Err: why not (the continuous-time neurons are online only; keys
/// with no offline counterpart are named). None: not an online spec.
pub fn fit_from_online(text: &str) -> Option<Result<ModelSpec, String>> {
    let on: Table = toml::from_str(text).ok()?;
    let spec: OnlineSpec = toml::from_str(text).ok()?;
    if spec.structure == super::online_spec::OnlineStructure::WienerHammerstein {
        return Some(block_to_fit(&on, &spec));
    }
    Some(online_table_to_fit(&on, &spec))
}

fn online_table_to_fit(on: &Table, spec: &OnlineSpec) -> Result<ModelSpec, String> {
    let structure = on
        .get("structure")
        .and_then(Value::as_str)
        .unwrap_or("continuous");
    let mut out = Table::new();
    let mut missing = Vec::new();
    match structure {
        "lagged" => {
            let linear = spec.degree == 1;
            out.insert("kind".into(), if linear { "arx" } else { "rhonn" }.into());
        }
        "cascade" => {
            out.insert("kind".into(), "cascade".into());
        }
        _ => {
            return Err(
                "the continuous-time neurons (structure = \"continuous\", the default) are online only: give `rhonn fit` a lagged, cascade or wiener-hammerstein structure".into(),
            )
        }
    }
    for (k, v) in on {
        match k.as_str() {
            "structure" => {}
            "lags" | "cascade" => {
                for (sk, sv) in v.as_table().into_iter().flatten() {
                    let dotted = format!("{k}.{sk}");
                    match FIT_TO_ONLINE.iter().find(|(_, to)| *to == Some(dotted.as_str())) {
                        Some((f, _)) => put(&mut out, f, sv.clone()),
                        None => missing.push((dotted, sv.clone())),
                    }
                }
            }
            "degree" | "max_factors" if out.get("kind").and_then(Value::as_str) == Some("arx") => {}
            _ => match FIT_TO_ONLINE.iter().find(|(_, to)| *to == Some(k.as_str())) {
                Some((f, _)) => put(&mut out, f, v.clone()),
                None => missing.push((k.clone(), v.clone())),
            },
        }
    }
    if !missing.is_empty() {
        return Err(format!(
            "an online spec (structure = \"{structure}\") whose keys {} have no counterpart in `rhonn fit`: remove them, or write the fit spec (kind = ...)",
            listed(&missing)
        ));
    }
    out.try_into::<ModelSpec>().map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A Wiener-Hammerstein spec goes both ways with `rhonn fit`'s values (its defaults
    /// too), and a key with no counterpart is named.
    #[test]
    fn a_wiener_hammerstein_spec_goes_both_ways_or_names_the_key() {
        let on = online_from_fit("kind = \"wiener-hammerstein\"\nna = 4\nnb = 5\nnk = 0\ndegree = 7\n")
            .unwrap()
            .unwrap();
        let b = on.block.clone().unwrap();
        assert_eq!(
            (b.poles, b.nk, b.degree, b.iterations),
            (4, 0, 7, ModelSpec::default().epochs)
        );
        assert_eq!(on.output_margin, ModelSpec::default().output_margin);
        let e = online_from_fit("kind = \"wiener-hammerstein\"\nna = 4\nnb = 2\n")
            .unwrap()
            .unwrap_err();
        assert!(e.contains("nb = 2") && e.contains("nb = na + 1"), "{e}");
        let fit = fit_from_online(
            "structure = \"wiener-hammerstein\"\nblock = { poles = 3, degree = 5, iterations = 9 }\n",
        )
        .unwrap()
        .unwrap();
        assert_eq!((fit.na, fit.nb, fit.degree, fit.epochs), (3, 4, 5, 9));
        assert_eq!(fit.kind, crate::models::Kind::WienerHammerstein);
        let e = fit_from_online("structure = \"wiener-hammerstein\"\nblock = { window = 900 }\nepochs = 2\n")
            .unwrap()
            .unwrap_err();
        assert!(
            e.contains("block.window = 900") && e.contains("epochs = 2"),
            "{e}"
        );
    }
}
