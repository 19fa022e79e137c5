//! Second pass over a TDMS file: each channel allocated once and its raw values (contiguous or
//! interleaved, either byte order, every numeric type) converted into place, in parallel for large
//! files.

use super::format::{TdmsObject, T_BOOL, T_TIMESTAMP};
use super::segments::{columns, type_size, Col, Plan, Run};
use super::source::{Source, Tuning, Window};
use greybox_core::{Error, Result, SourcePos};
use rayon::prelude::*;
use std::ops::Range;

/// Work for one thread: (run, blocks of the run).
pub(super) type Units = Vec<(usize, Range<usize>)>;

impl Plan {
    /// Second pass: every object's values, allocated once at their exact count, the raw data
    /// converted into place. Big files are split into groups of blocks (and large blocks into
    /// pieces) converted in parallel.
    pub(super) fn fill(
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
    pub(super) fn fill_blocks(
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
pub(super) fn decode_blocks(
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
pub(super) fn decode_par(
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
pub(super) fn take_front<'a>(slot: &mut &'a mut [f64], n: usize) -> &'a mut [f64] {
    let all = std::mem::take(slot);
    let (head, tail) = all.split_at_mut(n.min(all.len()));
    *slot = tail;
    head
}

/// `dst.len()` values of type `dtype` from the file at `at`.
#[cfg(any(unix, windows))]
#[allow(clippy::too_many_arguments)]
pub(super) fn read_values(
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
pub(super) fn decode(dtype: u32, big: bool, raw: &[u8], stride: usize, dst: &mut [f64]) {
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
pub(super) fn conv<const N: usize>(
    raw: &[u8],
    stride: usize,
    dst: &mut [f64],
    f: impl Fn([u8; N]) -> f64,
) {
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
