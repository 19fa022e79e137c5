//! The measured conditions of a suite (a CSV, one row per condition, units in the column
//! names, every row citing its source) and the cutting set-up of one condition from a
//! material's template.

use super::{MaterialRuns, ToolModel};
use anyhow::{bail, Context, Result};
use greybox_core::csvutil::{csv_error, parse_f64, parse_u64, record_line, Header};
use greybox_sim::cutting::CuttingSetup;
use serde::Serialize;
use std::path::Path;

/// One measured condition (SI inside; the CSV has units in its column names).
#[derive(Debug, Clone, Serialize)]
pub struct Condition {
    pub id: String,
    pub material: String,
    pub source: String,
    pub cutting_speed_m_s: f64,
    pub uncut_chip_thickness_m: f64,
    pub rake_deg: f64,
    pub clearance_deg: f64,
    pub edge_radius_m: f64,
    /// Measured forces per width, N/m, and their reported dispersions.
    pub cutting_force_n_per_m: f64,
    pub cutting_force_dispersion_n_per_m: Option<f64>,
    pub feed_force_n_per_m: f64,
    pub feed_force_dispersion_n_per_m: Option<f64>,
    /// Chip compression ratio h_c/h, where reported, and its reported dispersion.
    pub chip_ratio: Option<f64>,
    pub chip_ratio_dispersion: Option<f64>,
    /// What the row's dispersions are (columns `dispersion_sigmas` and `repeats`), where the
    /// data say: without it the measured values' own uncertainty cannot be counted.
    pub dispersion: Option<DispersionMeaning>,
    /// Tool–chip contact length, m, where reported.
    pub contact_length_m: Option<f64>,
}

/// What a row's dispersion columns mean: `sigmas` standard deviations of the `repeats`
/// measurements whose mean the row reports (a source drawing 2σ error bars over three
/// repeated cuts: 2 and 3).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct DispersionMeaning {
    pub sigmas: f64,
    pub repeats: u64,
}

impl DispersionMeaning {
    /// A row's meaning from its `dispersion_sigmas` and `repeats` cells (`None`: both empty
    /// or absent); one without the other, no repeats or k ≤ 0 is refused naming the line.
    fn of_row(
        sigmas: Option<f64>,
        repeats: Option<&str>,
        src: &str,
        line: u64,
    ) -> Result<Option<Self>> {
        match (sigmas, repeats.filter(|r| !r.trim().is_empty())) {
            (None, None) => Ok(None),
            (Some(sigmas), Some(r)) => {
                let repeats = parse_u64(r, src, line, "repeats")?;
                if sigmas <= 0.0 || repeats == 0 {
                    bail!(
                        "{src}: line {line}: columns dispersion_sigmas, repeats: expected a number of standard deviations > 0 and a count of repeated measurements >= 1, got {sigmas} and {repeats}"
                    );
                }
                Ok(Some(DispersionMeaning { sigmas, repeats }))
            }
            _ => bail!(
                "{src}: line {line}: columns dispersion_sigmas, repeats: expected both (what the dispersions are: how many standard deviations, over how many repeated measurements) or neither"
            ),
        }
    }
}

impl Condition {
    /// Standard errors of the measured means of F'c, F'f (N/m) and the chip ratio: the
    /// reported dispersion d over `sigmas`, the standard deviation of one measurement,
    /// over √repeats, se = d/(k √r). `None` where the row has no dispersion or does not say
    /// what it is.
    pub fn measured_standard_errors(&self) -> [Option<f64>; 3] {
        let se = |d: Option<f64>| {
            self.dispersion
                .zip(d)
                .map(|(m, d)| d / (m.sigmas * (m.repeats as f64).sqrt()))
        };
        [
            se(self.cutting_force_dispersion_n_per_m),
            se(self.feed_force_dispersion_n_per_m),
            se(self.chip_ratio_dispersion),
        ]
    }
}

/// Reads the measured conditions.
pub fn read_conditions(path: &Path) -> Result<Vec<Condition>> {
    let src = path.display().to_string();
    let mut rdr = greybox_core::input::data_csv(
        path,
        "validation conditions",
        csv::ReaderBuilder::new().comment(Some(b'#')),
    )?;
    let header = Header::new(&src, rdr.headers().map_err(|e| csv_error(&src, e))?);
    let need = |n: &str| header.require(n);
    let cols = [
        need("id")?,
        need("material")?,
        need("source")?,
        need("cutting_speed_m_per_min")?,
        need("uncut_chip_thickness_mm")?,
        need("rake_deg")?,
        need("clearance_deg")?,
        need("edge_radius_um")?,
        need("cutting_force_N_per_mm")?,
        need("feed_force_N_per_mm")?,
    ];
    let opt = |n: &str| header.find(n);
    let (c_fcd, c_ffd, c_ratio, c_ratio_d, c_lc) = (
        opt("cutting_force_dispersion_N_per_mm"),
        opt("feed_force_dispersion_N_per_mm"),
        opt("chip_ratio"),
        opt("chip_ratio_dispersion"),
        opt("contact_length_mm"),
    );
    let (c_sigmas, c_repeats) = (opt("dispersion_sigmas"), opt("repeats"));
    let mut out: Vec<Condition> = Vec::new();
    for (k, rec) in rdr.records().enumerate() {
        let rec = rec.map_err(|e| csv_error(&src, e))?;
        let line = record_line(rec.position(), k as u64 + 2);
        let num = |c: usize| parse_f64(&rec[c], &src, line, &header.names()[c]);
        let maybe = |c: Option<usize>| -> Result<Option<f64>> {
            match c {
                Some(c) if !rec[c].trim().is_empty() => Ok(Some(num(c)?)),
                _ => Ok(None),
            }
        };
        let positive = |c: usize, v: f64| -> Result<f64> {
            if v > 0.0 {
                Ok(v)
            } else {
                bail!(
                    "{src}: line {line}: column {}: expected a value > 0, got {v}",
                    header.names()[c]
                )
            }
        };
        let non_negative = |c: Option<usize>| -> Result<Option<f64>> {
            match maybe(c)? {
                Some(v) if v < 0.0 => bail!(
                    "{src}: line {line}: column {}: expected a dispersion >= 0, got {v}",
                    header.names()[c.unwrap_or_default()]
                ),
                v => Ok(v),
            }
        };
        let dispersion =
            DispersionMeaning::of_row(maybe(c_sigmas)?, c_repeats.map(|c| &rec[c]), &src, line)?;
        let id = rec[cols[0]].trim().to_string();
        if id.is_empty() || out.iter().any(|c| c.id == id) {
            bail!("{src}: line {line}: column id: expected a unique, non-empty id, got '{id}'");
        }
        out.push(Condition {
            id,
            material: rec[cols[1]].trim().to_string(),
            source: rec[cols[2]].trim().to_string(),
            cutting_speed_m_s: positive(cols[3], num(cols[3])?)? / 60.0,
            uncut_chip_thickness_m: positive(cols[4], num(cols[4])?)? * 1e-3,
            rake_deg: num(cols[5])?,
            clearance_deg: num(cols[6])?,
            edge_radius_m: num(cols[7])? * 1e-6,
            cutting_force_n_per_m: positive(cols[8], num(cols[8])?)? * 1e3,
            cutting_force_dispersion_n_per_m: non_negative(c_fcd)?.map(|v| v * 1e3),
            feed_force_n_per_m: positive(cols[9], num(cols[9])?)? * 1e3,
            feed_force_dispersion_n_per_m: non_negative(c_ffd)?.map(|v| v * 1e3),
            chip_ratio: maybe(c_ratio)?,
            chip_ratio_dispersion: non_negative(c_ratio_d)?,
            dispersion,
            contact_length_m: maybe(c_lc)?.map(|v| v * 1e-3),
        });
    }
    if out.is_empty() {
        bail!("{src}: no conditions");
    }
    Ok(out)
}

/// The set-up of condition `c` from `template` for `tool`.
pub fn condition_setup(
    template: &CuttingSetup,
    c: &Condition,
    runs: &MaterialRuns,
    tool: ToolModel,
) -> Result<CuttingSetup> {
    let mut s = template.clone();
    if let Some(dx) = runs.spacing_m {
        s.spacing_m = dx;
    }
    if runs.refinement.is_some() {
        s.refinement.clone_from(&runs.refinement);
    }
    if runs.local_time_stepping {
        s.numerics.local_time_stepping = true;
    }
    s.insert.rake_deg = c.rake_deg;
    s.insert.clearance_deg = c.clearance_deg;
    s.insert.edge_radius_m = c.edge_radius_m;
    s.uncut_chip_thickness_m = c.uncut_chip_thickness_m;
    let run = runs.run_speed_m_per_min / 60.0;
    if c.cutting_speed_m_s < run {
        s.cutting_speed_m_s = run;
        s.physical_cutting_speed_m_s = Some(c.cutting_speed_m_s);
    } else {
        s.cutting_speed_m_s = c.cutting_speed_m_s;
        s.physical_cutting_speed_m_s = None;
    }
    match tool {
        ToolModel::Adiabatic => {
            s.tool_thermal = None;
            s.numerics.friction_heat_share = 1.0;
        }
        ToolModel::Thermal => {
            if s.tool_thermal.is_none() {
                bail!(
                    "{}: the set-up template {} has no [tool_thermal] section for the thermal tool",
                    runs.name,
                    runs.setup
                );
            }
        }
    }
    s.validate()
        .with_context(|| format!("condition {}", c.id))?;
    Ok(s)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A suite entry's `spacing_m` and `refinement` replace the template's (the refinement
    /// with its coarsening), `local_time_stepping` turns it on; a refinement
    /// whose finest spacing leaves fewer than 4 particles across the uncut chip is refused
    /// for the condition it fails.
    #[test]
    fn a_suite_entry_chooses_the_refined_variant_of_its_template() {
        let template = CuttingSetup::iwf_ti64_reference();
        let runs: MaterialRuns = toml::from_str(
            r#"
            name = "Ti6Al4V"
            setup = "t.toml"
            run_speed_m_per_min = 600.0
            calibration = []
            mu_bracket = [0.2, 0.8]
            spacing_m = 2.0e-5
            refinement = { regions = [{ ahead_m = 0.2e-3, behind_m = 0.0, below_m = 0.04e-3, above_m = 0.3e-3 }], coarsen_behind_m = 0.1e-3 }
            local_time_stepping = true
            "#,
        )
        .unwrap();
        let mut c = Condition {
            id: "X".into(),
            material: "Ti6Al4V".into(),
            source: "test".into(),
            cutting_speed_m_s: 10.0,
            uncut_chip_thickness_m: 60e-6,
            rake_deg: 15.0,
            clearance_deg: 2.0,
            edge_radius_m: 20e-6,
            cutting_force_n_per_m: 1e5,
            cutting_force_dispersion_n_per_m: None,
            feed_force_n_per_m: 5e4,
            feed_force_dispersion_n_per_m: None,
            chip_ratio: None,
            chip_ratio_dispersion: None,
            dispersion: None,
            contact_length_m: None,
        };
        let s = condition_setup(&template, &c, &runs, ToolModel::Adiabatic).unwrap();
        assert_eq!(s.spacing_m, 2e-5);
        assert_eq!(s.surface_spacing(), 1e-5);
        assert_eq!(s.refinement, runs.refinement);
        assert!(s.numerics.local_time_stepping && !template.numerics.local_time_stepping);
        // Unrefined at 20 µm, 30 µm of chip would be 1.5 particles: with the refinement,
        // 3 fine particles, still too few.
        c.uncut_chip_thickness_m = 30e-6;
        let e = condition_setup(&template, &c, &runs, ToolModel::Adiabatic).unwrap_err();
        assert!(
            format!("{e:#}").contains("fewer than 4 particle spacings"),
            "{e:#}"
        );
    }

    #[test]
    fn reads_conditions_with_units_and_names_bad_fields() {
        let d = tempfile::tempdir().unwrap();
        let p = d.path().join("c.csv");
        std::fs::write(&p, "# measured\nid,material,source,cutting_speed_m_per_min,uncut_chip_thickness_mm,rake_deg,clearance_deg,edge_radius_um,cutting_force_N_per_mm,feed_force_N_per_mm,chip_ratio\nA,Ti6Al4V,x,30,0.06,15,2,20,118.2,50.3,1.23\n").unwrap();
        let c = read_conditions(&p).unwrap();
        assert_eq!(c.len(), 1);
        assert!((c[0].cutting_speed_m_s - 0.5).abs() < 1e-12);
        assert!((c[0].uncut_chip_thickness_m - 6e-5).abs() < 1e-15);
        assert!((c[0].cutting_force_n_per_m - 118_200.0).abs() < 1e-9);
        assert_eq!(c[0].chip_ratio, Some(1.23));
        assert_eq!(c[0].dispersion, None);
        assert_eq!(c[0].measured_standard_errors(), [None; 3]);
        std::fs::write(&p, "id,material,source,cutting_speed_m_per_min,uncut_chip_thickness_mm,rake_deg,clearance_deg,edge_radius_um,cutting_force_N_per_mm,feed_force_N_per_mm\nA,Ti,x,30,-0.06,15,2,20,118,50\n").unwrap();
        let e = format!("{:#}", read_conditions(&p).unwrap_err());
        assert!(
            e.contains("line 2") && e.contains("uncut_chip_thickness_mm"),
            "{e}"
        );
    }

    /// A row's dispersions are read with what they are (k standard deviations over r
    /// repeats: se = d/(k √r)); half a meaning, a count of no repeats or a negative dispersion
    /// is refused with the line and the columns named.
    #[test]
    fn reads_what_the_dispersions_are() {
        let d = tempfile::tempdir().unwrap();
        let p = d.path().join("c.csv");
        let head = "id,material,source,cutting_speed_m_per_min,uncut_chip_thickness_mm,rake_deg,clearance_deg,edge_radius_um,cutting_force_N_per_mm,cutting_force_dispersion_N_per_mm,feed_force_N_per_mm,feed_force_dispersion_N_per_mm,chip_ratio,chip_ratio_dispersion,dispersion_sigmas,repeats\n";
        let write = |rows: &str| std::fs::write(&p, format!("{head}{rows}")).unwrap();
        write("A,Ti,x,30,0.06,15,2,20,118.2,12.0,50.3,6.0,1.23,0.30,2,3\nB,Ti,x,40,0.06,15,2,20,118.2,12.0,50.3,,1.20,,,\n");
        let c = read_conditions(&p).unwrap();
        let k3 = 2.0 * 3f64.sqrt();
        let se = c[0].measured_standard_errors();
        assert!((se[0].unwrap() - 12_000.0 / k3).abs() < 1e-9);
        assert!((se[1].unwrap() - 6_000.0 / k3).abs() < 1e-9);
        assert!((se[2].unwrap() - 0.30 / k3).abs() < 1e-12);
        assert_eq!(c[1].measured_standard_errors(), [None; 3]);
        for (row, needle) in [
            ("A,Ti,x,30,0.06,15,2,20,118,12,50,6,1.2,0.3,2,\n", "both"),
            (
                "A,Ti,x,30,0.06,15,2,20,118,12,50,6,1.2,0.3,2,0\n",
                "repeated measurements >= 1",
            ),
            (
                "A,Ti,x,30,0.06,15,2,20,118,12,50,6,1.2,0.3,0,3\n",
                "standard deviations > 0",
            ),
            (
                "A,Ti,x,30,0.06,15,2,20,118,12,50,6,1.2,0.3,2,2.5\n",
                "non-negative integer",
            ),
            (
                "A,Ti,x,30,0.06,15,2,20,118,12,50,6,1.2,-0.3,2,3\n",
                "chip_ratio_dispersion",
            ),
        ] {
            write(row);
            let e = format!("{:#}", read_conditions(&p).unwrap_err());
            assert!(e.contains("line 2") && e.contains(needle), "{row}: {e}");
        }
    }
}
