//! What users read, checked: the README is a front door (at most 400 lines, prerequisites
//! and the two commands first); every link in the README, CHANGELOG and docs/ resolves;
//! the README's shell blocks run as written (from a folder holding the shipped data; its
//! campaign cut to 4 runs) and print the lines its `text` blocks quote; the guides' shell
//! blocks run (campaigns cut short) and every file they name ships;
//! the scenario reference's TOML blocks are scenarios `rhonn run` accepts. (The guides' Rust
//! blocks are doctests of `rhonn-report` and `rhonn-core`.)

use crate::util;

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use util::{rhonn, stderr, user_docs};

fn root() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."))
}

/// The fenced blocks of `text` whose info string starts with `lang`, each as its lines.
fn blocks(text: &str, lang: &str) -> Vec<Vec<String>> {
    let mut out = Vec::new();
    let mut cur: Option<Vec<String>> = None;
    for line in text.lines() {
        let t = line.trim_start();
        if let Some(info) = t.strip_prefix("```") {
            match cur.take() {
                Some(b) => out.push(b),
                None if info.split([',', ' ']).next() == Some(lang) => cur = Some(Vec::new()),
                None => cur = Some(vec!["\u{0}skip".into()]),
            }
            continue;
        }
        if let Some(b) = &mut cur {
            b.push(line.to_string());
        }
    }
    out.retain(|b| b.first().is_none_or(|l| l != "\u{0}skip"));
    out
}

/// Shell lines with their `\` continuations joined and comments cut.
fn commands(block: &[String]) -> Vec<String> {
    let mut out = Vec::new();
    let mut cur = String::new();
    for l in block {
        let code = match l.find(" #") {
            Some(i) if !l[..i].contains('"') => &l[..i],
            _ => l.as_str(),
        };
        let code = code.trim_end();
        if let Some(head) = code.strip_suffix('\\') {
            cur.push_str(head);
            cur.push(' ');
        } else {
            cur.push_str(code);
            if !cur.trim().is_empty() {
                out.push(cur.split_whitespace().collect::<Vec<_>>().join(" "));
            }
            cur.clear();
        }
    }
    out
}

#[test]
fn the_readme_is_a_front_door() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let lines = readme.lines().count();
    assert!(lines <= 400, "README.md has {lines} lines");
    let first_block = readme.find("```").unwrap();
    assert!(
        readme[..first_block].contains("**Prerequisites.**"),
        "the README opens with its prerequisites"
    );
    let sh = &blocks(&readme, "sh")[0];
    let cmds = commands(sh);
    assert_eq!(cmds, ["cargo run --release -- reproduce", "./test-all.sh"]);
    let after = &readme[first_block..];
    let para = after.split("\n\n").nth(1).unwrap();
    assert!(para.contains("minutes") && para.contains("2-core"), "{para}");
}

/// GitHub's anchor of a heading: lower case, spaces to `-`, punctuation but `-` and `_`
/// dropped.
fn slug(heading: &str) -> String {
    heading
        .trim()
        .to_lowercase()
        .chars()
        .filter_map(|c| match c {
            ' ' => Some('-'),
            c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
            _ => None,
        })
        .collect()
}

fn anchors(text: &str) -> BTreeSet<String> {
    let mut fence = false;
    let mut out = BTreeSet::new();
    for l in text.lines() {
        if l.trim_start().starts_with("```") {
            fence = !fence;
        } else if !fence && l.starts_with('#') {
            out.insert(slug(l.trim_start_matches('#')));
        }
    }
    out
}

#[test]
fn every_link_in_what_users_read_resolves() {
    let root = root();
    let mut checked = 0;
    for (name, text) in user_docs(&root) {
        let dir = root.join(&name).parent().unwrap().to_path_buf();
        for (i, _) in text.match_indices("](") {
            let rest = &text[i + 2..];
            let Some(end) = rest.find(')') else { continue };
            let target = rest[..end].split_whitespace().next().unwrap_or("");
            if target.starts_with("http") || target.starts_with("mailto:") {
                continue;
            }
            let (file, anchor) = target.split_once('#').unwrap_or((target, ""));
            let path = if file.is_empty() {
                root.join(&name)
            } else {
                dir.join(file)
            };
            assert!(path.exists(), "{name}: the link `{target}` leads nowhere");
            if !anchor.is_empty() {
                let t = std::fs::read_to_string(&path).unwrap();
                assert!(
                    anchors(&t).contains(anchor),
                    "{name}: no heading `#{anchor}` in {}",
                    path.display()
                );
            }
            checked += 1;
        }
    }
    assert!(checked > 20, "only {checked} links: the scan is broken");
}

/// A folder holding links to the shipped data, models and scenarios, and a `bin` folder
/// whose `rhonn` is the binary under test.
fn sandbox() -> tempfile::TempDir {
    let d = tempfile::tempdir().unwrap();
    for f in ["data", "models", "scenarios"] {
        std::os::unix::fs::symlink(root().join(f), d.path().join(f)).unwrap();
    }
    std::fs::create_dir(d.path().join("bin")).unwrap();
    std::os::unix::fs::symlink(env!("CARGO_BIN_EXE_rhonn"), d.path().join("bin/rhonn")).unwrap();
    d
}

/// `cmd` run by bash in the sandbox `d`, its `rhonn` first on the PATH.
fn run_sh(d: &tempfile::TempDir, cmd: &str) -> std::process::Output {
    let path = format!(
        "{}:{}",
        d.path().join("bin").display(),
        std::env::var("PATH").unwrap_or_default()
    );
    std::process::Command::new("bash")
        .args(["-ec", cmd])
        .current_dir(d.path())
        .env("PATH", &path)
        .output()
        .unwrap()
}

#[test]
fn the_readme_shell_blocks_run_and_print_what_it_quotes() {
    let readme = std::fs::read_to_string(root().join("README.md")).unwrap();
    let d = sandbox();
    let mut printed = String::new();
    let mut ran = 0;
    for block in blocks(&readme, "sh").iter().skip(1) {
        for cmd in commands(block) {
            // Building and installing are the reader's; the tests build the binary.
            if cmd.starts_with("cargo ") {
                continue;
            }
            // A campaign cut to 4 runs, as in the guides: its 1,000 runs add 40 CPU-seconds
            // and nothing the README quotes (crates/rhonn/tests/control.rs checks its figures).
            let cmd = cmd.replace("--runs 1000", "--runs 4");
            let o = run_sh(&d, &cmd);
            assert!(o.status.success(), "`{cmd}`: {}", stderr(&o));
            printed.push_str(&String::from_utf8_lossy(&o.stdout));
            ran += 1;
        }
    }
    assert!(ran >= 7, "only {ran} commands ran");
    for block in blocks(&readme, "text") {
        for line in block {
            assert!(
                printed.contains(&line),
                "the README quotes a line no command printed: {line}"
            );
        }
    }
    for f in [
        "out/tanks/model.json",
        "out/tanks-validation/report.html",
        "out/tanks-online/summary.json",
        "runs/mine/trajectory.csv",
    ] {
        assert!(d.path().join(f).exists(), "{f}");
    }
}

/// Every repository path a guide's shell block names ships (the lines
/// `the_guides_shell_blocks_run` does not run included: Slurm, Python, the firmware).
#[test]
fn every_file_a_guides_shell_block_names_ships() {
    let root = root();
    let tops = [
        "data/",
        "models/",
        "scenarios/",
        "python/",
        "slurm/",
        "embedded/",
        "tools/",
    ];
    let mut named = 0;
    for (name, text) in user_docs(&root) {
        for block in blocks(&text, "sh") {
            for cmd in commands(&block) {
                for word in cmd.split_whitespace() {
                    let w = word.trim_matches(['"', '\'']);
                    if tops.iter().any(|t| w.starts_with(t)) && !w.contains(['*', '<', '[']) {
                        named += 1;
                        assert!(
                            root.join(w).exists(),
                            "{name}: `{cmd}` names {w}, which does not ship"
                        );
                    }
                }
            }
        }
    }
    assert!(named > 15, "only {named} files named: the scan is broken");
}

/// The guides' shell blocks run as written, in order, from a folder holding the shipped
/// data (each guide in its own): every `rhonn` line, with campaigns cut to 4 runs and the
/// shards of a merge made first. Not run, and why: lines with placeholders (`[...]`,
/// `SPEC.toml`, your own `run1.csv`), `cargo` (building, examples, the 77 s benchmark),
/// Python, Slurm and the firmware (their own tests: `python/test.sh`, `embedded/run-qemu.sh`).
#[test]
fn the_guides_shell_blocks_run() {
    let skip = |c: &str| {
        !(c.starts_with("rhonn ") || c.starts_with("for "))
            || c.contains('[')
            || c.contains("SPEC")
            || c.contains("run1.csv")
    };
    let mut ran = Vec::new();
    for (name, text) in user_docs(&root()) {
        if !name.starts_with("docs/guides/") {
            continue;
        }
        let d = sandbox();
        for block in blocks(&text, "sh") {
            for cmd in commands(&block) {
                if skip(&cmd) {
                    continue;
                }
                let mut cmd = cmd
                    .replace("--runs 1000", "--runs 4")
                    .replace("--runs 100000", "--runs 4");
                if cmd.starts_with("rhonn merge s1 s2 s3 s4") {
                    // The guide shows one shard's command; the merge needs all four.
                    let shards: Vec<String> = (1..=4)
                        .map(|k| {
                            format!(
                                "rhonn campaign control-adaptive --runs 4 --seed 1 --shard {k}/4 --out s{k}"
                            )
                        })
                        .collect();
                    cmd = format!("{} && {cmd}", shards.join(" && "));
                }
                let o = run_sh(&d, &cmd);
                assert!(o.status.success(), "{name}: `{cmd}`: {}", stderr(&o));
                ran.push(format!("{name}: {cmd}"));
            }
        }
    }
    assert!(ran.len() >= 15, "only {} commands ran: {ran:#?}", ran.len());
}

/// The scenario reference (docs/reference/scenarios.md): its first block is a scenario of
/// the tanks with sensor noise, a delay and a dither; the second an open-loop scenario of the
/// pump; each later block, in place of `[input.current]` (a controller) or added to it (an
/// identifier), is one too; every key shown commented out but `degree` and `max_factors`
/// (the alternative to `terms`) is accepted when uncommented.
#[test]
fn the_scenario_reference_blocks_are_scenarios_rhonn_runs() {
    let text = std::fs::read_to_string(root().join("docs/reference/scenarios.md")).unwrap();
    let toml = blocks(&text, "toml");
    assert!(toml.len() >= 5, "{} TOML blocks", toml.len());
    let uncomment = |b: &[String]| -> String {
        b.iter()
            .map(|l| {
                let t = l.trim_start();
                match t.strip_prefix("# ") {
                    Some(k)
                        if k.split_once(" = ").is_some_and(|(key, _)| {
                            key.chars().all(|c| c.is_ascii_lowercase() || c == '_')
                                && !["degree", "max_factors"].contains(&key)
                        }) =>
                    {
                        k.to_string()
                    }
                    _ => l.clone(),
                }
            })
            .collect::<Vec<_>>()
            .join("\n")
    };
    let base = uncomment(&toml[1]);
    let open_loop = |s: &str| -> String {
        let start = s.find("[input.current]").unwrap();
        let end = start + s[start..].find("\n\n").unwrap();
        format!("{}{}", &s[..start], &s[end..])
    };
    let cases = [
        ("open loop", base.clone()),
        ("pi", format!("{}\n{}", open_loop(&base), uncomment(&toml[2]))),
        (
            "adaptive",
            format!("{}\n{}", open_loop(&base), uncomment(&toml[3])),
        ),
        ("identifier", format!("{base}\n{}", uncomment(&toml[4]))),
        // The tanks with their noise, delay and dither.
        ("plant", uncomment(&toml[0])),
    ];
    let d = tempfile::tempdir().unwrap();
    for (name, scenario) in cases {
        let scenario = scenario.replace("duration_s = 40.0", "duration_s = 4.0");
        let file = d.path().join(format!("{}.toml", name.replace(' ', "-")));
        std::fs::write(&file, &scenario).unwrap();
        let o = rhonn(d.path(), &["run", file.to_str().unwrap(), "--out", name]);
        assert!(o.status.success(), "{name}: {}\n{scenario}", stderr(&o));
        assert!(Path::new(&d.path().join(name).join("summary.json")).exists());
    }
    let csv = std::fs::read_to_string(d.path().join("plant/trajectory.csv")).unwrap();
    assert!(
        csv.lines().next().unwrap().contains("h2_measured"),
        "the noise's column"
    );
}
