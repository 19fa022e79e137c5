//! Apparent friction coefficients from raw recordings: alignment, drift compensation,
//! plateau detection and per-plateau statistics.
//!
//! Per pin:
//! 1. **Align** the plan with the recording: the trigger's rising edge (linear
//!    interpolation of the threshold crossing), or — without a trigger — the onset of sliding
//!    taken as the first S command.
//! 2. **Check** the recording covers the plan, and that the loaded level matches the
//!    planned force (catches wrong units or channel mapping).
//! 3. **Latency**: the onset of sliding (tangential force leaving its unloaded baseline)
//!    against the first S command gives the NC-to-spindle delay; all nominal times shift by it.
//! 4. **Drift**: per channel, the medians of the unloaded windows at the start and end of
//!    the pin define a linear offset, subtracted from the whole recording.
//! 5. **Plateaus**: within each step, spikes are masked (Hampel filter), μ = F_t/F_N is
//!    smoothed, the plateau level is taken from the tail of the step, and the end of the
//!    spindle ramp is the last time the smoothed μ is outside a robust band around that
//!    level. The plateau starts at the later of that time and the nominal ramp end, plus a
//!    settle time; it ends a margin before the next S command.
//! 6. **Statistics**: mean and standard deviation of F_t/F_N, sample count, linear trend
//!    (flag `trend`), and the peak-to-peak of the smoothed, detrended μ (flag `stick-slip`).

use crate::plan::Plan;
use crate::signal::running_median;
use crate::steady_window::{level_band, plateau_stats, step_signals};
use greybox_contact::hertz::PinContact;
use greybox_core::dataset::{flags, FrictionDataset, FrictionRecord};
use greybox_core::stats::median;
use greybox_core::{Error, Result, SourcePos};
use greybox_recording::Recording;
use serde::Serialize;

pub use crate::config::{IdentifyConfig, TimeZero};

/// What was found about a pin's recording besides the plateaus.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PinDiagnostics {
    pub pin: u32,
    pub source: String,
    /// Trigger edge, s on the recording's clock.
    pub trigger_s: f64,
    /// NC-to-spindle latency, s.
    pub latency_s: f64,
    /// Drift of the normal and tangential channels over the pin, N.
    pub drift_normal_n: f64,
    pub drift_tangential_n: f64,
    /// Samples masked as spikes in the plateaus.
    pub spikes_removed: usize,
}

/// Index of the first sample with time ≥ t.
fn index_at(time: &[f64], t: f64) -> usize {
    time.partition_point(|x| *x < t)
}

fn trigger_edge(rec: &Recording, cfg: &IdentifyConfig) -> Result<f64> {
    let trig = rec.trigger_v.as_ref().ok_or_else(|| {
        Error::input(
            SourcePos::file(&rec.source).field("trigger"),
            "no trigger channel mapped; map one or use `align` first-plateau",
        )
    })?;
    let (lo, hi) = trig
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(*v), b.max(*v))
        });
    let thr = cfg.trigger_threshold_v.unwrap_or(0.5 * (lo + hi));
    if !(hi - lo > 0.5) || thr <= lo || thr >= hi {
        return Err(Error::input(
            SourcePos::file(&rec.source).field("trigger"),
            format!("the trigger channel never switches (range {lo:.3}..{hi:.3} V, threshold {thr:.3} V)"),
        ));
    }
    if trig[0] >= thr {
        return Err(Error::input(
            SourcePos::file(&rec.source).field("trigger"),
            "the trigger is already high at the first sample: the recording misses the trigger edge (use `align` first-plateau)",
        ));
    }
    let i = trig
        .windows(2)
        .position(|w| w[0] < thr && w[1] >= thr)
        .expect("a crossing exists between lo and hi")
        + 1;
    let f = (thr - trig[i - 1]) / (trig[i] - trig[i - 1]);
    Ok(rec.time_s[i - 1] + f * (rec.time_s[i] - rec.time_s[i - 1]))
}

/// Median of `x` over the samples with t in [a, b).
fn window_median(rec: &Recording, x: &[f64], a: f64, b: f64) -> Option<f64> {
    let (i, j) = (index_at(&rec.time_s, a), index_at(&rec.time_s, b));
    (j > i + 2).then(|| median(&x[i..j]))
}

/// First time after `from` where the running median of (x − base) exceeds `thr`.
fn onset_after(rec: &Recording, x: &[f64], base: f64, from: f64, thr: f64) -> Option<f64> {
    let i0 = index_at(&rec.time_s, from);
    let dev: Vec<f64> = x[i0..].iter().map(|v| v - base).collect();
    let rm = running_median(&dev, 5);
    rm.iter().position(|v| *v > thr).map(|k| rec.time_s[i0 + k])
}

/// The load measured on a pin's first plateau against the plan: the error message when it
/// is nearer another pin's planned load than its own (swapped or mislabelled recordings), or
/// off its own by more than `tolerance` (relative: a channel in kN read as N, a wrong
/// mapping).
fn check_pin_load(
    loaded_n: f64,
    pin: u32,
    plan: &Plan,
    tolerance: f64,
) -> std::result::Result<(), String> {
    let own = plan.pins[pin as usize - 1].normal_force_n;
    let distance = |l: f64| (loaded_n / l).ln().abs();
    if !(loaded_n > 0.0) {
        return Err(format!(
            "measured normal force {loaded_n:.3} N during the first plateau, planned {own} N: check the channel mapping, sign and units"
        ));
    }
    if let Some((other, load)) = plan
        .pins
        .iter()
        .enumerate()
        .map(|(k, p)| (k as u32 + 1, p.normal_force_n))
        .filter(|(k, l)| *k != pin && *l != own)
        .min_by(|a, b| distance(a.1).total_cmp(&distance(b.1)))
    {
        if distance(load) < distance(own) && (loaded_n / load - 1.0).abs() <= tolerance {
            return Err(format!(
                "measured {loaded_n:.1} N on the first plateau is nearer pin {other}'s planned {load} N than this pin's ({pin}) {own} N: are the recordings swapped or mislabelled? (the files are taken in pin order)"
            ));
        }
    }
    if (loaded_n / own - 1.0).abs() > tolerance {
        let ratio = loaded_n / own;
        // the physics table's unit mistakes of a load against its plan (kgf, kN, mN as N);
        // a friction force in the normal channel is μ × the load
        let mut hints: Vec<String> = greybox_core::physics::mistake_against(
            greybox_core::physics::Quantity::NormalForce,
            loaded_n,
            own,
        )
        .into_iter()
        .collect();
        if ratio < 1.0 && greybox_core::physics::Quantity::Mu.usual().contains(&ratio) {
            hints.push(format!(
                "normal and friction channels swapped (the load would be μ {ratio:.3} × the planned one)"
            ));
        }
        let hint = if hints.is_empty() {
            String::new()
        } else {
            format!(": {}?", hints.join(" or "))
        };
        return Err(format!(
            "measured normal force {loaded_n:.3} N during the first plateau is {:+.0} % off the planned {own} N (tolerance {:.0} %){hint}; check the channel mapping and units",
            100.0 * (ratio - 1.0),
            100.0 * tolerance
        ));
    }
    Ok(())
}

/// Identify every plateau of one pin (1-based).
pub fn identify_pin(
    rec: &Recording,
    plan: &Plan,
    pin: u32,
    contact: &PinContact,
    cfg: &IdentifyConfig,
) -> Result<(Vec<FrictionRecord>, PinDiagnostics)> {
    rec.validate()?;
    let sched = plan
        .pins
        .get(pin as usize - 1)
        .ok_or_else(|| Error::invalid("identify", format!("no pin {pin} in the plan")))?;
    let c = PinContext {
        rec,
        plan,
        pin,
        sched,
        steps: plan.pin_steps(pin),
        cfg,
    };
    let (t0, known_latency) = align(&c)?;
    check_coverage(&c, t0)?;
    let latency = match known_latency {
        Some(l) => l,
        None => sliding_latency(&c, t0)?,
    };
    let ts = t0 + latency; // plan time zero on the recording clock
    let drift = remove_drift(&c, ts)?;
    // the loaded level must match the plan (units, mapping and file order check)
    let s0 = &c.steps[0];
    let loaded = window_median(
        rec,
        &drift.normal_n,
        ts + s0.plateau_start_s,
        ts + s0.plateau_end_s,
    )
    .unwrap_or(0.0);
    check_pin_load(loaded, pin, plan, cfg.match_load_tolerance)
        .map_err(|m| Error::input(c.src().field("normal"), m))?;
    let (rows, spikes_removed) = measure_plateaus(&c, ts, &drift, contact)?;
    Ok((
        rows,
        PinDiagnostics {
            pin,
            source: rec.source.clone(),
            trigger_s: t0,
            latency_s: latency,
            drift_normal_n: drift.drift_normal_n,
            drift_tangential_n: drift.drift_tangential_n,
            spikes_removed,
        },
    ))
}

/// What every stage of [`identify_pin`] looks at: the recording and the pin's part of the plan.
struct PinContext<'a> {
    rec: &'a Recording,
    plan: &'a Plan,
    pin: u32,
    sched: &'a crate::plan::PinSchedule,
    steps: &'a [crate::plan::PlanStep],
    cfg: &'a IdentifyConfig,
}

impl PinContext<'_> {
    fn src(&self) -> SourcePos {
        SourcePos::file(&self.rec.source)
    }
}

/// Stage 1, alignment: the plan's time zero on the recording clock, t0 (s), from the trigger
/// edge, or from the onset of sliding (then the latency is zero by construction, returned
/// as `Some(0)`).
fn align(c: &PinContext) -> Result<(f64, Option<f64>)> {
    let rec = c.rec;
    let z = c.plan.spec.zero_time_s;
    let f_nom = c.sched.normal_force_n;
    Ok(match c.cfg.align {
        TimeZero::Trigger => (trigger_edge(rec, c.cfg)?, None),
        TimeZero::FirstPlateau => {
            // unloaded baseline = first zero window of the recording
            let t_first = rec.time_s[0];
            let base_n =
                window_median(rec, &rec.normal_n, t_first, t_first + 0.5 * z).ok_or_else(|| {
                    Error::input(c.src(), "recording too short for an unloaded baseline")
                })?;
            let load =
                onset_after(rec, &rec.normal_n, base_n, t_first, 0.5 * f_nom).ok_or_else(|| {
                    Error::input(
                        c.src().field("normal"),
                        format!("the normal force never reaches half the planned {f_nom} N"),
                    )
                })?;
            let base_t =
                window_median(rec, &rec.tangential_n, t_first, t_first + 0.5 * z).unwrap_or(0.0);
            let level = window_median(
                rec,
                &rec.tangential_n,
                load + c.plan.spec.load_time_s,
                rec.time_s[rec.len() - 1],
            )
            .unwrap_or(0.0)
                - base_t;
            let onset = onset_after(
                rec,
                &rec.tangential_n,
                base_t,
                load,
                0.3 * level.abs().max(1e-9),
            )
            .ok_or_else(|| {
                Error::input(c.src().field("tangential"), "no onset of sliding found")
            })?;
            (onset - c.steps[0].step_start_s, Some(0.0))
        }
    })
}

/// Stage 2: the recording must cover the plan up to the middle of the final unloaded window.
fn check_coverage(c: &PinContext, t0: f64) -> Result<()> {
    let z = c.plan.spec.zero_time_s;
    let needed = t0 + c.sched.end_s - 0.5 * z;
    let last = c.rec.time_s[c.rec.len() - 1];
    if last < needed {
        return Err(Error::input(
            c.src(),
            format!(
                "recording is shorter than the plan: it ends {:.3} s after the trigger, pin {} needs {:.3} s",
                last - t0,
                c.pin,
                c.sched.end_s - 0.5 * z
            ),
        ));
    }
    Ok(())
}

/// Stage 3: the NC-to-spindle latency (s), from the onset of sliding after the first S
/// command; more than `max_latency_s` is an error.
fn sliding_latency(c: &PinContext, t0: f64) -> Result<f64> {
    let (rec, cfg) = (c.rec, c.cfg);
    let z = c.plan.spec.zero_time_s;
    let base_t =
        window_median(rec, &rec.tangential_n, t0 + 0.05 * z, t0 + 0.9 * z).ok_or_else(|| {
            Error::input(
                c.src(),
                "no samples in the unloaded window after the trigger",
            )
        })?;
    let s0 = &c.steps[0];
    let level = window_median(
        rec,
        &rec.tangential_n,
        t0 + s0.plateau_start_s + 0.1 * c.plan.spec.dwell_s,
        t0 + s0.plateau_end_s,
    )
    .ok_or_else(|| Error::input(c.src(), "no samples in the first plateau"))?
        - base_t;
    let from = t0 + s0.step_start_s - cfg.max_latency_s;
    let onset = onset_after(
        rec,
        &rec.tangential_n,
        base_t,
        from,
        0.3 * level.abs().max(1e-9),
    )
    .ok_or_else(|| {
        Error::input(
            c.src().field("tangential"),
            "no onset of sliding found near the first S command",
        )
    })?;
    let l = onset - (t0 + s0.step_start_s);
    if l.abs() > cfg.max_latency_s {
        return Err(Error::input(
            c.src(),
            format!(
                "sliding starts {l:.3} s after the first S command (max ±{} s): check the plan and the alignment",
                cfg.max_latency_s
            ),
        ));
    }
    Ok(l)
}

/// The forces with offset and linear drift removed, and the drift over the pin (N).
struct Drift {
    normal_n: Vec<f64>,
    tangential_n: Vec<f64>,
    drift_normal_n: f64,
    drift_tangential_n: f64,
}

/// Stage 4: offset and drift, a line through the medians of the unloaded windows at the
/// start and at the end of the pin (plan time zero `ts` on the recording clock), removed.
fn remove_drift(c: &PinContext, ts: f64) -> Result<Drift> {
    let rec = c.rec;
    let (spec, z) = (&c.plan.spec, c.plan.spec.zero_time_s);
    let last = rec.time_s[rec.len() - 1];
    let pre = (ts + 0.05 * z, ts + 0.9 * z);
    let post_start = ts + c.sched.unload_start_s + spec.load_time_s + 0.1 * z;
    let post = (post_start, (ts + c.sched.end_s - 0.05 * z).min(last));
    let pre_mid = 0.5 * (pre.0 + pre.1);
    let post_mid = 0.5 * (post.0 + post.1);
    let corrected = |x: &[f64], name: &str| -> Result<(Vec<f64>, f64)> {
        let (a, b) = match (
            window_median(rec, x, pre.0, pre.1),
            window_median(rec, x, post.0, post.1),
        ) {
            (Some(a), Some(b)) => (a, b),
            _ => {
                return Err(Error::input(
                    c.src().field(name),
                    "the unloaded windows at the start and end of the pin are empty",
                ))
            }
        };
        let slope = (b - a) / (post_mid - pre_mid);
        let v = rec
            .time_s
            .iter()
            .zip(x)
            .map(|(t, v)| v - a - slope * (t - pre_mid))
            .collect();
        Ok((v, slope * (post_mid - pre_mid)))
    };
    let (normal_n, drift_normal_n) = corrected(&rec.normal_n, "normal")?;
    let (tangential_n, drift_tangential_n) = corrected(&rec.tangential_n, "tangential")?;
    Ok(Drift {
        normal_n,
        tangential_n,
        drift_normal_n,
        drift_tangential_n,
    })
}

/// Stages 5 and 6: per step, the end of the spindle ramp from the smoothed μ, the steady
/// part after it, and μ with spikes masked; the rows and the number of spikes removed.
fn measure_plateaus(
    c: &PinContext,
    ts: f64,
    d: &Drift,
    contact: &PinContact,
) -> Result<(Vec<FrictionRecord>, usize)> {
    let (rec, cfg, pin) = (c.rec, c.cfg, c.pin);
    let fs = rec.sample_rate_hz();
    let f_nom = c.sched.normal_force_n;
    let mut out = Vec::with_capacity(c.steps.len());
    let mut spikes_total = 0usize;
    for s in c.steps {
        let a = ts + s.step_start_s;
        let b = ts + s.plateau_end_s;
        let (i, j) = (index_at(&rec.time_s, a), index_at(&rec.time_s, b));
        let pos = || c.src().field(format!("pin {pin} step {}", s.step));
        if j < i + 2 * cfg.min_plateau_samples {
            return Err(Error::input(pos(), "too few samples in the step window"));
        }
        let sig = step_signals(&d.normal_n, &d.tangential_n, i, j, cfg, fs, |k, f_n| {
            if f_n <= 0.1 * f_nom {
                return Err(Error::input(
                    pos(),
                    format!("normal force {f_n:.3} N at t = {:.3} s: zero or negative during a plateau (planned {f_nom} N)", rec.time_s[k]),
                ));
            }
            Ok(())
        })?;
        let sm = &sig.smooth;
        let n = sm.len();
        let (level, band) = level_band(&sm[(n * 6) / 10..], 0.002);
        let head_end = (n * 7) / 10;
        let ramp_end_k = sm[..head_end]
            .iter()
            .rposition(|v| (v - level).abs() > band)
            .map(|k| k + sig.w_smooth / 2);
        let nominal_start = ts + s.plateau_start_s;
        let detected = ramp_end_k
            .map(|k| rec.time_s[i + k.min(n - 1)])
            .unwrap_or(a);
        let p_start = detected.max(nominal_start) + cfg.settle_time_s;
        let p_end = b - cfg.end_margin_s;
        // settle and end margins longer than the step leave an empty plateau, not an index
        // outside the step's window
        let (pi, pj) = (
            index_at(&rec.time_s, p_start).saturating_sub(i).min(n),
            index_at(&rec.time_s, p_end).saturating_sub(i).min(n),
        );
        let mut st = plateau_stats(&rec.time_s, &d.normal_n, &sig, pi, pj, ts, cfg).ok_or_else(|| {
            let usable = (pi..pj).filter(|k| sig.good[*k]).count();
            let why = if p_end <= nominal_start + cfg.settle_time_s {
                format!(
                    "settle_time_s ({} s) and end_margin_s ({} s) leave nothing of the step's {:.3} s plateau",
                    cfg.settle_time_s,
                    cfg.end_margin_s,
                    b - nominal_start
                )
            } else {
                "the spindle ramp overran the dwell".to_string()
            };
            Error::input(
                pos(),
                format!(
                    "only {usable} usable samples in the plateau (min {}): {why}",
                    cfg.min_plateau_samples
                ),
            )
        })?;
        if detected > nominal_start + 0.5 * c.plan.spec.dwell_s {
            st.flags.insert(0, flags::RAMP_UNCONFIRMED.to_string());
        }
        spikes_total += st.spikes;
        let flags = std::mem::take(&mut st.flags);
        out.push(st.record(
            contact,
            crate::steady_window::PlateauPlace {
                pin,
                step: s.step,
                planned_n: Some(s.normal_force_n),
                velocity_m_s: s.sliding_velocity_m_s,
                flags,
                label_evidence: Some(greybox_core::dataset::label_evidence::PLAN_TIMING),
            },
        )?);
    }
    Ok((out, spikes_total))
}

/// Identify a whole campaign: `recordings[k]` is pin k + 1.
pub fn identify_pins(
    plan: &Plan,
    recordings: &[Recording],
    contact: &PinContact,
    cfg: &IdentifyConfig,
) -> Result<(FrictionDataset, Vec<PinDiagnostics>)> {
    if recordings.len() != plan.pins.len() {
        return Err(Error::invalid(
            "identify",
            format!(
                "the plan has {} pins but {} recordings were given",
                plan.pins.len(),
                recordings.len()
            ),
        ));
    }
    let mut records = Vec::with_capacity(plan.steps.len());
    let mut diags = Vec::with_capacity(recordings.len());
    for (k, rec) in recordings.iter().enumerate() {
        let (r, d) = identify_pin(rec, plan, k as u32 + 1, contact, cfg)?;
        records.extend(r);
        diags.push(d);
    }
    Ok((FrictionDataset { records }, diags))
}
