//! The settings of friction windows from a coated tool mesh (`greybox windows`, Python's
//! `windows`): one type, one default per field.
//!
//! ```
//! use greybox_pipeline::settings::{from_json, windows::WindowsSettings};
//! let s: WindowsSettings = from_json("windows", r#"{"mesh": "tool.msh"}"#)?;
//! assert_eq!((s.coating_set.as_str(), s.deform_objects.0), ("COATING", [2, 1]));
//! let bad = WindowsSettings { mu: -3.0, ..s };
//! assert!(bad.run().unwrap_err().to_string().starts_with("windows.mu"));
//! # Ok::<(), anyhow::Error>(())
//! ```

use anyhow::Result;
use greybox_core::setting::refused;
use greybox_couple::mesh::Mesh;
use greybox_couple::windows::{Window, WindowOptions};
use greybox_friction::export::engine::ObjectPair;
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// The coating's element set when none is named.
pub const DEFAULT_COATING_SET: &str = "COATING";
/// Window extent outside the tool surface, mesh length unit.
pub const DEFAULT_OUTWARD: f64 = 0.02;
/// Window extent inside the tool surface, mesh length unit.
pub const DEFAULT_INWARD: f64 = 0.005;
/// The initial Coulomb μ of the DEFORM FRCWIN blocks.
pub const DEFAULT_INITIAL_MU: f64 = 0.3;
/// The output directory when no `out` is given.
pub const DEFAULT_WINDOWS_DIR: &str = "windows-out";

/// One set of friction windows as a user states it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[cfg_attr(feature = "cli", derive(clap::Args))]
#[serde(deny_unknown_fields, default)]
pub struct WindowsSettings {
    /// Tool mesh: Gmsh .msh (v4 ASCII, physical groups) or Abaqus .inp (*ELSET).
    #[cfg_attr(feature = "cli", arg(long))]
    pub mesh: PathBuf,
    /// Element set of the coating (one element thick).
    #[cfg_attr(feature = "cli", arg(long, default_value = DEFAULT_COATING_SET))]
    pub coating_set: String,
    /// Window extent outside the tool surface (mesh length unit).
    #[cfg_attr(feature = "cli", arg(long, default_value_t = DEFAULT_OUTWARD))]
    pub outward: f64,
    /// Window extent inside the tool surface (mesh length unit).
    #[cfg_attr(feature = "cli", arg(long, default_value_t = DEFAULT_INWARD))]
    pub inward: f64,
    /// Group boundary segments into windows of at least this length (default: one per
    /// segment).
    #[cfg_attr(feature = "cli", arg(long))]
    pub segment_length: Option<f64>,
    /// Initial Coulomb μ written into the DEFORM FRCWIN blocks.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = DEFAULT_INITIAL_MU))]
    pub mu: f64,
    /// DEFORM object numbers TOOL,WORKPIECE.
    #[cfg_attr(feature = "cli", arg(long, default_value_t = ObjectPair::DEFORM_DEFAULT))]
    pub deform_objects: ObjectPair,
    /// Output directory: windows.json, windows.csv, windows_frcwin.key, windows.vtk.
    #[cfg_attr(feature = "cli", arg(long, default_value = DEFAULT_WINDOWS_DIR))]
    pub out: PathBuf,
    /// Replace an existing, non-empty output directory (swapped out whole once this run is
    /// complete; without it such a directory is refused).
    #[cfg_attr(feature = "cli", arg(long))]
    pub force: bool,
}

impl Default for WindowsSettings {
    fn default() -> Self {
        WindowsSettings {
            mesh: PathBuf::new(),
            coating_set: DEFAULT_COATING_SET.into(),
            outward: DEFAULT_OUTWARD,
            inward: DEFAULT_INWARD,
            segment_length: None,
            mu: DEFAULT_INITIAL_MU,
            deform_objects: ObjectPair::DEFORM_DEFAULT,
            out: PathBuf::from(DEFAULT_WINDOWS_DIR),
            force: false,
        }
    }
}

impl WindowsSettings {
    /// Build the windows and write them into `out`.
    pub fn run(&self) -> Result<(Mesh, Vec<Window>)> {
        if self.mesh.as_os_str().is_empty() {
            return Err(refused("windows", "mesh", "give the tool mesh (.msh or .inp)").into());
        }
        greybox_core::physics::admit_setting(
            greybox_core::physics::Quantity::Mu,
            self.mu,
            &greybox_core::setting::SettingPath::new("windows", "mu"),
        )?;
        crate::windows::windows(
            &self.mesh,
            &self.coating_set,
            WindowOptions {
                outward: self.outward,
                inward: self.inward,
                segment_length: self.segment_length,
            },
            self.mu,
            (self.deform_objects.0[0], self.deform_objects.0[1]),
            &self.out,
            self.force,
        )
    }
}
