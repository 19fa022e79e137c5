//! `greybox windows`: friction windows from a coated tool mesh.

use anyhow::Result;
use greybox_couple::windows::WindowOptions;
use greybox_pipeline::windows::windows;
use std::path::PathBuf;

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Tool mesh: Gmsh .msh (v4 ASCII, physical groups) or Abaqus .inp (*ELSET).
    #[arg(long)]
    pub mesh: PathBuf,
    /// Element set of the coating (one element thick).
    #[arg(long, default_value = "COATING")]
    pub coating_set: String,
    /// Window extent outside the tool surface (mesh length unit).
    #[arg(long, default_value_t = 0.02)]
    pub outward: f64,
    /// Window extent inside the tool surface (mesh length unit).
    #[arg(long, default_value_t = 0.005)]
    pub inward: f64,
    /// Group boundary segments into windows of at least this length (default: one per segment).
    #[arg(long)]
    pub segment_length: Option<f64>,
    /// Initial Coulomb μ written into the DEFORM FRCWIN blocks.
    #[arg(long, default_value_t = 0.3)]
    pub mu: f64,
    /// DEFORM object numbers (tool, workpiece).
    #[arg(long, value_delimiter = ',', default_value = "2,1")]
    pub deform_objects: Vec<u32>,
    /// Output directory: windows.json, windows.csv, windows_frcwin.key, windows.vtk.
    #[arg(long, default_value = "windows-out")]
    pub out: PathBuf,
    /// Replace an existing, non-empty output directory (swapped out whole once this run is
    /// complete; without it such a directory is refused).
    #[arg(long)]
    pub force: bool,
}

pub fn run(a: Args) -> Result<()> {
    if a.deform_objects.len() != 2 {
        anyhow::bail!("--deform-objects takes two object numbers");
    }
    let (mesh, w) = windows(
        &a.mesh,
        &a.coating_set,
        WindowOptions {
            outward: a.outward,
            inward: a.inward,
            segment_length: a.segment_length,
        },
        a.mu,
        (a.deform_objects[0], a.deform_objects[1]),
        &a.out,
        a.force,
    )?;
    let total: f64 = w.iter().map(|x| x.length).sum();
    println!(
        "{} windows on {:.4} length units of coated surface from {} ({} nodes, {} elements); wrote {}/windows.{{json,csv,vtk}} and windows_frcwin.key",
        w.len(),
        total,
        a.mesh.display(),
        mesh.nodes.len(),
        mesh.elements.len(),
        a.out.display()
    );
    Ok(())
}
