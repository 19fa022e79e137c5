#![allow(clippy::neg_cmp_op_on_partial_ord)] // `!(x > 0.0)` deliberately rejects NaN too
//! greybox-recording: a tribometer's raw force recordings, read from any rig's files.
//!
//! The readers: [`text_table`] (CSV and other delimited text, headerless logs, vendor
//! preambles), [`xlsx_table`] (spreadsheets), [`tdms`] (NI TDMS, read and written) and
//! [`csv_recording`] (greybox's own CSV recordings), each giving a [`Table`](table::Table);
//! [`readers`] picks one by the file's content, and [`profiles`] are rigs' known layouts.
//!
//! A reader's [`Table`](crate::table::Table) (named columns with their units) becomes a [`Recording`]: a
//! [`ChannelMap`] says which
//! column plays which role — time, normal and tangential force, and where the rig records
//! them, radial force, trigger, step number, spindle or sliding speed, track radius — and
//! [`recording_from_table`] converts them to SI. Roles not mapped explicitly are found by
//! their usual names ([`ROLE_ALIASES`]), ignoring case, spaces and units in the header.
//!
//! The pieces: [`types`] (the recording and the reader's report), [`roles`] (what a column
//! can be, and its usual names), [`channel_map`] (the user's mapping) with
//! [`reader_options`] (how a file is read: delimiter, decimal comma, header line, sheet,
//! TDMS group, column names), [`assign`] (columns given roles), [`unitless`] (a friction
//! force without a unit), [`convert`] (the table in SI units) and [`diagnosis`] (why a role
//! found no column).

mod assign;
mod channel_map;
mod convert;
mod diagnosis;
mod map_keys;
mod reader_options;
mod roles;
mod types;
mod unitless;

mod bulk;
pub mod csv_recording;
pub mod decimal;
pub mod profiles;
pub mod readers;
pub mod table;
pub mod tdms;
pub mod text_table;
pub mod xlsx_table;

pub use assign::{column_number, looks_like_cof};
pub use channel_map::{ChannelMap, DEFAULT_TDMS_GROUP};
pub use convert::{recording_from_table, FOOTER_LINES_NOTED};
pub use reader_options::ReaderOptions;
pub use roles::{force_unit_from_name, time_unit_from_name, ChannelSpec, Role, ROLE_ALIASES};
pub use types::{FoundBy, MappedColumn, ReadReport, Recording, SpeedTrace, TestMode};
pub use unitless::COF_DISAGREEMENT_FRACTION;

#[cfg(test)]
mod tests {
    use super::types::{first_non_finite, first_non_increasing};
    use super::*;
    use crate::table::Column;

    #[test]
    fn column_numbers_and_cof_names() {
        assert_eq!(column_number("#3"), Some(3));
        assert_eq!(column_number(" # 12 "), Some(12));
        for not in ["#0", "#", "3", "F #2", "#x"] {
            assert_eq!(column_number(not), None, "{not}");
        }
        let cof = |h: &str| looks_like_cof(&Column::numbers(h, Vec::new()));
        for h in [
            "COF",
            "DAQ.COF ()",
            "µ",
            "Mu kinetic",
            "Friction coefficient",
            "Friction coeff.",
            "Reibwert",
            "Friction (-)",
            "Friction (µ)",
            "COF_avg",
        ] {
            assert!(cof(h), "{h}");
        }
        for h in [
            "Friction force (N)",
            "Fx",
            "Load",
            "Friction",
            "Muffle temp (K)",
        ] {
            assert!(!cof(h), "{h}");
        }
        let spec = ChannelSpec::parse("#3:N").unwrap();
        assert_eq!(
            (spec.name.as_str(), spec.unit.as_deref()),
            ("#3", Some("N"))
        );
    }

    /// The parallel block screens find the same index as a plain scan, at block edges too.
    #[test]
    fn screens_find_the_first_bad_sample() {
        let n = 3 * (1 << 14) + 17;
        let good: Vec<f64> = (0..n).map(|i| i as f64 * 1e-3).collect();
        assert_eq!(first_non_finite(&good), None);
        assert_eq!(first_non_increasing(&good), None);
        for at in [
            0,
            1,
            (1 << 14) - 1,
            1 << 14,
            (1 << 14) + 1,
            2 * (1 << 14),
            n - 1,
        ] {
            for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                let mut v = good.clone();
                v[at] = bad;
                v[n - 1] = f64::NAN;
                assert_eq!(first_non_finite(&v), Some(at), "{bad} at {at}");
            }
            let mut t = good.clone();
            t[at] = if at == 0 { 1e9 } else { t[at - 1] };
            let want = t.windows(2).position(|w| !(w[1] > w[0]));
            assert_eq!(first_non_increasing(&t), want, "repeat at {at}");
        }
    }

    /// The reader options sit beside the map's own keys (a study's `[recording]` is flat), and a
    /// key neither knows is refused.
    #[test]
    fn reader_options_are_flat_keys_of_the_map() {
        let text = r#"{"normal": {"name": "Fz", "unit": "kN", "scale": 1.0}, "delimiter": "semicolon",
            "decimal_comma": true, "header_line": 3, "sheet": "Data", "tdms_group": "Dyno",
            "columns": ["t_s", "Fn_N"], "sample_rate_hz": 100.0}"#;
        let map: ChannelMap = serde_json::from_str(text).unwrap();
        assert_eq!(
            map.reader,
            ReaderOptions {
                tdms_group: Some("Dyno".into()),
                header_line: Some(3),
                delimiter: Some(crate::text_table::Delimiter::Semicolon),
                decimal_comma: Some(true),
                sheet: Some("Data".into()),
                columns: vec!["t_s".into(), "Fn_N".into()],
            }
        );
        assert_eq!(map.sample_rate_hz, Some(100.0));
        assert!(map.auto, "defaults kept");
        let back = serde_json::to_string(&map).unwrap();
        assert_eq!(serde_json::from_str::<ChannelMap>(&back).unwrap(), map);
        assert!(back.ends_with(r#""tdms_group":"Dyno","header_line":3,"delimiter":"semicolon","decimal_comma":true,"sheet":"Data","columns":["t_s","Fn_N"]}"#), "{back}");
        let e = serde_json::from_str::<ChannelMap>(r#"{"delimiter": "tab", "delimitr": "tab"}"#)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("delimitr") && e.contains("expected one of"),
            "{e}"
        );
    }
}
