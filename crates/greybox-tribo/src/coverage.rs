//! Every sample accounted for: how a file's sliding time was used.
//!
//! The sliding time of a file (loaded and sliding, [`crate::sliding`]) is divided into
//! * **steady**: the steady windows that gave rows, less
//! * **masked**: their samples masked as spikes (Hampel), which no row averages;
//! * **unsettled**: the windows of rows whose μ never settles (the mean after the warm-up,
//!   with its trend: [`crate::steady_window::steady_stretch`]) — a row, but no steady state;
//! * **run-in**: from a row's segment start to the end of its run-in (`auto` rule);
//! * **dropped**: segments that gave no row, each with its reason (no steady part, shorter
//!   than `min_segment_s`, no planned step matched, merged into the next step);
//! * **transitions**: the rest (ramps, settling, the margins at a segment's ends, and
//!   sliding outside any segment).
//!
//! A file whose steady share is below `min_steady_share` flags its rows `low-coverage`, so
//! that a result resting on a sliver of a long recording says so.

use serde::Serialize;

/// Sliding time that gave no row, and why.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Dropped {
    /// What was dropped (`segment 3`, `0.12-0.31 s`).
    pub what: String,
    pub reason: String,
    pub seconds: f64,
}

/// How one file's sliding time was used, s.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct Coverage {
    pub sliding_s: f64,
    pub steady_s: f64,
    /// Samples inside the steady windows masked as spikes, s (not in `steady_s`).
    pub masked_s: f64,
    /// Windows of rows whose μ never settles, s (not in `steady_s`).
    pub unsettled_s: f64,
    pub run_in_s: f64,
    pub transitions_s: f64,
    pub dropped_s: f64,
    pub dropped: Vec<Dropped>,
}

/// One segment's part in the coverage: its span, steady window and run-in, s.
#[derive(Debug, Clone, Copy)]
pub(crate) struct SegmentTime {
    pub start_s: f64,
    pub end_s: f64,
    pub steady_s: f64,
    pub run_in_s: f64,
    /// Of the steady window, the time masked as spikes, s.
    pub masked_s: f64,
    /// μ never settles in the window: it counts as unsettled, not steady.
    pub unsettled: bool,
}

impl Coverage {
    /// The coverage of `sliding_s` seconds of sliding by the segments that gave rows and
    /// those dropped (with their reasons).
    pub(crate) fn of(sliding_s: f64, rows: &[SegmentTime], dropped: Vec<Dropped>) -> Coverage {
        let masked_s: f64 = rows.iter().map(|r| r.masked_s.min(r.steady_s)).sum();
        let unsettled_s: f64 = rows
            .iter()
            .filter(|r| r.unsettled)
            .map(|r| r.steady_s - r.masked_s.min(r.steady_s))
            .sum();
        let steady_s: f64 = rows.iter().map(|r| r.steady_s).sum::<f64>() - masked_s - unsettled_s;
        let run_in_s: f64 = rows
            .iter()
            .map(|r| r.run_in_s.clamp(0.0, r.end_s - r.start_s))
            .sum();
        let dropped_s: f64 = dropped.iter().map(|d| d.seconds).sum();
        // the segments may hold a few non-sliding samples: the whole is at least their sum
        let used = steady_s + masked_s + unsettled_s + run_in_s + dropped_s;
        let sliding_s = sliding_s.max(used);
        Coverage {
            sliding_s,
            steady_s,
            masked_s,
            unsettled_s,
            run_in_s,
            transitions_s: (sliding_s - used).max(0.0),
            dropped_s,
            dropped,
        }
    }

    /// The share of the sliding time that is steady (1 with no sliding).
    pub fn steady_share(&self) -> f64 {
        if self.sliding_s > 0.0 {
            self.steady_s / self.sliding_s
        } else {
            1.0
        }
    }

    /// `steady 62 % · run-in 8 % · transitions 27 % · dropped 3 % of 1200.0 s sliding`, with
    /// `masked 1 %` after the steady share where spikes were masked and `unsettled 5 %` where
    /// a row's μ never settled.
    pub fn line(&self) -> String {
        let pct = |x: f64| {
            if self.sliding_s > 0.0 {
                (100.0 * x / self.sliding_s).max(0.0)
            } else {
                0.0
            }
        };
        let part = |x: f64, what: &str| {
            if x > 0.0 {
                format!(" · {what} {:.0} %", pct(x))
            } else {
                String::new()
            }
        };
        let masked = part(self.masked_s, "masked") + &part(self.unsettled_s, "unsettled");
        format!(
            "steady {:.0} %{masked} · run-in {:.0} % · transitions {:.0} % · dropped {:.0} % of {:.1} s sliding",
            pct(self.steady_s),
            pct(self.run_in_s),
            pct(self.transitions_s),
            pct(self.dropped_s),
            self.sliding_s
        )
    }

    /// One note per dropped part: `dropped segment 4 (12.0 s): no steady part …`.
    pub fn dropped_notes(&self) -> Vec<String> {
        self.dropped
            .iter()
            .map(|d| format!("dropped {} ({:.1} s): {}", d.what, d.seconds, d.reason))
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn shares_add_up_to_the_sliding_time() {
        let rows = [SegmentTime {
            start_s: 0.0,
            end_s: 100.0,
            steady_s: 60.0,
            run_in_s: 20.0,
            masked_s: 0.0,
            unsettled: false,
        }];
        let dropped = vec![Dropped {
            what: "segment 2".into(),
            reason: "no steady part".into(),
            seconds: 50.0,
        }];
        let c = Coverage::of(200.0, &rows, dropped);
        assert_eq!(c.transitions_s, 70.0);
        assert!((c.steady_share() - 0.3).abs() < 1e-12);
        assert_eq!(
            c.line(),
            "steady 30 % · run-in 10 % · transitions 35 % · dropped 25 % of 200.0 s sliding"
        );
        assert_eq!(
            c.dropped_notes(),
            vec!["dropped segment 2 (50.0 s): no steady part"]
        );
    }
}
