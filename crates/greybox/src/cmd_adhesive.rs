//! `greybox adhesive`: the ploughing correction μ_adh = μ_app − μ_plough.

use crate::output::{print_json, Table};
use anyhow::{bail, Context, Result};
use greybox_core::atomic::write_string_atomic;
use greybox_core::dataset::FrictionDataset;
use greybox_tribo::ploughing::{article_table3, correct_analytic, Correction, TrackWidth};
use std::path::{Path, PathBuf};

#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Method {
    /// Bowden–Tabor sphere ploughing with measured track widths.
    Analytic,
    /// Inverse pin-sliding simulation (comes with the simulator).
    Simulation,
}

#[derive(clap::Args, Debug)]
pub struct Args {
    /// Friction dataset CSV from `greybox identify`.
    #[arg(long)]
    pub data: PathBuf,
    #[arg(long, value_enum, default_value_t = Method::Analytic)]
    pub method: Method,
    /// Pin tip radius, mm.
    #[arg(long = "pin-radius-mm", default_value_t = 17.0)]
    pub pin_radius_mm: f64,
    /// Measured track width as FORCE_N:WIDTH_um (repeatable); default: the article's Table 3.
    #[arg(long = "track-width")]
    pub track_width: Vec<String>,
    /// CSV of measured track widths with columns normal_force_N, track_width_um.
    #[arg(long = "track-widths-csv")]
    pub track_widths_csv: Option<PathBuf>,
    /// Output dataset with the cof_adhesive column (the correction goes beside it as .correction.json).
    #[arg(long, default_value = "dataset_adhesive.csv")]
    pub out: PathBuf,
    #[arg(long)]
    pub json: bool,
}

fn widths(a: &Args) -> Result<Vec<TrackWidth>> {
    let mut w = Vec::new();
    for t in &a.track_width {
        let (f, x) = t
            .split_once(':')
            .with_context(|| format!("--track-width '{t}': expected FORCE_N:WIDTH_um"))?;
        let parse = |s: &str| {
            s.trim()
                .parse::<f64>()
                .with_context(|| format!("--track-width '{t}': '{s}' is not a number"))
        };
        w.push(TrackWidth {
            normal_force_n: parse(f)?,
            width_um: parse(x)?,
        });
    }
    if let Some(p) = &a.track_widths_csv {
        let mut rdr =
            csv::Reader::from_path(p).with_context(|| format!("cannot read {}", p.display()))?;
        for (k, r) in rdr.deserialize::<TrackWidth>().enumerate() {
            w.push(r.with_context(|| {
                format!(
                    "{}, line {}: expected normal_force_N,track_width_um",
                    p.display(),
                    k + 2
                )
            })?);
        }
    }
    if w.is_empty() {
        w = article_table3();
    }
    Ok(w)
}

/// Apply the correction and write the dataset and the correction record.
pub fn adhesive(a: &Args) -> Result<(FrictionDataset, Correction)> {
    if a.method == Method::Simulation {
        bail!("--method simulation (inverse pin-sliding simulation) needs the built-in simulator, which is not part of greybox yet; use --method analytic");
    }
    let mut ds = FrictionDataset::read_csv(&a.data)?;
    let corr = correct_analytic(&mut ds, a.pin_radius_mm * 1e-3, &widths(a)?)?;
    ds.write_csv(&a.out)?;
    write_string_atomic(
        &correction_path(&a.out),
        &serde_json::to_string_pretty(&corr)?,
    )?;
    Ok((ds, corr))
}

pub fn correction_path(out: &Path) -> PathBuf {
    out.with_extension("correction.json")
}

pub fn print_correction(c: &Correction) {
    println!(
        "ploughing correction ({}), pin radius {} mm",
        c.method, c.pin_tip_radius_mm
    );
    println!(
        "  w(F) = {:.2} um * F^{:.4}",
        c.width_law.a_um, c.width_law.b
    );
    let mut t = Table::new(&["F_N [N]", "track width [um]", "depth [um]", "mu_plough"]);
    for l in &c.per_load {
        t.row(vec![
            format!("{:.1}", l.normal_force_n),
            format!("{:.0}", l.width_um),
            format!("{:.2}", l.depth_um),
            format!("{:.4}", l.mu_plough),
        ]);
    }
    print!("{}", t.render());
    println!(
        "  mean reduction of the COF: {:.2} % (article: 7.29 % at its highest loads)",
        c.mean_reduction_percent
    );
}

pub fn run(a: Args) -> Result<()> {
    let (_, c) = adhesive(&a)?;
    if a.json {
        return print_json(&c);
    }
    print_correction(&c);
    println!(
        "wrote {} and {}",
        a.out.display(),
        correction_path(&a.out).display()
    );
    Ok(())
}
