//! The data lines parsed in parallel chunks straight into columns: a fast path for plain numeric
//! rows, the general field splitter for the rest, and the lines that are not data.

use super::fields::{decode, is_blank, parse_number, strip_cr, trim, Line};
use super::sniff::{mostly_numeric, shape, Candidate};
use rayon::prelude::*;

/// A line of the data region that is not a data row (a footer, a block's settings or header
/// line, a malformed row).
#[derive(Debug, Clone)]
pub(super) struct OtherLine {
    pub(super) line: u64,
    /// The line as written (line end removed, not trimmed).
    pub(super) text: String,
    /// A numeric row with the wrong number of fields: how many it has.
    pub(super) wrong: Option<usize>,
    /// Data rows of its chunk above it.
    pub(super) row: usize,
}

/// One parsed chunk of data lines.
pub(super) struct Chunk {
    /// Data rows written to the front of the chunk's column slices.
    pub(super) rows: usize,
    /// First non-number per column: (line, text).
    pub(super) bad: Vec<Option<(u64, String)>>,
    /// Columns with at least one non-empty cell.
    pub(super) filled: Vec<bool>,
    /// Lines that are not data rows.
    pub(super) other: Vec<OtherLine>,
    pub(super) last_data_line: u64,
}

/// How the one-pass row parser ([`fast_row`]) sees a line: the field separator and the
/// decimal mark.
#[derive(Clone, Copy)]
pub(super) struct FastLayout {
    /// `None`: runs of spaces or tabs separate fields (leading and trailing ones allowed).
    pub(super) separator: Option<u8>,
    pub(super) mark: u8,
}

impl FastLayout {
    pub(super) fn of(c: &Candidate) -> Self {
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
pub(super) fn number_prefix(s: &[u8], mark: u8) -> Option<(f64, usize)> {
    if let Some(r) = crate::decimal::parse_plain_prefix(s, mark) {
        return Some(r);
    }
    if mark != b'.' {
        return None;
    }
    let (v, used) = fast_float2::parse_partial::<f64, _>(s).ok()?;
    (used > 0 && v.is_finite()).then_some((v, used))
}

pub(super) fn is_blank_byte(b: u8) -> bool {
    b == b' ' || b == b'\t'
}

/// The common case in one pass over the bytes, without finding the line end first: a line of
/// `row.len()` numbers separated as `f` says (an optional trailing delimiter), each finite,
/// ended by LF, CRLF or the end of `text`. The bytes used, line end included; `None` for
/// anything else (the caller takes the general path, which gives the same values or a
/// precise error).
#[inline]
pub(super) fn fast_row(text: &[u8], f: FastLayout, row: &mut [f64]) -> Option<usize> {
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
pub(super) fn parse_chunk(
    part: &[u8],
    first_line: u64,
    c: &Candidate,
    out: &mut [&mut [f64]],
) -> Chunk {
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
pub(super) fn general_row(
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
pub(super) fn parse_chunks(
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

/// Chunk boundaries of about `target` bytes, each after a line end.
pub(super) fn chunk_bounds(data: &[u8], target: usize) -> Vec<usize> {
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
