//! The library names its settings by their fields, as both surfaces know them: typed, in a
//! [`SettingError`] (`identify.track_radii_mm[1]`), or marked in a message's text with
//! backticks (`` `map` ``, `` `identify.map` ``). The command line shows a setting as its
//! flag (`--track-radii-mm`) where the flag was given on the command line, as its name with
//! the flag beside it (`` `map` (--map) ``) where it was not (the value came from a study or
//! sweep file, or from nowhere), and as its name alone where the subcommand has no such flag
//! ([`Flags::setting`]). Only the
//! arguments of the subcommand that ran (and the global ones) are flags; ordinary words are
//! never touched.

use greybox_core::setting::SettingPath;
use std::collections::HashMap;
use std::sync::OnceLock;

/// One argument of the command line that ran: its flag, and whether the user gave it there.
#[derive(Debug)]
struct Arg {
    flag: String,
    given: bool,
}

/// Field name → the argument, for the arguments of one command line.
#[derive(Debug, Default)]
pub struct Flags(HashMap<String, Arg>);

static SHOWN: OnceLock<Flags> = OnceLock::new();

impl Flags {
    /// The long flags of `cmd` and of the subcommands that `matches` ran, by argument id (clap
    /// derives the id from the struct field's name), with whether each was given.
    pub fn of(cmd: &clap::Command, matches: &clap::ArgMatches) -> Flags {
        let mut map = HashMap::new();
        let (mut cmd, mut matches) = (cmd, matches);
        loop {
            for a in cmd.get_arguments() {
                if let Some(long) = a.get_long() {
                    let id = a.get_id().as_str();
                    let given = matches!(
                        matches.value_source(id),
                        Some(clap::parser::ValueSource::CommandLine)
                    );
                    let arg = Arg {
                        flag: format!("--{long}"),
                        given,
                    };
                    map.insert(id.to_string(), arg);
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

    /// A setting as the command line names it: its flag where the user gave it there
    /// (`--track-radii-mm (value 2)` for an element), the setting's name with its flag beside
    /// it where not (`` `map` (--map) ``: the value came from a study or sweep file, or from
    /// nowhere), and the name alone where this subcommand has no such flag.
    pub fn setting(&self, p: &SettingPath) -> String {
        let name = format!("`{p}`");
        let Some(a) = self.0.get(&p.field) else {
            return name;
        };
        let element = p
            .index
            .map(|i| format!(" (value {})", i + 1))
            .unwrap_or_default();
        match a.given {
            true => format!("{}{element}", a.flag),
            false => format!("{name} ({})", a.flag),
        }
    }

    /// A backticked name (`map`, `identify.map`, `hertz.force_N[0]`) as a setting, if it is
    /// one (`plan.json` is a file, `a.b.c` no setting).
    fn named(name: &str) -> Option<SettingPath> {
        let (stage, rest) = match name.split_once('.') {
            Some((stage, rest)) => (stage, rest),
            None => ("", name),
        };
        let p = SettingPath::parse(stage, rest);
        let plain =
            |s: &str| !s.is_empty() && s.chars().all(|c| c.is_ascii_alphanumeric() || c == '_');
        let back = format!("{}{}", p.field, p.index_suffix());
        (plain(stage) || stage.is_empty())
            .then_some(p)
            .filter(|p| plain(&p.field) && p.field != "json" && back == rest)
    }

    /// `text` with each `` `field` `` and `` `stage.field` `` that is an argument shown as its
    /// flag (the source position's `field 'name'` too).
    pub fn rewrite(&self, text: &str) -> String {
        let mut out = String::with_capacity(text.len());
        let mut rest = text;
        while let Some(c) = rest.chars().next() {
            let quote = match c {
                '\'' if out.ends_with("field ") => Some('\''),
                '`' => Some('`'),
                _ => None,
            };
            if let Some(q) = quote {
                if let Some(end) = rest[1..].find(q) {
                    let name = &rest[1..1 + end];
                    // a setting as [`Flags::setting`] names it; in a source position's quotes
                    // only where the flag was given
                    let shown = Self::named(name)
                        .filter(|p| self.0.get(&p.field).is_some_and(|a| q == '`' || a.given))
                        .map(|p| self.setting(&p));
                    if let Some(shown) = shown {
                        match q {
                            '`' => out.push_str(&shown),
                            _ => out.push_str(&format!("'{shown}'")),
                        }
                        rest = &rest[end + 2..];
                        continue;
                    }
                }
            }
            out.push(c);
            rest = &rest[c.len_utf8()..];
        }
        out
    }

    /// Make these the flags that [`shown`] and [`shown_error`] use (once, after parsing the
    /// command line).
    pub fn install(self) {
        let _ = SHOWN.set(self);
    }
}

fn installed() -> &'static Flags {
    SHOWN.get_or_init(Flags::default)
}

/// A library message as the command line shows it: settings fields as flags.
pub fn shown(text: &str) -> String {
    installed().rewrite(text)
}

/// An error and its causes as the command line shows them: each [`SettingError`] with its
/// settings named by [`Flags::setting`], other text by [`shown`].
pub fn shown_error(e: &anyhow::Error) -> String {
    let flags = installed();
    greybox_pipeline::settings::render_error(e, &|p| flags.setting(p), &|t| flags.rewrite(t))
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::{CommandFactory, Parser};
    use greybox_core::setting::SettingError;

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
        let f = flags(&["greybox", "identify", "--map", "x", "--track-radii-mm", "3"]);
        assert_eq!(
            f.rewrite("state its unit: `map` tangential=NAME:kN, or `track_radii_mm`"),
            "state its unit: --map tangential=NAME:kN, or --track-radii-mm"
        );
        // a flag not given: the name stays, its flag beside it
        assert_eq!(
            f.rewrite("`identify.map`: bad; raise `max_input_mib`"),
            "--map: bad; raise `max_input_mib` (--max-input-mib)"
        );
        // an element of a list flag
        assert_eq!(
            f.rewrite("`identify.track_radii_mm[0]`: small"),
            "--track-radii-mm (value 1): small"
        );
        // not arguments of `identify`, not in backticks, or a file: kept
        assert_eq!(f.rewrite("give `force`"), "give `force`");
        assert_eq!(
            f.rewrite("identify.map: the map of law.json"),
            "identify.map: the map of law.json"
        );
        assert_eq!(
            f.rewrite("`plan.json`, `plan.map.csv`"),
            "`plan.json`, `plan.map.csv`"
        );
        assert_eq!(f.rewrite("a `b` `map` ü"), "a `b` --map ü");
        assert_eq!(
            flags(&["greybox", "identify"]).rewrite("give `map`"),
            "give `map` (--map)"
        );
        assert_eq!(f.rewrite("unclosed `map"), "unclosed `map");
        assert_eq!(
            f.rewrite("import, field 'map': 'map' x"),
            "import, field '--map': 'map' x"
        );
        assert_eq!(
            flags(&["greybox", "identify"]).rewrite("import, field 'map': x"),
            "import, field 'map': x"
        );
        assert_eq!(
            flags(&["greybox", "fit", "--force"]).rewrite("give `force`"),
            "give --force"
        );
    }

    #[test]
    fn a_refused_setting_is_its_flag_where_given_and_its_name_where_not() {
        let given = flags(&[
            "greybox",
            "identify",
            "--track-radii-mm",
            "3",
            "--track-radii-mm",
            "0",
        ]);
        let e = SettingError::new(
            SettingPath::new("identify", "track_radii_mm").at(1),
            "must be positive",
        )
        .value(0);
        assert_eq!(
            e.render(|p| given.setting(p)),
            "--track-radii-mm (value 2): must be positive, got 0"
        );
        // from a file (the flag not given): the setting's name, its flag beside it
        let from_study = flags(&["greybox", "identify"]);
        assert_eq!(
            e.render(|p| from_study.setting(p)),
            "`identify.track_radii_mm[1]` (--track-radii-mm): must be positive, got 0"
        );
        // a setting the subcommand has no flag for: its name alone
        let e = SettingError::new(SettingPath::new("identify", "steady"), "not a rule");
        assert_eq!(
            e.render(|p| from_study.setting(p)),
            "`identify.steady`: not a rule"
        );
    }
}
