//! Dialect sniffing and header detection: the delimiter and decimal comma that give the longest run
//! of numeric rows, the header line above it, or none (a headerless log).

use super::fields::{clip, is_blank, parse_number, split_fields, split_header, trim, Line};
use super::options::{Delimiter, TextOptions, CONFIRM_ROWS, SNIFF_LINES};
use crate::table::is_unit_token;
use greybox_core::{Error, Result, SourcePos};

/// The shape of a split line: `core` fields up to the last non-empty one and `raw` fields in
/// all (the empty ones after `core` are trailing delimiters). A row fits a table of `n`
/// columns when `core <= n <= raw`: it may leave trailing columns empty (`1,2,,`) and may end
/// in more delimiters than the header (`0,98;  2,41;;` under `TIME;  FF;`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Shape {
    pub(super) core: usize,
    pub(super) raw: usize,
}

impl Shape {
    pub(super) fn fits(self, n: usize) -> bool {
        self.core <= n && n <= self.raw
    }
}

/// Split `line` into `spans` and give its [`Shape`].
pub(super) fn shape(line: &[u8], d: Delimiter, spans: &mut Vec<(usize, usize)>) -> Shape {
    split_fields(line, d, spans);
    let core = spans
        .iter()
        .rposition(|&(a, b)| !trim(&line[a..b]).is_empty())
        .map_or(0, |k| k + 1);
    Shape {
        core,
        raw: spans.len(),
    }
}

/// Whether the non-empty fields among `spans` are (mostly) numbers: at least two numbers (one
/// in a one-field row) and at least half of the non-empty fields (a date or comment column may
/// sit beside the numbers; sparse exports leave many fields empty).
pub(super) fn mostly_numeric(line: &[u8], spans: &[(usize, usize)], dc: bool) -> bool {
    let (mut filled, mut numbers) = (0, 0);
    for &(a, b) in spans {
        if trim(&line[a..b]).is_empty() {
            continue;
        }
        filled += 1;
        numbers += usize::from(parse_number(&line[a..b], dc).is_some());
    }
    numbers >= 2.min(spans.len()) && numbers > 0 && 2 * numbers >= filled
}

/// Fewer than half of the fields are numbers (a header may have a numeric name or two).
pub(super) fn mostly_text(line: &[u8], d: Delimiter, dc: bool) -> bool {
    let mut spans = Vec::new();
    let n = shape(line, d, &mut spans).core;
    let numbers = spans[..n]
        .iter()
        .filter(|&&(a, b)| parse_number(&line[a..b], dc).is_some())
        .count();
    2 * numbers < n.max(1) || n == 1
}

/// The shape of a row of (mostly) numbers, with `decimal_comma` deciding the mark.
pub(super) fn numeric_row(
    line: &[u8],
    d: Delimiter,
    dc: bool,
    spans: &mut Vec<(usize, usize)>,
) -> Option<Shape> {
    let s = shape(line, d, spans);
    (s.core > 0 && mostly_numeric(line, &spans[..s.core], dc)).then_some(s)
}

/// The names of a header (or units) line with trailing empty names (trailing delimiters)
/// dropped.
pub(super) fn header_names(text: &[u8], d: Delimiter) -> Vec<String> {
    let mut names = split_header(text, d);
    while names.last().is_some_and(|s| s.is_empty()) {
        names.pop();
    }
    names
}

/// A row right under the header whose fields are all units (at least one not empty).
pub(super) fn units_row(text: &[u8], d: Delimiter) -> bool {
    let fields = header_names(text, d);
    !fields.is_empty() && fields.iter().all(|f| is_unit_token(f))
}

/// The layout found for one delimiter.
#[derive(Debug, Clone, Copy)]
pub(super) struct Candidate {
    pub(super) delimiter: Delimiter,
    pub(super) decimal_comma: bool,
    /// Index into the sniffed lines of the header (None: no header line).
    pub(super) header: Option<usize>,
    /// Index of the units row right under the header, if there is one.
    pub(super) units: Option<usize>,
    /// Index of the first data line.
    pub(super) data: usize,
    pub(super) fields: usize,
    /// Every field of the first data row is a number.
    pub(super) all_numeric: bool,
}

/// The fields a run of numeric rows from line `i` agrees on: (most `core`, least `raw`); at
/// least two rows (one if the lines end there) and two fields.
pub(super) fn confirmed_run(
    lines: &[Line],
    numeric: &[Option<Shape>],
    i: usize,
) -> Option<(usize, usize)> {
    let first = numeric[i]?;
    let (mut core, mut raw) = (first.core, first.raw);
    let mut k = 0;
    let mut ended = true;
    for (j, l) in lines.iter().enumerate().skip(i) {
        if is_blank(l.text) {
            continue;
        }
        match numeric[j].filter(|s| s.core.max(core) <= s.raw.min(raw)) {
            Some(s) => {
                core = core.max(s.core);
                raw = raw.min(s.raw);
            }
            None => {
                ended = false;
                break;
            }
        }
        k += 1;
        if k == CONFIRM_ROWS {
            break;
        }
    }
    (core >= 2 && (k >= 2 || (k == 1 && ended))).then_some((core, raw))
}

/// A log of one column (a rig that writes only its μ, one number per line): from line `i` to
/// the last line looked at, every non-blank line is one number, at least two of them. Taken
/// only when no run of several fields exists, so numbers in a preamble (a serial number, a
/// setting per line) never hide the table below them: (1, raw).
pub(super) fn single_column_run(
    lines: &[Line],
    numeric: &[Option<Shape>],
    i: usize,
) -> Option<(usize, usize)> {
    numeric[i].filter(|s| s.core == 1)?;
    let mut raw = usize::MAX;
    let mut rows = 0;
    for (j, l) in lines.iter().enumerate().skip(i) {
        if is_blank(l.text) {
            continue;
        }
        let s = numeric[j].filter(|s| s.core == 1)?;
        raw = raw.min(s.raw);
        rows += 1;
    }
    (rows >= 2).then_some((1, raw))
}

/// A line that a comma, semicolon or tab splits into several names (a header of several
/// columns; spaces do not count, `Friction coefficient` is one name).
fn names_several(text: &[u8]) -> bool {
    [Delimiter::Comma, Delimiter::Semicolon, Delimiter::Tab]
        .into_iter()
        .any(|d| {
            header_names(text, d)
                .iter()
                .filter(|n| !n.is_empty())
                .count()
                > 1
        })
}

/// Header (and units row) above the data line `data`: the last non-blank line above it, or
/// the one above that when that last line is a units row. A header is not numeric, mostly
/// text, and names between `core` and `raw` columns (any number when forced).
pub(super) fn find_header(
    lines: &[Line],
    numeric: &[Option<Shape>],
    data: usize,
    (d, dc): (Delimiter, bool),
    forced: Option<usize>,
    (core, raw): (usize, usize),
) -> (Option<usize>, Option<usize>) {
    let prev_text =
        |below: usize, floor: usize| (floor..below).rev().find(|&i| !is_blank(lines[i].text));
    let header_ok = |h: usize| {
        numeric[h].is_none()
            && mostly_text(lines[h].text, d, dc)
            && (forced.is_some() || (core..=raw).contains(&header_names(lines[h].text, d).len()))
    };
    let units_ok = |u: usize| numeric[u].is_none() && units_row(lines[u].text, d);
    if let Some(h) = forced {
        // the user's header is taken as it stands, even of numbers (channel numbers `1,2,3`)
        let units =
            prev_text(data, h + 1).filter(|&u| units_ok(u) && prev_text(u, h + 1).is_none());
        return (Some(h), units);
    }
    let Some(last) = prev_text(data, 0) else {
        return (None, None);
    };
    if units_ok(last) {
        if let Some(h) =
            prev_text(last, 0).filter(|&h| header_ok(h) && !units_row(lines[h].text, d))
        {
            return (Some(h), Some(last));
        }
    }
    (header_ok(last).then_some(last), None)
}

/// The other lines above the data that could name its columns: not numeric, mostly text, as
/// many names as the data has fields, neither the header taken nor its units row. When the
/// header taken (the last such line above the data) names no channel, one of these may (a
/// garbled or separator line between the header and the data): (1-based line, names).
pub(super) fn other_header_lines(lines: &[Line], c: &Candidate) -> Vec<(u64, Vec<String>)> {
    let mut spans = Vec::new();
    lines[..c.data]
        .iter()
        .enumerate()
        .filter(|&(i, l)| {
            Some(i) != c.header
                && Some(i) != c.units
                && !is_blank(l.text)
                && numeric_row(l.text, c.delimiter, c.decimal_comma, &mut spans).is_none()
                && mostly_text(l.text, c.delimiter, c.decimal_comma)
                && !units_row(l.text, c.delimiter)
        })
        .map(|(_, l)| (l.number, header_names(l.text, c.delimiter)))
        .filter(|(_, names)| names.len() == c.fields)
        .collect()
}

/// Find header and data start for one delimiter among the first lines.
pub(super) fn sniff(
    lines: &[Line],
    d: Delimiter,
    dc: bool,
    forced_header: Option<usize>,
) -> Option<Candidate> {
    let mut spans = Vec::new();
    let numeric: Vec<Option<Shape>> = lines
        .iter()
        .map(|l| numeric_row(l.text, d, dc, &mut spans))
        .collect();
    let start = forced_header.map_or(0, |h| h + 1);
    let (data, (core, raw)) = (start..lines.len())
        .find_map(|i| Some((i, confirmed_run(lines, &numeric, i)?)))
        .or_else(|| {
            (start..lines.len()).find_map(|i| Some((i, single_column_run(lines, &numeric, i)?)))
        })?;
    let (header, units) = find_header(lines, &numeric, data, (d, dc), forced_header, (core, raw));
    if core == 1 && header.is_some_and(|h| names_several(lines[h].text)) && forced_header.is_none()
    {
        // a header of several names over one number per line is no one-column log
        return None;
    }
    let fields = header
        .map(|h| header_names(lines[h].text, d).len())
        .filter(|n| (core..=raw).contains(n))
        .unwrap_or(core);
    split_fields(lines[data].text, d, &mut spans);
    let all_numeric = spans[..fields]
        .iter()
        .all(|&(a, b)| parse_number(&lines[data].text[a..b], dc).is_some());
    Some(Candidate {
        delimiter: d,
        decimal_comma: dc,
        header,
        units,
        data,
        fields,
        all_numeric,
    })
}

pub(super) fn choose_layout(lines: &[Line], opts: &TextOptions, source: &str) -> Result<Candidate> {
    let forced_header = match opts.header_line {
        Some(0) => None,
        Some(h) => Some(lines.iter().position(|l| l.number == h).ok_or_else(|| {
            Error::input(
                SourcePos::file(source).line(h),
                format!("`header_line` {h}: the file has only {} lines", lines.len()),
            )
        })?),
        None => None,
    };
    let delims: Vec<Delimiter> = match opts.delimiter {
        Some(d) => vec![d],
        None => Delimiter::ALL.to_vec(),
    };
    let mut best: Option<Candidate> = None;
    for d in delims {
        let marks: Vec<bool> = match (opts.decimal_comma, d) {
            (Some(dc), _) => vec![dc],
            (None, Delimiter::Comma) => vec![false],
            (None, _) => vec![false, true],
        };
        for dc in marks {
            let Some(c) = sniff(lines, d, dc, forced_header) else {
                continue;
            };
            // prefer: a header found, rows of numbers only, more fields, the earlier data, then
            // the delimiter order
            let better = match &best {
                None => true,
                Some(b) => {
                    (
                        c.header.is_some(),
                        c.all_numeric,
                        c.fields,
                        std::cmp::Reverse(c.data),
                    ) > (
                        b.header.is_some(),
                        b.all_numeric,
                        b.fields,
                        std::cmp::Reverse(b.data),
                    )
                }
            };
            if better {
                best = Some(c);
            }
        }
    }
    let c = best.ok_or_else(|| {
        Error::input(
            SourcePos::file(source),
            format!(
                "no table found in the first {SNIFF_LINES} lines: expected a header line followed by rows of numbers separated by commas, semicolons, tabs or spaces"
            ),
        )
    })?;
    if c.header.is_none() && !headerless(lines, &c) {
        let candidate = other_header_lines(lines, &c).pop().map_or(
            "N for the header's line".to_string(),
            |(line, names)| {
                format!(
                    "{line} if line {line} ({}) is the header",
                    clip(&names.join(", "))
                )
            },
        );
        return Err(Error::input(
            SourcePos::file(source).line(lines[c.data].number),
            format!(
                "found {}-delimited numeric data from line {} in {} columns, but the lines above it are not a header that names them (nor comments above a file of numbers only); give `header_line` {candidate}",
                c.delimiter.name(),
                lines[c.data].number,
                c.fields
            ),
        ));
    }
    Ok(c)
}

/// A file of numbers only (a DAQ or microcontroller log): no header above the data, at most
/// comment lines of one field each (`# logger v2`). Its columns are named `#1`, `#2`, … A line
/// of several names or of numbers above the data is a header that does not fit, or broken
/// data: not headerless.
pub(super) fn headerless(lines: &[Line], c: &Candidate) -> bool {
    lines[..c.data].iter().all(|l| {
        is_blank(l.text)
            || header_names(l.text, c.delimiter)
                .iter()
                .filter(|n| !n.is_empty())
                .count()
                < 2
    })
}
