//! Calibration across conditions: the numeric set-up fields (by default the Johnson–Cook
//! C; any field, e.g. a parameter of an inline friction law, `friction.law.b`, or a flow
//! stress constant), and optionally a scale on the Coulomb μ, that minimise the mean
//! relative error over measured conditions, each evaluation one sweep over the training
//! conditions on the chosen executor. Conditions held out are simulated once at the result
//! and reported apart.
//!
//! The error is the mean of |simulated − measured| / measured over the quantities measured:
//! F'c always; F'f where a friction parameter is fitted (friction shows in the feed force);
//! the chip thickness ratio h_c/h wherever the measured file has it. Identifying the flow
//! stress on forces *and* chip thickness is what the measurements' source recommends after
//! its own FE model, whose material parameters were chosen for their cutting force, missed
//! h_c/h by 17 % (Ducobu, Pantalé & Lauwers 2022, `pantale/CIRP-2022-paper`, after Kugalur
//! Palanisamy et al., Metals 12 (2022) 976): the cutting force alone does not determine the
//! flow stress, and the chip tells apart sets that give the same force.
//!
//! The search is [`crate::search::coordinate_descent`]: golden-section on one field at a
//! time (ln C and ln of the scale on a log scale), over every field again for each pass
//! ([`default_passes`]), which needs no derivative and tolerates
//! the solver's small run-to-run differences between parameter values; every evaluation's
//! cases are kept, so a repeated value costs nothing.
//!
//! How sure the result is comes from the same evaluations ([`crate::fit_certainty`]): each
//! fitted value's range over the evaluations the training conditions cannot tell from the
//! best (paired across the conditions), a side left open where the evaluations did not
//! bound it, and the mean errors with their t-intervals across the conditions.

use super::fit_certainty::{across_ci95, certainty, mean_or_infinite, Certainty, Evaluation};
use super::launch::CaseCommand;
use super::search::{coordinate_descent, FitField};
use super::spec::{Axis, FieldValues, SweepFile};
use super::{Executor, Plan};
use anyhow::{bail, Context, Result};
use greybox_core::atomic::write_string_atomic;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// The field the calibration sets.
pub const C_FIELD: &str = "material.plasticity.c";
/// The measured cutting force column, N/mm.
pub const FC: &str = "cutting_force_N_per_mm";
/// The measured feed force column (optional), N/mm.
pub const FF: &str = "feed_force_N_per_mm";
/// The measured chip thickness ratio h_c/h column (optional).
pub const CHIP: &str = "chip_ratio";

/// One measured condition: the configuration fields that define it, its forces and chip.
#[derive(Debug, Clone, Serialize)]
pub struct Condition {
    pub values: Vec<(String, String)>,
    pub cutting_force_n_per_mm: f64,
    pub feed_force_n_per_mm: Option<f64>,
    /// The chip thickness ratio h_c/h, where measured.
    pub chip_ratio: Option<f64>,
}

/// What one cut gave: F'c and F'f, N/mm, and h_c/h (NaN where the cut did not report one).
#[derive(Debug, Clone, Copy, PartialEq)]
struct Simulated {
    cutting_force: f64,
    feed_force: f64,
    chip_ratio: f64,
}

/// Reads measured conditions: columns named by configuration fields (dotted paths) plus
/// `cutting_force_N_per_mm` and optionally `feed_force_N_per_mm` and `chip_ratio` (h_c/h).
pub fn read_measured(path: &Path) -> Result<Vec<Condition>> {
    let src = path.display().to_string();
    let mut rdr =
        greybox_core::input::data_csv(path, "measured conditions", &csv::ReaderBuilder::new())?;
    let header: Vec<String> = rdr
        .headers()?
        .iter()
        .map(|h| h.trim().to_string())
        .collect();
    let fc = header
        .iter()
        .position(|h| h == FC)
        .with_context(|| format!("{src}: no column {FC}"))?;
    let ff = header.iter().position(|h| h == FF);
    let chip = header.iter().position(|h| h == CHIP);
    let mut out = Vec::new();
    for (k, r) in rdr.records().enumerate() {
        let line = k + 2;
        let r = r.with_context(|| format!("{src}: line {line}"))?;
        let positive = |i: usize, what: &str| -> Result<f64> {
            let v: f64 = r[i]
                .trim()
                .parse()
                .ok()
                .filter(|v: &f64| v.is_finite() && *v > 0.0)
                .with_context(|| {
                    format!(
                        "{src}: line {line}, column {}: expected {what}, got '{}'",
                        header[i], &r[i]
                    )
                })?;
            Ok(v)
        };
        let force = |i: usize| positive(i, "a force > 0 in N/mm");
        out.push(Condition {
            values: header
                .iter()
                .enumerate()
                .filter(|(i, _)| *i != fc && Some(*i) != ff && Some(*i) != chip)
                .map(|(i, h)| (h.clone(), r[i].trim().to_string()))
                .collect(),
            cutting_force_n_per_mm: force(fc)?,
            feed_force_n_per_mm: ff.map(force).transpose()?,
            chip_ratio: chip
                .map(|i| positive(i, "a chip thickness ratio h_c/h > 0"))
                .transpose()?,
        });
    }
    if out.is_empty() {
        bail!("{src}: no conditions");
    }
    Ok(out)
}

/// Which conditions are held out.
#[derive(Debug, Clone)]
pub enum HoldOut {
    /// Every k-th condition (k, 2k, … counting from 1).
    Every(usize),
    /// These conditions, counting from 1.
    List(Vec<usize>),
}

impl HoldOut {
    fn held(&self, i: usize) -> bool {
        match self {
            HoldOut::Every(k) => *k > 0 && (i + 1).is_multiple_of(*k),
            HoldOut::List(l) => l.contains(&(i + 1)),
        }
    }
}

/// What to calibrate and how.
#[derive(Debug, Clone)]
pub struct CalibrateOptions {
    /// The sweep file: its base case, `[sweep]` settings and `[slurm]` resources (its axes
    /// are replaced by the measured conditions).
    pub sweep_file: PathBuf,
    pub measured: PathBuf,
    pub out: PathBuf,
    pub executor: Executor,
    /// How a case's process starts (handed in by the program running the calibration).
    pub command: CaseCommand,
    /// The fitted set-up fields and their brackets (by default C, [`C_FIELD`]).
    pub fields: Vec<FitField>,
    /// Evaluations per golden-section search.
    pub iterations: usize,
    /// Passes of the coordinate search over every searched parameter (`None`: two where
    /// more than one is searched, one otherwise; [`default_passes`]).
    pub passes: Option<usize>,
    pub hold_out: HoldOut,
    /// Also scale the Coulomb `mu` of the base (bracket 0.5 … 2).
    pub friction_scale: bool,
}

/// One condition at the result.
#[derive(Debug, Clone, Serialize)]
pub struct Residual {
    pub condition: usize,
    pub held_out: bool,
    pub values: Vec<(String, String)>,
    pub measured_cutting_force_n_per_mm: f64,
    pub simulated_cutting_force_n_per_mm: f64,
    pub cutting_force_error: f64,
    pub measured_feed_force_n_per_mm: Option<f64>,
    pub simulated_feed_force_n_per_mm: f64,
    pub feed_force_error: Option<f64>,
    pub measured_chip_ratio: Option<f64>,
    /// h_c/h of the cut (`None`: it reported none).
    pub simulated_chip_ratio: Option<f64>,
    pub chip_ratio_error: Option<f64>,
}

/// The calibration's result (`calibration.json`).
#[derive(Debug, Clone, Serialize)]
pub struct Calibration {
    /// Every fitted field and its value, in the order given.
    pub parameters: Vec<(String, f64)>,
    /// The Johnson–Cook C where it was fitted.
    pub c: Option<f64>,
    pub friction_scale: Option<f64>,
    /// Mean relative error over the training conditions at the result (module doc: the
    /// forces and, where measured, the chip ratio).
    pub training_error: f64,
    /// Half-width of its 95 % t-interval across the training conditions (`None`: one).
    pub training_error_ci95: Option<f64>,
    /// The same over the held-out conditions (None: none held out).
    pub held_out_error: Option<f64>,
    pub held_out_error_ci95: Option<f64>,
    /// The searched parameters: the fitted fields, then `friction scale` where fitted.
    pub searched: Vec<String>,
    /// Passes of the coordinate search over `searched`.
    pub passes: usize,
    /// Every evaluation: the searched parameters' values, in the order of `searched`, the
    /// training error and each training condition's share of it.
    pub evaluations: Vec<Evaluation>,
    /// How sure the fit is of each searched parameter ([`crate::fit_certainty`]; `None`
    /// with fewer than two training conditions).
    pub certainty: Option<Certainty>,
    pub residuals: Vec<Residual>,
}

/// Passes of the coordinate search over `searched` parameters where none is asked for: two
/// where more than one is searched, since one golden section per coordinate leaves each
/// parameter at its best for the others' *starting* values, and coupled parameters (the
/// flow stress and the friction both move the forces) move each other's best; one
/// otherwise.
pub fn default_passes(searched: usize) -> usize {
    if searched > 1 {
        2
    } else {
        1
    }
}

/// The sweep of `conds` with the fitted fields at `values` (and μ scaled by `scale`): what
/// each cut gave.
fn evaluate(
    o: &CalibrateOptions,
    base: &SweepFile,
    dir: &Path,
    conds: &[&Condition],
    values: &[f64],
    scale: Option<f64>,
) -> Result<Vec<Simulated>> {
    let mut f = base.clone();
    let fields: Vec<String> = conds[0].values.iter().map(|v| v.0.clone()).collect();
    f.axis = if fields.is_empty() {
        Vec::new()
    } else {
        vec![Axis {
            field: None,
            values: None,
            range: None,
            zip: fields
                .iter()
                .enumerate()
                .map(|(j, name)| FieldValues {
                    field: name.clone(),
                    values: Some(conds.iter().map(|k| parse_value(&k.values[j].1)).collect()),
                    range: None,
                })
                .collect(),
        }]
    };
    let mut extra: Vec<(String, toml::Value)> = o
        .fields
        .iter()
        .zip(values)
        .map(|(f, &v)| (f.field.clone(), toml::Value::Float(v)))
        .collect();
    if let Some(s) = scale {
        let mu0 = super::case::read_base(
            &dir.join(&base.sweep.base),
            base.sweep.kind,
            base.sweep.stop_when_sure,
        )?
        .get("mu")
        .and_then(toml::Value::as_float)
        .context("friction scale: the base has no constant `mu` to scale")?;
        extra.push(("mu".to_string(), toml::Value::Float(mu0 * s)));
    }
    let plan = Plan::expand(&f, dir, &o.sweep_file.display().to_string(), &extra)?;
    let report = super::run_plan(&plan, &o.out, &o.executor, &o.command)?;
    if let Some(first) = report.failed.first() {
        bail!(
            "{}: case {} failed: {}",
            show_values(&o.fields, values),
            first.index,
            first.error
        );
    }
    plan.cases
        .iter()
        .map(|case| {
            let dir = super::case::CaseDir::of(&o.out, &case.id);
            let d = dir
                .read_done(case)?
                .with_context(|| format!("{}: missing", dir.done().display()))?;
            let g = |k: &str| {
                d.summary
                    .get(k)
                    .and_then(serde_json::Value::as_f64)
                    .unwrap_or(f64::NAN)
            };
            Ok(Simulated {
                cutting_force: g("cutting_force_n_per_mm"),
                feed_force: g("feed_force_n_per_mm"),
                chip_ratio: g("compression_ratio"),
            })
        })
        .collect()
}

/// A CSV cell as a TOML value: a number if it reads as one, else a string.
fn parse_value(s: &str) -> toml::Value {
    s.parse::<i64>()
        .map(toml::Value::Integer)
        .or_else(|_| s.parse::<f64>().map(toml::Value::Float))
        .unwrap_or_else(|_| toml::Value::String(s.to_string()))
}

/// Each condition's share of the mean relative error of simulated against measured
/// quantities: F'c; F'f where measured and `with_feed` (a scale on μ or a friction field is
/// fitted); h_c/h where measured. A condition's share is the sum of its terms times
/// (conditions / terms), so that the shares' mean is the mean over all terms; a cut without
/// a chip ratio makes its share, and so the mean, infinite.
fn condition_errors(conds: &[&Condition], sim: &[Simulated], with_feed: bool) -> Vec<f64> {
    let mut terms = 0usize;
    let sums: Vec<f64> = conds
        .iter()
        .zip(sim)
        .map(|(c, s)| {
            let measured = [
                Some((s.cutting_force, c.cutting_force_n_per_mm)),
                c.feed_force_n_per_mm
                    .filter(|_| with_feed)
                    .map(|ff| (s.feed_force, ff)),
                c.chip_ratio.map(|r| (s.chip_ratio, r)),
            ];
            measured
                .into_iter()
                .flatten()
                .map(|(simulated, m)| {
                    terms += 1;
                    let e = ((simulated - m) / m).abs();
                    if e.is_finite() {
                        e
                    } else {
                        f64::INFINITY
                    }
                })
                .sum()
        })
        .collect();
    let per = conds.len() as f64 / terms.max(1) as f64;
    sums.into_iter().map(|s| s * per).collect()
}

/// `field = value, …` for messages.
fn show_values(fields: &[FitField], values: &[f64]) -> String {
    fields
        .iter()
        .zip(values)
        .map(|(f, v)| format!("{} = {v}", f.field))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The bracket of the μ scale, searched on a log scale.
const SCALE_RANGE: [f64; 2] = [0.5, 2.0];

/// Each condition's measured and simulated forces and chip ratio and their relative errors.
fn residuals(conds: &[Condition], sim: &[Simulated], hold_out: &HoldOut) -> Vec<Residual> {
    conds
        .iter()
        .zip(sim)
        .enumerate()
        .map(|(i, (m, s))| Residual {
            condition: i + 1,
            held_out: hold_out.held(i),
            values: m.values.clone(),
            measured_cutting_force_n_per_mm: m.cutting_force_n_per_mm,
            simulated_cutting_force_n_per_mm: s.cutting_force,
            cutting_force_error: (s.cutting_force - m.cutting_force_n_per_mm)
                / m.cutting_force_n_per_mm,
            measured_feed_force_n_per_mm: m.feed_force_n_per_mm,
            simulated_feed_force_n_per_mm: s.feed_force,
            feed_force_error: m.feed_force_n_per_mm.map(|f| (s.feed_force - f) / f),
            measured_chip_ratio: m.chip_ratio,
            simulated_chip_ratio: s.chip_ratio.is_finite().then_some(s.chip_ratio),
            chip_ratio_error: m
                .chip_ratio
                .filter(|_| s.chip_ratio.is_finite())
                .map(|r| (s.chip_ratio - r) / r),
        })
        .collect()
}

/// Runs the calibration and writes `calibration.json` into `o.out`.
pub fn calibrate(o: &CalibrateOptions) -> Result<Calibration> {
    let (base, dir) = SweepFile::load(&o.sweep_file)?;
    if o.fields.is_empty() && !o.friction_scale {
        bail!("nothing to calibrate: expected at least one fitted field or the friction scale");
    }
    for f in &o.fields {
        f.check()?;
    }
    let conds = read_measured(&o.measured)?;
    let training: Vec<&Condition> = conds
        .iter()
        .enumerate()
        .filter(|(i, _)| !o.hold_out.held(*i))
        .map(|(_, c)| c)
        .collect();
    let held: Vec<&Condition> = conds
        .iter()
        .enumerate()
        .filter(|(i, _)| o.hold_out.held(*i))
        .map(|(_, c)| c)
        .collect();
    if training.is_empty() {
        bail!("every condition is held out: nothing to calibrate on");
    }
    // The search runs over the fields, then the scale (one more coordinate).
    let mut search = o.fields.clone();
    if o.friction_scale {
        search.push(FitField::new("friction scale", SCALE_RANGE, true));
    }
    let n = o.fields.len();
    let split = |x: &[f64]| (x[..n].to_vec(), o.friction_scale.then(|| x[n]));
    let start: Vec<f64> = search.iter().map(FitField::middle).collect();
    let mut evals = Vec::new();
    let passes = o.passes.unwrap_or_else(|| default_passes(search.len()));
    // friction shows in the feed force: it counts where friction is fitted
    let with_feed = o.friction_scale
        || o.fields
            .iter()
            .any(|f| f.field.starts_with("friction.") || f.field == "mu");
    let (best, _) = coordinate_descent(&search, &start, passes, o.iterations, &mut |x| {
        let (values, scale) = split(x);
        let shares = condition_errors(
            &training,
            &evaluate(o, &base, &dir, &training, &values, scale)?,
            with_feed,
        );
        let e = Evaluation::new(x.to_vec(), shares);
        let objective = e.error;
        evals.push(e);
        Ok(objective)
    })?;
    let (values, scale) = split(&best);
    let all: Vec<&Condition> = conds.iter().collect();
    let sim = evaluate(o, &base, &dir, &all, &values, scale)?;
    let residuals = residuals(&conds, &sim, &o.hold_out);
    let sim_of = |set: &[&Condition]| -> Vec<Simulated> {
        set.iter()
            .map(|c| sim[conds.iter().position(|x| std::ptr::eq(x, *c)).unwrap_or(0)])
            .collect()
    };
    let parameters: Vec<(String, f64)> = o
        .fields
        .iter()
        .zip(&values)
        .map(|(f, &v)| (f.field.clone(), v))
        .collect();
    let shares = |set: &[&Condition]| condition_errors(set, &sim_of(set), with_feed);
    let (trained, held_shares) = (shares(&training), shares(&held));
    let result = Calibration {
        c: parameters.iter().find(|p| p.0 == C_FIELD).map(|p| p.1),
        parameters,
        friction_scale: scale,
        training_error: mean_or_infinite(&trained),
        training_error_ci95: across_ci95(&trained),
        held_out_error: (!held.is_empty()).then(|| mean_or_infinite(&held_shares)),
        held_out_error_ci95: across_ci95(&held_shares),
        searched: search.iter().map(|f| f.field.clone()).collect(),
        passes,
        certainty: certainty(&search, &evals),
        evaluations: evals,
        residuals,
    };
    write_string_atomic(
        &o.out.join("calibration.json"),
        &serde_json::to_string_pretty(&result)?,
    )?;
    Ok(result)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The mean relative error over `conds` (the mean of [`condition_errors`]).
    fn error(conds: &[&Condition], sim: &[Simulated], with_feed: bool) -> f64 {
        mean_or_infinite(&condition_errors(conds, sim, with_feed))
    }

    fn measured(text: &str) -> Result<Vec<Condition>> {
        let d = tempfile::tempdir().unwrap();
        let p = d.path().join("measured.csv");
        std::fs::write(&p, text).unwrap();
        read_measured(&p)
    }

    #[test]
    fn several_searched_parameters_take_two_passes_by_default() {
        assert_eq!(default_passes(1), 1);
        assert_eq!(default_passes(2), 2);
        assert_eq!(default_passes(4), 2);
    }

    /// The chip ratio column is a measurement, not a set-up field, and it counts in the error
    /// with the forces: |Δ|/measured of each measured quantity, averaged.
    #[test]
    fn a_measured_chip_ratio_counts_in_the_error() {
        let conds = measured(
            "uncut_chip_thickness_m,cutting_force_N_per_mm,feed_force_N_per_mm,chip_ratio\n\
             6e-5,100,50,2.0\n8e-5,150,60,\n",
        );
        // an empty chip cell is not a measurement: refused, like an empty force
        let e = format!("{:#}", conds.unwrap_err());
        assert!(
            e.contains("line 3, column chip_ratio: expected a chip thickness ratio h_c/h > 0"),
            "{e}"
        );
        let conds = measured(
            "uncut_chip_thickness_m,cutting_force_N_per_mm,feed_force_N_per_mm,chip_ratio\n\
             6e-5,100,50,2.0\n8e-5,150,60,1.5\n",
        )
        .unwrap();
        assert_eq!(
            conds[0].values,
            [("uncut_chip_thickness_m".into(), "6e-5".into())]
        );
        assert_eq!(conds[1].chip_ratio, Some(1.5));
        let refs: Vec<&Condition> = conds.iter().collect();
        let sim = [
            Simulated {
                cutting_force: 110.0,
                feed_force: 40.0,
                chip_ratio: 1.8,
            },
            Simulated {
                cutting_force: 150.0,
                feed_force: 60.0,
                chip_ratio: 1.8,
            },
        ];
        // F'c 10 % and 0 %, chip 10 % and 20 %: 40 % over four terms
        assert!((error(&refs, &sim, false) - 0.10).abs() < 1e-12);
        // with the feed force as well: + 20 % and 0 % over six terms
        assert!((error(&refs, &sim, true) - 0.60 / 6.0).abs() < 1e-12);
        // a cut that measured no chip cannot be judged on the chip
        let mut blind = sim;
        blind[1].chip_ratio = f64::NAN;
        assert_eq!(error(&refs, &blind, false), f64::INFINITY);
        let r = residuals(&conds, &blind, &HoldOut::List(vec![2]));
        assert_eq!(r[0].chip_ratio_error.map(|e| (e * 1e9).round()), Some(-1e8));
        assert!(r[1].held_out && r[1].simulated_chip_ratio.is_none());
        assert!(r[1].chip_ratio_error.is_none());
    }

    /// Without a chip column nothing changes: the forces alone, as before.
    #[test]
    fn without_a_chip_column_the_error_is_the_forces() {
        let conds = measured("mu,cutting_force_N_per_mm\n0.3,100\n0.4,200\n").unwrap();
        assert!(conds.iter().all(|c| c.chip_ratio.is_none()));
        let refs: Vec<&Condition> = conds.iter().collect();
        let sim = [90.0, 220.0].map(|f| Simulated {
            cutting_force: f,
            feed_force: 0.0,
            chip_ratio: 9.0,
        });
        assert!((error(&refs, &sim, true) - 0.10).abs() < 1e-12);
        for bad in ["nan", "-1", "inf", "x"] {
            let e = format!(
                "{:#}",
                measured(&format!(
                    "mu,cutting_force_N_per_mm,chip_ratio\n0.3,100,{bad}\n"
                ))
                .unwrap_err()
            );
            assert!(e.contains("line 2, column chip_ratio"), "{bad}: {e}");
        }
    }
}
