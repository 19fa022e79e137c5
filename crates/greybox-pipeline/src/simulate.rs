//! The built-in 2D SPH solver as a stage: pin sliding and orthogonal cutting runs with
//! their outputs (forces, contact profile, μ history, plots, VTK, checkpoints).

use crate::chip_picture::{write_chip_pictures, FrameRecorder};
use crate::output::provenance;
use anyhow::{Context, Result};
use greybox_core::atomic::write_string_atomic;
use greybox_core::outputs::{check_dir_output, Existing, StagedDir};
use greybox_core::FrictionLaw;
use greybox_sim::checkpoint::{Checkpoint, Checkpointer};
use greybox_sim::chip::{CutMeasures, ProfilePoint};
use greybox_sim::cut_run::{fingerprint as fingerprint_cut, CutRun};
use greybox_sim::cutting::CuttingSetup;
use greybox_sim::output::{
    write_mu_history_csv, write_profile_csv, write_tool_temperature_csv, write_windows_csv,
    ForceHistory, VtkSeries,
};
use greybox_sim::pin::{fingerprint, simulate_from, PinResult, PinSetup};
use greybox_sim::tool::WindowStats;
use greybox_sim::ConstantMu;
use greybox_sim::{Hooks, SavedState, Solver};
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// The output directory of a simulation when no `out` is given.
pub const DEFAULT_SIM_DIR: &str = "sim-out";

/// Where and how a simulation writes.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
#[serde(deny_unknown_fields, default)]
pub struct RunOutput {
    /// Output directory.
    #[cfg_attr(feature = "cli", arg(long, default_value = DEFAULT_SIM_DIR))]
    pub out: PathBuf,
    /// Write VTK particle files every N steps (0: first and last only).
    #[cfg_attr(feature = "cli", arg(long = "vtk-every", default_value_t = StepInterval::of(0)))]
    pub vtk_every: StepInterval,
    /// Write a checkpoint every N steps (0: none).
    #[cfg_attr(feature = "cli", arg(long = "checkpoint-every", default_value_t = StepInterval::of(0)))]
    pub checkpoint_every: StepInterval,
    /// Resume an interrupted run from its checkpoint (`OUT.partial/checkpoint.json`: a run
    /// with checkpoints works in `OUT.partial` until it is complete, then becomes `OUT`).
    /// The resumed run's outputs equal those of an uninterrupted one.
    #[cfg_attr(feature = "cli", arg(long))]
    pub resume: Option<PathBuf>,
    /// Replace an existing, non-empty output directory (or a left-over `OUT.partial`) whole.
    #[cfg_attr(feature = "cli", arg(long))]
    pub force: bool,
    /// Cuts: also draw the chip at this many evenly spaced instants (`frames/chip_NNN.svg`,
    /// shown as a strip and a slider by the report); 0: only the last state
    /// (`chip_temperature.svg`, `chip_plastic_strain.svg`).
    #[cfg_attr(feature = "cli", arg(long, default_value_t = Frames::of(0)))]
    pub frames: Frames,
}

impl Default for RunOutput {
    fn default() -> Self {
        RunOutput {
            out: PathBuf::from(DEFAULT_SIM_DIR),
            vtk_every: StepInterval::of(0),
            checkpoint_every: StepInterval::of(0),
            resume: None,
            force: false,
            frames: Frames::of(0),
        }
    }
}

impl RunOutput {
    /// Write into `out`, VTK at the first and last step only, no checkpoints.
    pub fn to(out: impl Into<PathBuf>) -> Self {
        RunOutput {
            out: out.into(),
            ..Default::default()
        }
    }
    /// The directory this run writes into: a staging directory swapped in whole when the run
    /// completes; for runs with checkpoints, the resumable `OUT.partial`.
    fn stage(&self) -> Result<StagedDir> {
        let existing = Existing::from_force(self.force);
        if self.checkpoint_every.get() > 0 || self.resume.is_some() {
            return Ok(StagedDir::resumable(
                &self.out,
                "out",
                existing,
                self.resume.is_some(),
            )?);
        }
        check_dir_output(&self.out, "out", &[])?;
        Ok(StagedDir::begin(&self.out, "out", existing)?)
    }
}

/// Time steps between two outputs (VTK files, checkpoints); 0: none.
pub type StepInterval = greybox_core::count::Count<0, 1_000_000_000_000>;
/// Chip pictures drawn during a cut (each an SVG file); 0: the last state only.
pub type Frames = greybox_core::count::Count<0, 10_000>;

/// Output seams shared by pin and cutting runs: the VTK series and the checkpoints.
struct Observers {
    vtk: VtkSeries,
    ckpt: Option<Checkpointer>,
}

impl Observers {
    fn new(o: &RunOutput, dir: &Path, setup_id: &str) -> Self {
        Observers {
            vtk: VtkSeries::new(
                &dir.join("vtk"),
                match o.vtk_every.as_u64() {
                    0 => u64::MAX,
                    n => n,
                },
            ),
            ckpt: (o.checkpoint_every.get() > 0).then(|| {
                Checkpointer::new(
                    &dir.join("checkpoint.json"),
                    o.checkpoint_every.as_u64(),
                    setup_id,
                )
            }),
        }
    }
    fn hooks(&mut self) -> Hooks<'_> {
        let hooks = Hooks::new().observe(&mut self.vtk);
        match self.ckpt.as_mut() {
            Some(c) => hooks.checkpoint(c),
            None => hooks,
        }
    }
}

/// Whether `e` is a call stopped on request rather than a failure, from any stage: the core's
/// [`greybox_core::interrupt::Interrupted`] or [`greybox_core::Error::Interrupted`], or the
/// simulator's [`greybox_sim::SimError::Interrupted`], anywhere in its chain of causes.
pub fn is_interrupted(e: &anyhow::Error) -> bool {
    e.chain().any(|cause| {
        cause
            .downcast_ref::<greybox_core::interrupt::Interrupted>()
            .is_some()
            || matches!(
                cause.downcast_ref::<greybox_core::Error>(),
                Some(greybox_core::Error::Interrupted)
            )
            || cause
                .downcast_ref::<greybox_sim::SimError>()
                .is_some_and(greybox_sim::SimError::is_interrupted)
    })
}

fn read_checkpoint(p: &Option<PathBuf>) -> Result<Option<Checkpoint>> {
    p.as_ref().map(|p| Ok(Checkpoint::read(p)?)).transpose()
}

/// Adds the files a failed run left behind to the error.
fn failure_context(e: greybox_sim::SimError, obs: &Observers) -> anyhow::Error {
    let mut files: Vec<String> = obs
        .vtk
        .written
        .iter()
        .filter(|p| p.to_string_lossy().contains("last_good"))
        .map(|p| p.display().to_string())
        .collect();
    if let Some(p) = obs.ckpt.as_ref().and_then(|c| c.failure_path.as_ref()) {
        files.push(p.display().to_string());
    }
    if files.is_empty() {
        anyhow::anyhow!(e)
    } else {
        anyhow::anyhow!("{e}\nlast good state written to: {}", files.join(", "))
    }
}

fn write_common(
    out: &Path,
    sim: &Solver,
    hist: &ForceHistory,
    summary: &impl serde::Serialize,
) -> Result<()> {
    hist.write_csv(&out.join("forces.csv"))?;
    for (k, t) in sim.tools.iter().enumerate() {
        write_windows_csv(
            &out.join(format!("windows_tool{k}.csv")),
            t,
            sim.particles.spacing,
        )?;
    }
    write_string_atomic(
        &out.join("summary.json"),
        &serde_json::to_string_pretty(summary)?,
    )?;
    Ok(())
}

/// How deep the pin is pressed in.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Indentation {
    /// The depth, m.
    Depth(f64),
    /// A measured track width w, m: depth d = r − √(r² − (w/2)²) for a pin of radius r.
    TrackWidth(f64),
}

impl Indentation {
    /// The depth, m, for a pin of radius `pin_radius_m`.
    pub fn depth_m(self, pin_radius_m: f64) -> Result<f64> {
        Ok(match self {
            Indentation::Depth(d) => d,
            Indentation::TrackWidth(w) => greybox_contact::ploughing::track_depth(pin_radius_m, w)?,
        })
    }
}

/// Press and slide a pin ([`PinSetup`]); writes forces, windows, VTK, the summary and
/// the provenance into `o.out`.
pub fn run_pin(setup: &PinSetup, o: &RunOutput) -> Result<PinResult> {
    let resume = read_checkpoint(&o.resume)?;
    let staged = o.stage()?;
    let mut obs = Observers::new(o, staged.path(), &fingerprint(setup));
    let (res, hist, sim) =
        simulate_from(setup, resume, &mut obs.hooks()).map_err(|e| failure_context(e, &obs))?;
    write_common(staged.path(), &sim, &hist, &res)?;
    let resume_input: Vec<(&str, &Path)> =
        o.resume.iter().map(|r| ("resume", r.as_path())).collect();
    provenance(&resume_input)?.write_into(staged.path())?;
    staged.commit()?;
    Ok(res)
}

/// A cutting set-up TOML with the friction law it names.
pub struct CutCase {
    pub setup: CuttingSetup,
    pub law: Arc<dyn FrictionLaw>,
    /// Where the law came from (file path or "constant mu").
    pub law_source: String,
    /// The files the case was read from (set-up TOML, law file), for the run's provenance.
    pub inputs: Vec<(&'static str, PathBuf)>,
}

/// Reads a cutting set-up TOML and loads its law file (relative to the set-up's folder).
pub fn read_cutting_setup(path: &Path) -> Result<CutCase> {
    let text = crate::config_toml::read_text(path, "cutting set-up")?;
    cutting_setup_of_text(&text, path, &path.display().to_string())
}

/// [`read_cutting_setup`] of the set-up `text` that stands for the file at `path` (its
/// directory resolves relative paths); `source` names it in messages.
pub fn cutting_setup_of_text(text: &str, path: &Path, source: &str) -> Result<CutCase> {
    let mut setup: CuttingSetup = crate::config_toml::parse(text, source, "cutting set-up")?;
    let base = path.parent().unwrap_or(Path::new("."));
    let material_inputs =
        load_material_files(&mut setup.material, base).with_context(|| source.to_string())?;
    setup.validate().with_context(|| source.to_string())?;
    let mut case = cut_case(setup, base)?;
    case.inputs.insert(0, ("config", path.to_path_buf()));
    case.inputs.extend(material_inputs);
    Ok(case)
}

/// Reads the files a material names (a flow-stress table's curves; relative paths against
/// `base`) into it; returns them for the run's provenance.
pub fn load_material_files(
    material: &mut greybox_material::Material,
    base: &Path,
) -> Result<Vec<(&'static str, PathBuf)>> {
    let mut inputs = Vec::new();
    if let Some(greybox_material::FlowStress::Table(t)) = material.plasticity.as_mut() {
        if let Some(f) = &t.file {
            inputs.push(("material.plasticity.file", base.join(f)));
        }
        t.load(base)?;
    }
    Ok(inputs)
}

/// Pairs a set-up with its law: the law file or the inline law (relative paths against
/// `base`), or Coulomb `mu`.
pub fn cut_case(setup: CuttingSetup, base: &Path) -> Result<CutCase> {
    let mut inputs = Vec::new();
    if let Some(inline) = &setup.friction.law {
        let spec: greybox_friction::spec::LawSpec = serde_json::from_value(inline.clone())
            .map_err(|e| anyhow::anyhow!("[friction.law]: invalid inline law: {e}"))?;
        inputs.extend(
            spec.files(base)
                .into_iter()
                .map(|f| ("a file friction.law reads", f)),
        );
        let law = spec.build(base).context("[friction.law]")?;
        return Ok(CutCase {
            law_source: format!("inline law {}", law.name()),
            law: Arc::from(law),
            setup,
            inputs,
        });
    }
    let (law, law_source): (Arc<dyn FrictionLaw>, String) = match &setup.friction.law_file {
        Some(f) => {
            let p = base.join(f);
            let law_file = greybox_friction::spec::LawFile::read(&p)
                .with_context(|| format!("friction.law_file {}", p.display()))?;
            let law_files = law_file.inputs();
            let law = law_file
                .build()
                .with_context(|| format!("friction.law_file {}", p.display()))?;
            for f in law_files {
                let role = if f == p {
                    "friction.law_file"
                } else {
                    "a file friction.law_file reads"
                };
                inputs.push((role, f));
            }
            (Arc::from(law), p.display().to_string())
        }
        None => (
            Arc::new(ConstantMu(setup.mu)),
            format!("constant mu = {}", setup.mu),
        ),
    };
    Ok(CutCase {
        setup,
        law,
        law_source,
        inputs,
    })
}

/// What coarsening did in a cut (see `greybox_sim::coarsen`).
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct Coarsened {
    /// Particles merged away (three per merge).
    pub particles: u64,
    /// Kinetic and elastic energy the merges averaged out, J/m.
    pub energy_j_per_m: f64,
    /// That energy over the external work.
    pub share_of_work: f64,
}

/// What a cut gave: forces, chip measures, speed, files.
#[derive(Debug, Clone, serde::Serialize)]
pub struct CutSummary {
    pub particles: usize,
    /// Particles removed above `chip_break_height_m` (absent without a chip break; see
    /// `greybox_sim::sink`); their energy is in the balance of `energy_error`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub chip_removed_particles: Option<u64>,
    /// Refined particles merged away behind the tool and in the chip (three per merge), and
    /// the kinetic and elastic energy the merges averaged out, J/m (absent without
    /// `coarsen_behind_m` and `coarsen_chip_above_m`; see `greybox_sim::coarsen`); the energy
    /// is in the balance of `energy_error`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub coarsened: Option<Coarsened>,
    pub steps: u64,
    /// Steps of the tool's approach, before any particle could move, that skipped the
    /// particle passes (their results would be the same); included in `steps` and left out
    /// of the particle-steps rates.
    pub idle_steps: u64,
    pub dt_s: f64,
    pub simulated_cut_length_mm: f64,
    pub wall_s: f64,
    pub particle_steps_per_s: f64,
    pub particle_steps_per_s_per_core: f64,
    pub threads: usize,
    /// Instruction set of the pair passes on this CPU (`baseline`, `avx2`, `avx512`; every
    /// path gives the same bits, see `greybox_sim::cpu`).
    pub simd: &'static str,
    pub mass_scaling: f64,
    pub law: String,
    pub windows: usize,
    pub window_updates: usize,
    /// Whether a steady stretch was found, and the cut length where it starts.
    pub steady: bool,
    pub steady_from_mm: Option<f64>,
    /// Whether the force intervals met the targets (`steady_criterion`), and the cut length
    /// where they first did.
    pub sure: bool,
    pub sure_at_mm: Option<f64>,
    /// The run ended because it was sure (before its length limit, `cut_length_m`).
    pub stopped_when_sure: bool,
    /// The run asked to stop when sure but reached its length limit first: its intervals
    /// are wider than the targets.
    pub limit_reached: bool,
    /// The steady stretch spans fewer contact renewals than `steady_criterion` asks: its
    /// intervals may understate the scatter (docs/cutting.md).
    pub short_stretch: bool,
    /// The targets (relative half-widths of F'c's and F'f's 95 % intervals), the minimum
    /// cut length, and whether the run stops once they are met.
    pub steady_criterion: greybox_sim::cutting::SteadySetup,
    /// Mean cutting and feed force, N/mm: over the steady stretch (whole periods), or the
    /// last half of a run too short to have one.
    pub cutting_force_n_per_mm: f64,
    pub feed_force_n_per_mm: f64,
    /// Half-widths of their 95 % intervals, N/mm (`None`: no steady stretch, or too short a
    /// one to say; `steady_state.rests_on` tells).
    pub cutting_force_ci95_n_per_mm: Option<f64>,
    pub feed_force_ci95_n_per_mm: Option<f64>,
    /// Half-width of the chip compression ratio's 95 % interval.
    pub compression_ratio_ci95: Option<f64>,
    /// Every steady quantity with its interval and what it rests on (`None`: no steady
    /// stretch).
    pub steady_state: Option<greybox_sim::steady_report::SteadyReport>,
    /// Feed over cutting force.
    pub force_ratio: f64,
    /// Specific cutting force F'c / h, N/mm².
    pub specific_cutting_force_n_per_mm2: f64,
    /// Profiles and measures are time averages from this cut length on, mm.
    pub averaged_from_mm: f64,
    #[serde(flatten)]
    pub measures: CutMeasures,
    pub energy_error: f64,
    /// The hottest particle over the run, °C (sampled 500 times and at the end;
    /// `max_temperature_c` is the hottest at the end).
    pub peak_temperature_c: f64,
    /// The flow-stress model's melting point, °C (compare `peak_temperature_c`).
    pub melt_temperature_c: Option<f64>,
    /// Hottest tool cell at the end, °C (thermal tools).
    pub tool_max_temperature_c: Option<f64>,
    /// Heat into the tool over all heat generated (β W_plastic + W_friction) (thermal tools).
    pub tool_heat_share: Option<f64>,
    /// How far ductile damage has gone in the particles at the end (a material with
    /// `[material.damage]`; absent otherwise).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub damage_at_end: Option<greybox_sim::particles::DamageState>,
    /// Time scaling: run speed over physical speed (1: none).
    pub speed_up: f64,
    pub files: Vec<String>,
}

/// Runs a cut; writes forces, contact profile, μ history, plots and the summary to `o.out`.
pub fn run_cut(case: &CutCase, fraction: f64, o: &RunOutput) -> Result<CutSummary> {
    let setup = &case.setup;
    let id = fingerprint_cut(setup);
    let resume = read_checkpoint(&o.resume)?;
    let staged = o.stage()?;
    let mut obs = Observers::new(o, staged.path(), &id);
    let mut frames = match resume
        .as_ref()
        .and_then(|c| c.observers.get(<FrameRecorder as SavedState>::KEY))
    {
        Some(v) => serde_json::from_value(v.clone()).context("the checkpoint's chip frames")?,
        None => FrameRecorder::new(setup.duration_s() * fraction, o.frames.get().max(1)),
    };
    let r = {
        let mut hooks = obs.hooks().observe(&mut frames);
        CutRun::execute(setup, case.law.clone(), fraction, resume, &mut hooks)
    }
    .map_err(|e| failure_context(e, &obs))?;
    let v = setup.cutting_speed_m_s;
    let tool = &r.sim.tools[0];
    let out = staged.path();
    let mut files = vec![
        out.join("forces.csv"),
        out.join("contact_profile.csv"),
        out.join("mu_history.csv"),
        out.join("summary.json"),
    ];
    r.forces.write_csv(&files[0])?;
    write_profile_csv(&files[1], &r.profile)?;
    write_mu_history_csv(&files[2], &r.updater.history, tool, &r.layout)?;
    let tool_field = out.join("tool_temperature.csv");
    if write_tool_temperature_csv(&tool_field, tool)? {
        files.push(tool_field);
    }
    let averaged = AveragedPart {
        from_mm: r.averaged_from_s * v * 1e3,
        steady: r.steady_state.is_some(),
    };
    files.extend(write_cut_plots(
        out,
        &r.forces,
        &r.profile,
        v,
        Some(averaged),
    )?);
    files.extend(write_chip_pictures(
        out,
        &frames.frames,
        o.frames.get() > 0,
        &|t| t * v * 1e3,
    )?);
    let shown = files
        .iter()
        .map(|p| staged.shown(p).display().to_string())
        .collect();
    let s = cut_summary(case, &r, shown);
    write_string_atomic(&files[3], &serde_json::to_string_pretty(&s)?)?;
    let mut inputs: Vec<(&str, &Path)> =
        case.inputs.iter().map(|(r, p)| (*r, p.as_path())).collect();
    if let Some(r) = &o.resume {
        inputs.push(("resume", r.as_path()));
    }
    provenance(&inputs)?.write_into(out)?;
    staged.commit()?;
    Ok(s)
}

/// The summary of cut run `r` of `case` (forces per mm of width, chip measures, heat,
/// speeds), listing `files`.
fn cut_summary(case: &CutCase, r: &CutRun, files: Vec<String>) -> CutSummary {
    let setup = &case.setup;
    let v = setup.cutting_speed_m_s;
    let tool = &r.sim.tools[0];
    let threads = greybox_sim::threads();
    let f = r.force;
    let steady = r
        .steady_state
        .as_ref()
        .map(|s| greybox_sim::steady_report::SteadyReport::of(s, v, setup.uncut_chip_thickness_m));
    CutSummary {
        particles: r.sim.particle_count(),
        chip_removed_particles: setup
            .chip_break_height_m
            .map(|_| r.sim.energy.removed_particles),
        coarsened: setup
            .refinement
            .as_ref()
            .filter(|c| c.coarsen_behind_m.is_some() || c.coarsen_chip_above_m.is_some())
            .map(|_| Coarsened {
                particles: r.sim.energy.coarsened_particles,
                energy_j_per_m: r.sim.energy.coarsened,
                share_of_work: r.sim.energy.coarsened
                    / r.sim.energy.external_work.abs().max(f64::MIN_POSITIVE),
            }),
        steps: r.summary.steps,
        idle_steps: r.summary.idle_steps,
        dt_s: r.sim.dt,
        simulated_cut_length_mm: r.sim.time * v * 1e3,
        wall_s: r.summary.wall_s,
        particle_steps_per_s: r.summary.particle_steps_per_s,
        particle_steps_per_s_per_core: r.summary.particle_steps_per_s / threads as f64,
        threads,
        simd: greybox_sim::cpu::active().name(),
        mass_scaling: r.sim.numerics.mass_scaling,
        law: format!("{} ({})", case.law.name(), case.law_source),
        windows: tool.windows.len(),
        window_updates: r.updater.history.len(),
        steady: r.steady_state.is_some(),
        steady_from_mm: r.steady_state.as_ref().map(|s| s.window.from_s * v * 1e3),
        sure: r.sure_at_s.is_some(),
        sure_at_mm: r.sure_at_s.map(|t| t * v * 1e3),
        stopped_when_sure: r.summary.stopped_by_observer
            && setup.steady.stop_when_sure
            && r.sure_at_s.is_some(),
        limit_reached: setup.steady.stop_when_sure && r.sure_at_s.is_none(),
        short_stretch: r
            .steady_state
            .as_ref()
            .is_none_or(|s| s.short(&setup.steady)),
        steady_criterion: setup.steady.clone(),
        cutting_force_n_per_mm: f[0] * 1e-3,
        feed_force_n_per_mm: f[1] * 1e-3,
        cutting_force_ci95_n_per_mm: steady.as_ref().and_then(|s| s.cutting_force_n_per_mm.ci95),
        feed_force_ci95_n_per_mm: steady.as_ref().and_then(|s| s.feed_force_n_per_mm.ci95),
        compression_ratio_ci95: steady
            .as_ref()
            .and_then(|s| s.compression_ratio.as_ref())
            .and_then(|q| q.ci95),
        steady_state: steady,
        force_ratio: if f[0] != 0.0 { f[1] / f[0] } else { 0.0 },
        specific_cutting_force_n_per_mm2: f[0] * 1e-3 / (setup.uncut_chip_thickness_m * 1e3),
        averaged_from_mm: r.averaged_from_s * v * 1e3,
        measures: r.measures,
        energy_error: r.sim.energy_balance().relative_error,
        peak_temperature_c: r.peak_temperature.peak_k - 273.15,
        melt_temperature_c: setup
            .material
            .plasticity
            .as_ref()
            .map(|f| f.melt_temperature_k() - 273.15),
        tool_max_temperature_c: tool.thermal.as_ref().map(|t| t.max_temperature() - 273.15),
        tool_heat_share: tool.thermal.as_ref().map(|_| {
            let e = &r.sim.energy;
            let sources = setup.material.thermal.taylor_quinney * e.plastic_work + e.friction_work;
            if sources > 0.0 {
                e.tool_heat / sources
            } else {
                0.0
            }
        }),
        damage_at_end: setup
            .material
            .damage
            .as_ref()
            .map(|_| r.sim.particles.damage_state()),
        speed_up: setup.speed_up(),
        files,
    }
}

/// The part of a cut its forces and profiles are averaged over: from `from_mm` of cut to
/// the end; `steady`: the steady-force criterion was met there (else: the last half).
#[derive(Debug, Clone, Copy)]
pub struct AveragedPart {
    pub from_mm: f64,
    pub steady: bool,
}

/// SVG plots of a cut: force history (with the averaged part shaded) and the rake-face
/// contact profile (the article's Fig. 15, bottom: pressure and shear stress, sliding
/// velocity, μ, temperature).
pub fn write_cut_plots(
    out: &Path,
    hist: &ForceHistory,
    profile: &[ProfilePoint],
    v: f64,
    averaged: Option<AveragedPart>,
) -> Result<Vec<PathBuf>> {
    let mut written = vec![write_force_plot(out, hist, v, averaged)?];
    written.extend(write_profile_plots(out, profile)?);
    Ok(written)
}

/// `name` in `out`: an SVG of `series` (label, colour, x, y) against the x axis `x_label`,
/// with shaded x `bands`.
fn save_plot(
    out: &Path,
    name: &str,
    title: &str,
    axes: (&str, &str),
    series: &[(&str, &str, &[f64], &[f64])],
    bands: &[(f64, f64, &str)],
) -> Result<PathBuf> {
    let (x_label, y_label) = axes;
    use greybox_core::plot::{lines, Line};
    let ls: Vec<Line> = series
        .iter()
        .map(|&(label, colour, x, y)| Line {
            label,
            colour,
            x,
            y,
        })
        .collect();
    let p = out.join(name);
    write_string_atomic(&p, &lines(title, x_label, y_label, &ls, false, bands))?;
    Ok(p)
}

/// forces.svg: cutting and feed force per unit width over the cut length.
fn write_force_plot(
    out: &Path,
    hist: &ForceHistory,
    v: f64,
    averaged: Option<AveragedPart>,
) -> Result<PathBuf> {
    let cut_mm: Vec<f64> = hist.rows.iter().map(|r| r[0] * v * 1e3).collect();
    let fc: Vec<f64> = hist.rows.iter().map(|r| r[3] * 1e-3).collect();
    let ff: Vec<f64> = hist.rows.iter().map(|r| r[4] * 1e-3).collect();
    let end = cut_mm.last().copied().unwrap_or(0.0);
    let band: Vec<(f64, f64, &str)> = averaged
        .map(|a| {
            let what = if a.steady {
                "steady: averaged"
            } else {
                "not steady: last half averaged"
            };
            (a.from_mm, end, what)
        })
        .into_iter()
        .collect();
    save_plot(
        out,
        "forces.svg",
        "Tool forces",
        ("cut length (mm)", "force per unit width (N/mm)"),
        &[
            ("cutting force F'c", "#1f77b4", &cut_mm, &fc),
            ("feed force F'f", "#d62728", &cut_mm, &ff),
        ],
        &band,
    )
}

/// The rake-face profiles in contact, ordered from the edge outwards: stresses, sliding
/// velocity, μ and temperature.
fn write_profile_plots(out: &Path, profile: &[ProfilePoint]) -> Result<Vec<PathBuf>> {
    let mut rake: Vec<(f64, WindowStats, f64)> = profile
        .iter()
        .filter(|p| p.distance_m >= 0.0)
        .filter_map(|p| p.stats.map(|s| (p.distance_m * 1e3, s, p.mu)))
        .collect();
    rake.sort_by(|a, b| a.0.total_cmp(&b.0));
    let d: Vec<f64> = rake.iter().map(|r| r.0).collect();
    let col = |f: &dyn Fn(&WindowStats, f64) -> f64| -> Vec<f64> {
        rake.iter().map(|r| f(&r.1, r.2)).collect()
    };
    let p = col(&|s, _| s.pressure_pa * 1e-6);
    let sn = col(&|s, _| s.normal_stress_pa * 1e-6);
    let tau = col(&|s, _| s.shear_stress_pa * 1e-6);
    let vs = col(&|s, _| s.sliding_velocity_m_s * 60.0);
    let mu = col(&|_, m| m);
    let mu_eff = col(&|s, _| s.mu_effective);
    let temp = col(&|s, _| s.temperature_k - 273.15);
    let x = "distance from the cutting edge along the rake face (mm)";
    Ok(vec![
        save_plot(
            out,
            "profile_stress.svg",
            "Rake face: contact pressure and shear stress",
            (x, "stress (MPa)"),
            &[
                ("pressure in contact", "#1f77b4", &d, &p),
                ("mean normal stress", "#2ca02c", &d, &sn),
                ("shear stress", "#d62728", &d, &tau),
            ],
            &[],
        )?,
        save_plot(
            out,
            "profile_velocity.svg",
            "Rake face: sliding velocity",
            (x, "sliding velocity (m/min)"),
            &[("sliding velocity", "#2ca02c", &d, &vs)],
            &[],
        )?,
        save_plot(
            out,
            "profile_mu.svg",
            "Rake face: friction coefficient",
            (x, "friction coefficient mu (-)"),
            &[
                ("law mu", "#9467bd", &d, &mu),
                ("tau/p", "#ff7f0e", &d, &mu_eff),
            ],
            &[],
        )?,
        save_plot(
            out,
            "profile_temperature.svg",
            "Rake face: contact temperature",
            (x, "temperature (°C)"),
            &[("temperature", "#8c564b", &d, &temp)],
            &[],
        )?,
    ])
}
