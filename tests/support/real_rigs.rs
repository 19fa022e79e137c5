//! Where the tests find the real-rig corpus; included by path (`#[path]`) from the test crates
//! that read it, so that there is one rule for all of them.

/// The real-rig corpus: raw public exports kept outside the project, in
/// `../shared/data/real-rigs` beside the checkout (or `GREYBOX_REAL_RIGS_DIR`). `None` (the
/// caller skips) where it is absent, unless `GREYBOX_REQUIRE_REAL_RIGS=1` (`.ci/run` sets it),
/// where its absence fails the test.
pub fn real_rigs_dir() -> Option<std::path::PathBuf> {
    let dir = std::env::var_os("GREYBOX_REAL_RIGS_DIR")
        .map(std::path::PathBuf::from)
        .unwrap_or_else(|| {
            std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data/real-rigs")
        });
    if dir.is_dir() {
        return Some(dir);
    }
    assert!(
        std::env::var("GREYBOX_REQUIRE_REAL_RIGS").as_deref() != Ok("1"),
        "GREYBOX_REQUIRE_REAL_RIGS=1 but the real-rig corpus {} is missing",
        dir.display()
    );
    eprintln!("skipped: the real-rig corpus {} is not here", dir.display());
    None
}
