//! The reader's dialect vocabulary: the delimiter, the user's options, and how many lines sniffing
//! reads.

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
    pub(super) const ALL: [Delimiter; 4] = [
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
    pub(super) fn byte(self) -> Option<u8> {
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
pub(super) const SNIFF_LINES: usize = 200;

/// Numeric rows that must follow a header for it to count.
pub(super) const CONFIRM_ROWS: usize = 3;
