//! The load levels of a friction dataset and the loads an inverse ploughing route simulates.

use anyhow::Result;
use greybox_contact::ploughing::{track_depth, WidthLaw};
use greybox_core::dataset::FrictionDataset;

/// Loads simulated by an inverse route: each is a search of several pin runs.
pub type SimLoads = greybox_core::count::Count<1, 1_000>;
/// Runs of one load's search.
pub type SimRuns = greybox_core::count::Count<1, 100>;
/// Every n-th distinct load, from the highest.
pub type LoadStride = greybox_core::count::Count<1, 1_000>;

/// Relative spread of measured normal forces taken as one load level when a dataset has no
/// planned forces.
const LEVEL_SPREAD: f64 = 0.05;

/// The dataset's load levels, highest first, each as (mean measured normal force N, mean
/// μ_app): rows grouped by their planned force where every row has one, else by measured
/// forces within [`LEVEL_SPREAD`] of the level's lowest.
pub fn load_levels(ds: &FrictionDataset) -> Vec<(f64, f64)> {
    let planned = ds
        .records
        .iter()
        .all(|r| r.normal_force_planned_n.is_some());
    let mut rows: Vec<(f64, f64, f64)> = ds
        .records
        .iter()
        .map(|r| {
            let key = if planned {
                r.normal_force_planned_n.unwrap_or(r.normal_force_n)
            } else {
                r.normal_force_n
            };
            (key, r.normal_force_n, r.cof_apparent)
        })
        .collect();
    rows.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut levels: Vec<Vec<(f64, f64, f64)>> = Vec::new();
    for row in rows {
        match levels.last_mut() {
            Some(l) if row.0 == l[0].0 || (!planned && row.0 <= l[0].0 * (1.0 + LEVEL_SPREAD)) => {
                l.push(row)
            }
            _ => levels.push(vec![row]),
        }
    }
    let mean = |l: &[(f64, f64, f64)], f: fn(&(f64, f64, f64)) -> f64| {
        l.iter().map(f).sum::<f64>() / l.len() as f64
    };
    levels
        .iter()
        .rev()
        .map(|l| (mean(l, |r| r.1), mean(l, |r| r.2)))
        .collect()
}

/// The loads an inverse route simulates: every `stride`-th load level of the dataset from
/// the highest ([`load_levels`]), `count` of them at most, each as (mean normal force N,
/// track depth m from the fitted width law, mean measured μ_app).
pub fn loads_to_simulate(
    ds: &FrictionDataset,
    pin_radius_m: f64,
    law: &WidthLaw,
    count: SimLoads,
    stride: LoadStride,
) -> Result<Vec<(f64, f64, f64)>> {
    load_levels(ds)
        .into_iter()
        .step_by(stride.get())
        .take(count.get())
        .map(|(f, mu_app)| {
            Ok((
                f,
                track_depth(pin_radius_m, law.width_um(f) * 1e-6)?,
                mu_app,
            ))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use greybox_core::dataset::FrictionDataset;

    fn dataset(rows: &[(f64, Option<f64>, f64)]) -> FrictionDataset {
        let mut text = String::from("pin,step,normal_force_N,normal_force_planned_N,sliding_velocity_m_per_min,hertz_pressure_MPa,pressure_convention,cof_apparent,cof_apparent_std,n_samples,plateau_start_s,plateau_end_s,cof_trend_per_s,stationary,flags\n");
        for (k, (f, p, mu)) in rows.iter().enumerate() {
            let p = p.map(|p| p.to_string()).unwrap_or_default();
            text += &format!(
                "1,{},{f},{p},20,900,textbook-max,{mu},0.01,100,1,2,0,true,\n",
                k + 1
            );
        }
        FrictionDataset::read_csv_from(text.as_bytes(), "test.csv").unwrap()
    }

    #[test]
    fn load_levels_group_rows_by_planned_force_else_by_nearby_measured_force() {
        // measured forces scatter around the plan: one level per planned force
        let planned = dataset(&[
            (1995.0, Some(2000.0), 0.30),
            (2009.0, Some(2000.0), 0.32),
            (1003.0, Some(1000.0), 0.4),
        ]);
        let l = load_levels(&planned);
        assert_eq!(l.len(), 2);
        assert!((l[0].0 - 2002.0).abs() < 1e-9 && (l[0].1 - 0.31).abs() < 1e-12);
        assert_eq!(l[1], (1003.0, 0.4));
        // without a plan: forces within 5 % are one level
        let measured = dataset(&[
            (1995.0, None, 0.30),
            (2009.0, None, 0.32),
            (1003.0, None, 0.4),
            (990.0, None, 0.4),
        ]);
        let l = load_levels(&measured);
        assert_eq!(l.len(), 2);
        assert!((l[0].0 - 2002.0).abs() < 1e-9 && (l[1].0 - 996.5).abs() < 1e-9);
        // every second level from the highest
        let w = WidthLaw { a_um: 50.0, b: 0.5 };
        let s =
            loads_to_simulate(&measured, 17e-3, &w, SimLoads::of(6), LoadStride::of(2)).unwrap();
        assert_eq!(s.len(), 1);
        // no load to simulate is not a value of the count: refused where it enters
        assert!(SimLoads::new(0)
            .unwrap_err()
            .to_string()
            .starts_with("0 is below the least allowed 1"));
    }
}
