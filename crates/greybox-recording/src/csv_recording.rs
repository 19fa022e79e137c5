//! CSV recordings: reading any delimited-text layout (see [`crate::text_table`]) and writing
//! greybox's own (`time_s` plus force and trigger columns, units in the column names).

use crate::readers::recording_with_profile as recording_from_table;
use crate::text_table::parse_text_table;
use crate::{ChannelMap, Recording};
use greybox_core::atomic::write_atomic;
use greybox_core::{Error, Result, SourcePos};
use std::io::{Read, Write};
use std::path::Path;

/// Read a delimited-text recording with a channel map.
pub fn read_csv_recording(path: &Path, map: &ChannelMap) -> Result<Recording> {
    let table = crate::text_table::read_text_table(path, &map.reader.text_options())?;
    recording_from_table(table, map)
}

/// Read a delimited-text recording from any reader (`source` names it in errors).
pub fn read_csv_recording_from(
    reader: impl std::io::Read,
    source: &str,
    map: &ChannelMap,
) -> Result<Recording> {
    let cap = greybox_core::budget::Cap::RecordingBytes;
    let mut bytes = Vec::new();
    reader
        .take(cap.limit().saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(|e| Error::io(source, e))?;
    cap.check(bytes.len() as u64, || {
        format!("the recording is more than {} bytes", cap.limit())
    })
    .map_err(|m| Error::input(SourcePos::file(source), m))?;
    recording_from_table(
        parse_text_table(&bytes, source, &map.reader.text_options())?,
        map,
    )
}

/// Write a recording as CSV (`time_s,normal_force_N,tangential_force_N,radial_force_N,trigger_V`).
pub fn write_csv_recording(path: &Path, rec: &Recording) -> Result<()> {
    write_atomic(path, |w| write_csv_recording_to(w, rec))
}

pub fn write_csv_recording_to(w: &mut dyn Write, rec: &Recording) -> std::io::Result<()> {
    let mut head = String::from("time_s,normal_force_N,tangential_force_N");
    if rec.radial_n.is_some() {
        head.push_str(",radial_force_N");
    }
    if rec.trigger_v.is_some() {
        head.push_str(",trigger_V");
    }
    writeln!(w, "{head}")?;
    let mut line = String::with_capacity(96);
    use std::fmt::Write as _;
    for i in 0..rec.len() {
        line.clear();
        let _ = write!(
            line,
            "{:.4},{:.4},{:.4}",
            rec.time_s[i], rec.normal_n[i], rec.tangential_n[i]
        );
        if let Some(r) = &rec.radial_n {
            let _ = write!(line, ",{:.4}", r[i]);
        }
        if let Some(t) = &rec.trigger_v {
            let _ = write!(line, ",{:.4}", t[i]);
        }
        line.push('\n');
        w.write_all(line.as_bytes())?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn read(text: &str, map: &ChannelMap) -> Result<Recording> {
        read_csv_recording_from(text.as_bytes(), "rec.csv", map)
    }

    const GOOD: &str = "time_s,normal_force_N,tangential_force_N,radial_force_N,trigger_V\n\
                        0.000,1.0,0.5,0.1,0\n0.001,2.0,0.7,0.1,5\n0.002,3.0,0.9,0.1,5\n";

    #[test]
    fn reads_default_layout() {
        let r = read(GOOD, &ChannelMap::default()).unwrap();
        assert_eq!(r.len(), 3);
        assert_eq!(r.tangential_n, vec![0.5, 0.7, 0.9]);
        assert!((r.sample_rate_hz() - 1000.0).abs() < 1e-6);
    }

    #[test]
    fn mapping_with_units_and_scale() {
        let text = "t_ms,Fz,Fx\n0,1.5,-0.2\n1,1.5,-0.3\n";
        let mut map = ChannelMap::default();
        map.apply_override("time=t_ms").unwrap();
        map.apply_override("normal=Fz:kN").unwrap();
        map.apply_override("tangential=Fx:kN:-1").unwrap();
        let r = read(text, &map).unwrap();
        assert_eq!(r.normal_n, vec![1500.0, 1500.0]);
        assert_eq!(r.tangential_n, vec![200.0, 300.0]);
        assert_eq!(r.time_s, vec![0.0, 0.001]);
    }

    // one test per failure class
    #[test]
    fn missing_column() {
        let mut map = ChannelMap::default();
        map.apply_override("radial=radial_force_N").unwrap();
        let e = read(&GOOD.replace("radial_force_N", "radial_F"), &map)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("rec.csv, line 1") && e.contains("missing column 'radial_force_N'"),
            "{e}"
        );
        // not mapped: a missing radial channel is simply absent
        let r = read(
            &GOOD.replace("radial_force_N", "other_N"),
            &ChannelMap::default(),
        )
        .unwrap();
        assert!(r.radial_n.is_none());
        let e = read("time_s,Fz_N\n0,1\n1,2\n2,3\n", &ChannelMap::default())
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("tangential: no friction force") && e.contains("`map` tangential=NAME:N"),
            "{e}"
        );
    }
    #[test]
    fn unknown_unit() {
        let mut map = ChannelMap::default();
        let e = read(&GOOD.replace("normal_force_N", "normal_force [tonf]"), &map)
            .unwrap_err()
            .to_string();
        assert!(e.contains("unknown force unit 'tonf'"), "{e}");
        let e = read(&GOOD.replace("normal_force_N", "normal_force"), &map)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("states no unit") && e.contains("`map` normal="),
            "{e}"
        );
        let e = map
            .apply_override("normal=Fz:tonf")
            .unwrap_err()
            .to_string();
        assert!(e.contains("unknown force unit 'tonf'"), "{e}");
    }
    #[test]
    fn one_column_two_roles() {
        let mut map = ChannelMap::default();
        map.apply_override("tangential=normal_force_N").unwrap();
        let e = read(GOOD, &map).unwrap_err().to_string();
        assert!(e.contains("cannot be two roles"), "{e}");
    }
    #[test]
    fn time_restarting_per_step() {
        let text = "Step,Time (s),Fz (N),Fx (N)\n1,0,10,4\n1,0.1,10,4\n2,0,10,4\n2,0.1,10,4\n";
        let r = read(text, &ChannelMap::default()).unwrap();
        assert_eq!(r.time_s, vec![0.0, 0.1, 0.2, 0.30000000000000004]);
        let notes = &r.provenance.as_ref().unwrap().notes;
        assert!(notes[0].contains("restarts at 1 step change"), "{notes:?}");
        let e = read(&text.replace("Step", "Stp"), &ChannelMap::default())
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 4") && e.contains("`map` step="), "{e}");
    }
    #[test]
    fn malformed_csv() {
        let e = read(
            &format!("{GOOD}0.003,1.0,4,5\n0.004,1,1,1,1\n"),
            &ChannelMap::default(),
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("line 5") && e.contains("expected 5 fields, found 4"),
            "{e}"
        );
    }
    #[test]
    fn nan_and_inf() {
        let e = read(&GOOD.replace("0.7", "NaN"), &ChannelMap::default())
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("line 3") && e.contains("tangential_force_N") && e.contains("'NaN'"),
            "{e}"
        );
        let e = read(&GOOD.replace("0.9", "inf"), &ChannelMap::default())
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 4") && e.contains("'inf'"), "{e}");
        let e = read(&GOOD.replace("0.9", "abc"), &ChannelMap::default())
            .unwrap_err()
            .to_string();
        assert!(e.contains("expected a number, found 'abc'"), "{e}");
    }
    #[test]
    fn time_not_increasing() {
        let e = read(&GOOD.replace("0.002,", "0.001,"), &ChannelMap::default())
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("line 4") && e.contains("increase strictly"),
            "{e}"
        );
    }
    #[test]
    fn write_read_round_trip() {
        let r = read(GOOD, &ChannelMap::default()).unwrap();
        let mut buf = Vec::new();
        write_csv_recording_to(&mut buf, &r).unwrap();
        let back = read(std::str::from_utf8(&buf).unwrap(), &ChannelMap::default()).unwrap();
        assert_eq!(back.normal_n, r.normal_n);
        assert_eq!(back.trigger_v, r.trigger_v);
    }
}
