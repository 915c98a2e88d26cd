//! Every field of every `summary.json` (and `weights.json`) the commands write, said in
//! words from the same source as the field itself: the doc comment on the Rust field that
//! serialises it. Each output's JSON Schema (`schemars`, derived on the types that write
//! it, so it follows their serde names, renames and skips) is walked into one row per key
//! path; `docs/reference/fields.md` is [`markdown`]'s text (the test
//! `fields::the_reference_is_generated_from_the_fields` keeps it so and asks for a doc
//! comment on every field), and [`Describer`] gives the report's "what it is" column.
//!
//! Settings echoed back (a scenario, a model's structure, a campaign's plan) are one row
//! each, described where they are written (`docs/reference/scenarios.md`, the fit guide).

use serde_json::Value;

/// One output file of a command and its schema.
pub struct Output {
    /// The command (`rhonn fit`).
    pub command: &'static str,
    /// The file (`summary.json`), and for which runs when not every one.
    pub file: &'static str,
    /// Its JSON Schema (as JSON).
    pub schema: Value,
}

fn schema_of<T: schemars::JsonSchema>() -> Value {
    schemars::schema_for!(T).to_value()
}

/// Every output with fields, in the order of the reference.
pub fn outputs() -> Vec<Output> {
    use rhonn::experiment::{BenchFigures, ModelFile, PlantSummary};
    let out = |command, file, schema| Output {
        command,
        file,
        schema,
    };
    vec![
        out("rhonn run", "summary.json", schema_of::<PlantSummary>()),
        out(
            "rhonn run",
            "weights.json (with an identifier)",
            schema_of::<ModelFile>(),
        ),
        out(
            "rhonn fit",
            "summary.json",
            schema_of::<rhonn::sysid::FitSummary>(),
        ),
        out(
            "rhonn predict",
            "summary.json (an offline model)",
            schema_of::<rhonn::sysid::PredictSummary>(),
        ),
        out(
            "rhonn predict",
            "summary.json (an online model)",
            crate::identify::prediction_schema(),
        ),
        out(
            "rhonn identify",
            "summary.json",
            schema_of::<rhonn::identification::IdentifySummary>(),
        ),
        out("rhonn benchmark", "summary.json", crate::benchmark_file::schema()),
        out(
            "rhonn benchmark",
            "<benchmark>/summary.json",
            schema_of::<rhonn::benchmark::BenchmarkOutcome>(),
        ),
        out("rhonn corpus", "summary.json", crate::corpus_file::schema()),
        out(
            "rhonn corpus",
            "<system>/summary.json",
            crate::corpus_file::system_schema(),
        ),
        out("rhonn bench", "summary.json", crate::bench_report::schema()),
        out(
            "rhonn bench",
            "(one scenario's figures)",
            schema_of::<BenchFigures>(),
        ),
        out("rhonn campaign", "summary.json", crate::campaign_file::schema()),
    ]
}

/// The rows of a schema: each key path (`selection.candidates[].score`) and its
/// description, depth first in the fields' order.
pub fn rows(schema: &Value) -> Vec<(String, String)> {
    let mut out = Vec::new();
    let mut seen = Vec::new();
    walk(schema, schema, "", (&mut out, &mut seen), None);
    out
}

/// [`rows`] with every type's keys under every path it appears at (to a depth of 12 keys).
fn every_row(schema: &Value) -> Vec<(String, String)> {
    let mut out = Vec::new();
    walk(schema, schema, "", (&mut out, &mut Vec::new()), Some(12));
    out
}

/// A named type met again: where its keys were listed first.
type Seen = Vec<(String, String)>;

/// The schema `s` stands for: a `$ref` followed into the root's `$defs`, an optional's
/// non-null branch, an array's items (`[]` added to the path), a map's values (`.*`).
fn resolve<'a>(root: &'a Value, s: &'a Value, path: &mut String, def: &mut Option<String>) -> &'a Value {
    if let Some(r) = s.get("$ref").and_then(Value::as_str) {
        let name = r.trim_start_matches("#/$defs/");
        return match root.get("$defs").and_then(|d| d.get(name)) {
            Some(found) => {
                *def = Some(name.to_string());
                resolve(root, found, path, def)
            }
            None => s,
        };
    }
    for key in ["anyOf", "oneOf"] {
        if let Some(branches) = s.get(key).and_then(Value::as_array) {
            let real: Vec<&Value> = branches
                .iter()
                .filter(|b| b.get("type") != Some(&"null".into()))
                .collect();
            if let [one] = real[..] {
                return resolve(root, one, path, def);
            }
        }
    }
    if let Some(items) = s.get("items").filter(|i| i.is_object()) {
        path.push_str("[]");
        return resolve(root, items, path, def);
    }
    if let Some(values) = s.get("additionalProperties").filter(|v| v.is_object()) {
        path.push_str(".*");
        return resolve(root, values, path, def);
    }
    s
}

/// The rows under `s` at `prefix`: a type met again named, not listed (`expand`: listed
/// again, down to that many keys).
fn walk(
    root: &Value,
    s: &Value,
    prefix: &str,
    (out, seen): (&mut Vec<(String, String)>, &mut Seen),
    expand: Option<usize>,
) {
    let Some(props) = s.get("properties").and_then(Value::as_object) else {
        return;
    };
    if expand == Some(0) {
        return;
    }
    for (key, prop) in props {
        let mut path = if prefix.is_empty() {
            key.clone()
        } else {
            format!("{prefix}.{key}")
        };
        let text = prop
            .get("description")
            .and_then(Value::as_str)
            .map(clean)
            .unwrap_or_default();
        let mut def = None;
        let inner = resolve(root, prop, &mut path, &mut def);
        // The type's own doc comment stands in for a field without one.
        let mut text = if text.is_empty() {
            inner
                .get("description")
                .and_then(Value::as_str)
                .map(clean)
                .unwrap_or_default()
        } else {
            text
        };
        let has_keys = inner.get("properties").is_some();
        // A type whose keys are already listed (the same figures of another run) is
        // listed once, and named here (so a recursive type ends too).
        match (&def, seen.iter().find(|(d, _)| Some(d) == def.as_ref())) {
            (Some(_), Some((_, first))) if has_keys && expand.is_none() => {
                text = format!("{text} (its keys as under `{first}`)");
                out.push((path, text));
            }
            _ => {
                if let (Some(d), true) = (def, has_keys) {
                    seen.push((d, path.clone()));
                }
                out.push((path.clone(), text));
                walk(root, inner, &path, (&mut *out, &mut *seen), expand.map(|d| d - 1));
            }
        }
    }
}

/// A doc comment as plain text: rustdoc's escapes and link brackets out, one line.
fn clean(doc: &str) -> String {
    let s = doc
        .replace("\\[", "[")
        .replace("\\]", "]")
        .replace("[`", "`")
        .replace("`]", "`");
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// `docs/reference/fields.md`: a table per output, a row per key path.
pub fn markdown() -> String {
    let mut md = String::from(
        "# The fields of every output\n\n\
         Generated from the doc comments of the fields that write them (`rhonn_report::fields`);\n\
         do not edit: `RHONN_BLESS=1 cargo test --test integration fields::` writes it anew. Units are in\n\
         the key's name where a number could be misread; `[]` is a list's items, `.*` a map's values.\n\
         Concepts (series-parallel, free run, fit %) are in the [glossary](glossary.md).\n",
    );
    for o in outputs() {
        md.push_str(&format!(
            "\n## `{}`: {}\n\n| key | what it is |\n|---|---|\n",
            o.command, o.file
        ));
        for (path, text) in rows(&o.schema) {
            md.push_str(&format!("| `{path}` | {} |\n", text.replace('|', "\\|")));
        }
    }
    md
}

/// Whether row `row` of the reference names key path `key` (`a.b[3].c`, `a.b[].c` or
/// `a.b.c`: a list's brackets and indices aside; `*` in a row is any map key).
pub fn names(row: &str, key: &str) -> bool {
    let bare = |s: &str| match s.find('[') {
        Some(i) => s[..i].to_string(),
        None => s.to_string(),
    };
    let (r, k): (Vec<&str>, Vec<&str>) = (row.split('.').collect(), key.split('.').collect());
    let r = match r.last() {
        // A map's row (`units.*`) names the key that holds it too.
        Some(&"*") if r.len() == k.len() + 1 => &r[..k.len()],
        _ => &r[..],
    };
    r.len() == k.len() && r.iter().zip(&k).all(|(a, b)| bare(a) == bare(b) || *a == "*")
}

/// Says what the keys of one `summary.json` are: the doc comments of the output whose
/// fields name most of its keys (the report's "what it is" column).
pub struct Describer {
    rows: Vec<(String, String)>,
}

impl Describer {
    /// For `summary`, a `summary.json` of any command.
    pub fn for_summary(summary: &Value) -> Self {
        let keys = key_paths(summary);
        let rows = outputs()
            .iter()
            .map(|o| every_row(&o.schema))
            .max_by_key(|rows| {
                keys.iter()
                    .filter(|k| rows.iter().any(|(r, _)| names(r, k)))
                    .count()
            })
            .unwrap_or_default();
        Describer { rows }
    }

    /// What the field at key path `key` is (`selection.candidates[3].score`); empty for a
    /// key inside an echoed setting (a row with no rows below it, `scenario`); None for a
    /// key no field names.
    pub fn describe(&self, key: &str) -> Option<&str> {
        if let Some((_, t)) = self.rows.iter().find(|(r, _)| names(r, key)) {
            return Some(t);
        }
        let mut p = key.to_string();
        while let Some(cut) = p.rfind(['.', '[']) {
            p.truncate(cut);
            let leaf =
                |r: &str| names(r, &p) && !self.rows.iter().any(|(x, _)| x.starts_with(&format!("{r}.")));
            if self.rows.iter().any(|(r, _)| leaf(r)) {
                return Some("");
            }
        }
        None
    }
}

/// Every key path of a JSON tree, lists' indices as `[]` (`selection.candidates[].score`).
pub fn key_paths(v: &Value) -> std::collections::BTreeSet<String> {
    fn walk(v: &Value, prefix: &str, out: &mut std::collections::BTreeSet<String>) {
        match v {
            Value::Object(map) => {
                for (k, v) in map {
                    let p = if prefix.is_empty() {
                        k.clone()
                    } else {
                        format!("{prefix}.{k}")
                    };
                    out.insert(p.clone());
                    walk(v, &p, out);
                }
            }
            Value::Array(items) => items.iter().for_each(|i| walk(i, &format!("{prefix}[]"), out)),
            _ => {}
        }
    }
    let mut out = std::collections::BTreeSet::new();
    walk(v, "", &mut out);
    out
}
