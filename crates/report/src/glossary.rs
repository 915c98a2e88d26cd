//! The glossary of the figures (docs/reference/glossary.md, compiled in): the concepts
//! behind them and the names a campaign's columns take. Its first column names them (in
//! backticks; `*` and `...` stand for any text), its second says what they are. A report's
//! table reads each field's own doc comment first ([`crate::fields`]), this for the rest.

const GLOSSARY: &str = include_str!("../../../docs/reference/glossary.md");

/// Whether `name` matches a glossary pattern (`*` and `...`: any text).
pub fn matches(pattern: &str, name: &str) -> bool {
    let p = pattern.replace("...", "*");
    let parts: Vec<&str> = p.split('*').collect();
    if parts.len() == 1 {
        return p == name;
    }
    let (first, last) = (parts[0], parts[parts.len() - 1]);
    if name.len() < first.len() + last.len() || !name.starts_with(first) || !name.ends_with(last) {
        return false;
    }
    let mut rest = &name[first.len()..name.len() - last.len()];
    for mid in &parts[1..parts.len() - 1] {
        match rest.find(mid) {
            Some(i) => rest = &rest[i + mid.len()..],
            None => return false,
        }
    }
    true
}

/// The glossary's rows: the names of the first column and the text of the second with its
/// Markdown backticks and escapes removed.
fn rows() -> Vec<(Vec<&'static str>, String)> {
    GLOSSARY
        .lines()
        .filter(|l| l.starts_with("| ") && !l.starts_with("| name in outputs"))
        .filter_map(|l| {
            let cells: Vec<&str> = l[2..].splitn(2, " | ").collect();
            let [names, text] = cells[..] else { return None };
            let names: Vec<&str> = names.split('`').skip(1).step_by(2).collect();
            let text = text.trim_end_matches(" |").replace('`', "").replace("\\|", "|");
            Some((names, text))
        })
        .collect()
}

/// What the glossary says of a summary.json key (`figures.regulation.iae_mpa_s`: its last
/// name, `iae_mpa_s`, without an index), or None.
pub fn describe(key: &str) -> Option<String> {
    let last = key.rsplit('.').next()?;
    let last = last.split('[').next()?;
    // A row naming the key itself before a row whose pattern covers it (`*_rms_*` would
    // take `current_rms_change_per_sample_a`).
    let rows = rows();
    rows.iter()
        .find(|(names, _)| names.contains(&last))
        .or_else(|| {
            rows.iter()
                .find(|(names, _)| names.iter().any(|n| matches(n, last)))
        })
        .map(|(_, text)| text.clone())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keys_are_described_by_their_last_name() {
        let d = describe("control[].iae").unwrap();
        assert!(d.starts_with("IAE: the integral"), "{d}");
        assert!(describe("identification.parallel[1].convergence_time_s").is_some());
        assert!(describe("no_such_key_anywhere").is_none());
        let activity = describe("control[].input_rms_change_per_sample").unwrap();
        assert!(activity.contains("actuator activity"), "{activity}");
        assert!(describe("training_rms_error")
            .unwrap()
            .starts_with("root mean square"));
        assert!(matches("*_rms_*", "training_rms_error") && !matches("*_rms_*", "rms_error"));
    }
}
