//! `greybox windows`: friction windows from a coated tool mesh.

use anyhow::Result;
use greybox_pipeline::settings::windows::WindowsSettings;

#[derive(clap::Args, Debug)]
pub struct Args {
    #[command(flatten)]
    pub settings: WindowsSettings,
}

pub fn run(a: Args) -> Result<()> {
    let (mesh, w) = a.settings.run()?;
    let total: f64 = w.iter().map(|x| x.length).sum();
    println!(
        "{} windows on {:.4} length units of coated surface from {} ({} nodes, {} elements); wrote {}/windows.{{json,csv,vtk}} and windows_frcwin.key",
        w.len(),
        total,
        a.settings.mesh.display(),
        mesh.nodes.len(),
        mesh.elements.len(),
        a.settings.out.display()
    );
    Ok(())
}
