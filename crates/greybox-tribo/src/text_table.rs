//! Delimited text tables as rigs export them (CSV, TXT, DAT, TSV), dialect found from the file.
//!
//! What is sniffed from the first lines: a UTF-8 byte-order mark, CRLF or LF line ends, the
//! delimiter (tab, semicolon, comma or runs of whitespace), decimal commas, the header line
//! below any preamble (the last line above the first run of numeric rows that has as many
//! fields), and a trailing delimiter on every line. Lines after the data that are not data
//! (an `End of data` or a summary) are the footer: reported, not an error. A file of numbers
//! only (a DAQ or microcontroller log; comment lines of one field may stand above) has no
//! header: its columns are named `#1`, `#2`, … by position ([`crate::table::Table::headerless`]).
//! Double quotes protect a delimiter inside a field, in the header and in the data (a quoted
//! `"1,5"` in a comma-delimited file is a decimal comma); header bytes that are not UTF-8 are
//! Latin-1. A non-numeric cell
//! inside the data only matters when a role is mapped to its column
//! ([`crate::table::ColumnData::NotNumeric`]).
//!
//! The data lines are parsed in parallel chunks (rayon) straight from the memory-mapped file
//! into the final columns: plain decimals exactly by [`crate::decimal`], other numbers with
//! `fast-float2`. The result does not depend on the number of threads.

use crate::table::{is_unit_token, unit_token, Column, ColumnData, Table};
use greybox_core::{Error, Result, SourcePos};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

/// Field delimiter of a text table.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Delimiter {
    Tab,
    Semicolon,
    Comma,
    /// One or more spaces or tabs.
    Whitespace,
}

impl Delimiter {
    /// In the order a tie is broken.
    const ALL: [Delimiter; 4] = [
        Delimiter::Tab,
        Delimiter::Semicolon,
        Delimiter::Comma,
        Delimiter::Whitespace,
    ];
    pub fn name(self) -> &'static str {
        match self {
            Delimiter::Tab => "tab",
            Delimiter::Semicolon => "semicolon",
            Delimiter::Comma => "comma",
            Delimiter::Whitespace => "whitespace",
        }
    }
    fn byte(self) -> Option<u8> {
        match self {
            Delimiter::Tab => Some(b'\t'),
            Delimiter::Semicolon => Some(b';'),
            Delimiter::Comma => Some(b','),
            Delimiter::Whitespace => None,
        }
    }
}

/// What the caller knows about the file's layout; everything else is sniffed.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct TextOptions {
    /// 1-based line of the header (default: found automatically). A line given is always
    /// the header, even one of numbers (channel numbers `1,2,3`); the data starts below it.
    pub header_line: Option<u64>,
    pub delimiter: Option<Delimiter>,
    pub decimal_comma: Option<bool>,
}

/// How many lines are looked at to find the layout.
const SNIFF_LINES: usize = 200;
/// Numeric rows that must follow a header for it to count.
const CONFIRM_ROWS: usize = 3;

/// Read a text table from a file.
///
/// Only a regular file of at most the budget `max_recording_bytes` is read
/// ([`greybox_core::budget::open_recording`]: a FIFO, a device or a link to one is refused by
/// name). It is memory-mapped (no copy of a file of hundreds of MB into a buffer); the file
/// must not be truncated while it is read, as with any reader that maps files. On a file
/// system without mmap it is read into memory.
pub fn read_text_table(path: &std::path::Path, opts: &TextOptions) -> Result<Table> {
    let source = path.display().to_string();
    let (file, len) = greybox_core::budget::open_recording(path)?;
    if len > 0 {
        // SAFETY: the map is read-only and lives only for this call. Like every reader that
        // maps files (ripgrep, polars), this relies on no other process truncating or
        // rewriting the recording while it is parsed, as the doc comment states.
        if let Ok(map) = unsafe { memmap2::Mmap::map(&file) } {
            return parse_text_table(&map, &source, opts);
        }
    }
    drop(file);
    parse_text_table(
        &greybox_core::budget::read_recording_bytes(path)?,
        &source,
        opts,
    )
}

/// One line of the file: its 1-based number and its bytes without the line end.
#[derive(Clone, Copy)]
struct Line<'a> {
    number: u64,
    text: &'a [u8],
}

fn strip_cr(l: &[u8]) -> &[u8] {
    l.strip_suffix(b"\r").unwrap_or(l)
}

fn is_blank(l: &[u8]) -> bool {
    l.iter().all(|b| b.is_ascii_whitespace())
}

fn trim(b: &[u8]) -> &[u8] {
    let s = b
        .iter()
        .position(|c| !c.is_ascii_whitespace())
        .unwrap_or(b.len());
    let e = b
        .iter()
        .rposition(|c| !c.is_ascii_whitespace())
        .map_or(s, |e| e + 1);
    &b[s..e.max(s)]
}

fn unquote(b: &[u8]) -> &[u8] {
    let t = trim(b);
    if t.len() >= 2 && t[0] == b'"' && t[t.len() - 1] == b'"' {
        &t[1..t.len() - 1]
    } else {
        t
    }
}

/// Split a line into fields. Double quotes protect a delimiter inside a field (`"Load, N"`,
/// `"1,5"`); a line without quotes is split at every delimiter.
fn split_fields(line: &[u8], d: Delimiter, out: &mut Vec<(usize, usize)>) {
    out.clear();
    match d.byte() {
        Some(b) if memchr::memchr(b'"', line).is_some() => {
            let (mut start, mut quoted) = (0, false);
            for (i, &c) in line.iter().enumerate() {
                if c == b'"' {
                    quoted = !quoted;
                } else if c == b && !quoted {
                    out.push((start, i));
                    start = i + 1;
                }
            }
            out.push((start, line.len()));
        }
        Some(b) => {
            let mut start = 0;
            for i in memchr::memchr_iter(b, line) {
                out.push((start, i));
                start = i + 1;
            }
            out.push((start, line.len()));
        }
        None => {
            let mut i = 0;
            let n = line.len();
            while i < n {
                while i < n && (line[i] == b' ' || line[i] == b'\t') {
                    i += 1;
                }
                if i == n {
                    break;
                }
                let s = i;
                while i < n && line[i] != b' ' && line[i] != b'\t' {
                    i += 1;
                }
                out.push((s, i));
            }
        }
    }
}

/// Parse a number; with `decimal_comma`, `,` is the decimal mark, and a quoted field with one
/// comma (`"1,5"`, as spreadsheets write decimal commas into a comma-delimited file) is read
/// with a decimal comma too unless it may be a thousands separator ([`quoted_decimal_comma`]).
/// `None` for anything else (including NaN and infinities, which a recording never
/// legitimately holds).
#[inline]
fn parse_number(field: &[u8], decimal_comma: bool) -> Option<f64> {
    // fast path: a plain number without spaces or quotes
    if !decimal_comma {
        if let Ok(v) = fast_float2::parse::<f64, _>(field) {
            return v.is_finite().then_some(v);
        }
    }
    let t = unquote(field);
    if t.is_empty() {
        return None;
    }
    let quoted_comma = t.len() < trim(field).len() && quoted_decimal_comma(t);
    let v = if (decimal_comma || quoted_comma) && memchr::memchr(b',', t).is_some() {
        if t.len() > 64 || memchr::memchr(b'.', t).is_some() {
            return None;
        }
        let mut buf = [0u8; 64];
        for (k, c) in t.iter().enumerate() {
            buf[k] = if *c == b',' { b'.' } else { *c };
        }
        fast_float2::parse::<f64, _>(&buf[..t.len()]).ok()?
    } else {
        fast_float2::parse::<f64, _>(t).ok()?
    };
    v.is_finite().then_some(v)
}

/// Whether the one comma of a quoted number can only be a decimal mark: `"1,5"`, `"0,125"`,
/// `"12,25"`. `"1,234"` or `"-12,500"` (1 to 3 digits, not led by 0, then 3 digits) may be a
/// thousands separator as well, so it is no number (an error naming its line when the column
/// is used) rather than a value that may be 1000 times off.
fn quoted_decimal_comma(t: &[u8]) -> bool {
    let mut parts = t.split(|&b| b == b',');
    let (Some(int), Some(frac), None) = (parts.next(), parts.next(), parts.next()) else {
        return false;
    };
    let digits = int
        .strip_prefix(b"-")
        .or(int.strip_prefix(b"+"))
        .unwrap_or(int);
    let thousands = (1..=3).contains(&digits.len())
        && digits[0] != b'0'
        && digits.iter().all(u8::is_ascii_digit)
        && frac.len() == 3
        && frac.iter().all(u8::is_ascii_digit);
    !thousands
}

/// Text of a header or preamble line: UTF-8, else Latin-1 (Windows rig software writes `µm`
/// and `°C` as single bytes 0xB5 and 0xB0), so that a unit survives either encoding.
fn decode(bytes: &[u8]) -> std::borrow::Cow<'_, str> {
    match std::str::from_utf8(bytes) {
        Ok(s) => std::borrow::Cow::Borrowed(s),
        Err(_) => std::borrow::Cow::Owned(bytes.iter().map(|&b| char::from(b)).collect()),
    }
}

/// Split a header line into names; double quotes may protect delimiters inside a name
/// ([`split_fields`]) and are removed.
fn split_header(line: &[u8], d: Delimiter) -> Vec<String> {
    if d == Delimiter::Whitespace {
        // names with single spaces ("Normal force") are separated by two or more spaces or tabs
        let by_wide: Vec<String> = decode(line)
            .split('\t')
            .flat_map(|p| p.split("  "))
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .map(str::to_string)
            .collect();
        return by_wide;
    }
    let mut spans = Vec::new();
    split_fields(line, d, &mut spans);
    spans
        .iter()
        .map(|&(a, b)| decode(&line[a..b]).replace('"', "").trim().to_string())
        .collect()
}

/// The shape of a split line: `core` fields up to the last non-empty one and `raw` fields in
/// all (the empty ones after `core` are trailing delimiters). A row fits a table of `n`
/// columns when `core <= n <= raw`: it may leave trailing columns empty (`1,2,,`) and may end
/// in more delimiters than the header (`0,98;  2,41;;` under `TIME;  FF;`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
struct Shape {
    core: usize,
    raw: usize,
}

impl Shape {
    fn fits(self, n: usize) -> bool {
        self.core <= n && n <= self.raw
    }
}

/// Split `line` into `spans` and give its [`Shape`].
fn shape(line: &[u8], d: Delimiter, spans: &mut Vec<(usize, usize)>) -> Shape {
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
fn mostly_numeric(line: &[u8], spans: &[(usize, usize)], dc: bool) -> bool {
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
fn mostly_text(line: &[u8], d: Delimiter, dc: bool) -> bool {
    let mut spans = Vec::new();
    let n = shape(line, d, &mut spans).core;
    let numbers = spans[..n]
        .iter()
        .filter(|&&(a, b)| parse_number(&line[a..b], dc).is_some())
        .count();
    2 * numbers < n.max(1) || n == 1
}

/// The shape of a row of (mostly) numbers, with `decimal_comma` deciding the mark.
fn numeric_row(
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
fn header_names(text: &[u8], d: Delimiter) -> Vec<String> {
    let mut names = split_header(text, d);
    while names.last().is_some_and(|s| s.is_empty()) {
        names.pop();
    }
    names
}

/// A row right under the header whose fields are all units (at least one not empty).
fn units_row(text: &[u8], d: Delimiter) -> bool {
    let fields = header_names(text, d);
    !fields.is_empty() && fields.iter().all(|f| is_unit_token(f))
}

/// The layout found for one delimiter.
#[derive(Debug, Clone, Copy)]
struct Candidate {
    delimiter: Delimiter,
    decimal_comma: bool,
    /// Index into the sniffed lines of the header (None: no header line).
    header: Option<usize>,
    /// Index of the units row right under the header, if there is one.
    units: Option<usize>,
    /// Index of the first data line.
    data: usize,
    fields: usize,
    /// Every field of the first data row is a number.
    all_numeric: bool,
}

/// The fields a run of numeric rows from line `i` agrees on: (most `core`, least `raw`); at
/// least two rows (one if the lines end there) and two fields.
fn confirmed_run(lines: &[Line], numeric: &[Option<Shape>], i: usize) -> Option<(usize, usize)> {
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

/// Header (and units row) above the data line `data`: the last non-blank line above it, or
/// the one above that when that last line is a units row. A header is not numeric, mostly
/// text, and names between `core` and `raw` columns (any number when forced).
fn find_header(
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

/// Find header and data start for one delimiter among the first lines.
fn sniff(
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
    let data = (start..lines.len()).find(|&i| confirmed_run(lines, &numeric, i).is_some())?;
    let (core, raw) = confirmed_run(lines, &numeric, data)?;
    let (header, units) = find_header(lines, &numeric, data, (d, dc), forced_header, (core, raw));
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

fn choose_layout(lines: &[Line], opts: &TextOptions, source: &str) -> Result<Candidate> {
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
        return Err(Error::input(
            SourcePos::file(source).line(lines[c.data].number),
            format!(
                "found {}-delimited numeric data from line {} in {} columns, but the lines above it are not a header that names them (nor comments above a file of numbers only); give `header_line` N for the header's line",
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
fn headerless(lines: &[Line], c: &Candidate) -> bool {
    lines[..c.data].iter().all(|l| {
        is_blank(l.text)
            || header_names(l.text, c.delimiter)
                .iter()
                .filter(|n| !n.is_empty())
                .count()
                < 2
    })
}

/// A line of the data region that is not a data row (a footer, a block's settings or header
/// line, a malformed row).
#[derive(Debug, Clone)]
struct OtherLine {
    line: u64,
    /// The line as written (line end removed, not trimmed).
    text: String,
    /// A numeric row with the wrong number of fields: how many it has.
    wrong: Option<usize>,
    /// Data rows of its chunk above it.
    row: usize,
}

/// One parsed chunk of data lines.
struct Chunk {
    /// Data rows written to the front of the chunk's column slices.
    rows: usize,
    /// First non-number per column: (line, text).
    bad: Vec<Option<(u64, String)>>,
    /// Columns with at least one non-empty cell.
    filled: Vec<bool>,
    /// Lines that are not data rows.
    other: Vec<OtherLine>,
    last_data_line: u64,
}

/// How the one-pass row parser ([`fast_row`]) sees a line: the field separator and the
/// decimal mark.
#[derive(Clone, Copy)]
struct FastLayout {
    /// `None`: runs of spaces or tabs separate fields (leading and trailing ones allowed).
    separator: Option<u8>,
    mark: u8,
}

impl FastLayout {
    fn of(c: &Candidate) -> Self {
        FastLayout {
            separator: c.delimiter.byte(),
            mark: if c.decimal_comma { b',' } else { b'.' },
        }
    }
}

/// One number at the start of `s`: a plain decimal exactly ([`crate::decimal`]), anything
/// else through `fast-float2` (point mark only; a decimal-comma number with an exponent takes
/// the general path).
#[inline]
fn number_prefix(s: &[u8], mark: u8) -> Option<(f64, usize)> {
    if let Some(r) = crate::decimal::parse_plain_prefix(s, mark) {
        return Some(r);
    }
    if mark != b'.' {
        return None;
    }
    let (v, used) = fast_float2::parse_partial::<f64, _>(s).ok()?;
    (used > 0 && v.is_finite()).then_some((v, used))
}

fn is_blank_byte(b: u8) -> bool {
    b == b' ' || b == b'\t'
}

/// The common case in one pass over the bytes, without finding the line end first: a line of
/// `row.len()` numbers separated as `f` says (an optional trailing delimiter), each finite,
/// ended by LF, CRLF or the end of `text`. The bytes used, line end included; `None` for
/// anything else (the caller takes the general path, which gives the same values or a
/// precise error).
#[inline]
fn fast_row(text: &[u8], f: FastLayout, row: &mut [f64]) -> Option<usize> {
    let line = text;
    let mut p = 0;
    let n = row.len();
    let skip_blanks = |p: &mut usize| {
        while line.get(*p).is_some_and(|b| is_blank_byte(*b)) {
            *p += 1;
        }
    };
    if f.separator.is_none() {
        skip_blanks(&mut p);
    }
    for (k, slot) in row.iter_mut().enumerate() {
        let (v, used) = number_prefix(&line[p..], f.mark)?;
        *slot = v;
        p += used;
        if k + 1 < n {
            match f.separator {
                Some(d) => {
                    if line.get(p) != Some(&d) {
                        return None;
                    }
                    p += 1;
                }
                None => {
                    let before = p;
                    skip_blanks(&mut p);
                    if p == before {
                        return None;
                    }
                }
            }
        }
    }
    match f.separator {
        Some(d) if line.get(p) == Some(&d) => p += 1,
        Some(_) => {}
        None => skip_blanks(&mut p),
    }
    if line.get(p) == Some(&b'\r') {
        p += 1;
    }
    match line.get(p) {
        None => Some(p),
        Some(b'\n') => Some(p + 1),
        Some(_) => None,
    }
}

/// Parse the lines of `part` (starting at line number `first_line`) into `out`, one slice per
/// column with room for every line of the part.
fn parse_chunk(part: &[u8], first_line: u64, c: &Candidate, out: &mut [&mut [f64]]) -> Chunk {
    let n = c.fields;
    let mut ch = Chunk {
        rows: 0,
        bad: vec![None; n],
        filled: vec![false; n],
        other: Vec::new(),
        last_data_line: 0,
    };
    let mut spans = Vec::with_capacity(n + 1);
    let mut row = vec![0.0; n];
    let fast = FastLayout::of(c);
    let mut p = 0;
    let mut number = first_line;
    let mut any_fast = false;
    while p < part.len() {
        if let Some(used) = fast_row(&part[p..], fast, &mut row) {
            for (col, v) in out.iter_mut().zip(&row) {
                col[ch.rows] = *v;
            }
            any_fast = true;
            ch.rows += 1;
            ch.last_data_line = number;
            number += 1;
            p += used;
            continue;
        }
        let end = memchr::memchr(b'\n', &part[p..]).map_or(part.len(), |i| p + i);
        let l = Line {
            number,
            text: strip_cr(&part[p..end]),
        };
        number += 1;
        p = end + 1;
        if !is_blank(l.text) && !general_row(l, c, &mut spans, &mut ch, out) {
            let s = shape(l.text, c.delimiter, &mut spans);
            // a data row is mostly numbers; a line that is not is a footer, comment or header
            let numeric = !s.fits(n) && mostly_numeric(l.text, &spans[..s.core], c.decimal_comma);
            ch.other.push(OtherLine {
                line: l.number,
                text: decode(l.text).into_owned(),
                wrong: numeric.then_some(if s.core > n { s.core } else { s.raw }),
                row: ch.rows,
            });
        }
    }
    if any_fast {
        ch.filled.iter_mut().for_each(|f| *f = true);
    }
    ch
}

/// A line the fast path did not take: stored as the chunk's next row when it fits the table
/// and its non-empty fields are mostly numbers (empty or text cells are recorded in `bad`);
/// `false` when it is not a data row.
fn general_row(
    l: Line,
    c: &Candidate,
    spans: &mut Vec<(usize, usize)>,
    ch: &mut Chunk,
    out: &mut [&mut [f64]],
) -> bool {
    let n = c.fields;
    if !shape(l.text, c.delimiter, spans).fits(n)
        || !mostly_numeric(l.text, &spans[..n], c.decimal_comma)
    {
        return false;
    }
    for (col, &(a, b)) in spans[..n].iter().enumerate() {
        let field = &l.text[a..b];
        let v = parse_number(field, c.decimal_comma);
        ch.filled[col] |= !trim(field).is_empty();
        if v.is_none() && ch.bad[col].is_none() {
            ch.bad[col] = Some((l.number, String::from_utf8_lossy(field).to_string()));
        }
        out[col][ch.rows] = v.unwrap_or(f64::NAN);
    }
    ch.rows += 1;
    ch.last_data_line = l.number;
    true
}

/// Parse the chunks `bounds` of `data` in parallel straight into one vector per column:
/// chunk k writes its rows into its own slice of `room[k]` slots (a data row is a line, so
/// they fit); rows are then moved down over the slots of lines that were not data (blank,
/// footer), and the columns cut to the rows found. No per-chunk vectors, no concatenation.
fn parse_chunks(
    data: &[u8],
    bounds: &[usize],
    first_line: &[u64],
    room: &[usize],
    c: &Candidate,
) -> std::result::Result<(Vec<Vec<f64>>, Vec<Chunk>), String> {
    let total: usize = room.iter().sum();
    // zeroed allocations: pages are touched first by the thread that parses into them
    let mut columns: Vec<Vec<f64>> = (0..c.fields)
        .map(|_| crate::bulk::zeroed_values(total))
        .collect::<std::result::Result<_, _>>()
        .map_err(|m| {
            format!(
                "the table's {} columns of up to {total} rows: {m} for each (raise the memory limit or split the recording)",
                c.fields
            )
        })?;
    let mut slices: Vec<Vec<&mut [f64]>> =
        room.iter().map(|_| Vec::with_capacity(c.fields)).collect();
    for col in columns.iter_mut() {
        let mut rest: &mut [f64] = col.as_mut_slice();
        for (k, &len) in room.iter().enumerate() {
            let (mine, after) = std::mem::take(&mut rest).split_at_mut(len);
            slices[k].push(mine);
            rest = after;
        }
    }
    let chunks: Vec<Chunk> = slices
        .into_par_iter()
        .zip(bounds.par_windows(2))
        .zip(first_line.par_iter())
        .map(|((mut out, w), &l0)| parse_chunk(&data[w[0]..w[1]], l0, c, &mut out))
        .collect();
    for col in columns.iter_mut() {
        let (mut from, mut to) = (0, 0);
        for (ch, &len) in chunks.iter().zip(room) {
            if from != to {
                col.copy_within(from..from + ch.rows, to);
            }
            from += len;
            to += ch.rows;
        }
        col.truncate(to);
    }
    Ok((columns, chunks))
}

/// Parse a text table from bytes (`source` names it in errors).
pub fn parse_text_table(bytes: &[u8], source: &str, opts: &TextOptions) -> Result<Table> {
    parse_in_chunks(bytes, source, opts, 1 << 20)
}

/// Whether the lines end in a bare CR (classic Mac OS): a CR in the first line (up to the first
/// LF, so a plain LF file is not scanned to its end) that is not followed by LF.
fn bare_cr(body: &[u8]) -> bool {
    let first = memchr::memchr(b'\n', body).unwrap_or(body.len());
    memchr::memchr(b'\r', &body[..first]).is_some_and(|i| body.get(i + 1) != Some(&b'\n'))
}

/// The body with every CR that is not followed by LF turned into LF.
fn cr_to_lf(body: &[u8]) -> Vec<u8> {
    let mut out = body.to_vec();
    for i in memchr::memchr_iter(b'\r', body) {
        if body.get(i + 1) != Some(&b'\n') {
            out[i] = b'\n';
        }
    }
    out
}

/// [`parse_text_table`] with data chunks of at least `min_chunk` bytes (tests use tiny ones).
fn parse_in_chunks(
    bytes: &[u8],
    source: &str,
    opts: &TextOptions,
    min_chunk: usize,
) -> Result<Table> {
    if bytes.starts_with(&[0xFF, 0xFE]) || bytes.starts_with(&[0xFE, 0xFF]) {
        return Err(Error::input(
            SourcePos::file(source),
            "the file is UTF-16 encoded: save it as UTF-8 (or ASCII) text",
        ));
    }
    let bom = bytes.starts_with(&[0xEF, 0xBB, 0xBF]);
    let body = if bom { &bytes[3..] } else { bytes };
    let cr = bare_cr(body);
    let lf_body;
    let body = if cr {
        lf_body = cr_to_lf(body);
        &lf_body[..]
    } else {
        body
    };
    let crlf = memchr::memchr(b'\n', body).is_some_and(|i| i > 0 && body[i - 1] == b'\r');
    check_head_line_lengths(body, source)?;
    let head = head_lines(body);
    let c = choose_layout(&head, opts, source)?;
    let Header { key, names, line } = resolve_header(&head, &c, source)?;
    if let (Some(units), Some(u)) = (key.units.as_deref(), c.units) {
        check_units_row(&names, units, head[u].number, source)?;
    }
    let preamble: Vec<String> = head[..c.header.unwrap_or(c.data)]
        .iter()
        .filter(|l| !is_blank(l.text))
        .map(|l| decode(l.text).trim().to_string())
        .collect();
    let (columns_data, chunks) = parse_data(body, &head[c.data], &c, min_chunk)
        .map_err(|m| Error::input(SourcePos::file(source), m))?;
    let regions = assemble(&chunks, &c, &key, line, source)?;
    let rows: usize = chunks.iter().map(|ch| ch.rows).sum();
    let built = build_columns(&names, key.units.as_deref(), columns_data, &chunks);
    let mut block_preambles = regions.block_preambles;
    let mut block_starts = regions.block_starts;
    if !block_starts.is_empty() {
        block_starts.insert(0, 0);
        block_preambles.insert(0, preamble.clone());
    }
    let shape = shape(head[c.data].text, c.delimiter, &mut Vec::new());
    let layout = Layout {
        c: &c,
        trailing: shape.raw > c.fields,
        bom,
        crlf,
        cr,
        header_line: line,
        units_line: c.units.map(|u| head[u].number),
        preamble: preamble.len(),
        footer: regions.footer.len(),
        blocks: block_starts.len(),
    };
    Ok(Table {
        source: source.to_string(),
        columns: built.columns,
        rows,
        layout: layout.describe(),
        // a headerless table's "header" is the line above its data, so that line numbers
        // computed from it (header + 1 + row) stay right
        header_line: line.unwrap_or(head[c.data].number - 1),
        headerless: line.is_none(),
        preamble,
        footer: regions.footer,
        sample_interval_s: None,
        start_time_s: None,
        block_starts,
        block_preambles,
        positions: built.positions,
        notes: built.notes,
    })
}

/// Parse the data, from its first line to the end of `body`, in chunks split at line ends.
fn parse_data(
    body: &[u8],
    first: &Line,
    c: &Candidate,
    min_chunk: usize,
) -> std::result::Result<(Vec<Vec<f64>>, Vec<Chunk>), String> {
    let data_start = first.text.as_ptr() as usize - body.as_ptr() as usize;
    let data = &body[data_start..];
    let threads = rayon::current_num_threads().max(1);
    let bounds = chunk_bounds(data, (data.len() / (4 * threads)).max(min_chunk.max(1)));
    // line ends per chunk: the first line number of each, and room for every line
    let newlines: Vec<usize> = bounds
        .par_windows(2)
        .map(|w| memchr::memchr_iter(b'\n', &data[w[0]..w[1]]).count())
        .collect();
    let first_line: Vec<u64> = newlines
        .iter()
        .scan(first.number, |acc, n| {
            let first = *acc;
            *acc += *n as u64;
            Some(first)
        })
        .collect();
    let mut room = newlines;
    if let Some(last) = room.last_mut() {
        *last += usize::from(!data.ends_with(b"\n"));
    }
    parse_chunks(data, &bounds, &first_line, &room, c)
}

/// Refuses a head line (one of the first [`SNIFF_LINES`]) longer than the budget
/// `max_line_bytes`, looking no further than the cap for each line end: a file of gigabytes
/// without a newline fails at once instead of being sniffed as one line.
fn check_head_line_lengths(body: &[u8], source: &str) -> Result<()> {
    let cap = greybox_core::budget::Cap::LineBytes;
    let window = usize::try_from(cap.limit())
        .unwrap_or(usize::MAX)
        .saturating_add(1);
    let mut pos = 0;
    for number in 1..=SNIFF_LINES as u64 {
        if pos >= body.len() {
            break;
        }
        let part = &body[pos..body.len().min(pos.saturating_add(window))];
        let len = memchr::memchr(b'\n', part).unwrap_or(part.len());
        cap.check(len as u64, || {
            format!("line {number} is longer than {} bytes", len - 1)
        })
        .map_err(|m| Error::input(SourcePos::file(source).line(number), m))?;
        pos += len + 1;
    }
    Ok(())
}

/// The first [`SNIFF_LINES`] lines of the body, for sniffing.
fn head_lines(body: &[u8]) -> Vec<Line<'_>> {
    let mut head = Vec::with_capacity(SNIFF_LINES);
    let mut pos = 0;
    while head.len() < SNIFF_LINES && pos < body.len() {
        let end = memchr::memchr(b'\n', &body[pos..]).map_or(body.len(), |i| pos + i);
        head.push(Line {
            number: head.len() as u64 + 1,
            text: strip_cr(&body[pos..end]),
        });
        pos = end + 1;
    }
    head
}

/// What stands above the data: the header as written (names and units row, which every later
/// block repeats), one column name per field, and the header's line (`None`: a headerless
/// file, whose columns are named `#1`, `#2`, … by position).
struct Header {
    key: HeaderKey,
    names: Vec<String>,
    line: Option<u64>,
}

fn resolve_header(head: &[Line], c: &Candidate, source: &str) -> Result<Header> {
    let Some(h) = c.header else {
        return Ok(Header {
            key: HeaderKey {
                names: Vec::new(),
                units: None,
            },
            names: (1..=c.fields).map(|k| format!("#{k}")).collect(),
            line: None,
        });
    };
    Ok(Header {
        key: HeaderKey {
            names: header_names(head[h].text, c.delimiter),
            units: c.units.map(|u| header_names(head[u].text, c.delimiter)),
        },
        names: column_names(&head[h], c, source)?,
        line: Some(head[h].number),
    })
}

/// "header on line N", or "no header line" for a headerless file.
fn header_at(line: Option<u64>) -> String {
    line.map_or("no header line".to_string(), |h| {
        format!("header on line {h}")
    })
}

/// The header's column names, one per data field (an empty one named `column K`); an error
/// when the counts differ.
fn column_names(header: &Line, c: &Candidate, source: &str) -> Result<Vec<String>> {
    let mut names = header_names(header.text, c.delimiter);
    if names.len() != c.fields {
        return Err(Error::input(
            SourcePos::file(source).line(header.number),
            format!(
                "the header names {} columns but the data rows have {} ({}-delimited)",
                names.len(),
                c.fields,
                c.delimiter.name()
            ),
        ));
    }
    for (k, nm) in names.iter_mut().enumerate() {
        if nm.is_empty() {
            *nm = format!("column {}", k + 1);
        }
    }
    Ok(names)
}

/// Refuses a units row that contradicts the unit its column's header states (`Fz (kN)` over
/// `N`): which one is meant cannot be told, and taking either silently scales the column by
/// the ratio. The error names the file, the units row's line, the column and both units.
fn check_units_row(
    names: &[String],
    units: &[String],
    units_line: u64,
    source: &str,
) -> Result<()> {
    for (k, name) in names.iter().enumerate() {
        let (bare, Some(stated)) = crate::table::split_unit(name) else {
            continue;
        };
        let Some(row) = units.get(k).and_then(|u| unit_token(u)) else {
            continue;
        };
        if row != stated {
            return Err(Error::input(
                SourcePos::file(source).line(units_line),
                format!(
                    "column {} ('{bare}'): the header states the unit {stated} but the units row says {row}; \
                     correct one of them (or name the column's unit with `columns`)",
                    k + 1
                ),
            ));
        }
    }
    Ok(())
}

/// The columns of a text table, where they sit in the file, and notes on what was changed.
struct BuiltColumns {
    columns: Vec<Column>,
    positions: Vec<usize>,
    notes: Vec<String>,
}

/// The columns from their names, the units row (a unit for a header that states none) and the
/// parsed values. Columns without a single non-empty cell are dropped (noted); repeated
/// header names are told apart ([`mark_duplicates`]).
fn build_columns(
    names: &[String],
    units: Option<&[String]>,
    values: Vec<Vec<f64>>,
    chunks: &[Chunk],
) -> BuiltColumns {
    let mut out = BuiltColumns {
        columns: Vec::with_capacity(names.len()),
        positions: Vec::with_capacity(names.len()),
        notes: Vec::new(),
    };
    let mut dropped = Vec::new();
    for (k, (name, values)) in names.iter().zip(values).enumerate() {
        if !chunks.iter().any(|ch| ch.filled[k]) {
            dropped.push(name.as_str());
            continue;
        }
        let mut col = Column::numbers(name, Vec::new());
        if col.unit.is_none() {
            col.unit = units.and_then(|u| u.get(k)).and_then(|u| unit_token(u));
        }
        col.data = match chunks.iter().find_map(|ch| ch.bad[k].clone()) {
            Some((line, text)) => ColumnData::NotNumeric { line, text },
            None => ColumnData::Numbers(values),
        };
        out.columns.push(col);
        out.positions.push(k + 1);
    }
    if !dropped.is_empty() {
        out.notes.push(format!(
            "{} column(s) without a single value left out: {}",
            dropped.len(),
            dropped.join(", ")
        ));
    }
    mark_duplicates(&mut out.columns, &out.positions, &mut out.notes);
    out
}

/// Columns that share a header keep it (so a role mapped by that name takes the first), and
/// the second and later get `name #2`, `name #3`; a note names their positions.
fn mark_duplicates(columns: &mut [Column], positions: &[usize], notes: &mut Vec<String>) {
    for k in 0..columns.len() {
        let same: Vec<usize> = (k..columns.len())
            .filter(|&j| columns[j].header == columns[k].header)
            .collect();
        let first_time = !(0..k).any(|j| columns[j].header == columns[k].header);
        if same.len() < 2 || !first_time {
            continue;
        }
        for (i, &j) in same.iter().enumerate().skip(1) {
            columns[j].name = format!("{} #{}", columns[j].name, i + 1);
        }
        let at: Vec<String> = same.iter().map(|&j| positions[j].to_string()).collect();
        notes.push(format!(
            "{} columns are named '{}' (columns {}): the first answers to that name, the others are '{} #2'…",
            same.len(),
            columns[k].header,
            at.join(", "),
            columns[k].name
        ));
    }
}

/// The first block's header names and units row, which every later block repeats.
struct HeaderKey {
    names: Vec<String>,
    units: Option<Vec<String>>,
}

/// The non-data lines sorted out: the footer and the blocks after the first.
#[derive(Default)]
struct Regions {
    footer: Vec<(u64, String)>,
    /// Row where each block after the first begins.
    block_starts: Vec<usize>,
    /// The lines between the previous block's data and each block's header.
    block_preambles: Vec<Vec<String>>,
}

/// Sort the lines that are not data rows into regions (lines with no data row between them):
/// after the last data row, the footer; between data rows, a block's settings lines ending
/// in the first block's header (and units row). Anything else between data rows, and a
/// malformed row anywhere, is an error naming its line.
fn assemble(
    chunks: &[Chunk],
    c: &Candidate,
    key: &HeaderKey,
    header_line: Option<u64>,
    source: &str,
) -> Result<Regions> {
    let total: usize = chunks.iter().map(|ch| ch.rows).sum();
    let mut lines: Vec<(usize, &OtherLine)> = Vec::new();
    let mut offset = 0;
    for ch in chunks {
        lines.extend(ch.other.iter().map(|o| (offset + o.row, o)));
        offset += ch.rows;
    }
    let mut out = Regions::default();
    for region in lines.chunk_by(|a, b| a.0 == b.0) {
        let row = region[0].0;
        let region: Vec<&OtherLine> = region.iter().map(|r| r.1).collect();
        if let Some(bad) = region.iter().position(|o| o.wrong.is_some()) {
            return Err(region_error(&region[..=bad], c, key, header_line, source));
        }
        let trimmed = |ls: &[&OtherLine]| -> Vec<(u64, String)> {
            ls.iter()
                .map(|o| (o.line, o.text.trim().to_string()))
                .collect()
        };
        if row == total {
            out.footer = trimmed(&region);
            continue;
        }
        let Some(h) = block_header(&region, c.delimiter, key) else {
            return Err(region_error(&region, c, key, header_line, source));
        };
        // headers before the last one: blocks without a data row, kept (empty) so that the
        // blocks after them keep their numbers
        let (kl, mut start, mut i) = (key_lines(key), 0, 0);
        while i + kl <= h {
            // the lines start..i+kl end in a header (and units row) that starts at i
            if block_header(&region[start..i + kl], c.delimiter, key) == Some(i - start) {
                out.block_starts.push(row);
                out.block_preambles.push(
                    trimmed(&region[start..i])
                        .into_iter()
                        .map(|(_, t)| t)
                        .collect(),
                );
                start = i + kl;
                i = start;
            } else {
                i += 1;
            }
        }
        out.block_starts.push(row);
        out.block_preambles.push(
            trimmed(&region[start..h])
                .into_iter()
                .map(|(_, t)| t)
                .collect(),
        );
    }
    Ok(out)
}

/// Lines of a block's header: the names, and the units row if the first block has one.
fn key_lines(key: &HeaderKey) -> usize {
    1 + usize::from(key.units.is_some())
}

/// Where a region ends in the first block's header (and units row): the header's index.
fn block_header(region: &[&OtherLine], d: Delimiter, key: &HeaderKey) -> Option<usize> {
    let names = |o: &OtherLine| header_names(o.text.as_bytes(), d);
    let n = region.len();
    match &key.units {
        Some(u) => (n >= 2 && names(region[n - 2]) == key.names && names(region[n - 1]) == *u)
            .then_some(n - 2),
        None => (names(region[n - 1]) == key.names).then_some(n - 1),
    }
}

/// The error for a region that is neither footer nor block: a header that differs from the
/// first (the last header-like line), else the region's last line when it is a malformed row,
/// else its first line, which is not data.
fn region_error(
    region: &[&OtherLine],
    c: &Candidate,
    key: &HeaderKey,
    header_line: Option<u64>,
    source: &str,
) -> Error {
    let last = region[region.len() - 1];
    let header_like = region.iter().rev().find(|o| {
        let names = header_names(o.text.as_bytes(), c.delimiter);
        o.wrong.is_none()
            && !units_row(o.text.as_bytes(), c.delimiter)
            && names.iter().filter(|s| !s.is_empty()).count() >= 2
            && mostly_text(o.text.as_bytes(), c.delimiter, c.decimal_comma)
    });
    let (line, msg) = if let Some(o) = header_like {
        let names = header_names(o.text.as_bytes(), c.delimiter);
        let what = if key.names.is_empty() {
            "the file has no header line above its first data".to_string()
        } else if names == key.names {
            "its units row differs from the first block's (or is missing)".to_string()
        } else {
            format!(
                "its header differs from the first block's (line {}): first '{}', here '{}'",
                header_line.unwrap_or(0),
                clip(&key.names.join(", ")),
                clip(&names.join(", "))
            )
        };
        (o.line, format!("a new block of the table starts here, but {what}; every block must have the same columns"))
    } else if let Some(k) = last.wrong {
        let msg = format!(
            "malformed row: expected {} fields, found {k} ({}-delimited, {})",
            c.fields,
            c.delimiter.name(),
            header_at(header_line),
        );
        (last.line, msg)
    } else {
        let first = region[0];
        let msg = format!(
            "a line that is not data inside the data: '{}'",
            clip(first.text.trim())
        );
        (first.line, msg)
    };
    Error::input(SourcePos::file(source).line(line), msg)
}

/// Chunk boundaries of about `target` bytes, each after a line end.
fn chunk_bounds(data: &[u8], target: usize) -> Vec<usize> {
    let mut bounds = vec![0usize];
    while let Some(&last) = bounds.last().filter(|b| **b < data.len()) {
        let from = last + target;
        if from >= data.len() {
            bounds.push(data.len());
            break;
        }
        bounds.push(memchr::memchr(b'\n', &data[from..]).map_or(data.len(), |i| from + i + 1));
    }
    bounds
}

/// What [`Layout::describe`] puts in words.
struct Layout<'a> {
    c: &'a Candidate,
    trailing: bool,
    bom: bool,
    crlf: bool,
    cr: bool,
    header_line: Option<u64>,
    units_line: Option<u64>,
    preamble: usize,
    footer: usize,
    blocks: usize,
}

impl Layout<'_> {
    /// The layout in words, for reports: "semicolon-delimited, decimal comma, header on line 3, …".
    fn describe(&self) -> String {
        let mut layout = format!("{}-delimited", self.c.delimiter.name());
        for (on, what) in [
            (self.c.decimal_comma, "decimal comma"),
            (self.trailing, "trailing delimiter"),
            (self.bom, "UTF-8 BOM"),
            (self.crlf, "CRLF"),
            (self.cr, "CR line ends"),
        ] {
            if on {
                layout.push_str(", ");
                layout.push_str(what);
            }
        }
        layout.push_str(", ");
        layout.push_str(&header_at(self.header_line));
        if self.header_line.is_none() {
            layout.push_str(&format!(" (columns #1 to #{})", self.c.fields));
        }
        if let Some(u) = self.units_line {
            layout.push_str(&format!(", units row on line {u}"));
        }
        if self.preamble > 0 {
            layout.push_str(&format!(", {} preamble line(s)", self.preamble));
        }
        if self.blocks > 1 {
            layout.push_str(&format!(", {} blocks", self.blocks));
        }
        if self.footer > 0 {
            layout.push_str(&format!(", {} footer line(s)", self.footer));
        }
        layout
    }
}

fn clip(s: &str) -> String {
    if s.chars().count() > 60 {
        format!("{}…", s.chars().take(60).collect::<String>())
    } else {
        s.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Table> {
        parse_text_table(text.as_bytes(), "t.csv", &TextOptions::default())
    }
    fn col(t: &Table, k: usize) -> &[f64] {
        t.columns[k].values(&t.source).unwrap()
    }

    #[test]
    fn plain_csv() {
        let t = parse("time_s,normal_force_N\n0,1.5\n0.001,2.5\n0.002,3\n").unwrap();
        assert_eq!(t.rows, 3);
        assert_eq!(col(&t, 1), &[1.5, 2.5, 3.0]);
        assert_eq!(t.columns[0].unit.as_deref(), Some("s"));
        assert_eq!(t.header_line, 1);
    }

    #[test]
    fn preamble_trailing_delimiter_footer() {
        let text = "Instrument: RT,Serial 12\nTest: 2026-05-03 10:12,Operator: X\n\
                    Step, Time (s), DAQ.Fz (N), DAQ.Fx (N),\n1,0.0,10.0,4.0,\n1,0.1,10.1,4.1,\n\
                    2,0.0,10.2,4.2,\n2,0.1,10.3,4.3,\nEnd of data,\nTotal time: 250 s\n";
        let t = parse(text).unwrap();
        assert_eq!(t.header_line, 3);
        assert_eq!(t.columns.len(), 4);
        assert_eq!(t.columns[2].name, "DAQ.Fz");
        assert_eq!(col(&t, 3), &[4.0, 4.1, 4.2, 4.3]);
        assert_eq!(t.preamble.len(), 2);
        assert_eq!(t.footer.len(), 2);
        assert_eq!(t.footer[0].0, 8);
        assert!(t.layout.contains("trailing delimiter"), "{}", t.layout);
    }

    #[test]
    fn semicolon_decimal_comma_bom_crlf() {
        let text = "\u{feff}Zeit [s];Fn [kN];Ft/N\r\n0,000;0,2001;80,5\r\n0,002;0,2002;80,6\r\n0,004;0,2003;80,7\r\n";
        let t = parse(text).unwrap();
        assert_eq!(col(&t, 1), &[0.2001, 0.2002, 0.2003]);
        assert_eq!(col(&t, 2), &[80.5, 80.6, 80.7]);
        assert!(t.layout.contains("decimal comma") && t.layout.contains("BOM"));
        assert_eq!(t.columns[0].name, "Zeit");
    }

    #[test]
    fn tab_and_whitespace() {
        let t = parse("Fz_kN\tFx_N\tSpeed_mm/s\n0.4\t160\t500\n0.4\t161\t500\n0.4\t162\t501\n")
            .unwrap();
        assert_eq!(t.columns[2].unit.as_deref(), Some("mm/s"));
        assert_eq!(col(&t, 1), &[160.0, 161.0, 162.0]);
        let t = parse("Time  Normal force  Friction force\n0   10  4\n0.1 10  4.1\n0.2 10  4.2\n")
            .unwrap();
        assert_eq!(t.columns.len(), 3);
        assert_eq!(t.columns[1].name, "Normal force");
    }

    #[test]
    fn text_column_only_fails_when_used() {
        let t = parse("t_s,F_N,comment\n0,1,ok\n1,2,fine\n2,3,x\n").unwrap();
        assert_eq!(col(&t, 1), &[1.0, 2.0, 3.0]);
        let e = t.columns[2].values(&t.source).unwrap_err().to_string();
        assert!(
            e.contains("line 2") && e.contains("comment") && e.contains("'ok'"),
            "{e}"
        );
    }

    #[test]
    fn broken_rows_are_errors_with_lines() {
        let e = parse("t_s,F_N\n0,1\n1,2\n2\n3,4\n")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("line 4") && e.contains("expected 2 fields, found 1"),
            "{e}"
        );
        let e = parse("t_s,F_N\n0,1\n1,2\nsomething else here\n3,4\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 4") && e.contains("not data"), "{e}");
        let t = parse("t_s,F_N,G_N\n0,1,1\n1,abc,2\n2,3,3\n").unwrap();
        let e = t.columns[1].values(&t.source).unwrap_err().to_string();
        assert!(e.contains("line 3") && e.contains("'abc'"), "{e}");
        let e = parse("just some text\nno numbers\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("no table found"), "{e}");
        // numbers only are a headerless table (see `headerless_logs`), but numbers and
        // broken rows above the data are not
        let e = parse("t_s,F_N\n0,1\n1,abc\n2,3\n").unwrap_err().to_string();
        assert!(
            e.contains("line 4") && e.contains("not a header that names them"),
            "{e}"
        );
        // a header line that names fewer columns than the data has is not taken as comments
        let e = parse("time,force\n0,1,2\n1,2,3\n2,3,4\n")
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 2") && e.contains("3 columns"), "{e}");
    }

    /// DAQ and microcontroller logs without a header: comma, semicolon with decimal comma,
    /// tab and whitespace, with comment lines above; columns are `#1`, `#2`, …
    #[test]
    fn headerless_logs() {
        let cases = [
            ("0.00,12.1,3.4\n0.01,12.0,3.5\n0.02,12.2,3.6\n", "comma"),
            (
                "0,00;12,1;3,4\r\n0,01;12,0;3,5\r\n0,02;12,2;3,6\r\n",
                "semicolon",
            ),
            (
                "# logger v2\n\n0.00\t12.1\t3.4\n0.01\t12.0\t3.5\n0.02\t12.2\t3.6\n",
                "tab",
            ),
            (
                "  0.00  12.1  3.4\n  0.01  12.0  3.5\n  0.02  12.2  3.6\n",
                "whitespace",
            ),
        ];
        for (text, delim) in cases {
            let t = parse(text).unwrap();
            assert!(t.headerless, "{delim}");
            let names: Vec<&str> = t.columns.iter().map(|c| c.name.as_str()).collect();
            assert_eq!(names, ["#1", "#2", "#3"], "{delim}");
            assert_eq!(col(&t, 0), &[0.0, 0.01, 0.02], "{delim}");
            assert_eq!(col(&t, 2), &[3.4, 3.5, 3.6], "{delim}");
            assert!(t.layout.starts_with(delim), "{}", t.layout);
            assert!(
                t.layout.contains("no header line (columns #1 to #3)"),
                "{}",
                t.layout
            );
            // the "header" is the line above the data, so header + 1 + row is the row's line
            assert_eq!(t.header_line + 1, if delim == "tab" { 3 } else { 1 });
        }
        let t = parse("# logger v2\n0.00\t12.1\t3.4\n0.01\t12.0\t3.5\n").unwrap();
        assert_eq!(t.preamble, ["# logger v2"]);
        // a malformed row names the line and that there is no header
        let e = parse("1,2\n3,4\n5\n6,7\n").unwrap_err().to_string();
        assert!(e.contains("line 3") && e.contains("no header line"), "{e}");
    }

    /// A forced header line is taken even where sniffing would choose another layout, and a
    /// forced line that is no header is an error naming it, never ignored.
    #[test]
    fn forced_header_is_never_ignored() {
        let opts = |h| TextOptions {
            header_line: Some(h),
            ..Default::default()
        };
        let text = "Time,Fn,Ft\n0,1,2\n1,2,3\n2,3,4\n";
        let t = parse_text_table(text.as_bytes(), "t.csv", &opts(1)).unwrap();
        assert_eq!(t.header_line, 1);
        assert!(!t.headerless);
        assert_eq!(t.columns[2].name, "Ft");
        // a header of channel numbers, which sniffing takes for data, is the header when forced
        let t = parse_text_table(b"0,1,2\n1,2,3\n2,3,4\n", "t.csv", &opts(1)).unwrap();
        assert!(!t.headerless);
        assert_eq!(t.rows, 2);
        assert_eq!(t.columns[1].name, "1");
        assert_eq!(col(&t, 1), &[2.0, 3.0]);
        let t = parse_text_table(b"0,1,2\n1,2,3\n2,3,4\n", "t.csv", &TextOptions::default());
        assert!(t.unwrap().headerless);
        // a forced header naming another number of columns is an error naming its line
        let e = parse_text_table(b"a,b\n1,2,3\n2,3,4\n", "t.csv", &opts(1))
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 1") && e.contains("names 2 columns"), "{e}");
    }

    /// Quotes protect delimiters in headers and in data fields; a quoted `"1,5"` in a
    /// comma-delimited file is a decimal comma.
    #[test]
    fn quoted_fields_with_delimiters() {
        let text = "\"Time, s\",\"Load, N\",\"Friction, N\"\n\"0,0\",\"10,5\",\"1,5\"\n\"0,1\",\"10,5\",\"1,25\"\n0.2,10.5,\"1,0\"\n";
        let t = parse(text).unwrap();
        assert_eq!(t.columns.len(), 3);
        assert_eq!(t.columns[1].header, "Load, N");
        assert_eq!(col(&t, 0), &[0.0, 0.1, 0.2]);
        assert_eq!(col(&t, 2), &[1.5, 1.25, 1.0]);
        // two commas in quotes are no number, nor a comma that may separate thousands
        for bad in ["\"1,234,5\"", "\"1,234\"", "\"-12,500\"", "\"999,000\""] {
            assert_eq!(parse_number(bad.as_bytes(), false), None, "{bad}");
        }
        for (good, v) in [
            ("\"0,125\"", 0.125),
            ("\"12,25\"", 12.25),
            ("\"1234,500\"", 1234.5),
        ] {
            assert_eq!(parse_number(good.as_bytes(), false), Some(v), "{good}");
        }
        // with the file's decimal comma, the same field is a decimal
        assert_eq!(parse_number(b"\"1,234\"", true), Some(1.234));
    }

    /// Header bytes that are not UTF-8 are Latin-1: `µm` written as 0xB5 keeps its unit.
    #[test]
    fn latin1_header() {
        let mut bytes = b"t (s);Pos (".to_vec();
        bytes.push(0xB5);
        bytes.extend_from_slice(b"m);Fz (N)\n0;1;2\n1;2;3\n2;3;4\n");
        let t = parse_text_table(&bytes, "t.csv", &TextOptions::default()).unwrap();
        assert_eq!(t.columns[1].unit.as_deref(), Some("µm"));
    }

    #[test]
    fn forced_header_line() {
        let text = "a,b\n1,2\nx_s,y_N\n0,1\n1,2\n2,3\n";
        let t = parse_text_table(
            text.as_bytes(),
            "t.csv",
            &TextOptions {
                header_line: Some(3),
                ..Default::default()
            },
        )
        .unwrap();
        assert_eq!(t.columns[0].name, "x");
        assert_eq!(t.rows, 3);
    }

    #[test]
    fn same_result_in_many_chunks() {
        let mut text = String::from("time_s,F_N\n");
        for i in 0..200_000 {
            text.push_str(&format!("{},{}\n", i as f64 * 1e-3, (i % 97) as f64 * 0.5));
        }
        let t = parse(&text).unwrap();
        assert_eq!(t.rows, 200_000);
        assert_eq!(col(&t, 1)[199_999], (199_999 % 97) as f64 * 0.5);
        assert!(t.footer.is_empty());
    }

    /// Tiny chunks, blank lines, rows only the general path reads (quoted, padded, exponent
    /// with a decimal comma) and a footer: every chunking gives the one-chunk table.
    #[test]
    fn chunk_boundaries_blank_lines_and_slow_rows() {
        let mut text = String::from("Messung 7\n\nt [s];Fz [N];Fx [N];\n");
        for i in 0..3_000 {
            let row = match i % 11 {
                0 => format!("\"{},{:03}\";\"{}\";1,5e2;\n", i / 1000, i % 1000, i % 7),
                3 => format!(" {},{:03} ; {} ;-0,25;\r\n", i / 1000, i % 1000, i % 5),
                5 => "\n".to_string(),
                _ => format!("{},{:03};{};{},5;\n", i / 1000, i % 1000, i % 13, i % 3),
            };
            text.push_str(&row);
        }
        text.push_str("Ende der Messung\n");
        let one =
            parse_in_chunks(text.as_bytes(), "t", &TextOptions::default(), usize::MAX).unwrap();
        assert_eq!(one.rows, 3_000 - 3_000 / 11 - 1);
        assert_eq!(one.footer.len(), 1);
        assert!(one.layout.contains("decimal comma"), "{}", one.layout);
        for min_chunk in [1, 7, 64, 1000] {
            let t =
                parse_in_chunks(text.as_bytes(), "t", &TextOptions::default(), min_chunk).unwrap();
            assert_eq!(t.rows, one.rows);
            assert_eq!(t.footer, one.footer);
            for k in 0..3 {
                assert_eq!(
                    col(&t, k),
                    col(&one, k),
                    "column {k}, chunks of {min_chunk} B"
                );
            }
        }
        assert_eq!(col(&one, 0)[0], 0.0);
        assert_eq!(col(&one, 2)[0], 150.0);
        assert_eq!(col(&one, 2)[3], -0.25);
        assert_eq!(col(&one, 1)[1], 1.0);
    }

    #[test]
    fn units_row_under_the_header() {
        let t = parse("Time,Fz,Fx,COF,Speed,Temp\ns,(N),gf,-,[mm/s],°C\n0,1,2,0.1,5,20\n1,1,2,0.1,5,20\n2,1,2,0.2,5,21\n")
            .unwrap();
        assert_eq!(t.rows, 3);
        let units: Vec<Option<&str>> = t.columns.iter().map(|c| c.unit.as_deref()).collect();
        assert_eq!(
            units,
            [
                Some("s"),
                Some("N"),
                Some("gf"),
                Some("-"),
                Some("mm/s"),
                Some("°C")
            ]
        );
        assert_eq!(t.header_line, 1);
        assert!(t.layout.contains("units row on line 2"), "{}", t.layout);
        // an empty unit, and a header that states its own unit, the same as the units row's
        let t = parse("Instrument X\n\nt;Fz (kN);Step\ns;kN;\n0;1;1\n1;2;1\n2;3;2\n").unwrap();
        assert_eq!(t.columns[0].unit.as_deref(), Some("s"));
        assert_eq!(t.columns[1].unit.as_deref(), Some("kN"));
        assert_eq!(t.columns[2].unit, None);
        assert_eq!(t.preamble, ["Instrument X"]);
        // a units row that contradicts the header is refused with both units and its line
        let e = parse("Instrument X\n\nt;Fz (kN);Step\ns;N;\n0;1;1\n1;2;1\n2;3;2\n")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("line 4") && e.contains("Fz") && e.contains("kN") && e.contains("says N"),
            "{e}"
        );
        // a text row of non-units above the data is the header, not units
        let t = parse("Instrument X,Serial 12\nTime,Force\n0,1\n1,2\n").unwrap();
        assert_eq!(t.columns[1].name, "Force");
        assert_eq!(t.preamble.len(), 1);
    }

    #[test]
    fn sparse_tab_rows_empty_names_and_duplicates() {
        let mut text = String::from("Test data\nt (s)\tF (N)\t\t\tF (N)\tLoad (N)\tv\n");
        for i in 0..5 {
            text.push_str(&format!(
                "{i}\t{}.5\t\t\t{}.5\t\t{}\t\t\n",
                i + 1,
                i + 1,
                2 * i
            ));
        }
        text.push_str("\nEnd of test\n");
        let t = parse(&text).unwrap();
        assert_eq!(t.rows, 5);
        // the two empty-named columns and the empty `Load` column are left out
        let names: Vec<&str> = t.columns.iter().map(|c| c.name.as_str()).collect();
        assert_eq!(names, ["t", "F", "F #2", "v"]);
        assert_eq!(t.columns[2].header, "F (N)");
        assert_eq!(t.positions, [1, 2, 5, 7]);
        assert_eq!(col(&t, 2), &[1.5, 2.5, 3.5, 4.5, 5.5]);
        assert_eq!(col(&t, 3), &[0.0, 2.0, 4.0, 6.0, 8.0]);
        assert_eq!(t.column_label(1), "column 2, the first of 2 with that name");
        assert_eq!(
            t.column_label(2),
            "column 5, the second of 2 with that name"
        );
        assert_eq!(t.column_label(3), "column 7");
        assert!(
            t.notes
                .iter()
                .any(|n| n.contains("column 3, column 4, Load (N)")),
            "{:?}",
            t.notes
        );
        assert_eq!(t.footer.len(), 1);
        // a column with some empty cells is kept and fails only when used
        let t = parse("a\tb\tc\n1\t2\t3\n2\t\t4\n3\t5\t6\n").unwrap();
        let e = t.columns[1].values(&t.source).unwrap_err().to_string();
        assert!(e.contains("line 3") && e.contains("empty field"), "{e}");
        assert_eq!(col(&t, 2), &[3.0, 4.0, 6.0]);
    }

    fn blocks_text(blocks: usize, header2: &str) -> String {
        let mut text = String::from("Rig 7\nProfile: stepped\n");
        for b in 0..blocks {
            text.push_str(&format!(
                "\nStep {} started\nLoad setpoint,{}\n",
                b + 1,
                10 * (b + 1)
            ));
            text.push_str(if b == 1 { header2 } else { "Time,Fz,Fx" });
            text.push_str("\ns,N,N\n");
            for i in 0..4 {
                text.push_str(&format!("{i},{},{}.5\n", 10 * (b + 1), b * 10 + i));
            }
        }
        text.push_str("\nTest completed\n");
        text
    }

    #[test]
    fn blocks_with_settings_units_and_time_restarting() {
        for blocks in [2, 3] {
            let text = blocks_text(blocks, "Time,Fz,Fx");
            for min_chunk in [1, 16, usize::MAX] {
                let t =
                    parse_in_chunks(text.as_bytes(), "b.csv", &TextOptions::default(), min_chunk)
                        .unwrap();
                assert_eq!(t.rows, 4 * blocks);
                let starts: Vec<usize> = (0..blocks).map(|b| 4 * b).collect();
                assert_eq!(t.block_starts, starts);
                assert_eq!(t.block_preambles.len(), blocks);
                assert_eq!(t.block_preambles[1], ["Step 2 started", "Load setpoint,20"]);
                assert_eq!(t.block_preambles[0], t.preamble);
                assert_eq!(&col(&t, 0)[..5], &[0.0, 1.0, 2.0, 3.0, 0.0]);
                assert_eq!(col(&t, 1)[4 * blocks - 1], 10.0 * blocks as f64);
                assert_eq!(t.columns[1].unit.as_deref(), Some("N"));
                assert_eq!(t.footer.len(), 1);
                assert_eq!(t.block_of_row(5), 1);
                assert!(
                    t.layout.contains(&format!("{blocks} blocks")),
                    "{}",
                    t.layout
                );
            }
        }
        // a single table has no blocks
        let t = parse("Time,Fz\n0,1\n1,2\n").unwrap();
        assert!(t.block_starts.is_empty() && t.block_preambles.is_empty());
        assert_eq!(t.block_of_row(1), 0);
    }

    /// A block with a header but no data row keeps its place: the blocks after it keep their
    /// numbers (issue 46 item 5: an empty block renumbered the rest).
    #[test]
    fn an_empty_block_keeps_its_place() {
        let full = blocks_text(3, "Time,Fz,Fx");
        // block 2's rows removed: its settings and header stand right above block 3's
        let text: String = full
            .lines()
            .filter(|l| !(l.starts_with(|c: char| c.is_ascii_digit()) && l.contains(",20,")))
            .map(|l| format!("{l}\n"))
            .collect();
        for min_chunk in [1, 16, usize::MAX] {
            let t = parse_in_chunks(text.as_bytes(), "b.csv", &TextOptions::default(), min_chunk)
                .unwrap();
            assert_eq!(t.rows, 8);
            assert_eq!(t.block_starts, [0, 4, 4]);
            assert_eq!(t.block_preambles[1], ["Step 2 started", "Load setpoint,20"]);
            assert_eq!(t.block_preambles[2], ["Step 3 started", "Load setpoint,30"]);
            assert_eq!(t.block_of_row(4), 2);
        }
    }

    #[test]
    fn block_with_another_header_is_refused() {
        // same field count, other names
        let e = parse(&blocks_text(3, "Time,Fn,Ft"))
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("line 15") && e.contains("'Time, Fz, Fx'") && e.contains("'Time, Fn, Ft'"),
            "{e}"
        );
        // another field count: its rows are malformed, the header is named
        let e = parse(&blocks_text(2, "Time,Fz")).unwrap_err().to_string();
        assert!(e.contains("line 15") && e.contains("'Time, Fz'"), "{e}");
        // the same header with other units
        let text = blocks_text(2, "Time,Fz,Fx")
            .replacen("s,N,N", "s,kN,N", 2)
            .replacen("s,kN,N", "s,N,N", 1);
        let e = parse(&text).unwrap_err().to_string();
        assert!(
            e.contains("line 15") && e.contains("units row differs"),
            "{e}"
        );
    }

    #[test]
    fn bare_cr_and_semicolon_fixed_width_with_extra_delimiter() {
        let text = "          TIME;          FF;\r        0,9800;      2,41;;\r        1,9610;      7,99;;\r        2,9390;     14,03;;\r";
        let t = parse(text).unwrap();
        assert_eq!(t.rows, 3);
        assert_eq!(t.columns.len(), 2);
        assert_eq!(t.columns[0].name, "TIME");
        assert_eq!(col(&t, 0), &[0.98, 1.961, 2.939]);
        assert_eq!(col(&t, 1), &[2.41, 7.99, 14.03]);
        assert!(
            t.layout.contains("CR line ends") && t.layout.contains("decimal comma"),
            "{}",
            t.layout
        );
        // the same with LF and CRLF line ends reads the same
        for end in ["\n", "\r\n"] {
            let u = parse(&text.replace('\r', end)).unwrap();
            assert_eq!(u.columns, t.columns);
        }
        // line numbers in errors count CR line ends
        let e = parse("t;F\r0;1\r1;2\r2\r3;4\r").unwrap_err().to_string();
        assert!(e.contains("line 4"), "{e}");
    }
}
