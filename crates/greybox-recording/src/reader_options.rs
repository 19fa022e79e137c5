//! How a recording's file is read, apart from which column plays which role: the text
//! dialect (header line, delimiter, decimal comma), the spreadsheet's sheet, the TDMS
//! group, and names for the file's columns. Part of a [`super::ChannelMap`] (its keys sit
//! beside the map's own in a study's `[recording]`).

use serde::{Deserialize, Serialize};

/// Options that configure a reader (the defaults: everything found in the file).
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(default)]
pub struct ReaderOptions {
    /// TDMS group holding the channels (default: `Tribometer`, or the file's only group).
    pub tdms_group: Option<String>,
    /// Text files: 1-based header line (default: found automatically).
    pub header_line: Option<u64>,
    /// Text files: delimiter (default: sniffed).
    pub delimiter: Option<crate::text_table::Delimiter>,
    /// Text files: decimal comma (default: sniffed).
    pub decimal_comma: Option<bool>,
    /// Spreadsheets: sheet name (default: the first sheet holding a table).
    pub sheet: Option<String>,
    /// Names for the file's columns in order (`--columns t_s,Fn_N,Ft_N`), units in the names
    /// as in any header; for a headerless log, whose columns are otherwise `#1`, `#2`, …, and
    /// for renaming the columns of a file with a header alike. Empty: the file's own names.
    pub columns: Vec<String>,
}

impl ReaderOptions {
    /// Options for the text-table reader.
    pub fn text_options(&self) -> crate::text_table::TextOptions {
        crate::text_table::TextOptions {
            header_line: self.header_line,
            delimiter: self.delimiter,
            decimal_comma: self.decimal_comma,
        }
    }
}
