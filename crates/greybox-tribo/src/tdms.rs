//! LabVIEW TDMS files: a strict reader and a writer, implemented from NI's published
//! description of the format ("TDMS File Format Internal Structure", ni.com).
//!
//! Supported: multi-segment files, incremental metadata (objects added/updated between
//! segments, "same index as previous segment", segments without metadata), contiguous and
//! interleaved raw data, little- and big-endian segments, every fixed-size numeric type
//! (read as f64), timestamps, and properties of all common types. String channels are
//! skipped. DAQmx raw data is rejected with a clear error.
//!
//! Reading takes two passes: the first checks every lead-in and metadata block and notes
//! where each object's values lie (runs of same-shaped segments, as written a few values at
//! a time, are kept as one run); the second allocates each channel once at its exact length
//! and converts the raw data into place, on all cores for large files. From a file, big
//! blocks are read straight into the channels (no whole-file buffer, no copy for
//! little-endian doubles).
//!
//! Why our own code rather than the `tdms` crate: greybox must also *write* TDMS (the
//! virtual tribometer), and every malformed or truncated file must yield an error that
//! names the segment and byte offset, never a panic.

use crate::recording::{ChannelMap, Recording, DEFAULT_TDMS_GROUP};
use crate::table::{split_unit, Column, ColumnData, Table};
use greybox_core::atomic::write_atomic;
use greybox_core::{Error, Result, SourcePos};
use rayon::prelude::*;
use std::collections::HashMap;
use std::io::Write;
use std::ops::Range;
use std::path::Path;

const TOC_META_DATA: u32 = 1 << 1;
const TOC_NEW_OBJ_LIST: u32 = 1 << 2;
const TOC_RAW_DATA: u32 = 1 << 3;
const TOC_INTERLEAVED: u32 = 1 << 5;
const TOC_BIG_ENDIAN: u32 = 1 << 6;
const TOC_DAQMX: u32 = 1 << 7;
const LEAD_IN: usize = 28;
const NO_RAW_DATA: u32 = 0xFFFF_FFFF;
const SAME_AS_PREVIOUS: u32 = 0;

const T_STRING: u32 = 0x20;
const T_BOOL: u32 = 0x21;
const T_TIMESTAMP: u32 = 0x44;
const T_F64: u32 = 10;

/// A property value.
#[derive(Debug, Clone, PartialEq)]
pub enum PropValue {
    Int(i64),
    UInt(u64),
    Float(f64),
    Str(String),
    Bool(bool),
    /// Seconds since 1904-01-01 00:00 UTC.
    Timestamp(f64),
}

impl PropValue {
    pub fn as_f64(&self) -> Option<f64> {
        match self {
            PropValue::Int(v) => Some(*v as f64),
            PropValue::UInt(v) => Some(*v as f64),
            PropValue::Float(v) => Some(*v),
            PropValue::Timestamp(v) => Some(*v),
            _ => None,
        }
    }
    pub fn as_str(&self) -> Option<&str> {
        match self {
            PropValue::Str(s) => Some(s),
            _ => None,
        }
    }
}

/// A TDMS object (root, group or channel) with its properties and numeric data.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TdmsObject {
    pub path: String,
    pub properties: Vec<(String, PropValue)>,
    /// TDMS data type code of the raw data, if the object has any.
    pub data_type: Option<u32>,
    /// Numeric raw data converted to f64.
    pub data: Vec<f64>,
}

impl TdmsObject {
    pub fn property(&self, name: &str) -> Option<&PropValue> {
        self.properties
            .iter()
            .rev()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v)
    }
    fn set_property(&mut self, name: String, value: PropValue) {
        match self.properties.iter_mut().find(|(n, _)| *n == name) {
            Some(slot) => slot.1 = value,
            None => self.properties.push((name, value)),
        }
    }
}

/// A whole TDMS file in memory.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TdmsFile {
    pub source: String,
    pub objects: Vec<TdmsObject>,
}

/// Object path of a channel: `/'group'/'channel'` (single quotes doubled inside names).
pub fn channel_path(group: &str, channel: &str) -> String {
    format!(
        "/'{}'/'{}'",
        group.replace('\'', "''"),
        channel.replace('\'', "''")
    )
}
pub fn group_path(group: &str) -> String {
    format!("/'{}'", group.replace('\'', "''"))
}

impl TdmsFile {
    pub fn object(&self, path: &str) -> Option<&TdmsObject> {
        self.objects.iter().find(|o| o.path == path)
    }
    pub fn channel(&self, group: &str, channel: &str) -> Option<&TdmsObject> {
        self.object(&channel_path(group, channel))
    }
    /// Names of the channels of a group.
    pub fn channel_names(&self, group: &str) -> Vec<String> {
        let prefix = format!("{}/", group_path(group));
        self.objects
            .iter()
            .filter_map(|o| o.path.strip_prefix(&prefix))
            .map(|c| c.trim_matches('\'').replace("''", "'"))
            .collect()
    }

    /// Read a TDMS file. Files of a megabyte or more are not loaded whole: after a first
    /// pass over the segments' lead-ins and metadata, every channel gets its exact number of
    /// values allocated once and its raw data is read straight into place (little-endian
    /// doubles without any conversion), large files on all cores.
    pub fn read(path: &Path) -> Result<Self> {
        Self::read_tuned(path, &Tuning::DEFAULT)
    }

    fn read_tuned(path: &Path, tuning: &Tuning) -> Result<Self> {
        let source = path.display().to_string();
        let (file, len) = greybox_core::budget::open_recording(path)?;
        #[cfg(any(unix, windows))]
        if len >= tuning.whole_read_max as u64 {
            if let Ok(len) = usize::try_from(len) {
                let src = Source::File {
                    file: &file,
                    path,
                    len,
                };
                return parse_source(&src, &source, tuning);
            }
        }
        drop(file);
        let bytes = greybox_core::budget::read_recording_bytes(path)?;
        parse_source(&Source::Mem(&bytes), &source, tuning)
    }

    /// Parse a TDMS byte buffer. `source` names the file in errors.
    pub fn parse(bytes: &[u8], source: &str) -> Result<Self> {
        parse_source(&Source::Mem(bytes), source, &Tuning::DEFAULT)
    }
}

/// Size thresholds of the reader (tests shrink them to reach every path with small files).
struct Tuning {
    /// Files shorter than this are read whole into memory, then parsed.
    whole_read_max: usize,
    /// Raw data of at least this many bytes is converted on all cores.
    parallel_min: usize,
    /// Bytes per parallel piece of one channel's raw data.
    piece_bytes: usize,
    /// From a file, chunks whose channels average at least this many bytes are read channel
    /// by channel straight into place; smaller ones through a buffer of `buffer_bytes`.
    direct_min: usize,
    buffer_bytes: usize,
    /// Lead-ins and metadata are read this many bytes at a time while segments are small
    /// (one read then covers many of them), exactly otherwise.
    read_ahead: usize,
}

impl Tuning {
    const DEFAULT: Tuning = Tuning {
        whole_read_max: 1 << 20,
        parallel_min: 4 << 20,
        piece_bytes: 1 << 20,
        direct_min: 64 << 10,
        buffer_bytes: 1 << 20,
        read_ahead: 16 << 10,
    };
}

/// Where the bytes come from: a buffer, or a file read with positioned reads.
enum Source<'a> {
    Mem(&'a [u8]),
    #[cfg(any(unix, windows))]
    File {
        file: &'a std::fs::File,
        path: &'a Path,
        len: usize,
    },
}

impl<'a> Source<'a> {
    fn len(&self) -> usize {
        match self {
            Source::Mem(b) => b.len(),
            #[cfg(any(unix, windows))]
            Source::File { len, .. } => *len,
        }
    }
    /// Fill `buf` with the bytes from `at` on.
    fn read_into(&self, at: usize, buf: &mut [u8]) -> Result<()> {
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
struct Window {
    buf: Vec<u8>,
    start: usize,
}

impl Window {
    /// Bytes `start..end` (within the source's length).
    fn get<'x>(
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
fn read_exact_at(file: &std::fs::File, buf: &mut [u8], at: u64) -> std::io::Result<()> {
    std::os::unix::fs::FileExt::read_exact_at(file, buf, at)
}

#[cfg(windows)]
fn read_exact_at(file: &std::fs::File, mut buf: &mut [u8], mut at: u64) -> std::io::Result<()> {
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

fn parse_source(src: &Source, source: &str, tuning: &Tuning) -> Result<TdmsFile> {
    let (mut file, plan) = scan(src, source, tuning)?;
    plan.fill(src, source, &mut file.objects, tuning)?;
    Ok(file)
}

/// One object's raw data in each chunk of a segment.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Entry {
    obj: usize,
    idx: RawIndex,
}

/// Raw data of `repeat` segments of the same shape, `step` bytes apart from `start` on,
/// validated: each holds `n_chunks` blocks of `chunk` bytes laid out as
/// `Plan::layouts[layout]`. Interleaved data is counted in rows: one block per row, one
/// value per object. (Files written a few values at a time are long runs of such segments.)
#[derive(Debug)]
struct Run {
    start: usize,
    step: usize,
    repeat: usize,
    n_chunks: usize,
    chunk: usize,
    big: bool,
    interleaved: bool,
    layout: usize,
}

impl Run {
    /// File offset of block `b` (counted over all the run's segments).
    fn block_pos(&self, b: usize) -> usize {
        self.start + (b / self.n_chunks) * self.step + (b % self.n_chunks) * self.chunk
    }
}

/// What the first pass found: where every object's values are.
#[derive(Debug, Default)]
struct Plan {
    runs: Vec<Run>,
    /// Raw data layouts (objects with a non-zero byte count, in order), shared by the
    /// segments that reuse the previous one's.
    layouts: Vec<Vec<Entry>>,
}

/// Where one object's values lie in each block of a run: `n` values `stride` bytes apart,
/// from `offset` in the block.
#[derive(Debug, Clone, Copy)]
struct Col {
    obj: usize,
    dtype: u32,
    n: usize,
    offset: usize,
    stride: usize,
}

/// The numeric columns of a run's blocks.
fn columns(layout: &[Entry], interleaved: bool) -> Vec<Col> {
    let mut offset = 0;
    let mut cols = Vec::with_capacity(layout.len());
    for e in layout {
        let size = type_size(e.idx.dtype);
        if let Some(size) = size {
            cols.push(Col {
                obj: e.obj,
                dtype: e.idx.dtype,
                n: if interleaved {
                    1
                } else {
                    e.idx.n_values as usize
                },
                offset,
                stride: size,
            });
        }
        offset += match (interleaved, size) {
            (true, Some(size)) => size,
            _ => e.idx.bytes as usize,
        };
    }
    cols
}

/// An error at byte `at` of segment `segment` of `source`.
fn segment_error(source: &str, segment: usize, at: usize, msg: String) -> Error {
    Error::input(
        SourcePos::file(source).byte(at as u64),
        format!("segment {segment}: {msg}"),
    )
}

/// One segment's lead-in, checked: its table of contents and where its metadata and raw
/// data lie in the file.
struct LeadIn {
    toc: u32,
    big: bool,
    /// First byte after the lead-in (the metadata).
    seg_start: usize,
    /// First byte of the raw data.
    meta_end: usize,
    /// First byte after the segment.
    seg_end: usize,
}

/// Parse and check the 28-byte lead-in of the segment at `pos` of a `len`-byte file.
fn read_lead_in(
    lead_in: &[u8],
    pos: usize,
    len: usize,
    source: &str,
    segment: usize,
) -> Result<LeadIn> {
    let err = |at: usize, msg: String| segment_error(source, segment, at, msg);
    let tag = &lead_in[..4];
    if tag != b"TDSm" {
        let hint = if tag == b"TDSh" {
            " (this is a .tdms_index file; read the .tdms file)"
        } else {
            ""
        };
        return Err(err(
            pos,
            format!(
                "expected segment tag 'TDSm', found {:?}{hint}",
                String::from_utf8_lossy(tag)
            ),
        ));
    }
    let toc = u32::from_le_bytes(lead_in[4..8].try_into().expect("4 bytes"));
    let big = toc & TOC_BIG_ENDIAN != 0;
    let mut lead = Cursor {
        bytes: lead_in,
        base: pos,
        pos: pos + 8,
        end: pos + LEAD_IN,
        big,
        source,
        segment,
    };
    let version = lead.u32()?;
    if version != 4712 && version != 4713 {
        return Err(err(
            pos + 8,
            format!("unsupported TDMS version {version} (expected 4712 or 4713)"),
        ));
    }
    let next_offset = lead.u64()?;
    let raw_offset = lead.u64()?;
    let seg_start = pos + LEAD_IN;
    let seg_end = if next_offset == u64::MAX {
        len // segment left open by an interrupted writer: data runs to the end of file
    } else {
        match (seg_start as u64).checked_add(next_offset) {
            Some(end) if end <= len as u64 => end as usize,
            _ => {
                return Err(err(
                    pos,
                    format!("truncated: the segment declares {next_offset} bytes after its lead-in, the file has {}", len - seg_start),
                ))
            }
        }
    };
    if raw_offset > (seg_end - seg_start) as u64 {
        return Err(err(
            pos + 20,
            format!("raw data offset {raw_offset} lies beyond the segment end"),
        ));
    }
    if toc & TOC_DAQMX != 0 {
        return Err(err(pos, "DAQmx raw data is not supported".into()));
    }
    Ok(LeadIn {
        toc,
        big,
        seg_start,
        meta_end: seg_start + raw_offset as usize,
        seg_end,
    })
}

/// The objects met so far, and which of them carry raw data in the current segment.
struct Objects {
    file: TdmsFile,
    index_of: HashMap<String, usize>,
    /// Each object's last raw data index (for "same as previous").
    last_index: HashMap<usize, RawIndex>,
    /// The objects with raw data in the current segment, in order.
    active: Vec<(usize, RawIndex)>,
    /// Whether `active` changed since the last layout was recorded.
    active_changed: bool,
}

impl Objects {
    /// Read a segment's metadata (`c` spans it): new objects, raw data indices, properties.
    fn read_meta(&mut self, c: &mut Cursor, new_list: bool) -> Result<()> {
        self.active_changed = true;
        if new_list {
            self.active.clear();
        }
        let n_objects = c.u32()?;
        for _ in 0..n_objects {
            let at = c.pos;
            let path = c.string()?;
            let obj = self.object(&path);
            let index_len = c.u32()?;
            self.read_raw_index(c, obj, &path, at, index_len)?;
            let n_props = c.u32()?;
            for _ in 0..n_props {
                let name = c.string()?;
                let ptype = c.u32()?;
                let value = c.property(ptype)?;
                self.file.objects[obj].set_property(name, value);
            }
        }
        Ok(())
    }

    /// The index of the object `path`, added on first sight.
    fn object(&mut self, path: &str) -> usize {
        let objects = &mut self.file.objects;
        *self.index_of.entry(path.to_string()).or_insert_with(|| {
            objects.push(TdmsObject {
                path: path.to_string(),
                ..Default::default()
            });
            objects.len() - 1
        })
    }

    /// An object's raw data index (`index_len` already read): none, the previous one, or a
    /// new one (data type, dimension, value count, and for strings the byte count).
    fn read_raw_index(
        &mut self,
        c: &mut Cursor,
        obj: usize,
        path: &str,
        at: usize,
        index_len: u32,
    ) -> Result<()> {
        let (source, segment) = (c.source, c.segment);
        let err = |msg: String| segment_error(source, segment, at, msg);
        match index_len {
            NO_RAW_DATA => self.active.retain(|(o, _)| *o != obj),
            SAME_AS_PREVIOUS => {
                let idx = *self.last_index.get(&obj).ok_or_else(|| {
                    err(format!(
                        "object {path} reuses a previous raw data index but has none"
                    ))
                })?;
                upsert(&mut self.active, obj, idx);
            }
            0x6912_0000 | 0x6913_0000 => {
                return Err(err(format!(
                    "object {path}: DAQmx raw data is not supported"
                )))
            }
            _ => {
                let dtype = c.u32()?;
                let dim = c.u32()?;
                if dim != 1 {
                    return Err(err(format!(
                        "object {path}: array dimension {dim}, TDMS allows only 1"
                    )));
                }
                let n_values = c.u64()?;
                let bytes_total = if dtype == T_STRING {
                    c.u64()?
                } else {
                    let size = type_size(dtype).ok_or_else(|| {
                        err(format!("object {path}: unsupported data type 0x{dtype:x}"))
                    })?;
                    n_values
                        .checked_mul(size as u64)
                        .ok_or_else(|| err("value count overflows".into()))?
                };
                let idx = RawIndex {
                    dtype,
                    n_values,
                    bytes: bytes_total,
                };
                if let Some(prev) = self.file.objects[obj].data_type {
                    if prev != dtype {
                        return Err(err(format!(
                            "object {path} changes data type from 0x{prev:x} to 0x{dtype:x}"
                        )));
                    }
                }
                self.file.objects[obj].data_type = Some(dtype);
                self.last_index.insert(obj, idx);
                upsert(&mut self.active, obj, idx);
            }
        }
        Ok(())
    }
}

impl Plan {
    /// Record where a segment's raw data lie: its chunks checked against the active objects,
    /// appended to the current run when it continues it at the same step.
    fn add_raw_data(
        &mut self,
        objects: &mut Objects,
        seg: &LeadIn,
        source: &str,
        segment: usize,
    ) -> Result<()> {
        let err = |msg: String| segment_error(source, segment, seg.meta_end, msg);
        let active = &objects.active;
        let chunk = active
            .iter()
            .try_fold(0u64, |sum, (_, i)| sum.checked_add(i.bytes))
            .ok_or_else(|| err("raw data chunk size overflows".into()))?;
        let data_len = (seg.seg_end - seg.meta_end) as u64;
        if chunk == 0 {
            return Ok(()); // nothing to read
        }
        if !data_len.is_multiple_of(chunk) {
            return Err(err(format!(
                "raw data truncated: {data_len} bytes is not a whole number of {chunk}-byte chunks"
            )));
        }
        let interleaved = seg.toc & TOC_INTERLEAVED != 0;
        // values per channel in a chunk: the rows of an interleaved chunk
        let n = active[0].1.n_values;
        if interleaved
            && active
                .iter()
                .any(|(_, i)| i.n_values != n || i.dtype == T_STRING)
        {
            return Err(err(
                "interleaved data needs equal-length numeric channels".into()
            ));
        }
        // chunk <= data_len <= len: both fit in usize
        let n_chunks = (data_len / chunk) as usize;
        if n_chunks == 0 {
            return Ok(());
        }
        if objects.active_changed || self.layouts.is_empty() {
            // every entry holds at least one byte of this segment: the layouts stay smaller
            // than the file
            let layout: Vec<Entry> = active
                .iter()
                .filter(|(_, i)| i.bytes > 0)
                .map(|&(obj, idx)| Entry { obj, idx })
                .collect();
            if self.layouts.last() != Some(&layout) {
                self.layouts.push(layout);
            }
            objects.active_changed = false;
        }
        let layout = self.layouts.len() - 1;
        let (n_chunks, chunk) = if interleaved {
            // rows: the values' sizes add up to chunk / n
            ((data_len / chunk * n) as usize, (chunk / n) as usize)
        } else {
            (n_chunks, chunk as usize)
        };
        let (big, start) = (seg.big, seg.meta_end);
        match self.runs.last_mut() {
            Some(run)
                if (
                    run.n_chunks,
                    run.chunk,
                    run.big,
                    run.interleaved,
                    run.layout,
                ) == (n_chunks, chunk, big, interleaved, layout)
                    && (run.repeat == 1 || start == run.start + run.repeat * run.step) =>
            {
                if run.repeat == 1 {
                    run.step = start - run.start;
                }
                run.repeat += 1;
            }
            _ => self.runs.push(Run {
                start,
                step: 0,
                repeat: 1,
                n_chunks,
                chunk,
                big,
                interleaved,
                layout,
            }),
        }
        Ok(())
    }
}

/// First pass: lead-ins and metadata of every segment, checked; objects with their
/// properties; where the raw data lies. No raw data is read.
fn scan(src: &Source, source: &str, tuning: &Tuning) -> Result<(TdmsFile, Plan)> {
    let mut objects = Objects {
        file: TdmsFile {
            source: source.to_string(),
            objects: Vec::new(),
        },
        index_of: HashMap::new(),
        last_index: HashMap::new(),
        active: Vec::new(),
        active_changed: true,
    };
    let mut plan = Plan::default();
    let mut window = Window::default();
    let mut ahead = tuning.read_ahead;
    let mut pos = 0usize;
    let mut segment = 0usize;
    let len = src.len();
    if len == 0 {
        return Err(Error::input(
            SourcePos::file(source).byte(0),
            "empty file: not a TDMS file",
        ));
    }
    while pos < len {
        segment += 1;
        if len - pos < LEAD_IN {
            return Err(segment_error(
                source,
                segment,
                pos,
                format!("truncated lead-in: {} of {LEAD_IN} bytes", len - pos),
            ));
        }
        let lead_in = window.get(src, pos, pos + LEAD_IN, ahead)?;
        let seg = read_lead_in(lead_in, pos, len, source, segment)?;
        if seg.toc & TOC_META_DATA != 0 {
            let meta = window.get(src, seg.seg_start, seg.meta_end, ahead)?;
            let mut c = Cursor {
                bytes: meta,
                base: seg.seg_start,
                pos: seg.seg_start,
                end: seg.meta_end,
                big: seg.big,
                source,
                segment,
            };
            objects.read_meta(&mut c, seg.toc & TOC_NEW_OBJ_LIST != 0)?;
        }
        if seg.toc & TOC_RAW_DATA != 0 && !objects.active.is_empty() {
            plan.add_raw_data(&mut objects, &seg, source, segment)?;
        }
        ahead = if seg.seg_end - pos <= tuning.read_ahead {
            tuning.read_ahead
        } else {
            0
        };
        pos = seg.seg_end;
    }
    Ok((objects.file, plan))
}

/// Work for one thread: (run, blocks of the run).
type Units = Vec<(usize, Range<usize>)>;

impl Plan {
    /// Second pass: every object's values, allocated once at their exact count, the raw data
    /// converted into place. Big files are split into groups of blocks (and large blocks into
    /// pieces) converted in parallel.
    fn fill(
        &self,
        src: &Source,
        source: &str,
        objects: &mut [TdmsObject],
        tuning: &Tuning,
    ) -> Result<()> {
        if self.runs.is_empty() {
            return Ok(());
        }
        let n_obj = objects.len();
        let total: usize = self
            .runs
            .iter()
            .map(|r| r.repeat * r.n_chunks * r.chunk)
            .sum();
        let threads = rayon::current_num_threads();
        let parallel = threads > 1 && total >= tuning.parallel_min;
        let k = if parallel { threads * 4 } else { 1 };
        // groups of consecutive blocks of about equal size, with their value counts
        let mut groups: Vec<(Units, Vec<usize>)> = Vec::with_capacity(k);
        let mut done = 0usize;
        for (i, run) in self.runs.iter().enumerate() {
            let cols = columns(&self.layouts[run.layout], run.interleaved);
            let blocks = run.repeat * run.n_chunks;
            let mut b = 0;
            while b < blocks {
                let g = (done as u128 * k as u128 / total as u128) as usize;
                if groups.len() <= g {
                    groups.push((Vec::new(), vec![0; n_obj]));
                }
                let group_end = ((g as u128 + 1) * total as u128).div_ceil(k as u128) as usize;
                let take = group_end
                    .saturating_sub(done)
                    .div_ceil(run.chunk)
                    .clamp(1, blocks - b);
                if let Some((units, counts)) = groups.last_mut() {
                    units.push((i, b..b + take));
                    for c in &cols {
                        counts[c.obj] += take * c.n;
                    }
                }
                done += take * run.chunk;
                b += take;
            }
        }
        let mut dests: Vec<Vec<&mut [f64]>> = (0..groups.len())
            .map(|_| Vec::with_capacity(n_obj))
            .collect();
        for (o, obj) in objects.iter_mut().enumerate() {
            obj.data = crate::bulk::zeroed_values(groups.iter().map(|(_, c)| c[o]).sum()).map_err(
                |m| {
                    Error::input(
                        SourcePos::file(source),
                        format!("channel {}: {m}", obj.path),
                    )
                },
            )?;
            let mut rest: &mut [f64] = &mut obj.data;
            for (g, (_, counts)) in groups.iter().enumerate() {
                dests[g].push(take_front(&mut rest, counts[o]));
            }
        }
        let work = |(units, mut dests): (Units, Vec<&mut [f64]>)| {
            let mut window = Window::default();
            let mut scratch = Vec::new();
            units.into_iter().try_for_each(|(run, blocks)| {
                self.fill_blocks(
                    src,
                    &self.runs[run],
                    blocks,
                    &mut dests,
                    (&mut window, &mut scratch),
                    parallel,
                    tuning,
                )
            })
        };
        let groups: Vec<_> = groups.into_iter().map(|(u, _)| u).zip(dests).collect();
        if groups.len() > 1 {
            groups.into_par_iter().try_for_each(work)
        } else {
            groups.into_iter().try_for_each(work)
        }
    }

    /// Blocks `blocks` of a run into the objects' slices.
    #[allow(clippy::too_many_arguments)]
    fn fill_blocks(
        &self,
        src: &Source,
        run: &Run,
        blocks: Range<usize>,
        dests: &mut [&mut [f64]],
        (window, scratch): (&mut Window, &mut Vec<u8>),
        parallel: bool,
        tuning: &Tuning,
    ) -> Result<()> {
        let layout = &self.layouts[run.layout];
        let cols = columns(layout, run.interleaved);
        let per_piece = match src {
            Source::Mem(_) => blocks.len(),
            #[cfg(any(unix, windows))]
            Source::File { .. } => {
                if !run.interleaved && run.chunk >= tuning.direct_min.saturating_mul(layout.len()) {
                    // big channel blocks: each straight into its place
                    for b in blocks {
                        let at = run.block_pos(b);
                        for c in &cols {
                            let dst = take_front(&mut dests[c.obj], c.n);
                            read_values(
                                src,
                                at + c.offset,
                                c.dtype,
                                run.big,
                                dst,
                                scratch,
                                parallel,
                                tuning,
                            )?;
                        }
                    }
                    return Ok(());
                }
                // small ones: about `buffer_bytes` of the file at a time
                let span = if run.repeat > 1 {
                    run.chunk.max(run.step.div_ceil(run.n_chunks))
                } else {
                    run.chunk
                };
                (tuning.buffer_bytes / span).max(1)
            }
        };
        let mut b0 = blocks.start;
        while b0 < blocks.end {
            let b1 = (b0 + per_piece).min(blocks.end);
            let base = run.block_pos(b0);
            let end = run.block_pos(b1 - 1) + run.chunk;
            let raw = window.get(src, base, end, tuning.buffer_bytes)?;
            for c in &cols {
                let dst = take_front(&mut dests[c.obj], (b1 - b0) * c.n);
                decode_blocks(raw, base, run, b0..b1, c, dst, parallel, tuning);
            }
            b0 = b1;
        }
        Ok(())
    }
}

/// One column's values in blocks `blocks` of a run; `raw` holds the file from `base` on.
#[allow(clippy::too_many_arguments)]
fn decode_blocks(
    raw: &[u8],
    base: usize,
    run: &Run,
    blocks: Range<usize>,
    c: &Col,
    mut dst: &mut [f64],
    parallel: bool,
    tuning: &Tuning,
) {
    let at = |b: usize| raw.get(run.block_pos(b) - base + c.offset..).unwrap_or(&[]);
    let decode = |raw: &[u8], stride: usize, dst: &mut [f64]| {
        decode_par(
            c.dtype,
            run.big,
            raw,
            stride.max(c.stride),
            dst,
            parallel,
            tuning,
        )
    };
    if c.n == 1 && run.n_chunks == 1 {
        // one value per segment: one pass over the segments
        decode(at(blocks.start), run.step, dst);
    } else if c.n == 1 {
        // one value per block: one pass per segment
        let mut b = blocks.start;
        while b < blocks.end {
            let seg_end = (b / run.n_chunks + 1) * run.n_chunks;
            let n = seg_end.min(blocks.end) - b;
            decode(at(b), run.chunk, take_front(&mut dst, n));
            b += n;
        }
    } else {
        for b in blocks {
            decode(at(b), c.stride, take_front(&mut dst, c.n));
        }
    }
}

/// `decode`, on all cores when the values span at least two pieces.
fn decode_par(
    dtype: u32,
    big: bool,
    raw: &[u8],
    stride: usize,
    dst: &mut [f64],
    parallel: bool,
    tuning: &Tuning,
) {
    if parallel && dst.len() * stride >= 2 * tuning.piece_bytes {
        let per = (tuning.piece_bytes / stride).max(1);
        dst.par_chunks_mut(per).enumerate().for_each(|(i, d)| {
            decode(
                dtype,
                big,
                raw.get(i * per * stride..).unwrap_or(&[]),
                stride,
                d,
            )
        });
    } else {
        decode(dtype, big, raw, stride, dst);
    }
}

/// Split the first `n` values (at most all) off a destination slice.
fn take_front<'a>(slot: &mut &'a mut [f64], n: usize) -> &'a mut [f64] {
    let all = std::mem::take(slot);
    let (head, tail) = all.split_at_mut(n.min(all.len()));
    *slot = tail;
    head
}

/// `dst.len()` values of type `dtype` from the file at `at`.
#[cfg(any(unix, windows))]
#[allow(clippy::too_many_arguments)]
fn read_values(
    src: &Source,
    at: usize,
    dtype: u32,
    big: bool,
    dst: &mut [f64],
    scratch: &mut Vec<u8>,
    parallel: bool,
    tuning: &Tuning,
) -> Result<()> {
    let size = type_size(dtype).unwrap_or(1);
    if parallel && dst.len() * size >= 2 * tuning.piece_bytes {
        let per = (tuning.piece_bytes / size).max(1);
        return dst.par_chunks_mut(per).enumerate().try_for_each_init(
            Vec::new,
            |scratch, (i, d)| {
                read_values(
                    src,
                    at + i * per * size,
                    dtype,
                    big,
                    d,
                    scratch,
                    false,
                    tuning,
                )
            },
        );
    }
    if matches!(dtype, 10 | 0x1A) {
        src.read_into(at, bytemuck::cast_slice_mut(dst))?;
        if big != cfg!(target_endian = "big") {
            for v in dst.iter_mut() {
                *v = f64::from_bits(v.to_bits().swap_bytes());
            }
        }
        return Ok(());
    }
    scratch.resize(dst.len() * size, 0);
    src.read_into(at, scratch)?;
    decode(dtype, big, scratch, size, dst);
    Ok(())
}

/// Values of type `dtype`, `stride` bytes apart in `raw`, converted to f64 into `dst` (as
/// many as both hold).
fn decode(dtype: u32, big: bool, raw: &[u8], stride: usize, dst: &mut [f64]) {
    macro_rules! num {
        ($t:ty, $n:literal) => {
            if big {
                conv::<$n>(raw, stride, dst, |a| <$t>::from_be_bytes(a) as f64)
            } else {
                conv::<$n>(raw, stride, dst, |a| <$t>::from_le_bytes(a) as f64)
            }
        };
    }
    match dtype {
        1 => num!(i8, 1),
        2 => num!(i16, 2),
        3 => num!(i32, 4),
        4 => num!(i64, 8),
        5 => num!(u8, 1),
        6 => num!(u16, 2),
        7 => num!(u32, 4),
        8 => num!(u64, 8),
        9 | 0x19 => num!(f32, 4),
        10 | 0x1A => {
            let n = dst.len() * 8;
            match raw.get(..n) {
                Some(raw) if stride == 8 && big == cfg!(target_endian = "big") => {
                    bytemuck::cast_slice_mut::<f64, u8>(dst).copy_from_slice(raw)
                }
                _ if big => conv::<8>(raw, stride, dst, f64::from_be_bytes),
                _ => conv::<8>(raw, stride, dst, f64::from_le_bytes),
            }
        }
        T_BOOL => conv::<1>(raw, stride, dst, |a| (a[0] != 0) as u8 as f64),
        T_TIMESTAMP => {
            // little-endian layout: u64 fraction (2^-64 s), then i64 seconds since 1904;
            // big-endian: i64 seconds, then u64 fraction
            let t = |secs: i64, frac: u64| secs as f64 + frac as f64 / 18_446_744_073_709_551_616.0;
            if big {
                conv::<16>(raw, stride, dst, |a| {
                    let (s, f) = a.split_at(8);
                    t(
                        i64::from_be_bytes(s.try_into().expect("8 bytes")),
                        u64::from_be_bytes(f.try_into().expect("8 bytes")),
                    )
                })
            } else {
                conv::<16>(raw, stride, dst, |a| {
                    let (f, s) = a.split_at(8);
                    t(
                        i64::from_le_bytes(s.try_into().expect("8 bytes")),
                        u64::from_le_bytes(f.try_into().expect("8 bytes")),
                    )
                })
            }
        }
        _ => {} // the first pass admits no other raw data type
    }
}

#[inline(always)]
fn conv<const N: usize>(raw: &[u8], stride: usize, dst: &mut [f64], f: impl Fn([u8; N]) -> f64) {
    if stride == N {
        let (values, _) = raw.as_chunks::<N>();
        for (d, a) in dst.iter_mut().zip(values) {
            *d = f(*a);
        }
    } else {
        for (d, row) in dst.iter_mut().zip(raw.chunks(stride)) {
            if let Some(a) = row.first_chunk::<N>() {
                *d = f(*a);
            }
        }
    }
}

fn upsert(active: &mut Vec<(usize, RawIndex)>, obj: usize, idx: RawIndex) {
    match active.iter_mut().find(|(o, _)| *o == obj) {
        Some(slot) => slot.1 = idx,
        None => active.push((obj, idx)),
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
struct RawIndex {
    dtype: u32,
    n_values: u64,
    bytes: u64,
}

/// Size in bytes of a fixed-size TDMS data type.
fn type_size(dtype: u32) -> Option<usize> {
    Some(match dtype {
        1 | 5 | T_BOOL => 1,
        2 | 6 => 2,
        3 | 7 | 9 | 0x19 => 4,
        4 | 8 | 10 | 0x1A => 8,
        T_TIMESTAMP => 16,
        _ => return None,
    })
}

/// Reads metadata from `bytes`, which hold the file's bytes from offset `base` on; `pos`
/// and `end` are file offsets (errors name them).
struct Cursor<'a> {
    bytes: &'a [u8],
    base: usize,
    pos: usize,
    end: usize,
    big: bool,
    source: &'a str,
    segment: usize,
}

impl Cursor<'_> {
    fn take(&mut self, n: usize) -> Result<&[u8]> {
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
    fn arr<const N: usize>(&mut self) -> Result<[u8; N]> {
        let mut a: [u8; N] = self.take(N)?.try_into().expect("N bytes");
        if self.big {
            a.reverse();
        }
        Ok(a)
    }
    fn u32(&mut self) -> Result<u32> {
        Ok(u32::from_le_bytes(self.arr()?))
    }
    fn u64(&mut self) -> Result<u64> {
        Ok(u64::from_le_bytes(self.arr()?))
    }
    fn string(&mut self) -> Result<String> {
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
    fn timestamp(&mut self) -> Result<f64> {
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
    fn value(&mut self, dtype: u32) -> Result<f64> {
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
    fn property(&mut self, ptype: u32) -> Result<PropValue> {
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

#[cfg(test)]
mod reader_tests {
    //! The reader against files with known contents, and the buffer and file paths (at
    //! every size threshold) against each other, on valid and on mutated files.
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// A random but valid TDMS file exercising what the reader supports (every raw data type,
    /// strings, big-endian and interleaved segments, several chunks per segment, incremental
    /// metadata, reused indices, properties), with the values each object must read back.
    fn random_tdms(rng: &mut ChaCha8Rng) -> (Vec<u8>, Vec<(String, Vec<f64>)>) {
        const DTYPES: [u32; 14] = [1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 0x19, 0x1A, 0x21, 0x44];
        struct Obj {
            path: String,
            dtype: Option<u32>,
            last: Option<(u32, u64, u64)>,
        }
        fn put(buf: &mut Vec<u8>, le: &[u8], big: bool) {
            if big {
                buf.extend(le.iter().rev());
            } else {
                buf.extend_from_slice(le);
            }
        }
        fn put_str(buf: &mut Vec<u8>, s: &[u8], big: bool) {
            put(buf, &(s.len() as u32).to_le_bytes(), big);
            buf.extend_from_slice(s);
        }
        /// One value of `dtype`: its bytes (in the segment's byte order) and its f64.
        fn value(rng: &mut ChaCha8Rng, dtype: u32, big: bool, buf: &mut Vec<u8>) -> f64 {
            macro_rules! int {
                ($t:ty) => {{
                    let v: $t = rng.gen();
                    put(buf, &v.to_le_bytes(), big);
                    v as f64
                }};
            }
            match dtype {
                1 => int!(i8),
                2 => int!(i16),
                3 => int!(i32),
                4 => int!(i64),
                5 => int!(u8),
                6 => int!(u16),
                7 => int!(u32),
                8 => int!(u64),
                9 | 0x19 => {
                    let v = rng.gen_range(-1e6f32..1e6);
                    put(buf, &v.to_le_bytes(), big);
                    v as f64
                }
                10 | 0x1A => {
                    let v = rng.gen_range(-1e9..1e9);
                    put(buf, &f64::to_le_bytes(v), big);
                    v
                }
                0x21 => {
                    let b = [0u8, 1, 7][rng.gen_range(0..3)];
                    buf.push(b);
                    (b != 0) as u8 as f64
                }
                0x44 => {
                    let secs: i64 = rng.gen_range(-1 << 40..1 << 40);
                    let frac: u64 = rng.gen();
                    if big {
                        put(buf, &secs.to_le_bytes(), true);
                        put(buf, &frac.to_le_bytes(), true);
                    } else {
                        buf.extend_from_slice(&frac.to_le_bytes());
                        buf.extend_from_slice(&secs.to_le_bytes());
                    }
                    secs as f64 + frac as f64 / 18_446_744_073_709_551_616.0
                }
                _ => unreachable!(),
            }
        }
        let mut out = Vec::new();
        let mut objs: Vec<Obj> = Vec::new();
        let mut expected: Vec<(String, Vec<f64>)> = Vec::new();
        let mut active: Vec<(usize, (u32, u64, u64))> = Vec::new();
        let n_segments = rng.gen_range(1..8);
        for s in 0..n_segments {
            let big = rng.gen_bool(0.3);
            let mut toc = 0u32;
            let mut meta = Vec::new();
            if s == 0 || rng.gen_bool(0.6) {
                toc |= TOC_META_DATA;
                if s == 0 || rng.gen_bool(0.3) {
                    toc |= TOC_NEW_OBJ_LIST;
                    active.clear();
                }
                let k = rng.gen_range(0..5u32);
                put(&mut meta, &k.to_le_bytes(), big);
                for _ in 0..k {
                    let o = if objs.is_empty() || rng.gen_bool(0.4) {
                        let path = if rng.gen_bool(0.2) {
                            group_path(&format!("g{}", rng.gen_range(0..3)))
                        } else {
                            channel_path(
                                &format!("g'{}", rng.gen_range(0..3)),
                                &format!("c{}", objs.len()),
                            )
                        };
                        match objs.iter().position(|o| o.path == path) {
                            Some(o) => o,
                            None => {
                                objs.push(Obj {
                                    path: path.clone(),
                                    dtype: None,
                                    last: None,
                                });
                                expected.push((path, Vec::new()));
                                objs.len() - 1
                            }
                        }
                    } else {
                        rng.gen_range(0..objs.len())
                    };
                    put_str(&mut meta, objs[o].path.as_bytes(), big);
                    let r = rng.gen_range(0..10);
                    if r == 0 {
                        put(&mut meta, &NO_RAW_DATA.to_le_bytes(), big);
                        active.retain(|(a, _)| *a != o);
                    } else if r <= 2 && objs[o].last.is_some() {
                        put(&mut meta, &SAME_AS_PREVIOUS.to_le_bytes(), big);
                        let idx = objs[o].last.unwrap();
                        match active.iter_mut().find(|(a, _)| *a == o) {
                            Some(slot) => slot.1 = idx,
                            None => active.push((o, idx)),
                        }
                    } else {
                        let dtype = *objs[o].dtype.get_or_insert_with(|| {
                            if rng.gen_bool(0.1) {
                                T_STRING
                            } else {
                                DTYPES[rng.gen_range(0..DTYPES.len())]
                            }
                        });
                        let n: u64 = rng.gen_range(0..20);
                        let bytes = match type_size(dtype) {
                            Some(size) => n * size as u64,
                            None => rng.gen_range(0..30),
                        };
                        put(&mut meta, &20u32.to_le_bytes(), big);
                        put(&mut meta, &dtype.to_le_bytes(), big);
                        put(&mut meta, &1u32.to_le_bytes(), big);
                        put(&mut meta, &n.to_le_bytes(), big);
                        if dtype == T_STRING {
                            put(&mut meta, &bytes.to_le_bytes(), big);
                        }
                        let idx = (dtype, n, bytes);
                        objs[o].last = Some(idx);
                        match active.iter_mut().find(|(a, _)| *a == o) {
                            Some(slot) => slot.1 = idx,
                            None => active.push((o, idx)),
                        }
                    }
                    let n_props = rng.gen_range(0..3u32);
                    put(&mut meta, &n_props.to_le_bytes(), big);
                    for p in 0..n_props {
                        put_str(&mut meta, format!("p{p}").as_bytes(), big);
                        let ptype =
                            [3u32, 8, 10, T_STRING, T_BOOL, T_TIMESTAMP][rng.gen_range(0..6)];
                        put(&mut meta, &ptype.to_le_bytes(), big);
                        match ptype {
                            T_STRING => put_str(&mut meta, b"text", big),
                            T_BOOL => meta.push(1),
                            _ => {
                                value(rng, ptype, big, &mut meta);
                            }
                        }
                    }
                }
            }
            let mut raw = Vec::new();
            if rng.gen_bool(0.9) {
                toc |= TOC_RAW_DATA;
                let chunk: u64 = active.iter().map(|(_, i)| i.2).sum();
                let n0 = active.first().map(|(_, i)| i.1);
                if !active.is_empty()
                    && active
                        .iter()
                        .all(|(_, i)| Some(i.1) == n0 && i.0 != T_STRING)
                    && rng.gen_bool(0.4)
                {
                    toc |= TOC_INTERLEAVED;
                }
                let n_chunks = if chunk == 0 { 0 } else { rng.gen_range(0..4) };
                for _ in 0..n_chunks {
                    if toc & TOC_INTERLEAVED != 0 {
                        for _ in 0..n0.unwrap_or(0) {
                            for (o, i) in &active {
                                let v = value(rng, i.0, big, &mut raw);
                                expected[*o].1.push(v);
                            }
                        }
                    } else {
                        for (o, i) in &active {
                            if i.0 == T_STRING {
                                raw.extend((0..i.2).map(|_| rng.gen::<u8>()));
                            } else {
                                for _ in 0..i.1 {
                                    let v = value(rng, i.0, big, &mut raw);
                                    expected[*o].1.push(v);
                                }
                            }
                        }
                    }
                }
            }
            if big {
                toc |= TOC_BIG_ENDIAN;
            }
            out.extend_from_slice(b"TDSm");
            out.extend_from_slice(&toc.to_le_bytes());
            put(
                &mut out,
                &[4712u32, 4713][rng.gen_range(0..2)].to_le_bytes(),
                big,
            );
            let next = if s + 1 == n_segments && rng.gen_bool(0.2) {
                u64::MAX
            } else {
                (meta.len() + raw.len()) as u64
            };
            put(&mut out, &next.to_le_bytes(), big);
            put(&mut out, &(meta.len() as u64).to_le_bytes(), big);
            out.extend_from_slice(&meta);
            out.extend_from_slice(&raw);
        }
        (out, expected)
    }

    /// Thresholds small enough that the test files take every path of the file reader.
    const TINY: [Tuning; 3] = [
        Tuning {
            whole_read_max: 0,
            parallel_min: 0,
            piece_bytes: 8,
            direct_min: 0,
            buffer_bytes: 1,
            read_ahead: 0,
        },
        Tuning {
            whole_read_max: 0,
            parallel_min: 0,
            piece_bytes: 64,
            direct_min: 1 << 40,
            buffer_bytes: 40,
            read_ahead: 7,
        },
        Tuning {
            whole_read_max: 0,
            ..Tuning::DEFAULT
        },
    ];

    fn show(r: Result<TdmsFile>) -> String {
        match r {
            Ok(f) => format!("{:?}", f.objects), // Debug: NaN from mutated bytes compares equal
            Err(e) => format!("error: {e}"),
        }
    }

    fn from_file(bytes: &[u8], tuning: &Tuning) -> String {
        let mut tmp = tempfile::NamedTempFile::new().unwrap();
        tmp.write_all(bytes).unwrap();
        let file = std::fs::File::open(tmp.path()).unwrap();
        let src = Source::File {
            file: &file,
            path: tmp.path(),
            len: bytes.len(),
        };
        show(parse_source(&src, "f.tdms", tuning))
    }

    #[test]
    fn random_files_read_back_their_values() {
        for seed in 0..300 {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let (bytes, expected) = random_tdms(&mut rng);
            let file = TdmsFile::parse(&bytes, "f.tdms").unwrap();
            let got: Vec<(String, Vec<f64>)> = file
                .objects
                .iter()
                .map(|o| (o.path.clone(), o.data.clone()))
                .collect();
            assert_eq!(got, expected, "seed {seed}");
            for tuning in &TINY {
                assert_eq!(
                    from_file(&bytes, tuning),
                    show(Ok(file.clone())),
                    "seed {seed}"
                );
            }
        }
    }

    #[test]
    fn mutated_files_read_the_same_from_a_buffer_and_from_a_file() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        for seed in 0..150 {
            let (base, _) = random_tdms(&mut ChaCha8Rng::seed_from_u64(1000 + seed));
            for _ in 0..8 {
                let mut b = base.clone();
                match rng.gen_range(0..3) {
                    0 if !b.is_empty() => {
                        let i = rng.gen_range(0..b.len());
                        b[i] = rng.gen();
                    }
                    1 if !b.is_empty() => b.truncate(rng.gen_range(0..b.len())),
                    _ => {
                        let i = rng.gen_range(0..=b.len());
                        let v: u64 =
                            [u64::MAX, 0, 1 << 31, 1 << 40, rng.gen()][rng.gen_range(0..5)];
                        b.splice(i..i, v.to_le_bytes());
                    }
                }
                let mem = show(TdmsFile::parse(&b, "f.tdms"));
                for tuning in &TINY {
                    assert_eq!(from_file(&b, tuning), mem, "seed {seed}");
                }
            }
        }
    }

    #[test]
    fn fragmented_files_contiguous_and_interleaved() {
        // runs of small segments of the same shape, from a buffer and from a file
        let a: Vec<f64> = (0..60).map(|i| i as f64).collect();
        let b: Vec<f64> = (0..60).map(|i| -(i as f64) - 0.5).collect();
        let chans = [
            WriteChannel {
                name: "a",
                unit: "",
                data: &a,
            },
            WriteChannel {
                name: "b",
                unit: "",
                data: &b,
            },
        ];
        for seg in [1, 2, 7, 60] {
            let mut buf = Vec::new();
            write_tdms(&mut buf, "G", &chans, 1.0, 0.0, seg).unwrap();
            let file = TdmsFile::parse(&buf, "f.tdms").unwrap();
            assert_eq!(file.channel("G", "a").unwrap().data, a, "{seg}");
            assert_eq!(file.channel("G", "b").unwrap().data, b, "{seg}");
            for tuning in &TINY {
                assert_eq!(from_file(&buf, tuning), show(Ok(file.clone())), "{seg}");
            }
            // the same bytes as interleaved segments: each segment's values taken in rows
            let mut pos = 0;
            while pos < buf.len() {
                buf[pos + 4] |= TOC_INTERLEAVED as u8;
                let next = u64::from_le_bytes(buf[pos + 12..pos + 20].try_into().unwrap());
                pos += LEAD_IN + next as usize;
            }
            let (mut ra, mut rb) = (Vec::<f64>::new(), Vec::<f64>::new());
            for start in (0..60).step_by(seg) {
                let end = (start + seg).min(60);
                let d: Vec<f64> = a[start..end]
                    .iter()
                    .chain(&b[start..end])
                    .copied()
                    .collect();
                ra.extend(d.iter().step_by(2));
                rb.extend(d.iter().skip(1).step_by(2));
            }
            let file = TdmsFile::parse(&buf, "f.tdms").unwrap();
            assert_eq!(file.channel("G", "a").unwrap().data, ra, "{seg}");
            assert_eq!(file.channel("G", "b").unwrap().data, rb, "{seg}");
            for tuning in &TINY {
                assert_eq!(from_file(&buf, tuning), show(Ok(file.clone())), "{seg}");
            }
        }
    }

    #[test]
    fn big_files_are_read_in_place_and_in_parallel() {
        // several segments of a few megabytes, little- and big-endian doubles and int16:
        // the default thresholds' parallel direct path, against the buffer parser
        let n = 300_000usize;
        let mut bytes = Vec::new();
        for (s, big) in [false, true, false].into_iter().enumerate() {
            let mut meta = Vec::new();
            let put = |buf: &mut Vec<u8>, le: &[u8]| {
                if big {
                    buf.extend(le.iter().rev())
                } else {
                    buf.extend_from_slice(le)
                }
            };
            put(&mut meta, &2u32.to_le_bytes());
            for (name, dtype, size) in [("a", T_F64, 8u64), ("b", 2, 2)] {
                let path = channel_path("G", name);
                put(&mut meta, &(path.len() as u32).to_le_bytes());
                meta.extend_from_slice(path.as_bytes());
                put(&mut meta, &20u32.to_le_bytes());
                put(&mut meta, &dtype.to_le_bytes());
                put(&mut meta, &1u32.to_le_bytes());
                put(&mut meta, &(n as u64).to_le_bytes());
                put(&mut meta, &0u32.to_le_bytes());
                let _ = size;
            }
            let mut raw = Vec::new();
            for i in 0..n {
                put(&mut raw, &((s * n + i) as f64 * 0.5).to_le_bytes());
            }
            for i in 0..n {
                put(&mut raw, &((i % 30_000) as i16 - 15_000).to_le_bytes());
            }
            let toc = TOC_META_DATA | TOC_RAW_DATA | if big { TOC_BIG_ENDIAN } else { 0 };
            bytes.extend_from_slice(b"TDSm");
            bytes.extend_from_slice(&toc.to_le_bytes());
            put(&mut bytes, &4713u32.to_le_bytes());
            put(&mut bytes, &((meta.len() + raw.len()) as u64).to_le_bytes());
            put(&mut bytes, &(meta.len() as u64).to_le_bytes());
            bytes.extend_from_slice(&meta);
            bytes.extend_from_slice(&raw);
        }
        let mut tmp = tempfile::NamedTempFile::new().unwrap();
        tmp.write_all(&bytes).unwrap();
        let file = TdmsFile::read(tmp.path()).unwrap();
        let a = &file.channel("G", "a").unwrap().data;
        assert_eq!(a.len(), 3 * n);
        assert!(a.iter().enumerate().all(|(i, v)| *v == i as f64 * 0.5));
        let b = &file.channel("G", "b").unwrap().data;
        assert!(b
            .iter()
            .enumerate()
            .all(|(i, v)| *v == ((i % n) % 30_000) as f64 - 15_000.0));
        let mem = TdmsFile::parse(&bytes, &tmp.path().display().to_string()).unwrap();
        assert_eq!(file, mem);
    }
}

// ---------------------------------------------------------------------------------------
// Writer

/// A channel to write: name, unit string, f64 data.
pub struct WriteChannel<'a> {
    pub name: &'a str,
    pub unit: &'a str,
    pub data: &'a [f64],
}

fn put_str(buf: &mut Vec<u8>, s: &str) {
    buf.extend_from_slice(&(s.len() as u32).to_le_bytes());
    buf.extend_from_slice(s.as_bytes());
}

fn put_lead_in(
    out: &mut dyn Write,
    toc: u32,
    meta_len: usize,
    raw_len: usize,
) -> std::io::Result<()> {
    out.write_all(b"TDSm")?;
    out.write_all(&toc.to_le_bytes())?;
    out.write_all(&4713u32.to_le_bytes())?;
    out.write_all(&((meta_len + raw_len) as u64).to_le_bytes())?;
    out.write_all(&(meta_len as u64).to_le_bytes())
}

/// Write one group of equal-length f64 channels as a waveform TDMS file (`wf_increment`,
/// `wf_start_offset`, `unit_string` properties), split into segments of at most
/// `segment_samples` values per channel. The first segment carries the full metadata; full
/// segments after it carry raw data only; a shorter last segment updates the raw indices.
pub fn write_tdms(
    out: &mut dyn Write,
    group: &str,
    channels: &[WriteChannel],
    dt_s: f64,
    t0_s: f64,
    segment_samples: usize,
) -> std::io::Result<()> {
    let n = channels.first().map(|c| c.data.len()).unwrap_or(0);
    assert!(
        channels.iter().all(|c| c.data.len() == n),
        "channels must have equal length"
    );
    let seg = segment_samples.max(1);
    let mut start = 0usize;
    let mut first = true;
    let mut last_len = 0usize;
    loop {
        let len = (n - start).min(seg);
        let mut meta = Vec::new();
        let mut toc = TOC_RAW_DATA;
        if first || len != last_len {
            toc |= TOC_META_DATA;
            if first {
                toc |= TOC_NEW_OBJ_LIST;
                meta.extend_from_slice(&(2 + channels.len() as u32).to_le_bytes());
                put_str(&mut meta, "/");
                meta.extend_from_slice(&NO_RAW_DATA.to_le_bytes());
                meta.extend_from_slice(&0u32.to_le_bytes());
                put_str(&mut meta, &group_path(group));
                meta.extend_from_slice(&NO_RAW_DATA.to_le_bytes());
                meta.extend_from_slice(&0u32.to_le_bytes());
            } else {
                meta.extend_from_slice(&(channels.len() as u32).to_le_bytes());
            }
            for c in channels {
                put_str(&mut meta, &channel_path(group, c.name));
                meta.extend_from_slice(&20u32.to_le_bytes());
                meta.extend_from_slice(&T_F64.to_le_bytes());
                meta.extend_from_slice(&1u32.to_le_bytes());
                meta.extend_from_slice(&(len as u64).to_le_bytes());
                if first {
                    meta.extend_from_slice(&3u32.to_le_bytes());
                    put_str(&mut meta, "unit_string");
                    meta.extend_from_slice(&T_STRING.to_le_bytes());
                    put_str(&mut meta, c.unit);
                    put_str(&mut meta, "wf_increment");
                    meta.extend_from_slice(&T_F64.to_le_bytes());
                    meta.extend_from_slice(&dt_s.to_le_bytes());
                    put_str(&mut meta, "wf_start_offset");
                    meta.extend_from_slice(&T_F64.to_le_bytes());
                    meta.extend_from_slice(&t0_s.to_le_bytes());
                } else {
                    meta.extend_from_slice(&0u32.to_le_bytes());
                }
            }
        }
        put_lead_in(out, toc, meta.len(), len * 8 * channels.len())?;
        out.write_all(&meta)?;
        let mut raw = Vec::with_capacity(len * 8);
        for c in channels {
            raw.clear();
            for v in &c.data[start..start + len] {
                raw.extend_from_slice(&v.to_le_bytes());
            }
            out.write_all(&raw)?;
        }
        first = false;
        last_len = len;
        start += len;
        if start >= n {
            break;
        }
    }
    Ok(())
}

/// Default number of samples per channel in one TDMS segment.
pub const DEFAULT_SEGMENT_SAMPLES: usize = 10_000;

/// Write a recording as TDMS: group `map.tdms_group`, channels named as the CSV columns.
/// Time is stored as waveform timing (uniform sampling required).
pub fn write_tdms_recording(path: &Path, rec: &Recording, group: &str) -> Result<()> {
    let dt = 1.0 / rec.sample_rate_hz();
    let channels = recording_channels(rec);
    write_atomic(path, |w| {
        write_tdms(
            w,
            group,
            &channels,
            dt,
            rec.time_s[0],
            DEFAULT_SEGMENT_SAMPLES,
        )
    })
}

/// The channels of a recording, named as the CSV columns.
fn recording_channels(rec: &Recording) -> Vec<WriteChannel<'_>> {
    let mut channels = vec![
        WriteChannel {
            name: "normal_force_N",
            unit: "N",
            data: &rec.normal_n,
        },
        WriteChannel {
            name: "tangential_force_N",
            unit: "N",
            data: &rec.tangential_n,
        },
    ];
    if let Some(r) = &rec.radial_n {
        channels.push(WriteChannel {
            name: "radial_force_N",
            unit: "N",
            data: r,
        });
    }
    if let Some(t) = &rec.trigger_v {
        channels.push(WriteChannel {
            name: "trigger_V",
            unit: "V",
            data: t,
        });
    }
    channels
}

/// Read a recording from a TDMS file through a channel map.
pub fn read_tdms_recording(path: &Path, map: &ChannelMap) -> Result<Recording> {
    let file = TdmsFile::read(path)?;
    recording_from_tdms(file, map)
}

/// Build a recording from a parsed TDMS file.
pub fn recording_from_tdms(file: TdmsFile, map: &ChannelMap) -> Result<Recording> {
    crate::recording::recording_from_table(table_from_tdms(file, map.tdms_group.as_deref())?, map)
}

/// The channels of one group as a table (columns named by channel, units from
/// `unit_string`, waveform timing from the first channel's `wf_increment` and
/// `wf_start_offset`). Without a group name: `Tribometer` if present, else the file's only
/// group holding channels.
pub fn table_from_tdms(mut file: TdmsFile, group: Option<&str>) -> Result<Table> {
    let groups: Vec<String> = file
        .objects
        .iter()
        .filter_map(|o| {
            let rest = o.path.strip_prefix("/'")?;
            let end = rest.find("'/'")?;
            Some(rest[..end].replace("''", "'"))
        })
        .fold(Vec::new(), |mut v, g| {
            if !v.contains(&g) {
                v.push(g);
            }
            v
        });
    let group = match group {
        Some(g) => g.to_string(),
        None if groups.iter().any(|g| g == DEFAULT_TDMS_GROUP) => DEFAULT_TDMS_GROUP.to_string(),
        None if groups.len() == 1 => groups[0].clone(),
        None => {
            return Err(Error::input(
                SourcePos::file(&file.source),
                format!(
                    "{} groups hold channels ({}): name one with `tdms_group`",
                    groups.len(),
                    groups.join(", ")
                ),
            ))
        }
    };
    let names = file.channel_names(&group);
    if names.is_empty() {
        return Err(Error::input(
            SourcePos::file(&file.source).field(&group),
            if file.object(&group_path(&group)).is_none() {
                format!(
                    "no group '{group}' in the file; it has: {}",
                    groups.join(", ")
                )
            } else {
                format!("group '{group}' has no channels")
            },
        ));
    }
    let mut columns = Vec::with_capacity(names.len());
    let mut interval = None;
    let mut start = None;
    for name in &names {
        let path = channel_path(&group, name);
        let Some(obj) = file.objects.iter_mut().find(|o| o.path == path) else {
            continue;
        };
        if obj.data_type == Some(T_STRING) || obj.data_type.is_none() {
            continue;
        }
        if interval.is_none() {
            interval = obj.property("wf_increment").and_then(PropValue::as_f64);
            start = obj.property("wf_start_offset").and_then(PropValue::as_f64);
        }
        let unit = obj
            .property("unit_string")
            .and_then(PropValue::as_str)
            .map(str::trim)
            .filter(|u| !u.is_empty())
            .map(str::to_string);
        let (base, header_unit) = split_unit(name);
        columns.push(Column {
            header: name.clone(),
            name: base,
            unit: unit.or(header_unit),
            data: ColumnData::Numbers(std::mem::take(&mut obj.data)),
        });
    }
    let rows = columns.iter().map(|c| match &c.data {
        ColumnData::Numbers(v) => v.len(),
        ColumnData::NotNumeric { .. } => 0,
    });
    let rows = rows.max().unwrap_or(0);
    Ok(Table {
        source: file.source.clone(),
        columns,
        rows,
        layout: format!("TDMS, group '{group}'"),
        header_line: 0,
        headerless: false,
        preamble: Vec::new(),
        footer: Vec::new(),
        sample_interval_s: interval,
        start_time_s: start,
        ..Default::default()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample_recording(n: usize) -> Recording {
        Recording {
            source: "mem".into(),
            time_s: (0..n).map(|i| i as f64 * 1e-3).collect(),
            normal_n: (0..n).map(|i| 100.0 + i as f64).collect(),
            tangential_n: (0..n).map(|i| 30.0 + 0.5 * i as f64).collect(),
            radial_n: Some(vec![1.0; n]),
            trigger_v: Some((0..n).map(|i| if i > 3 { 5.0 } else { 0.0 }).collect()),
            ..Recording::new("", Vec::new(), Vec::new(), Vec::new())
        }
    }

    fn to_bytes(rec: &Recording, seg: usize) -> Vec<u8> {
        let chans = recording_channels(rec);
        let mut buf = Vec::new();
        write_tdms(&mut buf, "Tribometer", &chans, 1e-3, 0.0, seg).unwrap();
        buf
    }

    #[test]
    fn write_read_multisegment() {
        let rec = sample_recording(25);
        for seg in [1, 7, 10, 25, 100] {
            let buf = to_bytes(&rec, seg);
            let file = TdmsFile::parse(&buf, "mem.tdms").unwrap();
            let back = recording_from_tdms(file, &ChannelMap::default()).unwrap();
            assert_eq!(back.normal_n, rec.normal_n, "segments of {seg}");
            assert_eq!(back.trigger_v, rec.trigger_v);
            assert!(back
                .time_s
                .iter()
                .zip(&rec.time_s)
                .all(|(a, b)| (a - b).abs() < 1e-12));
        }
    }

    #[test]
    fn truncated_file_is_an_error_naming_the_byte() {
        let buf = to_bytes(&sample_recording(25), 10);
        for cut in [0, 5, 27, 60, buf.len() - 1] {
            let e = TdmsFile::parse(&buf[..cut], "cut.tdms")
                .unwrap_err()
                .to_string();
            assert!(e.starts_with("cut.tdms, byte"), "{cut}: {e}");
            assert!(e.contains("truncated") || e.contains("empty"), "{cut}: {e}");
        }
    }

    #[test]
    fn not_tdms_and_missing_channels() {
        let e = TdmsFile::parse(b"time_s,normal_force_N\n0,1\n1,2\n3,4\n5,6\n", "x.tdms")
            .unwrap_err()
            .to_string();
        assert!(e.contains("expected segment tag 'TDSm'"), "{e}");
        let buf = to_bytes(&sample_recording(5), 10);
        let file = TdmsFile::parse(&buf, "m.tdms").unwrap();
        let map = ChannelMap {
            normal: Some(crate::recording::ChannelSpec::named("Fz")),
            ..Default::default()
        };
        let e = recording_from_tdms(file.clone(), &map)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("missing column 'Fz'") && e.contains("normal_force_N"),
            "{e}"
        );
        let map = ChannelMap {
            tdms_group: Some("Other".into()),
            ..Default::default()
        };
        let e = recording_from_tdms(file.clone(), &map)
            .unwrap_err()
            .to_string();
        assert!(e.contains("no group 'Other'"), "{e}");
        let mut map = ChannelMap::default();
        map.apply_override("normal=normal_force_N:kN").unwrap();
        let e = recording_from_tdms(file, &map).unwrap_err().to_string();
        assert!(
            e.contains("mapped as kN but the file says the unit is 'N'"),
            "{e}"
        );
    }
}
