//! The code's shape, checked: no source file over 800 lines (alarmed at 760), no function
//! over 120 (alarmed at 108), and no circle of imports between the modules of a crate
//! (`use super::x` / `crate::x::y` between siblings).

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};

const SOURCE_ROOTS: [&str; 14] = [
    "crates/base/src",
    "crates/study/src",
    "crates/ident/src",
    "crates/sysid/src",
    "crates/sim/src",
    "crates/rhonn/src",
    "crates/mutate/src",
    "embedded/src",
    "crates/report/src",
    "crates/app/src",
    "crates/core/src",
    "crates/ode/src",
    "crates/cli/src",
    "python/src",
];

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap().flatten() {
        let p = e.path();
        if p.is_dir() {
            rust_files(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

/// The module path of `file` under `root` (`a/b.rs` and `a/b/mod.rs` are `a::b`).
fn module_of(root: &Path, file: &Path) -> Vec<String> {
    let rel = file.strip_prefix(root).unwrap().with_extension("");
    let mut parts: Vec<String> = rel.iter().map(|s| s.to_string_lossy().into_owned()).collect();
    if matches!(parts.last().map(String::as_str), Some("mod" | "lib" | "main")) {
        parts.pop();
    }
    parts
}

/// The modules of the same crate that `file` (module `me`) names outside its tests.
fn imports(text: &str, me: &[String]) -> BTreeSet<Vec<String>> {
    let code = text.split("#[cfg(test)]").next().unwrap_or("");
    let mut out = BTreeSet::new();
    for (prefix, base) in [
        ("super::", me[..me.len().saturating_sub(1)].to_vec()),
        ("crate::", vec![]),
    ] {
        for (i, _) in code.match_indices(prefix) {
            let before = code[..i].chars().last().unwrap_or(' ');
            if before.is_alphanumeric() || before == '_' || before == ':' {
                continue;
            }
            let rest = &code[i + prefix.len()..];
            // `use crate::{a::X, b}`: each path of the group.
            let paths: Vec<&str> = match rest.strip_prefix('{') {
                Some(group) => group.split('}').next().unwrap_or("").split(',').collect(),
                None => vec![rest],
            };
            for path in paths {
                let segs: Vec<&str> = path
                    .trim()
                    .split("::")
                    .map(|s| {
                        s.split(|c: char| !(c.is_alphanumeric() || c == '_'))
                            .next()
                            .unwrap_or("")
                    })
                    .take_while(|s| !s.is_empty() && s.chars().next().is_some_and(|c| c.is_lowercase()))
                    .take(2)
                    .collect();
                for n in 1..=segs.len() {
                    let mut m = base.clone();
                    m.extend(segs[..n].iter().map(|s| s.to_string()));
                    out.insert(m);
                }
            }
        }
    }
    out
}

#[test]
fn no_source_file_is_over_800_lines_and_no_modules_import_each_other_in_a_circle() {
    let repo = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let mut too_long = Vec::new();
    for root in SOURCE_ROOTS {
        let root = repo.join(root);
        let mut files = Vec::new();
        rust_files(&root, &mut files);
        assert!(!files.is_empty(), "{}", root.display());
        let mut graph: BTreeMap<Vec<String>, BTreeSet<Vec<String>>> = BTreeMap::new();
        let mut texts = Vec::new();
        for f in &files {
            let text = std::fs::read_to_string(f).unwrap();
            if text.lines().count() > NEAR_FILE_LINES && !f.to_string_lossy().contains("tests") {
                too_long.push(format!("{} ({} lines)", f.display(), text.lines().count()));
            }
            texts.push((module_of(&root, f), text));
        }
        let modules: BTreeSet<Vec<String>> = texts.iter().map(|(m, _)| m.clone()).collect();
        for (m, text) in &texts {
            let deps = imports(text, m)
                .into_iter()
                .filter(|d| modules.contains(d) && d != m && !m.starts_with(d) && !d.starts_with(m))
                .collect();
            graph.insert(m.clone(), deps);
        }
        // A circle: a module that reaches itself.
        for start in graph.keys() {
            let mut seen = BTreeSet::new();
            let mut stack: Vec<(Vec<String>, Vec<Vec<String>>)> = vec![(start.clone(), vec![start.clone()])];
            while let Some((m, path)) = stack.pop() {
                for d in &graph[&m] {
                    assert!(
                        d != start,
                        "{}: modules import each other in a circle: {}",
                        root.display(),
                        path.iter()
                            .chain([d])
                            .map(|p| p.join("::"))
                            .collect::<Vec<_>>()
                            .join(" -> ")
                    );
                    if seen.insert(d.clone()) {
                        let mut p = path.clone();
                        p.push(d.clone());
                        stack.push((d.clone(), p));
                    }
                }
            }
        }
    }
    assert!(
        too_long.is_empty(),
        "files within 5 % of the 800-line limit (over {NEAR_FILE_LINES}): a better cut is due: {too_long:?}"
    );
}

/// The limits are alarms: a file within 5 % of 800 lines, or a function within 10 % of 120,
/// fails too (a file or function at its limit wants a better cut, not a split to pass).
const NEAR_FILE_LINES: usize = 760;
const NEAR_FUNCTION_LINES: usize = 108;

/// Where functions are counted: the sources and the examples (tests aside).
const FUNCTION_ROOTS: [&str; 3] = ["crates", "python/src", "embedded/src"];

/// The functions of `text` (up to its test module) longer than `limit` lines: the line
/// of each `fn` to its matching closing brace (braces in strings are not told apart;
/// none of ours unbalance a function).
fn long_functions(text: &str, limit: usize) -> Vec<(usize, usize)> {
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let l = lines[i].trim_start();
        if l.starts_with("#[cfg(test)]") {
            break;
        }
        let head = l
            .trim_start_matches("pub(crate) ")
            .trim_start_matches("pub(super) ")
            .trim_start_matches("pub ")
            .trim_start_matches("const ");
        if !head.starts_with("fn ") {
            i += 1;
            continue;
        }
        let (mut depth, mut started, mut j) = (0i64, false, i);
        while j < lines.len() {
            for c in lines[j].chars() {
                match c {
                    '{' => {
                        depth += 1;
                        started = true;
                    }
                    '}' => depth -= 1,
                    _ => {}
                }
            }
            if (started && depth == 0) || (!started && lines[j].trim_end().ends_with(';')) {
                break;
            }
            j += 1;
        }
        if j + 1 - i > limit {
            out.push((i + 1, j + 1 - i));
        }
        i = j + 1;
    }
    out
}

#[test]
fn no_function_is_over_120_lines() {
    let repo = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let mut long = Vec::new();
    for root in FUNCTION_ROOTS {
        let mut files = Vec::new();
        if repo.join(root).is_dir() {
            rust_files(&repo.join(root), &mut files);
        }
        for f in files {
            let rel = f.strip_prefix(repo).unwrap().to_string_lossy().into_owned();
            if rel.contains("/tests/") || rel.contains("/target/") || rel.ends_with("_tests.rs") {
                continue;
            }
            for (line, n) in long_functions(&std::fs::read_to_string(&f).unwrap(), NEAR_FUNCTION_LINES) {
                long.push(format!("{rel}:{line} ({n} lines)"));
            }
        }
    }
    assert!(
        long.is_empty(),
        "functions within 10 % of the 120-line limit (over {NEAR_FUNCTION_LINES}): a better cut is due: {long:?}"
    );
    // The counter itself: a 3-line function, and one of 122.
    let short = "fn a() {\n    1;\n}\n";
    assert!(long_functions(short, 120).is_empty());
    let body = "    x;\n".repeat(120);
    assert_eq!(
        long_functions(&format!("pub fn b() {{\n{body}}}\n"), 120),
        vec![(1, 122)]
    );
}

/// Every controller kind registered in `loop_kinds!` (`crates/sim/src/control/mod.rs`)
/// is one file in `control/` and is listed in docs/ARCHITECTURE.md by its `kind`.
#[test]
fn every_registered_controller_kind_is_one_file_and_listed_in_the_architecture() {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let control = root.join("crates/sim/src/control");
    let text = std::fs::read_to_string(control.join("mod.rs")).unwrap();
    let start = text.find("\nloop_kinds! {").expect("the registry");
    let block = &text[start..start + text[start..].find("\n}").unwrap()];
    let arch = std::fs::read_to_string(root.join("docs/ARCHITECTURE.md")).unwrap();
    let mut kinds = 0;
    for line in block
        .lines()
        .skip(1)
        .map(str::trim)
        .filter(|l| !l.starts_with(['#', '/']))
    {
        let Some((variant, settings)) = line.trim_end_matches("),").split_once('(') else {
            continue;
        };
        let mut kind = String::new();
        for (i, c) in variant.chars().enumerate() {
            if c.is_ascii_uppercase() && i > 0 {
                kind.push('-');
            }
            kind.push(c.to_ascii_lowercase());
        }
        let file = settings.split("::").next().filter(|_| settings.contains("::"));
        let used = match file {
            Some(f) => f.to_string(),
            None => {
                // Settings re-exported in mod.rs: `pub use FILE::{..., SETTINGS, ...}`.
                let at = text.find(settings).unwrap();
                let line = text[..at].rsplit("pub use ").next().unwrap();
                line.split("::").next().unwrap().to_string()
            }
        };
        assert!(
            control.join(format!("{used}.rs")).exists(),
            "{kind}: no control/{used}.rs"
        );
        assert!(
            arch.contains(&format!("`{kind}`")),
            "docs/ARCHITECTURE.md does not list `{kind}`"
        );
        kinds += 1;
    }
    assert!(kinds >= 4, "{kinds} kinds read from the registry");
}

/// The kinds of a registry `fn NAME(kind: Kind)` in `DIR/FILE`: each one implementation
/// of `TRAIT` in its own file of `DIR`, named in docs/ARCHITECTURE.md.
fn registered_kinds(dir: &str, file: &str, registry: &str, tr: &str) -> usize {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let dir = root.join(dir);
    let text = std::fs::read_to_string(dir.join(file)).unwrap();
    let start = text
        .find(&format!("fn {registry}(kind: Kind)"))
        .expect("the registry");
    let block = &text[start..start + text[start..].find("\n    }").unwrap()];
    let arch = std::fs::read_to_string(root.join("docs/ARCHITECTURE.md")).unwrap();
    let mut kinds = 0;
    for line in block.lines().skip(2) {
        // `Kind::A | Kind::B => &FILE::TYPE,`
        let Some((_, target)) = line.split_once("=> &") else {
            continue;
        };
        let (module, ty) = target.trim_end_matches(',').split_once("::").unwrap();
        let file = [dir.join(format!("{module}.rs")), dir.join(module).join("mod.rs")]
            .into_iter()
            .find(|f| f.exists())
            .unwrap_or_else(|| panic!("{ty}: no {module}.rs or {module}/mod.rs in {}", dir.display()));
        let src = std::fs::read_to_string(&file).unwrap();
        assert!(
            src.contains(&format!("impl super::kinds::{tr} for {ty} {{"))
                || src.contains(&format!("impl {tr} for {ty} {{")),
            "{ty}: {} does not implement {tr}",
            file.display()
        );
        assert!(
            arch.contains(&format!("`{module}")),
            "docs/ARCHITECTURE.md does not name `{module}`"
        );
        kinds += 1;
    }
    kinds
}

/// Every model kind is one file of `models/` (its structure and prediction, registered in
/// `models::model_kind`) and one file of `sysid/` (its training, registered in
/// `sysid::fitter`), and docs/ARCHITECTURE.md names them.
#[test]
fn every_registered_model_kind_is_one_file_and_listed_in_the_architecture() {
    let structures = registered_kinds("crates/base/src/models", "mod.rs", "model_kind", "Structure");
    let fits = registered_kinds("crates/sysid/src", "lib.rs", "fitter", "Fit");
    assert!(structures >= 4, "{structures} kinds read from the registry");
    assert_eq!(
        structures, fits,
        "a kind with a structure and no training, or the reverse"
    );
}

/// The rhonn crates a crate's manifest depends on (`[dependencies]` only).
fn rhonn_dependencies(manifest: &str) -> BTreeSet<String> {
    let text =
        std::fs::read_to_string(Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join(manifest))
            .unwrap();
    let deps = text.split("\n[dependencies]\n").nth(1).unwrap_or("");
    let deps = deps.split("\n[").next().unwrap_or("");
    deps.lines()
        .filter_map(|l| l.split(['=', '.']).next())
        .map(|n| n.trim().to_string())
        .filter(|n| n.starts_with("rhonn"))
        .collect()
}

/// The library's layers, crates of their own: the foundations (with the model structures)
/// below both identifiers, the offline one (`rhonn-sysid`) below the online one
/// (`rhonn-ident`, whose Wiener-Hammerstein structure is fitted on a window by the offline
/// training) and never the reverse; simulation above the online identifier (a run
/// identifies as it goes); `rhonn` above all, with what uses
/// several. The studies of the pump's controllers (`rhonn-study`) stand on the public API
/// alone; the files (`rhonn-report`) on the facade, the commands (`rhonn-app`) on both, and
/// the command line (`rhonn-cli`) on the three. No library crate over about 10,000 lines.
#[test]
fn the_layers_depend_downwards_only() {
    let set = |v: &[&str]| v.iter().map(|s| s.to_string()).collect::<BTreeSet<_>>();
    let layers: [(&str, BTreeSet<String>); 8] = [
        ("crates/base/Cargo.toml", set(&["rhonn-core", "rhonn-ode"])),
        (
            "crates/ident/Cargo.toml",
            set(&["rhonn-base", "rhonn-sysid", "rhonn-core", "rhonn-ode"]),
        ),
        ("crates/sysid/Cargo.toml", set(&["rhonn-base"])),
        (
            "crates/sim/Cargo.toml",
            set(&["rhonn-base", "rhonn-ident", "rhonn-core", "rhonn-ode"]),
        ),
        ("crates/study/Cargo.toml", set(&["rhonn", "rhonn-report"])),
        // Rendering on the facade; the application layer on both; the doors on the three.
        ("crates/report/Cargo.toml", set(&["rhonn"])),
        ("crates/app/Cargo.toml", set(&["rhonn", "rhonn-report"])),
        (
            "crates/cli/Cargo.toml",
            set(&["rhonn", "rhonn-report", "rhonn-app"]),
        ),
    ];
    for (manifest, allowed) in layers {
        let deps = rhonn_dependencies(manifest);
        assert!(
            !deps.is_empty() || manifest.contains("base"),
            "{manifest}: no dependencies read"
        );
        let beyond: Vec<_> = deps.difference(&allowed).collect();
        assert!(
            beyond.is_empty(),
            "{manifest} depends on {beyond:?}, beyond its layer {allowed:?}"
        );
    }
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    for krate in ["base", "ident", "sysid", "sim", "rhonn", "report", "app"] {
        let mut files = Vec::new();
        rust_files(&root.join("crates").join(krate).join("src"), &mut files);
        let lines: usize = files
            .iter()
            .map(|f| std::fs::read_to_string(f).unwrap().lines().count())
            .sum();
        assert!(lines > 500 && lines <= 10_500, "crates/{krate}: {lines} lines");
    }
}

/// Python's door is conversion only: its Rust side stays within 500 lines (issue 35),
/// the logic it calls living in the library.
#[test]
fn the_python_door_is_at_most_500_lines() {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join("python/src");
    let mut files = Vec::new();
    rust_files(&root, &mut files);
    let lines: usize = files
        .iter()
        .map(|f| std::fs::read_to_string(f).unwrap().lines().count())
        .sum();
    assert!(!files.is_empty(), "no Rust file under {}", root.display());
    assert!(
        lines <= 500,
        "python/src holds {lines} lines: at most 500 (move logic into the library)"
    );
}

/// docs/ARCHITECTURE.md is a map a reader takes in at once: at most about 150 lines, none
/// of them a paragraph (a table cell once held 4,858 characters).
#[test]
fn the_architecture_is_a_map() {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let text = std::fs::read_to_string(root.join("docs/ARCHITECTURE.md")).unwrap();
    let n = text.lines().count();
    assert!((60..=150).contains(&n), "{n} lines");
    for (i, line) in text.lines().enumerate() {
        let chars = line.chars().count();
        assert!(
            chars <= 220,
            "docs/ARCHITECTURE.md line {}: {chars} characters",
            i + 1
        );
    }
}

/// Every learning law is one file of `law/` implementing `LearningLaw`, registered by a
/// `Rule` variant and its one arm in `Rule::law`: every other method of `Rule` (the
/// derivative, the sampled update, the gain, the rate) goes through that arm, so a new law
/// touches no other `match`; docs/ARCHITECTURE.md says so.
#[test]
fn every_learning_law_is_one_file_and_one_arm_in_the_registry() {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let dir = root.join("crates/base/src/law");
    let text = std::fs::read_to_string(dir.join("mod.rs")).unwrap();
    let start = text.find("pub enum Rule {").expect("the registry's enum");
    let body = &text[start..start + text[start..].find("\n}").unwrap()];
    let variants: Vec<(&str, &str)> = body
        .lines()
        .map(str::trim)
        .filter(|l| !l.starts_with(['#', '/']))
        .filter_map(|l| l.trim_end_matches("),").split_once('('))
        .collect();
    assert!(variants.len() >= 3, "{variants:?}");
    let registry = &text[text.find("fn law(&self) -> &dyn LearningLaw").expect("Rule::law")..];
    let registry = &registry[..registry.find("\n    }\n").unwrap()];
    let impls: String = ["impl LearningLaw for Rule {", "for Rule {\n    fn law_states"]
        .iter()
        .map(|h| {
            let at = text.find(h).unwrap_or_else(|| panic!("no `{h}`"));
            text[at..at + text[at..].find("\n}\n").unwrap()].to_string()
        })
        .collect();
    assert!(
        !impls.contains("Rule::"),
        "a method of Rule matches on the laws itself:\n{impls}"
    );
    for (variant, ty) in variants {
        assert_eq!(
            registry.matches(&format!("Rule::{variant}(")).count(),
            1,
            "{variant}: one arm in Rule::law"
        );
        let files: Vec<String> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| {
                std::fs::read_to_string(p).is_ok_and(|s| s.contains(&format!("impl LearningLaw for {ty} {{")))
            })
            .map(|p| p.display().to_string())
            .collect();
        assert_eq!(files.len(), 1, "{ty}: implemented in {files:?}");
    }
    let arch = std::fs::read_to_string(root.join("docs/ARCHITECTURE.md")).unwrap();
    assert!(
        arch.contains("`Rule::law`"),
        "docs/ARCHITECTURE.md does not name `Rule::law`"
    );
}
