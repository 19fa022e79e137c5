//! Stage 2: identify a campaign — recordings from any rig to apparent friction coefficients
//! per plateau (the dataset), with what was found per file and how it matched the plan.

use crate::output::provenance;
use crate::study::Study;
use anyhow::{bail, Context, Result};
use greybox_core::dataset::FrictionDataset;
use greybox_recording::readers::{read_recording, RecordingFormat};
use greybox_recording::Recording;
use greybox_tribo::campaign::{
    expected_from_plan, match_segments, segment_recordings, Campaign, ExpectedStep, FileReport,
    Identification,
};
use greybox_tribo::plan::Plan;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// Natural order: digit runs compare as numbers (`pin2` before `pin10`).
fn natural_key(name: &str) -> Vec<(u8, u64, String)> {
    let mut out = Vec::new();
    let mut chars = name.chars().peekable();
    while let Some(&c) = chars.peek() {
        if c.is_ascii_digit() {
            let mut n = String::new();
            while let Some(&d) = chars.peek().filter(|d| d.is_ascii_digit()) {
                n.push(d);
                chars.next();
            }
            out.push((0, n.parse().unwrap_or(u64::MAX), n));
        } else {
            let mut t = String::new();
            while let Some(&d) = chars.peek().filter(|d| !d.is_ascii_digit()) {
                t.push(d.to_ascii_lowercase());
                chars.next();
            }
            out.push((1, 0, t));
        }
    }
    out
}

/// Resolve the recording files: explicit files as given; a directory gives `pinNN.<ext>`
/// for every pin of the plan when they all exist, else every recording file in it (of
/// `format`, if given) in natural order.
pub fn recording_files(
    paths: &[PathBuf],
    format: Option<RecordingFormat>,
    pins: Option<usize>,
) -> Result<Vec<PathBuf>> {
    let mut files = Vec::new();
    for p in paths {
        if !p.is_dir() {
            files.push(p.clone());
            continue;
        }
        if let Some(pins) = pins {
            let ext = format.unwrap_or(RecordingFormat::Csv).extension();
            let named: Vec<PathBuf> = (1..=pins)
                .map(|k| p.join(format!("pin{k:02}.{ext}")))
                .collect();
            if named.iter().all(|f| f.is_file()) {
                files.extend(named);
                continue;
            }
        }
        let mut found: Vec<PathBuf> = std::fs::read_dir(p)
            .with_context(|| format!("cannot read directory {}", p.display()))?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|f| f.is_file())
            .filter(|f| match (RecordingFormat::of_path(f), format) {
                (Some(have), Some(want)) => have == want,
                (Some(_), None) => true,
                (None, _) => false,
            })
            .filter(|f| {
                // greybox's own side files are not recordings
                let n = f.file_name().and_then(|n| n.to_str()).unwrap_or("");
                n != "ground_truth.csv" && n != "run_sheet.csv"
            })
            .collect();
        found.sort_by_key(|f| {
            natural_key(
                &f.file_name()
                    .map(|n| n.to_string_lossy().to_string())
                    .unwrap_or_default(),
            )
        });
        if found.is_empty() {
            bail!(
                "{}: no recording files (.csv, .txt, .tsv, .dat, .xlsx, .xls, .ods, .tdms)",
                p.display()
            );
        }
        files.extend(found);
    }
    Ok(files)
}

/// Identified against true COFs (a virtual rig's ground truth).
#[derive(Debug, Clone, Serialize)]
pub struct TruthComparison {
    pub max_abs_error: f64,
    pub mean_abs_error: f64,
    pub plateaus: usize,
}

/// Compare identified COFs to a ground truth CSV written by `greybox synth`.
pub fn compare_with_truth(ds: &FrictionDataset, truth_csv: &Path) -> Result<TruthComparison> {
    let mut rdr =
        greybox_core::input::data_csv(truth_csv, "ground truth", &csv::ReaderBuilder::new())?;
    let header = rdr.headers()?.clone();
    let col = |name: &str| {
        header
            .iter()
            .position(|h| h == name)
            .with_context(|| format!("{}: missing column '{name}'", truth_csv.display()))
    };
    let (ip, is, ic) = (col("pin")?, col("step")?, col("cof_true")?);
    let mut truth = std::collections::HashMap::new();
    for (k, r) in rdr.records().enumerate() {
        let r = r.with_context(|| format!("{}: line {}", truth_csv.display(), k + 2))?;
        let parse = |i: usize| -> Result<f64> {
            r[i].parse::<f64>().with_context(|| {
                format!(
                    "{}: line {}: bad number '{}'",
                    truth_csv.display(),
                    k + 2,
                    &r[i]
                )
            })
        };
        truth.insert((parse(ip)? as u32, parse(is)? as u32), parse(ic)?);
    }
    let mut errs = Vec::new();
    for rec in &ds.records {
        let t = truth
            .get(&(rec.pin, rec.step))
            .with_context(|| format!("no ground truth for pin {} step {}", rec.pin, rec.step))?;
        errs.push((rec.cof_apparent - t).abs());
    }
    Ok(TruthComparison {
        max_abs_error: errs.iter().cloned().fold(0.0, f64::max),
        mean_abs_error: errs.iter().sum::<f64>() / errs.len() as f64,
        plateaus: errs.len(),
    })
}

/// What identification found and wrote.
#[derive(Debug, Clone, Serialize)]
pub struct IdentifySummary {
    pub dataset: String,
    pub plateaus: usize,
    pub non_stationary: usize,
    pub pressure_convention: String,
    /// The per-cycle file of reciprocating tests (`<dataset>.cycles.csv`), when any.
    pub cycles: Option<String>,
    #[serde(flatten)]
    pub identification: Identification,
    pub truth: Option<TruthComparison>,
}

/// Called with the segments found per file and the inspect directory (see
/// [`IdentifyOutput::on_segments`]).
pub type SegmentsHook<'a> = &'a dyn Fn(&[FileReport], &Path);

/// What identification is matched against.
#[derive(Debug, Clone)]
pub enum Expectation {
    /// A greybox plan with timing (also gives its steps and track radius).
    Plan(Plan),
    /// Steps without timing.
    Steps(Vec<ExpectedStep>),
    None,
}

/// Where identification writes: the dataset, optional inspect plots, and the inputs besides
/// the recordings (study, step list) that its provenance records.
pub struct IdentifyOutput<'a> {
    pub dataset: &'a Path,
    pub inspect_dir: Option<&'a Path>,
    /// Called with the segments found per file and the inspect directory, once the
    /// recordings are segmented and before they are matched to the plan (so that a caller
    /// can show them even when matching fails).
    pub on_segments: Option<SegmentsHook<'a>>,
    pub side_inputs: &'a [(&'a str, &'a Path)],
}

/// Read all recordings and identify them; writes the dataset.
pub fn identify(
    study: &Study,
    expect: &Expectation,
    files: &[PathBuf],
    track_radii_mm: &[f64],
    o: &IdentifyOutput,
) -> Result<(FrictionDataset, Identification)> {
    let (out, inspect_dir, side_inputs) = (o.dataset, o.inspect_dir, o.side_inputs);
    let inputs: Vec<(&str, &Path)> = files.iter().map(|f| ("recordings", f.as_path())).collect();
    greybox_core::outputs::check_file_output(out, "out", &inputs)?;
    let recs = read_recordings(files, study)?;
    let steps;
    let (expected, plan) = match expect {
        Expectation::Plan(p) => {
            steps = expected_from_plan(p);
            (Some(steps.as_slice()), Some(p))
        }
        Expectation::Steps(s) => (Some(s.as_slice()), None),
        Expectation::None => (None, None),
    };
    let radii: Vec<f64> = if track_radii_mm.is_empty() {
        study.recording.track_radius_mm.clone()
    } else {
        track_radii_mm.to_vec()
    };
    let campaign = Campaign {
        expected,
        plan,
        contact: &study.contact,
        cfg: &study.identify,
        track_radius_mm: &radii,
    };
    let mut files_found = segment_recordings(&recs, &campaign)?;
    if let Some(dir) = inspect_dir {
        write_inspect_plots(&recs, &files_found, dir)?;
        if let Some(show) = o.on_segments {
            show(&files_found, dir);
        }
    }
    let (dataset, matching) = match_segments(&mut files_found, &campaign)
        .map_err(|e| anyhow::anyhow!("{e}\n  {}", refusal_lines(&files_found).join("\n  ")))?;
    if let Some(dir) = inspect_dir {
        // again, now that each segment knows its planned step (or that it has none)
        write_inspect_plots(&recs, &files_found, dir)?;
    }
    let id = Identification {
        dataset,
        files: files_found,
        matching,
    };
    if id.dataset.records.is_empty() {
        bail!(
            "no plateau was identified in any recording\n  {}",
            refusal_lines(&id.files).join("\n  ")
        );
    }
    write_dataset(&id, out, &inputs, side_inputs)?;
    Ok((id.dataset.clone(), id))
}

/// Every recording read with the study's recording settings, interruptible between files.
fn read_recordings(files: &[PathBuf], study: &Study) -> Result<Vec<Recording>> {
    let progress =
        greybox_core::progress::task("read recordings", Some(files.len() as u64), "files");
    let recs = files
        .iter()
        .map(|f| {
            greybox_core::interrupt::check()?;
            let r = read_recording(f, &study.recording);
            progress.inc(1);
            r
        })
        .collect::<Result<Vec<_>, _>>()?;
    progress.finish("done");
    Ok(recs)
}

/// What a refusal lists, each line after its file's name: the coverage line (as `--inspect`
/// prints it), every segment — those with a steady window too — with its fate, the notes,
/// warnings and dropped sliding time.
fn refusal_lines(files: &[FileReport]) -> Vec<String> {
    files
        .iter()
        .flat_map(|f| {
            std::iter::once(format!("coverage: {}", f.coverage.line()))
                .chain(f.segment_lines())
                .chain(f.notes.iter().chain(&f.warnings).cloned())
                .chain(f.coverage.dropped_notes())
                .map(move |n| format!("{}: {n}", f.source))
        })
        .collect()
}

/// Writes the dataset to `out`, with its provenance record and, for reciprocating tests,
/// the cycles file beside it: all staged first, then put in place together.
fn write_dataset(
    id: &Identification,
    out: &Path,
    inputs: &[(&str, &Path)],
    side_inputs: &[(&str, &Path)],
) -> Result<()> {
    // reciprocating tests: the per-cycle evolution beside the dataset, checked before either
    // is written
    let cycles = if crate::identify_cycles::any_reciprocating(&id.files) {
        let path = crate::identify_cycles::cycles_path(out);
        greybox_core::outputs::check_file_output(
            &path,
            "the cycles file beside the dataset",
            inputs,
        )?;
        Some((path, crate::identify_cycles::cycles_csv(&id.files)?))
    } else {
        None
    };
    greybox_core::interrupt::check()?;
    let mut all_inputs = inputs.to_vec();
    all_inputs.extend_from_slice(side_inputs);
    // every file written in full before any is put in place, the provenance record before
    // the dataset: a full disk leaves neither new, never a dataset without its provenance
    let mut staged = vec![provenance(&all_inputs)?.stage_beside(out)?];
    if let Some((path, text)) = cycles {
        staged.push(greybox_core::atomic::stage(&path, |w| {
            w.write_all(text.as_bytes())
        })?);
    }
    staged.push(id.dataset.stage_csv(out)?);
    greybox_core::atomic::commit_together(staged)?;
    Ok(())
}

/// Options of [`identify_campaign`]: the recordings, what they are matched against and
/// where the dataset goes.
#[derive(Debug, Clone)]
pub struct IdentifyOptions {
    /// Recording files, or directories (see [`recording_files`]).
    pub recordings: Vec<PathBuf>,
    /// Which files to pick from a directory (`None`: every supported format).
    pub format: Option<RecordingFormat>,
    /// The plan or step list the segments are matched to.
    pub expect: Expectation,
    /// Track radius per segment for rpm speed channels, mm (empty: the study's
    /// `[recording] track_radius_mm`).
    pub track_radii_mm: Vec<f64>,
    /// The dataset CSV written.
    pub dataset: PathBuf,
    /// Write an SVG per recording with the steady windows shaded here.
    pub inspect_dir: Option<PathBuf>,
    /// A ground truth CSV (`greybox synth`) to compare the identified COFs with.
    pub truth: Option<PathBuf>,
    /// Further inputs recorded in the dataset's provenance (role, path), e.g. the study file.
    pub side_inputs: Vec<(String, PathBuf)>,
}

impl IdentifyOptions {
    /// Identify `recordings` (files or directories) into the dataset CSV `dataset`, with
    /// loads and velocities as measured (no plan; see [`IdentifyOptions::with_plan`]).
    pub fn new(recordings: Vec<PathBuf>, dataset: impl Into<PathBuf>) -> Self {
        IdentifyOptions {
            recordings,
            format: None,
            expect: Expectation::None,
            track_radii_mm: Vec::new(),
            dataset: dataset.into(),
            inspect_dir: None,
            truth: None,
            side_inputs: Vec::new(),
        }
    }
    /// Match the segments to the steps of `plan` (a greybox plan with timing).
    pub fn with_plan(mut self, plan: Plan) -> Self {
        self.expect = Expectation::Plan(plan);
        self
    }
}

/// The dataset and what identification found.
pub struct IdentifyResult {
    pub dataset: FrictionDataset,
    pub summary: IdentifySummary,
}

/// Identify a campaign: resolve the recording files, segment, match and write the dataset;
/// compare with a ground truth when one is given. `on_segments` as in [`IdentifyOutput`].
///
/// A small campaign on the virtual rig, identified against its plan and ground truth:
///
/// ```
/// use greybox_pipeline::identify::{identify_campaign, IdentifyOptions};
/// use greybox_pipeline::{synth::synth, Study};
/// use greybox_recording::readers::RecordingFormat;
/// let dir = tempfile::tempdir().unwrap();
/// let mut study = Study::parse(greybox_pipeline::study::DEMO_STUDY, "demo").unwrap();
/// study.plan.normal_force_count = greybox_tribo::plan::PinCount::of(2);
/// study.plan.velocity_count = greybox_tribo::plan::VelocityCount::of(3);
/// let rec = dir.path().join("recordings");
/// synth(&study, &[RecordingFormat::Csv], &rec, false, &[]).unwrap();
/// let mut o = IdentifyOptions::new(vec![rec.clone()], dir.path().join("dataset.csv"))
///     .with_plan(study.plan.build().unwrap());
/// o.truth = Some(rec.join("ground_truth.csv"));
/// let r = identify_campaign(&study, &o, None).unwrap();
/// assert_eq!(r.dataset.records.len(), 6);
/// assert!(r.summary.truth.unwrap().max_abs_error < 0.01);
/// ```
pub fn identify_campaign(
    study: &Study,
    o: &IdentifyOptions,
    on_segments: Option<SegmentsHook>,
) -> Result<IdentifyResult> {
    if let Some(r) = o
        .track_radii_mm
        .iter()
        .find(|r| !(r.is_finite() && **r > 0.0))
    {
        let why = format!("every radius must be positive, got {r}");
        return Err(greybox_core::setting::refused("identify", "track_radii_mm", why).into());
    }
    let side_inputs: Vec<(&str, &Path)> = o
        .side_inputs
        .iter()
        .map(|(r, p)| (r.as_str(), p.as_path()))
        .collect();
    greybox_core::outputs::check_file_output(&o.dataset, "out", &side_inputs)?;
    let pins = match &o.expect {
        Expectation::Plan(p) => Some(p.pins.len()),
        _ => None,
    };
    let files = recording_files(&o.recordings, o.format, pins)?;
    let (ds, id) = identify(
        study,
        &o.expect,
        &files,
        &o.track_radii_mm,
        &IdentifyOutput {
            dataset: &o.dataset,
            inspect_dir: o.inspect_dir.as_deref(),
            on_segments,
            side_inputs: &side_inputs,
        },
    )?;
    let truth = o
        .truth
        .as_deref()
        .map(|p| compare_with_truth(&ds, p))
        .transpose()?;
    let summary = IdentifySummary {
        dataset: o.dataset.display().to_string(),
        plateaus: ds.records.len(),
        non_stationary: ds.records.iter().filter(|r| !r.stationary).count(),
        pressure_convention: study.contact.convention.name().to_string(),
        cycles: crate::identify_cycles::any_reciprocating(&id.files).then(|| {
            crate::identify_cycles::cycles_path(&o.dataset)
                .display()
                .to_string()
        }),
        identification: id,
        truth,
    };
    Ok(IdentifyResult {
        dataset: ds,
        summary,
    })
}

/// A segment's label in the inspect plot: its number, and once matched its planned step
/// (`3 → p1 s2`) or, where matching left it out, `extra`.
fn segment_label(g: &greybox_tribo::campaign::SegmentReport, matched_any: bool) -> String {
    match (g.matched, g.cof.is_some(), matched_any) {
        (Some((p, k)), _, _) => format!("{} → p{p} s{k}", g.index),
        (None, true, true) => format!("{} extra", g.index),
        (None, true, false) => format!("{}", g.index),
        (None, false, _) => format!("{} (no steady part)", g.index),
    }
}

/// One SVG per recording: μ = F_t/F_N and F_N / max F_N over time, steady windows shaded.
fn write_inspect_plots(recs: &[Recording], found: &[FileReport], dir: &Path) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    for (rec, f) in recs.iter().zip(found) {
        let n = rec.len();
        let step = (n / 3000).max(1);
        let fmax = rec
            .normal_n
            .iter()
            .fold(0.0f64, |m, v| m.max(v.abs()))
            .max(1e-12);
        let sign = if f.tangential_sign_flipped { -1.0 } else { 1.0 };
        let (mut t, mut mu, mut fnr) = (Vec::new(), Vec::new(), Vec::new());
        for c in (0..n).step_by(step) {
            let e = (c + step).min(n);
            let fn_m = rec.normal_n[c..e].iter().sum::<f64>() / (e - c) as f64;
            let ft_m = rec.tangential_n[c..e].iter().sum::<f64>() / (e - c) as f64;
            t.push(rec.time_s[c]);
            fnr.push(fn_m / fmax);
            mu.push(if fn_m.abs() > 0.02 * fmax {
                sign * ft_m / fn_m
            } else {
                0.0
            });
        }
        let matched_any = f.segments.iter().any(|g| g.matched.is_some());
        let labels: Vec<String> = f
            .segments
            .iter()
            .map(|g| segment_label(g, matched_any))
            .collect();
        let mut bands: Vec<(f64, f64, &str)> = f
            .segments
            .iter()
            .zip(&labels)
            .filter_map(|(g, l)| Some((g.steady_start_s?, g.steady_end_s?, l.as_str())))
            .collect();
        // weakly determined boundaries: a band of ± their uncertainty around each
        let unsure: Vec<(f64, f64, String)> = f
            .segments
            .iter()
            .filter_map(|g| Some((g.start_s, g.end_s, g.boundary_uncertainty_s?)))
            .flat_map(|(a, b, u)| [a, b].map(|x| (x - u, x + u, format!("?±{u:.2}s"))))
            .collect();
        bands.extend(unsure.iter().map(|(a, b, l)| (*a, *b, l.as_str())));
        let name = Path::new(&f.source)
            .file_name()
            .map(|s| s.to_string_lossy().to_string())
            .unwrap_or_else(|| "recording".into());
        let svg = greybox_core::plot::lines(
            &format!(
                "{name}: steady windows shaded, uncertain boundaries as ?±s ({})",
                f.segmentation
            ),
            "time [s]",
            "F_t/F_N [-] and F_N/max F_N [-]",
            &[
                greybox_core::plot::Line {
                    label: "F_t/F_N",
                    colour: "#1f4e9c",
                    x: &t,
                    y: &mu,
                },
                greybox_core::plot::Line {
                    label: "F_N/max",
                    colour: "#b2182b",
                    x: &t,
                    y: &fnr,
                },
            ],
            false,
            &bands,
        );
        greybox_core::atomic::write_string_atomic(&dir.join(format!("{name}.svg")), &svg)?;
        crate::identify_cycles::write_cycles_plot(f, dir, &name)?;
    }
    Ok(())
}
