//! Delimited text tables as rigs export them (CSV, TXT, DAT, TSV), dialect found from the file.
//!
//! What is sniffed from the first lines: a UTF-8 byte-order mark, CRLF or LF line ends, the
//! delimiter (tab, semicolon, comma or runs of whitespace), decimal commas, the header line
//! below any preamble (the last line above the first run of numeric rows that has as many
//! fields), and a trailing delimiter on every line. Lines after the data that are not data
//! (an `End of data` or a summary) are the footer: reported, not an error. A non-numeric cell
//! inside the data only matters when a role is mapped to its column
//! ([`crate::table::ColumnData::NotNumeric`]).
//!
//! The data lines are parsed in parallel chunks (rayon) straight from the memory-mapped file
//! into the final columns: plain decimals exactly by [`crate::decimal`], other numbers with
//! `fast-float2`. The result does not depend on the number of threads.

use crate::table::{Column, ColumnData, Table};
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
    /// 1-based line of the header (default: found automatically).
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
/// A regular file is memory-mapped (no copy of a file of hundreds of MB into a buffer); the
/// file must not be truncated while it is read, as with any reader that maps files. Anything
/// else (a pipe, an empty file, a file system without mmap) is read into memory.
pub fn read_text_table(path: &std::path::Path, opts: &TextOptions) -> Result<Table> {
    let source = path.display().to_string();
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    let regular = file.metadata().is_ok_and(|m| m.is_file() && m.len() > 0);
    if regular {
        // SAFETY: the map is read-only and lives only for this call. Like every reader that
        // maps files (ripgrep, polars), this relies on no other process truncating or
        // rewriting the recording while it is parsed, as the doc comment states.
        if let Ok(map) = unsafe { memmap2::Mmap::map(&file) } {
            return parse_text_table(&map, &source, opts);
        }
    }
    let mut bytes = Vec::new();
    std::io::Read::read_to_end(&mut &file, &mut bytes).map_err(|e| Error::io(path, e))?;
    parse_text_table(&bytes, &source, opts)
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

/// Split a line into fields (no quoting rules: numeric data has none; see [`split_header`]).
fn split_fields(line: &[u8], d: Delimiter, out: &mut Vec<(usize, usize)>) {
    out.clear();
    match d.byte() {
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

/// Parse a number; with `decimal_comma`, `,` is the decimal mark. `None` for anything else
/// (including NaN and infinities, which a recording never legitimately holds).
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
    let v = if decimal_comma && memchr::memchr(b',', t).is_some() {
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

/// Split a header line into names; double quotes may protect delimiters inside a name.
fn split_header(line: &str, d: Delimiter) -> Vec<String> {
    if d == Delimiter::Whitespace {
        // names with single spaces ("Normal force") are separated by two or more spaces or tabs
        let by_wide: Vec<String> = line
            .split('\t')
            .flat_map(|p| p.split("  "))
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .map(str::to_string)
            .collect();
        return by_wide;
    }
    let delim = d.byte().map(char::from).unwrap_or(',');
    let mut out = Vec::new();
    let mut cur = String::new();
    let mut quoted = false;
    for c in line.chars() {
        match c {
            '"' => quoted = !quoted,
            c if c == delim && !quoted => out.push(std::mem::take(&mut cur)),
            c => cur.push(c),
        }
    }
    out.push(cur);
    out.into_iter().map(|s| s.trim().to_string()).collect()
}

/// Fields of a line with a trailing empty field dropped (a trailing delimiter).
fn field_count(line: &[u8], d: Delimiter, spans: &mut Vec<(usize, usize)>) -> (usize, bool) {
    split_fields(line, d, spans);
    let mut n = spans.len();
    let trailing = n > 1 && trim(&line[spans[n - 1].0..spans[n - 1].1]).is_empty();
    if trailing {
        n -= 1;
    }
    (n, trailing)
}

/// At least two fields, and at least half of them, are numbers (a date or comment column
/// may sit beside the numbers).
fn mostly_numeric(line: &[u8], spans: &[(usize, usize)], dc: bool) -> bool {
    let numbers = spans
        .iter()
        .filter(|&&(a, b)| parse_number(&line[a..b], dc).is_some())
        .count();
    numbers >= 2.min(spans.len()) && numbers > 0 && 2 * numbers >= spans.len()
}

/// Fewer than half of the fields are numbers (a header may have a numeric name or two).
fn mostly_text(line: &[u8], d: Delimiter, dc: bool) -> bool {
    let mut spans = Vec::new();
    let (n, _) = field_count(line, d, &mut spans);
    let numbers = spans[..n]
        .iter()
        .filter(|&&(a, b)| parse_number(&line[a..b], dc).is_some())
        .count();
    2 * numbers < n.max(1) || n == 1
}

/// The field count of a row of (mostly) numbers, with `decimal_comma` deciding the mark.
fn numeric_row(
    line: &[u8],
    d: Delimiter,
    dc: bool,
    spans: &mut Vec<(usize, usize)>,
) -> Option<usize> {
    let (n, _) = field_count(line, d, spans);
    (n > 0 && mostly_numeric(line, &spans[..n], dc)).then_some(n)
}

/// The layout found for one delimiter.
#[derive(Debug, Clone, Copy)]
struct Candidate {
    delimiter: Delimiter,
    decimal_comma: bool,
    /// Index into the sniffed lines of the header (None: no header line).
    header: Option<usize>,
    /// Index of the first data line.
    data: usize,
    fields: usize,
    /// Every field of the first data row is a number.
    all_numeric: bool,
}

/// Find header and data start for one delimiter among the first lines.
fn sniff(
    lines: &[Line],
    d: Delimiter,
    dc: bool,
    forced_header: Option<usize>,
) -> Option<Candidate> {
    let mut spans = Vec::new();
    let numeric: Vec<Option<usize>> = lines
        .iter()
        .map(|l| numeric_row(l.text, d, dc, &mut spans))
        .collect();
    let confirmed = |i: usize| -> Option<usize> {
        let n = numeric[i]?;
        if n < 2 {
            return None;
        }
        // at least two rows of as many numbers (one if the file ends there)
        let mut k = 0;
        let mut ended = true;
        for (j, l) in lines.iter().enumerate().skip(i) {
            if is_blank(l.text) {
                continue;
            }
            if numeric[j] != Some(n) {
                ended = false;
                break;
            }
            k += 1;
            if k == CONFIRM_ROWS {
                break;
            }
        }
        (k >= 2 || (k == 1 && ended)).then_some(n)
    };
    let start = forced_header.map_or(0, |h| h + 1);
    let data = (start..lines.len()).find(|&i| confirmed(i).is_some())?;
    let fields = confirmed(data)?;
    let header = match forced_header {
        Some(h) => Some(h),
        None => (0..data).rev().find(|&i| !is_blank(lines[i].text)),
    };
    // the header must name as many columns as the data has, and not be numbers itself
    let header = header.filter(|&h| {
        if numeric[h].is_some() || !mostly_text(lines[h].text, d, dc) {
            return false;
        }
        let text = String::from_utf8_lossy(lines[h].text);
        let mut names = split_header(&text, d);
        if names.len() > fields && names.last().is_some_and(|s| s.is_empty()) {
            names.pop();
        }
        names.len() == fields || forced_header.is_some()
    });
    field_count(lines[data].text, d, &mut spans);
    let all_numeric = spans[..fields]
        .iter()
        .all(|&(a, b)| parse_number(&lines[data].text[a..b], dc).is_some());
    Some(Candidate {
        delimiter: d,
        decimal_comma: dc,
        header,
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
                format!("--header-line {h}: the file has only {} lines", lines.len()),
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
    if c.header.is_none() {
        return Err(Error::input(
            SourcePos::file(source).line(lines[c.data].number),
            format!(
                "found {}-delimited numeric data from line {} but no header line above it that names its {} columns; give --header-line N",
                c.delimiter.name(),
                lines[c.data].number,
                c.fields
            ),
        ));
    }
    Ok(c)
}

/// One parsed chunk of data lines.
struct Chunk {
    /// Data rows written to the front of the chunk's column slices.
    rows: usize,
    /// First non-number per column: (line, text).
    bad: Vec<Option<(u64, String)>>,
    /// Lines that are not data rows: (line, text, wrong field count).
    other: Vec<(u64, String, Option<usize>)>,
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
        other: Vec::new(),
        last_data_line: 0,
    };
    let mut spans = Vec::with_capacity(n + 1);
    let mut values: Vec<Option<f64>> = Vec::with_capacity(n);
    let mut row = vec![0.0; n];
    let fast = FastLayout::of(c);
    let mut p = 0;
    let mut number = first_line;
    while p < part.len() {
        if let Some(used) = fast_row(&part[p..], fast, &mut row) {
            for (col, v) in out.iter_mut().zip(&row) {
                col[ch.rows] = *v;
            }
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
        if is_blank(l.text) {
            continue;
        }
        let (k, _) = field_count(l.text, c.delimiter, &mut spans);
        if k != n {
            // a data row is mostly numbers; a line that is not is a footer or comment
            let numeric = mostly_numeric(l.text, &spans[..k], c.decimal_comma);
            ch.other.push((
                l.number,
                String::from_utf8_lossy(l.text).trim().to_string(),
                numeric.then_some(k),
            ));
            continue;
        }
        values.clear();
        values.extend(
            spans[..n]
                .iter()
                .map(|&(a, b)| parse_number(&l.text[a..b], c.decimal_comma)),
        );
        let numbers = values.iter().filter(|v| v.is_some()).count();
        if numbers < n && !(numbers >= 2.min(n) && 2 * numbers >= n) {
            ch.other.push((
                l.number,
                String::from_utf8_lossy(l.text).trim().to_string(),
                None,
            ));
            continue;
        }
        for (col, v) in values.iter().enumerate() {
            if v.is_none() && ch.bad[col].is_none() {
                let (a, b) = spans[col];
                ch.bad[col] = Some((l.number, String::from_utf8_lossy(&l.text[a..b]).to_string()));
            }
            out[col][ch.rows] = v.unwrap_or(f64::NAN);
        }
        ch.rows += 1;
        ch.last_data_line = l.number;
    }
    ch
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
) -> (Vec<Vec<f64>>, Vec<Chunk>) {
    let total: usize = room.iter().sum();
    // zeroed allocations: pages are touched first by the thread that parses into them
    let mut columns: Vec<Vec<f64>> = (0..c.fields)
        .map(|_| crate::bulk::zeroed_values(total))
        .collect();
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
    (columns, chunks)
}

/// Parse a text table from bytes (`source` names it in errors).
pub fn parse_text_table(bytes: &[u8], source: &str, opts: &TextOptions) -> Result<Table> {
    parse_in_chunks(bytes, source, opts, 1 << 20)
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
    let crlf = memchr::memchr(b'\n', body).is_some_and(|i| i > 0 && body[i - 1] == b'\r');
    check_head_line_lengths(body, source)?;
    let head = head_lines(body);
    let c = choose_layout(&head, opts, source)?;
    let h = c.header.expect("checked in choose_layout");
    let names = column_names(&head[h], &c, source)?;
    let preamble: Vec<String> = head[..h]
        .iter()
        .filter(|l| !is_blank(l.text))
        .map(|l| String::from_utf8_lossy(l.text).trim().to_string())
        .collect();

    // the data: from the first data line, in chunks split at line ends
    let data_start = head[c.data].text.as_ptr() as usize - body.as_ptr() as usize;
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
        .scan(head[c.data].number, |acc, n| {
            let first = *acc;
            *acc += *n as u64;
            Some(first)
        })
        .collect();
    let mut room = newlines;
    if let Some(last) = room.last_mut() {
        *last += usize::from(!data.ends_with(b"\n"));
    }
    let (columns_data, chunks) = parse_chunks(data, &bounds, &first_line, &room, &c);
    let footer = footer_lines(&chunks, &c, head[h].number, source)?;
    let rows: usize = chunks.iter().map(|ch| ch.rows).sum();
    let columns = names
        .iter()
        .enumerate()
        .zip(columns_data)
        .map(|((k, name), values)| {
            let mut col = Column::numbers(name, Vec::new());
            col.data = match chunks.iter().find_map(|ch| ch.bad[k].clone()) {
                Some((line, text)) => ColumnData::NotNumeric { line, text },
                None => ColumnData::Numbers(values),
            };
            col
        })
        .collect();
    let trailing = field_count(head[c.data].text, c.delimiter, &mut Vec::new()).1;
    let layout = describe_layout(
        &c,
        trailing,
        bom,
        crlf,
        head[h].number,
        preamble.len(),
        footer.len(),
    );
    Ok(Table {
        source: source.to_string(),
        columns,
        rows,
        layout,
        header_line: head[h].number,
        preamble,
        footer,
        sample_interval_s: None,
        start_time_s: None,
    })
}

/// Refuses a head line (one of the first [`SNIFF_LINES`]) longer than the budget
/// `max_line_bytes`, looking no further than the cap for each line end: a file of gigabytes
/// without a newline fails at once instead of being sniffed as one line.
fn check_head_line_lengths(body: &[u8], source: &str) -> Result<()> {
    let cap = greybox_core::budget::Cap::LineBytes;
    let window = usize::try_from(cap.limit()).unwrap_or(usize::MAX).saturating_add(1);
    let mut pos = 0;
    for number in 1..=SNIFF_LINES as u64 {
        if pos >= body.len() {
            break;
        }
        let part = &body[pos..body.len().min(pos.saturating_add(window))];
        let len = memchr::memchr(b'\n', part).unwrap_or(part.len());
        cap.check(len as u64, || format!("line {number} is longer than {} bytes", len - 1))
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

/// The header's column names, one per data field (a trailing empty name dropped, an empty
/// one named `column K`); an error when the counts differ.
fn column_names(header: &Line, c: &Candidate, source: &str) -> Result<Vec<String>> {
    let mut names = split_header(&String::from_utf8_lossy(header.text), c.delimiter);
    while names.len() > c.fields && names.last().is_some_and(|s| s.is_empty()) {
        names.pop();
    }
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

/// The footer: the non-data lines after the last data line. A non-data line before it, or a
/// numeric row with the wrong field count anywhere, is an error naming its line.
fn footer_lines(
    chunks: &[Chunk],
    c: &Candidate,
    header_line: u64,
    source: &str,
) -> Result<Vec<(u64, String)>> {
    let last_data = chunks.iter().map(|ch| ch.last_data_line).max().unwrap_or(0);
    let mut footer = Vec::new();
    for (line, text, wrong) in chunks.iter().flat_map(|ch| &ch.other) {
        if *line < last_data || wrong.is_some() {
            let msg = match wrong {
                Some(k) => format!(
                    "malformed row: expected {} fields, found {k} ({}-delimited, header on line {header_line})",
                    c.fields,
                    c.delimiter.name(),
                ),
                None => format!("a line that is not data inside the data: '{}'", clip(text)),
            };
            return Err(Error::input(SourcePos::file(source).line(*line), msg));
        }
        footer.push((*line, text.clone()));
    }
    Ok(footer)
}

/// The layout in words, for reports: "semicolon-delimited, decimal comma, header on line 3, …".
fn describe_layout(
    c: &Candidate,
    trailing: bool,
    bom: bool,
    crlf: bool,
    header_line: u64,
    preamble: usize,
    footer: usize,
) -> String {
    let mut layout = format!("{}-delimited", c.delimiter.name());
    for (on, what) in [
        (c.decimal_comma, "decimal comma"),
        (trailing, "trailing delimiter"),
        (bom, "UTF-8 BOM"),
        (crlf, "CRLF"),
    ] {
        if on {
            layout.push_str(", ");
            layout.push_str(what);
        }
    }
    layout.push_str(&format!(", header on line {header_line}"));
    if preamble > 0 {
        layout.push_str(&format!(", {preamble} preamble line(s)"));
    }
    if footer > 0 {
        layout.push_str(&format!(", {footer} footer line(s)"));
    }
    layout
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
        let e = parse("0,1\n1,2\n2,3\n").unwrap_err().to_string();
        assert!(e.contains("no header line"), "{e}");
        let e = parse("t_s,F_N\n0,1\n1,abc\n2,3\n").unwrap_err().to_string();
        assert!(e.contains("line 4") && e.contains("no header line"), "{e}");
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
}
