//! Rule 4 of issue 58: a Stribeck sweep without a speed channel (tests/support/stribeck.rs:
//! 8–24 speed steps over two to three decades, μ changing level at every step down to the
//! elastohydrodynamic 0.004–0.02, every free choice drawn from the seed) keeps its steps:
//! it never falls into pieces, its rows cover the truth at their stated level when the plan
//! gives step durations, rest on order alone (and say so) when it does not, and rows resting
//! on a sliver of the sliding time say so.

mod glue;
mod support;

use glue::{plan_of, recording};
use greybox_core::dataset::flags;
use greybox_recording::Recording;
use greybox_tribo::campaign::{ExpectedStep, Identification};
use greybox_tribo::config::IdentifyConfig;
use support::stribeck::{sweep, Shape};

fn identify(rec: &Recording, plan: &[ExpectedStep]) -> Identification {
    glue::identify(
        std::slice::from_ref(rec),
        Some(plan),
        &IdentifyConfig::default(),
    )
}

fn has(flags: &[String], f: &str) -> bool {
    flags.iter().any(|x| x == f)
}

/// A sweep of k steps gives at most k segments plus what comes before the first step and
/// the pieces of a load ramp (never hundreds of pieces), a row for nearly every step, and
/// most of its sliding time steady. With step durations in the plan, the rows' 95 %
/// intervals cover their step's truth in 90–99 % of the rows; a row outside its interval by
/// more than its step's change to a neighbour carries a flag that says why. Without
/// durations every row says `label-by-order` (and is never silently placed).
#[test]
fn a_stribeck_sweep_without_a_speed_channel_keeps_its_steps() {
    let (mut rows, mut hits) = (0usize, 0usize);
    for seed in 0..40u64 {
        let (t, truth) = sweep(seed, Shape::Steps);
        let rec = recording(&t);
        let k = truth.len();
        for durations in [false, true] {
            let id = identify(&rec, &plan_of(&truth, durations));
            let f = &id.files[0];
            let what = format!("seed {seed} (durations {durations}, {k} steps)");
            assert!(
                f.segments.len() <= k + 3,
                "{what}: {} segments: {}",
                f.segments.len(),
                f.coverage.line()
            );
            assert!(
                id.dataset.records.len() + 1 >= k,
                "{what}: {} rows: {:#?}",
                id.dataset.records.len(),
                id.matching
            );
            assert!(
                f.coverage.steady_share() > 0.6,
                "{what}: {}",
                f.coverage.line()
            );
            for r in &id.dataset.records {
                let step = &truth[r.step as usize - 1];
                let ci = r.cof_apparent_ci95.unwrap();
                let off = (r.cof_apparent - step.mu).abs();
                assert!(!has(&r.flags, flags::LOW_COVERAGE), "{what}: {:?}", r.flags);
                if !durations {
                    assert!(
                        has(&r.flags, flags::LABEL_BY_ORDER),
                        "{what}: {:?}",
                        r.flags
                    );
                    continue;
                }
                rows += 1;
                if off <= ci {
                    hits += 1;
                    continue;
                }
                eprintln!(
                    "{what} step {}: μ {:.4} ± {ci:.4} truth {:.4} {:?}",
                    r.step, r.cof_apparent, step.mu, r.flags
                );
                // a row in the wrong step is never silent
                let neighbour = truth
                    .iter()
                    .filter(|s| s.step.abs_diff(step.step) == 1)
                    .map(|s| (s.mu - step.mu).abs())
                    .fold(f64::INFINITY, f64::min);
                if off > 0.5 * neighbour {
                    assert!(
                        r.flags.iter().any(|x| [
                            flags::LABEL_CONTRADICTED,
                            flags::AMBIGUOUS_ALIGNMENT,
                            flags::UNCERTAIN_BOUNDARY
                        ]
                        .contains(&x.as_str())),
                        "{what} step {}: silently in the wrong step: {:?}",
                        r.step,
                        r.flags
                    );
                }
            }
        }
    }
    let share = hits as f64 / rows as f64;
    eprintln!(
        "Stribeck sweep with durations: the 95 % interval covers the truth in {hits} of {rows} rows ({:.1} %)",
        100.0 * share
    );
    assert!(rows >= 400, "{rows} rows");
    assert!((0.90..=0.99).contains(&share), "coverage {share:.3}");
}

/// A sweep that spends most of its sliding time in long excursions of μ (dwells of 1.5–2.5 s
/// between excursions of 30–60 s), with or without durations in the plan: where the rows rest
/// on less than `min_steady_share` of the sliding time, every row carries `low-coverage` and
/// the file's notes say on how much they rest; where they rest on more, no row carries it.
/// At least half of these sweeps are below the share (the test is never vacuous).
#[test]
fn rows_on_a_sliver_of_the_sliding_time_say_so() {
    let cfg = IdentifyConfig::default();
    let (mut below, mut runs) = (0, 0);
    for seed in 0..16u64 {
        let (t, truth) = sweep(seed, Shape::MostlyRamps);
        let rec = recording(&t);
        for durations in [false, true] {
            let id = identify(&rec, &plan_of(&truth, durations));
            let f = &id.files[0];
            let what = format!("seed {seed} (durations {durations}): {}", f.coverage.line());
            let low = f.coverage.steady_share() < cfg.min_steady_share;
            runs += 1;
            below += low as usize;
            for r in &id.dataset.records {
                assert_eq!(
                    has(&r.flags, flags::LOW_COVERAGE),
                    low,
                    "{what}: {:?}",
                    r.flags
                );
            }
            assert_eq!(
                f.notes.iter().any(|n| n.starts_with("low coverage")),
                low && !id.dataset.records.is_empty(),
                "{what}: {:?}",
                f.notes
            );
        }
    }
    eprintln!("{below} of {runs} sweeps rest on less than the steady share");
    assert!(2 * below >= runs, "only {below} of {runs} below the share");
}
