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
//!
//! The pieces: [`format`] (the model: objects, properties, flags and type codes),
//! [`source`] (the file's bytes and a metadata cursor), [`segments`] (first pass: lead-ins
//! and metadata), [`raw_data`] (second pass: the values converted into the channels),
//! [`write`] (the writer) and [`table`] (a group's channels as a table or a recording).

mod format;
mod raw_data;
mod read;
mod segments;
mod source;
mod table;
mod write;

pub use format::{channel_path, group_path, PropValue, TdmsFile, TdmsObject};
pub use table::{read_tdms_recording, recording_from_tdms, table_from_tdms};
pub use write::{write_tdms, write_tdms_recording, WriteChannel, DEFAULT_SEGMENT_SAMPLES};

#[cfg(test)]
mod reader_tests {
    //! The reader against files with known contents, and the buffer and file paths (at
    //! every size threshold) against each other, on valid and on mutated files.
    use super::{format::*, read::parse_source, segments::*, source::*, write::*};
    use greybox_core::Result;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;
    use std::io::Write;

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

#[cfg(test)]
mod tests {
    use super::{format::*, table::*, write::*};
    use crate::{ChannelMap, Recording};

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
            normal: Some(crate::ChannelSpec::named("Fz")),
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
            reader: crate::ReaderOptions {
                tdms_group: Some("Other".into()),
                ..Default::default()
            },
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
