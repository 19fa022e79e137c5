//! Rules over the sources. The command line converts units only through
//! `greybox_core::units` (one place for every factor), so a flag in MPa or m/min cannot drift
//! from the library's conversion; and no library crate names a command-line flag.

use std::path::{Path, PathBuf};

/// Unit factors as they would appear in code: powers of ten of SI prefixes and minutes.
const FACTORS: [&str; 10] = [
    "1e3", "1e-3", "1e6", "1e-6", "1e9", "1e-9", "60.0", "1000.0", "3600.0", "1.0e6",
];

#[test]
fn the_cli_has_no_unit_factors_of_its_own() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut found = Vec::new();
    for p in rust_files(&src) {
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

/// Every `.rs` file under `dir`, in a stable order.
fn rust_files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut entries: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    entries.sort();
    for p in entries {
        if p.is_dir() {
            out.extend(rust_files(&p));
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
    out
}

/// Every `.rs` file under the `src` of each crate `keep` accepts (by its directory name),
/// as (path from `crates/`, text), in a stable order.
fn crate_sources(keep: impl Fn(&str) -> bool) -> Vec<(String, String)> {
    let crates = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
    let mut dirs: Vec<PathBuf> = std::fs::read_dir(crates)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.join("src").is_dir())
        .filter(|p| keep(&p.file_name().unwrap().to_string_lossy()))
        .collect();
    dirs.sort();
    assert!(dirs.len() >= 10, "the crates were not found");
    let mut out = Vec::new();
    for dir in &dirs {
        for f in rust_files(&dir.join("src")) {
            let rel = f
                .strip_prefix(crates)
                .unwrap()
                .to_string_lossy()
                .replace('\\', "/");
            out.push((rel, std::fs::read_to_string(&f).unwrap()));
        }
    }
    out
}

/// Files that write real command lines (a Slurm script with its `#SBATCH` lines and `sbatch`
/// calls), and lines of others that show a whole command: their flags are the command's own.
const COMMAND_LINES: [(&str, &str); 5] = [
    ("greybox-sweep/src/slurm.rs", ""),
    // how the `greybox` program runs a sweep case, once for the CLI and Python
    ("greybox-sweep/src/launch.rs", "--quiet"),
    ("greybox-sweep/src/launch.rs", "--index"),
    (
        "greybox-report/src/text/demo.rs",
        "cargo build --release -p greybox-ffi",
    ),
    ("greybox-report/src/text/demo.rs", "greybox couple --deck"),
];

/// `source` without its `#[cfg(test)] mod … { … }` blocks (up to the `}` at the `mod`'s
/// indentation), lines kept as blank so that line numbers stay.
fn without_test_mods(source: &str) -> String {
    let lines: Vec<&str> = source.lines().collect();
    let mut out = Vec::with_capacity(lines.len());
    let mut i = 0;
    while i < lines.len() {
        let next = lines.get(i + 1).map_or("", |l| l.trim_start());
        if lines[i].trim() == "#[cfg(test)]" && next.starts_with("mod ") && next.ends_with('{') {
            let indent = &lines[i + 1][..lines[i + 1].len() - next.len()];
            let close = format!("{indent}}}");
            let end = (i + 2..lines.len())
                .find(|&k| lines[k] == close)
                .unwrap_or(lines.len() - 1);
            out.extend(std::iter::repeat_n("", end + 1 - i));
            i = end + 1;
        } else {
            out.push(lines[i]);
            i += 1;
        }
    }
    out.join("\n")
}

/// The string literals of Rust `source` with the line each starts on: comments (line, block,
/// doc) are skipped, escapes and raw strings read, char literals and lifetimes told apart.
fn string_literals(source: &str) -> Vec<(usize, String)> {
    let c: Vec<char> = source.chars().collect();
    let (mut out, mut i, mut line) = (Vec::new(), 0, 1);
    let ident = |k: usize| k > 0 && (c[k - 1].is_alphanumeric() || c[k - 1] == '_');
    while i < c.len() {
        match c[i] {
            '\n' => line += 1,
            '/' if c.get(i + 1) == Some(&'/') => {
                while i < c.len() && c[i] != '\n' {
                    i += 1;
                }
                continue;
            }
            '/' if c.get(i + 1) == Some(&'*') => {
                let mut depth = 0;
                while i < c.len() {
                    if c[i] == '/' && c.get(i + 1) == Some(&'*') {
                        depth += 1;
                        i += 1;
                    } else if c[i] == '*' && c.get(i + 1) == Some(&'/') {
                        depth -= 1;
                        i += 1;
                    } else if c[i] == '\n' {
                        line += 1;
                    }
                    i += 1;
                    if depth == 0 {
                        break;
                    }
                }
                continue;
            }
            '\'' => {
                // a char literal ('x', '\n', '"'), else a lifetime
                if c.get(i + 1) == Some(&'\\') {
                    i += 2;
                    while i < c.len() && c[i] != '\'' {
                        i += 1;
                    }
                } else if c.get(i + 2) == Some(&'\'') {
                    i += 2;
                }
            }
            'r' if !ident(i) && matches!(c.get(i + 1), Some('"') | Some('#')) => {
                let hashes = c[i + 1..].iter().take_while(|&&x| x == '#').count();
                if c.get(i + 1 + hashes) == Some(&'"') {
                    let (start, mut k) = (line, i + 2 + hashes);
                    let mut text = String::new();
                    while k < c.len()
                        && !(c[k] == '"' && c[k + 1..].iter().take(hashes).all(|&x| x == '#'))
                    {
                        line += usize::from(c[k] == '\n');
                        text.push(c[k]);
                        k += 1;
                    }
                    out.push((start, text));
                    i = k + 1 + hashes;
                    continue;
                }
            }
            '"' => {
                let (start, mut k) = (line, i + 1);
                let mut text = String::new();
                while k < c.len() && c[k] != '"' {
                    if c[k] == '\\' {
                        text.push(c[k]);
                        k += 1;
                    }
                    line += usize::from(c[k] == '\n');
                    text.push(c[k]);
                    k += 1;
                }
                out.push((start, text));
                i = k + 1;
                continue;
            }
            _ => {}
        }
        i += 1;
    }
    out
}

/// The first `--name` (two dashes, then a letter) in `text`.
fn flag_in(text: &str) -> Option<&str> {
    text.match_indices("--").find_map(|(i, _)| {
        let before = text[..i].chars().last().unwrap_or(' ');
        let rest = &text[i + 2..];
        let name = rest
            .find(|ch: char| !(ch.is_ascii_alphanumeric() || ch == '-' || ch == '_'))
            .unwrap_or(rest.len());
        (before != '-' && rest.starts_with(|ch: char| ch.is_ascii_alphabetic()))
            .then(|| &text[i..i + 2 + name])
    })
}

/// `file:line: --flag` for every string literal of `source` (outside its test modules) that
/// holds a flag, less those `allowed` (a needle the literal contains; "" allows the file).
fn flags_in_source(rel: &str, source: &str, allowed: &[&str]) -> Vec<String> {
    if allowed.contains(&"") {
        return Vec::new();
    }
    string_literals(&without_test_mods(source))
        .into_iter()
        .filter(|(_, lit)| !allowed.iter().any(|a| lit.contains(a)))
        .filter_map(|(n, lit)| flag_in(&lit).map(|f| format!("{rel}:{n}: {f}")))
        .collect()
}

/// The library speaks in its settings' field names (`map`, `identify.track_radii_mm`,
/// `force`), never in the command line's flags: a Python user must not read `--map` in an
/// error. The CLI shows the fields as its flags when it prints a message.
#[test]
fn no_library_crate_names_a_command_line_flag() {
    let mut found = Vec::new();
    for (rel, text) in crate_sources(|name| name != "greybox-cli") {
        let allowed: Vec<&str> = COMMAND_LINES
            .iter()
            .filter(|(file, _)| *file == rel)
            .map(|(_, needle)| *needle)
            .collect();
        found.extend(flags_in_source(&rel, &text, &allowed));
    }
    assert!(
        found.is_empty(),
        "flag names in library strings (name the settings field instead, e.g. `map`):\n{}",
        found.join("\n")
    );
}

#[test]
fn the_flag_check_finds_a_flag_in_code_only() {
    let src = "fn f() -> Result<()> {\n    // give --comment\n    /* --block */\n    let c = '\"';\n    let s: &'static str = r#\"raw --raw\"#;\n    bail!(\"a {x}\\\"\n     give --foo N\", y)\n}\n#[cfg(test)]\nmod tests {\n    const A: &str = \"--test\";\n}\n";
    assert_eq!(
        flags_in_source("lib.rs", src, &[]),
        ["lib.rs:5: --raw", "lib.rs:6: --foo"]
    );
    assert!(flags_in_source("lib.rs", src, &[""]).is_empty());
    assert_eq!(
        flags_in_source("lib.rs", src, &["--raw"]),
        ["lib.rs:6: --foo"]
    );
    assert_eq!(flag_in("a -- b --- c"), None);
    assert_eq!(flag_in("x=--max-input-mib."), Some("--max-input-mib"));
}

/// How a file is opened for reading other than through `greybox_core::input` (issue 62,
/// mechanism 1): each of these follows a FIFO into a wait for a writer, or reads `/dev/zero`
/// until memory runs out.
const RAW_OPENS: [&str; 6] = [
    "File::open(",
    "fs::read_to_string(",
    "fs::read(",
    "from_path(",
    ".read(true)",
    "Mmap::map(",
];

/// Where a raw open is the point: the one safe open itself, and a map of a file it opened.
const SAFE_OPEN_ITSELF: [&str; 2] = [
    "greybox-core/src/input.rs",
    "greybox-recording/src/text_table/assemble.rs",
];

/// Every library crate (and the CLI, and the Python extension) reads its inputs through the
/// one safe open: a source that opens a file another way is named with its line.
#[test]
fn every_input_is_opened_through_the_one_safe_open() {
    let mut found = Vec::new();
    for (rel, text) in crate_sources(|name| name != "greybox-testkit") {
        if !SAFE_OPEN_ITSELF.contains(&rel.as_str()) {
            found.extend(raw_opens(&rel, &text));
        }
    }
    assert!(
        found.is_empty(),
        "files opened for reading outside greybox_core::input (use input::open / read_text / data_csv):\n{}",
        found.join("\n")
    );
}

/// The raw opens in the code of `source` (test modules and comments left out), as
/// `file:line: pattern`.
fn raw_opens(rel: &str, source: &str) -> Vec<String> {
    let text = without_test_mods(source);
    let mut found = Vec::new();
    for (n, line) in text.lines().enumerate() {
        let code = line.split("//").next().unwrap_or("");
        if let Some(raw) = RAW_OPENS.iter().find(|r| code.contains(**r)) {
            found.push(format!("{rel}:{}: {raw}", n + 1));
        }
    }
    found
}

#[test]
fn the_open_check_finds_a_raw_open_in_code_only() {
    let source = "fn a(p: &Path) {\n    let t = std::fs::read_to_string(p);\n    // csv::Reader::from_path(p) in a comment\n}\n#[cfg(test)]\nmod tests {\n    fn b() { std::fs::File::open(\"x\"); }\n}\n";
    assert_eq!(
        raw_opens("x.rs", source),
        vec!["x.rs:2: fs::read_to_string("]
    );
}

/// Every record a library crate writes with the `csv` crate goes through
/// `greybox_core::escape::csv_cells` (issue 62, mechanism 5: a text cell a spreadsheet would
/// run as a formula gets a leading `'`); writers of CSV text use `csv_field`.
#[test]
fn every_csv_record_neutralises_formulas() {
    let mut found = Vec::new();
    for (rel, text) in crate_sources(|_| true) {
        for (n, line) in without_test_mods(&text).lines().enumerate() {
            let code = line.split("//").next().unwrap_or("");
            if code.contains(".write_record(") && !code.contains("csv_cells(") {
                found.push(format!("{rel}:{}", n + 1));
            }
        }
    }
    assert!(
        found.is_empty(),
        "CSV records written without escape::csv_cells:\n{}",
        found.join("\n")
    );
}
