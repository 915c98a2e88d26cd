//! Every kind of `report.html`, opened in a real browser (headless Chromium, Debian's
//! `chromium` package, which CI installs): the page loads from a file URL with no console
//! message, shows text and every figure with a non-zero size, fetches nothing, and a
//! screenshot of it is written (`target/report-screenshots/`). Without a Chromium on the
//! machine the test says so on stderr and checks the pages' HTML only.

use crate::util;

use std::path::{Path, PathBuf};
use std::process::Command;
use util::{rhonn, stderr};

/// Chromium: `RHONN_CHROMIUM`, else the first of the usual names on PATH.
fn chromium() -> Option<PathBuf> {
    if let Some(p) = std::env::var_os("RHONN_CHROMIUM") {
        return Some(PathBuf::from(p));
    }
    let path = std::env::var_os("PATH")?;
    [
        "chromium",
        "chromium-browser",
        "google-chrome",
        "google-chrome-stable",
    ]
    .iter()
    .flat_map(|n| std::env::split_paths(&path).map(move |d| d.join(n)))
    .find(|p| p.is_file())
}

fn headless(chrome: &Path, profile: &Path) -> Command {
    let mut c = Command::new(chrome);
    c.args([
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-quic",
        "--no-first-run",
        "--disable-background-networking",
        "--disable-component-update",
        "--disable-sync",
        "--enable-logging=stderr",
        "--v=0",
    ])
    .arg(format!("--user-data-dir={}", profile.display()));
    c
}

/// What the browser saw of one report: figure sizes, text length.
#[derive(serde::Deserialize, Debug)]
struct Seen {
    figures: Vec<(f64, f64)>,
    text: usize,
}

/// Open `report` in an iframe of a test page (file access between local files allowed
/// for the test page only), measure it with the test page's script, read the result
/// from the DOM Chromium dumps; check the console.
fn open(chrome: &Path, work: &Path, report: &Path) -> Seen {
    let url = format!("file://{}", report.canonicalize().unwrap().display());
    let page = work.join("check.html");
    std::fs::write(
        &page,
        format!(
            r#"<!DOCTYPE html><html><head><meta charset="utf-8"></head><body><pre id="out">pending</pre>
<iframe id="f" style="width:1000px;height:800px"></iframe><script>
const f = document.getElementById('f');
f.addEventListener('load', () => {{
  const d = f.contentDocument;
  const figs = [...d.querySelectorAll('figure svg')].map(s => {{ const r = s.getBoundingClientRect(); return [r.width, r.height]; }});
  document.getElementById('out').textContent = JSON.stringify({{figures: figs, text: d.body ? d.body.innerText.length : 0}});
}});
f.src = {url:?};
</script></body></html>"#
        ),
    )
    .unwrap();
    let o = headless(chrome, &work.join("profile"))
        .arg("--allow-file-access-from-files")
        .arg("--dump-dom")
        .arg(format!("file://{}", page.display()))
        .output()
        .expect("Chromium runs");
    let log = String::from_utf8_lossy(&o.stderr);
    let console: Vec<&str> = log.lines().filter(|l| l.contains(":CONSOLE")).collect();
    assert!(
        console.is_empty(),
        "{}: console messages {console:?}",
        report.display()
    );
    let dom = String::from_utf8_lossy(&o.stdout);
    let json = dom
        .split("<pre id=\"out\">")
        .nth(1)
        .and_then(|s| s.split("</pre>").next())
        .unwrap_or_else(|| panic!("{}: no result in the DOM: {dom:.300}", report.display()));
    serde_json::from_str(&json.replace("&quot;", "\"")).unwrap_or_else(|e| panic!("{json}: {e}"))
}

fn screenshot(chrome: &Path, work: &Path, report: &Path, name: &str) {
    let dir = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join("target/report-screenshots");
    std::fs::create_dir_all(&dir).unwrap();
    let png = dir.join(format!("{name}.png"));
    let o = headless(chrome, &work.join("profile-shot"))
        .arg("--window-size=1000,1400")
        .arg(format!("--screenshot={}", png.display()))
        .arg(format!("file://{}", report.canonicalize().unwrap().display()))
        .output()
        .expect("Chromium runs");
    let size = std::fs::metadata(&png).map(|m| m.len()).unwrap_or(0);
    // A blank 1000 x 1400 page compresses to a few kB; text and plots take far more.
    assert!(
        size > 30_000,
        "{name}: screenshot of {size} bytes ({})",
        stderr(&o)
    );
}

/// One folder of every kind, made by the command line.
fn folders(d: &Path) -> Vec<(&'static str, PathBuf)> {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let data = root.join("data/cascaded-tanks");
    let (est, val) = (data.join("estimation.csv"), data.join("validation.csv"));
    let (est, val) = (est.to_str().unwrap(), val.to_str().unwrap());
    let spec = root.join("models/tanks-online.toml");
    let compare = d.join("compare.json");
    std::fs::write(
        &compare,
        r#"[{"run": "thesis-ch5 training", "tool": "scipy solve_ivp(RK45)", "median_s": 0.2, "rhs_evaluations": 11936},
            {"run": "thesis-ch5 training", "tool": "rhonn", "median_s": 0.001, "rhs_evaluations": 11100}]"#,
    )
    .unwrap();
    // The default fit of `est` is the one the tests share (`util::tanks_default_fit`), copied
    // in as this folder's `fit`.
    util::copy_dir(util::tanks_default_fit(), &d.join("fit"));
    let runs: [(&str, Vec<&str>); 6] = [
        ("run", vec!["run", "thesis-ch5", "--out", "run"]),
        ("control", vec!["run", "control-adaptive", "--out", "control"]),
        (
            "predict",
            vec![
                "predict",
                "--model",
                "fit/model.json",
                "--data",
                val,
                "--steps-ahead",
                "10",
                "--out",
                "predict",
            ],
        ),
        (
            "identify",
            vec![
                "identify",
                "--data",
                est,
                "--inputs",
                "u",
                "--outputs",
                "y",
                "--model",
                spec.to_str().unwrap(),
                "--epochs",
                "2",
                "--validate",
                val,
                "--out",
                "identify",
            ],
        ),
        (
            "campaign",
            vec![
                "campaign",
                "control-adaptive",
                "--runs",
                "1000",
                "--out",
                "campaign",
            ],
        ),
        (
            "bench",
            vec![
                "bench",
                "thesis-ch3",
                "thesis-ch5",
                "--seconds",
                "0.05",
                "--compare",
                compare.to_str().unwrap(),
                "--out",
                "bench",
            ],
        ),
    ];
    std::iter::once(("fit", d.join("fit")))
        .chain(runs.into_iter().map(|(name, args)| {
            let o = rhonn(d, &args);
            assert!(o.status.success(), "{name}: {}", stderr(&o));
            (
                name,
                d.join(args[args.iter().position(|a| *a == "--out").unwrap() + 1]),
            )
        }))
        .collect()
}

#[test]
fn every_kind_of_report_renders_in_a_real_browser() {
    let d = tempfile::tempdir().unwrap();
    let chrome = chromium();
    if chrome.is_none() {
        eprintln!("skipping the browser checks: no Chromium found (install Debian's `chromium`, or set RHONN_CHROMIUM); checking the HTML only");
    }
    for (name, dir) in folders(d.path()) {
        let report = dir.join("report.html");
        let html = std::fs::read_to_string(&report).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(!html.contains("<script"), "{name}: a script in the report");
        for attr in ["src=\"http", "href=\"http", "@import", "url(http"] {
            assert!(!html.contains(attr), "{name}: fetches {attr}");
        }
        if name == "predict" {
            // MATLAB's compare and resid: the fit in the legend is summary.json's, and the
            // residuals' correlations are drawn against their 99 % band.
            let summary: serde_json::Value =
                serde_json::from_str(&std::fs::read_to_string(dir.join("summary.json")).unwrap()).unwrap();
            let fit = summary["outputs"][0]["fit_percent"].as_f64().unwrap();
            assert!(
                html.contains(&format!("y_hat (10 steps ahead, fit {fit:.1} %)")),
                "fit {fit:.1} % not in the legend"
            );
            for text in [
                "autocorrelation of the residuals",
                "cross-correlation of input u",
                "99 % band of white noise",
            ] {
                assert!(html.contains(text), "predict: no `{text}`");
            }
        }
        // What each kind must show besides its plots.
        let must: &[&str] = match name {
            "bench" => &[
                "measured side by side",
                "scipy solve_ivp(RK45)",
                "runs per second",
            ],
            "campaign" => &["worst runs by controller_iae_mpa_s", "worst-run-"],
            "control" => &["ball radius (bound)", "Lyapunov function"],
            "identify" => &["autocorrelation of the residuals", "99 % band of white noise"],
            _ => &[],
        };
        for text in must {
            assert!(html.contains(text), "{name}: no `{text}`");
        }
        let Some(chrome) = &chrome else { continue };
        let seen = open(chrome, d.path(), &report);
        assert!(seen.text > 300, "{name}: {} characters of text", seen.text);
        assert!(!seen.figures.is_empty(), "{name}: no figure");
        assert!(
            seen.figures.iter().all(|&(w, h)| w > 100.0 && h > 100.0),
            "{name}: figure sizes {:?}",
            seen.figures
        );
        if name == "campaign" {
            // 1,000 runs: the page stays small (its load time is the machine's, not a
            // test's: the test command runs its parts side by side).
            assert!(html.len() < 2_000_000, "campaign report of {} bytes", html.len());
        }
        screenshot(chrome, d.path(), &report, name);
    }
}
