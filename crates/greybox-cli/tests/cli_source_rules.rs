//! The command line converts units only through `greybox_core::units` (one place for every
//! factor), so a flag in MPa or m/min cannot drift from the library's conversion.

use std::path::Path;

/// Unit factors as they would appear in code: powers of ten of SI prefixes and minutes.
const FACTORS: [&str; 10] = [
    "1e3", "1e-3", "1e6", "1e-6", "1e9", "1e-9", "60.0", "1000.0", "3600.0", "1.0e6",
];

#[test]
fn the_cli_has_no_unit_factors_of_its_own() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut found = Vec::new();
    for e in std::fs::read_dir(&src).unwrap() {
        let p = e.unwrap().path();
        let text = std::fs::read_to_string(&p).unwrap();
        for (n, line) in text.lines().enumerate() {
            let code = line.split("//").next().unwrap_or("");
            // flag defaults are values in the flag's unit, not conversions
            if code.trim_start().starts_with("#[arg(") {
                continue;
            }
            for f in FACTORS {
                let hit = code.match_indices(f).any(|(i, _)| {
                    let before = code[..i].chars().last().unwrap_or(' ');
                    let after = code[i + f.len()..].chars().next().unwrap_or(' ');
                    !before.is_ascii_alphanumeric()
                        && before != '.'
                        && !after.is_ascii_digit()
                        && after != '.'
                });
                if hit {
                    found.push(format!("{}:{}: {f}", p.display(), n + 1));
                }
            }
        }
    }
    assert!(
        found.is_empty(),
        "unit factors in the CLI:\n{}",
        found.join("\n")
    );
}
