//! Mutation operators: one hostile change to a TOML, JSON or CSV text, with the names an
//! error about it should mention (the key or column changed, or `line` for a change of
//! the text's shape).

use rand::seq::SliceRandom;
use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// The format of a mutated file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Format {
    /// A TOML scenario or model spec.
    Toml,
    /// A model.json.
    Json,
    /// A CSV recording with a header.
    Csv,
}

pub use crate::mutant::Mutant;

/// A key path in a TOML or JSON document.
#[derive(Debug, Clone)]
enum Seg {
    Key(String),
    Index(usize),
}

fn path_text(p: &[Seg]) -> String {
    let mut s = String::new();
    for seg in p {
        match seg {
            Seg::Key(k) if s.is_empty() => s.push_str(k),
            Seg::Key(k) => {
                s.push('.');
                s.push_str(k);
            }
            Seg::Index(i) => s.push_str(&format!("[{i}]")),
        }
    }
    s
}

/// The keys of a path, innermost first: what an error may name.
fn path_names(p: &[Seg]) -> Vec<String> {
    let mut v: Vec<String> = p
        .iter()
        .rev()
        .filter_map(|s| match s {
            Seg::Key(k) => Some(k.to_lowercase()),
            Seg::Index(_) => None,
        })
        .collect();
    v.push(path_text(p).to_lowercase());
    v
}

/// Mutate `text` once.
pub fn mutate(text: &str, format: Format, rng: &mut ChaCha8Rng) -> Mutant {
    // One case in eight changes the text's shape; the rest change one value or key.
    if rng.gen_bool(0.125) || format == Format::Csv {
        if format == Format::Csv {
            return crate::csv_mutation::mutate_csv(text, rng);
        }
        return mutate_text(text, rng);
    }
    match format {
        Format::Toml => mutate_toml(text, rng),
        Format::Json => mutate_json(text, rng),
        Format::Csv => unreachable!(),
    }
}

/// Shape changes any text format can suffer: truncated, a line lost or doubled, a stray
/// character, emptied.
fn mutate_text(text: &str, rng: &mut ChaCha8Rng) -> Mutant {
    let lines: Vec<&str> = text.lines().collect();
    let names = vec!["line".to_string()];
    match rng.gen_range(0..5) {
        0 => {
            let mut cut = rng.gen_range(0..text.len().max(1));
            while !text.is_char_boundary(cut) {
                cut -= 1;
            }
            Mutant {
                text: text[..cut].to_string(),
                what: format!("truncated at byte {cut}"),
                names,
            }
        }
        1 if !lines.is_empty() => {
            let k = rng.gen_range(0..lines.len());
            let mut v = lines.clone();
            v.remove(k);
            Mutant {
                text: v.join("\n"),
                what: format!("line {} deleted", k + 1),
                names,
            }
        }
        2 if !lines.is_empty() => {
            let k = rng.gen_range(0..lines.len());
            let mut v = lines.clone();
            v.insert(k, lines[k]);
            Mutant {
                text: v.join("\n"),
                what: format!("line {} doubled", k + 1),
                names,
            }
        }
        3 => {
            let mut pos = rng.gen_range(0..text.len().max(1));
            while !text.is_char_boundary(pos) {
                pos -= 1;
            }
            // Stray characters: an opening brace, a quote, '=', ']', NUL, a non-ASCII
            // letter, a comma (as code points: the shape test counts braces in the text).
            let c = char::from_u32(*[0x7b, 0x22, 0x3d, 0x5d, 0x0, 0xe9, 0x2c].choose(rng).unwrap()).unwrap();
            let mut t = text.to_string();
            t.insert(pos, c);
            Mutant {
                text: t,
                what: format!("{c:?} inserted at byte {pos}"),
                names,
            }
        }
        _ => Mutant {
            text: String::new(),
            what: "emptied".into(),
            names,
        },
    }
}

/// Hostile TOML values: extremes, non-finite, wrong types.
fn hostile_toml(rng: &mut ChaCha8Rng) -> toml::Value {
    use toml::Value as V;
    let floats = [
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        1.7e308,
        -1.7e308,
        5e-324,
        0.0,
        -1.0,
        1e9,
        1e-9,
    ];
    match rng.gen_range(0..10) {
        0..=4 => V::Float(*floats.choose(rng).unwrap()),
        5 | 6 => V::Integer(*[0, -1, i64::MAX, i64::MIN, 1_000_000_000].choose(rng).unwrap()),
        7 => V::String(["", "x", "nan", "1e308"].choose(rng).unwrap().to_string()),
        8 => V::Boolean(true),
        _ => V::Array(vec![]),
    }
}

fn hostile_json(rng: &mut ChaCha8Rng) -> serde_json::Value {
    use serde_json::json;
    match rng.gen_range(0..10) {
        0..=4 => json!(*[1.7e308, -1.7e308, 5e-324, 0.0, -1.0, 1e9, 1e-9, 1e300]
            .choose(rng)
            .unwrap()),
        5 | 6 => json!(*[0i64, -1, i64::MAX, i64::MIN, 1_000_000_000].choose(rng).unwrap()),
        7 => json!(*["", "x", "NaN"].choose(rng).unwrap()),
        8 => serde_json::Value::Null,
        _ => json!([]),
    }
}

fn toml_leaves(v: &toml::Value, path: &mut Vec<Seg>, out: &mut Vec<Vec<Seg>>) {
    match v {
        toml::Value::Table(t) => {
            for (k, x) in t {
                path.push(Seg::Key(k.clone()));
                out.push(path.clone());
                toml_leaves(x, path, out);
                path.pop();
            }
        }
        toml::Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                path.push(Seg::Index(i));
                out.push(path.clone());
                toml_leaves(x, path, out);
                path.pop();
            }
        }
        _ => {}
    }
}

fn toml_at<'a>(v: &'a mut toml::Value, p: &[Seg]) -> Option<&'a mut toml::Value> {
    let mut cur = v;
    for s in p {
        cur = match (s, cur) {
            (Seg::Key(k), toml::Value::Table(t)) => t.get_mut(k)?,
            (Seg::Index(i), toml::Value::Array(a)) => a.get_mut(*i)?,
            _ => return None,
        };
    }
    Some(cur)
}

fn scale_factor(rng: &mut ChaCha8Rng) -> f64 {
    *[-1.0, 0.0, 0.5, 2.0, 10.0, 1000.0].choose(rng).unwrap()
}

fn mutate_toml(text: &str, rng: &mut ChaCha8Rng) -> Mutant {
    let Ok(mut doc) = text.parse::<toml::Table>().map(toml::Value::Table) else {
        return mutate_text(text, rng);
    };
    let mut paths = Vec::new();
    toml_leaves(&doc, &mut Vec::new(), &mut paths);
    let Some(p) = paths.choose(rng).cloned() else {
        return mutate_text(text, rng);
    };
    let names = path_names(&p);
    let where_ = path_text(&p);
    let what;
    match rng.gen_range(0..10) {
        0 => {
            // Delete the key (or the array element).
            let (last, parent) = p.split_last().unwrap();
            let parent = toml_at(&mut doc, parent).unwrap();
            match (last, parent) {
                (Seg::Key(k), toml::Value::Table(t)) => {
                    t.remove(k);
                }
                (Seg::Index(i), toml::Value::Array(a)) => {
                    a.remove(*i);
                }
                _ => {}
            }
            what = format!("{where_} deleted");
        }
        1 => {
            let parent = toml_at(&mut doc, &p[..p.len() - 1]).unwrap();
            if let toml::Value::Table(t) = parent {
                t.insert("unknown_key".into(), toml::Value::Float(1.0));
            }
            what = format!("unknown_key added beside {where_}");
            let mut n = names.clone();
            n.push("unknown_key".into());
            return finish_toml(doc, what, n, text, rng);
        }
        2 | 3 => {
            let leaf = toml_at(&mut doc, &p).unwrap();
            let f = scale_factor(rng);
            match leaf {
                toml::Value::Float(x) => *x *= f,
                toml::Value::Integer(i) => *i = (*i as f64 * f) as i64,
                _ => *leaf = hostile_toml(rng),
            }
            what = format!("{where_} = {leaf}");
        }
        _ => {
            let leaf = toml_at(&mut doc, &p).unwrap();
            *leaf = hostile_toml(rng);
            what = format!("{where_} = {leaf}");
        }
    }
    finish_toml(doc, what, names, text, rng)
}

fn finish_toml(
    doc: toml::Value,
    what: String,
    names: Vec<String>,
    text: &str,
    rng: &mut ChaCha8Rng,
) -> Mutant {
    match toml::to_string(&doc) {
        Ok(t) => Mutant { text: t, what, names },
        Err(_) => mutate_text(text, rng),
    }
}

fn json_leaves(v: &serde_json::Value, path: &mut Vec<Seg>, out: &mut Vec<Vec<Seg>>) {
    match v {
        serde_json::Value::Object(t) => {
            for (k, x) in t {
                path.push(Seg::Key(k.clone()));
                out.push(path.clone());
                json_leaves(x, path, out);
                path.pop();
            }
        }
        serde_json::Value::Array(a) => {
            for (i, x) in a.iter().enumerate() {
                path.push(Seg::Index(i));
                out.push(path.clone());
                json_leaves(x, path, out);
                path.pop();
            }
        }
        _ => {}
    }
}

fn json_at<'a>(v: &'a mut serde_json::Value, p: &[Seg]) -> Option<&'a mut serde_json::Value> {
    let mut cur = v;
    for s in p {
        cur = match (s, cur) {
            (Seg::Key(k), serde_json::Value::Object(t)) => t.get_mut(k)?,
            (Seg::Index(i), serde_json::Value::Array(a)) => a.get_mut(*i)?,
            _ => return None,
        };
    }
    Some(cur)
}

fn mutate_json(text: &str, rng: &mut ChaCha8Rng) -> Mutant {
    let Ok(mut doc) = serde_json::from_str::<serde_json::Value>(text) else {
        return mutate_text(text, rng);
    };
    let mut paths = Vec::new();
    json_leaves(&doc, &mut Vec::new(), &mut paths);
    // Numbers are where the hostile values hurt: most mutations pick one.
    let numeric: Vec<Vec<Seg>> = paths
        .iter()
        .filter(|p| json_at(&mut doc.clone(), p).is_some_and(|v| v.is_number()))
        .cloned()
        .collect();
    let pool = if !numeric.is_empty() && rng.gen_bool(0.7) {
        &numeric
    } else {
        &paths
    };
    let Some(p) = pool.choose(rng).cloned() else {
        return mutate_text(text, rng);
    };
    let names = path_names(&p);
    let where_ = path_text(&p);
    let what = match rng.gen_range(0..11) {
        10 => return huge_json_array(doc, &p, names),
        0 => {
            let (last, parent) = p.split_last().unwrap();
            match (last, json_at(&mut doc, parent).unwrap()) {
                (Seg::Key(k), serde_json::Value::Object(t)) => {
                    t.remove(k);
                }
                (Seg::Index(i), serde_json::Value::Array(a)) => {
                    a.remove(*i);
                }
                _ => {}
            }
            format!("{where_} deleted")
        }
        1..=3 => {
            let leaf = json_at(&mut doc, &p).unwrap();
            let f = scale_factor(rng);
            *leaf = match leaf.as_f64() {
                Some(x) if leaf.is_f64() => serde_json::json!(x * f),
                Some(x) => serde_json::json!((x * f) as i64),
                None => hostile_json(rng),
            };
            format!("{where_} = {leaf}")
        }
        4 => {
            // NaN is no JSON number: the text must be refused with its line.
            let leaf = json_at(&mut doc, &p).unwrap();
            *leaf = serde_json::json!("__NAN__");
            let t = serde_json::to_string_pretty(&doc)
                .unwrap()
                .replace("\"__NAN__\"", "NaN");
            return Mutant {
                text: t,
                what: format!("{where_} = NaN"),
                names: vec!["line".into()],
            };
        }
        _ => {
            let leaf = json_at(&mut doc, &p).unwrap();
            *leaf = hostile_json(rng);
            format!("{where_} = {leaf}")
        }
    };
    Mutant {
        text: serde_json::to_string_pretty(&doc).unwrap(),
        what,
        names,
    }
}

/// A huge valid-looking array: the array holding the leaf at `p` (or the leaf itself in
/// one) grown to 200,000 copies of its first element, a few MB of plausible values: the
/// sizes must be checked before the work they would cost.
fn huge_json_array(mut doc: serde_json::Value, p: &[Seg], names: Vec<String>) -> Mutant {
    let depth = (0..p.len()).rev().find(|&d| matches!(p[d], Seg::Index(_)));
    let where_ = match depth {
        Some(d) => {
            let parent = &p[..d];
            if let Some(serde_json::Value::Array(a)) = json_at(&mut doc, parent) {
                let first = a[0].clone();
                a.resize(200_000, first);
            }
            path_text(parent)
        }
        None => {
            let leaf = json_at(&mut doc, p).unwrap();
            *leaf = serde_json::Value::Array(vec![leaf.clone(); 200_000]);
            path_text(p)
        }
    };
    Mutant {
        text: serde_json::to_string(&doc).unwrap(),
        what: format!("{where_}: an array of 200,000 elements"),
        names,
    }
}

/// Every numeric value of a TOML or JSON text replaced, one at a time, by each extreme a
/// user's file may hold (zero, negative, tiny, huge, the largest float, the smallest
/// subnormal; TOML also infinity and NaN): the systematic sweep (`--sweep`), where the
/// random cases draw one key and one value. Array elements past the second are left out
/// (a model's weights would otherwise make thousands of cases); a CSV gives none.
pub fn sweep(text: &str, format: Format) -> Vec<Mutant> {
    const FLOATS: [f64; 9] = [
        0.0,
        -1.0,
        1e-9,
        1e9,
        1.7e308,
        -1.7e308,
        5e-324,
        f64::INFINITY,
        f64::NAN,
    ];
    const INTS: [i64; 5] = [0, -1, 1_000_000_000, i64::MAX, i64::MIN];
    let short = |p: &Vec<Seg>| p.iter().all(|s| !matches!(s, Seg::Index(i) if *i >= 2));
    let mut out = Vec::new();
    match format {
        Format::Toml => {
            let Ok(doc) = text.parse::<toml::Table>().map(toml::Value::Table) else {
                return out;
            };
            let mut paths = Vec::new();
            toml_leaves(&doc, &mut Vec::new(), &mut paths);
            for p in paths.iter().filter(|p| short(p)) {
                let values: Vec<toml::Value> = match toml_at(&mut doc.clone(), p) {
                    Some(toml::Value::Float(_)) => FLOATS.iter().map(|v| toml::Value::Float(*v)).collect(),
                    Some(toml::Value::Integer(_)) => INTS.iter().map(|v| toml::Value::Integer(*v)).collect(),
                    _ => continue,
                };
                for v in values {
                    let mut d = doc.clone();
                    *toml_at(&mut d, p).unwrap() = v.clone();
                    if let Ok(t) = toml::to_string(&d) {
                        let what = format!("{} = {v}", path_text(p));
                        out.push(Mutant {
                            text: t,
                            what,
                            names: path_names(p),
                        });
                    }
                }
            }
        }
        Format::Json => {
            let Ok(doc) = serde_json::from_str::<serde_json::Value>(text) else {
                return out;
            };
            let mut paths = Vec::new();
            json_leaves(&doc, &mut Vec::new(), &mut paths);
            for p in paths.iter().filter(|p| short(p)) {
                if !json_at(&mut doc.clone(), p).is_some_and(|v| v.is_number()) {
                    continue;
                }
                // JSON holds no infinity or NaN (the random cases write NaN as text).
                for v in FLOATS.iter().filter(|v| v.is_finite()) {
                    let mut d = doc.clone();
                    *json_at(&mut d, p).unwrap() = serde_json::json!(v);
                    let what = format!("{} = {v:e}", path_text(p));
                    let text = serde_json::to_string_pretty(&d).unwrap();
                    out.push(Mutant {
                        text,
                        what,
                        names: path_names(p),
                    });
                }
            }
        }
        Format::Csv => {}
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_sweep_sets_each_number_to_each_extreme_and_leaves_long_arrays_short() {
        let toml = "a = 1.5\nn = 3\nname = \"x\"\n[s]\nv = [1.0, 2.0, 3.0]\n";
        let m = sweep(toml, Format::Toml);
        // a: 9 floats; n: 5 integers; v[0], v[1]: 9 each; v[2] and the string: none.
        assert_eq!(m.len(), 9 + 5 + 18);
        assert!(m
            .iter()
            .any(|m| m.what == "a = 1.7e308" || m.what.starts_with("a = 170000")));
        assert!(m
            .iter()
            .any(|m| m.what == "s.v[1] = nan" && m.names.contains(&"v".to_string())));
        assert!(m
            .iter()
            .all(|m| !m.what.starts_with("s.v[2]") && !m.what.starts_with("name")));
        let json = r#"{"w": [[1.0, 2.0, 3.0]], "dt": 0.1, "kind": "x"}"#;
        let m = sweep(json, Format::Json);
        // JSON holds no infinity or NaN: 7 finite extremes for dt, w[0][0] and w[0][1].
        assert_eq!(m.len(), 3 * 7);
        assert!(m
            .iter()
            .all(|m| serde_json::from_str::<serde_json::Value>(&m.text).is_ok()));
        assert!(sweep("t,u\n0,1\n", Format::Csv).is_empty());
    }
}
