//! `report.html`: one self-contained page per output folder (inline SVG and CSS, no
//! script, no font or file fetched from anywhere; it opens offline and from a file URL):
//! the run's settings and figures as tables (from `summary.json`), its findings in words,
//! and every plot of the folder. Written by every command that writes a folder, and by
//! `rhonn report DIR` for folders made by older versions or merged campaigns.

use crate::{Error, Result};
use serde_json::Value;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Build `dir/report.html` from the folder's `summary.json` and SVG files (written under
/// a temporary name, then renamed); returns its path.
pub fn write_report(dir: &Path) -> Result<PathBuf> {
    write_report_as(dir, dir)
}

/// [`write_report`] of a staging folder `dir` whose files will be in `shown` (the page
/// names that folder).
pub fn write_report_as(dir: &Path, shown: &Path) -> Result<PathBuf> {
    let html = render(dir, shown)?;
    let path = dir.join("report.html");
    let tmp = dir.join(".report.html.partial");
    let fail = |e: std::io::Error| Error::File {
        path: path.clone(),
        message: e.to_string(),
    };
    std::fs::write(&tmp, html).map_err(fail)?;
    std::fs::rename(&tmp, &path).map_err(fail)?;
    Ok(path)
}

const STYLE: &str = "body{font-family:system-ui,-apple-system,'Segoe UI',sans-serif;margin:2em auto;max-width:1000px;color:#222;line-height:1.45;padding:0 1em}
h1{font-size:1.6em;margin-bottom:0.2em}h2{font-size:1.25em;margin-top:1.6em;border-bottom:1px solid #ccc}
table{border-collapse:collapse;margin:0.5em 0;font-size:0.92em}td,th{border:1px solid #ddd;padding:3px 8px;text-align:left;vertical-align:top}
th{background:#f3f3f3}td.num{text-align:right;font-variant-numeric:tabular-nums}td.what{color:#555;font-size:90%}
figure{margin:1em 0}figure svg{max-width:100%;height:auto;border:1px solid #eee}figcaption{font-size:0.9em;color:#555}
.muted{color:#666;font-size:0.9em}ul.findings li{margin:0.2em 0}";

/// The page's HTML.
fn render(dir: &Path, shown: &Path) -> Result<String> {
    let unreadable =
        |p: &Path, e: &dyn std::fmt::Display| Error::Input(format!("cannot read {}: {e}", p.display()));
    if !dir.is_dir() {
        return Err(Error::Input(format!(
            "{} is not a folder written by rhonn (give the folder of a run, fit, prediction, identification or campaign)",
            dir.display()
        )));
    }
    let summary_path = dir.join("summary.json");
    let summary: Option<Value> = match std::fs::read_to_string(&summary_path) {
        Ok(text) => Some(serde_json::from_str(&text).map_err(|e| unreadable(&summary_path, &e))?),
        Err(_) => None,
    };
    let mut svgs: Vec<PathBuf> = std::fs::read_dir(dir)
        .map_err(|e| unreadable(dir, &e))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "svg"))
        .collect();
    svgs.sort();
    if summary.is_none() && svgs.is_empty() {
        return Err(Error::Input(format!(
            "{} holds neither summary.json nor plots: not a folder written by rhonn",
            dir.display()
        )));
    }
    let title = title_of(shown, summary.as_ref());
    let mut h = String::new();
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><meta name=\"viewport\" content=\"width=device-width,initial-scale=1\">\n<title>{}</title><style>{STYLE}</style></head><body>\n<h1>{}</h1>\n<p class=\"muted\">rhonn {} report of <code>{}</code>: findings, every plot of the folder, then the figures and settings of summary.json (display units; the CSV files are SI).</p>\n",
        esc(&title),
        esc(&title),
        env!("CARGO_PKG_VERSION"),
        esc(&shown.display().to_string())
    );
    if let Some(s) = &summary {
        let findings = collect_findings(s);
        if !findings.is_empty() {
            h.push_str("<h2>Findings</h2>\n<ul class=\"findings\">\n");
            for f in findings {
                let _ = writeln!(h, "<li>{}</li>", esc(&f));
            }
            h.push_str("</ul>\n");
        }
    }
    if !svgs.is_empty() {
        h.push_str("<h2>Plots</h2>\n");
    }
    for p in &svgs {
        let svg = std::fs::read_to_string(p).map_err(|e| unreadable(p, &e))?;
        let name = p
            .file_name()
            .map(|n| n.to_string_lossy().to_string())
            .unwrap_or_default();
        let _ = writeln!(
            h,
            "<figure>{}<figcaption>{}</figcaption></figure>",
            strip_xml_prolog(&svg),
            esc(&name)
        );
    }
    if let Some(s) = &summary {
        h.push_str("<h2>Figures and settings (summary.json)</h2>\n");
        let mut rows = Vec::new();
        flatten("", s, &mut rows);
        h.push_str("<table><tr><th>field</th><th>value</th><th>what it is</th></tr>\n");
        let fields = crate::fields::Describer::for_summary(s);
        for (k, v) in rows {
            let class = if v.parse::<f64>().is_ok() {
                " class=\"num\""
            } else {
                ""
            };
            // The field's own doc comment, else the glossary's word for its name.
            let what = fields
                .describe(&k)
                .map(str::to_string)
                .or_else(|| crate::glossary::describe(&k))
                .unwrap_or_default();
            let _ = writeln!(
                h,
                "<tr><td>{}</td><td{class}>{}</td><td class=\"what\">{}</td></tr>",
                esc(&k),
                esc(&v),
                esc(&what)
            );
        }
        h.push_str("</table>\n");
    }
    h.push_str("</body></html>\n");
    Ok(h)
}

/// The page title: the scenario's or the data's name, else the folder's.
fn title_of(dir: &Path, summary: Option<&Value>) -> String {
    let folder = dir
        .file_name()
        .map(|n| n.to_string_lossy().to_string())
        .unwrap_or_else(|| dir.display().to_string());
    let name = summary.and_then(|s| {
        s.pointer("/scenario/name")
            .or_else(|| s.get("scenario"))
            .and_then(Value::as_str)
            .map(str::to_string)
    });
    match name {
        Some(n) => format!("{n} ({folder})"),
        None => folder,
    }
}

/// Every `findings` array of the summary, in order, and every `warnings` array's lines
/// led by "warning:" (what the user must know, said plainly at the top).
fn collect_findings(v: &Value) -> Vec<String> {
    let mut out = Vec::new();
    match v {
        Value::Object(m) => {
            for (k, x) in m {
                if k == "findings" || k == "warnings" {
                    let lead = if k == "warnings" { "warning: " } else { "" };
                    if let Value::Array(a) = x {
                        out.extend(a.iter().filter_map(|f| f.as_str().map(|f| format!("{lead}{f}"))));
                    }
                } else {
                    out.extend(collect_findings(x));
                }
            }
        }
        Value::Array(a) => a.iter().for_each(|x| out.extend(collect_findings(x))),
        _ => {}
    }
    out
}

/// Rows `path -> value` of the summary's leaves (long arrays of numbers shortened).
fn flatten(prefix: &str, v: &Value, rows: &mut Vec<(String, String)>) {
    let key = |k: &str| {
        if prefix.is_empty() {
            k.to_string()
        } else {
            format!("{prefix}.{k}")
        }
    };
    match v {
        Value::Object(m) => {
            for (k, x) in m {
                if k != "findings" && k != "warnings" {
                    flatten(&key(k), x, rows);
                }
            }
        }
        Value::Array(a) if a.is_empty() => rows.push((prefix.to_string(), "none".into())),
        Value::Array(a) if a.iter().all(|x| x.is_number()) => {
            let shown: Vec<String> = a.iter().take(12).map(number).collect();
            let more = if a.len() > 12 {
                format!(" ... ({} values)", a.len())
            } else {
                String::new()
            };
            rows.push((prefix.to_string(), format!("[{}]{more}", shown.join(", "))));
        }
        Value::Array(a) => {
            for (i, x) in a.iter().enumerate().take(50) {
                flatten(&format!("{prefix}[{i}]"), x, rows);
            }
            if a.len() > 50 {
                rows.push((
                    prefix.to_string(),
                    format!("... {} entries in all (summary.json)", a.len()),
                ));
            }
        }
        Value::Number(_) => rows.push((prefix.to_string(), number(v))),
        Value::String(s) => rows.push((prefix.to_string(), s.clone())),
        Value::Bool(b) => rows.push((prefix.to_string(), b.to_string())),
        Value::Null => rows.push((prefix.to_string(), "none".into())),
    }
}

/// A number with 6 significant digits.
fn number(v: &Value) -> String {
    match v.as_f64() {
        Some(x) if x != 0.0 && (x.abs() >= 1e6 || x.abs() < 1e-3) => format!("{x:.5e}"),
        Some(x) => {
            let s = format!("{x:.6}");
            let s = s.trim_end_matches('0').trim_end_matches('.');
            s.to_string()
        }
        None => v.to_string(),
    }
}

fn strip_xml_prolog(svg: &str) -> &str {
    match svg.find("<svg") {
        Some(i) => &svg[i..],
        None => svg,
    }
}

/// HTML-escaped text.
fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_page_from_a_folder_with_figures_findings_and_plots() {
        let d = tempfile::tempdir().unwrap();
        std::fs::write(
            d.path().join("summary.json"),
            r#"{"scenario": {"name": "x<y"}, "figures": {"iae_mpa_s": 10.5, "steps": [1, 2], "overshoot_percent": []}, "findings": ["adaptive better"]}"#,
        )
        .unwrap();
        std::fs::write(
            d.path().join("a.svg"),
            "<?xml version=\"1.0\"?><svg width=\"10\" height=\"10\"></svg>",
        )
        .unwrap();
        let p = write_report(d.path()).unwrap();
        let html = std::fs::read_to_string(p).unwrap();
        assert!(html.contains("<title>x&lt;y"));
        assert!(html.contains("<li>adaptive better</li>"));
        assert!(html.contains("figures.iae_mpa_s</td><td class=\"num\">10.5"));
        // An empty list reads "none", not "[]".
        assert!(
            html.contains("figures.overshoot_percent</td><td") && !html.contains("[]"),
            "{html}"
        );
        assert!(html.contains("<figure><svg width=\"10\""));
        assert!(
            !html.contains("<script") && !html.contains("http"),
            "self-contained"
        );
        assert!(!d.path().join(".report.html.partial").exists());
    }

    #[test]
    fn a_folder_without_rhonn_files_is_a_clear_error() {
        let d = tempfile::tempdir().unwrap();
        let e = write_report(d.path()).unwrap_err().to_string();
        assert!(e.contains("neither summary.json nor plots"), "{e}");
        let e = write_report(&d.path().join("none")).unwrap_err().to_string();
        assert!(e.contains("is not a folder written by rhonn"), "{e}");
    }
}
