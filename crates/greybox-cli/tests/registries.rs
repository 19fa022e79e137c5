//! The registries are the one list of what exists, and every surface agrees with them: each
//! engine export format writes a table and is listed by the command line and the Python
//! package; docs/architecture.md names only files that exist (its "where to add" table is the
//! map a maintainer follows). The model-family and reader registries check their own
//! consumers (`greybox-model/src/family.rs`, `greybox-tribo/src/readers.rs`).

mod common;

use common::{greybox, ok};
use greybox_core::choice::Choice;
use greybox_friction::classical::Coulomb;
use greybox_friction::export::engine::{ExportFormat, TableSpec};
use greybox_friction::export::write::table_text;
use std::path::{Path, PathBuf};

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

#[test]
fn every_registered_export_format_writes_a_table_and_every_surface_lists_it() {
    let help = ok(&greybox(&["export", "--help"], &repo()));
    let python =
        std::fs::read_to_string(repo().join("crates/greybox-py/python/greybox/__init__.py"))
            .unwrap();
    let docstring = python
        .split("def export_table(")
        .nth(1)
        .and_then(|rest| rest.split("\"\"\"").nth(1))
        .expect("export_table has a docstring");
    for &format in ExportFormat::ALL {
        let name = format.name();
        let t = table_text(&Coulomb { mu: 0.3 }, &TableSpec::new(format))
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(
            !t.text.is_empty() && t.report.max_deviation.is_some(),
            "{name}"
        );
        assert!(
            help.contains(name),
            "`greybox export --help` does not list {name}"
        );
        assert!(
            docstring.contains(name),
            "export_table's docstring does not list {name}"
        );
    }
}

/// The file paths docs/architecture.md names in backticks (`greybox-tribo/src/readers.rs`,
/// `tribo/src/readers.rs`, `scripts/module_cycles.py`), each of which must exist.
fn named_paths(doc: &str) -> Vec<String> {
    doc.split('`')
        .skip(1)
        .step_by(2)
        .filter(|t| {
            !t.contains(' ')
                && !t.contains('<')
                && !t.contains('*')
                && t.contains('/')
                && [".rs", ".py", ".toml", ".md", ".sh", ".pyi"]
                    .iter()
                    .any(|x| t.ends_with(x))
        })
        .map(str::to_string)
        .collect()
}

#[test]
fn docs_architecture_names_only_files_that_exist() {
    let root = repo();
    let doc = std::fs::read_to_string(root.join("docs/architecture.md")).unwrap();
    let paths = named_paths(&doc);
    assert!(paths.len() >= 30, "too few paths found: {paths:?}");
    let missing: Vec<&String> = paths
        .iter()
        .filter(|p| {
            let p = p.trim_start_matches("../");
            ![
                root.join(p),
                root.join("crates").join(p),
                root.join("crates").join(format!("greybox-{p}")),
                root.join("..").join(p),
            ]
            .iter()
            .any(|c| c.exists())
        })
        .collect();
    assert!(
        missing.is_empty(),
        "docs/architecture.md names files that do not exist: {missing:?}"
    );
}
