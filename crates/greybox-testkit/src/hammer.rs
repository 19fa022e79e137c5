//! A virtual impact-hammer test of a single-degree-of-freedom rig as a CSV recording.

use greybox_tribo::frf::ImpactRecording;
use std::path::Path;

/// `rec` as CSV with the columns `time_s,hammer_N,response_m`.
pub fn hammer_csv(rec: &ImpactRecording) -> String {
    let mut s = String::from("time_s,hammer_N,response_m\n");
    for k in 0..rec.hammer.len() {
        s.push_str(&format!(
            "{},{},{}\n",
            k as f64 / rec.sample_rate_hz,
            rec.hammer[k],
            rec.response[k]
        ));
    }
    s
}

/// Write [`hammer_csv`] of `rec` to `path`.
pub fn write_hammer_csv(path: &Path, rec: &ImpactRecording) {
    std::fs::write(path, hammer_csv(rec)).unwrap();
}
