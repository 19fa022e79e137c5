//! First pass over a TDMS file: each segment's lead-in (DAQmx data refused) and metadata, the
//! objects' raw-data indices, and the runs of values they give each channel.

use super::format::{
    TdmsFile, TdmsObject, LEAD_IN, NO_RAW_DATA, SAME_AS_PREVIOUS, TOC_BIG_ENDIAN, TOC_DAQMX,
    TOC_INTERLEAVED, TOC_META_DATA, TOC_NEW_OBJ_LIST, TOC_RAW_DATA, T_BOOL, T_STRING, T_TIMESTAMP,
};
use super::source::{Cursor, Source, Tuning, Window};
use greybox_core::{Error, Result, SourcePos};
use std::collections::HashMap;

/// One object's raw data in each chunk of a segment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Entry {
    pub(super) obj: usize,
    pub(super) idx: RawIndex,
}

/// Raw data of `repeat` segments of the same shape, `step` bytes apart from `start` on,
/// validated: each holds `n_chunks` blocks of `chunk` bytes laid out as
/// `Plan::layouts[layout]`. Interleaved data is counted in rows: one block per row, one
/// value per object. (Files written a few values at a time are long runs of such segments.)
#[derive(Debug)]
pub(super) struct Run {
    pub(super) start: usize,
    pub(super) step: usize,
    pub(super) repeat: usize,
    pub(super) n_chunks: usize,
    pub(super) chunk: usize,
    pub(super) big: bool,
    pub(super) interleaved: bool,
    pub(super) layout: usize,
}

impl Run {
    /// File offset of block `b` (counted over all the run's segments).
    pub(super) fn block_pos(&self, b: usize) -> usize {
        self.start + (b / self.n_chunks) * self.step + (b % self.n_chunks) * self.chunk
    }
}

/// What the first pass found: where every object's values are.
#[derive(Debug, Default)]
pub(super) struct Plan {
    pub(super) runs: Vec<Run>,
    /// Raw data layouts (objects with a non-zero byte count, in order), shared by the
    /// segments that reuse the previous one's.
    pub(super) layouts: Vec<Vec<Entry>>,
}

/// Where one object's values lie in each block of a run: `n` values `stride` bytes apart,
/// from `offset` in the block.
#[derive(Debug, Clone, Copy)]
pub(super) struct Col {
    pub(super) obj: usize,
    pub(super) dtype: u32,
    pub(super) n: usize,
    pub(super) offset: usize,
    pub(super) stride: usize,
}

/// The numeric columns of a run's blocks.
pub(super) fn columns(layout: &[Entry], interleaved: bool) -> Vec<Col> {
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
pub(super) fn segment_error(source: &str, segment: usize, at: usize, msg: String) -> Error {
    Error::input(
        SourcePos::file(source).byte(at as u64),
        format!("segment {segment}: {msg}"),
    )
}

/// One segment's lead-in, checked: its table of contents and where its metadata and raw
/// data lie in the file.
pub(super) struct LeadIn {
    pub(super) toc: u32,
    pub(super) big: bool,
    /// First byte after the lead-in (the metadata).
    pub(super) seg_start: usize,
    /// First byte of the raw data.
    pub(super) meta_end: usize,
    /// First byte after the segment.
    pub(super) seg_end: usize,
}

/// Parse and check the 28-byte lead-in of the segment at `pos` of a `len`-byte file.
pub(super) fn read_lead_in(
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
pub(super) struct Objects {
    pub(super) file: TdmsFile,
    pub(super) index_of: HashMap<String, usize>,
    /// Each object's last raw data index (for "same as previous").
    pub(super) last_index: HashMap<usize, RawIndex>,
    /// The objects with raw data in the current segment, in order.
    pub(super) active: Vec<(usize, RawIndex)>,
    /// Whether `active` changed since the last layout was recorded.
    pub(super) active_changed: bool,
}

impl Objects {
    /// Read a segment's metadata (`c` spans it): new objects, raw data indices, properties.
    pub(super) fn read_meta(&mut self, c: &mut Cursor, new_list: bool) -> Result<()> {
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
    pub(super) fn object(&mut self, path: &str) -> usize {
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
    pub(super) fn read_raw_index(
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
    pub(super) fn add_raw_data(
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
pub(super) fn scan(src: &Source, source: &str, tuning: &Tuning) -> Result<(TdmsFile, Plan)> {
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

#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct RawIndex {
    pub(super) dtype: u32,
    pub(super) n_values: u64,
    pub(super) bytes: u64,
}

/// Size in bytes of a fixed-size TDMS data type.
pub(super) fn type_size(dtype: u32) -> Option<usize> {
    Some(match dtype {
        1 | 5 | T_BOOL => 1,
        2 | 6 => 2,
        3 | 7 | 9 | 0x19 => 4,
        4 | 8 | 10 | 0x1A => 8,
        T_TIMESTAMP => 16,
        _ => return None,
    })
}

pub(super) fn upsert(active: &mut Vec<(usize, RawIndex)>, obj: usize, idx: RawIndex) {
    match active.iter_mut().find(|(o, _)| *o == obj) {
        Some(slot) => slot.1 = idx,
        None => active.push((obj, idx)),
    }
}
