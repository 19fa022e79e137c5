//! Text escaped where it lands: the one place where free text (model, law, feature and
//! window names, labels, titles, paths) is made safe for the file format it is written into.
//!
//! Every writer that embeds text it did not choose itself goes through one of these, never
//! through `format!` alone:
//!
//! | lands in | function | rule |
//! | --- | --- | --- |
//! | a name read from a file or the command line | [`check_name`] | a word, not a line: no control characters, at most [`MAX_NAME_CHARS`] characters |
//! | an Abaqus / CalculiX `.inp` comment, an LS-DYNA `.k` comment, a DEFORM keyword-file comment | [`deck_comment`] | one line: control characters and line separators written as `\n`, `\u{…}` |
//! | a CSV field (header or cell) | [`csv_field`], [`csv_quoted`]; [`csv_cell`] for writers using the `csv` crate | no formula (a text cell starting with `=`, `+`, `-`, `@` gets a leading `'`), one line, then RFC 4180 §2.6–2.7 quoting |
//! | a markdown table cell or text | [`markdown_text`] | `\|`, `\\`, `` ` ``, `*`, `[`, `]`, `<`, `>`, `&` backslash-escaped; one line |
//! | a shell word (`sh -c`, generated scripts) | [`shell_quote`] (also `shell::quote`) | POSIX single quotes, `'` as `'\''` |
//! | XML / SVG / HTML text and attribute values | [`xml_text`] | the five predefined entities of XML 1.0 §4.6 |
//!
//! Deck comments: an Abaqus input line starting with `**` is a comment, one starting with a
//! single `*` a keyword (Abaqus Analysis User's Guide, "Input syntax rules"); an LS-DYNA
//! keyword-file line starting with `$` is a comment, one starting with `*` a keyword (LS-DYNA
//! Keyword User's Manual, "General card format"); greybox's DEFORM keyword files start
//! comment lines with `*` (DEFORM's keyword reader skips them; a keyword such as `FRCFAC`
//! starts a line with its name). In all three a comment ends at the end of its line, so a
//! name that cannot hold a line break cannot leave the comment: once [`deck_comment`] has
//! written every line-breaking character as a visible escape, the line's prefix (`**`, `$`,
//! `*`) decides what it is, and it stays a comment whatever the name says.

use crate::{Error, Result, SourcePos};

/// The longest name accepted ([`check_name`]): longer than any column or feature name a
/// person writes, short enough for a deck's comment line (Abaqus reads 256 characters).
pub const MAX_NAME_CHARS: usize = 256;

/// Whether `c` can start a new line or is invisible control: C0 and C1 control characters
/// (newline, CR, NUL, tab, escape, NEL U+0085, …) and the Unicode line and paragraph
/// separators U+2028 and U+2029.
fn breaks_text(c: char) -> bool {
    c.is_control() || c == '\u{2028}' || c == '\u{2029}'
}

/// Why `name` is not a word (a name that may stand in a deck comment, a CSV header, a plot
/// label): `None` when it is one. Names with control characters or line separators, or of
/// more than [`MAX_NAME_CHARS`] characters, are not.
pub fn name_problem(name: &str) -> Option<String> {
    if let Some((i, c)) = name.chars().enumerate().find(|(_, c)| breaks_text(*c)) {
        return Some(format!(
            "a name must be a word, not a line: it holds the control character {:?} at character {} ({:?}…)",
            c,
            i + 1,
            name.chars().take(40).collect::<String>()
        ));
    }
    let n = name.chars().count();
    if n > MAX_NAME_CHARS {
        return Some(format!(
            "a name must be a word, not a text: {n} characters, at most {MAX_NAME_CHARS} are accepted ({:?}…)",
            name.chars().take(40).collect::<String>()
        ));
    }
    None
}

/// `name` checked to be a word ([`name_problem`]); the error names `pos` (file and field, or
/// the command-line option).
pub fn check_name(pos: SourcePos, name: &str) -> Result<()> {
    match name_problem(name) {
        None => Ok(()),
        Some(m) => Err(Error::input(pos, m)),
    }
}

/// `text` as one line: every control character and line separator written as its Rust
/// escape (`\n`, `\r`, `\0`, `\u{2028}`), everything else as it is. Plain text comes out
/// unchanged.
pub fn one_line(text: &str) -> String {
    if !text.chars().any(breaks_text) {
        return text.to_string();
    }
    let mut s = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        if breaks_text(c) {
            s.extend(c.escape_default());
        } else {
            s.push(c);
        }
    }
    s
}

/// The most characters of a value a message quotes ([`excerpt`]).
pub const MAX_EXCERPT_CHARS: usize = 80;

/// `text` as a message quotes it: on one line ([`one_line`]) and, beyond
/// [`MAX_EXCERPT_CHARS`] characters, its beginning with the length ("abc… (52428800 bytes)"):
/// a 50 MB key of a file is named, never echoed whole.
pub fn excerpt(text: &str) -> String {
    if text.chars().count() <= MAX_EXCERPT_CHARS {
        return one_line(text);
    }
    let head: String = text.chars().take(MAX_EXCERPT_CHARS - 20).collect();
    format!("{}… ({} bytes)", one_line(&head), text.len())
}

/// `text` for the body of an FE-engine deck comment (Abaqus/CalculiX `** …`, LS-DYNA `$ …`,
/// DEFORM `* …`): [`one_line`], so the comment cannot end early and nothing after it can
/// start a keyword (see the module's notes on each format's comment rule).
pub fn deck_comment(text: &str) -> String {
    one_line(text)
}

/// Whether a spreadsheet would run `text` as a formula when it opens a CSV file: a text
/// cell starting with `=`, `+`, `-`, `@`, a tab or a carriage return (OWASP, "CSV
/// Injection"). A number (`-0.5`, `+3`, `-inf`) is not a formula: it stays a number.
pub fn is_formula(text: &str) -> bool {
    text.starts_with(['=', '+', '-', '@', '\t', '\r']) && text.trim().parse::<f64>().is_err()
}

/// A CSV text cell a spreadsheet will show as text: a cell that [`is_formula`] gets a
/// leading `'` (Excel, LibreOffice and Google Sheets show the rest as text and do not
/// evaluate it); every other cell, numbers included, unchanged. The one helper of every CSV
/// writer for cells it did not compute itself (names, ids, labels, axis values); writers
/// that use the `csv` crate call it on each such cell, the others through [`csv_field`].
pub fn csv_cell(text: &str) -> std::borrow::Cow<'_, str> {
    if is_formula(text) {
        std::borrow::Cow::Owned(format!("'{text}"))
    } else {
        std::borrow::Cow::Borrowed(text)
    }
}

/// The cells of one record for a `csv::Writer`, each through [`csv_cell`] (the `csv` crate
/// quotes; this neutralises formulas): `w.write_record(csv_cells(row))`.
pub fn csv_cells<S: AsRef<str>>(cells: impl IntoIterator<Item = S>) -> Vec<String> {
    cells
        .into_iter()
        .map(|c| csv_cell(c.as_ref()).into_owned())
        .collect()
}

/// `text` as one CSV field on one line: [`one_line`] first (a record never spans lines, so
/// line-oriented readers and `grep` see one record per line), then RFC 4180 §2.6–2.7
/// quoting — as it is when it holds no comma or double quote, else enclosed in double quotes
/// with each `"` doubled. A CSV reader returns exactly `text` when `text` has no control
/// characters (names never have: [`check_name`]) and is no formula ([`csv_cell`]: a cell
/// starting with `=`, `+`, `-` or `@` gets a leading `'`).
pub fn csv_field(text: &str) -> String {
    let t = one_line(&csv_cell(text));
    if t.contains([',', '"']) {
        csv_quoted(&t)
    } else {
        t
    }
}

/// [`csv_field`], always enclosed in double quotes (for columns of free text that are quoted
/// in every row); a formula neutralised as by [`csv_cell`].
pub fn csv_quoted(text: &str) -> String {
    let t = one_line(&csv_cell(text));
    let mut s = String::with_capacity(t.len() + 2);
    s.push('"');
    for c in t.chars() {
        if c == '"' {
            s.push('"');
        }
        s.push(c);
    }
    s.push('"');
    s
}

/// `text` as markdown text (a table cell, a list item) that renders as the text itself: on
/// one line ([`one_line`]: a newline would end the table row), with every character that ends
/// a cell or starts markup backslash-escaped (CommonMark 0.31 §2.4: any ASCII punctuation may
/// be escaped) — `|`, `\`, `` ` `` (code), `*` (emphasis), `[`, `]` (links, images), `<`,
/// `>` (HTML, autolinks), `&` (entities). `_` is left: inside a word (`max_depth`) it is no
/// emphasis, and a terminal shows the same text. Plain words and numbers come out unchanged.
pub fn markdown_text(text: &str) -> String {
    const MARKUP: &[char] = &['\\', '`', '*', '[', ']', '<', '>', '|', '&'];
    let t = one_line(text);
    if !t.contains(MARKUP) {
        return t;
    }
    let mut s = String::with_capacity(t.len() + 8);
    for c in t.chars() {
        if MARKUP.contains(&c) {
            s.push('\\');
        }
        s.push(c);
    }
    s
}

/// `text` as one POSIX shell word (POSIX.1-2017 XCU 2.2.2, single quotes: every character
/// between them is literal, so a `'` is written `'\''`); NUL is refused, since no argument
/// can carry it.
pub fn shell_quote(text: &str) -> Result<String> {
    if text.contains('\0') {
        return Err(Error::invalid(
            "shell word",
            format!("{text:?} holds a NUL byte, which no shell argument can carry"),
        ));
    }
    let mut q = String::with_capacity(text.len() + 2);
    q.push('\'');
    for c in text.chars() {
        if c == '\'' {
            q.push_str("'\\''");
        } else {
            q.push(c);
        }
    }
    q.push('\'');
    Ok(q)
}

/// `text` safe in XML/SVG/HTML character data and in single- or double-quoted attribute
/// values: `& < > " '` written as the predefined entities (XML 1.0 §4.6), so no tag,
/// attribute or entity can start inside it.
pub fn xml_text(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&#39;"),
            c => out.push(c),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The names a tester tries against every format.
    fn hostile() -> Vec<String> {
        vec![
            "cof\n*INCLUDE, INPUT=/etc/passwd".into(),
            "cof\r\n$ x\n*KEYWORD".into(),
            "cof\nFRCFAC 1 2 2 0 1 1 1".into(),
            "it's \"quoted\"".into(),
            "$(touch PWNED)".into(),
            "<script>alert(1)</script>".into(),
            "a\u{2028}b\u{85}c\0d".into(),
            "x".repeat(10_000_000),
        ]
    }

    #[test]
    fn plain_names_pass_unchanged() {
        for n in [
            "cof_adhesive",
            "normal_force_N",
            "μ ratio (−)",
            "Reibwert µ",
        ] {
            assert_eq!(name_problem(n), None);
            assert_eq!(deck_comment(n), n);
            assert_eq!(csv_field(n), n);
            assert_eq!(xml_text(n), n);
        }
    }

    #[test]
    fn hostile_names_are_refused_with_the_field() {
        for n in hostile() {
            let expect_refused = n.chars().any(breaks_text) || n.chars().count() > 256;
            let r = check_name(SourcePos::file("m.json").field("target.name"), &n);
            assert_eq!(r.is_err(), expect_refused, "{:?}", &n[..n.len().min(40)]);
            if let Err(e) = r {
                let e = e.to_string();
                assert!(e.contains("m.json") && e.contains("target.name"), "{e}");
                assert!(e.contains("a word"), "{e}");
                assert!(
                    e.len() < 400,
                    "the error quotes at most a prefix: {} bytes",
                    e.len()
                );
            }
        }
    }

    #[test]
    fn deck_comments_stay_one_line() {
        for n in hostile() {
            let c = deck_comment(&n);
            assert!(!c.contains(['\n', '\r', '\0', '\u{85}', '\u{2028}']));
            for prefix in ["** law: ", "$ law: ", "* law: "] {
                assert_eq!(format!("{prefix}{c}\n").lines().count(), 1);
            }
        }
        assert_eq!(
            deck_comment("cof\n*INCLUDE, INPUT=/etc/passwd"),
            "cof\\n*INCLUDE, INPUT=/etc/passwd"
        );
    }

    /// A minimal RFC 4180 reader of one record, as spreadsheets read it.
    fn read_field(s: &str) -> String {
        match s.strip_prefix('"').and_then(|r| r.strip_suffix('"')) {
            Some(inner) => inner.replace("\"\"", "\""),
            None => s.to_string(),
        }
    }

    #[test]
    fn csv_fields_round_trip_and_keep_the_record() {
        for n in ["it's \"quoted\"", "a,b", "$(touch PWNED)", "<b>", "plain"] {
            let f = csv_field(n);
            assert_eq!(read_field(&f), n);
            assert_eq!(read_field(&csv_quoted(n)), n);
        }
        assert_eq!(csv_field("a,\"b\""), "\"a,\"\"b\"\"\"");
        assert_eq!(csv_quoted("plain"), "\"plain\"");
        for n in hostile() {
            for f in [csv_field(&n), csv_quoted(&n)] {
                assert!(!f.contains(['\n', '\r']), "one record, one line");
                if f.starts_with('"') {
                    // every quote inside is doubled: no field ends inside
                    assert_eq!(f[1..f.len() - 1].matches('"').count() % 2, 0);
                }
            }
        }
    }

    #[test]
    fn xml_text_opens_no_tag() {
        let x = xml_text("<script>alert('x')</script>&amp;\"");
        assert!(!x.contains(['<', '>', '"', '\'']));
        assert_eq!(
            x,
            "&lt;script&gt;alert(&#39;x&#39;)&lt;/script&gt;&amp;amp;&quot;"
        );
    }

    #[test]
    fn shell_quote_is_the_shell_module_rule() {
        assert_eq!(shell_quote("w;touch PWNED;x").unwrap(), "'w;touch PWNED;x'");
        assert_eq!(shell_quote("it's").unwrap(), "'it'\\''s'");
        assert!(shell_quote("a\0b").is_err());
    }

    #[test]
    fn formulas_become_text_and_numbers_stay_numbers() {
        for f in [
            "=1+1",
            "+SUM(A1)",
            "-2+3",
            "@SUM(1)",
            "=cmd|' /C calc'!A0",
            "\t=1",
        ] {
            assert!(is_formula(f), "{f}");
            assert_eq!(csv_cell(f), format!("'{f}"));
            assert!(
                csv_field(f).starts_with("'") || csv_field(f).starts_with("\"'"),
                "{f}"
            );
        }
        for n in ["-0.5", "+3", "-1e-9", "150", "-inf", "rake", "", "a=b"] {
            assert!(!is_formula(n), "{n}");
            assert_eq!(csv_cell(n), n);
        }
        assert_eq!(csv_quoted("=1,2"), "\"'=1,2\"");
    }

    #[test]
    fn markdown_markup_and_cell_ends_are_escaped() {
        assert_eq!(
            markdown_text("AISI 1045, 150 m/min"),
            "AISI 1045, 150 m/min"
        );
        assert_eq!(markdown_text("a|b"), "a\\|b");
        assert_eq!(
            markdown_text("<img src=x onerror=alert(1)> **bold** [l](javascript:x)"),
            "\\<img src=x onerror=alert(1)\\> \\*\\*bold\\*\\* \\[l\\](javascript:x)"
        );
        assert_eq!(markdown_text("row\n| x |"), r"row\\n\| x \|");
        for h in hostile() {
            let m = markdown_text(&h);
            assert!(
                !m.contains('\n') && !m.replace("\\<", "").contains('<'),
                "{}",
                excerpt(&m)
            );
        }
    }

    #[test]
    fn an_excerpt_names_a_long_value_never_echoes_it() {
        let long = "k".repeat(50 << 20);
        let e = excerpt(&long);
        assert!(e.len() < 200 && e.contains("52428800 bytes"), "{e}");
        assert_eq!(excerpt("short\nkey"), "short\\nkey");
    }
}
