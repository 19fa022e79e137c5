//! The registries are the one list of what exists, and every surface agrees with them: each
//! engine export format writes a table and is listed by the command line and the Python
//! package; docs/architecture.md names only files that exist (its "where to add" table is the
//! map a maintainer follows). The model-family and reader registries check their own
//! consumers (`greybox-model/src/family.rs`, `greybox-recording/src/readers.rs`).

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
        let t = table_text(
            &Coulomb { mu: 0.3 },
            &TableSpec::new(format).validated().unwrap(),
        )
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

/// The file paths docs/architecture.md names in backticks (`greybox-recording/src/readers.rs`,
/// `recording/src/readers.rs`, `scripts/module_cycles.py`), each of which must exist.
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

/// Where a `module::path::Item` named by the docs lives: the crate (a `greybox_x`, `x` short
/// name, or any crate when the path starts inside one), its module files, and the item.
struct Source {
    root: PathBuf,
}

impl Source {
    fn crates(&self) -> Vec<PathBuf> {
        let mut v: Vec<PathBuf> = std::fs::read_dir(self.root.join("crates"))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.join("src").is_dir())
            .collect();
        v.sort();
        v
    }

    /// The module file of `dir/seg` (`seg.rs` or `seg/mod.rs`) and the folder its children
    /// live in.
    fn module(dir: &Path, seg: &str) -> Option<(PathBuf, PathBuf)> {
        let file = dir.join(format!("{seg}.rs"));
        let folder = dir.join(seg);
        if file.is_file() {
            Some((file, folder))
        } else if folder.join("mod.rs").is_file() {
            Some((folder.join("mod.rs"), folder))
        } else {
            None
        }
    }

    /// Whether `text` declares or re-exports `name`.
    fn declares(text: &str, name: &str) -> bool {
        let word = |s: &str, at: usize| {
            s[at + name.len()..]
                .chars()
                .next()
                .is_none_or(|c| !(c.is_alphanumeric() || c == '_'))
        };
        [
            "fn ",
            "struct ",
            "enum ",
            "trait ",
            "type ",
            "const ",
            "static ",
            "mod ",
            "macro_rules! ",
            "use ",
            "as ",
            "::",
            "{",
            ", ",
        ]
        .iter()
        .any(|kw| {
            let pat = format!("{kw}{name}");
            text.match_indices(&pat)
                .any(|(at, _)| word(text, at + kw.len()))
        }) || text.contains(&format!("{name} =>"))
    }

    /// `segments` resolved inside one crate's `src`: modules by their files, then an item
    /// declared in the last module reached (or in its folder), then the item's members.
    fn resolves_in(src: &Path, segments: &[&str]) -> bool {
        let (mut file, mut folder) = (src.join("lib.rs"), src.to_path_buf());
        if !file.is_file() {
            file = src.join("main.rs");
        }
        let mut k = 0;
        while k < segments.len() {
            match Self::module(&folder, segments[k]) {
                Some((f, d)) => (file, folder) = (f, d),
                None => break,
            }
            k += 1;
        }
        if k == segments.len() {
            return true;
        }
        let mut texts = vec![std::fs::read_to_string(&file).unwrap_or_default()];
        let root = ["mod.rs", "lib.rs", "main.rs"];
        if folder.is_dir() && root.iter().any(|r| file.ends_with(r)) {
            for e in walk(&folder) {
                texts.push(std::fs::read_to_string(e).unwrap_or_default());
            }
        }
        segments[k..]
            .iter()
            .all(|name| texts.iter().any(|t| Self::declares(t, name)))
    }

    /// Whether a path as the docs write it (`core::FrictionLaw`, `greybox_sim::executor::Hooks`,
    /// `executor::Observer`, `export::write::table_text`) names something that exists.
    fn resolves(&self, path: &str) -> bool {
        let segments: Vec<&str> = path.split("::").collect();
        let named = |s: &str| {
            let dir = self.root.join("crates").join(format!(
                "greybox-{}",
                s.trim_start_matches("greybox_").replace('_', "-")
            ));
            (s == "greybox")
                .then(|| self.root.join("crates/greybox"))
                .or(Some(dir))
        };
        if let Some(dir) = named(segments[0]).filter(|d| d.join("src").is_dir()) {
            if Self::resolves_in(&dir.join("src"), &segments[1..]) {
                return true;
            }
        }
        self.crates()
            .iter()
            .any(|c| Self::resolves_in(&c.join("src"), &segments))
    }
}

fn walk(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    for e in std::fs::read_dir(dir).into_iter().flatten().flatten() {
        let p = e.path();
        if p.is_dir() {
            out.extend(walk(&p));
        } else if p.extension().is_some_and(|x| x == "rs") {
            out.push(p);
        }
    }
    out
}

/// The code names docs/architecture.md writes in backticks: crates (`greybox-tribo`), paths
/// (`friction::export::engine`, `core::FrictionLaw`) and type names (`PinContact`).
fn named_code(doc: &str) -> (Vec<String>, Vec<String>, Vec<String>) {
    let (mut crates, mut paths, mut types) = (Vec::new(), Vec::new(), Vec::new());
    for t in doc.split('`').skip(1).step_by(2) {
        let t = t.trim_end_matches("()").trim_end_matches('!');
        let ident = |s: &str| {
            !s.is_empty()
                && s.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
                && !s.starts_with(|c: char| c.is_ascii_digit())
        };
        if t.starts_with("greybox-") && t[8..].chars().all(|c| c.is_ascii_lowercase() || c == '-') {
            crates.push(t.to_string());
        } else if t.contains("::") && t.split("::").all(ident) {
            paths.push(t.to_string());
        } else if ident(t)
            && t.starts_with(|c: char| c.is_ascii_uppercase())
            && t.chars().any(|c| c.is_ascii_lowercase())
        {
            types.push(t.to_string());
        }
    }
    (crates, paths, types)
}

#[test]
fn docs_architecture_names_only_crates_modules_and_types_that_exist() {
    let root = repo();
    let doc = std::fs::read_to_string(root.join("docs/architecture.md")).unwrap();
    let (crates, paths, types) = named_code(&doc);
    assert!(crates.len() >= 15 && paths.len() >= 30 && types.len() >= 20);
    let src = Source { root: root.clone() };
    let members: Vec<String> = src
        .crates()
        .iter()
        .map(|c| c.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    let mut wrong: Vec<String> = crates
        .iter()
        .filter(|c| !members.contains(c))
        .map(|c| format!("crate {c}"))
        .collect();
    // every crate of the workspace is on the map, as a row of its table
    for m in &members {
        if !doc.contains(&format!("| `{m}` |")) {
            wrong.push(format!("crate {m} has no row in the crate map"));
        }
    }
    wrong.extend(
        paths
            .iter()
            .filter(|p| !src.resolves(p))
            .map(|p| format!("path {p}")),
    );
    let all: String = src
        .crates()
        .iter()
        .flat_map(|c| walk(&c.join("src")))
        .map(|f| std::fs::read_to_string(f).unwrap())
        .collect();
    wrong.extend(
        types
            .iter()
            .filter(|t| !Source::declares(&all, t))
            .map(|t| format!("type {t}")),
    );
    wrong.sort();
    wrong.dedup();
    assert!(
        wrong.is_empty(),
        "docs/architecture.md names what does not exist:\n{}",
        wrong.join("\n")
    );
}
