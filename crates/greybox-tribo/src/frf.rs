//! Frequency response functions from impact-hammer tests (digest §2; Ewins, *Modal Testing*,
//! 2000, ch. 3; Brandt, *Noise and Vibration Analysis*, 2011, ch. 13).
//!
//! 1. **Impacts**: the hammer signal crossing `trigger_fraction` × its peak starts an impact;
//!    a record of `block_s` starts `pretrigger_s` before it. Rejected: double hits (a second
//!    pulse above the trigger after the force has fallen back below 5 % of its peak) and
//!    overloads (the peak held for ≥ 3 samples, or at/above `clip_level`).
//! 2. **Windows**: a force window keeps the hammer pulse (up to `force_window_s` after the
//!    trigger) and zeroes the rest; an exponential window w(t) = exp(−t/τ), with τ chosen so
//!    that w falls to `exponential_end` at the record end, is applied to force and response.
//!    It adds the known decay rate 1/τ, so damping ratios are corrected: ζ = ζ_meas − 1/(τ ω_n).
//! 3. **Estimators** (averaged over the accepted impacts): G_ff = ⟨|F|²⟩, G_yy = ⟨|Y|²⟩,
//!    G_fy = ⟨F* Y⟩; H1 = G_fy / G_ff (unbiased for noise on the response), H2 = G_yy / G_yf
//!    (unbiased for noise on the force), coherence γ² = |G_fy|² / (G_ff G_yy).
//! 4. **Resonances**: local maxima of |H1| (on a zero-padded, interpolated spectrum) inside the
//!    usable band (force spectrum within 20 dB of its low-frequency level) with coherence
//!    ≥ 0.9 and at least 6 dB above the local median, damping
//!    from the half-power (−3 dB) bandwidth ζ = (f₂ − f₁) / (2 f_n), then the window correction.

use greybox_core::{Error, Result, SourcePos};
use realfft::num_complex::Complex64;
use realfft::{RealFftPlanner, RealToComplex};
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// Impact-test settings (study TOML `[characterize]`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ImpactConfig {
    /// Record length per impact, s (frequency resolution 1/block_s).
    pub block_s: f64,
    /// Record start before the trigger, s.
    pub pretrigger_s: f64,
    /// Trigger level as a fraction of the largest hammer force.
    pub trigger_fraction: f64,
    /// Length of the force window after the trigger, s.
    pub force_window_s: f64,
    /// Value of the exponential window at the record end (1: no exponential window).
    pub exponential_end: f64,
    /// Hammer level treated as clipped (overload), same unit as the hammer channel.
    pub clip_level: Option<f64>,
    /// Zero-padding factor for the peak search.
    pub zero_pad: usize,
    /// Lowest frequency of the peak search, Hz.
    pub min_frequency_hz: f64,
}

impl Default for ImpactConfig {
    fn default() -> Self {
        ImpactConfig {
            block_s: 1.0,
            pretrigger_s: 0.005,
            trigger_fraction: 0.1,
            force_window_s: 0.01,
            exponential_end: 0.01,
            clip_level: None,
            zero_pad: 8,
            min_frequency_hz: 5.0,
        }
    }
}

/// A hammer recording: the force and one response channel, uniformly sampled.
#[derive(Debug, Clone, PartialEq)]
pub struct ImpactRecording {
    pub source: String,
    pub sample_rate_hz: f64,
    pub hammer: Vec<f64>,
    pub response: Vec<f64>,
}

impl ImpactRecording {
    /// The recording as CSV with the columns `time_s,hammer_N,response_m` (one row a sample,
    /// t = k / f_s): the layout the characterize stage reads with its default channel names.
    pub fn to_csv(&self) -> String {
        let mut s = String::from("time_s,hammer_N,response_m\n");
        for k in 0..self.hammer.len() {
            s.push_str(&format!(
                "{},{},{}\n",
                k as f64 / self.sample_rate_hz,
                self.hammer[k],
                self.response[k]
            ));
        }
        s
    }
}

/// Why an impact was left out.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Rejected {
    pub time_s: f64,
    pub reason: String,
}

/// Averaged spectra of a set of impacts.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Frf {
    pub frequency_hz: Vec<f64>,
    pub h1: Vec<Complex64Ser>,
    pub h2: Vec<Complex64Ser>,
    pub coherence: Vec<f64>,
    pub impacts_used: usize,
    pub rejected: Vec<Rejected>,
    /// Time constant of the exponential window, s (∞ without one).
    pub tau_s: f64,
    /// Upper end of the usable band: where the hammer's force spectrum first falls 20 dB
    /// below its low-frequency level, Hz.
    pub usable_max_hz: f64,
    /// Zero-padded |H1| for peak picking.
    #[serde(skip)]
    fine: Vec<(f64, f64)>,
}

/// A complex number that serialises as [re, im].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Complex64Ser(pub Complex64);

impl Serialize for Complex64Ser {
    fn serialize<S: serde::Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        [self.0.re, self.0.im].serialize(s)
    }
}

/// A resonance found in |H1|.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Resonance {
    pub frequency_hz: f64,
    pub magnitude: f64,
    /// Half-power damping ratio as measured (includes the exponential window).
    pub damping_measured: f64,
    /// Damping ratio after the exponential-window correction.
    pub damping: f64,
}

fn err(src: &str, msg: impl Into<String>) -> Error {
    Error::input(SourcePos::file(src), msg)
}

/// Find and validate the impacts of a recording; returns the record start indices.
pub fn find_impacts(
    rec: &ImpactRecording,
    cfg: &ImpactConfig,
) -> Result<(Vec<usize>, Vec<Rejected>)> {
    let fs = rec.sample_rate_hz;
    if !(fs > 0.0) || rec.hammer.len() != rec.response.len() || rec.hammer.is_empty() {
        return Err(err(&rec.source, "hammer and response need the same, non-zero number of samples and a positive sample rate"));
    }
    if let Some(i) = rec
        .hammer
        .iter()
        .chain(&rec.response)
        .position(|v| !v.is_finite())
    {
        return Err(err(
            &rec.source,
            format!("sample {} is not finite", i % rec.hammer.len()),
        ));
    }
    let peak = rec.hammer.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if peak == 0.0 {
        return Err(err(
            &rec.source,
            "no impact found: the hammer channel is zero",
        ));
    }
    let thr = cfg.trigger_fraction * peak;
    let block = (cfg.block_s * fs).round() as usize;
    let pre = (cfg.pretrigger_s * fs).round() as usize;
    let fw = ((cfg.force_window_s * fs).round() as usize).max(1);
    let mut starts = Vec::new();
    let mut rejected = Vec::new();
    let mut i = 1;
    let n = rec.hammer.len();
    while i < n {
        if rec.hammer[i].abs() >= thr && rec.hammer[i - 1].abs() < thr {
            let t = i as f64 / fs;
            let start = i.saturating_sub(pre);
            if start + block > n {
                rejected.push(Rejected {
                    time_s: t,
                    reason: "record runs past the end of the file".into(),
                });
                break;
            }
            // pulse: from the trigger until the force falls below 5 % of the local peak
            let seg = &rec.hammer[i..(i + fw).min(n)];
            let local = seg.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let held = seg.windows(3).any(|w| {
                w.iter()
                    .all(|v| (v.abs() - local).abs() <= 1e-12 * local.max(1.0))
            });
            let clipped = cfg.clip_level.is_some_and(|c| local >= c);
            let end_pulse = seg
                .iter()
                .position(|v| v.abs() < 0.05 * local)
                .map(|k| i + k)
                .unwrap_or(i + seg.len());
            let double = rec.hammer[end_pulse..(start + block).min(n)]
                .iter()
                .any(|v| v.abs() >= thr);
            if held || clipped {
                rejected.push(Rejected {
                    time_s: t,
                    reason: "overload: the hammer signal is clipped".into(),
                });
            } else if double {
                rejected.push(Rejected {
                    time_s: t,
                    reason: "double hit within the record".into(),
                });
            } else {
                starts.push(start);
            }
            i = start + block; // next record after this one
            continue;
        }
        i += 1;
    }
    if starts.is_empty() {
        let why = if rejected.is_empty() {
            "no impact found".to_string()
        } else {
            format!(
                "no usable impact: {}",
                rejected
                    .iter()
                    .map(|r| format!("{:.3} s {}", r.time_s, r.reason))
                    .collect::<Vec<_>>()
                    .join("; ")
            )
        };
        return Err(err(&rec.source, why));
    }
    Ok((starts, rejected))
}

/// H1, H2 and coherence over all usable impacts of the recordings (same sample rate).
pub fn estimate(recs: &[ImpactRecording], cfg: &ImpactConfig) -> Result<Frf> {
    let fs = common_sample_rate(recs)?;
    if !(cfg.exponential_end > 0.0
        && cfg.exponential_end <= 1.0
        && cfg.block_s > 0.0
        && cfg.zero_pad > 0)
    {
        return Err(Error::invalid(
            "FRF",
            "exponential_end must be in (0, 1], block_s > 0, zero_pad ≥ 1",
        ));
    }
    if !(fs.is_finite() && fs > 0.0) {
        return Err(Error::invalid(
            "FRF",
            format!("the sample rate is {fs} Hz: expected a finite rate > 0"),
        ));
    }
    let mut impacts = Vec::with_capacity(recs.len());
    let mut rejected = Vec::new();
    for rec in recs {
        let (starts, rej) = find_impacts(rec, cfg)?;
        rejected.extend(rej);
        impacts.push(starts);
    }
    // The block is filled from one recording: a longer block is refused here, before its
    // buffers are allocated.
    let longest = recs.iter().map(|r| r.hammer.len()).max().unwrap_or(0);
    let block = cfg.block_s * fs;
    if !(block <= longest as f64) {
        return Err(Error::invalid(
            "FRF",
            format!(
                "block_s = {} s at {fs} Hz is {block} samples; the longest recording has {longest}",
                cfg.block_s
            ),
        ));
    }
    if cfg.zero_pad > 64 {
        return Err(Error::invalid(
            "FRF",
            format!("zero_pad = {} (at most 64)", cfg.zero_pad),
        ));
    }
    let mut sums = SpectralSums::new(fs, cfg);
    for (rec, starts) in recs.iter().zip(impacts) {
        for s in starts {
            sums.add(rec, s)?;
        }
    }
    Ok(sums.frf(fs, rejected))
}

/// The sample rate shared by all recordings.
fn common_sample_rate(recs: &[ImpactRecording]) -> Result<f64> {
    let fs = recs
        .first()
        .ok_or_else(|| Error::invalid("FRF", "no recordings"))?
        .sample_rate_hz;
    if let Some(r) = recs
        .iter()
        .find(|r| (r.sample_rate_hz - fs).abs() > 1e-9 * fs)
    {
        return Err(err(
            &r.source,
            format!(
                "sample rate {} Hz differs from {} Hz of the first recording",
                r.sample_rate_hz, fs
            ),
        ));
    }
    Ok(fs)
}

/// Auto- and cross-spectra G_ff, G_yy, G_fy summed over impacts, on the block's frequency
/// grid and (G_ff, G_fy) on the zero-padded fine grid, with the FFT plans and buffers they
/// are computed with. The force is kept only up to the end of the force window, both
/// signals are weighted by the exponential window.
struct SpectralSums {
    block: usize,
    /// Samples kept of the force: pre-trigger plus the force window.
    force_kept: usize,
    tau_s: f64,
    window: Vec<f64>,
    fft: Arc<dyn RealToComplex<f64>>,
    fft_fine: Arc<dyn RealToComplex<f64>>,
    gff: Vec<f64>,
    gyy: Vec<f64>,
    gfy: Vec<Complex64>,
    gff_f: Vec<f64>,
    gfy_f: Vec<Complex64>,
    used: usize,
    buffers: FftBuffers,
}

/// Time and frequency buffers of [`SpectralSums`], reused from impact to impact.
struct FftBuffers {
    xf: Vec<f64>,
    xy: Vec<f64>,
    sf: Vec<Complex64>,
    sy: Vec<Complex64>,
    pf: Vec<f64>,
    py: Vec<f64>,
    sff: Vec<Complex64>,
    sfy: Vec<Complex64>,
}

impl SpectralSums {
    fn new(fs: f64, cfg: &ImpactConfig) -> Self {
        let block = (cfg.block_s * fs).round() as usize;
        let pre = (cfg.pretrigger_s * fs).round() as usize;
        let fw = ((cfg.force_window_s * fs).round() as usize).max(1);
        let tau_s = if cfg.exponential_end < 1.0 {
            cfg.block_s / (1.0 / cfg.exponential_end).ln()
        } else {
            f64::INFINITY
        };
        let window: Vec<f64> = (0..block)
            .map(|k| (-((k as f64) / fs) / tau_s).exp())
            .collect();
        let mut planner = RealFftPlanner::<f64>::new();
        let fft = planner.plan_fft_forward(block);
        let nfine = block * cfg.zero_pad;
        let fft_fine = planner.plan_fft_forward(nfine);
        let (nf, nff) = (block / 2 + 1, nfine / 2 + 1);
        let buffers = FftBuffers {
            xf: vec![0.0; block],
            xy: vec![0.0; block],
            sf: fft.make_output_vec(),
            sy: fft.make_output_vec(),
            pf: vec![0.0; nfine],
            py: vec![0.0; nfine],
            sff: fft_fine.make_output_vec(),
            sfy: fft_fine.make_output_vec(),
        };
        SpectralSums {
            block,
            force_kept: pre + fw,
            tau_s,
            window,
            fft,
            fft_fine,
            gff: vec![0.0; nf],
            gyy: vec![0.0; nf],
            gfy: vec![Complex64::new(0.0, 0.0); nf],
            gff_f: vec![0.0; nff],
            gfy_f: vec![Complex64::new(0.0, 0.0); nff],
            used: 0,
            buffers,
        }
    }

    /// Add the impact of `rec` whose block starts at sample `s`.
    fn add(&mut self, rec: &ImpactRecording, s: usize) -> Result<()> {
        let block = self.block;
        let b = &mut self.buffers;
        for k in 0..block {
            b.xf[k] = if k < self.force_kept {
                rec.hammer[s + k] * self.window[k]
            } else {
                0.0
            };
            b.xy[k] = rec.response[s + k] * self.window[k];
        }
        b.pf[..block].copy_from_slice(&b.xf);
        b.py[..block].copy_from_slice(&b.xy);
        b.pf[block..].iter_mut().for_each(|v| *v = 0.0);
        b.py[block..].iter_mut().for_each(|v| *v = 0.0);
        let fft_err = |e: realfft::FftError| Error::invalid("FFT", e.to_string());
        self.fft.process(&mut b.xf, &mut b.sf).map_err(fft_err)?;
        self.fft.process(&mut b.xy, &mut b.sy).map_err(fft_err)?;
        self.fft_fine
            .process(&mut b.pf, &mut b.sff)
            .map_err(fft_err)?;
        self.fft_fine
            .process(&mut b.py, &mut b.sfy)
            .map_err(fft_err)?;
        for k in 0..self.gff.len() {
            self.gff[k] += b.sf[k].norm_sqr();
            self.gyy[k] += b.sy[k].norm_sqr();
            self.gfy[k] += b.sf[k].conj() * b.sy[k];
        }
        for k in 0..self.gff_f.len() {
            self.gff_f[k] += b.sff[k].norm_sqr();
            self.gfy_f[k] += b.sff[k].conj() * b.sfy[k];
        }
        self.used += 1;
        Ok(())
    }

    /// H1 = G_fy / G_ff, H2 = G_yy / G_fy*, the coherence |G_fy|² / (G_ff G_yy), |H1| on the
    /// fine grid, and the usable band (where G_ff is within 20 dB of its low-frequency value).
    fn frf(self, fs: f64, rejected: Vec<Rejected>) -> Frf {
        let (gff, gyy, gfy) = (&self.gff, &self.gyy, &self.gfy);
        let nf = gff.len();
        let df = fs / self.block as f64;
        let zero = Complex64::new(0.0, 0.0);
        let h1 = (0..nf)
            .map(|k| Complex64Ser(if gff[k] > 0.0 { gfy[k] / gff[k] } else { zero }))
            .collect();
        let h2 = (0..nf)
            .map(|k| {
                Complex64Ser(if gfy[k].norm() > 0.0 {
                    Complex64::new(gyy[k], 0.0) / gfy[k].conj()
                } else {
                    zero
                })
            })
            .collect();
        let coherence = (0..nf)
            .map(|k| {
                if gff[k] * gyy[k] > 0.0 {
                    gfy[k].norm_sqr() / (gff[k] * gyy[k])
                } else {
                    0.0
                }
            })
            .collect();
        let dff = fs / self.fine_len() as f64;
        let fine = (0..self.gff_f.len())
            .map(|k| {
                (
                    k as f64 * dff,
                    if self.gff_f[k] > 0.0 {
                        (self.gfy_f[k] / self.gff_f[k]).norm()
                    } else {
                        0.0
                    },
                )
            })
            .collect();
        let g0 = gff[1.min(nf - 1)];
        let usable_max_hz = (1..nf)
            .find(|&k| gff[k] < 0.01 * g0)
            .map(|k| k as f64 * df)
            .unwrap_or(fs / 2.0);
        Frf {
            frequency_hz: (0..nf).map(|k| k as f64 * df).collect(),
            h1,
            h2,
            coherence,
            impacts_used: self.used,
            rejected,
            tau_s: self.tau_s,
            usable_max_hz,
            fine,
        }
    }

    /// Length of the zero-padded block.
    fn fine_len(&self) -> usize {
        self.buffers.pf.len()
    }
}

impl Frf {
    /// Resonances of |H1| above `min_frequency_hz`, strongest first, with half-power damping.
    pub fn resonances(&self, cfg: &ImpactConfig, max_count: usize) -> Vec<Resonance> {
        let f = &self.fine;
        let nyq = f.last().map(|p| p.0).unwrap_or(0.0);
        let mut peaks = Vec::new();
        for k in 1..f.len().saturating_sub(1) {
            let (fk, m) = f[k];
            if fk < cfg.min_frequency_hz
                || fk > 0.8 * nyq
                || fk > self.usable_max_hz
                || !(m > f[k - 1].1 && m >= f[k + 1].1)
            {
                continue;
            }
            let half = m / std::f64::consts::SQRT_2;
            let left = (0..k).rev().find(|&j| f[j].1 < half);
            let right = (k + 1..f.len()).find(|&j| f[j].1 < half);
            let (Some(l), Some(r)) = (left, right) else {
                continue;
            };
            let interp = |a: usize, b: usize| {
                f[a].0 + (half - f[a].1) / (f[b].1 - f[a].1) * (f[b].0 - f[a].0)
            };
            let (f1, f2) = (interp(l, l + 1), interp(r - 1, r));
            // a genuine resonance is a peak of its own half-power band, measured coherently
            if (l..=r).any(|j| f[j].1 > m) {
                continue;
            }
            // prominence: at least 6 dB above the median |H1| within ±20 % of the frequency
            let mut around: Vec<f64> = f
                .iter()
                .filter(|p| (p.0 - fk).abs() <= 0.2 * fk)
                .map(|p| p.1)
                .collect();
            let mid = around.len() / 2;
            let (_, med, _) = around.select_nth_unstable_by(mid, f64::total_cmp);
            if m < 2.0 * *med {
                continue;
            }
            let df = self.frequency_hz.get(1).copied().unwrap_or(1.0);
            let kc = ((fk / df).round() as usize).min(self.coherence.len().saturating_sub(1));
            if self.coherence.get(kc).is_none_or(|c| *c < 0.9) {
                continue;
            }
            let zm = (f2 - f1) / (2.0 * fk);
            let wn = 2.0 * std::f64::consts::PI * fk;
            peaks.push(Resonance {
                frequency_hz: fk,
                magnitude: m,
                damping_measured: zm,
                damping: zm - 1.0 / (self.tau_s * wn),
            });
        }
        peaks.sort_by(|a, b| b.magnitude.total_cmp(&a.magnitude));
        peaks.truncate(max_count);
        peaks
    }
}

/// The article's dynamics check: the first resonance against the campaign's spindle
/// excitation (rotation frequency n/60 and its harmonics for every planned velocity).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ExcitationCheck {
    pub first_resonance_hz: f64,
    /// The plan's highest spindle speed, rpm: its rotation frequency's harmonics are checked.
    pub max_spindle_rpm: f64,
    pub max_excitation_hz: f64,
    pub harmonics: usize,
    /// first resonance / highest excitation frequency.
    pub ratio: f64,
    /// The article requires an order of magnitude.
    pub pass: bool,
}

/// Compare the lowest resonance with the plan's excitation frequencies.
pub fn excitation_check(
    resonances: &[Resonance],
    plan: &crate::plan::Plan,
    harmonics: usize,
) -> Result<ExcitationCheck> {
    let first = resonances
        .iter()
        .map(|r| r.frequency_hz)
        .fold(f64::INFINITY, f64::min);
    if !first.is_finite() {
        return Err(Error::invalid(
            "excitation check",
            "no resonance found in the FRF",
        ));
    }
    let max_rpm = plan.steps.iter().map(|s| s.spindle_rpm).fold(0.0, f64::max);
    let max_exc = max_rpm / 60.0 * harmonics.max(1) as f64;
    let ratio = first / max_exc;
    Ok(ExcitationCheck {
        first_resonance_hz: first,
        max_spindle_rpm: max_rpm,
        max_excitation_hz: max_exc,
        harmonics,
        ratio,
        pass: ratio >= 10.0,
    })
}
