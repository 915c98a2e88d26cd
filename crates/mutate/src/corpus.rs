//! The surfaces: every file a user hands the `rhonn` command, a valid base of each (made
//! here: recordings, specs, a model.json of every kind, every shipped scenario shortened),
//! and the command that reads it.

use crate::mutation::Format;
use anyhow::{bail, Context, Result};
use std::path::{Path, PathBuf};
use std::process::Command;

/// One surface: a base file, its format, and the command that reads it (`{M}` the mutated
/// file, `{O}` the output folder, `{B}` the folder of the valid bases).
#[derive(Debug, Clone)]
pub struct Surface {
    /// A short name for the report.
    pub name: String,
    /// The mutated file's name (what an error should name).
    pub file_name: String,
    /// The valid text it starts from.
    pub base: String,
    /// Its format.
    pub format: Format,
    /// The command's arguments.
    pub args: Vec<String>,
    /// What the command wrote from the valid base (set by `prepare`): a JSON null is a
    /// NaN where this output has a number.
    pub base_out: PathBuf,
}

/// A recording of `y[k+1] = 0.85 y + 0.3 u + 0.1 u tanh(y)` under seeded steps of `u`.
fn recording(rows: usize, seed: u64) -> String {
    let mut s = String::from("t,u,y\n");
    let (mut y, mut u, mut state) = (
        0.0_f64,
        0.0_f64,
        seed.wrapping_mul(6364136223846793005).wrapping_add(1),
    );
    for k in 0..rows {
        if k % 7 == 0 {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            u = ((state >> 33) as f64 / (1u64 << 31) as f64) * 4.0 - 2.0;
        }
        s.push_str(&format!("{},{:.6},{:.6}\n", k as f64 * 0.5, u, y));
        y = 0.85 * y + 0.3 * u + 0.1 * u * y.tanh();
    }
    s
}

const SPECS: [(&str, &str); 6] = [
    ("arx.toml", "kind = \"arx\"\nna = 2\nnb = 2\nnk = 1\n"),
    (
        "rhonn.toml",
        "kind = \"rhonn\"\nna = 2\nnb = 2\nnk = 1\ndegree = 2\n",
    ),
    (
        "cascade.toml",
        "kind = \"cascade\"\nneurons = 2\nstarts = 2\nepochs = 3\n",
    ),
    (
        "online.toml",
        "filters_s = [2.0]\na_per_s = 0.5\ngain = 0.1\nepochs = 1\n",
    ),
    (
        "online-lagged.toml",
        "structure = \"lagged\"\ndegree = 2\nlags = { na = 2, nb = 2, nk = 1 }\n",
    ),
    (
        "online-cascade.toml",
        "structure = \"cascade\"\nepochs = 1\ncascade = { neurons = 2, starts = 2, settle = 3 }\n",
    ),
];

fn run_ok(bin: &Path, args: &[String]) -> Result<()> {
    let o = Command::new(bin)
        .args(args)
        .output()
        .with_context(|| format!("running {}", bin.display()))?;
    if !o.status.success() {
        bail!(
            "base case `rhonn {}` failed: {}",
            args.join(" "),
            String::from_utf8_lossy(&o.stderr)
        );
    }
    Ok(())
}

fn s(v: &[&str]) -> Vec<String> {
    v.iter().map(|x| x.to_string()).collect()
}

/// Shipped scenarios shortened to a few seconds of plant time.
fn scenarios(bin: &Path) -> Result<Vec<(String, String)>> {
    let o = Command::new(bin).arg("scenarios").output()?;
    let list = String::from_utf8_lossy(&o.stdout).into_owned();
    let mut v = Vec::new();
    for name in list.lines().filter_map(|l| l.split_whitespace().next()) {
        let o = Command::new(bin).args(["show", name]).output()?;
        let mut doc: toml::Table = String::from_utf8_lossy(&o.stdout)
            .parse()
            .with_context(|| format!("rhonn show {name}"))?;
        let tanks = doc
            .get("plant")
            .and_then(|p| p.get("kind"))
            .and_then(|k| k.as_str())
            == Some("tanks");
        doc.insert(
            "duration_s".into(),
            toml::Value::Float(if tanks { 120.0 } else { 0.5 }),
        );
        v.push((name.to_string(), toml::to_string(&doc)?));
    }
    Ok(v)
}

/// Write the valid bases into `base` (recordings, specs, a model.json of every kind,
/// made by `rhonn fit` and `rhonn identify`) and list the surfaces, each run once on its
/// valid base (the reference of its JSON).
pub fn prepare(bin: &Path, base: &Path) -> Result<Vec<Surface>> {
    std::fs::create_dir_all(base)?;
    std::fs::write(base.join("data.csv"), recording(300, 1))?;
    std::fs::write(base.join("val.csv"), recording(200, 2))?;
    for (f, t) in SPECS {
        std::fs::write(base.join(f), t)?;
    }
    make_models(bin, base)?;
    let mut v = file_surfaces(base)?;
    for (name, text) in scenarios(bin)? {
        v.push(Surface {
            name: format!("run {name}"),
            file_name: "scenario.toml".into(),
            base: text,
            format: Format::Toml,
            args: s(&["run", "{M}", "--out", "{O}"]),
            base_out: PathBuf::new(),
        });
    }
    for (k, sf) in v.iter_mut().enumerate() {
        let dir = base.join(format!("surface-{k}"));
        std::fs::create_dir_all(&dir)?;
        let file = mutant_path(&dir, sf);
        std::fs::write(&file, &sf.base)?;
        sf.base_out = dir.join("out");
        run_ok(bin, &case_args(sf, &file, &sf.base_out))?;
    }
    Ok(v)
}

fn io_args(data: &str) -> Vec<String> {
    s(&["--data", data, "--inputs", "u", "--outputs", "y"])
}

/// A model.json of every kind, by `rhonn fit` and `rhonn identify`, in `base/m-<kind>`.
fn make_models(bin: &Path, base: &Path) -> Result<()> {
    let b = |f: &str| base.join(f).display().to_string();
    for (cmd, kinds) in [
        ("fit", ["arx", "rhonn", "cascade"]),
        ("identify", ["online", "online-lagged", "online-cascade"]),
    ] {
        for kind in kinds {
            let mut a = s(&[cmd]);
            a.extend(io_args(&b("data.csv")));
            a.extend(s(&[
                "--model",
                &b(&format!("{kind}.toml")),
                "--out",
                &b(&format!("m-{kind}")),
            ]));
            run_ok(bin, &a)?;
        }
    }
    Ok(())
}

/// One surface, its reference output not yet made.
fn surface(name: &str, file: &str, text: String, format: Format, args: Vec<String>) -> Surface {
    Surface {
        name: name.into(),
        file_name: file.into(),
        base: text,
        format,
        args,
        base_out: PathBuf::new(),
    }
}

/// The surfaces of the recordings, specs and model.json files.
fn file_surfaces(base: &Path) -> Result<Vec<Surface>> {
    let b = |f: &str| base.join(f).display().to_string();
    let read = |f: &str| std::fs::read_to_string(base.join(f)).with_context(|| f.to_string());
    let mut v = Vec::new();
    let mut fit = s(&[
        "fit",
        "--data",
        "{M}",
        "--inputs",
        "u",
        "--outputs",
        "y",
        "--model",
    ]);
    fit.extend(s(&[&b("rhonn.toml"), "--out", "{O}"]));
    v.push(surface(
        "fit data.csv",
        "data.csv",
        read("data.csv")?,
        Format::Csv,
        fit,
    ));
    for kind in ["arx", "rhonn", "cascade"] {
        let mut a = s(&["fit"]);
        a.extend(io_args(&b("data.csv")));
        a.extend(s(&["--model", "{M}", "--out", "{O}"]));
        v.push(surface(
            &format!("fit spec {kind}"),
            "spec.toml",
            read(&format!("{kind}.toml"))?,
            Format::Toml,
            a,
        ));
    }
    let pred = s(&[
        "predict",
        "--model",
        &b("m-rhonn/model.json"),
        "--data",
        "{M}",
        "--out",
        "{O}",
    ]);
    v.push(surface(
        "predict data.csv",
        "val.csv",
        read("val.csv")?,
        Format::Csv,
        pred,
    ));
    for kind in [
        "arx",
        "rhonn",
        "cascade",
        "online",
        "online-lagged",
        "online-cascade",
    ] {
        let a = s(&[
            "predict",
            "--model",
            "{M}",
            "--data",
            &b("val.csv"),
            "--out",
            "{O}",
        ]);
        let text = read(&format!("m-{kind}/model.json"))?;
        v.push(surface(
            &format!("predict model.json ({kind})"),
            "model.json",
            text,
            Format::Json,
            a,
        ));
    }
    v.extend(identify_surfaces(base)?);
    Ok(v)
}

/// The surfaces of `rhonn identify`'s recordings and specs.
fn identify_surfaces(base: &Path) -> Result<Vec<Surface>> {
    let b = |f: &str| base.join(f).display().to_string();
    let read = |f: &str| std::fs::read_to_string(base.join(f)).with_context(|| f.to_string());
    let mut v = Vec::new();
    let mut ident = s(&[
        "identify",
        "--data",
        "{M}",
        "--inputs",
        "u",
        "--outputs",
        "y",
        "--model",
    ]);
    ident.extend(s(&[
        &b("online-lagged.toml"),
        "--validate",
        &b("val.csv"),
        "--out",
        "{O}",
    ]));
    v.push(surface(
        "identify data.csv",
        "data.csv",
        read("data.csv")?,
        Format::Csv,
        ident,
    ));
    let mut ident = s(&["identify"]);
    ident.extend(io_args(&b("data.csv")));
    ident.extend(s(&[
        "--model",
        &b("online.toml"),
        "--validate",
        "{M}",
        "--out",
        "{O}",
    ]));
    v.push(surface(
        "identify --validate",
        "val.csv",
        read("val.csv")?,
        Format::Csv,
        ident,
    ));
    for kind in ["online", "online-lagged", "online-cascade"] {
        let mut a = s(&["identify"]);
        a.extend(io_args(&b("data.csv")));
        a.extend(s(&[
            "--model",
            "{M}",
            "--validate",
            &b("val.csv"),
            "--out",
            "{O}",
        ]));
        v.push(surface(
            &format!("identify spec {kind}"),
            "spec.toml",
            read(&format!("{kind}.toml"))?,
            Format::Toml,
            a,
        ));
    }
    Ok(v)
}

/// The arguments of a case: `{M}` and `{O}` replaced.
pub fn case_args(surface: &Surface, mutant: &Path, out: &Path) -> Vec<String> {
    surface
        .args
        .iter()
        .map(|a| match a.as_str() {
            "{M}" => mutant.display().to_string(),
            "{O}" => out.display().to_string(),
            _ => a.clone(),
        })
        .collect()
}

/// Where a case's mutated file goes.
pub fn mutant_path(case_dir: &Path, surface: &Surface) -> PathBuf {
    case_dir.join(&surface.file_name)
}
