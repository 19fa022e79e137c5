//! The friction dataset: one row per (pin, velocity plateau), and its CSV schema.
//!
//! Columns (units in the names): `pin`, `step`, `normal_force_N` (measured: the mean over
//! the steady part), `normal_force_planned_N` (empty without a plan), `sliding_velocity_m_per_min`, `hertz_pressure_MPa`
//! (of the measured force),
//! `pressure_convention`, `cof_apparent`, `cof_apparent_std`, `cof_apparent_ci95` (half-width
//! of μ's 95 % confidence interval), `n_samples`, `plateau_start_s`, `plateau_end_s`,
//! `cof_trend_per_s`, `stationary`, `flags`, `label_evidence` (what placed the row on its
//! step, [`label_evidence`]) and, once the ploughing correction has run, `cof_adhesive`.
//!
//! `cof_apparent_ci95` and `label_evidence` are optional when reading (files written before
//! they existed), empty fields reading as absent.
//!
//! Files written before the measured load became `normal_force_N` (they have
//! `normal_force_measured_N` beside a planned `normal_force_N`) are still read, with the
//! columns given their meaning.

use crate::csvutil::{csv_error, parse_f64, parse_u64, record_line, Header};
use crate::{units, Error, Result, SourcePos};
use serde::{Deserialize, Serialize};
use std::io::Write;
use std::path::Path;

/// Which Hertz pressure a dataset's `hertz_pressure_MPa` column holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum PressureConvention {
    /// Textbook maximum (central) Hertz pressure p0 (Johnson 1985, ch. 4).
    #[default]
    TextbookMax,
    /// Textbook mean pressure F / (π a²) = (2/3) p0.
    TextbookMean,
    /// The seed article's eq. 7 as evaluated there: (1/π)·cbrt(3 F E*² / (2 r²)) = p0 / 4^(1/3).
    ArticleEq7,
}

crate::choice!(
    PressureConvention,
    "convention",
    [
        TextbookMax => "textbook-max",
        TextbookMean => "textbook-mean",
        ArticleEq7 => "article-eq7",
    ],
    text
);

impl PressureConvention {
    /// The convention's name (its [`Choice`](crate::choice::Choice) name).
    pub fn name(self) -> &'static str {
        crate::choice::Choice::name(self)
    }
    /// The convention named `s` (surrounding blanks ignored), if any.
    pub fn parse(s: &str) -> Option<Self> {
        <Self as crate::choice::Choice>::parse_choice(s.trim()).ok()
    }
}

/// Quality flags raised while identifying one plateau. A flag is raised only where it changes
/// what a user should do with the row (docs/recordings.md, "Flags"): how sure μ is, is the
/// `cof_apparent_ci95` column, not a flag.
pub mod flags {
    /// μ drifts within the plateau more than the tolerance (and four standard errors): the
    /// value depends on the window; the interval is widened by the drift.
    pub const TREND: &str = "trend";
    /// Stick-slip: low-frequency oscillation of μ above the threshold.
    pub const STICK_SLIP: &str = "stick-slip";
    /// The end of the spindle ramp could not be confirmed from the signal.
    pub const RAMP_UNCONFIRMED: &str = "ramp-unconfirmed";
    /// The masked spikes matter: μ with them differs from μ without them by more than the
    /// interval's half-width (the value depends on the spike filter).
    pub const SPIKES_REMOVED: &str = "spikes-removed";
    /// A segment boundary touching this row is weakly determined (the change across it is
    /// comparable to the noise, or the segments contradict the plan's regular timing) AND
    /// its uncertainty reaches into the steady window, moving μ by more than half the
    /// mean-uncertainty tolerance; the identification report gives it in seconds.
    pub const UNCERTAIN_BOUNDARY: &str = "uncertain-boundary";
    /// A linear reciprocating test (ASTM G133): μ is the mean over the steady cycles of the
    /// forward and backward strokes' mid-stroke μ (sign taken by direction).
    pub const RECIPROCATING: &str = "reciprocating";
    /// The file's rows rest on less than the stated share of its sliding time
    /// (`min_steady_share`): most of the recording was run-in, transitions or dropped, as
    /// its coverage line says.
    pub const LOW_COVERAGE: &str = "low-coverage";
    /// The row's plan step rests on the order of the segments alone, where something else
    /// could have happened (an unplanned piece at a file's start, a ramp cut as a step, two
    /// steps merged): neither a step column, a measured speed, a distinct load nor the plan's
    /// timing confirms it.
    pub const LABEL_BY_ORDER: &str = "label-by-order";
    /// The alignment with the plan had another solution within `ambiguity_margin` of the one
    /// taken that puts this segment elsewhere: the evidence cannot decide between them.
    pub const AMBIGUOUS_ALIGNMENT: &str = "ambiguous-alignment";
    /// The signal contradicts the row's step: μ inside the segment holds two levels (a step
    /// change the segmentation did not cut), so its steady window may belong to a neighbour.
    pub const LABEL_CONTRADICTED: &str = "label-contradicted";
}

/// What placed a dataset row on its plan step (the `label_evidence` column), strongest first.
pub mod label_evidence {
    /// The recording's own step column or blocks.
    pub const STEP_COLUMN: &str = "step-column";
    /// The plan's timing: a trigger edge and the plan's step times, or the plan's step
    /// durations cutting a sliding run.
    pub const PLAN_TIMING: &str = "plan-timing";
    /// A measured speed channel matched the planned speed.
    pub const MEASURED_SPEED: &str = "measured-speed";
    /// The measured load matched the planned load, and no other step of the pin has it.
    pub const MEASURED_LOAD: &str = "measured-load";
    /// The segment's duration matched the planned duration (no speed measured, loads alike).
    pub const DURATION: &str = "duration";
    /// The order of the segments alone.
    pub const ORDER: &str = "order";
    /// Every value, for readers.
    pub const ALL: [&str; 6] = [
        STEP_COLUMN,
        PLAN_TIMING,
        MEASURED_SPEED,
        MEASURED_LOAD,
        DURATION,
        ORDER,
    ];
}

/// One identified friction coefficient (SI units).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct FrictionRecord {
    pub pin: u32,
    pub step: u32,
    /// Measured normal force: the mean over the plateau's steady part, N.
    pub normal_force_n: f64,
    /// The plan's normal force for this step, N (None without a plan).
    pub normal_force_planned_n: Option<f64>,
    /// Planned sliding velocity, m/s.
    pub sliding_velocity_m_s: f64,
    /// Hertz pressure of the measured force under `pressure_convention`, Pa.
    pub hertz_pressure_pa: f64,
    pub pressure_convention: PressureConvention,
    /// Mean of F_t/F_N over the plateau.
    pub cof_apparent: f64,
    /// Sample standard deviation of F_t/F_N over the plateau.
    pub cof_apparent_std: f64,
    /// Half-width of the 95 % confidence interval of `cof_apparent`: the steady window's
    /// standard error under serial correlation times Student's t at its effective sample
    /// size, widened by μ's change when the window's ends move by their boundary's
    /// uncertainty (None: a file written before intervals were reported).
    pub cof_apparent_ci95: Option<f64>,
    pub n_samples: u64,
    /// Plateau used, seconds after the recording trigger.
    pub plateau_start_s: f64,
    pub plateau_end_s: f64,
    /// Linear trend of μ within the plateau, 1/s.
    pub cof_trend_per_s: f64,
    pub stationary: bool,
    pub flags: Vec<String>,
    /// What placed the row on its plan step ([`label_evidence`]; None: a file written before
    /// labels stated their evidence).
    pub label_evidence: Option<String>,
    /// Adhesive COF after the ploughing correction, if computed.
    pub cof_adhesive: Option<f64>,
}

/// A friction dataset: the records in campaign order.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct FrictionDataset {
    pub records: Vec<FrictionRecord>,
}

const COLUMNS: [&str; 18] = [
    "pin",
    "step",
    "normal_force_N",
    "normal_force_planned_N",
    "sliding_velocity_m_per_min",
    "hertz_pressure_MPa",
    "pressure_convention",
    "cof_apparent",
    "cof_apparent_std",
    "cof_apparent_ci95",
    "n_samples",
    "plateau_start_s",
    "plateau_end_s",
    "cof_trend_per_s",
    "stationary",
    "flags",
    "label_evidence",
    "cof_adhesive",
];
/// Columns a file may lack: the plan's load (no plan), the interval and the label's evidence
/// (files written before they were reported), the adhesive μ (no ploughing correction yet).
const OPTIONAL: [&str; 4] = [
    "normal_force_planned_N",
    "cof_apparent_ci95",
    "label_evidence",
    "cof_adhesive",
];
/// The measured-load column of files written before `normal_force_N` became the measured load.
const LEGACY_MEASURED: &str = "normal_force_measured_N";

impl FrictionDataset {
    /// Write the dataset CSV atomically. `cof_adhesive` is written only if every record has it.
    pub fn write_csv(&self, path: &Path) -> Result<()> {
        self.stage_csv(path)?.commit()
    }

    /// [`Self::write_csv`] written in full beside `path` but not yet in place
    /// ([`crate::atomic::Staged`]), to be committed together with its provenance record.
    pub fn stage_csv(&self, path: &Path) -> Result<crate::atomic::Staged> {
        self.check_finite()?;
        let with_adhesive =
            !self.records.is_empty() && self.records.iter().all(|r| r.cof_adhesive.is_some());
        crate::atomic::stage(path, |w| self.write_csv_to(w, with_adhesive))
    }

    /// Every number of every record finite: a dataset that [`FrictionDataset::read_csv`]
    /// would refuse is never written (a rig export with a speed of 10³⁰⁸ rpm gives an
    /// infinite sliding velocity).
    pub fn check_finite(&self) -> Result<()> {
        for r in &self.records {
            let values = [
                ("normal_force_N", r.normal_force_n),
                (
                    "normal_force_planned_N",
                    r.normal_force_planned_n.unwrap_or(0.0),
                ),
                ("sliding_velocity_m_per_min", r.sliding_velocity_m_s),
                ("hertz_pressure_MPa", r.hertz_pressure_pa),
                ("cof_apparent", r.cof_apparent),
                ("cof_apparent_std", r.cof_apparent_std),
                ("cof_apparent_ci95", r.cof_apparent_ci95.unwrap_or(0.0)),
                ("plateau_start_s", r.plateau_start_s),
                ("plateau_end_s", r.plateau_end_s),
                ("cof_trend_per_s", r.cof_trend_per_s),
                ("cof_adhesive", r.cof_adhesive.unwrap_or(0.0)),
            ];
            if let Some((column, v)) = values.iter().find(|(_, v)| !v.is_finite()) {
                return Err(Error::invalid(
                    "friction dataset",
                    format!(
                        "pin {} step {}: {column} is {v}, not a number: the recording or the settings it was identified with are at fault",
                        r.pin, r.step
                    ),
                ));
            }
        }
        Ok(())
    }

    fn write_csv_to(&self, w: &mut dyn Write, with_adhesive: bool) -> std::io::Result<()> {
        let ncol = if with_adhesive {
            COLUMNS.len()
        } else {
            COLUMNS.len() - 1
        };
        writeln!(w, "{}", COLUMNS[..ncol].join(","))?;
        for r in &self.records {
            write!(
                w,
                "{},{},{},{},{},{},{},{},{},{},{},{:.4},{:.4},{},{},{},{}",
                r.pin,
                r.step,
                r.normal_force_n,
                r.normal_force_planned_n
                    .map_or(String::new(), |f| f.to_string()),
                units::m_per_s_to_m_per_min(r.sliding_velocity_m_s),
                r.hertz_pressure_pa / units::PA_PER_MPA,
                r.pressure_convention.name(),
                r.cof_apparent,
                r.cof_apparent_std,
                r.cof_apparent_ci95.map_or(String::new(), |c| c.to_string()),
                r.n_samples,
                r.plateau_start_s,
                r.plateau_end_s,
                r.cof_trend_per_s,
                r.stationary,
                r.flags.join(";"),
                r.label_evidence.as_deref().unwrap_or_default(),
            )?;
            if with_adhesive {
                write!(w, ",{}", r.cof_adhesive.unwrap_or(f64::NAN))?;
            }
            writeln!(w)?;
        }
        Ok(())
    }

    /// Read a dataset CSV strictly: every required column, finite numbers, positive forces.
    pub fn read_csv(path: &Path) -> Result<Self> {
        let file = crate::input::open(path, "friction dataset", crate::budget::Cap::DataBytes)?;
        Self::read_csv_from(file, &path.display().to_string())
    }

    /// Read dataset CSV text strictly (as [`FrictionDataset::read_csv`]); `source` names the
    /// text in errors.
    pub fn read_csv_from(reader: impl std::io::Read, source: &str) -> Result<Self> {
        let mut rdr = csv::ReaderBuilder::new()
            .has_headers(true)
            .from_reader(reader);
        let header = Header::new(source, rdr.headers().map_err(|e| csv_error(source, e))?);
        let cols = Columns::of(&header)?;
        let mut records = Vec::new();
        for (k, rec) in rdr.records().enumerate() {
            let rec = rec.map_err(|e| csv_error(source, e))?;
            let line = record_line(rec.position(), k as u64 + 2);
            let row = Row {
                rec: &rec,
                cols: &cols,
                source,
                line,
            };
            records.push(row.record()?);
        }
        if records.is_empty() {
            return Err(Error::input(
                SourcePos::file(source),
                "the dataset has no rows",
            ));
        }
        Ok(FrictionDataset { records })
    }
}

/// Where a dataset file's columns are: [`COLUMNS`] (`None` for an absent optional one) and
/// the legacy measured-force column, if the file has it.
struct Columns {
    idx: Vec<Option<usize>>,
    legacy_measured: Option<usize>,
}

impl Columns {
    /// The columns of `header`: every required one present, no unknown one.
    fn of(header: &Header) -> Result<Self> {
        let legacy_measured = header.find(LEGACY_MEASURED);
        let mut known = COLUMNS.to_vec();
        known.push(LEGACY_MEASURED);
        header.reject_unknown(&known)?;
        let idx: Vec<Option<usize>> = COLUMNS
            .iter()
            .map(|c| {
                if OPTIONAL.contains(c) {
                    Ok(header.find(c))
                } else {
                    header.require(c).map(Some)
                }
            })
            .collect::<Result<_>>()?;
        Ok(Columns {
            idx,
            legacy_measured,
        })
    }
}

/// One data row of a dataset file, read field by field (`i`: the index in [`COLUMNS`]).
struct Row<'a> {
    rec: &'a csv::StringRecord,
    cols: &'a Columns,
    source: &'a str,
    line: u64,
}

impl Row<'_> {
    /// The text of required column `i`.
    fn text(&self, i: usize) -> &str {
        &self.rec[self.cols.idx[i].expect("required column resolved")]
    }
    fn f(&self, i: usize) -> Result<f64> {
        parse_f64(self.text(i), self.source, self.line, COLUMNS[i])
    }
    fn u(&self, i: usize) -> Result<u64> {
        parse_u64(self.text(i), self.source, self.line, COLUMNS[i])
    }
    fn pos(&self, i: usize) -> SourcePos {
        SourcePos::file(self.source)
            .line(self.line)
            .field(COLUMNS[i])
    }
    fn positive(&self, i: usize) -> Result<f64> {
        let v = self.f(i)?;
        if v <= 0.0 {
            return Err(Error::input(
                self.pos(i),
                format!("expected a positive value, found {v}"),
            ));
        }
        Ok(v)
    }

    /// The text of optional column `i`, `None` where the file lacks the column or the
    /// field is empty.
    fn optional(&self, i: usize) -> Option<&str> {
        let i = self.cols.idx[i]?;
        let t = self.rec.get(i)?.trim();
        (!t.is_empty()).then_some(t)
    }

    /// The row as a record (fields checked in the order of the file's columns' meaning).
    fn record(&self) -> Result<FrictionRecord> {
        let convention = PressureConvention::parse(self.text(6)).ok_or_else(|| {
            Error::input(
                self.pos(6),
                format!(
                    "unknown pressure convention '{}'; expected one of textbook-max, textbook-mean, article-eq7",
                    self.text(6)
                ),
            )
        })?;
        let stationary = match self.text(14).trim() {
            "true" => true,
            "false" => false,
            other => {
                return Err(Error::input(
                    self.pos(14),
                    format!("expected true or false, found '{other}'"),
                ))
            }
        };
        let flags = self
            .text(15)
            .split(';')
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .map(String::from)
            .collect();
        let cof_apparent_ci95 = match self.optional(9) {
            Some(t) => {
                let v = parse_f64(t, self.source, self.line, COLUMNS[9])?;
                if v < 0.0 {
                    return Err(Error::input(
                        self.pos(9),
                        format!("a confidence interval's half-width is never negative, found {v}"),
                    ));
                }
                Some(v)
            }
            None => None,
        };
        let label_evidence = match self.optional(16) {
            Some(t) if label_evidence::ALL.contains(&t) => Some(t.to_string()),
            Some(t) => {
                return Err(Error::input(
                    self.pos(16),
                    format!(
                        "unknown label evidence '{t}'; expected one of {}",
                        label_evidence::ALL.join(", ")
                    ),
                ))
            }
            None => None,
        };
        let cof_adhesive = match self.cols.idx[17] {
            Some(i) => Some(parse_f64(
                &self.rec[i],
                self.source,
                self.line,
                COLUMNS[17],
            )?),
            None => None,
        };
        let (normal_force_n, normal_force_planned_n) = self.normal_forces()?;
        Ok(FrictionRecord {
            pin: self.u(0)? as u32,
            step: self.u(1)? as u32,
            normal_force_n,
            normal_force_planned_n,
            sliding_velocity_m_s: units::m_per_min_to_m_per_s(self.positive(4)?),
            hertz_pressure_pa: self.positive(5)? * units::PA_PER_MPA,
            pressure_convention: convention,
            cof_apparent: self.f(7)?,
            cof_apparent_std: self.f(8)?,
            cof_apparent_ci95,
            n_samples: self.u(10)?,
            plateau_start_s: self.f(11)?,
            plateau_end_s: self.f(12)?,
            cof_trend_per_s: self.f(13)?,
            stationary,
            flags,
            label_evidence,
            cof_adhesive,
        })
    }

    /// The measured and planned normal forces, N: a legacy file's measured column holds the
    /// measured force and `normal_force_N` the planned one.
    fn normal_forces(&self) -> Result<(f64, Option<f64>)> {
        Ok(match self.cols.legacy_measured {
            Some(i) => {
                let measured = parse_f64(&self.rec[i], self.source, self.line, LEGACY_MEASURED)?;
                if !(measured > 0.0) {
                    return Err(Error::input(
                        SourcePos::file(self.source)
                            .line(self.line)
                            .field(LEGACY_MEASURED),
                        format!("expected a positive value, found {measured}"),
                    ));
                }
                (measured, Some(self.positive(2)?))
            }
            None => {
                let planned = match self.cols.idx[3].map(|i| self.rec[i].trim()) {
                    None | Some("") => None,
                    Some(_) => Some(self.positive(3)?),
                };
                (self.positive(2)?, planned)
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> FrictionDataset {
        FrictionDataset {
            records: vec![FrictionRecord {
                pin: 1,
                step: 1,
                normal_force_n: 149.8,
                normal_force_planned_n: Some(150.0),
                sliding_velocity_m_s: 20.0 / 60.0,
                hertz_pressure_pa: 914.7e6,
                pressure_convention: PressureConvention::ArticleEq7,
                cof_apparent: 0.41,
                cof_apparent_std: 0.01,
                cof_apparent_ci95: Some(0.002),
                n_samples: 450,
                plateau_start_s: 2.1,
                plateau_end_s: 2.55,
                cof_trend_per_s: 0.001,
                stationary: true,
                flags: vec!["spikes-removed".into()],
                label_evidence: Some(label_evidence::MEASURED_SPEED.into()),
                cof_adhesive: None,
            }],
        }
    }

    #[test]
    fn csv_round_trip() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("d.csv");
        let d = sample();
        d.write_csv(&p).unwrap();
        let back = FrictionDataset::read_csv(&p).unwrap();
        assert_eq!(back.records.len(), 1);
        let (a, b) = (&d.records[0], &back.records[0]);
        assert!((a.sliding_velocity_m_s - b.sliding_velocity_m_s).abs() < 1e-15);
        assert!((a.hertz_pressure_pa - b.hertz_pressure_pa).abs() < 1e-6);
        assert_eq!(a.flags, b.flags);
        assert_eq!(a.pressure_convention, b.pressure_convention);
        assert_eq!(b.normal_force_n, 149.8);
        assert_eq!(b.normal_force_planned_n, Some(150.0));
    }

    /// A file of the earlier schema (planned `normal_force_N`, `normal_force_measured_N`)
    /// reads with the measured load as the load.
    #[test]
    fn earlier_schema_reads_with_the_measured_load() {
        let text = "pin,step,normal_force_N,normal_force_measured_N,sliding_velocity_m_per_min,hertz_pressure_MPa,pressure_convention,cof_apparent,cof_apparent_std,n_samples,plateau_start_s,plateau_end_s,cof_trend_per_s,stationary,flags\n2,1,561,751.6,20,914,article-eq7,0.4,0.01,400,2.1,2.5,0.0,true,\n";
        let d = FrictionDataset::read_csv_from(text.as_bytes(), "old.csv").unwrap();
        assert_eq!(d.records[0].normal_force_n, 751.6);
        assert_eq!(d.records[0].normal_force_planned_n, Some(561.0));
        // and a plan-free row leaves the planned load empty
        let mut r = d.records[0].clone();
        r.normal_force_planned_n = None;
        let mut buf = Vec::new();
        FrictionDataset { records: vec![r] }
            .write_csv_to(&mut buf, false)
            .unwrap();
        let back = FrictionDataset::read_csv_from(buf.as_slice(), "new.csv").unwrap();
        assert_eq!(back.records[0].normal_force_planned_n, None);
        assert_eq!(back.records[0].normal_force_n, 751.6);
    }

    /// The interval and the label's evidence survive a round trip; a file without them (an
    /// earlier version's) reads them as absent, and a bad value is named by line and field.
    #[test]
    fn interval_and_evidence_are_optional_and_checked() {
        let mut buf = Vec::new();
        sample().write_csv_to(&mut buf, false).unwrap();
        let text = String::from_utf8(buf).unwrap();
        let back = FrictionDataset::read_csv_from(text.as_bytes(), "t.csv").unwrap();
        assert_eq!(back.records[0].cof_apparent_ci95, Some(0.002));
        assert_eq!(
            back.records[0].label_evidence.as_deref(),
            Some("measured-speed")
        );
        let old = "pin,step,normal_force_N,sliding_velocity_m_per_min,hertz_pressure_MPa,pressure_convention,cof_apparent,cof_apparent_std,n_samples,plateau_start_s,plateau_end_s,cof_trend_per_s,stationary,flags\n1,1,150,20,914,article-eq7,0.4,0.01,400,2.1,2.5,0.0,true,\n";
        let d = FrictionDataset::read_csv_from(old.as_bytes(), "old.csv").unwrap();
        assert_eq!(d.records[0].cof_apparent_ci95, None);
        assert_eq!(d.records[0].label_evidence, None);
        let e = err_of(&text.replace("measured-speed", "guesswork"));
        assert!(
            e.contains("line 2") && e.contains("label_evidence") && e.contains("guesswork"),
            "{e}"
        );
        let e = err_of(&text.replace(",0.002,", ",-0.002,"));
        assert!(
            e.contains("cof_apparent_ci95") && e.contains("never negative"),
            "{e}"
        );
    }

    fn err_of(text: &str) -> String {
        FrictionDataset::read_csv_from(text.as_bytes(), "t.csv")
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn bad_inputs_are_named() {
        let mut buf = Vec::new();
        sample().write_csv_to(&mut buf, false).unwrap();
        let good = String::from_utf8(buf).unwrap();
        let e = err_of(&good.replace("149.8", "NaN"));
        assert!(
            e.contains("line 2") && e.contains("'normal_force_N'") && e.contains("finite"),
            "{e}"
        );
        let e = err_of(&good.replacen("150,", "-150,", 1));
        assert!(
            e.contains("normal_force_planned_N") && e.contains("positive"),
            "{e}"
        );
        let e = err_of(&good.replace("hertz_pressure_MPa", "hertz_pressure_kPa"));
        assert!(e.contains("unknown column 'hertz_pressure_kPa'"), "{e}");
        let e = err_of(&good.replace("article-eq7", "mystery"));
        assert!(e.contains("unknown pressure convention"), "{e}");
        let e = err_of(&format!("{good}1,2\n"));
        assert!(
            e.contains("line 3") && e.contains("expected 17 fields"),
            "{e}"
        );
    }
}
