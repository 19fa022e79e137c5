//! Values in generated shell scripts (the Slurm array script of `greybox sweep run`).
//!
//! Every value a script receives goes through one of three functions here, never through
//! `format!` alone:
//!
//! * [`quote`] — a word for the shell: POSIX single quotes (`'…'`, a `'` inside written
//!   `'\''`), in which no character is special, so `$()`, backticks, `;`, `|`, `&`, `*`,
//!   newlines and a leading `-` all stay text. Only a NUL byte cannot be passed (a C string
//!   ends there): refused.
//! * [`directive_value`] — a value in a `#SBATCH` line. `sbatch` reads those lines itself, not
//!   through a shell, and splits them at white space; a newline would start a new line of the
//!   script. Such values must match a conservative allow-list (ASCII letters, digits and
//!   `_ . - / : % @ + , =`), anything else is refused with the field named.
//! * [`comment`] — text in a `#` comment: control characters (a newline would end the
//!   comment) escaped as `\n`, `\u{…}`.

use crate::{Error, Result};

/// `s` as one shell word in POSIX single quotes; `sh -c "printf %s <quoted>"` prints exactly
/// `s`. Refused: a NUL byte (no shell argument can hold one).
pub fn quote(s: &str) -> Result<String> {
    crate::escape::shell_quote(s)
}

/// `s` as one shell word, quoted only where it needs to be: as it is when it is non-empty and
/// every character is plain (letters, digits, `_ . - / : % @ + , =`), else [`quote`]d. For
/// commands shown to a user to copy (`--map time=Time:s`, `--map 'tangential=Friction Force:N'`).
pub fn word(s: &str) -> Result<String> {
    if !s.is_empty() && s.chars().all(directive_char) {
        Ok(s.to_string())
    } else {
        quote(s)
    }
}

/// Whether `c` may stand in a `#SBATCH` directive value.
fn directive_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || "_.-/:%@+,=".contains(c)
}

/// `value` checked for a `#SBATCH` line (`field` names it in the error): non-empty, not
/// starting with `-`, only characters of the allow-list (no white space, quotes, newlines or
/// shell metacharacters).
pub fn directive_value<'a>(field: &str, value: &'a str) -> Result<&'a str> {
    let bad: Vec<char> = value.chars().filter(|c| !directive_char(*c)).collect();
    if value.is_empty() || value.starts_with('-') || !bad.is_empty() {
        return Err(Error::invalid(
            field,
            format!(
                "{value:?} cannot go into an #SBATCH line{}: sbatch reads those lines itself, so only ASCII letters, digits and _ . - / : % @ + , = are accepted (and no leading '-')",
                if bad.is_empty() {
                    String::new()
                } else {
                    format!(" (it holds {:?})", bad.iter().collect::<String>())
                }
            ),
        ));
    }
    Ok(value)
}

/// `text` for a `#` comment line: control characters escaped, so the comment stays one line
/// ([`crate::escape::one_line`]).
pub fn comment(text: &str) -> String {
    crate::escape::one_line(text)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::process::Command;

    /// Strings a tester would try: quotes, newlines, substitutions, separators, globs, a
    /// leading dash, unicode, backslashes, an empty string.
    const HOSTILE: &[&str] = &[
        "",
        "plain",
        "it's",
        "''",
        "'\\''",
        "a\nb",
        "x'\ntouch /tmp/greybox-pwned\n'",
        "$(touch /tmp/greybox-pwned)",
        "`touch /tmp/greybox-pwned`",
        "${HOME}",
        "a; touch /tmp/greybox-pwned",
        "a | cat",
        "a & b",
        "a && b || c",
        "*",
        "/*/*",
        "-n",
        "--help",
        "é ü 漢字 🚀",
        "back\\slash\\",
        "\"double\"",
        "tab\there",
        "!event",
        "~root",
        "a > /tmp/greybox-pwned",
        "#comment",
        "\r\n",
    ];

    fn printed_by(shell: &str, quoted: &str) -> Vec<u8> {
        let out = Command::new(shell)
            .arg("-c")
            .arg(format!("printf %s {quoted}"))
            .current_dir(std::env::temp_dir())
            .output()
            .unwrap_or_else(|e| panic!("cannot run {shell}: {e}"));
        assert!(
            out.status.success(),
            "{shell} failed on {quoted}: {:?}",
            out
        );
        out.stdout
    }

    #[test]
    fn every_hostile_string_round_trips_through_sh_and_bash() {
        for s in HOSTILE {
            let q = quote(s).unwrap();
            for shell in ["/bin/sh", "/bin/bash"] {
                assert_eq!(
                    printed_by(shell, &q),
                    s.as_bytes(),
                    "{shell} printed something else for {s:?} quoted as {q}"
                );
            }
        }
    }

    #[test]
    fn nul_is_refused() {
        let e = quote("a\0b").unwrap_err().to_string();
        assert!(e.contains("NUL"), "{e}");
    }

    #[test]
    fn directive_values_follow_the_allow_list() {
        for ok in [
            "compute",
            "gpu,cpu",
            "01:30:00",
            "2-00:00:00",
            "/data/o/slurm/%A_%a.log",
        ] {
            assert_eq!(directive_value("f", ok).unwrap(), ok);
        }
        for s in HOSTILE.iter().filter(|s| !["plain"].contains(s)) {
            let e = directive_value("[slurm] partition", s)
                .unwrap_err()
                .to_string();
            assert!(
                e.contains("[slurm] partition") && e.contains("#SBATCH"),
                "{e}"
            );
        }
        assert!(directive_value("p", "a b").is_err());
        assert!(directive_value("p", "a\0b").is_err());
    }

    #[test]
    fn comments_stay_one_line() {
        let c = comment("s.toml\nrm -rf ~\r\0");
        assert!(
            !c.contains('\n') && !c.contains('\r') && !c.contains('\0'),
            "{c}"
        );
        assert!(c.contains("\\n"), "{c}");
        assert_eq!(comment("é.toml"), "é.toml");
    }

    #[test]
    fn words_are_quoted_only_where_needed() {
        assert_eq!(word("time=Time:s").unwrap(), "time=Time:s");
        assert_eq!(word("t=Friction Force:N").unwrap(), "'t=Friction Force:N'");
        assert_eq!(word("a;b").unwrap(), "'a;b'");
        assert_eq!(word("").unwrap(), "''");
        assert!(word("a\0b").is_err());
    }
}
