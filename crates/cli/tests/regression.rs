//! One test per reported bug, named after what went wrong, with the report's words above it.

use crate::util;

use std::path::Path;
use util::{files_in, rhonn, stderr};

/// Every file below `dir`, as paths relative to it.
fn tree(dir: &Path) -> Vec<String> {
    fn walk(base: &Path, dir: &Path, out: &mut Vec<String>) {
        for e in std::fs::read_dir(dir).unwrap() {
            let p = e.unwrap().path();
            out.push(p.strip_prefix(base).unwrap().display().to_string());
            if p.is_dir() {
                walk(base, &p, out);
            }
        }
    }
    let mut v = Vec::new();
    walk(dir, dir, &mut v);
    v.sort();
    v
}

/// "A scenario can write outside its output folder: `name = ".."` passes the name check,
/// and `rhonn run` writes trajectory.csv, summary.json and three SVGs into the current
/// directory."
#[test]
fn a_scenario_name_never_leaves_the_output_folder() {
    let preset = std::fs::read_to_string(concat!(
        concat!(env!("CARGO_MANIFEST_DIR"), "/../.."),
        "/scenarios/thesis-ch3.toml"
    ))
    .unwrap();
    assert!(preset.contains("name = \"thesis-ch3\""));
    let tricks = [
        "..",
        ".",
        "../x",
        "a/../../b",
        "/tmp/abs",
        "",
        " ",
        "a\\\\b",
        ".hidden",
        "sub/dir",
    ];
    for name in tricks {
        let d = tempfile::tempdir().unwrap();
        let work = d.path().join("work");
        std::fs::create_dir(&work).unwrap();
        let text = preset.replace("name = \"thesis-ch3\"", &format!("name = \"{name}\""));
        std::fs::write(work.join("s.toml"), text).unwrap();
        for args in [vec!["run", "s.toml"], vec!["campaign", "s.toml", "--runs", "2"]] {
            let o = rhonn(&work, &args);
            assert_eq!(o.status.code(), Some(2), "{name:?} {args:?}: {}", stderr(&o));
            let e = stderr(&o);
            assert!(
                e.contains("`name`") && e.contains("no separators, no `.` or `..`"),
                "{name:?}: {e}"
            );
            assert_eq!(tree(d.path()), ["work", "work/s.toml"], "{name:?} {args:?}");
        }
    }
    // A plain name with dots still works and writes inside out/.
    let d = tempfile::tempdir().unwrap();
    let text = preset
        .replace("name = \"thesis-ch3\"", "name = \"v1.2-run\"")
        .replace("duration_s = 40.0", "duration_s = 0.5");
    std::fs::write(d.path().join("s.toml"), text).unwrap();
    let o = rhonn(d.path(), &["run", "s.toml"]);
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(files_in(d.path()), ["out", "s.toml"]);
    assert!(d.path().join("out/v1.2-run/trajectory.csv").exists());
}

/// "A fit can succeed on garbage: `rhonn fit` on data with values near 1e300 exits 0,
/// prints `fit NaN %`, and writes a model.json with null weights."
#[test]
fn a_fit_on_values_near_1e300_is_an_error_and_writes_no_model() {
    let d = tempfile::tempdir().unwrap();
    let mut csv = String::from("t,u,y\n");
    let mut y = 0.0;
    for k in 0..300 {
        let u = if (k / 7) % 2 == 0 { 1.0 } else { -1.0 };
        y = 0.9 * y + 0.1 * u;
        csv.push_str(&format!("{},{:e},{:e}\n", k as f64 * 0.1, u * 1e300, y * 1e300));
    }
    std::fs::write(d.path().join("huge.csv"), csv).unwrap();
    let o = rhonn(
        d.path(),
        &[
            "fit",
            "--data",
            "huge.csv",
            "--inputs",
            "u",
            "--outputs",
            "y",
            "--out",
            "m",
        ],
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("huge.csv, line 2, column `u`")
            && e.contains("1e300")
            && e.contains("magnitude at most 1e150"),
        "{e}"
    );
    assert!(e.contains("rescale"), "{e}");
    assert_eq!(files_in(d.path()), ["huge.csv"]);
}

/// Issue: "a hand-edited `model.json` with 3 outputs and `na = 50` indexes past a fixed
/// 128-entry array in `sysid/mod.rs`". Such a model is refused, naming `model.na`.
#[test]
fn a_model_file_with_more_lagged_regressors_than_allowed_is_refused() {
    let d = tempfile::tempdir().unwrap();
    let mut csv = String::from("t,u,y1,y2,y3\n");
    let (mut a, mut b, mut c) = (0.0, 0.0, 0.0);
    for k in 0..400 {
        let u = if (k / 5) % 3 == 0 { 1.0 } else { -0.5 };
        (a, b, c) = (0.9 * a + 0.1 * u, 0.8 * b + 0.2 * a, 0.7 * c + 0.3 * b);
        csv.push_str(&format!("{},{u},{a},{b},{c}\n", k as f64 * 0.1));
    }
    std::fs::write(d.path().join("r.csv"), csv).unwrap();
    std::fs::write(d.path().join("rh.toml"), "kind = \"rhonn\"\nna = 2\nnb = 2\n").unwrap();
    let fit = ["fit", "--data", "r.csv", "--inputs", "u", "--outputs", "y1,y2,y3"];
    let o = rhonn(
        d.path(),
        &[&fit[..], &["--model", "rh.toml", "--out", "m"]].concat(),
    );
    assert!(o.status.success(), "{}", stderr(&o));
    // Edit it by hand as a user might: 50 output lags, weights padded to match.
    let path = d.path().join("m/model.json");
    let mut m: serde_json::Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    m["model"]["spec"]["na"] = 50.into();
    let nf = 3 * 50 + 2 + m["model"]["terms"].as_array().unwrap().len() + 1;
    m["model"]["weights"] = serde_json::json!(vec![vec![0.0; nf]; 3]);
    std::fs::write(&path, serde_json::to_string(&m).unwrap()).unwrap();
    let o = rhonn(
        d.path(),
        &[
            "predict",
            "--model",
            "m/model.json",
            "--data",
            "r.csv",
            "--out",
            "p",
        ],
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("`model.na` = 50") && e.contains("at most 128 lagged regressors"),
        "{e}"
    );
    assert!(!d.path().join("p").exists());
}

/// "The README and `--help` carry internal notes ('issue 5', 'this session', 'last
/// session') ... Cargo.toml says 'MIT OR Apache-2.0' but there are no LICENSE files."
#[test]
fn what_users_read_carries_no_internal_notes_and_the_licenses_exist() {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let internal = |text: &str| {
        let low = text.to_lowercase();
        let issue = low
            .match_indices("issue ")
            .any(|(i, _)| low[i + 6..].chars().next().is_some_and(|c| c.is_ascii_digit()));
        issue || low.contains("this session") || low.contains("last session")
    };
    for (name, text) in util::user_docs(root) {
        assert!(!internal(&text), "{name} carries an internal note");
    }
    let d = tempfile::tempdir().unwrap();
    for cmd in [
        "",
        "run",
        "fit",
        "predict",
        "campaign",
        "merge",
        "identify",
        "bench",
        "reproduce",
        "show",
        "scenarios",
        "report",
    ] {
        let args: Vec<&str> = cmd.split_whitespace().chain(["--help"]).collect();
        let o = rhonn(d.path(), &args);
        assert!(o.status.success(), "{cmd} --help");
        assert!(
            !internal(&String::from_utf8_lossy(&o.stdout)),
            "`rhonn {cmd} --help`"
        );
    }
    for f in ["LICENSE-MIT", "LICENSE-APACHE"] {
        let text = std::fs::read_to_string(root.join(f)).unwrap();
        assert!(text.len() > 1000, "{f}");
    }
}

/// "A plain clone is not self-contained: the README points to `shared/spec/SPEC.md`, which
/// a clone does not have." Every repository path the README and docs/ name in backticks
/// exists in the repository.
#[test]
fn every_file_the_readme_names_is_in_the_repository() {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let tops = [
        "docs/",
        "data/",
        "models/",
        "scenarios/",
        "tools/",
        "crates/",
        "slurm/",
        "bench/",
        "python/",
        "embedded/",
    ];
    let mut named = 0;
    // The changelog is history: it may name files since removed.
    for (name, text) in util::user_docs(root)
        .into_iter()
        .filter(|(n, _)| n != "CHANGELOG.md")
    {
        for quoted in text.split('`').skip(1).step_by(2) {
            for word in quoted.split_whitespace() {
                let word = word.trim_end_matches([',', '.', ')', ':', ';']);
                // A segment in capitals (`NAME`, `DIR`) is a placeholder.
                let placeholder = word
                    .split('/')
                    .any(|seg| !seg.is_empty() && seg.chars().all(|c| c.is_ascii_uppercase() || c == '_'));
                if tops.iter().any(|t| word.starts_with(t)) && !word.contains(['<', '*', '{']) && !placeholder
                {
                    named += 1;
                    assert!(
                        root.join(word).exists(),
                        "{name} names `{word}`, which is not in the repository"
                    );
                }
            }
        }
        assert!(!text.contains("shared/"), "{name} points outside the repository");
    }
    assert!(named > 10, "only {named} paths found: the scan is broken");
}

/// "`run <a directory>` says 'no such file'; a campaign into a read-only folder says
/// 'Permission denied' without the path." Errors name the path and say what it is.
#[test]
fn path_errors_name_the_path_and_say_what_it_is() {
    let d = tempfile::tempdir().unwrap();
    std::fs::create_dir(d.path().join("adir")).unwrap();
    std::fs::write(d.path().join("afile"), "").unwrap();
    let cases: [(&[&str], &[&str]); 5] = [
        (&["run", "adir"], &["adir", "it is a directory, not a file"]),
        (
            &["run", "nope/x.toml"],
            &["nope/x.toml", "its folder nope does not exist"],
        ),
        (
            &["run", "thesis-ch3", "--out", "afile/sub"],
            &["afile/sub", "afile is a file, not a folder"],
        ),
        (
            &["campaign", "thesis-ch3", "--runs", "2", "--out", "afile/sub"],
            &["afile/sub", "afile is a file, not a folder"],
        ),
        (
            &[
                "fit",
                "--data",
                "adir",
                "--inputs",
                "u",
                "--outputs",
                "y",
                "--out",
                "m",
            ],
            &["adir", "it is a directory, not a file"],
        ),
    ];
    for (args, want) in cases {
        let o = rhonn(d.path(), args);
        assert!(!o.status.success(), "{args:?}");
        let e = stderr(&o);
        for w in want {
            assert!(e.contains(w), "{args:?}: `{w}` not in {e}");
        }
        assert_eq!(tree(d.path()), ["adir", "afile"], "{args:?}");
    }
}

/// "The README says every `rhonn-adaptive` setting is optional but leaving out
/// `setpoint_mpa` is an error." The reference marks the set-point required: a
/// `[control.controller]` with `kind` and `state` alone and no `[control.baseline]` (the
/// preset's `second_baseline`, a comparison rather than a setting, kept) runs, with the
/// same figures as the preset (whose other settings are the defaults written out), and
/// without `[control] setpoint` the error names it.
#[test]
fn the_adaptive_controller_needs_only_its_set_point() {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let preset = std::fs::read_to_string(root.join("scenarios/control-adaptive.toml")).unwrap();
    let short = preset.replace("duration_s = 60.0", "duration_s = 3.0");
    let (head, tail) = short.split_once("[control.controller]").unwrap();
    let (_, rest) = tail.split_once("[measurement]").unwrap();
    let setpoint = head.lines().find(|l| l.starts_with("setpoint = ")).unwrap();
    assert!(head.contains("second_baseline = \"nominal-optimal\""));
    let minimal = format!(
        "{head}[control.controller]\nkind = \"pump-rhonn-adaptive\"\nstate = \"p_line\"\n\n[measurement]{rest}"
    );
    let d = tempfile::tempdir().unwrap();
    std::fs::write(
        d.path().join("full.toml"),
        short.replace("control-adaptive", "full"),
    )
    .unwrap();
    std::fs::write(
        d.path().join("min.toml"),
        minimal.replace("control-adaptive", "min"),
    )
    .unwrap();
    for f in ["full.toml", "min.toml"] {
        let o = rhonn(d.path(), &["run", f]);
        assert!(o.status.success(), "{f}: {}", stderr(&o));
    }
    let read = |n: &str| std::fs::read_to_string(d.path().join(format!("out/{n}/trajectory.csv"))).unwrap();
    assert_eq!(
        read("full"),
        read("min"),
        "the preset's written-out settings are not the defaults"
    );
    let none = minimal.replace(setpoint, "").replace("control-adaptive", "none");
    std::fs::write(d.path().join("none.toml"), none).unwrap();
    let o = rhonn(d.path(), &["run", "none.toml"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("missing field `setpoint`"), "{}", stderr(&o));
}

/// "Plots: the PI and RHONN colours swap between `pressure.svg` and `inputs.svg` of the
/// same run." Each controller has one colour in every plot of a run (`states.svg`'s
/// panels and `inputs.svg`).
#[test]
fn each_controller_keeps_its_colour_across_the_plots_of_a_run() {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let preset = std::fs::read_to_string(root.join("scenarios/control-adaptive.toml")).unwrap();
    let d = tempfile::tempdir().unwrap();
    std::fs::write(
        d.path().join("s.toml"),
        preset.replace("duration_s = 60.0", "duration_s = 4.0"),
    )
    .unwrap();
    let o = rhonn(d.path(), &["run", "s.toml"]);
    assert!(o.status.success(), "{}", stderr(&o));
    // A legend entry: its text's top y, and the two segments of its mark, drawn
    // 5 px below that top (colour, x start, x end).
    let mark_of = |file: &str, label: &str| -> Vec<(String, i32, i32)> {
        let svg = std::fs::read_to_string(d.path().join("out/control-adaptive").join(file)).unwrap();
        let lines: Vec<&str> = svg.lines().collect();
        let at = lines
            .iter()
            .position(|l| l.trim() == label)
            .unwrap_or_else(|| panic!("{file}: no legend `{label}`"));
        let attr = |name: &str| -> i32 {
            lines[at - 1]
                .split(&format!(" {name}=\""))
                .nth(1)
                .unwrap()
                .split('"')
                .next()
                .unwrap()
                .parse()
                .unwrap()
        };
        let (x, y) = (attr("x"), attr("y"));
        let mut segs = Vec::new();
        for l in lines.iter().filter(|l| l.starts_with("<polyline")) {
            let pts: Vec<(i32, i32)> = l
                .split("points=\"")
                .nth(1)
                .unwrap()
                .split('"')
                .next()
                .unwrap()
                .split_whitespace()
                .map(|p| {
                    let (a, b) = p.split_once(',').unwrap();
                    (a.parse().unwrap(), b.parse().unwrap())
                })
                .collect();
            if pts.len() == 2
                && pts[0].1 == y + 5
                && pts[1].1 == y + 5
                && pts[0].0 >= x - 30
                && pts[1].0 <= x - 10
            {
                segs.push((
                    l.split("stroke=\"").nth(1).unwrap()[..7].to_string(),
                    pts[0].0,
                    pts[1].0,
                ));
            }
        }
        assert_eq!(segs.len(), 2, "{file} `{label}`: {segs:?}");
        segs
    };
    let color_of = |file: &str, label: &str| mark_of(file, label)[0].0.clone();
    // Legend marks are drawn as their series: solid lines touch, dashes leave a gap.
    let solid = mark_of("states.svg", "p_line (cascade-pi baseline)");
    assert_eq!(solid[0].2, solid[1].1, "{solid:?}");
    let dashed = mark_of("states.svg", "p_line set-point");
    assert!(dashed[1].1 > dashed[0].2, "{dashed:?}");
    let pi = [
        color_of("states.svg", "p_line (cascade-pi baseline)"),
        color_of("inputs.svg", "current (cascade-pi baseline)"),
        color_of("states.svg", "stroke (cascade-pi baseline)"),
    ];
    let adaptive = [
        color_of("states.svg", "p_line (rhonn-adaptive)"),
        color_of("inputs.svg", "current (rhonn-adaptive)"),
        color_of("states.svg", "stroke (rhonn-adaptive)"),
    ];
    assert!(pi.iter().all(|c| *c == pi[0]), "{pi:?}");
    assert!(adaptive.iter().all(|c| *c == adaptive[0]), "{adaptive:?}");
    assert_ne!(pi[0], adaptive[0]);
}
