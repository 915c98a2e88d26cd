//! `docs/reference/fields.md` is generated from the doc comments of the fields that write
//! each output (`rhonn_report::fields`), and every field has one.

use std::path::Path;

#[test]
fn the_reference_is_generated_from_the_fields() {
    let path = Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../..")).join("docs/reference/fields.md");
    let generated = rhonn_report::fields::markdown();
    if std::env::var_os("RHONN_BLESS").is_some() {
        std::fs::write(&path, &generated).unwrap();
    }
    // Every field says what it is (a doc comment on it, or on its type).
    let mut missing = Vec::new();
    for o in rhonn_report::fields::outputs() {
        for (key, text) in rhonn_report::fields::rows(&o.schema) {
            if text.is_empty() {
                missing.push(format!("{} {}: {key}", o.command, o.file));
            }
        }
    }
    assert!(
        missing.is_empty(),
        "{} fields without a doc comment:\n{}",
        missing.len(),
        missing.join("\n")
    );
    let on_disk = std::fs::read_to_string(&path).unwrap_or_default();
    assert!(
        on_disk == generated,
        "docs/reference/fields.md is not what the fields' doc comments generate: run `RHONN_BLESS=1 cargo test --test integration fields::`"
    );
}
