//! The library's integration tests in one binary: each file here is a module of it (one
//! link instead of sixteen, and the tests of every file share one harness's threads:
//! `./test-all.sh`'s time on a 2-core machine). Run one file's tests with its module
//! name: `cargo test --release -p rhonn --test integration tanks::`.

mod control;
mod core_pump;
mod fixed_online;
mod laws;
mod loop_conditions;
mod online;
mod online_bank;
mod online_cascade;
mod online_lagged;
mod open_loop;
mod pump_plant;
mod regulated;
mod robustness;
mod solver_settings;
mod tanks;
mod tanks_tuning;
mod thesis_ch3;
mod thesis_ch5;

/// A shipped scenario's file, as text (`scenarios/NAME.toml`).
pub fn shipped(name: &str) -> String {
    std::fs::read_to_string(format!(
        "{}/../../scenarios/{name}.toml",
        env!("CARGO_MANIFEST_DIR")
    ))
    .unwrap()
}
