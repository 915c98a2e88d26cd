//! `rhonn identify --stream` and `--follow`: a benchmark's training file piped line by line
//! gives the very model `rhonn identify --data` gives on it; a malformed line is named with
//! its line number and stops the stream (the model learned so far written) or is skipped;
//! Ctrl-C ends a followed file as the end of input ends a stream.

use crate::util;

use std::io::{BufRead, BufReader, Write};
use std::path::Path;
use std::process::{Command, Output, Stdio};
use util::{rhonn, stderr};

/// The DaISy hair dryer's training file as plain CSV in `dir`; its number of samples.
fn hair_dryer(dir: &Path) -> usize {
    let root = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../.."));
    let gz = std::fs::File::open(root.join("data/benchmarks/daisy-hair-dryer/train.csv.gz")).unwrap();
    let mut text = String::new();
    std::io::Read::read_to_string(&mut flate2::read::GzDecoder::new(gz), &mut text).unwrap();
    std::fs::write(dir.join("hd.csv"), &text).unwrap();
    text.lines().count() - 1
}

const COLUMNS: [&str; 6] = [
    "--time-column",
    "t_s",
    "--inputs",
    "u_heater_V",
    "--outputs",
    "y_outlet_temp_V",
];

/// `rhonn identify ARGS` in `dir` with `input` on its standard input.
fn piped(dir: &Path, args: &[&str], input: &str) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_rhonn"))
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // A command that refuses its arguments exits before reading: the pipe is then closed
    // under the writer, which is no error of the test (seen once in a full run of the tests).
    match child.stdin.take().unwrap().write_all(input.as_bytes()) {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => {}
        r => r.unwrap(),
    }
    child.wait_with_output().unwrap()
}

#[test]
fn a_piped_file_gives_the_model_of_identify_data_and_one_line_per_sample() {
    let d = tempfile::tempdir().unwrap();
    let n = hair_dryer(d.path());
    let text = std::fs::read_to_string(d.path().join("hd.csv")).unwrap();
    let samples = n.to_string();
    let mut args = vec!["identify", "--stream", "--samples", &samples, "--out", "s"];
    args.extend(COLUMNS);
    let o = piped(d.path(), &args, &text);
    assert!(o.status.success(), "{}", stderr(&o));
    let out = String::from_utf8_lossy(&o.stdout);
    let lines: Vec<&str> = out.lines().collect();
    // The header, then one line per sample after the first (it only sets the clock).
    assert_eq!(lines[0], "t,y_outlet_temp_V_hat,y_outlet_temp_V_prequential_rms");
    assert_eq!(lines.len(), n, "{}", lines.len());
    let last: Vec<f64> = lines[n - 1].split(',').map(|c| c.parse().unwrap()).collect();
    assert!(last[1].is_finite() && last[2] > 0.0 && last[2] < 1.0, "{last:?}");
    let mut args = vec!["identify", "--data", "hd.csv", "--out", "d"];
    args.extend(COLUMNS);
    let o = rhonn(d.path(), &args);
    assert!(o.status.success(), "{}", stderr(&o));
    let model = |dir: &str| std::fs::read_to_string(d.path().join(dir).join("model.json")).unwrap();
    assert_eq!(model("s"), model("d"));
}

#[test]
fn a_malformed_line_stops_the_stream_with_its_number_or_is_skipped() {
    let d = tempfile::tempdir().unwrap();
    hair_dryer(d.path());
    let text = std::fs::read_to_string(d.path().join("hd.csv")).unwrap();
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let cells: Vec<&str> = lines[600].split(',').collect();
    lines[600] = format!("{},{},oops,{}", cells[0], cells[1], cells[3]);
    let bad = lines.join("\n") + "\n";
    let samples = (lines.len() - 1).to_string();
    let mut args = vec!["identify", "--stream", "--samples", &samples, "--out", "stop"];
    args.extend(COLUMNS);
    let o = piped(d.path(), &args, &bad);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(
        e.contains("standard input, line 601, column `u_heater_V`") && e.contains("`oops`"),
        "{e}"
    );
    assert!(e.contains("the model learned until then was written"), "{e}");
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.path().join("stop/summary.json")).unwrap()).unwrap();
    assert_eq!(s["samples"], 599, "{s}");
    assert!(d.path().join("stop/model.json").exists());
    let mut args = vec![
        "identify",
        "--stream",
        "--samples",
        &samples,
        "--on-error",
        "skip",
        "--out",
        "skip",
    ];
    args.extend(COLUMNS);
    let o = piped(d.path(), &args, &bad);
    assert!(o.status.success(), "{}", stderr(&o));
    let e = stderr(&o);
    assert!(e.contains("warning: skipped: standard input, line 601"), "{e}");
    // Said as it came (before the folder's lines), and counted at the end.
    assert!(e.find("line 601") < e.find("wrote "), "{e}");
    assert!(e.contains("note: 1 malformed line skipped"), "{e}");
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.path().join("skip/summary.json")).unwrap()).unwrap();
    assert_eq!(s["samples"], lines.len() - 2, "{s}");
    // An open-ended stream shorter than the online selection's judging says what to give.
    let mut args = vec!["identify", "--stream", "--out", "open"];
    args.extend(COLUMNS);
    let o = piped(d.path(), &args, &text);
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(
        e.contains("the stream ended after 750 samples, open-ended")
            && e.contains("give the stream's length beforehand"),
        "{e}"
    );
    // Every candidate failed for one reason: said once, not once per candidate.
    assert_eq!(e.matches("no free-run window").count(), 1, "{e}");
    assert!(
        e.contains("every candidate of the online selection failed: no free-run window"),
        "{e}"
    );
    assert!(e.contains("(all 14 candidates)"), "{e}");
    assert!(!d.path().join("open").exists());
    // A malformed line before anything could be saved: the error names that line (it once
    // said only that the stream was too short), and that nothing was written.
    let mut args = vec!["identify", "--stream", "--out", "early"];
    args.extend(COLUMNS);
    let o = piped(d.path(), &args, &(lines[..2].join("\n") + "\n2,0.16,oops,1\n"));
    let e = stderr(&o);
    assert_eq!(o.status.code(), Some(2), "{e}");
    assert!(
        e.contains("standard input, line 3, column `u_heater_V`") && e.contains("nothing was written"),
        "{e}"
    );
    assert!(!d.path().join("early").exists());
}

/// A followed file is read to its end and then waited on; Ctrl-C (SIGINT), sent once the
/// last sample's line is printed, freezes and writes the model, exit 0.
#[cfg(unix)]
#[test]
fn ctrl_c_ends_a_followed_file_and_writes_the_model() {
    let d = tempfile::tempdir().unwrap();
    let n = hair_dryer(d.path());
    let samples = n.to_string();
    let mut args = vec![
        "identify",
        "--follow",
        "hd.csv",
        "--samples",
        &samples,
        "--out",
        "f",
    ];
    args.extend(COLUMNS);
    let mut child = Command::new(env!("CARGO_BIN_EXE_rhonn"))
        .args(&args)
        .current_dir(d.path())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut out = BufReader::new(child.stdout.take().unwrap());
    let mut line = String::new();
    for _ in 0..n {
        line.clear();
        assert!(out.read_line(&mut line).unwrap() > 0);
    }
    let kill = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(kill.success());
    let o = child.wait_with_output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let s: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.path().join("f/summary.json")).unwrap()).unwrap();
    assert_eq!(s["samples"], n, "{s}");
}

#[test]
fn every_zero_is_refused_and_nothing_is_written() {
    let d = tempfile::tempdir().unwrap();
    let mut args = vec!["identify", "--stream", "--every", "0", "--out", "z"];
    args.extend(COLUMNS);
    let out = piped(d.path(), &args, "t_s,u_heater_V,y_outlet_temp_V\n0,1,2\n");
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    let err = stderr(&out);
    assert!(err.contains("--every") && err.contains("at least 1"), "{err}");
    assert!(!d.path().join("z").exists());
}
