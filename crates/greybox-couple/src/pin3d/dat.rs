//! Reading a pin run's CalculiX `.dat` file: per increment, the pin's total reaction force
//! and the contact statistics.

use greybox_core::{Error, Result, SourcePos};

/// One printed increment.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Increment {
    /// Total time: 0–1 the press, 1–2 the slide.
    pub time: f64,
    /// Reaction force on the pin nodes (fx, fy, fz), N (half model).
    pub force: [f64; 3],
    /// Contact area, mm² (half model; 0 when no contact statistics were printed).
    pub contact_area: f64,
}

fn numbers(line: &str) -> Option<Vec<f64>> {
    line.split_whitespace()
        .map(|t| t.parse::<f64>().ok())
        .collect()
}

/// The increments of `text` (the file `source`), in order.
pub fn parse(text: &str, source: &str) -> Result<Vec<Increment>> {
    let lines: Vec<&str> = text.lines().collect();
    let bad = |i: usize, what: &str| {
        Error::input(
            SourcePos::file(source).line((i + 1) as u64),
            format!("expected {what} in the CalculiX output"),
        )
    };
    // the first non-blank line after i, as numbers
    let values = |i: usize, n: usize, what: &str| -> Result<Vec<f64>> {
        let (k, l) = lines
            .iter()
            .enumerate()
            .skip(i + 1)
            .find(|(_, l)| !l.trim().is_empty())
            .ok_or_else(|| bad(i, what))?;
        match numbers(l) {
            Some(v) if v.len() >= n && v.iter().all(|x| x.is_finite()) => Ok(v),
            _ => Err(bad(k, what)),
        }
    };
    let time_of = |i: usize, l: &str| -> Result<f64> {
        l.split_whitespace()
            .last()
            .and_then(|t| t.parse::<f64>().ok())
            .ok_or_else(|| bad(i, "a time at the end of the line"))
    };
    let mut out: Vec<Increment> = Vec::new();
    let mut stats_time = f64::NAN;
    for (i, l) in lines.iter().enumerate() {
        if l.contains("total force (fx,fy,fz) for set NPIN and time") {
            let v = values(i, 3, "three force components")?;
            out.push(Increment {
                time: time_of(i, l)?,
                force: [v[0], v[1], v[2]],
                contact_area: 0.0,
            });
        } else if l.contains("statistics for slave set") {
            stats_time = time_of(i, l)?;
        } else if l.contains("area,  normal force") {
            let v = values(i, 3, "area, normal force and shear force")?;
            if let Some(inc) = out.iter_mut().rev().find(|x| x.time == stats_time) {
                inc.contact_area = v[0];
            }
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    const DAT: &str = "
 total force (fx,fy,fz) for set NPIN and time  0.1000000E+01

        9.555770E-15  2.409551E+01 -1.858746E+03


 statistics for slave set SDISK, master set SPIN and time  0.1000000E+01

   total surface force (fx,fy,fz) and moment about the origin (mx,my,mz)

    1.5E-02  1.1E+00 -9.4E+01 -8.3E+00  2.5E-01  5.3E-04

   area,  normal force (+ = tension) and shear force (size)

    5.505563E-01 -1.858539E+03  3.486697E+00
 total force (fx,fy,fz) for set NPIN and time  0.1500000E+01

        6.0E+02  3.0E+01 -2.0E+03
";

    #[test]
    fn forces_and_areas_are_read_per_increment() {
        let v = parse(DAT, "pin.dat").unwrap();
        assert_eq!(v.len(), 2);
        assert_eq!(v[0].time, 1.0);
        assert_eq!(v[0].force[2], -1.858746e3);
        assert_eq!(v[0].contact_area, 0.5505563);
        assert_eq!(
            (v[1].time, v[1].force[0], v[1].contact_area),
            (1.5, 600.0, 0.0)
        );
    }

    #[test]
    fn a_truncated_file_names_its_line() {
        let e = parse(
            " total force (fx,fy,fz) for set NPIN and time  0.1E+01\n\n  1.0 abc 2.0\n",
            "p.dat",
        )
        .unwrap_err()
        .to_string();
        assert!(
            e.contains("p.dat") && e.contains("line 3") && e.contains("force"),
            "{e}"
        );
    }
}
