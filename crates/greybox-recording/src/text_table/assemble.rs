//! Reading a text table end to end: the file (memory-mapped) sniffed, its data parsed in chunks,
//! and the columns built, with repeated header blocks and footers found.

use super::chunks::{chunk_bounds, parse_chunks, Chunk, OtherLine};
use super::fields::{clip, decode, is_blank, Line};
use super::header::{
    check_head_line_lengths, check_units_row, head_lines, header_at, resolve_header, Header,
    HeaderKey, Layout,
};
use super::options::{Delimiter, TextOptions};
use super::sniff::{
    choose_layout, header_names, mostly_text, other_header_lines, shape, units_row, Candidate,
};
use crate::table::{unit_token, Column, ColumnData, Table};
use greybox_core::{Error, Result, SourcePos};
use rayon::prelude::*;

/// Read a text table from a file.
///
/// Only a regular file of at most the budget `max_recording_bytes` is read
/// ([`greybox_core::input::open_recording`]: a FIFO, a device or a link to one is refused by
/// name). It is memory-mapped (no copy of a file of hundreds of MB into a buffer); the file
/// must not be truncated while it is read, as with any reader that maps files. On a file
/// system without mmap it is read into memory.
pub fn read_text_table(path: &std::path::Path, opts: &TextOptions) -> Result<Table> {
    let source = path.display().to_string();
    let (file, len) = greybox_core::input::open_recording(path)?;
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
        &greybox_core::input::read_recording_bytes(path)?,
        &source,
        opts,
    )
}

/// Parse a text table from bytes (`source` names it in errors).
pub fn parse_text_table(bytes: &[u8], source: &str, opts: &TextOptions) -> Result<Table> {
    parse_in_chunks(bytes, source, opts, 1 << 20)
}

/// Whether the lines end in a bare CR (classic Mac OS): a CR in the first line (up to the first
/// LF, so a plain LF file is not scanned to its end) that is not followed by LF.
pub(super) fn bare_cr(body: &[u8]) -> bool {
    let first = memchr::memchr(b'\n', body).unwrap_or(body.len());
    memchr::memchr(b'\r', &body[..first]).is_some_and(|i| body.get(i + 1) != Some(&b'\n'))
}

/// The body with every CR that is not followed by LF turned into LF.
pub(super) fn cr_to_lf(body: &[u8]) -> Vec<u8> {
    let mut out = body.to_vec();
    for i in memchr::memchr_iter(b'\r', body) {
        if body.get(i + 1) != Some(&b'\n') {
            out[i] = b'\n';
        }
    }
    out
}

/// [`parse_text_table`] with data chunks of at least `min_chunk` bytes (tests use tiny ones).
pub(super) fn parse_in_chunks(
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
        header_alternatives: other_header_lines(&head, &c),
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
pub(super) fn parse_data(
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

/// The columns of a text table, where they sit in the file, and notes on what was changed.
pub(super) struct BuiltColumns {
    pub(super) columns: Vec<Column>,
    pub(super) positions: Vec<usize>,
    pub(super) notes: Vec<String>,
}

/// The columns from their names, the units row (a unit for a header that states none) and the
/// parsed values. Columns without a single non-empty cell are dropped (noted); repeated
/// header names are told apart ([`mark_duplicates`]).
pub(super) fn build_columns(
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
pub(super) fn mark_duplicates(
    columns: &mut [Column],
    positions: &[usize],
    notes: &mut Vec<String>,
) {
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

/// The non-data lines sorted out: the footer and the blocks after the first.
#[derive(Default)]
pub(super) struct Regions {
    pub(super) footer: Vec<(u64, String)>,
    /// Row where each block after the first begins.
    pub(super) block_starts: Vec<usize>,
    /// The lines between the previous block's data and each block's header.
    pub(super) block_preambles: Vec<Vec<String>>,
}

/// Sort the lines that are not data rows into regions (lines with no data row between them):
/// after the last data row, the footer; between data rows, a block's settings lines ending
/// in the first block's header (and units row). Anything else between data rows, and a
/// malformed row anywhere, is an error naming its line.
pub(super) fn assemble(
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
pub(super) fn key_lines(key: &HeaderKey) -> usize {
    1 + usize::from(key.units.is_some())
}

/// Where a region ends in the first block's header (and units row): the header's index.
pub(super) fn block_header(region: &[&OtherLine], d: Delimiter, key: &HeaderKey) -> Option<usize> {
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
pub(super) fn region_error(
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
        let suggestion = if names == key.names {
            String::new()
        } else {
            format!(
                " (if line {} is the header and the lines above it are the file's preamble, give `header_line` {})",
                o.line, o.line
            )
        };
        (o.line, format!("a new block of the table starts here, but {what}; every block must have the same columns{suggestion}"))
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
