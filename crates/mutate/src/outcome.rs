//! Judging a case (exit code, message, what it left) and the report over all cases.

use crate::corpus::Surface;
use crate::Verdict;
use std::collections::BTreeMap;
use std::path::Path;

/// Judge a finished case: exit code (`None`: killed by a signal), its stderr, the case's
/// folder, the output folder it was given, the mutated file's name, and the names an
/// error about the mutation may give.
pub fn judge(
    code: Option<i32>,
    stderr: &str,
    dir: &Path,
    out: &Path,
    s: &Surface,
    names: &[String],
) -> Verdict {
    let file = s.file_name.as_str();
    if let Some(tmp) = find_temporary(dir) {
        return Verdict::Failed(format!("temporary file left: {tmp}"));
    }
    if stderr.contains("panicked") || code == Some(101) {
        return Verdict::Failed("panic".into());
    }
    match code {
        Some(0) => match non_finite_written(out, &s.base_out) {
            Some(w) => Verdict::Failed(format!("non-finite written with exit 0: {w}")),
            None => Verdict::Accepted,
        },
        Some(2) => {
            // The output folder may be the input's own (then it holds the input).
            let written = std::fs::read_dir(out).map(|d| {
                d.flatten()
                    .any(|e| e.file_name().to_string_lossy() != file && e.file_name() != "stderr.txt")
            });
            if written.unwrap_or(false) {
                return Verdict::Failed("refused, but the output folder was written".into());
            }
            let low = stderr.to_lowercase();
            let named = low.contains(&file.to_lowercase()) && names.iter().any(|n| low.contains(n.as_str()));
            Verdict::Refused { named }
        }
        Some(c) => Verdict::Failed(format!("exit code {c}")),
        None => Verdict::Failed("killed by a signal".into()),
    }
}

/// Of two writers that both refused, the one refused on its input rather than on the
/// output folder the other held (the first when neither or both were).
pub fn input_refusal<'a>(a: (Option<i32>, &'a str), b: (Option<i32>, &'a str)) -> (Option<i32>, &'a str) {
    let on_folder = |e: &str| e.contains("cannot write to output folder");
    if on_folder(a.1) && !on_folder(b.1) {
        b
    } else {
        a
    }
}

fn find_temporary(dir: &Path) -> Option<String> {
    let rd = std::fs::read_dir(dir).ok()?;
    for e in rd.flatten() {
        let name = e.file_name().to_string_lossy().into_owned();
        if name.contains(".tmp") || name.starts_with(".rhonn-stage-") || name == ".rhonn-commit" {
            return Some(e.path().display().to_string());
        }
        if e.path().is_dir() {
            if let Some(t) = find_temporary(&e.path()) {
                return Some(t);
            }
        }
    }
    None
}

fn is_non_finite_cell(c: &str) -> bool {
    matches!(
        c.trim().to_lowercase().as_str(),
        "nan" | "inf" | "-inf" | "+inf" | "infinity" | "-infinity"
    )
}

/// The first null in `v` where `reference` (the same file written from the valid base)
/// has a number: a NaN or infinity, which serde writes as null. Nulls of optional fields,
/// null in the reference too, are no NaN.
fn json_null(v: &serde_json::Value, reference: Option<&serde_json::Value>, path: &str) -> Option<String> {
    use serde_json::Value as V;
    match v {
        V::Null if reference.is_some_and(|r| r.is_number()) => Some(path.to_string()),
        V::Array(a) => a.iter().enumerate().find_map(|(i, x)| {
            // Arrays may change length: compare with the reference's first element.
            let r = reference.and_then(|r| r.get(i).or_else(|| r.get(0)));
            json_null(x, r, &format!("{path}[{i}]"))
        }),
        V::Object(o) => o
            .iter()
            .find_map(|(k, x)| json_null(x, reference.and_then(|r| r.get(k)), &format!("{path}.{k}"))),
        _ => None,
    }
}

/// The first NaN, infinity or JSON null (how serde writes a NaN) in the folder's CSV and
/// JSON files.
pub fn non_finite_written(out: &Path, base_out: &Path) -> Option<String> {
    let rd = std::fs::read_dir(out).ok()?;
    for e in rd.flatten() {
        let p = e.path();
        let name = e.file_name().to_string_lossy().into_owned();
        let Ok(text) = std::fs::read_to_string(&p) else {
            continue;
        };
        if name.ends_with(".csv") {
            for (k, line) in text.lines().enumerate() {
                if line.split(',').any(is_non_finite_cell) {
                    return Some(format!("{name} line {}", k + 1));
                }
            }
        } else if name.ends_with(".json") {
            match serde_json::from_str::<serde_json::Value>(&text) {
                Ok(v) => {
                    let reference: Option<serde_json::Value> = std::fs::read_to_string(base_out.join(&name))
                        .ok()
                        .and_then(|t| serde_json::from_str(&t).ok());
                    // A model's settings may be optional (null when unset, also where a
                    // summary repeats them under `model`); its numbers (weights, scaling,
                    // normalisation, ranges) may not.
                    let numbers = ["weights", "scaling", "norm", "range", "params"];
                    let found = json_null(&v, reference.as_ref(), "")
                        .filter(|at| name != "model.json" || numbers.iter().any(|n| at.contains(n)))
                        .filter(|at| !at.starts_with(".model.") && !at.starts_with(".scenario."))
                        // Documented as null when the error never settled in its band.
                        .filter(|at| !at.ends_with("convergence_time_s"));
                    if let Some(at) = found {
                        return Some(format!("{name}: null at {at}"));
                    }
                }
                Err(e) => return Some(format!("{name}: not JSON ({e})")),
            }
        }
    }
    None
}

/// One surface's counts.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct SurfaceStats {
    /// Cases run.
    pub cases: usize,
    /// Exit 0 with finite outputs.
    pub accepted: usize,
    /// Exit 2.
    pub refused: usize,
    /// Exit 2 with a message naming the file and the field, column or line.
    pub named: usize,
    /// Failures of the rules.
    pub failed: usize,
}

/// A failed case, enough to run it again.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Failure {
    /// Case index.
    pub case: usize,
    /// Surface name.
    pub surface: String,
    /// The mutation.
    pub what: String,
    /// Which rule failed.
    pub reason: String,
    /// The start of its stderr.
    pub stderr: String,
}

/// Every case's outcome.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct Report {
    /// Per surface.
    pub surfaces: BTreeMap<String, SurfaceStats>,
    /// Failed cases.
    pub failures: Vec<Failure>,
    /// Refusals whose message names neither the file nor the field (case, surface, what,
    /// message).
    pub unnamed: Vec<Failure>,
    /// Cases per way of running them (`flavor::Flavor::name`).
    pub flavors: BTreeMap<String, usize>,
}

impl Report {
    pub(crate) fn new(surfaces: &[Surface]) -> Self {
        let mut r = Report::default();
        for s in surfaces {
            r.surfaces.insert(s.name.clone(), SurfaceStats::default());
        }
        r
    }

    pub(crate) fn add(
        &mut self,
        case: usize,
        s: &Surface,
        (what, flavor): (String, &str),
        stderr: &str,
        v: Verdict,
    ) {
        *self.flavors.entry(flavor.to_string()).or_default() += 1;
        let st = self.surfaces.entry(s.name.clone()).or_default();
        st.cases += 1;
        let item = |reason: String| Failure {
            case,
            surface: s.name.clone(),
            what: what.clone(),
            reason,
            stderr: stderr.chars().take(400).collect(),
        };
        match v {
            Verdict::Accepted => st.accepted += 1,
            Verdict::Refused { named } => {
                st.refused += 1;
                if named {
                    st.named += 1;
                } else {
                    self.unnamed
                        .push(item("error names neither the file and the field".into()));
                }
            }
            Verdict::Failed(reason) => {
                st.failed += 1;
                self.failures.push(item(reason));
            }
        }
    }

    /// Totals over surfaces: (cases, accepted, refused, named, failed).
    pub fn totals(&self) -> SurfaceStats {
        let mut t = SurfaceStats::default();
        for s in self.surfaces.values() {
            t.cases += s.cases;
            t.accepted += s.accepted;
            t.refused += s.refused;
            t.named += s.named;
            t.failed += s.failed;
        }
        t
    }

    /// Share of refusals that name the file and the field, column or line (1 when none).
    pub fn named_share(&self) -> f64 {
        let t = self.totals();
        if t.refused == 0 {
            1.0
        } else {
            t.named as f64 / t.refused as f64
        }
    }

    /// A table of the surfaces and totals, then the failures.
    pub fn table(&self) -> String {
        let mut s = format!(
            "{:<36} {:>6} {:>8} {:>7} {:>6} {:>6}\n",
            "surface", "cases", "accepted", "refused", "named", "failed"
        );
        let row = |n: &str, x: &SurfaceStats| {
            format!(
                "{:<36} {:>6} {:>8} {:>7} {:>6} {:>6}\n",
                n, x.cases, x.accepted, x.refused, x.named, x.failed
            )
        };
        for (n, x) in &self.surfaces {
            s.push_str(&row(n, x));
        }
        s.push_str(&row("all", &self.totals()));
        s.push_str(&format!(
            "errors naming the file and the field, column or line: {:.1} %\n",
            100.0 * self.named_share()
        ));
        let flavors: Vec<String> = self.flavors.iter().map(|(f, n)| format!("{f} {n}")).collect();
        s.push_str(&format!("cases run: {}\n", flavors.join(", ")));
        for f in &self.failures {
            s.push_str(&format!(
                "FAILED case {} ({}; {}): {}\n  {}\n",
                f.case,
                f.surface,
                f.what,
                f.reason,
                f.stderr.replace('\n', "\n  ")
            ));
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::input_refusal;

    #[test]
    fn of_two_refused_writers_the_one_refused_on_its_input_is_judged() {
        let held =
            "error: cannot write to output folder /w/out: another rhonn command is writing into it now\n";
        let input = "error: /w/model.json is not a model: field `model.spec.nk`\n";
        assert_eq!(input_refusal((Some(2), held), (Some(2), input)).1, input);
        assert_eq!(input_refusal((Some(2), input), (Some(2), held)).1, input);
        assert_eq!(input_refusal((Some(2), held), (Some(2), held)).1, held);
    }
}
