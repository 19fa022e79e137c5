//! Outputs: VTK legacy particle files for ParaView, force histories and friction-window CSV.
//! Every file is written atomically (temporary file, then rename).

use crate::chip::ProfilePoint;
use crate::cutting::EdgeLayout;
use crate::executor::{Control, Observer};
use crate::friction_loop::WindowUpdate;
use crate::particles::Particles;
use crate::solver::{SimError, Solver};
use crate::tool::{Tool, WindowStats};
use greybox_core::atomic::write_atomic;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Writes particles as a VTK legacy ASCII poly-data file (points + vertices + point data:
/// velocity m/s, pressure Pa, von Mises Pa, plastic strain, plastic strain rate 1/s,
/// temperature K, density kg/m³ (physical), boundary group).
pub fn write_vtk(
    path: &Path,
    p: &Particles,
    mass_scaling: f64,
    time: f64,
) -> greybox_core::Result<()> {
    write_atomic(path, |w| {
        let n = p.len();
        writeln!(w, "# vtk DataFile Version 3.0")?;
        writeln!(w, "greybox-sim particles t={time:.9e} s")?;
        writeln!(w, "ASCII\nDATASET POLYDATA\nPOINTS {n} double")?;
        for i in 0..n {
            writeln!(w, "{:e} {:e} 0", p.x[i], p.y[i])?;
        }
        writeln!(w, "VERTICES {n} {}", 2 * n)?;
        for i in 0..n {
            writeln!(w, "1 {i}")?;
        }
        writeln!(w, "POINT_DATA {n}\nVECTORS velocity_m_per_s double")?;
        for i in 0..n {
            writeln!(w, "{:e} {:e} 0", p.vx[i], p.vy[i])?;
        }
        let scalar =
            |w: &mut dyn Write, name: &str, f: &dyn Fn(usize) -> f64| -> std::io::Result<()> {
                writeln!(w, "SCALARS {name} double 1\nLOOKUP_TABLE default")?;
                for i in 0..n {
                    writeln!(w, "{:e}", f(i))?;
                }
                Ok(())
            };
        scalar(w, "pressure_Pa", &|i| p.p[i])?;
        scalar(w, "von_mises_Pa", &|i| p.von_mises(i))?;
        scalar(w, "plastic_strain", &|i| p.eps_p[i])?;
        scalar(w, "plastic_strain_rate_per_s", &|i| p.eps_rate[i])?;
        scalar(w, "temperature_K", &|i| p.temp[i])?;
        scalar(w, "density_kg_per_m3", &|i| p.rho[i] / mass_scaling)?;
        scalar(w, "boundary_group", &|i| p.group[i] as f64)?;
        if p.is_refined() {
            scalar(w, "spacing_m", &|i| p.spacing_of(i))?;
        }
        if p.damage.iter().any(|&d| d > 0.0) {
            scalar(w, "damage", &|i| p.damage[i])?;
        }
        Ok(())
    })
}

/// The tool's outline in the global frame, m: `n` points on its rounded polygon, found by
/// closest-point queries from a circle of probe points around the tool's centre.
pub fn tool_outline(tool: &Tool, n: usize) -> Vec<[f64; 2]> {
    let (lo, hi) = tool.shape.bounding_box();
    let c = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
    let r = (hi[0] - lo[0]).hypot(hi[1] - lo[1]).max(tool.shape.radius);
    (0..n)
        .map(|k| {
            let a = 2.0 * std::f64::consts::PI * k as f64 / n as f64;
            let probe = [c[0] + r * a.cos(), c[1] + r * a.sin()];
            let sp = tool.shape.closest(probe);
            [
                probe[0] - sp.distance * sp.normal[0] + tool.position[0],
                probe[1] - sp.distance * sp.normal[1] + tool.position[1],
            ]
        })
        .collect()
}

/// Writes the tool outline (closed poly-line of 720 points) as VTK.
pub fn write_tool_vtk(path: &Path, tool: &Tool) -> greybox_core::Result<()> {
    let per = tool.shape.perimeter();
    let n = 720usize;
    let pts = tool_outline(tool, n);
    write_atomic(path, |w| {
        writeln!(w, "# vtk DataFile Version 3.0")?;
        writeln!(w, "greybox-sim tool {} (perimeter {per:e} m)", tool.name)?;
        writeln!(w, "ASCII\nDATASET POLYDATA\nPOINTS {n} double")?;
        for p in &pts {
            writeln!(w, "{:e} {:e} 0", p[0], p[1])?;
        }
        writeln!(w, "LINES 1 {}", n + 2)?;
        write!(w, "{}", n + 1)?;
        for k in 0..n {
            write!(w, " {k}")?;
        }
        writeln!(w, " 0")?;
        Ok(())
    })
}

/// Records the force on tool `tool` averaged over every `every` steps.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct ForceHistory {
    pub tool: usize,
    pub every: u64,
    /// (time s, tool x m, tool y m, F_x N/m, F_y N/m, contacts).
    pub rows: Vec<[f64; 6]>,
    sum: [f64; 3],
    count: u64,
}

impl ForceHistory {
    pub fn new(tool: usize, every: u64) -> Self {
        ForceHistory {
            tool,
            every: every.max(1),
            rows: Vec::new(),
            sum: [0.0; 3],
            count: 0,
        }
    }

    /// Writes `time_s,tool_x_mm,tool_y_mm,force_x_N_per_mm,force_y_N_per_mm,contacts`.
    pub fn write_csv(&self, path: &Path) -> greybox_core::Result<()> {
        write_atomic(path, |w| {
            writeln!(
                w,
                "time_s,tool_x_mm,tool_y_mm,force_x_N_per_mm,force_y_N_per_mm,contact_particles"
            )?;
            for r in &self.rows {
                writeln!(
                    w,
                    "{:.6e},{:.6},{:.6},{:.6},{:.6},{:.1}",
                    r[0],
                    r[1] * 1e3,
                    r[2] * 1e3,
                    r[3] * 1e-3,
                    r[4] * 1e-3,
                    r[5]
                )?;
            }
            Ok(())
        })
    }

    /// Mean force (N/m) over rows with time in [t0, t1].
    pub fn mean_force(&self, t0: f64, t1: f64) -> Option<[f64; 2]> {
        Some([self.mean_column(3, t0, t1)?, self.mean_column(4, t0, t1)?])
    }

    /// Mean number of particles in contact over rows with time in [t0, t1].
    pub fn mean_contacts(&self, t0: f64, t1: f64) -> Option<f64> {
        self.mean_column(5, t0, t1)
    }

    /// Mean of row column `k` over rows with time in [t0, t1] (`None`: no such row).
    fn mean_column(&self, k: usize, t0: f64, t1: f64) -> Option<f64> {
        let sel: Vec<f64> = self
            .rows
            .iter()
            .filter(|r| r[0] >= t0 && r[0] <= t1)
            .map(|r| r[k])
            .collect();
        (!sel.is_empty()).then(|| sel.iter().sum::<f64>() / sel.len() as f64)
    }
}

impl Observer for ForceHistory {
    fn save_state(&self) -> Option<(&'static str, serde_json::Value)> {
        crate::executor::SavedState::saved(self)
    }
    fn after_step(&mut self, sim: &Solver) -> Result<Control, SimError> {
        let t = &sim.tools[self.tool];
        self.sum[0] += t.force[0];
        self.sum[1] += t.force[1];
        self.sum[2] += t.contacts as f64;
        self.count += 1;
        if self.count == self.every {
            let n = self.count as f64;
            self.rows.push([
                sim.time,
                t.position[0],
                t.position[1],
                self.sum[0] / n,
                self.sum[1] / n,
                self.sum[2] / n,
            ]);
            self.sum = [0.0; 3];
            self.count = 0;
        }
        Ok(Control::Continue)
    }
}

/// The hottest particle over a run, K: sampled at the start, every `every` steps and at the
/// end (the end-of-run maximum alone misses a peak that conduction has since spread out).
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct PeakTemperature {
    pub every: u64,
    count: u64,
    /// Highest particle temperature seen, K (−∞ before the first sample).
    pub peak_k: f64,
}

impl PeakTemperature {
    pub fn new(every: u64) -> Self {
        PeakTemperature {
            every: every.max(1),
            count: 0,
            peak_k: f64::NEG_INFINITY,
        }
    }

    fn sample(&mut self, sim: &Solver) {
        let hottest = sim.particles.temp.iter().copied().fold(f64::MIN, f64::max);
        self.peak_k = self.peak_k.max(hottest);
    }
}

impl Observer for PeakTemperature {
    fn save_state(&self) -> Option<(&'static str, serde_json::Value)> {
        crate::executor::SavedState::saved(self)
    }
    fn start(&mut self, sim: &Solver) -> Result<(), SimError> {
        self.sample(sim);
        Ok(())
    }
    fn after_step(&mut self, sim: &Solver) -> Result<Control, SimError> {
        self.count += 1;
        if self.count == self.every {
            self.count = 0;
            self.sample(sim);
        }
        Ok(Control::Continue)
    }
    fn finish(&mut self, sim: &Solver) -> Result<(), SimError> {
        self.sample(sim);
        Ok(())
    }
}

/// Writes a VTK file of the particles every `every` steps (and of the tools once).
pub struct VtkSeries {
    pub dir: PathBuf,
    pub every: u64,
    pub written: Vec<PathBuf>,
}

impl VtkSeries {
    pub fn new(dir: &Path, every: u64) -> Self {
        VtkSeries {
            dir: dir.to_path_buf(),
            every: every.max(1),
            written: Vec::new(),
        }
    }
    fn write(&mut self, sim: &Solver) -> Result<(), SimError> {
        let path = self.dir.join(format!("particles_{:08}.vtk", sim.step));
        write_vtk(&path, &sim.particles, sim.numerics.mass_scaling, sim.time)?;
        for (k, t) in sim.tools.iter().enumerate() {
            write_tool_vtk(&self.dir.join(format!("tool{k}_{:08}.vtk", sim.step)), t)?;
        }
        self.written.push(path);
        Ok(())
    }
}

impl Observer for VtkSeries {
    fn start(&mut self, sim: &Solver) -> Result<(), SimError> {
        self.write(sim)
    }
    fn after_step(&mut self, sim: &Solver) -> Result<Control, SimError> {
        if sim.step.is_multiple_of(self.every) {
            self.write(sim)?;
        }
        Ok(Control::Continue)
    }
    fn finish(&mut self, sim: &Solver) -> Result<(), SimError> {
        if !sim.step.is_multiple_of(self.every) {
            self.write(sim)?;
        }
        Ok(())
    }
    fn on_failure(&mut self, sim: &Solver, last_good: &Particles, step: u64, time: f64) {
        let path = self.dir.join(format!("last_good_{step:08}.vtk"));
        if write_vtk(&path, last_good, sim.numerics.mass_scaling, time).is_ok() {
            self.written.push(path);
        }
    }
}

/// The temperature field of a thermal tool in the workpiece frame:
/// `x_mm,y_mm,temperature_C,held` (one row per grid cell inside the tool; `held` = 1 for the
/// cells kept at the ambient temperature). Nothing is written for an adiabatic tool.
pub fn write_tool_temperature_csv(path: &Path, tool: &Tool) -> greybox_core::Result<bool> {
    let Some(tt) = &tool.thermal else {
        return Ok(false);
    };
    write_atomic(path, |w| {
        writeln!(w, "x_mm,y_mm,temperature_C,held")?;
        for (c, t, held) in tt.cells_with_kind() {
            writeln!(
                w,
                "{:.5},{:.5},{:.2},{}",
                (c[0] + tool.position[0]) * 1e3,
                (c[1] + tool.position[1]) * 1e3,
                t - 273.15,
                u8::from(held)
            )?;
        }
        Ok(())
    })?;
    Ok(true)
}

/// Per-window statistics of a tool as CSV: s range (mm), μ in use, law and the time-averaged
/// state (`pressure_MPa`, `sliding_velocity_m_per_min`, `temperature_C`, `shear_stress_MPa`,
/// `mu_effective`, `contact_fraction`, `slip_fraction`, `tool_temperature_C` (thermal tools);
/// empty where never in contact).
pub fn write_windows_csv(path: &Path, tool: &Tool, spacing: f64) -> greybox_core::Result<()> {
    write_atomic(path, |w| {
        writeln!(w, "window,s_start_mm,s_end_mm,law,mu,{STATS_HEADER}")?;
        for (k, win) in tool.windows.iter().enumerate() {
            write!(
                w,
                "{k},{:.6},{:.6},{},{:.6}",
                win.s_start * 1e3,
                win.s_end * 1e3,
                greybox_core::escape::csv_quoted(&win.law.name()),
                win.mu
            )?;
            write_stats(w, win.acc.stats(spacing, win.length()).as_ref())?;
        }
        Ok(())
    })
}

/// The columns after `STATS_HEADER`: the state in CSV units, empty fields without contact.
const STATS_HEADER: &str = "pressure_MPa,normal_stress_MPa,sliding_velocity_m_per_min,temperature_C,shear_stress_MPa,mu_effective,contact_fraction,slip_fraction,tool_temperature_C";

fn write_stats(w: &mut dyn Write, stats: Option<&WindowStats>) -> std::io::Result<()> {
    match stats {
        Some(s) => {
            write!(
                w,
                ",{:.3},{:.3},{:.3},{:.2},{:.3},{:.5},{:.4},{:.4},",
                s.pressure_pa * 1e-6,
                s.normal_stress_pa * 1e-6,
                s.sliding_velocity_m_s * 60.0,
                s.temperature_k - 273.15,
                s.shear_stress_pa * 1e-6,
                s.mu_effective,
                s.contact_fraction,
                s.slip_fraction
            )?;
            match s.tool_temperature_k {
                Some(t) => writeln!(w, "{:.2}", t - 273.15),
                None => writeln!(w),
            }
        }
        None => writeln!(w, ",,,,,,,,,"),
    }
}

/// Contact profile along the tool (rake face from its top down to the edge, then the
/// flank): `window,face,distance_from_edge_um,mu,` then the time-averaged state.
pub fn write_profile_csv(path: &Path, profile: &[ProfilePoint]) -> greybox_core::Result<()> {
    write_atomic(path, |w| {
        writeln!(w, "window,face,distance_from_edge_um,mu,{STATS_HEADER}")?;
        for p in profile {
            write!(
                w,
                "{},{},{:.3},{:.6}",
                p.window,
                p.face.name(),
                p.distance_m * 1e6,
                p.mu
            )?;
            write_stats(w, p.stats.as_ref())?;
        }
        Ok(())
    })
}

/// The μ history of the grey-box loop: one row per window update (`step,time_s,window,face,
/// distance_from_edge_um,mu,` the state the law saw — `law_pressure_MPa,
/// law_sliding_velocity_m_per_min,law_temperature_C`, the interval state smoothed as the
/// set-up asks — then the state averaged over the interval that ended there).
pub fn write_mu_history_csv(
    path: &Path,
    history: &[WindowUpdate],
    tool: &Tool,
    layout: &EdgeLayout,
) -> greybox_core::Result<()> {
    write_atomic(path, |w| {
        writeln!(
            w,
            "step,time_s,window,face,distance_from_edge_um,mu,law_pressure_MPa,law_sliding_velocity_m_per_min,law_temperature_C,{STATS_HEADER}"
        )?;
        for u in history {
            let win = &tool.windows[u.window];
            let (face, d) = layout.locate(0.5 * (win.s_start + win.s_end));
            write!(
                w,
                "{},{:.6e},{},{},{:.3},{:.6}",
                u.step,
                u.time_s,
                u.window,
                face.name(),
                d * 1e6,
                u.mu
            )?;
            let law = u.law_state.unwrap_or(greybox_core::ContactState {
                pressure_pa: u.stats.pressure_pa,
                sliding_velocity_m_s: u.stats.sliding_velocity_m_s,
                temperature_k: u.stats.temperature_k,
            });
            write!(
                w,
                ",{:.3},{:.3},{:.2}",
                law.pressure_pa * 1e-6,
                law.sliding_velocity_m_s * 60.0,
                law.temperature_k - 273.15
            )?;
            write_stats(w, Some(&u.stats))?;
        }
        Ok(())
    })
}

impl crate::executor::SavedState for ForceHistory {
    const KEY: &'static str = "forces";
}

impl crate::executor::SavedState for PeakTemperature {
    const KEY: &'static str = "peak_temperature";
}
