//! The steady state of a cut, every steady quantity with its confidence interval, and the rule
//! that runs a cut until it is sure.
//!
//! A cut's forces do not settle to a number: a serrated chip makes them periodic, contacts
//! entering and leaving the windows make them jitter, and the flank's contact with the
//! machined surface comes and goes. So a steady quantity is a mean over a long stretch, and
//! how sure it is depends on how long the stretch is against the signal's own correlation
//! ([`greybox_core::stats`]). Per cut:
//!
//! 1. **Force bins.** The tool force is averaged over bins of equal length (the force
//!    history's rows, each an exact mean over its steps).
//! 2. **Warm-up.** From the set-up's `min_cut_length_m` on (the chip must have formed), the
//!    start where the forces' marginal standard error is least (MSER-5,
//!    [`greybox_core::stats::mser_truncation`]; the later of F'c's and F'f's).
//! 3. **Period.** The fundamental period of the force signal (of F'c or F'f, whichever
//!    repeats more clearly; [`greybox_core::stats::period`]), the segmentation of a serrated
//!    chip; the averaged stretch is then a whole number of periods ending with the run, so
//!    that the mean holds no partial segment. Without one, the unit is one force bin.
//! 4. **Intervals.** Every quantity — F'c, F'f, the chip thickness, the contact length, the
//!    peak and mean rake-face temperature, the segment pitch and degree of segmentation —
//!    is averaged per unit over the same stretch (less its own warm-up: a quantity that
//!    settles later than the forces, a chip still rising into its measuring band, drops the
//!    whole units before its MSER start), and its 95 % interval is formed from batch
//!    means that respect its autocorrelation ([`greybox_core::stats::batch_means`]). Each
//!    interval says what it rests on (units, batches); one that would rest on fewer than
//!    four batches is not given: the cut is too short to say how sure it is.
//!
//! **How long is long enough.** No interval can see a fluctuation slower than the stretch it
//! is formed from. A cut's slowest ones are those of the tool–chip contact: a chip element
//! crosses the contact length l_c at the chip's speed v h/h_c, so the contact renews itself
//! once every l_c h_c/h of cut, and the contact length, the flank contact and with them F'f
//! wander on that scale. On the Ti6Al4V template (l_c h_c/h ≈ 0.17 mm) intervals formed from
//! stretches of 0.05–0.3 mm covered the long-run mean in 16–80 % of the sub-records, from
//! 0.5 mm on in 86–100 % (docs/validation.md). So every steady state states how many contact
//! renewals its stretch spans, an interval from fewer than `min_contact_renewals` (default 3)
//! is marked short, and a cut is never sure on one.
//!
//! **Drift.** Every quantity also states how much its batch means change across the stretch
//! along their least-squares line, with an interval ([`greybox_core::stats::Drift`]). A
//! change larger than its interval means the quantity was still settling (the forces of a
//! cut whose tool is still warming fall along the cut): its mean is that of the stretch, not
//! a steady value, and a force that drifts is never sure. Nor is a cut whose tool–chip
//! contact still lengthens: the contact is the cut's slowest state, and as it creeps up the
//! rake it takes load from the edge and the flank, so F'f falls — but by less than its
//! scatter for the first millimetres. Refined 5 µm Ti6Al4V cuts whose forces were sure at
//! 2 mm had contacts lengthening significantly across the stretch (+8 ± 5 µm), and a third
//! cut of the same condition, run on, had F'f fall by 8 N/mm (docs/validation.md, "The chip
//! that never breaks"). The contact is the grey-box loop's (the farthest window in contact,
//! per interval, [`LoopContact`]): the chip's farthest touching particle does not show the
//! creep, the load moving out does.
//!
//! **Run until sure** ([`RunUntilSure`]): with `stop_when_sure`, the force intervals are
//! re-formed as the cut goes (every hundredth of its length), and the cut stops once the
//! stretch spans `min_contact_renewals` renewals, neither force nor the contact length
//! drifts and F'c's and F'f's
//! relative half-widths are at most the set-up's targets; otherwise it runs to its `cut_length_m`, the length limit,
//! and says that it hit it. (The sequential check is the relative-precision procedure of Law
//! & Kelton, §9.4.1, on batch means, with a minimum length from the physics of the cut.)

use crate::cut_series::{ChipSampler, CutSeries, LoopContact, Samples};
use crate::cutting::{CuttingSetup, SteadySetup};
use crate::executor::{Control, Observer};
use crate::output::ForceHistory;
use crate::serration::Serration;
use crate::solver::{SimError, Solver};
use greybox_core::stats::{batch_means, mser_truncation, period, unit_means, MeanInterval, LEVEL};
use serde::{Deserialize, Serialize};

/// The least correlation at which a force signal counts as periodic.
pub const PERIOD_MIN_CORRELATION: f64 = 0.3;
/// Force bins per MSER batch (MSER-5).
const MSER_BATCH: usize = 5;
/// Fewest force bins a steady stretch is looked for in.
const MIN_BINS: usize = 16;

/// The averaged stretch of a cut: whole units (periods, or force bins) ending with the run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SteadyWindow {
    /// Start and end of the stretch, s.
    pub from_s: f64,
    pub to_s: f64,
    /// One unit, s: the force signal's period, or one force bin.
    pub unit_s: f64,
    /// Units in the stretch.
    pub units: usize,
    /// The period found in the force signal (chip segmentation), s.
    pub period_s: Option<f64>,
}

impl SteadyWindow {
    /// The stretch of `forces` to average: from `min_time_s` and past the warm-up, whole
    /// periods (or bins) ending with the last bin. `None` before [`MIN_BINS`] bins.
    pub fn of(forces: &ForceHistory, min_time_s: f64) -> Option<SteadyWindow> {
        let rows = &forces.rows;
        let i0 = rows.partition_point(|r| r[0] < min_time_s * (1.0 - 1e-12));
        if rows.len() < i0 + MIN_BINS {
            return None;
        }
        let column =
            |c: usize, from: usize| -> Vec<f64> { rows[from..].iter().map(|r| r[c]).collect() };
        let warm_up = mser_truncation(&column(3, i0), MSER_BATCH)
            .max(mser_truncation(&column(4, i0), MSER_BATCH));
        let start = i0 + warm_up;
        let bin_s = bin_length(rows)?;
        let n = rows.len() - start;
        let found = [3, 4]
            .into_iter()
            .filter_map(|c| period(&column(c, start), n / 3, PERIOD_MIN_CORRELATION))
            .max_by(|a, b| a.correlation.total_cmp(&b.correlation));
        let unit_s = found.map_or(bin_s, |p| p.samples * bin_s);
        let to_s = rows[rows.len() - 1][0];
        let span = to_s - (rows[start][0] - bin_s);
        let units = (span / unit_s * (1.0 + 1e-9)).floor() as usize;
        (units > 0).then(|| SteadyWindow {
            from_s: to_s - units as f64 * unit_s,
            to_s,
            unit_s,
            units,
            period_s: found.map(|p| p.samples * bin_s),
        })
    }

    /// The mean of `samples` over the stretch with its 95 % interval (`None`: no sample in it).
    pub fn mean(&self, samples: &[(f64, f64)]) -> Option<MeanInterval> {
        let units = self.units - self.own_warm_up_units(samples);
        let u = unit_means(samples, self.to_s, self.unit_s, units);
        (!u.is_empty()).then(|| batch_means(&u, LEVEL))
    }

    /// Whole units at the start of the stretch that `samples` spend still settling, past the
    /// forces' warm-up: a quantity that settles later than the forces (a chip still rising
    /// into its measuring band, a tool still heating) drops its own warm-up, found by MSER
    /// on its samples inside the stretch (at most half of them,
    /// [`greybox_core::stats::mser_truncation`]); at least one unit is kept.
    fn own_warm_up_units(&self, samples: &[(f64, f64)]) -> usize {
        let from = self.to_s - self.units as f64 * self.unit_s;
        let inside: Vec<(f64, f64)> = samples
            .iter()
            .copied()
            .filter(|&(t, _)| t > from && t <= self.to_s)
            .collect();
        let values: Vec<f64> = inside.iter().map(|s| s.1).collect();
        let d = mser_truncation(&values, 1);
        if d == 0 {
            return 0;
        }
        let settled_from = inside[d - 1].0;
        let dropped = ((settled_from - from) / self.unit_s * (1.0 - 1e-9)).floor() as usize;
        dropped.min(self.units - 1)
    }

    /// F'c and F'f (N/m) over the stretch with their intervals (the stretch is made of
    /// force bins, so it holds some).
    pub fn forces(&self, forces: &ForceHistory) -> [MeanInterval; 2] {
        [3, 4].map(|c| {
            let series: Samples = forces.rows.iter().map(|r| (r[0], r[c])).collect();
            batch_means(
                &unit_means(&series, self.to_s, self.unit_s, self.units),
                LEVEL,
            )
        })
    }
}

/// The length of one force bin, s (the rows' common spacing in time).
fn bin_length(rows: &[[f64; 6]]) -> Option<f64> {
    let n = rows.len();
    (n >= 2).then(|| (rows[n - 1][0] - rows[0][0]) / (n - 1) as f64)
}

/// A cut's steady state: the stretch averaged and every steady quantity with its interval.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SteadyState {
    pub window: SteadyWindow,
    /// Cutting and feed force per width, N/m.
    pub cutting_force: MeanInterval,
    pub feed_force: MeanInterval,
    /// Chip thickness, m ([`crate::chip::chip_thickness`]).
    pub chip_thickness: Option<MeanInterval>,
    /// The chip's extent along the rake-face normal, m ([`crate::chip::chip_extent`]).
    #[serde(default)]
    pub chip_extent: Option<MeanInterval>,
    /// Tool–chip contact length on the rake side, m.
    pub contact_length: Option<MeanInterval>,
    /// Hottest and contact-force-weighted mean window temperature along the rake face in
    /// contact, K.
    pub rake_peak_temperature: Option<MeanInterval>,
    pub rake_mean_temperature: Option<MeanInterval>,
    /// Segment pitch along the chip, m, and degree of segmentation (instants with a serrated
    /// chip only; `serrated_share` of the instants sampled in the stretch had one).
    pub segment_pitch: Option<MeanInterval>,
    pub segmentation_degree: Option<MeanInterval>,
    pub serrated_share: f64,
    /// The cut length over which the chip renews its contact with the rake face, m
    /// ([`ChipSampler::contact_renewal_m`]), and the renewals the stretch spans.
    pub contact_renewal_m: Option<f64>,
    pub renewals: Option<f64>,
}

impl SteadyState {
    /// Every steady quantity of a cut over `window`; `renewal_m`: the contact renewal length
    /// over it, `speed_m_s` the cutting speed.
    pub fn of(
        window: SteadyWindow,
        forces: &ForceHistory,
        series: &CutSeries,
        renewal_m: Option<f64>,
        speed_m_s: f64,
    ) -> SteadyState {
        let [cutting_force, feed_force] = window.forces(forces);
        let inside: Vec<&(f64, Option<Serration>)> = series
            .serration
            .iter()
            .filter(|(t, _)| *t > window.from_s && *t <= window.to_s)
            .collect();
        let serrated: Vec<(f64, Serration)> = inside
            .iter()
            .filter_map(|(t, s)| s.map(|s| (*t, s)))
            .collect();
        let serrated_share = if inside.is_empty() {
            0.0
        } else {
            serrated.len() as f64 / inside.len() as f64
        };
        // a chip serrated at most instants of the stretch has a pitch and a degree
        let of_serration = |f: &dyn Fn(&Serration) -> f64| {
            (serrated_share >= 0.5)
                .then(|| window.mean(&serrated.iter().map(|(t, s)| (*t, f(s))).collect::<Vec<_>>()))
                .flatten()
        };
        SteadyState {
            window,
            cutting_force,
            feed_force,
            chip_thickness: window.mean(&series.chip_thickness),
            chip_extent: window.mean(&series.chip_extent),
            contact_length: window.mean(&series.contact_length),
            rake_peak_temperature: window.mean(&series.rake_peak_temperature),
            rake_mean_temperature: window.mean(&series.rake_mean_temperature),
            segment_pitch: of_serration(&|s| s.pitch_m),
            segmentation_degree: of_serration(&|s| s.degree),
            serrated_share,
            contact_renewal_m: renewal_m,
            renewals: renewals(&window, renewal_m, speed_m_s),
        }
    }

    /// Whether the stretch is long enough and the force intervals meet the set-up's targets.
    pub fn sure(&self, st: &SteadySetup) -> bool {
        forces_sure(
            &[self.cutting_force, self.feed_force],
            self.contact_length.as_ref(),
            self.renewals,
            st,
        )
    }

    /// The stretch spans fewer contact renewals than `st` asks (its intervals may understate
    /// the scatter).
    pub fn short(&self, st: &SteadySetup) -> bool {
        !long_enough(self.renewals, st)
    }
}

/// The contact renewals the stretch of `w` spans (`None` without a renewal length).
fn renewals(w: &SteadyWindow, renewal_m: Option<f64>, speed_m_s: f64) -> Option<f64> {
    renewal_m
        .filter(|l| *l > 0.0)
        .map(|l| (w.to_s - w.from_s) * speed_m_s / l)
}

fn long_enough(renewals: Option<f64>, st: &SteadySetup) -> bool {
    renewals.is_some_and(|r| r >= st.min_contact_renewals)
}

/// Whether the stretch spans enough renewals, F'c's and F'f's relative half-widths are at
/// most the targets of `st`, and neither force nor the tool–chip contact length drifts
/// across the stretch (a force still settling is not sure of its steady value however
/// narrow its interval; a contact still lengthening moves the load from the edge and flank
/// up the rake, and F'f follows it later: module docs, "Drift").
fn forces_sure(
    f: &[MeanInterval; 2],
    contact: Option<&MeanInterval>,
    renewals: Option<f64>,
    st: &SteadySetup,
) -> bool {
    let within =
        |m: &MeanInterval, target: f64| !m.drifting() && m.relative().is_some_and(|r| r <= target);
    long_enough(renewals, st)
        && !contact.is_some_and(MeanInterval::drifting)
        && within(&f[0], st.cutting_force_rel_ci95)
        && within(&f[1], st.feed_force_rel_ci95)
}

/// The tool-force history and the chip's samples of a cut, and the stop once its force
/// intervals meet their targets (module docs).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct RunUntilSure {
    pub forces: ForceHistory,
    pub chip: ChipSampler,
    pub setup: SteadySetup,
    /// No steady state before this simulated time, s (the set-up's minimum cut length).
    pub min_time_s: f64,
    /// The intervals are re-formed every this many force bins.
    pub check_every_bins: usize,
    /// When the targets were met, s (once met).
    pub sure_at_s: Option<f64>,
    pub speed_m_s: f64,
    /// The contact length of each interval of the grey-box loop, m, as it closed.
    #[serde(default)]
    pub contact: Samples,
    #[serde(skip)]
    loop_contact: Option<LoopContact>,
    checked_bins: usize,
}

impl RunUntilSure {
    /// Force bins and chip samples every `bin_steps` steps of tool `tool` of the cut `cut`,
    /// checked every `check_every_bins` bins.
    pub fn new(tool: usize, bin_steps: u64, cut: &CuttingSetup, check_every_bins: usize) -> Self {
        let setup = &cut.steady;
        RunUntilSure {
            forces: ForceHistory::new(tool, bin_steps),
            chip: ChipSampler::new(cut, tool, bin_steps),
            speed_m_s: cut.cutting_speed_m_s,
            setup: setup.clone(),
            min_time_s: setup.min_cut_length_m / cut.cutting_speed_m_s,
            check_every_bins: check_every_bins.max(1),
            sure_at_s: None,
            contact: Vec::new(),
            loop_contact: LoopContact::new(cut),
            checked_bins: 0,
        }
    }

    /// The observer of a resumed run (its histories so far; the set-up given again).
    pub fn resumed(mut self, cut: &CuttingSetup) -> Self {
        self.chip = self.chip.resumed(cut);
        self.loop_contact = LoopContact::new(cut);
        self
    }

    /// The steady stretch of the cut so far.
    pub fn window(&self) -> Option<SteadyWindow> {
        SteadyWindow::of(&self.forces, self.min_time_s)
    }

    /// The contact renewal length over `w`, m.
    pub fn renewal_m(&self, w: &SteadyWindow) -> Option<f64> {
        self.chip.contact_renewal_m(w.from_s, w.to_s)
    }

    /// Whether the stretch so far is long enough, its force intervals meet the targets and
    /// the loop's contact length does not drift.
    fn sure_now(&self) -> bool {
        self.window().is_some_and(|w| {
            let r = renewals(&w, self.renewal_m(&w), self.speed_m_s);
            let contact = w.mean(&self.contact);
            forces_sure(&w.forces(&self.forces), contact.as_ref(), r, &self.setup)
        })
    }
}

impl Observer for RunUntilSure {
    fn start(&mut self, sim: &Solver) -> Result<(), SimError> {
        self.forces.start(sim)
    }
    fn save_state(&self) -> Option<(&'static str, serde_json::Value)> {
        crate::executor::SavedState::saved(self)
    }
    fn after_step(&mut self, sim: &Solver) -> Result<Control, SimError> {
        self.forces.after_step(sim)?;
        self.chip.after_step(sim)?;
        if let Some(l) = self
            .loop_contact
            .as_ref()
            .and_then(|c| c.at_close(sim, self.chip.tool))
        {
            self.contact.push((sim.time, l));
        }
        let bins = self.forces.rows.len();
        if bins < self.checked_bins + self.check_every_bins || sim.time < self.min_time_s {
            return Ok(Control::Continue);
        }
        self.checked_bins = bins;
        if self.sure_at_s.is_none() && self.sure_now() {
            self.sure_at_s = Some(sim.time);
        }
        Ok(if self.sure_at_s.is_some() && self.setup.stop_when_sure {
            Control::Stop
        } else {
            Control::Continue
        })
    }
}

impl crate::executor::SavedState for RunUntilSure {
    const KEY: &'static str = "steady";
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// A force history of `n` bins of 1 s (a period that is no whole number of bins, so that
    /// the sampled sawtooth averages to zero): a ramp over the first 40 bins to a level, then a
    /// sawtooth of `period` bins and amplitude `a` (a serrated chip) plus uniform noise of
    /// half-width `noise` (correlated over three bins), both components at `level`.
    fn history(
        n: usize,
        level: [f64; 2],
        period: f64,
        a: f64,
        noise: f64,
        seed: u64,
    ) -> ForceHistory {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let phase: f64 = rng.gen_range(0.0..1.0);
        let mut h = ForceHistory::new(0, 1);
        let mut e = [0.0; 2];
        for k in 0..n {
            let ramp = (k as f64 / 40.0).min(1.0);
            let saw = a * ((k as f64 / period + phase).fract() - 0.5);
            for ec in e.iter_mut() {
                *ec = 0.6 * *ec + rng.gen_range(-noise..noise);
            }
            let t = (k + 1) as f64;
            h.rows.push([
                t,
                0.0,
                0.0,
                ramp * (level[0] + saw + e[0]),
                ramp * (level[1] + 0.5 * saw + e[1]),
                0.0,
            ]);
        }
        h
    }

    #[test]
    fn the_window_skips_the_ramp_and_holds_whole_periods() {
        let h = history(600, [100.0, 40.0], 17.3, 20.0, 2.0, 1);
        let w = SteadyWindow::of(&h, 10.0).expect("a window");
        assert!(w.from_s >= 35.0, "{w:?}");
        let p = w.period_s.expect("the sawtooth's period");
        assert!((p - 17.3).abs() < 0.5, "{p}");
        assert!((w.to_s - w.from_s - w.units as f64 * w.unit_s).abs() < 1e-9);
        let [fc, ff] = w.forces(&h);
        assert!(fc.covers(100.0) && ff.covers(40.0), "{fc:?} {ff:?}");
        assert!(fc.batches >= 4);
    }

    #[test]
    fn the_force_intervals_cover_the_known_mean_at_their_level() {
        let (mut covered, mut formed) = (0usize, 0usize);
        for seed in 0..300 {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let period = rng.gen_range(8.0..30.0);
            let h = history(500, [100.0, 40.0], period, 15.0, 4.0, seed);
            let Some(w) = SteadyWindow::of(&h, 10.0) else {
                continue;
            };
            for (m, truth) in w.forces(&h).iter().zip([100.0, 40.0]) {
                if m.half_width.is_some() {
                    formed += 1;
                    covered += m.covers(truth) as usize;
                }
            }
        }
        let share = covered as f64 / formed as f64;
        assert!(formed >= 550, "{formed}");
        assert!(
            (0.90..=0.99).contains(&share),
            "coverage {share:.3} of {formed}"
        );
    }

    /// Targets of ±5 % on both forces (the records' noise meets them).
    fn five_percent_targets() -> SteadySetup {
        SteadySetup {
            cutting_force_rel_ci95: 0.05,
            feed_force_rel_ci95: 0.05,
            ..SteadySetup::default()
        }
    }

    /// A feed force that falls by 15 % along the cut (a tool still warming) has a
    /// narrow interval and is not sure; the same record without the fall is.
    #[test]
    fn a_drifting_force_is_never_sure() {
        let st = five_percent_targets();
        let level = history(1500, [100.0, 40.0], 17.3, 4.0, 8.0, 3);
        let mut falling = level.clone();
        for row in falling.rows.iter_mut() {
            row[4] -= 6.0 * row[0] / 1500.0;
        }
        let sure = |h: &ForceHistory| {
            let w = SteadyWindow::of(h, 100.0).expect("a window");
            let f = w.forces(h);
            (forces_sure(&f, None, Some(10.0), &st), f[1])
        };
        let (steady_sure, steady_ff) = sure(&level);
        assert!(steady_sure && !steady_ff.drifting(), "{steady_ff:?}");
        let (falling_sure, falling_ff) = sure(&falling);
        assert!(
            falling_ff.relative().is_some_and(|r| r <= 0.05),
            "{falling_ff:?}"
        );
        assert!(falling_ff.drifting() && !falling_sure, "{falling_ff:?}");
        let change = falling_ff.drift.expect("a drift").change;
        assert!(change < -4.0, "the fall across the stretch: {change}");
    }

    /// Steady forces with a contact that lengthens by 8 % across the stretch (under its
    /// noise at every instant) are not sure; the same forces with the contact level are.
    #[test]
    fn a_lengthening_contact_is_never_sure() {
        let st = five_percent_targets();
        let h = history(1500, [100.0, 40.0], 17.3, 4.0, 8.0, 3);
        let w = SteadyWindow::of(&h, 100.0).expect("a window");
        let f = w.forces(&h);
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let contact = |creep: f64, rng: &mut ChaCha8Rng| -> Samples {
            (1..=1500)
                .map(|k| {
                    let t = k as f64;
                    (
                        t,
                        100e-6 * (1.0 + creep * t / 1500.0) + rng.gen_range(-8e-6..8e-6),
                    )
                })
                .collect()
        };
        let level = w.mean(&contact(0.0, &mut rng)).expect("an interval");
        let creeping = w.mean(&contact(0.08, &mut rng)).expect("an interval");
        assert!(
            !level.drifting() && creeping.drifting(),
            "{level:?} {creeping:?}"
        );
        assert!(forces_sure(&f, Some(&level), Some(10.0), &st));
        assert!(!forces_sure(&f, Some(&creeping), Some(10.0), &st));
    }

    #[test]
    fn no_window_before_the_minimum_cut_length_or_from_a_few_bins() {
        let h = history(100, [100.0, 40.0], 10.0, 5.0, 1.0, 2);
        assert!(SteadyWindow::of(&h, 90.0).is_none());
        assert!(SteadyWindow::of(&h, 10.0).is_some());
    }
}
