//! A virtual impact-hammer test of a single-degree-of-freedom rig as a CSV recording.

use greybox_tribo::frf::ImpactRecording;
use std::path::Path;

/// `rec` as CSV with the columns `time_s,hammer_N,response_m` ([`ImpactRecording::to_csv`]).
pub fn hammer_csv(rec: &ImpactRecording) -> String {
    rec.to_csv()
}

/// Write [`hammer_csv`] of `rec` to `path`.
pub fn write_hammer_csv(path: &Path, rec: &ImpactRecording) {
    std::fs::write(path, hammer_csv(rec)).unwrap();
}
