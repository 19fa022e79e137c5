//! Spreadsheet recordings (`.xlsx`, `.xlsm`, `.xls`, `.xlsb`, `.ods`) through `calamine`.
//!
//! The header is found as in text files: the last non-empty row above the first run of rows
//! whose cells are numbers; rows after the data that are not data are the footer.

use crate::table::{Column, ColumnData, Table};
use calamine::{open_workbook_auto_from_rs, Data, Reader};
use greybox_core::{Error, Result, SourcePos};

/// Rows of numbers that must follow the header.
const CONFIRM_ROWS: usize = 3;

/// Whether a path names a spreadsheet by its extension.
pub fn is_spreadsheet(path: &std::path::Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .map(|e| {
            matches!(
                e.to_ascii_lowercase().as_str(),
                "xlsx" | "xlsm" | "xls" | "xlsb" | "ods"
            )
        })
        .unwrap_or(false)
}

/// Read one sheet (`sheet`: a name; default the first sheet that holds a table).
pub fn read_spreadsheet(path: &std::path::Path, sheet: Option<&str>) -> Result<Table> {
    let bytes = std::fs::read(path).map_err(|e| Error::io(path, e))?;
    parse_spreadsheet(&bytes, &path.display().to_string(), sheet)
}

fn cell_number(c: &Data) -> Option<f64> {
    match c {
        Data::Float(v) => Some(*v).filter(|v| v.is_finite()),
        Data::Int(v) => Some(*v as f64),
        Data::String(s) => s.trim().parse::<f64>().ok().filter(|v| v.is_finite()),
        _ => None,
    }
}

fn cell_text(c: &Data) -> String {
    match c {
        Data::Empty => String::new(),
        Data::String(s) => s.trim().to_string(),
        other => other.to_string(),
    }
}

/// Parse a spreadsheet from bytes (`source` names it in errors).
pub fn parse_spreadsheet(bytes: &[u8], source: &str, sheet: Option<&str>) -> Result<Table> {
    let pos = || SourcePos::file(source);
    // calamine may panic on some corrupted archives; a reader must never take the caller down
    let opened = std::panic::catch_unwind(|| {
        open_workbook_auto_from_rs(std::io::Cursor::new(bytes.to_vec()))
    });
    let mut wb = match opened {
        Ok(Ok(wb)) => wb,
        Ok(Err(e)) => {
            return Err(Error::input(
                pos(),
                format!("not a readable spreadsheet (xlsx, xls, xlsb, ods): {e}"),
            ))
        }
        Err(_) => {
            return Err(Error::input(
                pos(),
                "not a readable spreadsheet: the workbook structure is corrupted",
            ))
        }
    };
    let names = wb.sheet_names();
    let wanted: Vec<String> = match sheet {
        Some(s) => {
            if !names.iter().any(|n| n == s) {
                return Err(Error::input(
                    pos().field(s),
                    format!("no sheet '{s}'; the workbook has: {}", names.join(", ")),
                ));
            }
            vec![s.to_string()]
        }
        None => names.clone(),
    };
    let mut last_err = None;
    for name in &wanted {
        let range = match std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| {
            wb.worksheet_range(name)
        })) {
            Ok(Ok(r)) => r,
            Ok(Err(e)) => {
                last_err = Some(Error::input(
                    pos().field(name),
                    format!("cannot read sheet: {e}"),
                ));
                continue;
            }
            Err(_) => {
                last_err = Some(Error::input(pos().field(name), "corrupted sheet"));
                continue;
            }
        };
        let first_row = range.start().map_or(0, |(r, _)| r as u64);
        let rows: Vec<&[Data]> = range.rows().collect();
        match table_from_rows(&rows, first_row, source, name) {
            Ok(t) => return Ok(t),
            Err(e) => last_err = Some(e),
        }
    }
    Err(last_err.unwrap_or_else(|| Error::input(pos(), "the workbook has no sheets")))
}

fn table_from_rows(rows: &[&[Data]], first_row: u64, source: &str, sheet: &str) -> Result<Table> {
    let row_no = |i: usize| first_row + i as u64 + 1;
    let numeric_cols = |r: &[Data]| -> Vec<usize> {
        r.iter()
            .enumerate()
            .filter(|(_, c)| cell_number(c).is_some())
            .map(|(k, _)| k)
            .collect()
    };
    let is_empty = |r: &[Data]| r.iter().all(|c| matches!(c, Data::Empty));
    let data = (0..rows.len()).find(|&i| {
        let cols = numeric_cols(rows[i]);
        cols.len() >= 2
            && rows[i..]
                .iter()
                .filter(|r| !is_empty(r))
                .take(CONFIRM_ROWS)
                .all(|r| numeric_cols(r) == cols)
    });
    let Some(data) = data else {
        return Err(Error::input(
            SourcePos::file(source).field(sheet),
            "no table found: expected a header row followed by rows of numbers",
        ));
    };
    let cols = numeric_cols(rows[data]);
    let header = (0..data)
        .rev()
        .find(|&i| !is_empty(rows[i]))
        .ok_or_else(|| {
            Error::input(
                SourcePos::file(source).field(sheet).line(row_no(data)),
                "numeric rows without a header row above them that names the columns",
            )
        })?;
    let preamble: Vec<String> = rows[..header]
        .iter()
        .filter(|r| !is_empty(r))
        .map(|r| {
            r.iter()
                .map(cell_text)
                .filter(|s| !s.is_empty())
                .collect::<Vec<_>>()
                .join(" ")
        })
        .collect();
    // the data ends at the first row with no number in the table's columns
    let mut end = data;
    while end < rows.len()
        && (is_empty(rows[end])
            || cols
                .iter()
                .any(|&k| rows[end].get(k).and_then(cell_number).is_some()))
    {
        end += 1;
    }
    let footer: Vec<(u64, String)> = (end..rows.len())
        .filter(|&i| !is_empty(rows[i]))
        .map(|i| {
            (
                row_no(i),
                rows[i]
                    .iter()
                    .map(cell_text)
                    .filter(|s| !s.is_empty())
                    .collect::<Vec<_>>()
                    .join(" "),
            )
        })
        .collect();
    let body: Vec<usize> = (data..end).filter(|&i| !is_empty(rows[i])).collect();
    let mut columns = Vec::with_capacity(cols.len());
    for &k in &cols {
        let head = rows[header].get(k).map(cell_text).unwrap_or_default();
        let head = if head.is_empty() {
            format!("column {}", k + 1)
        } else {
            head
        };
        let mut values = Vec::with_capacity(body.len());
        let mut bad = None;
        for &i in &body {
            let cell = rows[i].get(k).unwrap_or(&Data::Empty);
            match cell_number(cell) {
                Some(v) => values.push(v),
                None => {
                    bad = Some((row_no(i), cell_text(cell)));
                    break;
                }
            }
        }
        let mut col = Column::numbers(&head, Vec::new());
        col.data = match bad {
            Some((line, text)) => ColumnData::NotNumeric { line, text },
            None => ColumnData::Numbers(values),
        };
        columns.push(col);
    }
    let mut layout = format!(
        "spreadsheet, sheet '{sheet}', header on row {}",
        row_no(header)
    );
    if !footer.is_empty() {
        layout.push_str(&format!(", {} footer row(s)", footer.len()));
    }
    Ok(Table {
        source: source.to_string(),
        columns,
        rows: body.len(),
        layout,
        header_line: row_no(header),
        preamble,
        footer,
        sample_interval_s: None,
        start_time_s: None,
        ..Default::default()
    })
}
