//! Campaign section: the plan's run sheet and, per pin, the recording with the steady
//! windows the identification used shaded.

use super::page::{Block, Section, Table};
use super::scan::Found;
use super::{num, shown, Ctx};
use anyhow::{Context, Result};
use greybox_core::dataset::FrictionDataset;
use greybox_core::plot::{lines, Line};
use greybox_core::provenance::Provenance;
use greybox_recording::ChannelMap;
use std::path::{Path, PathBuf};

/// At most this many recordings are drawn (one figure each).
const MAX_RECORDINGS: usize = 24;
/// Points per drawn force trace (min/max per bucket keep the peaks).
const TRACE_POINTS: usize = 1500;

pub fn section(dir: &Path, found: &Found, w: &mut Ctx) -> Option<Section> {
    let mut s = Section::new("campaign", "Campaign");
    for sheet in &found.run_sheets {
        let r = run_sheet(dir, sheet, w);
        s.add_from(sheet, r, w);
    }
    let mut drawn = 0;
    for ds in &found.datasets {
        match recordings_of(ds, w) {
            Ok(files) if !files.is_empty() => {
                s.heading(format!("Recordings identified into {}", shown(dir, ds)));
                let map = channel_map(found, w);
                recordings(dir, ds, &files, map, &mut drawn, &mut s, w);
            }
            Ok(_) => {}
            Err(e) => s.push(w.note(ds, &e)),
        }
    }
    (!s.blocks.is_empty()).then_some(s)
}

/// The channel map of the study file beside a run sheet (`greybox plan` copies it there),
/// else the default one.
fn channel_map(found: &Found, w: &mut Ctx) -> ChannelMap {
    found
        .run_sheets
        .iter()
        .filter_map(|p| p.parent().map(|d| d.join("study.toml")))
        .find(|p| p.is_file())
        .filter(|p| w.admit(p).is_ok())
        .and_then(|p| greybox_pipeline::Study::load(&p).ok())
        .map(|s| s.recording)
        .unwrap_or_default()
}

/// The run sheet: one row per pin (load, steps, speeds, duration), and the whole sheet
/// folded away below it.
fn run_sheet(dir: &Path, p: &Path, w: &mut Ctx) -> Result<Vec<Block>> {
    let mut rdr = w.csv(p)?;
    let header: Vec<String> = rdr.headers()?.iter().map(str::to_string).collect();
    let hdr: Vec<&str> = header.iter().map(String::as_str).collect();
    let name = shown(dir, p);
    let mut full = Table::new(&format!("Run sheet ({name})"), &hdr);
    let col = |c: &str| hdr.iter().position(|h| *h == c);
    let (cp, cf, cv, ce) = (
        col("pin"),
        col("normal_force_N"),
        col("sliding_velocity_m_per_min"),
        col("pin_end_s"),
    );
    // pin → (force N, steps, min speed, max speed, end s)
    let mut pins: Vec<(String, f64, usize, f64, f64, f64)> = Vec::new();
    for (k, r) in rdr.records().enumerate() {
        let r = r.with_context(|| format!("line {}", k + 2))?;
        // A column the sheet lacks stays NaN (shown as such); a cell that is there must be
        // a finite number.
        let cell = |c: Option<usize>| -> Result<f64> {
            let Some(c) = c else {
                return Ok(f64::NAN);
            };
            let v = r.get(c).unwrap_or("").trim();
            match v.parse::<f64>() {
                Ok(x) if x.is_finite() => Ok(x),
                _ => anyhow::bail!(
                    "line {}: {} is '{v}', expected a finite number",
                    k + 2,
                    hdr[c]
                ),
            }
        };
        let pin = cp.and_then(|c| r.get(c)).unwrap_or("").to_string();
        let v = cell(cv)?;
        match pins.last_mut() {
            Some(last) if last.0 == pin => {
                last.2 += 1;
                last.3 = last.3.min(v);
                last.4 = last.4.max(v);
            }
            _ => pins.push((pin, cell(cf)?, 1, v, v, cell(ce)?)),
        }
        let mut row = Vec::with_capacity(r.len());
        for (c, text) in r.iter().enumerate() {
            row.push(match text.trim().parse::<f64>() {
                Ok(x) if !x.is_finite() => anyhow::bail!(
                    "line {}: {} is '{text}', expected a finite number",
                    k + 2,
                    hdr.get(c).unwrap_or(&"a column past the header")
                ),
                Ok(x) if text.contains('.') => num(x, 6),
                _ => text.to_string(),
            });
        }
        full.row(row);
    }
    let mut per_pin = Table::new(
        &format!("Plan: one pin per load ({name})"),
        &[
            "pin",
            "normal force (N)",
            "steps",
            "sliding velocity (m/min)",
            "duration (s)",
        ],
    );
    for (pin, f, n, vlo, vhi, end) in pins {
        per_pin.row(vec![
            pin,
            num(f, 4),
            n.to_string(),
            format!("{} … {}", num(vlo, 3), num(vhi, 3)),
            num(end, 4),
        ]);
    }
    Ok(vec![
        Block::Table(per_pin),
        Block::Details {
            summary: format!("The whole run sheet: {} steps", full.rows.len()),
            blocks: vec![Block::Table(full)],
        },
    ])
}

/// The recordings a dataset was identified from, in the order given (its provenance).
fn recordings_of(dataset: &Path, w: &mut Ctx) -> Result<Vec<PathBuf>> {
    let prov = Provenance::path_beside(dataset);
    if !prov.is_file() {
        return Ok(Vec::new());
    }
    w.admit(&prov)?;
    let p = Provenance::read(&prov)?;
    let base = dataset.parent().unwrap_or(Path::new("."));
    Ok(p.inputs
        .iter()
        .filter(|i| i.role == "recordings")
        .map(|i| {
            let path = PathBuf::from(&i.path);
            if path.is_absolute() || path.exists() {
                path
            } else {
                // paths recorded relative to where the stage ran: the study directory
                // (greybox demo) or the dataset's own folder
                let beside = base.join(&path);
                if beside.exists() {
                    beside
                } else {
                    study_root(dataset).join(&path)
                }
            }
        })
        .collect())
}

/// The directory a path-relative provenance refers to: the nearest ancestor with a
/// `provenance.json` (the demo's root), else the dataset's folder.
fn study_root(dataset: &Path) -> PathBuf {
    let mut d = dataset.parent();
    while let Some(dir) = d {
        if dir.join("provenance.json").is_file() {
            return dir.to_path_buf();
        }
        d = dir.parent();
    }
    dataset.parent().unwrap_or(Path::new(".")).to_path_buf()
}

fn recordings(
    dir: &Path,
    dataset: &Path,
    files: &[PathBuf],
    map: ChannelMap,
    drawn: &mut usize,
    s: &mut Section,
    w: &mut Ctx,
) {
    let ds = match w
        .admit(dataset)
        .and_then(|()| Ok(FrictionDataset::read_csv(dataset)?))
    {
        Ok(d) => d,
        Err(e) => {
            s.push(w.note(dataset, &e));
            return;
        }
    };
    let mut pins: Vec<u32> = ds.records.iter().map(|r| r.pin).collect();
    pins.sort_unstable();
    pins.dedup();
    let paired = pins.len() == files.len();
    if !paired {
        s.text(format!(
            "{} recordings but {} pins in the dataset: the steady windows are not shaded.",
            files.len(),
            pins.len()
        ));
    }
    let mut figures = Vec::new();
    for (k, f) in files.iter().enumerate() {
        if *drawn >= MAX_RECORDINGS {
            s.text(format!(
                "Only the first {MAX_RECORDINGS} recordings are drawn."
            ));
            break;
        }
        let pin = paired.then(|| pins[k]);
        match w
            .admit(f)
            .and_then(|()| recording_figure(dir, f, &ds, pin, &map))
        {
            Ok(b) => figures.push(b),
            Err(e) => figures.push(w.note(f, &e)),
        }
        *drawn += 1;
    }
    s.push(Block::Row(figures));
}

/// `(x, y)` reduced to about `n` points: per bucket its minimum and maximum, in time order.
fn envelope(x: &[f64], y: &[f64], n: usize) -> (Vec<f64>, Vec<f64>) {
    let per = (x.len() / (n / 2).max(1)).max(1);
    let (mut xo, mut yo) = (Vec::new(), Vec::new());
    for (cx, cy) in x.chunks(per).zip(y.chunks(per)) {
        let (imin, imax) = cy.iter().enumerate().fold((0, 0), |(a, b), (i, v)| {
            (
                if *v < cy[a] { i } else { a },
                if *v > cy[b] { i } else { b },
            )
        });
        for i in if imin <= imax {
            [imin, imax]
        } else {
            [imax, imin]
        } {
            xo.push(cx[i]);
            yo.push(cy[i]);
        }
    }
    (xo, yo)
}

fn recording_figure(
    dir: &Path,
    f: &Path,
    ds: &FrictionDataset,
    pin: Option<u32>,
    map: &ChannelMap,
) -> Result<Block> {
    let r = greybox_recording::readers::read_recording(f, map)?;
    let (tn, fnorm) = envelope(&r.time_s, &r.normal_n, TRACE_POINTS);
    let (tt, ftan) = envelope(&r.time_s, &r.tangential_n, TRACE_POINTS);
    let bands: Vec<(f64, f64, &str)> = ds
        .records
        .iter()
        .filter(|rec| Some(rec.pin) == pin)
        .enumerate()
        .map(|(k, rec)| {
            (
                rec.plateau_start_s,
                rec.plateau_end_s,
                if k == 0 { "steady windows" } else { "" },
            )
        })
        .collect();
    let title = match pin {
        Some(p) => format!("Pin {p}: forces over time"),
        None => "Forces over time".to_string(),
    };
    let svg = lines(
        &title,
        "time after the trigger (s)",
        "force (N)",
        &[
            Line {
                label: "normal force F_N",
                colour: "#1f77b4",
                x: &tn,
                y: &fnorm,
            },
            Line {
                label: "friction force F_t",
                colour: "#d62728",
                x: &tt,
                y: &ftan,
            },
        ],
        false,
        &bands,
    );
    Ok(Block::Figure {
        svg: super::page::inline_svg(&svg).unwrap_or(svg),
        caption: format!(
            "{}: {} samples; shaded: the {} steady windows averaged into μ_app",
            shown(dir, f),
            r.time_s.len(),
            bands.len()
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    #[test]
    fn the_envelope_keeps_every_bucket_extreme_in_time_order() {
        let x: Vec<f64> = (0..1000).map(|i| i as f64).collect();
        let mut y = vec![0.0; 1000];
        y[500] = 9.0;
        y[501] = -9.0;
        let (xo, yo) = envelope(&x, &y, 100);
        assert!(xo.len() <= 102, "{}", xo.len());
        assert!(yo.contains(&9.0) && yo.contains(&-9.0));
        assert!(xo.windows(2).all(|w| w[0] <= w[1]));
    }
}
