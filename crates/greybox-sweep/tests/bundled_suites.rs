//! Every validation suite shipped in `validation/` reads, and every set-up template it names
//! reads and validates as a cutting set-up, with the entry's `set` fields applied: a suite
//! that cannot start is found here, not an hour into a run.
use greybox_sweep::validate::{read_conditions, Suite};
use std::path::Path;

#[test]
fn every_bundled_suite_and_its_templates_read() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../validation");
    let mut suites = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let name = path.file_name().unwrap().to_string_lossy().to_string();
        if !(name.starts_with("suite") && name.ends_with(".toml")) {
            continue;
        }
        let suite = Suite::read(&path).unwrap_or_else(|e| panic!("{name}: {e:#}"));
        let rows = read_conditions(&dir.join(&suite.data)).unwrap();
        for m in &suite.material {
            m.template(&dir)
                .unwrap_or_else(|e| panic!("{name}: {}: {e:#}", m.setup));
            for id in &m.calibration {
                assert!(
                    rows.iter().any(|r| &r.id == id),
                    "{name}: no condition {id}"
                );
            }
        }
        suites += 1;
    }
    assert!(suites >= 8, "{suites} suites in {}", dir.display());
}
