//! CSV recordings: `time_s` plus force and trigger columns, units in the column names.

use crate::recording::{
    force_unit_from_name, time_unit_from_name, ChannelMap, ChannelSpec, Recording,
};
use greybox_core::atomic::write_atomic;
use greybox_core::csvutil::{csv_error, parse_f64_bytes, Header};
use greybox_core::{Error, Result, SourcePos};
use std::io::Write;
use std::path::Path;

/// Read a CSV recording with a channel map.
pub fn read_csv_recording(path: &Path, map: &ChannelMap) -> Result<Recording> {
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    read_csv_recording_from(
        std::io::BufReader::with_capacity(1 << 20, file),
        &path.display().to_string(),
        map,
    )
}

fn force_column(header: &Header, spec: &ChannelSpec, source: &str) -> Result<(usize, f64)> {
    let idx = header.require(&spec.name)?;
    let unit = spec.unit.or_else(|| force_unit_from_name(&spec.name)).ok_or_else(|| {
        Error::input(
            SourcePos::file(source).line(1).field(&spec.name),
            format!(
                "column '{}' has no force unit: name it with a unit suffix (e.g. {}_N) or map it as NAME:UNIT (N, kN, daN, mN, lbf)",
                spec.name, spec.name
            ),
        )
    })?;
    Ok((idx, unit.to_newton() * spec.scale))
}

/// Read a CSV recording from any reader (`source` names it in errors).
pub fn read_csv_recording_from(
    reader: impl std::io::Read,
    source: &str,
    map: &ChannelMap,
) -> Result<Recording> {
    let mut rdr = csv::ReaderBuilder::new()
        .has_headers(true)
        .from_reader(reader);
    let header = Header::new(source, rdr.headers().map_err(|e| csv_error(source, e))?);
    let time = match &map.time {
        Some(name) => {
            let idx = header.require(name)?;
            let unit = map.time_unit.or_else(|| time_unit_from_name(name)).ok_or_else(|| {
                Error::input(
                    SourcePos::file(source).line(1).field(name),
                    format!("time column '{name}' has no unit: name it like time_s / time_ms or map it as time={name}:s"),
                )
            })?;
            Some((idx, unit))
        }
        None => None,
    };
    let (ni, ns) = force_column(&header, &map.normal, source)?;
    let (ti, ts) = force_column(&header, &map.tangential, source)?;
    let radial = map
        .radial
        .as_ref()
        .map(|s| force_column(&header, s, source))
        .transpose()?;
    let trigger = map
        .trigger
        .as_ref()
        .map(|t| header.require(t))
        .transpose()?;

    let mut rec = Recording {
        source: source.to_string(),
        time_s: Vec::new(),
        normal_n: Vec::new(),
        tangential_n: Vec::new(),
        radial_n: radial.map(|_| Vec::new()),
        trigger_v: trigger.map(|_| Vec::new()),
    };
    let names = header.names().to_vec();
    let mut row = csv::ByteRecord::new();
    let mut line: u64 = 1;
    let mut k: u64 = 0;
    loop {
        match rdr.read_byte_record(&mut row) {
            Ok(true) => {}
            Ok(false) => break,
            Err(e) => return Err(csv_error(source, e)),
        }
        line = row.position().map(|p| p.line()).unwrap_or(line + 1);
        let get = |i: usize| parse_f64_bytes(&row[i], source, line, &names[i]);
        match time {
            Some((i, unit)) => rec.time_s.push(get(i)? * unit.to_second()),
            None => rec.time_s.push(k as f64 / sample_rate(map, source)?),
        }
        rec.normal_n.push(get(ni)? * ns);
        rec.tangential_n.push(get(ti)? * ts);
        if let (Some((i, s)), Some(v)) = (radial, rec.radial_n.as_mut()) {
            v.push(get(i)? * s);
        }
        if let (Some(i), Some(v)) = (trigger, rec.trigger_v.as_mut()) {
            v.push(get(i)?);
        }
        k += 1;
    }
    if rec.time_s.windows(2).any(|w| !(w[1] > w[0])) {
        let i = rec
            .time_s
            .windows(2)
            .position(|w| !(w[1] > w[0]))
            .unwrap_or(0)
            + 1;
        let tname = map.time.clone().unwrap_or_default();
        return Err(Error::input(
            SourcePos::file(source).line(i as u64 + 2).field(tname),
            format!(
                "time must increase strictly: {} s follows {} s",
                rec.time_s[i],
                rec.time_s[i - 1]
            ),
        ));
    }
    rec.validate()?;
    Ok(rec)
}

fn sample_rate(map: &ChannelMap, source: &str) -> Result<f64> {
    match map.sample_rate_hz {
        Some(f) if f.is_finite() && f > 0.0 => Ok(f),
        _ => Err(Error::input(
            SourcePos::file(source),
            "no time column mapped and no positive sample_rate_hz given",
        )),
    }
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
        let mut map = ChannelMap {
            radial: None,
            trigger: None,
            ..Default::default()
        };
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
        let e = read(
            &GOOD.replace("radial_force_N", "radial"),
            &ChannelMap::default(),
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("rec.csv, line 1") && e.contains("missing column 'radial_force_N'"),
            "{e}"
        );
    }
    #[test]
    fn unknown_unit() {
        let mut map = ChannelMap {
            normal: ChannelSpec::named("normal_force_kgf"),
            ..Default::default()
        };
        let e = read(&GOOD.replace("normal_force_N", "normal_force_kgf"), &map)
            .unwrap_err()
            .to_string();
        assert!(e.contains("has no force unit"), "{e}");
        let e = map.apply_override("normal=Fz:kgf").unwrap_err().to_string();
        assert!(e.contains("unknown force unit 'kgf'"), "{e}");
    }
    #[test]
    fn malformed_csv() {
        let e = read(&format!("{GOOD}0.003,1.0\n"), &ChannelMap::default())
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("line 5") && e.contains("expected 5 fields, found 2"),
            "{e}"
        );
    }
    #[test]
    fn nan_and_inf() {
        let e = read(&GOOD.replace("0.7", "NaN"), &ChannelMap::default())
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("line 3") && e.contains("tangential_force_N") && e.contains("finite"),
            "{e}"
        );
        let e = read(&GOOD.replace("0.9", "inf"), &ChannelMap::default())
            .unwrap_err()
            .to_string();
        assert!(e.contains("line 4") && e.contains("finite"), "{e}");
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
