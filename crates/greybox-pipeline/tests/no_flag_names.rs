//! The library speaks in its own option names (`export.tolerance`, `out`), never in the
//! command line's flags: a Python user must not read `--pressure-MPa` in an error. Every
//! string literal in the pipeline's sources is checked, except the files that build command
//! lines for a scheduler (`sweep/slurm.rs`, `sweep/local.rs`) and lines that show a whole
//! command for the user to run (`greybox …`, `cargo …`).

use std::path::Path;

/// String literals of a Rust source line, up to a `//` comment outside them (escaped quotes
/// are skipped).
fn literals(line: &str) -> Vec<String> {
    let (mut out, mut cur, mut in_str, mut prev) = (Vec::new(), String::new(), false, ' ');
    for c in line.chars() {
        match (in_str, c) {
            (false, '/') if prev == '/' => break,
            (false, '"') => in_str = true,
            (true, '"') if prev != '\\' => {
                out.push(std::mem::take(&mut cur));
                in_str = false;
            }
            (true, c) => cur.push(c),
            _ => {}
        }
        prev = c;
    }
    out
}

/// `--name` (two dashes, then a letter) anywhere in `text`.
fn flag_in(text: &str) -> Option<&str> {
    let i = text.find("--")?;
    let rest = &text[i + 2..];
    rest.chars()
        .next()
        .filter(|c| c.is_ascii_alphabetic())
        .map(|_| &text[i..(i + 2 + rest.find([' ', ')', ',', ':', '\'']).unwrap_or(rest.len()))])
}

fn sources(dir: &Path, out: &mut Vec<std::path::PathBuf>) {
    for e in std::fs::read_dir(dir).unwrap() {
        let p = e.unwrap().path();
        if p.is_dir() {
            sources(&p, out);
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
}

#[test]
fn no_pipeline_source_names_a_command_line_flag() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    sources(&src, &mut files);
    assert!(files.len() > 20, "the pipeline's sources were not found");
    let mut found = Vec::new();
    for f in &files {
        let rel = f
            .strip_prefix(&src)
            .unwrap()
            .to_string_lossy()
            .replace('\\', "/");
        if rel == "sweep/slurm.rs" || rel == "sweep/local.rs" {
            continue;
        }
        for (n, line) in std::fs::read_to_string(f).unwrap().lines().enumerate() {
            if line.trim_start().starts_with("//") {
                continue;
            }
            for lit in &literals(line) {
                if lit.contains("greybox ") || lit.contains("cargo ") {
                    continue; // a command shown to the user
                }
                if let Some(flag) = flag_in(lit) {
                    found.push(format!("src/{rel}:{}: {flag}", n + 1));
                }
            }
        }
    }
    assert!(
        found.is_empty(),
        "flag names in library messages:\n{}",
        found.join("\n")
    );
}

#[test]
fn the_check_finds_a_flag() {
    assert_eq!(
        flag_in("bad --pressure-MPa: MIN < MAX"),
        Some("--pressure-MPa")
    );
    assert_eq!(flag_in("a -- b"), None);
    assert_eq!(
        literals(r#"bail!("--out is {x}", y) // "--c""#),
        vec!["--out is {x}"]
    );
}
