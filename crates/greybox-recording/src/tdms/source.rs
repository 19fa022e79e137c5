//! The bytes of a TDMS file: a memory map or a buffer, windows read from a file, and a cursor over
//! a segment's metadata.

use super::format::{PropValue, T_BOOL, T_STRING, T_TIMESTAMP};
use greybox_core::{Error, Result, SourcePos};
use std::path::Path;

/// Size thresholds of the reader (tests shrink them to reach every path with small files).
pub(super) struct Tuning {
    /// Files shorter than this are read whole into memory, then parsed.
    pub(super) whole_read_max: usize,
    /// Raw data of at least this many bytes is converted on all cores.
    pub(super) parallel_min: usize,
    /// Bytes per parallel piece of one channel's raw data.
    pub(super) piece_bytes: usize,
    /// From a file, chunks whose channels average at least this many bytes are read channel
    /// by channel straight into place; smaller ones through a buffer of `buffer_bytes`.
    pub(super) direct_min: usize,
    pub(super) buffer_bytes: usize,
    /// Lead-ins and metadata are read this many bytes at a time while segments are small
    /// (one read then covers many of them), exactly otherwise.
    pub(super) read_ahead: usize,
}

impl Tuning {
    pub(super) const DEFAULT: Tuning = Tuning {
        whole_read_max: 1 << 20,
        parallel_min: 4 << 20,
        piece_bytes: 1 << 20,
        direct_min: 64 << 10,
        buffer_bytes: 1 << 20,
        read_ahead: 16 << 10,
    };
}

/// Where the bytes come from: a buffer, or a file read with positioned reads.
pub(super) enum Source<'a> {
    Mem(&'a [u8]),
    #[cfg(any(unix, windows))]
    File {
        file: &'a std::fs::File,
        path: &'a Path,
        len: usize,
    },
}

impl<'a> Source<'a> {
    pub(super) fn len(&self) -> usize {
        match self {
            Source::Mem(b) => b.len(),
            #[cfg(any(unix, windows))]
            Source::File { len, .. } => *len,
        }
    }
    /// Fill `buf` with the bytes from `at` on.
    pub(super) fn read_into(&self, at: usize, buf: &mut [u8]) -> Result<()> {
        match self {
            Source::Mem(b) => {
                let src = b.get(at..at + buf.len()).ok_or_else(|| {
                    Error::input(
                        SourcePos::file("").byte(at as u64),
                        "raw data lies beyond the end of the buffer",
                    )
                })?;
                buf.copy_from_slice(src);
                Ok(())
            }
            #[cfg(any(unix, windows))]
            Source::File { file, path, .. } => {
                read_exact_at(file, buf, at as u64).map_err(|e| Error::io(*path, e))
            }
        }
    }
}

/// A window on the source: from a file, bytes are read at least `ahead` at a time, so that
/// a run of small segments costs one read rather than one per lead-in, metadata and raw
/// data block. From a buffer, no copy.
#[derive(Default)]
pub(super) struct Window {
    pub(super) buf: Vec<u8>,
    pub(super) start: usize,
}

impl Window {
    /// Bytes `start..end` (within the source's length).
    pub(super) fn get<'x>(
        &'x mut self,
        src: &'x Source<'_>,
        start: usize,
        end: usize,
        ahead: usize,
    ) -> Result<&'x [u8]> {
        match src {
            Source::Mem(b) => Ok(b.get(start..end).unwrap_or(&[])),
            #[cfg(any(unix, windows))]
            Source::File { len, .. } => {
                if start < self.start || end > self.start + self.buf.len() {
                    let stop = end.max(start.saturating_add(ahead).min(*len));
                    // no need to clear: the read overwrites it all
                    self.buf.resize(stop - start, 0);
                    src.read_into(start, &mut self.buf)?;
                    self.start = start;
                }
                Ok(self
                    .buf
                    .get(start - self.start..end - self.start)
                    .unwrap_or(&[]))
            }
        }
    }
}

#[cfg(unix)]
pub(super) fn read_exact_at(file: &std::fs::File, buf: &mut [u8], at: u64) -> std::io::Result<()> {
    std::os::unix::fs::FileExt::read_exact_at(file, buf, at)
}

#[cfg(windows)]
pub(super) fn read_exact_at(
    file: &std::fs::File,
    mut buf: &mut [u8],
    mut at: u64,
) -> std::io::Result<()> {
    use std::os::windows::fs::FileExt;
    while !buf.is_empty() {
        match file.seek_read(buf, at) {
            Ok(0) => {
                return Err(std::io::Error::new(
                    std::io::ErrorKind::UnexpectedEof,
                    "the file got shorter while being read",
                ))
            }
            Ok(n) => {
                buf = &mut buf[n..];
                at += n as u64;
            }
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return Err(e),
        }
    }
    Ok(())
}

/// Reads metadata from `bytes`, which hold the file's bytes from offset `base` on; `pos`
/// and `end` are file offsets (errors name them).
pub(super) struct Cursor<'a> {
    pub(super) bytes: &'a [u8],
    pub(super) base: usize,
    pub(super) pos: usize,
    pub(super) end: usize,
    pub(super) big: bool,
    pub(super) source: &'a str,
    pub(super) segment: usize,
}

impl Cursor<'_> {
    pub(super) fn take(&mut self, n: usize) -> Result<&[u8]> {
        let at = self.pos - self.base;
        let s = match self.bytes.get(at..at.saturating_add(n)) {
            Some(s) if self.end - self.pos >= n => s,
            _ => {
                return Err(Error::input(
                    SourcePos::file(self.source).byte(self.pos as u64),
                    format!(
                        "segment {}: truncated: needed {n} more bytes, {} left",
                        self.segment,
                        self.end - self.pos
                    ),
                ))
            }
        };
        self.pos += n;
        Ok(s)
    }
    pub(super) fn arr<const N: usize>(&mut self) -> Result<[u8; N]> {
        let mut a: [u8; N] = self.take(N)?.try_into().expect("N bytes");
        if self.big {
            a.reverse();
        }
        Ok(a)
    }
    pub(super) fn u32(&mut self) -> Result<u32> {
        Ok(u32::from_le_bytes(self.arr()?))
    }
    pub(super) fn u64(&mut self) -> Result<u64> {
        Ok(u64::from_le_bytes(self.arr()?))
    }
    pub(super) fn string(&mut self) -> Result<String> {
        let at = self.pos;
        let n = self.u32()? as usize;
        let b = self.take(n)?;
        String::from_utf8(b.to_vec()).map_err(|_| {
            Error::input(
                SourcePos::file(self.source).byte(at as u64),
                format!("segment {}: string is not UTF-8", self.segment),
            )
        })
    }
    pub(super) fn timestamp(&mut self) -> Result<f64> {
        // little-endian layout: u64 fraction (2^-64 s), then i64 seconds since 1904
        let (frac, secs) = if self.big {
            let s = i64::from_le_bytes(self.arr()?);
            (u64::from_le_bytes(self.arr()?), s)
        } else {
            let f = u64::from_le_bytes(self.arr()?);
            (f, i64::from_le_bytes(self.arr()?))
        };
        Ok(secs as f64 + frac as f64 / 18_446_744_073_709_551_616.0)
    }
    pub(super) fn value(&mut self, dtype: u32) -> Result<f64> {
        Ok(match dtype {
            1 => i8::from_le_bytes(self.arr()?) as f64,
            2 => i16::from_le_bytes(self.arr()?) as f64,
            3 => i32::from_le_bytes(self.arr()?) as f64,
            4 => i64::from_le_bytes(self.arr()?) as f64,
            5 => u8::from_le_bytes(self.arr()?) as f64,
            6 => u16::from_le_bytes(self.arr()?) as f64,
            7 => u32::from_le_bytes(self.arr()?) as f64,
            8 => u64::from_le_bytes(self.arr()?) as f64,
            9 | 0x19 => f32::from_le_bytes(self.arr()?) as f64,
            10 | 0x1A => f64::from_le_bytes(self.arr()?),
            T_BOOL => (self.take(1)?[0] != 0) as u8 as f64,
            T_TIMESTAMP => self.timestamp()?,
            other => {
                return Err(Error::input(
                    SourcePos::file(self.source).byte(self.pos as u64),
                    format!(
                        "segment {}: unsupported data type 0x{other:x}",
                        self.segment
                    ),
                ))
            }
        })
    }
    pub(super) fn property(&mut self, ptype: u32) -> Result<PropValue> {
        Ok(match ptype {
            1..=4 => PropValue::Int(self.value(ptype)? as i64),
            5..=8 => PropValue::UInt(match ptype {
                8 => u64::from_le_bytes(self.arr()?),
                _ => self.value(ptype)? as u64,
            }),
            9 | 10 | 0x19 | 0x1A => PropValue::Float(self.value(ptype)?),
            T_STRING => PropValue::Str(self.string()?),
            T_BOOL => PropValue::Bool(self.take(1)?[0] != 0),
            T_TIMESTAMP => PropValue::Timestamp(self.timestamp()?),
            other => {
                return Err(Error::input(
                    SourcePos::file(self.source).byte(self.pos as u64),
                    format!(
                        "segment {}: unsupported property type 0x{other:x}",
                        self.segment
                    ),
                ))
            }
        })
    }
}
