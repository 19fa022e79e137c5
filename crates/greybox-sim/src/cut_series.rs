//! The series a cut's steady state is formed from besides its forces ([`CutSeries`]): the chip sampled as the cut goes ([`ChipSampler`]: its
//! thickness and serration), and the rake-face contact of every interval of the grey-box loop
//! ([`contact_series`]: contact length, peak and mean temperature).

use crate::chip::{chip_thickness_and_extent, contact_length, contact_profile, IN_CONTACT};
use crate::cutting::{CuttingSetup, EdgeLayout, Face};
use crate::executor::{Control, Observer};
use crate::friction_loop::FrictionUpdater;
use crate::serration::{chip_shape, Serration};
use crate::solver::{SimError, Solver};
use crate::tool::Tool;
use serde::{Deserialize, Serialize};

/// A sampled series: (time s, value).
pub type Samples = Vec<(f64, f64)>;

/// The sampled series a cut's steady state is formed from, besides its forces.
#[derive(Debug, Clone, Default)]
pub struct CutSeries {
    pub chip_thickness: Samples,
    /// The chip's extent along the rake-face normal, m ([`crate::chip::chip_extent`]).
    pub chip_extent: Samples,
    pub contact_length: Samples,
    pub rake_peak_temperature: Samples,
    pub rake_mean_temperature: Samples,
    /// Serration per chip sample (`None`: no two segments at that instant).
    pub serration: Vec<(f64, Option<Serration>)>,
}

/// One instant of the chip: its thickness and extent (m, [`crate::chip`]), serration and
/// contact length with the rake face (m, [`crate::serration::ChipShape::contact_length_m`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ChipSample {
    pub time_s: f64,
    pub thickness_m: Option<f64>,
    #[serde(default)]
    pub extent_m: Option<f64>,
    pub serration: Option<Serration>,
    pub contact_length_m: Option<f64>,
}

/// Samples the chip of tool `tool` every `every` steps.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ChipSampler {
    pub tool: usize,
    pub every: u64,
    pub samples: Vec<ChipSample>,
    #[serde(skip)]
    setup: Option<Box<CuttingSetup>>,
}

impl ChipSampler {
    pub fn new(setup: &CuttingSetup, tool: usize, every: u64) -> Self {
        ChipSampler {
            tool,
            every: every.max(1),
            samples: Vec::new(),
            setup: Some(Box::new(setup.clone())),
        }
    }

    /// The sampler of a resumed run: its samples so far, the set-up given again.
    pub fn resumed(mut self, setup: &CuttingSetup) -> Self {
        self.setup = Some(Box::new(setup.clone()));
        self
    }

    /// The samples' (time s, value) where `value` has one.
    fn series(&self, value: impl Fn(&ChipSample) -> Option<f64>) -> Samples {
        self.samples
            .iter()
            .filter_map(|s| value(s).map(|v| (s.time_s, v)))
            .collect()
    }

    /// The cut length over which the chip renews its contact with the rake face, m: a chip
    /// element flows at v h/h_c over the contact length l_c, in l_c h_c/h of cut (the means
    /// of the samples in (from_s, to_s]; `None` without a chip in contact).
    pub fn contact_renewal_m(&self, from_s: f64, to_s: f64) -> Option<f64> {
        let h = self.setup.as_deref()?.uncut_chip_thickness_m;
        let inside = || {
            self.samples
                .iter()
                .filter(|s| s.time_s > from_s && s.time_s <= to_s)
        };
        let mean = |v: Vec<f64>| (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64);
        let l = mean(inside().filter_map(|s| s.contact_length_m).collect())?;
        let hc = mean(inside().filter_map(|s| s.thickness_m).collect())?;
        Some(l * hc / h)
    }
}

impl Observer for ChipSampler {
    fn after_step(&mut self, sim: &Solver) -> Result<Control, SimError> {
        if !sim.step.is_multiple_of(self.every) {
            return Ok(Control::Continue);
        }
        let Some(setup) = self.setup.as_deref() else {
            return Ok(Control::Continue);
        };
        let shape = chip_shape(sim, setup, self.tool);
        let (thickness_m, extent_m) = chip_thickness_and_extent(sim, setup, self.tool);
        self.samples.push(ChipSample {
            time_s: sim.time,
            thickness_m,
            extent_m,
            serration: shape.as_ref().and_then(|s| s.serration()),
            contact_length_m: shape.and_then(|s| s.contact_length_m),
        });
        Ok(Control::Continue)
    }
}

/// The contact length of the grey-box loop's intervals as they close, read off the tool's
/// windows (each keeps its last closed interval, [`crate::tool::Window::last_interval`], and
/// the tool the step it closed at, [`crate::tool::Tool::last_close_step`]): the same length
/// [`contact_series`] gives per interval, available while the cut runs, at whatever cadence
/// the loop closes.
#[derive(Debug, Clone)]
pub struct LoopContact {
    layout: EdgeLayout,
    window_length: f64,
}

impl LoopContact {
    /// For the loop of `setup` (`None`: its insert has no layout).
    pub fn new(setup: &CuttingSetup) -> Option<Self> {
        Some(LoopContact {
            layout: setup.insert.layout().ok()?,
            window_length: setup.friction.window_length_m,
        })
    }

    /// The contact length of the interval the loop closed at this step of `sim`, m (`None`:
    /// no interval closed at this step, or no window in contact).
    pub fn at_close(&self, sim: &Solver, tool: usize) -> Option<f64> {
        let t = sim.tools.get(tool)?;
        if t.last_close_step != Some(sim.step) {
            return None;
        }
        let sums: Vec<_> = t.windows.iter().map(|w| w.last_interval).collect();
        let profile = contact_profile(t, &self.layout, &sums, sim.particles.spacing);
        contact_length(&profile, self.window_length, IN_CONTACT)
    }
}

/// Per whole interval of the grey-box loop (at its end time; the partial one a run's end
/// closes is left out, as the stop rule never sees it): the contact length on the rake side
/// (m), and the hottest and the normal-force-weighted mean temperature (K) of the rake and
/// edge windows in contact for at least [`IN_CONTACT`] of their length.
pub fn contact_series(
    updater: &FrictionUpdater,
    tool: &Tool,
    layout: &EdgeLayout,
    spacing: f64,
    window_length: f64,
) -> [Samples; 3] {
    let mut out: [Samples; 3] = Default::default();
    for iv in updater.intervals.iter().filter(|iv| !iv.partial) {
        let profile = contact_profile(tool, layout, &iv.windows, spacing);
        let t = iv.t_end_s;
        if let Some(l) = contact_length(&profile, window_length, IN_CONTACT) {
            out[0].push((t, l));
        }
        let rake: Vec<(f64, f64)> = profile
            .iter()
            .filter(|p| matches!(p.face, Face::Rake | Face::Edge))
            .filter_map(|p| p.stats)
            .filter(|s| s.contact_fraction >= IN_CONTACT)
            .map(|s| (s.temperature_k, s.normal_stress_pa))
            .collect();
        let weight: f64 = rake.iter().map(|r| r.1).sum();
        if !rake.is_empty() && weight > 0.0 {
            out[1].push((t, rake.iter().map(|r| r.0).fold(f64::MIN, f64::max)));
            out[2].push((t, rake.iter().map(|r| r.0 * r.1).sum::<f64>() / weight));
        }
    }
    out
}

/// The series of a cut: the chip samples and the loop's contact intervals.
pub fn cut_series(
    chip: &ChipSampler,
    updater: &FrictionUpdater,
    tool: &Tool,
    layout: &EdgeLayout,
    spacing: f64,
    window_length: f64,
) -> CutSeries {
    let [contact_length, rake_peak_temperature, rake_mean_temperature] =
        contact_series(updater, tool, layout, spacing, window_length);
    CutSeries {
        chip_thickness: chip.series(|s| s.thickness_m),
        chip_extent: chip.series(|s| s.extent_m),
        contact_length,
        rake_peak_temperature,
        rake_mean_temperature,
        serration: chip
            .samples
            .iter()
            .map(|s| (s.time_s, s.serration))
            .collect(),
    }
}
