//! The header and units rows of a sniffed table: column names (or `#1`, `#2`, … without a header),
//! units, the lines above the data checked, and the layout in words.

use super::fields::{strip_cr, Line};
use super::options::SNIFF_LINES;
use super::sniff::{header_names, Candidate};
use crate::table::unit_token;
use greybox_core::{Error, Result, SourcePos};

/// The first block's header names and units row, which every later block repeats.
pub(super) struct HeaderKey {
    pub(super) names: Vec<String>,
    pub(super) units: Option<Vec<String>>,
}

/// Refuses a head line (one of the first [`SNIFF_LINES`]) longer than the budget
/// `max_line_bytes`, looking no further than the cap for each line end: a file of gigabytes
/// without a newline fails at once instead of being sniffed as one line.
pub(super) fn check_head_line_lengths(body: &[u8], source: &str) -> Result<()> {
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
pub(super) fn head_lines(body: &[u8]) -> Vec<Line<'_>> {
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
pub(super) struct Header {
    pub(super) key: HeaderKey,
    pub(super) names: Vec<String>,
    pub(super) line: Option<u64>,
}

pub(super) fn resolve_header(head: &[Line], c: &Candidate, source: &str) -> Result<Header> {
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
pub(super) fn header_at(line: Option<u64>) -> String {
    line.map_or("no header line".to_string(), |h| {
        format!("header on line {h}")
    })
}

/// The header's column names, one per data field (an empty one named `column K`); an error
/// when the counts differ.
pub(super) fn column_names(header: &Line, c: &Candidate, source: &str) -> Result<Vec<String>> {
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
pub(super) fn check_units_row(
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

/// What [`Layout::describe`] puts in words.
pub(super) struct Layout<'a> {
    pub(super) c: &'a Candidate,
    pub(super) trailing: bool,
    pub(super) bom: bool,
    pub(super) crlf: bool,
    pub(super) cr: bool,
    pub(super) header_line: Option<u64>,
    pub(super) units_line: Option<u64>,
    pub(super) preamble: usize,
    pub(super) footer: usize,
    pub(super) blocks: usize,
}

impl Layout<'_> {
    /// The layout in words, for reports: "semicolon-delimited, decimal comma, header on line 3, …".
    pub(super) fn describe(&self) -> String {
        let mut layout = match self.c.fields {
            1 => "one column".to_string(),
            _ => format!("{}-delimited", self.c.delimiter.name()),
        };
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
