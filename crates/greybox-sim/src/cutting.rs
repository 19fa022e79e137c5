//! Orthogonal cutting set-up: a rigid tool with rake angle, clearance angle and edge radius
//! moving at the cutting speed through a rectangular workpiece at the uncut chip thickness.
//!
//! Frame: the workpiece occupies x ∈ [0, L], y ∈ [−H, 0]; the tool comes from x > L and moves
//! in −x. The rake face leans back from the vertical by the rake angle γ (positive rake:
//! away from the chip), the flank face rises from the horizontal by the clearance angle α.

use crate::geometry::RoundedPolygon;
use crate::model::{BoundaryGroup, Model, Numerics};
use crate::particles::Particles;
use crate::sink::Sink;
use crate::tool::{ConstantMu, Motion, MotionSegment, Tool, Window};
use crate::tool_thermal::{ToolThermal, ToolThermalSetup};
use greybox_core::{ContactState, FrictionLaw};
use greybox_material::Material;
use serde::{Deserialize, Serialize};
use std::sync::Arc;

/// The band the chip thickness is measured in ([`crate::chip::chip_thickness`]), in uncut
/// chip thicknesses h above the original workpiece surface (which lies h above the cutting
/// edge): from h to 2h.
pub const MEASURING_BAND_H: [f64; 2] = [1.0, 2.0];

/// The top of [`MEASURING_BAND_H`] above the cutting edge, m, for an uncut chip thickness
/// `h`: what must stay fine for the chip to be measured at its own spacing.
pub fn measuring_band_top_above_edge(h: f64) -> f64 {
    (1.0 + MEASURING_BAND_H[1]) * h
}

/// The insert geometry (SI units, angles in degrees).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct InsertGeometry {
    pub rake_deg: f64,
    pub clearance_deg: f64,
    pub edge_radius_m: f64,
    /// Length of the modelled rake face, m.
    pub rake_length_m: f64,
    /// Length of the modelled flank face, m.
    pub flank_length_m: f64,
}

impl InsertGeometry {
    /// The rounded wedge with its sharp-edge point at the origin (before placement): the core
    /// polygon is the wedge offset inwards by the edge radius, so that the rounded shape's
    /// rake and flank faces lie on the lines through the origin.
    pub fn shape(&self) -> greybox_core::Result<RoundedPolygon> {
        let g = self.rake_deg.to_radians();
        let a = self.clearance_deg.to_radians();
        let ur = [g.sin(), g.cos()];
        let uf = [a.cos(), a.sin()];
        // Wedge angle β between the faces, bisector b into the wedge.
        let beta = (ur[0] * uf[0] + ur[1] * uf[1]).acos();
        if !(beta > 0.1_f64.to_radians() && beta < 179.0_f64.to_radians())
            || self.edge_radius_m < 0.0
        {
            return Err(greybox_core::Error::invalid(
                "insert geometry",
                format!(
                    "rake {}° and clearance {}° do not make a wedge",
                    self.rake_deg, self.clearance_deg
                ),
            ));
        }
        let b = {
            let (x, y) = (ur[0] + uf[0], ur[1] + uf[1]);
            let l = x.hypot(y);
            [x / l, y / l]
        };
        let r = self.edge_radius_m;
        let d = r / (0.5 * beta).sin();
        let e = [d * b[0], d * b[1]];
        let lf = self.flank_length_m;
        let lr = self.rake_length_m;
        let pf = [e[0] + lf * uf[0], e[1] + lf * uf[1]];
        let pr = [e[0] + lr * ur[0], e[1] + lr * ur[1]];
        // Far corner: where the back face (parallel to the rake, through pf) meets the top
        // face (parallel to the flank, through pr), kept convex by taking the max.
        let corner = [pf[0].max(pr[0] + lf * uf[0]), pr[1].max(pf[1] + lr * ur[1])];
        // Vertex order (counter-clockwise) puts the rake face, the edge arc and the flank face
        // first and contiguous in arc length: s runs down the rake from its top (s = 0) to
        // the edge, round the edge, and out along the flank (see [`EdgeLayout`]).
        RoundedPolygon::new(vec![pr, e, pf, corner], r)
    }

    /// Where the rake face, the edge and the flank face lie in the arc length of [`shape`].
    pub fn layout(&self) -> greybox_core::Result<EdgeLayout> {
        let shape = self.shape()?;
        let (rake_start, rake_end) = shape.edge_span(0);
        let (arc_start, arc_end) = shape.arc_span(1);
        let (_, flank_end) = shape.edge_span(1);
        debug_assert!(rake_start == 0.0 && (rake_end - arc_start).abs() < 1e-15);
        Ok(EdgeLayout {
            tip_s: 0.5 * (arc_start + arc_end),
            rake_end_s: rake_end,
            arc_end_s: arc_end,
            flank_end_s: flank_end,
        })
    }
}

/// Most friction windows along a tool: far more than any resolved contact needs, few enough
/// that their per-update work and memory stay small.
const MAX_WINDOWS: f64 = 100_000.0;

/// The cutting edge in the tool's arc length s (m): the rake face is s ∈ [0, `rake_end_s`)
/// running down towards the edge, the edge arc [`rake_end_s`, `arc_end_s`), the flank face
/// [`arc_end_s`, `flank_end_s`). Distances "from the edge" are measured along the surface
/// from the middle of the edge arc (`tip_s`): positive up the rake face, negative along the
/// flank.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct EdgeLayout {
    pub tip_s: f64,
    pub rake_end_s: f64,
    pub arc_end_s: f64,
    pub flank_end_s: f64,
}

/// Which face a point of the tool surface belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Face {
    Rake,
    Edge,
    Flank,
    Back,
}

impl Face {
    pub fn name(self) -> &'static str {
        match self {
            Face::Rake => "rake",
            Face::Edge => "edge",
            Face::Flank => "flank",
            Face::Back => "back",
        }
    }
}

impl EdgeLayout {
    /// The face at arc length s and the signed distance from the edge along the surface, m
    /// (positive on the rake side).
    pub fn locate(&self, s: f64) -> (Face, f64) {
        let face = if s < self.rake_end_s {
            Face::Rake
        } else if s < self.arc_end_s {
            Face::Edge
        } else if s < self.flank_end_s {
            Face::Flank
        } else {
            Face::Back
        };
        (face, self.tip_s - s)
    }

    /// Friction windows of length `length` (m): from the tip up the rake face and from the tip
    /// out along the flank face (the last window of each face may be shorter), then one
    /// window for the rest of the insert; every window holds `law`, sorted by s.
    pub fn windows(
        &self,
        length: f64,
        perimeter: f64,
        law: &Arc<dyn FrictionLaw>,
        start: &ContactState,
    ) -> Vec<Window> {
        let mut cuts = vec![0.0, self.tip_s, self.flank_end_s, perimeter + 1e-12];
        let mut s = self.tip_s - length;
        while s > 0.5 * length {
            cuts.push(s);
            s -= length;
        }
        let mut s = self.tip_s + length;
        while s < self.flank_end_s - 0.5 * length {
            cuts.push(s);
            s += length;
        }
        cuts.sort_by(f64::total_cmp);
        cuts.windows(2)
            .map(|c| Window::new(c[0], c[1], law.clone(), start))
            .collect()
    }
}

/// An orthogonal cut (SI units).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CuttingSetup {
    pub insert: InsertGeometry,
    /// Cutting speed, m/s.
    pub cutting_speed_m_s: f64,
    /// Uncut chip thickness h, m.
    pub uncut_chip_thickness_m: f64,
    /// Length of cut, m.
    pub cut_length_m: f64,
    /// Particle spacing, m.
    pub spacing_m: f64,
    /// Workpiece height below the surface, m.
    pub workpiece_height_m: f64,
    /// Coulomb μ on the whole tool (windows come with the grey-box set-up).
    pub mu: f64,
    pub initial_temperature_k: f64,
    pub material: Material,
    pub numerics: Numerics,
    /// Friction windows and the grey-box loop.
    #[serde(default)]
    pub friction: FrictionSetup,
    /// The steady state's warm-up, its interval targets and whether the cut stops once
    /// they are met ([`crate::steady`]).
    #[serde(default)]
    pub steady: SteadySetup,
    /// Heat conduction in the tool and thermal contact (`None`: a rigid, adiabatic tool, as
    /// in the ETH IWF codes).
    #[serde(default)]
    pub tool_thermal: Option<ToolThermalSetup>,
    /// Time scaling: the physical cutting speed, m/s, when the cut runs faster
    /// (`cutting_speed_m_s`) to save steps. With the speed-up s = v_run/v_phys the strain rate
    /// the flow stress sees is scaled back by 1/s, every conductivity (workpiece, tool) and
    /// the contact conductance are multiplied by s so that the thermal Péclet number v·L/α
    /// stays physical, and the friction windows report (and their law sees) the physical
    /// sliding velocity. Inertia grows as s² (ρ v² h per width; check it against the force).
    #[serde(default)]
    pub physical_cutting_speed_m_s: Option<f64>,
    /// Dynamic refinement around the cutting edge (`None`: one spacing everywhere). Unset,
    /// it is not written out (case ids and files of earlier runs stay).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub refinement: Option<CutRefinement>,
    /// Height above the uncut surface (the top particle centres), m, where the chip breaks
    /// off: free particles that rise above it leave the model (see [`crate::sink`]; `None`:
    /// the chip stays whole). It must lie above the band the chip thickness is measured in
    /// (h to 2h) by four spacings, and should lie above the tool–chip contact. Unset, it is
    /// not written out (case ids and files of earlier runs stay).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub chip_break_height_m: Option<f64>,
}

/// The refinement regions of a cut, in the frame of the cutting edge (the sharp-edge point,
/// where rake and flank lines meet), one per level, each inside the one before: a particle
/// inside k regions is split until it has spacing `spacing_m`/2ᵏ (see [`crate::refine`]).
/// The regions travel with the tool, so the band they sweep (the chip, the primary shear
/// zone, the machined surface layer) ends up fine and the rest of the workpiece keeps
/// `spacing_m`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CutRefinement {
    /// One region per level, coarsest first (at most 3).
    pub regions: Vec<CutRegion>,
    /// How a particle is split (`square`: four children).
    #[serde(default)]
    pub pattern: crate::refine::SplitPattern,
    /// Distance behind the cutting edge, m, beyond which the refined particles of the
    /// machined surface are merged back to `spacing_m` (see [`crate::coarsen`]): the region
    /// from there on, from the workpiece's bottom to half this distance above the edge (the
    /// chip, rising along the rake face, stays clear of it for rake angles up to 45°).
    /// `None` (unset, not written out): refined particles stay fine.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub coarsen_behind_m: Option<f64>,
    /// Height above the cutting edge, m, beyond which the refined particles of the chip are
    /// merged back to `spacing_m` (see [`crate::coarsen`]): the chip, past the contact and
    /// the band the chip thickness is measured in, on its way to its break. It must be at
    /// least 3h (the top of that band, [`crate::chip::chip_thickness`]) and at least the
    /// first region's `above_m`. `None` (unset, not written out): the chip stays fine.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub coarsen_chip_above_m: Option<f64>,
}

/// A refinement region around the cutting edge, m: how far it reaches ahead of the edge (in
/// the cutting direction), behind it (over the machined surface), below and above it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CutRegion {
    pub ahead_m: f64,
    pub behind_m: f64,
    pub below_m: f64,
    pub above_m: f64,
}

impl CutRefinement {
    /// The solver's refinement (regions in the tool frame; the tool moves in −x).
    pub fn refinement(&self) -> crate::refine::Refinement {
        crate::refine::Refinement {
            tool: 0,
            regions: self
                .regions
                .iter()
                .map(|r| crate::refine::Region {
                    x_min: -r.ahead_m,
                    x_max: r.behind_m,
                    y_min: -r.below_m,
                    y_max: r.above_m,
                })
                .collect(),
            pattern: self.pattern,
            coarsening: self.coarsening(),
        }
    }

    /// The coarsening regions in the tool frame (1 m: everything beyond): the machined
    /// surface from `coarsen_behind_m` behind the edge, from the workpiece's bottom to half
    /// that distance above the edge (the chip, rising along the rake face, stays clear of it
    /// for rake angles up to 45°); the chip above `coarsen_chip_above_m`.
    fn coarsening(&self) -> Option<crate::refine::Coarsening> {
        use crate::refine::Region;
        let behind = self.coarsen_behind_m.map(|behind| Region {
            x_min: behind,
            x_max: 1.0,
            y_min: -1.0,
            y_max: 0.5 * behind,
        });
        let chip = self.coarsen_chip_above_m.map(|above| Region {
            x_min: -1.0,
            x_max: 1.0,
            y_min: above,
            y_max: 1.0,
        });
        let regions: Vec<Region> = behind.into_iter().chain(chip).collect();
        (!regions.is_empty()).then_some(crate::refine::Coarsening { regions })
    }

    /// The finest spacing, m, for a level-0 spacing `dx`.
    pub fn finest_spacing(&self, dx: f64) -> f64 {
        dx * crate::particles::spacing_factor(self.regions.len().min(3) as u8)
    }

    /// The particles a workpiece of `length` × `height` (m, level-0 spacing `dx`) can end
    /// with, at most: the level-0 lattice plus, per level k, three children for each of the
    /// 4ᵏ⁻¹ level-(k−1) particles per level-0 cell of the band its region can sweep.
    pub fn particle_estimate(&self, length: f64, height: f64, dx: f64) -> f64 {
        let base = (length / dx).ceil() * (height / dx).ceil();
        self.regions
            .iter()
            .enumerate()
            .map(|(k, r)| {
                let band = length * (r.above_m + r.below_m).min(height);
                band / (dx * dx) * 3.0 * 4f64.powi(k as i32)
            })
            .sum::<f64>()
            + base
    }
}

/// Friction windows along the rake and flank faces and the in-process grey-box loop.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct FrictionSetup {
    /// Window length along the tool surface, m.
    pub window_length_m: f64,
    /// Re-evaluate every window's μ from its time-averaged state every N steps.
    pub update_every_steps: u64,
    /// Law file (`greybox fit` model, law or table file; relative to the set-up file). Without
    /// one (or an inline `law`) the insert uses the constant `mu`.
    pub law_file: Option<String>,
    /// An inline law: the content of a law file as a table (`[friction.law] law = "power"
    /// mu_ref = 0.5 …`), so that a sweep or a calibration can set its numeric fields
    /// (`friction.law.b`). At most one of `law` and `law_file`; read by the pipeline, which
    /// knows the law files.
    pub law: Option<serde_json::Value>,
    /// Smoothing of the state each window hands to its law, in time and along the tool
    /// (default: none; see [`crate::friction_loop`]).
    pub smoothing: crate::friction_loop::Smoothing,
    /// The limiting shear stress τ_max of the tool–chip interface, Pa: the friction stress is
    /// min(μσ_n, τ_max), Coulomb friction up to the shear the interface can carry (Zorev's
    /// sticking zone near the edge, where μσ_n would exceed it; Abaqus's `TAUMAX`, set to the
    /// material's shear yield A/√3 in Ducobu et al.'s Ti6Al4V model). `None` (unset, not
    /// written out): Coulomb alone.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shear_limit_pa: Option<f64>,
}

impl Default for FrictionSetup {
    fn default() -> Self {
        FrictionSetup {
            window_length_m: 10e-6,
            update_every_steps: 500,
            law_file: None,
            law: None,
            smoothing: Default::default(),
            shear_limit_pa: None,
        }
    }
}

/// When a cut is sure of its steady state (see [`crate::steady`]): its forces are averaged
/// over whole periods after the warm-up, from `min_cut_length_m` on, with 95 % intervals
/// from batch means; with `stop_when_sure` the cut ends once F'c's and F'f's relative
/// half-widths are at most their targets, otherwise (and at the latest) at `cut_length_m`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct SteadySetup {
    /// End the cut once both targets are met (`cut_length_m` is then the length limit).
    pub stop_when_sure: bool,
    /// Target relative half-width of the 95 % interval of the cutting force F'c.
    pub cutting_force_rel_ci95: f64,
    /// Target relative half-width of the 95 % interval of the feed force F'f.
    pub feed_force_rel_ci95: f64,
    /// No steady state before this much has been cut, m (the chip must have formed).
    pub min_cut_length_m: f64,
    /// Contact renewals (l_c h_c/h of cut each, [`crate::steady`]) the steady stretch must
    /// span before its intervals count: a shorter one cannot see the contact's slowest
    /// fluctuations and is marked short; a cut is never sure on one.
    pub min_contact_renewals: f64,
}

impl Default for SteadySetup {
    fn default() -> Self {
        SteadySetup {
            stop_when_sure: false,
            cutting_force_rel_ci95: 0.015,
            feed_force_rel_ci95: 0.03,
            min_cut_length_m: 0.0,
            min_contact_renewals: 3.0,
        }
    }
}

impl CuttingSetup {
    /// The ETH IWF CPU reference case (mfree_iwf-ul-cut-refine, single resolution): Ti6Al4V,
    /// rake 0°, clearance 11°, h = 0.1 mm, 500 m/min, 1 mm of cut, μ = 0.35 (the IWF value),
    /// 10 µm spacing (10 particles across h), edge radius 5 µm.
    pub fn iwf_ti64_reference() -> Self {
        CuttingSetup {
            insert: InsertGeometry {
                rake_deg: 0.0,
                clearance_deg: 11.0,
                edge_radius_m: 5e-6,
                rake_length_m: 0.5e-3,
                flank_length_m: 0.3e-3,
            },
            cutting_speed_m_s: 500.0 / 60.0,
            uncut_chip_thickness_m: 0.1e-3,
            cut_length_m: 1.0e-3,
            spacing_m: 10e-6,
            workpiece_height_m: 0.5e-3,
            mu: 0.35,
            initial_temperature_k: 300.0,
            material: Material::ti6al4v(),
            numerics: Numerics::default(),
            friction: FrictionSetup::default(),
            steady: SteadySetup::default(),
            tool_thermal: None,
            physical_cutting_speed_m_s: None,
            refinement: None,
            chip_break_height_m: None,
        }
    }

    /// The speed-up s of a time-scaled cut (1 without time scaling).
    pub fn speed_up(&self) -> f64 {
        self.physical_cutting_speed_m_s
            .map_or(1.0, |v| self.cutting_speed_m_s / v)
    }

    /// Length of the modelled tool surface that carries windows (an upper bound: rake and
    /// flank faces and a half circle of the edge radius), m.
    fn modelled_surface_m(&self) -> f64 {
        let g = &self.insert;
        g.rake_length_m + g.flank_length_m + std::f64::consts::PI * g.edge_radius_m
    }

    /// Spacing of the particles at the workpiece surface when the tool reaches them, m: the
    /// finest of a refinement (its regions split the surface ahead of the edge), else
    /// `spacing_m`. The uncut chip thickness is measured from their centres.
    pub fn surface_spacing(&self) -> f64 {
        self.refinement
            .as_ref()
            .map_or(self.spacing_m, |r| r.finest_spacing(self.spacing_m))
    }

    /// Workpiece length: the cut plus a margin of 0.2 mm ahead.
    pub fn workpiece_length(&self) -> f64 {
        self.cut_length_m + 0.2e-3
    }

    /// The refinement's regions (the solver's checks) and the chip's coarsening height,
    /// which must clear the band the chip thickness is measured in (2h to 3h above the
    /// edge, [`crate::chip::chip_thickness`]).
    fn validate_refinement(&self, r: &CutRefinement) -> greybox_core::Result<()> {
        let invalid = |e| greybox_core::Error::invalid("cutting set-up [refinement]", e);
        r.refinement().validate(1).map_err(invalid)?;
        let three_h = measuring_band_top_above_edge(self.uncut_chip_thickness_m);
        match r.coarsen_chip_above_m {
            Some(above) if !(above >= three_h * (1.0 - 1e-9)) => Err(invalid(format!(
                "coarsen_chip_above_m ({above:e} m) must be at least 3h = {three_h:e} m: the chip thickness is measured from 2h to 3h above the edge, on particles that must not be merged"
            ))),
            _ => Ok(()),
        }
    }

    pub fn validate(&self) -> greybox_core::Result<()> {
        use greybox_core::physics::Quantity;
        let h = self.uncut_chip_thickness_m;
        // The spacing the chip is cut at: the finest of a refinement.
        let dx = self.surface_spacing();
        if let Some(r) = &self.refinement {
            self.validate_refinement(r)?;
        }
        greybox_core::rules::Rules::new("cutting set-up")
            .section("insert", |r| {
                let g = &self.insert;
                r.between("rake_deg", g.rake_deg, -45.0, 45.0)
                    .between("clearance_deg", g.clearance_deg, 0.0, 45.0)
                    .non_negative("edge_radius_m", g.edge_radius_m)
                    .positive("rake_length_m", g.rake_length_m)
                    .positive("flank_length_m", g.flank_length_m);
            })
            .physics(
                "cutting_speed_m_s",
                Quantity::CuttingSpeed,
                self.cutting_speed_m_s,
            )
            .positive("uncut_chip_thickness_m", h)
            .positive("cut_length_m", self.cut_length_m)
            .positive("spacing_m", self.spacing_m)
            .positive("workpiece_height_m", self.workpiece_height_m)
            .physics("mu", Quantity::Mu, self.mu)
            .relation(
                self.physical_cutting_speed_m_s
                    .is_none_or(|v| v > 0.0 && v <= self.cutting_speed_m_s),
                format!(
                    "physical_cutting_speed_m_s ({:?}) must be > 0 and at most cutting_speed_m_s ({}): the cut runs at cutting_speed_m_s and is scaled back",
                    self.physical_cutting_speed_m_s, self.cutting_speed_m_s
                ),
            )
            .relation(
                self.chip_break_height_m
                    .is_none_or(|b| b.is_finite() && b > 2.0 * h + 4.0 * dx),
                format!(
                    "chip_break_height_m ({:?}) must be a height in m above 2 × uncut_chip_thickness_m + 4 spacings ({:e} m): the chip's thickness is measured between h and 2h above the surface",
                    self.chip_break_height_m,
                    2.0 * h + 4.0 * dx
                ),
            )
            .positive("initial_temperature_k", self.initial_temperature_k)
            .physics(
                "initial_temperature_k",
                Quantity::Temperature,
                self.initial_temperature_k,
            )
            .section("friction", |r| {
                r.positive("window_length_m", self.friction.window_length_m)
                    .at_least("update_every_steps", self.friction.update_every_steps, 1)
                    .relation(
                        !(self.friction.law.is_some() && self.friction.law_file.is_some()),
                        "give either law (inline) or law_file, not both",
                    );
                if let Some(tau) = self.friction.shear_limit_pa {
                    r.positive("shear_limit_pa", tau);
                }
            })
            .relation(
                !(self.modelled_surface_m() / self.friction.window_length_m > MAX_WINDOWS),
                format!(
                    "[friction] window_length_m = {:e} m cuts the modelled tool surface ({:.3} mm) into more than {MAX_WINDOWS:.0e} windows",
                    self.friction.window_length_m,
                    self.modelled_surface_m() * 1e3
                ),
            )
            .section("steady", |r| {
                r.above_up_to("cutting_force_rel_ci95", self.steady.cutting_force_rel_ci95, 0.0, 1.0)
                    .above_up_to("feed_force_rel_ci95", self.steady.feed_force_rel_ci95, 0.0, 1.0)
                    .non_negative("min_cut_length_m", self.steady.min_cut_length_m)
                    .within("min_contact_renewals", self.steady.min_contact_renewals, 0.0, 1e3);
            })
            .relation(
                !(self.workpiece_height_m <= h + 4.0 * dx),
                format!(
                    "workpiece_height_m ({:.1} µm) must exceed uncut_chip_thickness_m + 4 spacings ({:.1} µm)",
                    self.workpiece_height_m * 1e6,
                    (h + 4.0 * dx) * 1e6
                ),
            )
            .relation(
                !(h < 4.0 * dx),
                format!(
                    "the uncut chip thickness {:.1} µm spans fewer than 4 particle spacings ({:.1} µm); refine the spacing",
                    h * 1e6,
                    dx * 1e6
                ),
            )
            .finish()?;
        self.numerics.validate()?;
        self.friction.smoothing.validate()?;
        if let Some(t) = &self.tool_thermal {
            t.validate()?;
        }
        self.check_budgets()?;
        self.material.validate()
    }

    /// The particle count (the refinement's children included) and the thermal tool's grid
    /// against `numerics.max_particles`, before anything is allocated.
    fn check_budgets(&self) -> greybox_core::Result<()> {
        let (length, height, dx0) = (
            self.workpiece_length(),
            self.workpiece_height_m,
            self.spacing_m,
        );
        let count = self
            .refinement
            .as_ref()
            .map_or((length / dx0).ceil() * (height / dx0).ceil(), |r| {
                r.particle_estimate(length, height, dx0)
            });
        crate::particles::check_particle_budget(
            "cutting set-up",
            length,
            height,
            dx0,
            count,
            self.refinement.is_some(),
            self.numerics.max_particles.map(|c| c.as_u64()),
        )?;
        if let Some(t) = &self.tool_thermal {
            let grid = if t.grid_spacing_m > 0.0 {
                t.grid_spacing_m
            } else {
                dx0
            };
            ToolThermal::check_grid_budget(
                &self.insert.shape()?,
                grid,
                self.numerics.max_particles.map(|c| c.as_u64()),
            )?;
        }
        Ok(())
    }

    /// The contact state every window's law is evaluated at before its first update: the
    /// initial yield stress (J-C A; 1 GPa without plasticity) as pressure, the cutting speed and
    /// the initial temperature.
    pub fn nominal_contact(&self) -> ContactState {
        ContactState {
            pressure_pa: self
                .material
                .plasticity
                .as_ref()
                .map_or(1e9, |f| f.initial_yield_pa()),
            sliding_velocity_m_s: self.cutting_speed_m_s / self.speed_up(),
            temperature_k: self.initial_temperature_k,
        }
    }

    /// Simulated time of the whole configured cut, s: the cut length plus two spacings of
    /// approach at the cutting speed, plus half the speed ramp (5 % of the cut length).
    pub fn duration_s(&self) -> f64 {
        let v = self.cutting_speed_m_s;
        let ramp = 0.05 * self.cut_length_m / v;
        (self.cut_length_m + 2.0 * self.spacing_m) / v + 0.5 * ramp
    }

    /// The material and numerics a time-scaled cut runs with (see
    /// [`CuttingSetup::physical_cutting_speed_m_s`]): the strain rate the flow stress sees ÷ s
    /// and the workpiece's conductivity × s; unchanged at s = 1.
    fn time_scaled_material(&self) -> (Material, Numerics) {
        let speed_up = self.speed_up();
        let mut material = self.material.clone();
        let mut numerics = self.numerics.clone();
        if speed_up != 1.0 {
            numerics.strain_rate_scale /= speed_up;
            material
                .thermal
                .conductivity
                .y
                .iter_mut()
                .for_each(|k| *k *= speed_up);
        }
        (material, numerics)
    }

    /// Builds the model with `law` in every friction window of the insert.
    pub fn model_with_law(&self, law: Arc<dyn FrictionLaw>) -> greybox_core::Result<(Model, f64)> {
        self.validate()?;
        let dx = self.spacing_m;
        let (mut p, nx, ny) = Particles::workpiece(
            self.workpiece_length(),
            self.workpiece_height_m,
            dx,
            self.material.density_kg_m3,
            self.initial_temperature_k,
        );
        for j in 0..ny {
            for i in 0..nx {
                if j < 2 || i < 2 {
                    p.group[j * nx + i] = 1;
                }
            }
        }
        let groups = vec![BoundaryGroup {
            name: "clamped".into(),
            vx: Some(0.0),
            vy: Some(0.0),
        }];
        let shape = self.insert.shape()?;
        let (lo, _) = shape.bounding_box();
        // Place the lowest point of the tool at depth h below the top particle centres and
        // its leftmost point two spacings right of the workpiece.
        let top = -0.5 * self.surface_spacing();
        let lowest = shape.closest([0.0, -1.0]).distance; // distance from (0,−1) to the surface
        let y_low = -1.0 + lowest; // local y of the lowest surface point (below the edge)
        let position = [
            nx as f64 * dx + 2.0 * dx - lo[0],
            top - self.uncut_chip_thickness_m - y_low,
        ];
        let v = self.cutting_speed_m_s;
        let ramp = 0.05 * self.cut_length_m / v;
        let duration = self.duration_s();
        let motion = Motion {
            segments: vec![MotionSegment {
                duration_s: f64::INFINITY,
                velocity: [-v, 0.0],
                ramp_s: ramp,
            }],
        };
        let windows = self.insert.layout()?.windows(
            self.friction.window_length_m,
            shape.perimeter(),
            &law,
            &self.nominal_contact(),
        );
        let speed_up = self.speed_up();
        let layout = self.insert.layout()?;
        let thermal = self.tool_thermal.as_ref().map(|t| {
            let grid = if t.grid_spacing_m > 0.0 {
                t.grid_spacing_m
            } else {
                dx
            };
            ToolThermal::new(
                t.clone(),
                &shape,
                grid,
                self.initial_temperature_k,
                layout.flank_end_s,
                speed_up,
            )
        });
        let tool = Tool {
            name: "insert".into(),
            shape,
            position,
            motion,
            windows,
            force: [0.0, 0.0],
            contacts: 0,
            thermal,
            last_close_step: None,
            shear_limit_pa: self.friction.shear_limit_pa,
        };
        let (material, numerics) = self.time_scaled_material();
        Ok((
            Model {
                particles: p,
                material,
                tools: vec![tool],
                groups,
                numerics,
                refinement: self.refinement.as_ref().map(|r| r.refinement()),
                sink: self.chip_break_height_m.map(|height| Sink {
                    y_above_m: top + height,
                }),
            },
            duration,
        ))
    }

    pub fn model(&self) -> greybox_core::Result<(Model, f64)> {
        self.model_with_law(Arc::new(ConstantMu(self.mu)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The chip's coarsening region must start at or above 3h (the band the chip thickness
    /// is measured in stays fine) and clear of the refinement region.
    #[test]
    fn the_chip_is_coarsened_only_above_its_measuring_band_and_the_region() {
        let mut s = CuttingSetup::iwf_ti64_reference();
        let h = s.uncut_chip_thickness_m;
        s.refinement = Some(CutRefinement {
            regions: vec![CutRegion {
                ahead_m: 0.2e-3,
                behind_m: 0.02e-3,
                below_m: 0.04e-3,
                above_m: 3.0 * h,
            }],
            pattern: Default::default(),
            coarsen_behind_m: Some(0.1e-3),
            coarsen_chip_above_m: Some(3.0 * h),
        });
        s.validate().unwrap();
        let r = s.refinement.as_mut().unwrap();
        r.coarsen_chip_above_m = Some(2.9 * h);
        r.regions[0].above_m = 2.9 * h;
        let e = s.validate().unwrap_err().to_string();
        assert!(e.contains("must be at least 3h"), "{e}");
        let r = s.refinement.as_mut().unwrap();
        r.coarsen_chip_above_m = Some(3.0 * h);
        r.regions[0].above_m = 3.1 * h;
        let e = s.validate().unwrap_err().to_string();
        assert!(
            e.contains("coarsening region 2 overlaps refinement region 1"),
            "{e}"
        );
    }

    #[test]
    fn windows_tile_the_rake_and_flank_from_the_edge() {
        let g = InsertGeometry {
            rake_deg: 0.0,
            clearance_deg: 7.0,
            edge_radius_m: 20e-6,
            rake_length_m: 0.5e-3,
            flank_length_m: 0.3e-3,
        };
        let shape = g.shape().unwrap();
        let l = g.layout().unwrap();
        // Rake face straight part: its length; the edge arc turns by 180° − wedge angle (83°).
        assert!((l.rake_end_s - 0.5e-3).abs() < 1e-12);
        let turn = 97f64.to_radians();
        assert!((l.arc_end_s - l.rake_end_s - 20e-6 * turn).abs() < 1e-12);
        assert!((l.tip_s - l.rake_end_s - 10e-6 * turn).abs() < 1e-12);
        assert!((l.flank_end_s - l.arc_end_s - 0.3e-3).abs() < 1e-12);
        let law: Arc<dyn FrictionLaw> = Arc::new(ConstantMu(0.3));
        let w = l.windows(10e-6, shape.perimeter(), &law, &ContactState::new(1e9, 1.0));
        // Sorted, contiguous, covering the whole surface; a window boundary at the tip.
        assert_eq!(w[0].s_start, 0.0);
        assert!(w.windows(2).all(|p| p[0].s_end == p[1].s_start));
        assert!(w.last().unwrap().s_end >= shape.perimeter());
        assert!(w.iter().any(|x| x.s_start == l.tip_s));
        // Every window but the two face ends and the back is 10 µm long.
        let full = w
            .iter()
            .filter(|x| (x.length() - 10e-6).abs() < 1e-12)
            .count();
        assert!(full >= w.len() - 4, "{full} of {}", w.len());
        // Signed distance: positive up the rake, negative along the flank.
        let (f, d) = l.locate(l.tip_s - 50e-6);
        assert_eq!(f, Face::Rake);
        assert!((d - 50e-6).abs() < 1e-12);
        let (f, d) = l.locate(l.tip_s + 50e-6);
        assert_eq!(f, Face::Flank);
        assert!((d + 50e-6).abs() < 1e-12);
        assert_eq!(l.locate(l.tip_s).0, Face::Edge);
        // The rake face is where the shape's closest point says: a point left of the rake
        // line, 0.2 mm up, maps to the rake face 0.2 mm from the sharp edge.
        let q = shape.closest([-5e-6, 0.2e-3]);
        assert_eq!(l.locate(q.s).0, Face::Rake);
    }
}
