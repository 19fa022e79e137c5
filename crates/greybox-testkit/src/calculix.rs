//! Whether CalculiX is installed, for the tests that run it.

/// Whether `ccx` runs. Without it the caller skips (`what` names the test in the note on
/// stderr), unless `GREYBOX_REQUIRE_CCX` is set: then the test fails.
pub fn have_ccx(what: &str) -> bool {
    if std::process::Command::new("ccx").arg("-v").output().is_ok() {
        return true;
    }
    assert!(
        std::env::var("GREYBOX_REQUIRE_CCX").is_err(),
        "ccx (calculix-ccx) is required but not installed"
    );
    eprintln!("ccx not installed: skipping {what}");
    false
}
