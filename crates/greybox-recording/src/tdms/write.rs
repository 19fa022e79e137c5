//! Writing TDMS: channels in segments of a fixed number of samples, and a recording as a TDMS file.

use super::format::{
    channel_path, group_path, NO_RAW_DATA, TOC_META_DATA, TOC_NEW_OBJ_LIST, TOC_RAW_DATA, T_F64,
    T_STRING,
};
use crate::Recording;
use greybox_core::atomic::write_atomic;
use greybox_core::Result;
use std::io::Write;
use std::path::Path;

/// A channel to write: name, unit string, f64 data.
pub struct WriteChannel<'a> {
    pub name: &'a str,
    pub unit: &'a str,
    pub data: &'a [f64],
}

pub(super) fn put_str(buf: &mut Vec<u8>, s: &str) {
    buf.extend_from_slice(&(s.len() as u32).to_le_bytes());
    buf.extend_from_slice(s.as_bytes());
}

pub(super) fn put_lead_in(
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

/// Write a recording as TDMS: group `map.reader.tdms_group`, channels named as the CSV columns.
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
pub(super) fn recording_channels(rec: &Recording) -> Vec<WriteChannel<'_>> {
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
