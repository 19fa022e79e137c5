//! Heat conduction in a rigid tool and thermal contact with the workpiece.
//!
//! The tool's temperature lives on a Cartesian finite-volume grid in the tool's own frame
//! (cells whose centre lies inside the tool's shape; the surface is a staircase at the grid
//! spacing). Per cell, with conductivity λ(T) at the faces (harmonic mean of the two cells):
//!
//!   ρ c Δx² dT/dt = Σ_faces λ_f (T_nb − T) + Q,
//!
//! Q the heat per time and metre of thickness the contact puts in (W/m). Faces towards
//! cells outside the tool are adiabatic (the free rake and flank faces lose no heat); cells
//! next to the tool's far boundaries (the surface from arc length `ambient_from_s` on: the
//! back and top of a modelled insert) are held at the ambient temperature, standing for the
//! rest of the insert and its holder.
//!
//! Contact: a workpiece particle in contact exchanges q = h_eff (T_p − T_tool) per area of
//! its contact length Δx with the cell under its contact point, where the coating is a thin
//! thermal resistance in series with the interface conductance,
//! 1/h_eff = 1/h_c + t_coat/λ_coat(T_tool) (a layer of a few µm stores little heat next to
//! the substrate; its resistance is what matters). The share of the friction heat that the
//! set-up gives the tool goes into the same cell.
//!
//! Time stepping: explicit (forward Euler) over a sub-cycle of N solver steps, N the largest
//! that keeps the explicit scheme stable (or, where even one solver step is too long for it,
//! that step split into as many equal explicit steps as stability asks) (Δt_tool ≤ 0.9 ρ c Δx² / (4 λ_max + n h_eff Δx),
//! n = 4 contact particles per cell at most; ρc divided by `thermal_mass_scaling`, see
//! [`ToolThermalSetup::heat_capacity`]). The contact sees the tool temperature of the last
//! update.

use crate::geometry::RoundedPolygon;
use greybox_material::Table1d;
use serde::{Deserialize, Serialize};

/// The tool's thermal data (SI), as a set-up gives it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ToolThermalSetup {
    /// Substrate conductivity λ(T), W/(m·K).
    pub conductivity: Table1d,
    /// Substrate density, kg/m³.
    pub density_kg_m3: f64,
    /// Substrate specific heat c(T), J/(kg·K).
    pub specific_heat: Table1d,
    /// Coating thickness, m (0: uncoated).
    #[serde(default)]
    pub coating_thickness_m: f64,
    /// Coating conductivity λ(T), W/(m·K).
    #[serde(default = "default_coating")]
    pub coating_conductivity: Table1d,
    /// Thermal contact conductance of the tool–chip interface h_c, W/(m²·K).
    pub contact_conductance_w_m2k: f64,
    /// Grid spacing of the tool's temperature field, m (0: the particle spacing).
    #[serde(default)]
    pub grid_spacing_m: f64,
    /// Temperature of the tool's far boundaries, K (`None`: the workpiece's initial temperature).
    #[serde(default)]
    pub ambient_temperature_k: Option<f64>,
    /// The tool's heat capacity ρ c divided by this factor (≥ 1; 1: as given). See
    /// [`ToolThermalSetup::heat_capacity`].
    #[serde(default = "unscaled")]
    pub thermal_mass_scaling: f64,
}

fn unscaled() -> f64 {
    1.0
}

fn default_coating() -> Table1d {
    Table1d::constant(1.0)
}

impl ToolThermalSetup {
    /// A WC–Co carbide substrate with the article's AlTiN coating (its Table 6: λ = 4.64 +
    /// 0.00054 T W/(m·K), 3 µm; T taken in °C, the unit of the article's DEFORM input).
    /// Substrate: typical WC–6 % Co values (λ 80 W/(m·K) at 20 °C falling to 60 at 800 °C,
    /// ρ 14 900 kg/m³, c 200 J/(kg·K) at 20 °C rising to 280 at 800 °C): replace them with
    /// the grade's datasheet. Interface conductance 10⁷ W/(m²·K): the order cutting models
    /// use for a pressed, sliding tool–chip contact.
    pub fn carbide_altin() -> Self {
        let t: Vec<f64> = (0..=8).map(|k| 293.15 + 100.0 * k as f64).collect();
        let c = |x: &f64| x - 273.15;
        ToolThermalSetup {
            conductivity: Table1d {
                x: t.clone(),
                y: t.iter()
                    .map(|x| 80.0 - 0.025 * c(x).clamp(0.0, 800.0))
                    .collect(),
            },
            density_kg_m3: 14_900.0,
            specific_heat: Table1d {
                x: t.clone(),
                y: t.iter()
                    .map(|x| 200.0 + 0.1 * c(x).clamp(0.0, 800.0))
                    .collect(),
            },
            coating_thickness_m: 3e-6,
            coating_conductivity: Table1d {
                x: t.clone(),
                y: t.iter().map(|x| 4.64 + 0.00054 * c(x)).collect(),
            },
            contact_conductance_w_m2k: 1e7,
            grid_spacing_m: 0.0,
            ambient_temperature_k: None,
            thermal_mass_scaling: 1.0,
        }
    }

    /// The tool's heat capacity per volume at `t_k`, J/(m³·K): ρ c(T) / `thermal_mass_scaling`.
    ///
    /// Why a tool's thermal mass may be scaled: a simulated cut of a few millimetres lasts a
    /// fraction of a millisecond, while the tool near the contact settles in about l²/α
    /// (l = 0.1 mm, α = λ/(ρc) ≈ 3·10⁻⁵ m²/s for WC–Co: 0.4 ms) and the insert in tens of
    /// milliseconds, so the tool is still warming when the cut ends and the forces drift with
    /// it. A measured cut is averaged over seconds, with the tool at its steady field. That
    /// field solves ∇·(λ ∇T) + Q = 0 and does not depend on ρc, so dividing ρc by a factor
    /// s reaches the same steady field s times sooner (the idea of the separate steady-state
    /// heat-transfer analysis of the tool in FE cutting studies, e.g. Yen, Söhner, Lilly &
    /// Altan, J. Mater. Process. Technol. 146 (2004) 82–91). What is lost is the tool's own
    /// transient, the first fraction of a second of a real cut. The explicit sub-cycle
    /// shortens by the same factor (see the module docs).
    pub fn heat_capacity(&self, t_k: f64) -> f64 {
        self.density_kg_m3 * self.specific_heat.eval(t_k) / self.thermal_mass_scaling
    }

    pub fn validate(&self) -> greybox_core::Result<()> {
        greybox_core::rules::Rules::new("tool thermal")
            .positive("density_kg_m3", self.density_kg_m3)
            .relation(
                self.thermal_mass_scaling >= 1.0 && self.thermal_mass_scaling.is_finite(),
                "thermal_mass_scaling must be a finite factor of at least 1 (the tool's ρc is divided by it)",
            )
            .non_negative("coating_thickness_m", self.coating_thickness_m)
            .non_negative("contact_conductance_w_m2k", self.contact_conductance_w_m2k)
            .non_negative("grid_spacing_m", self.grid_spacing_m)
            .relation(
                self.ambient_temperature_k
                    .is_none_or(|t| t > 0.0 && t.is_finite()),
                "ambient_temperature_k must be a temperature above 0 K",
            )
            .finish()?;
        for (name, t, strict) in [
            ("conductivity", &self.conductivity, true),
            ("specific_heat", &self.specific_heat, true),
            ("coating_conductivity", &self.coating_conductivity, true),
        ] {
            t.validate()?;
            if t.y.iter().any(|&v| if strict { v <= 0.0 } else { v < 0.0 }) {
                return Err(greybox_core::Error::invalid(
                    "tool thermal",
                    format!("{name} must be > 0 everywhere"),
                ));
            }
        }
        Ok(())
    }
}

fn one_split() -> u64 {
    1
}

/// What a cell is.
const OUTSIDE: u8 = 0;
const INTERIOR: u8 = 1;
const AMBIENT: u8 = 2;

/// The tool's temperature field and its contact book-keeping.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ToolThermal {
    pub setup: ToolThermalSetup,
    /// Factor on every conductivity and on the contact conductance (a time-scaled run's
    /// speed-up keeps the thermal Péclet number physical).
    pub conductivity_scale: f64,
    /// Lower-left corner of the grid in the tool frame, m.
    pub origin: [f64; 2],
    pub dx: f64,
    pub nx: usize,
    pub ny: usize,
    /// Per cell: OUTSIDE, INTERIOR or AMBIENT.
    pub kind: Vec<u8>,
    /// Per cell: the nearest cell inside the tool (itself when inside).
    pub nearest_inside: Vec<u32>,
    /// Temperatures, K (outside cells unused).
    pub temp: Vec<f64>,
    pub ambient_k: f64,
    /// Heat put in per cell since the last update, J/m.
    pub heat_in: Vec<f64>,
    /// Solver steps per tool update, and steps since the last one.
    pub substeps: u64,
    pub pending_steps: u64,
    /// Explicit steps per tool update (more than one where the tool's stable step is shorter
    /// than the solver's).
    #[serde(default = "one_split")]
    pub splits: u64,
    /// Heat that left the tool through its ambient cells, J/m (cumulative).
    pub heat_to_ambient: f64,
}

impl ToolThermal {
    /// The grid of a tool of `shape` at spacing `dx`: cells along x and y (the bounding box
    /// with one cell of margin).
    fn grid_size(shape: &RoundedPolygon, dx: f64) -> (f64, f64) {
        let (lo, hi) = shape.bounding_box();
        (
            ((hi[0] - lo[0]) / dx).ceil() + 1.0,
            ((hi[1] - lo[1]) / dx).ceil() + 1.0,
        )
    }

    /// Refuses a tool grid of more than `max` cells (`numerics.max_particles`, the same
    /// budget as the workpiece's particles; `None`: its default) before anything is
    /// allocated: a face length given in mm where m was meant would otherwise ask for
    /// gigabytes.
    pub fn check_grid_budget(
        shape: &RoundedPolygon,
        dx: f64,
        max: Option<u64>,
    ) -> greybox_core::Result<()> {
        let (nx, ny) = Self::grid_size(shape, dx);
        let max = max.unwrap_or(crate::particles::DEFAULT_MAX_PARTICLES);
        if nx * ny <= max as f64 {
            return Ok(());
        }
        let found = format!(
            "the thermal tool's grid at {dx:e} m covers the modelled insert ({:.3} mm × {:.3} mm) with {:.3e} cells",
            (nx - 1.0) * dx * 1e3,
            (ny - 1.0) * dx * 1e3,
            nx * ny
        );
        let refusal = greybox_core::budget::over_cap(
            &found,
            "numerics.max_particles",
            &max.to_string(),
            "numerics.max_particles in the set-up",
        );
        Err(greybox_core::Error::invalid(
            "cutting set-up",
            format!("{refusal}; otherwise shorten [insert] rake_length_m / flank_length_m or coarsen [tool_thermal] grid_spacing_m"),
        ))
    }

    /// The grid for `shape` at spacing `dx` (m), all at `t0` (K); the outermost cells along
    /// the surface from arc length `ambient_from_s` on are held at the ambient temperature.
    pub fn new(
        setup: ToolThermalSetup,
        shape: &RoundedPolygon,
        dx: f64,
        t0: f64,
        ambient_from_s: f64,
        conductivity_scale: f64,
    ) -> Self {
        let (lo, _) = shape.bounding_box();
        let (nx, ny) = Self::grid_size(shape, dx);
        let (nx, ny) = (nx as usize, ny as usize);
        let origin = [lo[0] - 0.5 * dx, lo[1] - 0.5 * dx];
        let centre = |i: usize, j: usize| {
            [
                origin[0] + (i as f64 + 0.5) * dx,
                origin[1] + (j as f64 + 0.5) * dx,
            ]
        };
        let mut kind = vec![OUTSIDE; nx * ny];
        for j in 0..ny {
            for i in 0..nx {
                if shape.closest(centre(i, j)).distance < 0.0 {
                    kind[j * nx + i] = INTERIOR;
                }
            }
        }
        // Held cells: inside cells with a neighbour outside, where the surface nearest to
        // them lies from `ambient_from_s` on.
        let outside = |i: isize, j: isize| {
            i < 0
                || j < 0
                || i >= nx as isize
                || j >= ny as isize
                || kind[j as usize * nx + i as usize] == OUTSIDE
        };
        let mut held = Vec::new();
        for j in 0..ny {
            for i in 0..nx {
                let (ii, jj) = (i as isize, j as isize);
                let boundary = kind[j * nx + i] != OUTSIDE
                    && (outside(ii - 1, jj)
                        || outside(ii + 1, jj)
                        || outside(ii, jj - 1)
                        || outside(ii, jj + 1));
                if boundary && shape.closest(centre(i, j)).s >= ambient_from_s {
                    held.push(j * nx + i);
                }
            }
        }
        for c in held {
            kind[c] = AMBIENT;
        }
        let nearest_inside = nearest_inside_cells(&kind, nx, ny);
        let ambient_k = setup.ambient_temperature_k.unwrap_or(t0);
        let n = nx * ny;
        let mut t = ToolThermal {
            setup,
            conductivity_scale,
            origin,
            dx,
            nx,
            ny,
            temp: kind
                .iter()
                .map(|&k| if k == AMBIENT { ambient_k } else { t0 })
                .collect(),
            kind,
            nearest_inside,
            ambient_k,
            heat_in: vec![0.0; n],
            substeps: 1,
            pending_steps: 0,
            splits: 1,
            heat_to_ambient: 0.0,
        };
        t.substeps = 1;
        t
    }

    /// Sets the sub-cycle for solver steps of `dt_solver` seconds (see the module docs).
    pub fn set_solver_step(&mut self, dt_solver: f64, contact_length: f64) {
        let s = &self.setup;
        let k_max = s.conductivity.y.iter().copied().fold(0.0, f64::max) * self.conductivity_scale;
        let rho_c_min = s.density_kg_m3
            * s.specific_heat
                .y
                .iter()
                .copied()
                .fold(f64::INFINITY, f64::min)
            / s.thermal_mass_scaling;
        let h = s.contact_conductance_w_m2k * self.conductivity_scale;
        let stable = 0.9 * rho_c_min * self.dx * self.dx / (4.0 * k_max + 4.0 * h * contact_length);
        if stable >= dt_solver {
            self.substeps = (stable / dt_solver).floor() as u64;
            self.splits = 1;
        } else {
            self.substeps = 1;
            self.splits = (dt_solver / stable).ceil() as u64;
        }
    }

    /// The cell whose temperature the contact at tool-frame point `p` sees.
    #[inline]
    pub fn cell_at(&self, p: [f64; 2]) -> usize {
        let i = (((p[0] - self.origin[0]) / self.dx).floor().max(0.0) as usize).min(self.nx - 1);
        let j = (((p[1] - self.origin[1]) / self.dx).floor().max(0.0) as usize).min(self.ny - 1);
        self.nearest_inside[j * self.nx + i] as usize
    }

    /// Effective conductance of coating and interface in series at tool temperature `t`,
    /// W/(m²·K) (time-scaled).
    #[inline]
    pub fn conductance(&self, t: f64) -> f64 {
        let s = &self.setup;
        let h = s.contact_conductance_w_m2k;
        if h <= 0.0 {
            return 0.0;
        }
        let r = 1.0 / h + s.coating_thickness_m / s.coating_conductivity.eval(t);
        self.conductivity_scale / r
    }

    /// Books one solver step; every `substeps` steps advances the field by their total time.
    pub fn after_step(&mut self, dt_solver: f64) {
        self.pending_steps += 1;
        if self.pending_steps >= self.substeps {
            let dt = self.pending_steps as f64 * dt_solver;
            self.pending_steps = 0;
            self.conduct(dt);
        }
    }

    /// Advances the field by `dt` seconds with the heat booked since the last update: one
    /// explicit step, or `splits` equal ones each taking its share of the booked heat.
    pub fn conduct(&mut self, dt: f64) {
        // n = 1: dt/1 and a share of 1 are exact, the single step of before
        let n = self.splits.max(1);
        for _ in 0..n {
            self.explicit_step(dt / n as f64, 1.0 / n as f64);
        }
        self.heat_in.iter_mut().for_each(|q| *q = 0.0);
    }

    /// One explicit conduction step of `dt` seconds taking `share` of the booked heat.
    fn explicit_step(&mut self, dt: f64, share: f64) {
        let (nx, ny, dx) = (self.nx, self.ny, self.dx);
        let s = &self.setup;
        let k: Vec<f64> = self
            .temp
            .iter()
            .zip(&self.kind)
            .map(|(&t, &c)| {
                if c == OUTSIDE {
                    0.0
                } else {
                    s.conductivity.eval(t) * self.conductivity_scale
                }
            })
            .collect();
        let mut new = self.temp.clone();
        let mut to_ambient = 0.0;
        for j in 0..ny {
            for i in 0..nx {
                let c = j * nx + i;
                if self.kind[c] == OUTSIDE {
                    continue;
                }
                let mut flow = 0.0;
                let mut add = |n: usize| {
                    if self.kind[n] != OUTSIDE {
                        let kf = 2.0 * k[c] * k[n] / (k[c] + k[n]);
                        flow += kf * (self.temp[n] - self.temp[c]);
                    }
                };
                for_each_neighbour(i, j, nx, ny, &mut add);
                let q = flow * dt + self.heat_in[c] * share;
                if self.kind[c] == AMBIENT {
                    // Held: what flows in leaves to the ambient.
                    to_ambient += q;
                } else {
                    new[c] += q / (s.heat_capacity(self.temp[c]) * dx * dx);
                }
            }
        }
        self.temp = new;
        self.heat_to_ambient += to_ambient;
    }

    /// Heat stored in the tool above `reference_k`, J/m (∫ρ c dT per cell, c(T) integrated
    /// by the trapezoidal rule over 1 K steps when it varies).
    pub fn stored_heat(&self, reference_k: f64) -> f64 {
        let s = &self.setup;
        let area = self.dx * self.dx;
        let mut e = 0.0;
        for (&t, &k) in self.temp.iter().zip(&self.kind) {
            if k != INTERIOR {
                continue;
            }
            e += s.density_kg_m3 / s.thermal_mass_scaling
                * area
                * integrate(&s.specific_heat, reference_k, t);
        }
        e
    }

    /// Cells inside the tool (interior and held), as (tool-frame centre, temperature K,
    /// held at ambient).
    pub fn cells_with_kind(&self) -> impl Iterator<Item = ([f64; 2], f64, bool)> + '_ {
        (0..self.nx * self.ny)
            .filter(|&c| self.kind[c] != OUTSIDE)
            .map(|c| {
                let (i, j) = (c % self.nx, c / self.nx);
                (
                    [
                        self.origin[0] + (i as f64 + 0.5) * self.dx,
                        self.origin[1] + (j as f64 + 0.5) * self.dx,
                    ],
                    self.temp[c],
                    self.kind[c] == AMBIENT,
                )
            })
    }

    /// Cells inside the tool, as (tool-frame centre, temperature K).
    pub fn cells(&self) -> impl Iterator<Item = ([f64; 2], f64)> + '_ {
        self.cells_with_kind().map(|(c, t, _)| (c, t))
    }

    /// The hottest tool temperature, K.
    pub fn max_temperature(&self) -> f64 {
        self.cells()
            .map(|(_, t)| t)
            .fold(f64::NEG_INFINITY, f64::max)
    }
}

/// ∫ c(T) dT from a to b for a piecewise-linear c (exact for its linear pieces up to the
/// 1 K sub-steps).
pub fn integrate(c: &Table1d, a: f64, b: f64) -> f64 {
    if c.x.len() == 1 {
        return c.y[0] * (b - a);
    }
    let n = ((b - a).abs().ceil() as usize).max(1);
    let h = (b - a) / n as f64;
    (0..n)
        .map(|k| {
            let t0 = a + k as f64 * h;
            0.5 * (c.eval(t0) + c.eval(t0 + h)) * h
        })
        .sum()
}

/// For every cell, the nearest inside cell (grid distance, breadth-first from all inside
/// cells at once).
fn nearest_inside_cells(kind: &[u8], nx: usize, ny: usize) -> Vec<u32> {
    let mut near = vec![u32::MAX; nx * ny];
    let mut queue = std::collections::VecDeque::new();
    for (c, &k) in kind.iter().enumerate() {
        if k != OUTSIDE {
            near[c] = c as u32;
            queue.push_back(c);
        }
    }
    while let Some(c) = queue.pop_front() {
        let (i, j) = (c % nx, c / nx);
        let mut visit = |n: usize| {
            if near[n] == u32::MAX {
                near[n] = near[c];
                queue.push_back(n);
            }
        };
        for_each_neighbour(i, j, nx, ny, &mut visit);
    }
    near
}

/// Calls `f` with the index of each of the (up to four) face neighbours of cell (i, j) on a
/// row-major nx × ny grid.
#[inline]
fn for_each_neighbour(i: usize, j: usize, nx: usize, ny: usize, f: &mut impl FnMut(usize)) {
    let c = j * nx + i;
    if i > 0 {
        f(c - 1);
    }
    if i + 1 < nx {
        f(c + 1);
    }
    if j > 0 {
        f(c - nx);
    }
    if j + 1 < ny {
        f(c + nx);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn constant_setup(k: f64, rho: f64, c: f64) -> ToolThermalSetup {
        ToolThermalSetup {
            conductivity: Table1d::constant(k),
            density_kg_m3: rho,
            specific_heat: Table1d::constant(c),
            coating_thickness_m: 0.0,
            coating_conductivity: Table1d::constant(1.0),
            contact_conductance_w_m2k: 0.0,
            grid_spacing_m: 0.0,
            ambient_temperature_k: Some(300.0),
            thermal_mass_scaling: 1.0,
        }
    }

    /// A square held at ambient all round, started from T₀ + A sin(πx/L) sin(πy/L): the
    /// amplitude decays as exp(−2π² α t/L²) (separation of variables, e.g. Carslaw & Jaeger,
    /// *Conduction of Heat in Solids*, §6.3), α = λ/(ρc), L the distance between the held rows.
    #[test]
    fn square_mode_decays_at_the_analytic_rate() {
        let (w, dx) = (0.4e-3, 10e-6);
        let shape = RoundedPolygon::new(vec![[0.0, 0.0], [w, 0.0], [w, w], [0.0, w]], 0.0).unwrap();
        let (k, rho, c) = (80.0, 14_900.0, 200.0);
        let mut t = ToolThermal::new(constant_setup(k, rho, c), &shape, dx, 300.0, 0.0, 1.0);
        let centres: Vec<([f64; 2], u8)> = (0..t.nx * t.ny)
            .map(|i| {
                let (ix, iy) = (i % t.nx, i / t.nx);
                (
                    [
                        t.origin[0] + (ix as f64 + 0.5) * dx,
                        t.origin[1] + (iy as f64 + 0.5) * dx,
                    ],
                    t.kind[i],
                )
            })
            .collect();
        let held: Vec<f64> = centres
            .iter()
            .filter(|c| c.1 == AMBIENT)
            .map(|c| c.0[0])
            .collect();
        let (x0, x1) = held
            .iter()
            .fold((f64::MAX, f64::MIN), |(a, b), &x| (a.min(x), b.max(x)));
        let l = x1 - x0;
        assert!(l > 0.8 * w, "held cells span {l}");
        let amp = 100.0;
        let mode = |p: [f64; 2]| {
            (std::f64::consts::PI * (p[0] - x0) / l).sin()
                * (std::f64::consts::PI * (p[1] - x0) / l).sin()
        };
        for (i, (p, kind)) in centres.iter().enumerate() {
            if *kind == INTERIOR {
                t.temp[i] = 300.0 + amp * mode(*p);
            }
        }
        let alpha = k / (rho * c);
        let t_end = l * l / (2.0 * std::f64::consts::PI.powi(2) * alpha); // one e-folding
        let dt = 0.2 * dx * dx / alpha;
        let n = (t_end / dt).ceil() as usize;
        for _ in 0..n {
            t.conduct(t_end / n as f64);
        }
        // Projection of the field on the mode gives its amplitude.
        let (mut num, mut den) = (0.0, 0.0);
        for (i, (p, kind)) in centres.iter().enumerate() {
            if *kind == INTERIOR {
                num += (t.temp[i] - 300.0) * mode(*p);
                den += mode(*p) * mode(*p);
            }
        }
        let got = num / den / amp;
        let want = (-1.0f64).exp();
        assert!(
            (got / want - 1.0).abs() < 0.01,
            "amplitude ratio {got} vs e⁻¹ = {want}"
        );
        assert!(t.heat_to_ambient > 0.0);
    }

    /// A square tool with half its surface held at ambient and its centre cell, its ρc
    /// divided by `scaling`.
    fn square_tool(scaling: f64) -> (ToolThermal, usize) {
        let (w, dx) = (0.2e-3, 10e-6);
        let shape =
            RoundedPolygon::new(vec![[0.0, 0.0], [w, 0.0], [w, w], [0.0, w]], 5e-6).unwrap();
        let setup = ToolThermalSetup {
            thermal_mass_scaling: scaling,
            ..constant_setup(60.0, 14_900.0, 250.0)
        };
        let t = ToolThermal::new(setup, &shape, dx, 300.0, 0.5 * shape.perimeter(), 1.0);
        let cell = t.cell_at([0.1e-3, 0.1e-3]);
        assert_eq!(t.kind[cell], INTERIOR);
        (t, cell)
    }

    /// The square tool with `power` W/m put into its centre cell, run for `time` s in steps
    /// of `dt`.
    fn heated_square(scaling: f64, power: f64, time: f64, dt: f64) -> ToolThermal {
        let (mut t, cell) = square_tool(scaling);
        for _ in 0..(time / dt).round() as usize {
            t.heat_in[cell] += power * dt;
            t.conduct(dt);
        }
        t
    }

    /// A solver step longer than the tool's stable step (a scaled thermal mass on a
    /// time-scaled cut) is split into equal explicit steps, each with its share of the
    /// booked heat: the same field as booking and conducting in the short steps, where one
    /// long step would diverge.
    #[test]
    fn an_update_longer_than_the_tools_stable_step_is_split() {
        let (power, dt_solver, steps) = (5e3, 1e-8, 400);
        let (mut split, cell) = square_tool(1000.0);
        let (mut fine, mut long) = (split.clone(), split.clone());
        split.set_solver_step(dt_solver, 0.0);
        let n = split.splits;
        assert!(split.substeps == 1 && n > 1, "splits {n}");
        for _ in 0..steps {
            split.heat_in[cell] += power * dt_solver;
            split.after_step(dt_solver);
            for _ in 0..n {
                fine.heat_in[cell] += power * dt_solver / n as f64;
                fine.conduct(dt_solver / n as f64);
            }
            long.heat_in[cell] += power * dt_solver;
            long.conduct(dt_solver);
        }
        let rise = split.max_temperature() - 300.0;
        assert!(rise > 1.0 && rise < 1e4, "rise {rise} K");
        for (a, b) in split.temp.iter().zip(&fine.temp) {
            assert!((a - b).abs() < 1e-9 * rise, "{a} vs {b}");
        }
        let wild = long
            .temp
            .iter()
            .any(|t| !t.is_finite() || (t - 300.0).abs() > 1e3 * rise);
        assert!(
            wild,
            "one unsplit long step per update stays bounded: the test shows nothing"
        );
    }

    /// Heat put in is conserved: stored heat plus what left through the held cells, with the
    /// tool's thermal mass as given and scaled.
    #[test]
    fn heat_is_conserved() {
        for scaling in [1.0, 25.0] {
            let (power, time) = (5e5, 4e-6);
            let t = heated_square(scaling, power, time, 2e-9 / scaling);
            let kept = t.stored_heat(300.0) + t.heat_to_ambient;
            let put = power * time;
            assert!(
                (kept / put - 1.0).abs() < 1e-9,
                "scaling {scaling}: {kept} vs {put}"
            );
        }
    }

    /// Dividing ρc by s runs the tool's temperature history s times faster and leaves its
    /// steady field alone: ρc/s · dT/dt' = ∇·(λ∇T) + Q with t' = t/s is the unscaled
    /// equation, so the scaled tool at t/s (steps dt/s) equals the unscaled one at t (steps
    /// dt) to rounding — early in the transient and at the steady field (the square's
    /// l²/α ≈ 2.5 ms; 20 ms is eight of them).
    #[test]
    fn a_scaled_thermal_mass_reaches_the_same_field_sooner() {
        let (power, dt) = (5e3, 1e-6);
        for time in [20e-6, 20e-3] {
            let plain = heated_square(1.0, power, time, dt);
            let scaled = heated_square(20.0, power, time / 20.0, dt / 20.0);
            let rise = plain.max_temperature() - 300.0;
            assert!(rise > 1.0, "the heated cell warms ({rise} K)");
            for (a, b) in plain.temp.iter().zip(&scaled.temp) {
                assert!((a - b).abs() < 1e-9 * rise, "{a} vs {b} at {time} s");
            }
        }
        let half = heated_square(1.0, power, 10e-3, dt).max_temperature() - 300.0;
        let full = heated_square(1.0, power, 20e-3, dt).max_temperature() - 300.0;
        assert!(
            (full - half).abs() < 0.01 * full,
            "{half} → {full} K: not yet steady"
        );
    }

    #[test]
    fn a_thermal_mass_scaling_below_one_is_refused() {
        let setup = ToolThermalSetup {
            thermal_mass_scaling: 0.5,
            ..ToolThermalSetup::carbide_altin()
        };
        let e = setup.validate().unwrap_err().to_string();
        assert!(e.contains("thermal_mass_scaling"), "{e}");
    }
}
