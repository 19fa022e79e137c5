//! Tiny law files: a law JSON written as `law.json` in a fresh temporary directory.

/// Zorev's law: μ = 0.4 below the shear cap k = 500 MPa, i.e. μ = min(0.4, 500 MPa / p).
pub const ZOREV: &str = r#"{"law": "zorev", "mu": 0.4, "k_MPa": 500}"#;

/// A law that depends on pressure (Usui–Childs: the friction stress saturates at m·k).
pub const USUI_CHILDS: &str =
    r#"{"law": "usui-childs", "mu": 0.5, "m": 0.8, "n": 1.0, "k_MPa": 500}"#;

/// A temporary directory holding `law.json` with the text `law`.
pub fn law_dir(law: &str) -> tempfile::TempDir {
    let d = tempfile::tempdir().unwrap();
    std::fs::write(d.path().join("law.json"), law).unwrap();
    d
}
