//! The command's integration tests in one binary: each file here is a module of it (one
//! link instead of sixteen, and the tests of every file share one harness's threads:
//! `./test-all.sh`'s time on a 2-core machine). Run one file's tests with its module
//! name: `cargo test --release --test integration benchmark::`.

mod util;

mod activity;
mod benchmark;
mod browser;
mod cli;
mod corpus;
mod custom_plant;
mod determinism;
mod docs;
mod fields;
mod fit_advice;
mod fit_predict;
mod folders;
mod glossary;
mod identify;
mod integrity;
mod model_kind;
mod mutation;
mod regression;
mod shape;
mod stream;
mod tanks_cli;
mod worst_runs;
