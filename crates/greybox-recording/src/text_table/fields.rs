//! Lines and fields of a text table: line ends, quoting, splitting at the delimiter, number parsing
//! (decimal comma included), header bytes decoded.

use super::options::Delimiter;

/// One line of the file: its 1-based number and its bytes without the line end.
#[derive(Clone, Copy)]
pub(super) struct Line<'a> {
    pub(super) number: u64,
    pub(super) text: &'a [u8],
}

pub(super) fn strip_cr(l: &[u8]) -> &[u8] {
    l.strip_suffix(b"\r").unwrap_or(l)
}

pub(super) fn is_blank(l: &[u8]) -> bool {
    l.iter().all(|b| b.is_ascii_whitespace())
}

pub(super) fn trim(b: &[u8]) -> &[u8] {
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

pub(super) fn unquote(b: &[u8]) -> &[u8] {
    let t = trim(b);
    if t.len() >= 2 && t[0] == b'"' && t[t.len() - 1] == b'"' {
        &t[1..t.len() - 1]
    } else {
        t
    }
}

/// Split a line into fields. Double quotes protect a delimiter inside a field (`"Load, N"`,
/// `"1,5"`); a line without quotes is split at every delimiter.
pub(super) fn split_fields(line: &[u8], d: Delimiter, out: &mut Vec<(usize, usize)>) {
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
pub(super) fn parse_number(field: &[u8], decimal_comma: bool) -> Option<f64> {
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
pub(super) fn quoted_decimal_comma(t: &[u8]) -> bool {
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
pub(super) fn decode(bytes: &[u8]) -> std::borrow::Cow<'_, str> {
    match std::str::from_utf8(bytes) {
        Ok(s) => std::borrow::Cow::Borrowed(s),
        Err(_) => std::borrow::Cow::Owned(bytes.iter().map(|&b| char::from(b)).collect()),
    }
}

/// Split a header line into names; double quotes may protect delimiters inside a name
/// ([`split_fields`]) and are removed.
pub(super) fn split_header(line: &[u8], d: Delimiter) -> Vec<String> {
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

pub(super) fn clip(s: &str) -> String {
    if s.chars().count() > 60 {
        format!("{}…", s.chars().take(60).collect::<String>())
    } else {
        s.to_string()
    }
}
