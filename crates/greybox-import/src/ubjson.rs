//! A reader for Universal Binary JSON (UBJSON, Draft 12, ubjson.org), the binary form XGBoost
//! saves models in (`.ubj`), into a [`serde_json::Value`].
//!
//! Supported: every value type (`Z N T F i U I l L d D H C S [ {`), big-endian numbers, and
//! optimised containers (`$` type, `#` count), which XGBoost uses for its float32 and int32
//! arrays. float32 values become the f64 of the same value, so nothing is rounded. Errors
//! name the byte offset.

use greybox_core::budget::Cap;
use greybox_core::{Error, Result, SourcePos};
use serde_json::{Map, Number, Value};

/// Deepest nesting accepted (XGBoost models nest about 8 deep).
const MAX_DEPTH: usize = 64;

/// The fewest bytes a value of type `marker` takes after its marker (0 for null, true,
/// false and no-op; a string or high-precision number has at least a length).
fn min_size(marker: u8) -> u64 {
    match marker {
        b'Z' | b'T' | b'F' | b'N' => 0,
        b'I' => 2,
        b'l' | b'd' => 4,
        b'L' | b'D' => 8,
        b'S' | b'H' => 2,
        _ => 1,
    }
}

struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
    source: &'a str,
}

/// Parse a whole UBJSON document.
pub fn parse(bytes: &[u8], source: &str) -> Result<Value> {
    let mut r = Reader {
        bytes,
        at: 0,
        source,
    };
    let marker = r.marker()?;
    let v = r.value(marker, 0)?;
    if r.at != bytes.len() {
        return Err(r.fail(format!(
            "{} bytes after the end of the document",
            bytes.len() - r.at
        )));
    }
    Ok(v)
}

impl Reader<'_> {
    fn fail(&self, message: impl Into<String>) -> Error {
        Error::input(
            SourcePos::file(self.source).byte(self.at as u64),
            format!("UBJSON: {}", message.into()),
        )
    }

    fn take(&mut self, n: usize) -> Result<&[u8]> {
        if self.bytes.len() - self.at < n {
            return Err(self.fail(format!("needs {n} more bytes, the file ends")));
        }
        let s = &self.bytes[self.at..self.at + n];
        self.at += n;
        Ok(s)
    }

    fn array<const N: usize>(&mut self) -> Result<[u8; N]> {
        let mut a = [0u8; N];
        a.copy_from_slice(self.take(N)?);
        Ok(a)
    }

    /// The next type marker, skipping no-ops.
    fn marker(&mut self) -> Result<u8> {
        loop {
            let m = self.take(1)?[0];
            if m != b'N' {
                return Ok(m);
            }
        }
    }

    fn integer(&mut self, marker: u8) -> Result<i64> {
        Ok(match marker {
            b'i' => i8::from_be_bytes(self.array()?) as i64,
            b'U' => u8::from_be_bytes(self.array()?) as i64,
            b'I' => i16::from_be_bytes(self.array()?) as i64,
            b'l' => i32::from_be_bytes(self.array()?) as i64,
            b'L' => i64::from_be_bytes(self.array()?),
            m => {
                return Err(self.fail(format!("expected an integer marker, found {:?}", m as char)))
            }
        })
    }

    fn length(&mut self) -> Result<usize> {
        let m = self.marker()?;
        let n = self.integer(m)?;
        // a string's length is checked by `take`, a container's count by `check_count`
        usize::try_from(n)
            .ok()
            .ok_or_else(|| self.fail(format!("length {n} is not possible here")))
    }

    /// Refuses a container count the rest of the input cannot hold, before any element is
    /// read: each element takes at least [`min_size`] bytes (a key at least 2 more); elements
    /// that take none (typed null/true/false) are capped by [`Cap::ArrayLen`].
    fn check_count(&self, n: usize, typed: Option<u8>, object: bool) -> Result<()> {
        let per = typed.map_or(1, min_size) + if object { 2 } else { 0 };
        let left = (self.bytes.len() - self.at) as u64;
        if per == 0 {
            let what = typed.map_or('?', |t| t as char);
            return Cap::ArrayLen
                .check(n as u64, || {
                    format!("a typed array of {n} '{what}' elements (which take no bytes each)")
                })
                .map_err(|m| self.fail(m));
        }
        let need = (n as u64).saturating_mul(per);
        if need > left {
            return Err(self.fail(format!(
                "a container of {n} elements needs at least {need} bytes, only {left} are left in the file"
            )));
        }
        Ok(())
    }

    fn string(&mut self) -> Result<String> {
        let n = self.length()?;
        let b = self.take(n)?.to_vec();
        String::from_utf8(b).map_err(|_| self.fail("a string is not UTF-8"))
    }

    fn float(&self, v: f64) -> Result<Value> {
        Number::from_f64(v)
            .map(Value::Number)
            .ok_or_else(|| self.fail(format!("{v} is not a finite number")))
    }

    fn value(&mut self, marker: u8, depth: usize) -> Result<Value> {
        if depth > MAX_DEPTH {
            return Err(self.fail(format!("nested deeper than {MAX_DEPTH}")));
        }
        match marker {
            b'Z' => Ok(Value::Null),
            b'T' => Ok(Value::Bool(true)),
            b'F' => Ok(Value::Bool(false)),
            b'i' | b'U' | b'I' | b'l' | b'L' => Ok(Value::from(self.integer(marker)?)),
            b'd' => {
                let v = f32::from_be_bytes(self.array()?) as f64;
                self.float(v)
            }
            b'D' => {
                let v = f64::from_be_bytes(self.array()?);
                self.float(v)
            }
            b'H' => {
                let s = self.string()?;
                let v: f64 = s
                    .parse()
                    .map_err(|_| self.fail(format!("'{s}' is not a number")))?;
                self.float(v)
            }
            b'C' => Ok(Value::String((self.take(1)?[0] as char).to_string())),
            b'S' => Ok(Value::String(self.string()?)),
            b'[' => self.container(depth, false),
            b'{' => self.container(depth, true),
            m => Err(self.fail(format!("unknown type marker {:?}", m as char))),
        }
    }

    /// An array or object, with or without the optimised `$`/`#` header.
    fn container(&mut self, depth: usize, object: bool) -> Result<Value> {
        let mut typed = None;
        let mut count = None;
        if self.bytes.get(self.at) == Some(&b'$') {
            self.at += 1;
            typed = Some(self.take(1)?[0]);
            if self.bytes.get(self.at) != Some(&b'#') {
                return Err(self.fail("a typed container ($) needs a count (#)"));
            }
        }
        if self.bytes.get(self.at) == Some(&b'#') {
            self.at += 1;
            let n = self.length()?;
            self.check_count(n, typed, object)?;
            count = Some(n);
        }
        let mut items = Vec::new();
        let mut fields = Map::new();
        let mut k = 0;
        loop {
            match count {
                Some(n) if k == n => break,
                None => {
                    let end = if object { b'}' } else { b']' };
                    if self.bytes.get(self.at) == Some(&end) {
                        self.at += 1;
                        break;
                    }
                }
                _ => {}
            }
            let key = if object { Some(self.string()?) } else { None };
            let m = match typed {
                Some(t) => t,
                None => self.marker()?,
            };
            let v = self.value(m, depth + 1)?;
            match key {
                Some(key) => {
                    fields.insert(key, v);
                }
                None => items.push(v),
            }
            k += 1;
        }
        Ok(if object {
            Value::Object(fields)
        } else {
            Value::Array(items)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_plain_and_typed_containers() {
        // {"a": [1, 2.5], "b": "x", "c": [$d#i 2: 0.5, -1.0], "d": T}
        let mut b = vec![b'{'];
        b.extend([b'i', 1, b'a', b'[', b'i', 1, b'D']);
        b.extend(2.5f64.to_be_bytes());
        b.push(b']');
        b.extend([b'i', 1, b'b', b'S', b'i', 1, b'x']);
        b.extend([b'i', 1, b'c', b'[', b'$', b'd', b'#', b'i', 2]);
        b.extend(0.5f32.to_be_bytes());
        b.extend((-1.0f32).to_be_bytes());
        b.extend([b'i', 1, b'd', b'T', b'}']);
        let v = parse(&b, "t.ubj").unwrap();
        assert_eq!(
            v,
            serde_json::json!({"a": [1, 2.5], "b": "x", "c": [0.5, -1.0], "d": true})
        );
    }

    #[test]
    fn counts_are_bounded_by_the_bytes_left_and_the_array_cap() {
        // 80 M nulls in a typed array, as in a 10 MB file: refused by max_array_len
        let mut b = vec![b'[', b'$', b'Z', b'#', b'l'];
        b.extend(80_000_000i32.to_be_bytes());
        b.resize(10 << 20, b'N');
        let e = parse(&b, "m.ubj").unwrap_err().to_string();
        assert!(
            e.contains("m.ubj") && e.contains("80000000") && e.contains("max_array_len"),
            "{e}"
        );
        // 1000 float64 in a typed array with 16 bytes left: refused by the bytes left
        let mut b = vec![b'[', b'$', b'D', b'#', b'I'];
        b.extend(1000i16.to_be_bytes());
        b.extend([0u8; 16]);
        let e = parse(&b, "m.ubj").unwrap_err().to_string();
        assert!(e.contains("8000 bytes") && e.contains("16 are left"), "{e}");
        // a few typed nulls are fine
        let b = [b'[', b'$', b'Z', b'#', b'i', 3];
        assert_eq!(
            parse(&b, "m.ubj").unwrap(),
            serde_json::json!([null, null, null])
        );
    }

    #[test]
    fn truncated_input_names_the_byte() {
        let e = parse(&[b'[', b'D', 0, 0], "t.ubj").unwrap_err().to_string();
        assert!(e.contains("t.ubj") && e.contains("byte"), "{e}");
    }
}
