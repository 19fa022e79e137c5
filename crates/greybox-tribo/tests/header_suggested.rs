//! A garbled preamble line is never taken as the header in silence when another line names the
//! columns (issue 58, messages): generated exports with the line that names the columns above
//! a line that does not (a separator, mojibake, an operator's note with as many fields), or
//! above a block of numeric settings rows. The read is refused, the refusal names the line
//! that names the columns as `header_line` N, and with that setting the same file reads with
//! every channel taken from a column of that line.

use greybox_recording::readers::read_recording;
use greybox_recording::ChannelMap;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// A random choice among `options`.
fn pick<'a>(rng: &mut ChaCha8Rng, options: &[&'a str]) -> &'a str {
    options[rng.gen_range(0..options.len())]
}

/// What lies between the header that names the columns and the data.
#[derive(Debug, Clone, Copy)]
enum Garble {
    /// A line of dashes or equals signs, one per column.
    Separator,
    /// Words with as many fields as the data (an operator's note, a channel description).
    Words,
    /// Latin-1 bytes read as UTF-8 and control characters, as many fields as the data.
    Mojibake,
}

/// One generated export: its bytes and the 1-based line of the header that names the columns.
struct Export {
    bytes: Vec<u8>,
    header_line: u64,
    garble: Garble,
    names: [String; 3],
}

fn export(seed: u64) -> Export {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (delim, decimal_comma) = match rng.gen_range(0..4) {
        0 => (",", false),
        1 => (";", false),
        2 => (";", true),
        _ => ("\t", false),
    };
    let eol = if rng.gen_bool(0.5) { "\r\n" } else { "\n" };
    let names = [
        pick(&mut rng, &["Time (s)", "time_s", "t [s]", "Time [s]"]).to_string(),
        pick(
            &mut rng,
            &["Fz (N)", "Normal force (N)", "Fn_N", "Load [N]"],
        )
        .to_string(),
        pick(
            &mut rng,
            &["Fx (N)", "Friction force (N)", "Ft_N", "Ff [N]"],
        )
        .to_string(),
    ];
    let mut text = String::new();
    for k in 0..rng.gen_range(0..4) {
        text.push_str(&format!("Instrument note {k}: virtual rig {seed}{eol}"));
    }
    let header_line = text.matches(eol).count() as u64 + 1;
    text.push_str(&names.join(delim));
    text.push_str(eol);
    let garble = match rng.gen_range(0..3) {
        0 => Garble::Separator,
        1 => Garble::Words,
        _ => Garble::Mojibake,
    };
    let fields: Vec<String> = (0..names.len())
        .map(|k| match garble {
            Garble::Separator => pick(&mut rng, &["-----", "=====", "~~~"]).to_string(),
            Garble::Words => format!("{} {k}", pick(&mut rng, &["channel", "operator", "batch"])),
            Garble::Mojibake => format!("Ã©Â{}\u{7f}x{k}", pick(&mut rng, &["?", "¤", "#"])),
        })
        .collect();
    text.push_str(&fields.join(delim));
    text.push_str(eol);
    let dt = rng.gen_range(0.001..0.02);
    let load = rng.gen_range(2.0..50.0);
    let mu = rng.gen_range(0.1..0.8);
    for i in 0..400 {
        let t = i as f64 * dt;
        let row = [t, load, mu * load * (1.0 + 0.01 * (i % 7) as f64)]
            .map(|v| {
                let s = format!("{v:.5}");
                if decimal_comma {
                    s.replace('.', ",")
                } else {
                    s
                }
            })
            .join(delim);
        text.push_str(&row);
        text.push_str(eol);
    }
    Export {
        bytes: text.into_bytes(),
        header_line,
        garble,
        names,
    }
}

#[test]
fn the_line_that_names_the_columns_is_suggested_and_reads() {
    let dir = tempfile::tempdir().unwrap();
    for seed in 0..60 {
        let e = export(seed);
        let path = dir.path().join(format!("export-{seed}.csv"));
        std::fs::write(&path, &e.bytes).unwrap();
        let err = read_recording(&path, &ChannelMap::default())
            .map(|r| r.len())
            .expect_err(&format!(
                "seed {seed} ({:?}): a garbled line above the data was read as the header",
                e.garble
            ))
            .to_string();
        let wanted = format!("`header_line` {}", e.header_line);
        assert!(
            err.contains(&wanted) && err.contains(&path.display().to_string()),
            "seed {seed} ({:?}): the refusal does not point to line {}: {err}",
            e.garble,
            e.header_line
        );
        let mut map = ChannelMap::default();
        map.reader.header_line = Some(e.header_line);
        let rec = read_recording(&path, &map).unwrap_or_else(|e| panic!("seed {seed}: {e}"));
        assert_eq!(rec.len(), 400, "seed {seed}");
        let report = rec.provenance.as_ref().expect("a read report");
        assert_eq!(report.columns.len(), 3, "seed {seed}: {:?}", report.columns);
        assert!(
            report
                .columns
                .iter()
                .all(|c| e.names.iter().any(|n| n.starts_with(&c.column))),
            "seed {seed}: {:?} against {:?}",
            report.columns,
            e.names
        );
    }
}

#[test]
fn a_block_of_settings_rows_above_the_named_header_is_pointed_out() {
    let dir = tempfile::tempdir().unwrap();
    for (seed, delim) in [(1u64, ","), (2, ";"), (3, "\t")] {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut text = format!("garbled{delim}@@{delim}##\n");
        let settings = rng.gen_range(2..6);
        for k in 0..settings {
            text.push_str(&format!("{k}{delim}{}{delim}{}\n", k * 2, k * 3));
        }
        let header_line = settings + 2;
        text.push_str(&format!("Time (s){delim}Fz (N){delim}Fx (N)\n"));
        for i in 0..200 {
            text.push_str(&format!(
                "{}{delim}10{delim}3.{}\n",
                i as f64 * 0.01,
                i % 10
            ));
        }
        let path = dir.path().join(format!("blocks-{seed}.csv"));
        std::fs::write(&path, text).unwrap();
        let err = read_recording(&path, &ChannelMap::default())
            .map(|r| r.len())
            .expect_err("the settings block's first line is no header of the data")
            .to_string();
        assert!(
            err.contains(&format!("`header_line` {header_line}")),
            "seed {seed}: {err}"
        );
        let mut map = ChannelMap::default();
        map.reader.header_line = Some(header_line as u64);
        assert_eq!(read_recording(&path, &map).unwrap().len(), 200);
    }
}
