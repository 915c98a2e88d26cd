//! Shared by the integration tests: run the real `rhonn` binary in a folder and read what it left.

#![allow(dead_code)]

use std::path::Path;
use std::process::{Command, Output};

pub fn rhonn(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rhonn"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("runs rhonn")
}

pub fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

pub fn files_in(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .map(|rd| {
            rd.map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}
