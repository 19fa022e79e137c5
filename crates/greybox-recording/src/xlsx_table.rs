//! Spreadsheet recordings (`.xlsx`, `.xlsm`, `.xls`, `.xlsb`, `.ods`) through `calamine`.
//!
//! The header is found as in text files: the last non-empty row above the first run of rows
//! whose cells are numbers, or the row above it when that row holds units (`s`, `(N)`, …:
//! they give the columns whose names state none their unit); rows after the data that are
//! not data are the footer, and so is a short last row (a recording cut off mid-row).

use crate::table::{is_unit_token, unit_token, Column, ColumnData, Table};
use calamine::{open_workbook_auto_from_rs, Data, Reader};
use greybox_core::budget::Cap;
use greybox_core::{Error, Result, SourcePos};
use std::io::Read as _;

/// Rows of numbers that must follow the header.
const CONFIRM_ROWS: usize = 3;

/// Read one sheet (`sheet`: a name; default the first sheet that holds a table).
pub fn read_spreadsheet(path: &std::path::Path, sheet: Option<&str>) -> Result<Table> {
    let bytes = greybox_core::input::read_recording_bytes(path)?;
    parse_spreadsheet(&bytes, &path.display().to_string(), sheet)
}

/// Excel stores dates and times as days since 1899-12-30.
const SECONDS_PER_DAY: f64 = 86_400.0;

fn cell_number(c: &Data) -> Option<f64> {
    match c {
        Data::Float(v) => Some(*v).filter(|v| v.is_finite()),
        Data::Int(v) => Some(*v as f64),
        // a date, clock time or duration: Excel's serial days, as seconds
        Data::DateTime(d) => Some(d.as_f64() * SECONDS_PER_DAY).filter(|v| v.is_finite()),
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
    check_archive(bytes, source)?;
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
        // a sheet over the cell budget is refused, not passed over for the next one
        let boxed = std::panic::AssertUnwindSafe(|| check_cell_box(&mut wb, name, source));
        if let Ok(Err(e)) = std::panic::catch_unwind(boxed) {
            return Err(e);
        }
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
            Err(e) => {
                let values_start = range.start().unwrap_or((0, 0));
                let formulas = uncomputed_formulas(&mut wb, name, (&rows, values_start), source);
                last_err = Some(formulas.unwrap_or(e))
            }
        }
    }
    Err(last_err.unwrap_or_else(|| Error::input(pos(), "the workbook has no sheets")))
}

/// Where a sheet gave no table: the error for formulas stored without computed values (a
/// workbook written by a program that does not calculate, a script's `openpyxl` output),
/// which read as empty cells — naming how many, the first one and what to do. `None` when
/// the sheet has no such formula.
fn uncomputed_formulas<RS: std::io::Read + std::io::Seek>(
    wb: &mut calamine::Sheets<RS>,
    sheet: &str,
    (rows, values_start): (&[&[Data]], (u32, u32)),
    source: &str,
) -> Option<Error> {
    let formulas =
        std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| wb.worksheet_formula(sheet)))
            .ok()?
            .ok()?;
    let start = formulas.start().unwrap_or((0, 0));
    // the value range starts where its first stored cell is, the formula range where its own is
    let value_at = |r: u32, c: u32| {
        let (Some(i), Some(j)) = (r.checked_sub(values_start.0), c.checked_sub(values_start.1))
        else {
            return false;
        };
        rows.get(i as usize)
            .and_then(|row| row.get(j as usize))
            .is_some_and(|d| !matches!(d, Data::Empty))
    };
    let mut uncomputed = formulas
        .cells()
        .filter(|(_, _, f)| !f.is_empty())
        .map(|(r, c, f)| (start.0 + r as u32, start.1 + c as u32, f))
        .filter(|&(r, c, _)| !value_at(r, c));
    let (r, c, first) = uncomputed.next()?;
    let n = 1 + uncomputed.count();
    Some(Error::input(
        SourcePos::file(source).field(sheet),
        format!(
            "{n} formula cell(s) hold no computed value (the first at row {}, column {}: ={}): the workbook was saved by a program that does not calculate its formulas; open and save it in a spreadsheet program so the values are stored, or export the sheet as CSV",
            r + 1,
            c + 1,
            greybox_core::escape::excerpt(first)
        ),
    ))
}

fn row_empty(r: &[Data]) -> bool {
    r.iter().all(|c| matches!(c, Data::Empty))
}

/// A row of units: text cells that are all units, at least one of them.
fn units_row(r: &[Data]) -> bool {
    !row_empty(r)
        && r.iter().all(|c| match c {
            Data::Empty => true,
            Data::String(s) => is_unit_token(s),
            _ => false,
        })
}

/// The header above the first data row `data` (the last non-empty row above it, or the one
/// above that when it is a units row) and the units row.
fn header_and_units(rows: &[&[Data]], data: usize) -> (Option<usize>, Option<usize>) {
    let prev = |below: usize| (0..below).rev().find(|&i| !row_empty(rows[i]));
    let Some(last) = prev(data) else {
        return (None, None);
    };
    if units_row(rows[last]) {
        if let Some(h) = prev(last).filter(|&h| !units_row(rows[h])) {
            return (Some(h), Some(last));
        }
    }
    (Some(last), None)
}

/// A row's non-empty cells as one line of text.
fn row_text(r: &[Data]) -> String {
    r.iter()
        .map(cell_text)
        .filter(|s| !s.is_empty())
        .collect::<Vec<_>>()
        .join(" ")
}

/// Bytes of an entry's start kept for its declared sizes.
const HEAD_BYTES: usize = 4096;

/// Refuses a spreadsheet archive whose entries expand to more than `max_uncompressed_bytes`
/// together (decompressed in a stream and counted, nothing kept but each entry's first
/// [`HEAD_BYTES`]), or whose sheets or shared strings declare more than `max_sheet_cells`.
/// Anything that is not a readable zip archive is left to calamine.
fn check_archive(bytes: &[u8], source: &str) -> Result<()> {
    if !bytes.starts_with(b"PK") {
        return Ok(());
    }
    let Ok(mut zip) = zip::ZipArchive::new(std::io::Cursor::new(bytes)) else {
        return Ok(());
    };
    let cap = Cap::UncompressedBytes;
    let mut total = 0u64;
    let mut buf = vec![0u8; 64 << 10];
    for i in 0..zip.len() {
        let Ok(mut entry) = zip.by_index(i) else {
            continue;
        };
        let name = entry
            .name()
            .map(|n| n.into_owned())
            .unwrap_or_else(|_| format!("entry {i}"));
        let mut head = Vec::new();
        while let Ok(n @ 1..) = entry.read(&mut buf) {
            let keep = n.min(HEAD_BYTES - head.len());
            head.extend_from_slice(&buf[..keep]);
            total += n as u64;
            cap.check(total, || {
                format!("the archive's entries expand to more than {total} bytes (entry {name}, {} bytes in the file)", bytes.len())
            })
            .map_err(|m| Error::input(SourcePos::file(source).field(&name), m))?;
        }
        declared_cells(&name, &head)
            .map_err(|m| Error::input(SourcePos::file(source).field(&name), m))?;
    }
    Ok(())
}

/// The number in `attr="N"` within `text`, if present.
fn attribute<'a>(text: &'a str, attr: &str) -> Option<&'a str> {
    let at = text.find(&format!(" {attr}=\""))? + attr.len() + 3;
    text[at..].split('"').next()
}

/// (row, column), 1-based, of a cell reference such as `XFD1048576`.
fn cell_ref(r: &str) -> Option<(u64, u64)> {
    let letters = r.chars().take_while(char::is_ascii_alphabetic).count();
    let col = r[..letters].bytes().try_fold(0u64, |c, b| {
        c.checked_mul(26)?
            .checked_add((b.to_ascii_uppercase() - b'A' + 1) as u64)
    })?;
    let row = r[letters..].parse().ok()?;
    Some((row, col))
}

/// Checks a worksheet's `<dimension ref="A1:C10">` and the shared strings' `uniqueCount`
/// (calamine reserves room for that many) against `max_sheet_cells`.
fn declared_cells(name: &str, head: &[u8]) -> Result<(), String> {
    let text = String::from_utf8_lossy(head);
    if name.starts_with("xl/worksheets/") {
        let dim = text
            .find("<dimension")
            .and_then(|i| attribute(&text[i..], "ref"))
            .and_then(|r| r.split_once(':'))
            .and_then(|(a, b)| Some((cell_ref(a)?, cell_ref(b)?)));
        if let Some(((r0, c0), (r1, c1))) = dim {
            let (rows, cols) = (r1.abs_diff(r0) + 1, c1.abs_diff(c0) + 1);
            Cap::SheetCells.check(rows.saturating_mul(cols), || {
                format!("the sheet declares {rows} rows × {cols} columns")
            })?;
        }
    } else if name == "xl/sharedStrings.xml" {
        if let Some(n) = attribute(&text, "uniqueCount").and_then(|n| n.parse::<u64>().ok()) {
            Cap::SheetCells.check(n, || format!("the workbook declares {n} shared strings"))?;
        }
    }
    Ok(())
}

/// Refuses an xlsx sheet whose cells span a box of more than `max_sheet_cells` (calamine
/// holds the box densely: two cells at A1 and XFD1048576 would take 17·10⁹ cells), counted
/// in a streaming pass that keeps nothing.
fn check_cell_box<RS: std::io::Read + std::io::Seek>(
    wb: &mut calamine::Sheets<RS>,
    name: &str,
    source: &str,
) -> Result<()> {
    let calamine::Sheets::Xlsx(x) = wb else {
        return Ok(());
    };
    let Ok(mut cells) = x.worksheet_cells_reader(name) else {
        return Ok(()); // worksheet_range reports it
    };
    let (mut lo, mut hi) = ((u32::MAX, u32::MAX), (0u32, 0u32));
    while let Ok(Some(c)) = cells.next_cell() {
        let (r, k) = c.get_position();
        lo = (lo.0.min(r), lo.1.min(k));
        hi = (hi.0.max(r), hi.1.max(k));
    }
    if lo.0 > hi.0 {
        return Ok(());
    }
    let (rows, cols) = ((hi.0 - lo.0) as u64 + 1, (hi.1 - lo.1) as u64 + 1);
    Cap::SheetCells
        .check(rows * cols, || {
            format!("the sheet's cells span {rows} rows × {cols} columns")
        })
        .map_err(|m| Error::input(SourcePos::file(source).field(name), m))
}

/// The columns holding a number in a row.
fn numeric_cols(r: &[Data]) -> Vec<usize> {
    r.iter()
        .enumerate()
        .filter(|(_, c)| cell_number(c).is_some())
        .map(|(k, _)| k)
        .collect()
}

/// The first row of the table's data: at least two numbers, and the next
/// [`CONFIRM_ROWS`] non-empty rows with numbers in the same columns.
fn first_data_row(rows: &[&[Data]]) -> Option<usize> {
    (0..rows.len()).find(|&i| {
        let cols = numeric_cols(rows[i]);
        cols.len() >= 2
            && rows[i..]
                .iter()
                .filter(|r| !row_empty(r))
                .take(CONFIRM_ROWS)
                .all(|r| numeric_cols(r) == cols)
    })
}

/// Column `k` of a sheet's table: its name from the header row, its unit from the name or
/// the units row, its values from the `body` rows (up to the first cell that is not a
/// number); dates and times read as seconds, with a note.
fn sheet_column(
    rows: &[&[Data]],
    k: usize,
    (header, units): (usize, Option<usize>),
    body: &[usize],
    first_row: u64,
    notes: &mut Vec<String>,
) -> Column {
    let row_no = |i: usize| first_row + i as u64 + 1;
    let head = rows[header].get(k).map(cell_text).unwrap_or_default();
    let head = if head.is_empty() {
        format!("column {}", k + 1)
    } else {
        head
    };
    let mut values = Vec::with_capacity(body.len());
    let mut bad = None;
    let mut dated = false;
    for &i in body {
        let cell = rows[i].get(k).unwrap_or(&Data::Empty);
        dated |= matches!(cell, Data::DateTime(_));
        match cell_number(cell) {
            Some(v) => values.push(v),
            None => {
                bad = Some((row_no(i), cell_text(cell)));
                break;
            }
        }
    }
    let mut col = Column::numbers(&head, Vec::new());
    if col.unit.is_none() {
        col.unit = units
            .and_then(|u| rows[u].get(k))
            .and_then(|c| unit_token(&cell_text(c)));
    }
    if dated {
        let unit = col.unit.get_or_insert_with(|| "s".to_string());
        notes.push(format!(
            "column '{}' holds dates or times: read as seconds (Excel serial days × 86 400){}",
            col.name,
            if unit == "s" {
                String::new()
            } else {
                format!(", but its unit says {unit}")
            }
        ));
    }
    col.data = match bad {
        Some((line, text)) => ColumnData::NotNumeric { line, text },
        None => ColumnData::Numbers(values),
    };
    col
}

fn table_from_rows(rows: &[&[Data]], first_row: u64, source: &str, sheet: &str) -> Result<Table> {
    let row_no = |i: usize| first_row + i as u64 + 1;
    let is_empty = row_empty;
    let Some(data) = first_data_row(rows) else {
        return Err(Error::input(
            SourcePos::file(source).field(sheet),
            "no table found: expected a header row followed by rows of numbers",
        ));
    };
    let cols = numeric_cols(rows[data]);
    let (header, units) = header_and_units(rows, data);
    let header = header.ok_or_else(|| {
        Error::input(
            SourcePos::file(source).field(sheet).line(row_no(data)),
            "numeric rows without a header row above them that names the columns",
        )
    })?;
    let preamble: Vec<String> = rows[..header]
        .iter()
        .filter(|r| !is_empty(r))
        .map(|r| row_text(r))
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
    let mut footer: Vec<(u64, String)> = (end..rows.len())
        .filter(|&i| !is_empty(rows[i]))
        .map(|i| (row_no(i), row_text(rows[i])))
        .collect();
    let mut body: Vec<usize> = (data..end).filter(|&i| !is_empty(rows[i])).collect();
    // a last row with some of the table's cells empty was cut off: footer, with a note
    let mut notes = Vec::new();
    if let Some(&last) = body.last().filter(|_| body.len() > 1) {
        let missing = cols
            .iter()
            .filter(|&&k| matches!(rows[last].get(k).unwrap_or(&Data::Empty), Data::Empty))
            .count();
        if missing > 0 {
            body.pop();
            footer.insert(0, (row_no(last), row_text(rows[last])));
            notes.push(format!(
                "the last data row (row {}) has {missing} of {} cells empty: taken as cut off and reported in the footer",
                row_no(last),
                cols.len()
            ));
        }
    }
    let columns = cols
        .iter()
        .map(|&k| sheet_column(rows, k, (header, units), &body, first_row, &mut notes))
        .collect();
    let mut layout = format!(
        "spreadsheet, sheet '{sheet}', header on row {}",
        row_no(header)
    );
    if let Some(u) = units {
        layout.push_str(&format!(", units row {}", row_no(u)));
    }
    if !footer.is_empty() {
        layout.push_str(&format!(", {} footer row(s)", footer.len()));
    }
    Ok(Table {
        source: source.to_string(),
        columns,
        rows: body.len(),
        layout,
        header_line: row_no(header),
        headerless: false,
        preamble,
        header_alternatives: Vec::new(),
        footer,
        sample_interval_s: None,
        start_time_s: None,
        notes,
        ..Default::default()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A minimal workbook whose data cells are formulas with no stored value (as a script's
    /// writer leaves them), written part by part (ECMA-376 SpreadsheetML).
    fn uncalculated_workbook() -> Vec<u8> {
        use std::io::Write as _;
        let mut rows = String::from(
            r#"<row r="1"><c r="A1" t="inlineStr"><is><t>Time (s)</t></is></c><c r="B1" t="inlineStr"><is><t>Fn (N)</t></is></c></row>"#,
        );
        for k in 2..8 {
            rows += &format!(
                r#"<row r="{k}"><c r="A{k}"><f>(ROW()-2)*0.1</f></c><c r="B{k}"><f>10+ROW()</f></c></row>"#
            );
        }
        let parts = [
            ("[Content_Types].xml", r#"<?xml version="1.0" encoding="UTF-8"?><Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types"><Default Extension="rels" ContentType="application/vnd.openxmlformats-package.relationships+xml"/><Default Extension="xml" ContentType="application/xml"/><Override PartName="/xl/workbook.xml" ContentType="application/vnd.openxmlformats-officedocument.spreadsheetml.sheet.main+xml"/><Override PartName="/xl/worksheets/sheet1.xml" ContentType="application/vnd.openxmlformats-officedocument.spreadsheetml.worksheet+xml"/></Types>"#.to_string()),
            ("_rels/.rels", r#"<?xml version="1.0" encoding="UTF-8"?><Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships"><Relationship Id="rId1" Type="http://schemas.openxmlformats.org/officeDocument/2006/relationships/officeDocument" Target="xl/workbook.xml"/></Relationships>"#.to_string()),
            ("xl/workbook.xml", r#"<?xml version="1.0" encoding="UTF-8"?><workbook xmlns="http://schemas.openxmlformats.org/spreadsheetml/2006/main" xmlns:r="http://schemas.openxmlformats.org/officeDocument/2006/relationships"><sheets><sheet name="Sheet1" sheetId="1" r:id="rId1"/></sheets></workbook>"#.to_string()),
            ("xl/_rels/workbook.xml.rels", r#"<?xml version="1.0" encoding="UTF-8"?><Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships"><Relationship Id="rId1" Type="http://schemas.openxmlformats.org/officeDocument/2006/relationships/worksheet" Target="worksheets/sheet1.xml"/></Relationships>"#.to_string()),
            ("xl/worksheets/sheet1.xml", format!(r#"<?xml version="1.0" encoding="UTF-8"?><worksheet xmlns="http://schemas.openxmlformats.org/spreadsheetml/2006/main"><sheetData>{rows}</sheetData></worksheet>"#)),
        ];
        let mut z = zip::ZipWriter::new(std::io::Cursor::new(Vec::new()));
        let opts = zip::write::SimpleFileOptions::default();
        for (name, text) in parts {
            z.start_file(name, opts).unwrap();
            z.write_all(text.as_bytes()).unwrap();
        }
        z.finish().unwrap().into_inner()
    }

    #[test]
    fn formulas_without_computed_values_are_named() {
        let e = parse_spreadsheet(&uncalculated_workbook(), "calc.xlsx", None)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("calc.xlsx")
                && e.contains("12 formula cell(s)")
                && e.contains("row 2, column 1")
                && e.contains("(ROW()-2)*0.1")
                && e.contains("CSV"),
            "{e}"
        );
    }

    fn s(t: &str) -> Data {
        Data::String(t.to_string())
    }

    #[test]
    fn units_row_and_short_last_row() {
        let f = Data::Float;
        let rows: Vec<Vec<Data>> = vec![
            vec![s("UMT export"), Data::Empty, Data::Empty],
            vec![s("Time"), s("Fz"), s("Fx (kN)")],
            vec![s("s"), s("(N)"), s("N")],
            vec![f(0.0), f(10.0), f(1.0)],
            vec![f(0.1), f(10.5), f(1.5)],
            vec![f(0.2), f(11.0), f(2.0)],
            vec![f(0.3), f(11.5), Data::Empty],
        ];
        let refs: Vec<&[Data]> = rows.iter().map(|r| r.as_slice()).collect();
        let t = table_from_rows(&refs, 0, "u.xlsx", "Sheet1").unwrap();
        assert_eq!(t.header_line, 2);
        assert_eq!(t.preamble, ["UMT export"]);
        let units: Vec<Option<&str>> = t.columns.iter().map(|c| c.unit.as_deref()).collect();
        assert_eq!(units, [Some("s"), Some("N"), Some("kN")]);
        assert_eq!(t.rows, 3);
        assert_eq!(t.columns[2].values("u").unwrap(), &[1.0, 1.5, 2.0]);
        assert_eq!(t.footer, [(7, "0.3 11.5".to_string())]);
        assert!(t.notes[0].contains("row 7"), "{:?}", t.notes);
        assert!(t.layout.contains("units row 3"), "{}", t.layout);
    }
}
