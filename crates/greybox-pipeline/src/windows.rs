//! Friction windows from a coated tool mesh (Gmsh or Abaqus) as JSON, CSV, DEFORM FRCWIN
//! and VTK.

use crate::output::{provenance, stage_out_dir};
use anyhow::Result;
use greybox_core::atomic::write_string_atomic;
use greybox_couple::mesh::{read_mesh, Mesh};
use greybox_couple::windows::{
    build_windows, frcwin_text, write_csv, write_json, write_vtk, Window, WindowOptions,
};
use std::path::Path;

/// Build the windows of `coating_set` in `mesh_path` and write windows.json, windows.csv,
/// windows.vtk and windows_frcwin.key (initial Coulomb `mu`, DEFORM objects (tool,
/// workpiece)) into the directory `out` (an existing non-empty `out` needs `force`).
pub fn windows(
    mesh_path: &Path,
    coating_set: &str,
    options: WindowOptions,
    mu: f64,
    deform_objects: (u32, u32),
    out: &Path,
    force: bool,
) -> Result<(Mesh, Vec<Window>)> {
    let mesh = read_mesh(mesh_path)?;
    let w = build_windows(&mesh, coating_set, options)?;
    let inputs = [("mesh", mesh_path)];
    let staged = stage_out_dir(out, force, &inputs)?;
    let dir = staged.path();
    write_json(&dir.join("windows.json"), &w)?;
    write_csv(&dir.join("windows.csv"), &w)?;
    write_vtk(&dir.join("windows.vtk"), &w)?;
    write_string_atomic(
        &dir.join("windows_frcwin.key"),
        &frcwin_text(&w, mu, deform_objects),
    )?;
    provenance(&inputs)?.write_into(dir)?;
    staged.commit()?;
    Ok((mesh, w))
}
