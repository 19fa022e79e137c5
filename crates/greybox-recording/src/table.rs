//! Column tables as rigs export them, before any channel has a role.
//!
//! Every recording reader (delimited text in [`crate::text_table`], spreadsheets in
//! [`crate::xlsx_table`], TDMS in [`crate::tdms`]) produces a [`Table`]: named columns with the
//! unit their header states, and where they came from. [`crate::ChannelMap`] then
//! gives the columns roles (time, normal force, …) and converts them to SI.

use greybox_core::units::{ForceUnit, LengthUnit, SpeedUnit, TimeUnit};
use greybox_core::{Error, Result, SourcePos};

/// One column of a table.
#[derive(Debug, Clone, PartialEq)]
pub struct Column {
    /// The header text as written (trimmed), e.g. `DAQ.Fz (N)`.
    pub header: String,
    /// The header without its unit, e.g. `DAQ.Fz`.
    pub name: String,
    /// The unit the header (or a TDMS `unit_string`) states, e.g. `N`.
    pub unit: Option<String>,
    pub data: ColumnData,
}

/// A column's values, or where the first value that is not a number was found.
#[derive(Debug, Clone, PartialEq)]
pub enum ColumnData {
    Numbers(Vec<f64>),
    /// The column holds text (a comment, a date) or an empty or broken cell; an error only
    /// when a role is mapped to it.
    NotNumeric {
        /// 1-based line (text) or row (spreadsheet) of the first offending cell.
        line: u64,
        text: String,
    },
}

/// A table read from one file.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Table {
    /// File it was read from.
    pub source: String,
    pub columns: Vec<Column>,
    /// Number of data rows.
    pub rows: usize,
    /// How the file was laid out (for `identify --inspect`), e.g. `semicolon-delimited,
    /// decimal comma, header on line 3`.
    pub layout: String,
    /// 1-based line (row) of the header; 0 when the format has no header line (TDMS).
    pub header_line: u64,
    /// The file has no header line (a log of numbers only): its columns are named `#1`, `#2`,
    /// … by position (until [`Table::name_columns`] names them), and [`Table::header_line`]
    /// is the line above the data.
    pub headerless: bool,
    /// Lines above the header (instrument metadata), as text.
    pub preamble: Vec<String>,
    /// Other lines above the data that could be the header (as many names as columns, mostly
    /// text): (1-based line, names). When the header taken names no channel, the error
    /// suggests the one of these that does (`header_line` N). Empty for TDMS and forced headers.
    pub header_alternatives: Vec<(u64, Vec<String>)>,
    /// Non-data lines after the data: (1-based line, text). Reported, not an error.
    pub footer: Vec<(u64, String)>,
    /// Waveform sample interval from the file's own metadata (TDMS `wf_increment`), s.
    pub sample_interval_s: Option<f64>,
    /// Time of the first sample from the file's own metadata (TDMS `wf_start_offset`), s.
    pub start_time_s: Option<f64>,
    /// A file of blocks (one table per test step, each under its own settings lines and a
    /// repeat of the header): the row where each block begins, the first being 0. Empty for a
    /// single table. The rows of all blocks follow each other in the columns; a channel such
    /// as time may restart in every block.
    pub block_starts: Vec<usize>,
    /// The settings lines of each block (one entry per [`Table::block_starts`] entry): for the
    /// first block the [`Table::preamble`], for the others the lines between the previous
    /// block's data and the block's header. Empty for a single table.
    pub block_preambles: Vec<Vec<String>>,
    /// 1-based position of each column among the fields of a row in the file (columns without
    /// any value are left out of [`Table::columns`], so positions may skip). Empty: column k is
    /// at position k + 1.
    pub positions: Vec<usize>,
    /// What the reader changed or noticed in the layout, in words: columns without a single
    /// value left out, header names that occur more than once, a short last row.
    pub notes: Vec<String>,
}

impl Column {
    /// A numeric column from a header (the unit is split off the name).
    pub fn numbers(header: &str, values: Vec<f64>) -> Self {
        let (name, unit) = split_unit(header);
        Column {
            header: header.trim().to_string(),
            name,
            unit,
            data: ColumnData::Numbers(values),
        }
    }
    /// The values, or an error naming the file, line and column of the first non-number.
    pub fn values(&self, source: &str) -> Result<&[f64]> {
        match &self.data {
            ColumnData::Numbers(v) => Ok(v),
            ColumnData::NotNumeric { line, text } => Err(Error::input(
                SourcePos::file(source).line(*line).field(&self.header),
                if text.trim().is_empty() {
                    "expected a number, found an empty field".to_string()
                } else {
                    format!("expected a number, found '{}'", text.trim())
                },
            )),
        }
    }
    /// Take the values out (the column keeps an empty vector).
    pub fn take_values(&mut self, source: &str) -> Result<Vec<f64>> {
        self.values(source)?;
        match &mut self.data {
            ColumnData::Numbers(v) => Ok(std::mem::take(v)),
            ColumnData::NotNumeric { .. } => unreachable!("checked above"),
        }
    }
}

impl Table {
    /// A copy holding at most the first `rows` values of each column, and no preamble,
    /// footer or blocks: enough for trying other column names on a table whose data may be
    /// hundreds of MB (messages that ask "would these names resolve the channels?").
    pub fn head(&self, rows: usize) -> Table {
        let columns = self
            .columns
            .iter()
            .map(|c| Column {
                header: c.header.clone(),
                name: c.name.clone(),
                unit: c.unit.clone(),
                data: match &c.data {
                    ColumnData::Numbers(v) => ColumnData::Numbers(v[..v.len().min(rows)].to_vec()),
                    other => other.clone(),
                },
            })
            .collect();
        Table {
            source: self.source.clone(),
            columns,
            rows: self.rows.min(rows),
            layout: self.layout.clone(),
            header_line: self.header_line,
            headerless: self.headerless,
            sample_interval_s: self.sample_interval_s,
            start_time_s: self.start_time_s,
            positions: self.positions.clone(),
            ..Default::default()
        }
    }

    /// Column `k` for messages: its 1-based position in the file and, when other columns share
    /// its header, which of them it is, e.g. `column 14, the first of 2 with that name`.
    pub fn column_label(&self, k: usize) -> String {
        let position = self.position(k);
        let header = &self.columns[k].header;
        let same: Vec<usize> = (0..self.columns.len())
            .filter(|&j| &self.columns[j].header == header)
            .collect();
        if same.len() < 2 {
            return format!("column {position}");
        }
        let i = same.iter().position(|&j| j == k).unwrap_or(0) + 1;
        let nth = match i {
            1 => "first".to_string(),
            2 => "second".to_string(),
            3 => "third".to_string(),
            i => format!("{i}th"),
        };
        format!(
            "column {position}, the {nth} of {} with that name",
            same.len()
        )
    }
    /// Where the header is, for messages about a column: the file and the header's line (the
    /// file alone when it has no header line, headerless text or TDMS).
    pub fn header_pos(&self) -> SourcePos {
        let file = SourcePos::file(&self.source);
        match self.headerless || self.header_line == 0 {
            true => file,
            false => file.line(self.header_line),
        }
    }
    /// 1-based position of column `k` among the fields of a row in the file.
    pub fn position(&self, k: usize) -> usize {
        self.positions.get(k).copied().unwrap_or(k + 1)
    }
    /// The column at 1-based position `position` in the file, if it has values.
    pub fn at_position(&self, position: usize) -> Option<usize> {
        (0..self.columns.len()).find(|&k| self.position(k) == position)
    }
    /// Name the columns in file order (`--columns t_s,Fn_N,Ft_N`): `names[k]` becomes the
    /// header of the column at position k + 1, its unit split off as from any header. Fewer
    /// names than columns leave the rest as they are, and so does an empty name. An error
    /// names the file when there are more names than fields or a name is given twice.
    pub fn name_columns(&mut self, names: &[String]) -> Result<()> {
        let fields = (0..self.columns.len())
            .map(|k| self.position(k))
            .max()
            .unwrap_or(0);
        let pos = || SourcePos::file(&self.source).field("columns");
        if names.len() > fields {
            return Err(Error::input(
                pos(),
                format!(
                    "{} names given ({}) but the file has {fields} columns",
                    names.len(),
                    names.join(",")
                ),
            ));
        }
        let given: Vec<&str> = names
            .iter()
            .map(|n| n.trim())
            .filter(|n| !n.is_empty())
            .collect();
        if let Some(twice) = given
            .iter()
            .find(|n| given.iter().filter(|m| m == n).count() > 1)
        {
            return Err(Error::input(
                pos(),
                format!("'{twice}' is given twice: each column needs its own name"),
            ));
        }
        for (k, name) in names.iter().enumerate() {
            let Some(i) = self.at_position(k + 1).filter(|_| !name.trim().is_empty()) else {
                continue;
            };
            let data =
                std::mem::replace(&mut self.columns[i].data, ColumnData::Numbers(Vec::new()));
            self.columns[i] = Column {
                data,
                ..Column::numbers(name, Vec::new())
            };
        }
        Ok(())
    }
    /// The block (0-based) that row `row` belongs to; 0 for a single table.
    pub fn block_of_row(&self, row: usize) -> usize {
        self.block_starts
            .partition_point(|&s| s <= row)
            .saturating_sub(1)
    }
    /// Header names, for error messages.
    pub fn header_list(&self) -> String {
        self.columns
            .iter()
            .map(|c| c.header.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    }
}

/// Whether `text` is a unit greybox knows in a column name (force, time, speed, length,
/// volts, dimensionless).
pub fn is_known_unit(text: &str) -> bool {
    let t = text.trim();
    !t.is_empty()
        && (ForceUnit::parse_lenient(t).is_some()
            || TimeUnit::parse(t).is_some()
            || SpeedUnit::parse(t).is_some()
            || LengthUnit::parse(t).is_some()
            || matches!(t, "V" | "mV" | "-" | "1" | "%" | "°C" | "K"))
}

/// Whether a field of a units row is a unit: empty, bracketed (`(N)`, `[mm/s]`), a unit
/// greybox knows, or one of the other units rigs print (`gf`, `Hz`, `degC`, …).
pub fn is_unit_token(field: &str) -> bool {
    let t = field.trim();
    let inner = t
        .strip_prefix(['(', '['])
        .and_then(|s| s.strip_suffix([')', ']']))
        .map(str::trim);
    if let Some(inner) = inner {
        return inner.chars().count() <= 16 && inner.parse::<f64>().is_err();
    }
    t.is_empty()
        || is_known_unit(t)
        || matches!(
            t,
            "g" | "kg"
                | "gf"
                | "kgf"
                | "Hz"
                | "kHz"
                | "degC"
                | "deg"
                | "°"
                | "°F"
                | "Pa"
                | "kPa"
                | "MPa"
                | "GPa"
                | "bar"
                | "mbar"
                | "nm"
                | "µm"
                | "Nm"
                | "N.m"
                | "N*m"
                | "mA"
                | "A"
                | "W"
                | "J"
                | "rad"
                | "rad/s"
                | "1/s"
                | "sec"
                | "msec"
                | "ohm"
                | "Ohm"
                | "Ω"
        )
}

/// A unit from a units-row field: brackets removed, `None` when empty.
pub fn unit_token(field: &str) -> Option<String> {
    let t = field.trim();
    let t = t
        .strip_prefix(['(', '['])
        .and_then(|s| s.strip_suffix([')', ']']))
        .unwrap_or(t)
        .trim();
    (!t.is_empty()).then(|| t.to_string())
}

/// Split a header into its name and the unit it states, in the spellings rig software uses:
/// `Fz (N)`, `Fz [kN]`, `Fz_kN`, `Fz/N`, `Speed_mm/s`, `sliding_velocity_m_per_min`,
/// `Velocity (rpm)`. A bracketed unit is taken as written (checked when the column is used);
/// `_` and `/` suffixes only when they are a known unit, so `normal_force` keeps its name.
pub fn split_unit(header: &str) -> (String, Option<String>) {
    let h = header.trim().trim_matches('"').trim();
    for (open, close) in [('(', ')'), ('[', ']'), ('{', '}')] {
        if h.ends_with(close) {
            if let Some(i) = h.rfind(open) {
                let unit = h[i + 1..h.len() - 1].trim();
                let name = h[..i].trim().trim_end_matches(['/', '_', ',']).trim();
                if !name.is_empty() {
                    return (
                        name.to_string(),
                        (!unit.is_empty()).then(|| unit.to_string()),
                    );
                }
            }
        }
    }
    // `_unit` suffixes, the longest known one first (`m_per_min` before `min`)
    for (i, _) in h.match_indices('_') {
        let suffix = &h[i + 1..];
        if is_known_unit(suffix) && i > 0 {
            return (h[..i].to_string(), Some(suffix.to_string()));
        }
    }
    // `name/unit`, where the unit may itself contain a slash (`v/m/s` is unusual; `Ft/N`),
    // and `name, unit` (a quoted `"Load, N"`)
    for (i, _) in h.match_indices('/') {
        let suffix = &h[i + 1..];
        if is_known_unit(suffix) && i > 0 {
            return (h[..i].trim().to_string(), Some(suffix.to_string()));
        }
    }
    if let Some((name, unit)) = h.rsplit_once(',') {
        if is_known_unit(unit) && !name.trim().is_empty() {
            return (name.trim().to_string(), Some(unit.trim().to_string()));
        }
    }
    (h.to_string(), None)
}

/// A name normalised for matching: lower case, `_`, `-` and runs of spaces as one space.
pub fn normalise_name(name: &str) -> String {
    let lower = name.trim().to_lowercase();
    let mut out = String::with_capacity(lower.len());
    for part in lower.split(|c: char| c.is_whitespace() || c == '_' || c == '-') {
        if part.is_empty() {
            continue;
        }
        if !out.is_empty() {
            out.push(' ');
        }
        out.push_str(part);
    }
    out
}

/// Whether a column answers to `wanted` (a mapped name or an alias): the full header, the
/// name without unit, or the name's last dotted component (`DAQ.Fz` answers to `Fz`), all
/// compared after [`normalise_name`].
pub fn column_matches(column: &Column, wanted: &str) -> bool {
    let w = normalise_name(wanted);
    if w.is_empty() {
        return false;
    }
    let name = normalise_name(&column.name);
    if normalise_name(&column.header) == w || name == w {
        return true;
    }
    name.rsplit(['.', ':']).next().map(str::trim) == Some(w.as_str())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A head keeps names, units, positions and the first values, and nothing past them.
    #[test]
    fn a_head_keeps_the_first_rows_only() {
        let t = Table {
            source: "big.csv".into(),
            columns: vec![
                Column::numbers("t (s)", (0..5000).map(f64::from).collect()),
                Column::numbers("Fz (N)", vec![1.0; 5000]),
            ],
            rows: 5000,
            positions: vec![1, 3],
            preamble: vec!["rig".into()],
            ..Default::default()
        };
        let h = t.head(10);
        assert_eq!((h.rows, h.columns.len()), (10, 2));
        assert_eq!(h.columns[0].unit.as_deref(), Some("s"));
        assert_eq!(h.columns[1].data, ColumnData::Numbers(vec![1.0; 10]));
        assert_eq!(h.positions, [1, 3]);
        assert!(h.preamble.is_empty());
        assert_eq!(t.head(10_000).rows, 5000);
    }

    #[test]
    fn unit_spellings() {
        let cases = [
            ("Fz (N)", "Fz", Some("N")),
            (" DAQ.Fz (N)", "DAQ.Fz", Some("N")),
            ("Fz [kN]", "Fz", Some("kN")),
            ("Fz_kN", "Fz", Some("kN")),
            ("Fz/N", "Fz", Some("N")),
            ("Ft/N", "Ft", Some("N")),
            ("Speed_mm/s", "Speed", Some("mm/s")),
            (
                "sliding_velocity_m_per_min",
                "sliding_velocity",
                Some("m_per_min"),
            ),
            ("normal_force_N", "normal_force", Some("N")),
            ("time_s", "time", Some("s")),
            ("Velocity (rpm)", "Velocity", Some("rpm")),
            ("Load, N", "Load", Some("N")),
            ("Time, s", "Time", Some("s")),
            ("a,b", "a,b", None),
            ("v [m/min]", "v", Some("m/min")),
            ("normal_force", "normal_force", None),
            ("Step", "Step", None),
            ("COF", "COF", None),
        ];
        for (h, name, unit) in cases {
            let (n, u) = split_unit(h);
            assert_eq!((n.as_str(), u.as_deref()), (name, unit), "{h}");
        }
    }

    #[test]
    fn matching_ignores_case_spaces_and_prefixes() {
        let c = Column::numbers(" DAQ.Fz (N)", vec![]);
        assert!(column_matches(&c, "fz"));
        assert!(column_matches(&c, "DAQ.Fz"));
        assert!(column_matches(&c, "daq.fz (n)"));
        assert!(!column_matches(&c, "Fx"));
        let c = Column::numbers("Normal Force (N)", vec![]);
        assert!(column_matches(&c, "normal_force"));
    }
}
