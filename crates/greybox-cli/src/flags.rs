//! The library names its settings by their fields (`` `map` ``, `identify.track_radii_mm`),
//! as both surfaces know them; the command line shows those names as its flags (`--map`,
//! `--track-radii-mm`) when it prints a message. Only the arguments of the subcommand that
//! ran (and the global ones) are rewritten, and only in backticks, as `stage.field` or as a
//! source position's `field 'name'`, so ordinary words are never touched.

use std::collections::HashMap;
use std::sync::OnceLock;

/// The sections a setting is named under in `stage.field` (`identify.map`).
const STAGES: [&str; 13] = [
    "identify", "plan", "fit", "adhesive", "couple", "pin", "export", "import", "synth", "hertz",
    "law", "windows", "material",
];

/// Field name → `--flag` for the arguments of one command line.
#[derive(Debug, Default)]
pub struct Flags(HashMap<String, String>);

static SHOWN: OnceLock<Flags> = OnceLock::new();

impl Flags {
    /// The long flags of `cmd` and of the subcommands that `matches` ran, by argument id (clap
    /// derives the id from the struct field's name).
    pub fn of(cmd: &clap::Command, matches: &clap::ArgMatches) -> Flags {
        let mut map = HashMap::new();
        let (mut cmd, mut matches) = (cmd, matches);
        loop {
            for a in cmd.get_arguments() {
                if let Some(long) = a.get_long() {
                    map.insert(a.get_id().as_str().to_string(), format!("--{long}"));
                }
            }
            let Some((name, sub)) = matches.subcommand() else {
                break;
            };
            let Some(c) = cmd.find_subcommand(name) else {
                break;
            };
            (cmd, matches) = (c, sub);
        }
        Flags(map)
    }

    /// The flag of `name` (`map`, `identify.map`), if it is one of these arguments.
    fn flag(&self, name: &str) -> Option<&str> {
        let field = match name.split_once('.') {
            // `plan.json` is a file, not the flag --json
            Some((stage, field)) if STAGES.contains(&stage) && field != "json" => field,
            Some(_) => return None,
            None => name,
        };
        self.0.get(field).map(String::as_str)
    }

    /// `text` with `` `field` `` and `stage.field` shown as their flags.
    pub fn rewrite(&self, text: &str) -> String {
        let ident = |c: char| c.is_ascii_alphanumeric() || c == '_';
        let mut out = String::with_capacity(text.len());
        let mut rest = text;
        while let Some(c) = rest.chars().next() {
            if c == '\'' && out.ends_with("field ") {
                // a source position's `field 'target'`
                if let Some(end) = rest[1..].find('\'') {
                    if let Some(flag) = self.flag(&rest[1..1 + end]) {
                        out.push_str(&format!("'{flag}'"));
                        rest = &rest[end + 2..];
                        continue;
                    }
                }
            } else if c == '`' {
                if let Some(end) = rest[1..].find('`') {
                    if let Some(flag) = self.flag(&rest[1..1 + end]) {
                        out.push_str(flag);
                        rest = &rest[end + 2..];
                        continue;
                    }
                }
            } else if ident(c) && !out.ends_with(|p: char| ident(p) || p == '.' || p == '-') {
                // a word: `stage.field` when it is one (and not `stage.field.more`)
                let word_end = |s: &str| s.find(|c: char| !ident(c)).unwrap_or(s.len());
                let w = word_end(rest);
                if rest[w..].starts_with('.') {
                    let f = w + 1 + word_end(&rest[w + 1..]);
                    let more = rest[f..].starts_with('.') && rest[f + 1..].starts_with(ident);
                    if let (false, Some(flag)) = (more, self.flag(&rest[..f])) {
                        out.push_str(flag);
                        rest = &rest[f..];
                        continue;
                    }
                }
                out.push_str(&rest[..w]);
                rest = &rest[w..];
                continue;
            }
            out.push(c);
            rest = &rest[c.len_utf8()..];
        }
        out
    }

    /// Make these the flags that [`shown`] uses (once, after parsing the command line).
    pub fn install(self) {
        let _ = SHOWN.set(self);
    }
}

/// A library message as the command line shows it: settings fields as flags.
pub fn shown(text: &str) -> String {
    SHOWN.get_or_init(Flags::default).rewrite(text)
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::{CommandFactory, Parser};

    #[derive(Parser)]
    struct Cli {
        #[arg(long = "max-input-mib", global = true)]
        max_input_mib: Option<u64>,
        #[command(subcommand)]
        command: Sub,
    }
    #[derive(clap::Subcommand)]
    enum Sub {
        Identify {
            #[arg(long)]
            map: Vec<String>,
            #[arg(long = "track-radii-mm")]
            track_radii_mm: Vec<f64>,
            #[arg(long = "settle-s")]
            settle_time_s: Option<f64>,
            #[arg(long)]
            json: bool,
        },
        Fit {
            #[arg(long)]
            force: bool,
        },
    }

    fn flags(args: &[&str]) -> Flags {
        let cmd = Cli::command();
        let m = cmd.clone().get_matches_from(args);
        Flags::of(&cmd, &m)
    }

    #[test]
    fn fields_are_shown_as_the_flags_of_the_subcommand_that_ran() {
        let f = flags(&["greybox", "identify"]);
        assert_eq!(
            f.rewrite("state its unit: `map` tangential=NAME:kN, or `track_radii_mm`"),
            "state its unit: --map tangential=NAME:kN, or --track-radii-mm"
        );
        assert_eq!(
            f.rewrite("identify.map: bad; identify.settle_time_s; raise `max_input_mib`"),
            "--map: bad; --settle-s; raise --max-input-mib"
        );
        // not arguments of `identify`, not in backticks, or not a stage: kept
        assert_eq!(f.rewrite("give `force`"), "give `force`");
        assert_eq!(f.rewrite("the map of law.json"), "the map of law.json");
        assert_eq!(
            f.rewrite("out.json, plan.json, plan.map.csv"),
            "out.json, plan.json, plan.map.csv"
        );
        assert_eq!(f.rewrite("a `b` `map` ü"), "a `b` --map ü");
        assert_eq!(f.rewrite("unclosed `map"), "unclosed `map");
        assert_eq!(
            f.rewrite("import, field 'map': 'map' x"),
            "import, field '--map': 'map' x"
        );
        assert_eq!(
            flags(&["greybox", "fit"]).rewrite("give `force`"),
            "give --force"
        );
    }
}
