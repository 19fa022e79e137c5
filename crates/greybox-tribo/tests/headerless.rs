//! Logs without a header line (DAQ and microcontroller exports of numbers only), columns by
//! number (`#K`) or by `--columns` names, formats told by content, and the messages that say
//! how to map. Every file is written here from known values and read back through
//! `read_recording`; expected values are the ones written, in SI.

use greybox_recording::readers::{read_recording, read_table, RecordingFormat};
use greybox_recording::{ChannelMap, ReaderOptions};
use std::path::PathBuf;

/// Rows of (time s, normal N, friction N) written to every log.
const ROWS: [[f64; 3]; 5] = [
    [0.0, 12.5, 3.25],
    [0.01, 12.0, 3.5],
    [0.02, 12.25, 3.75],
    [0.03, 12.5, 3.5],
    [0.04, 12.75, 3.25],
];

/// Write `ROWS` (or only its force columns) with `delim`, decimal comma when `dc`.
fn log_text(delim: &str, dc: bool, with_time: bool) -> String {
    let mut text = String::new();
    for r in ROWS {
        let fields: Vec<String> = r[usize::from(!with_time)..]
            .iter()
            .map(|v| {
                let s = format!("{v:.2}");
                if dc {
                    s.replace('.', ",")
                } else {
                    s
                }
            })
            .collect();
        text.push_str(&fields.join(delim));
        text.push('\n');
    }
    text
}

fn write(dir: &tempfile::TempDir, name: &str, text: &[u8]) -> PathBuf {
    let p = dir.path().join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn map_of(flags: &[&str]) -> ChannelMap {
    let mut map = ChannelMap::default();
    for f in flags {
        map.apply_override(f).unwrap();
    }
    map
}

fn column(k: usize) -> Vec<f64> {
    ROWS.iter().map(|r| r[k]).collect()
}

#[test]
fn comma_log_mapped_by_column_number() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(&dir, "log.csv", log_text(",", false, true).as_bytes());
    let map = map_of(&["time=#1:s", "normal=#2:N", "tangential=#3:kN"]);
    let rec = read_recording(&p, &map).unwrap();
    assert_eq!(rec.time_s, column(0));
    assert_eq!(rec.normal_n, column(1));
    let kn: Vec<f64> = column(2).iter().map(|v| v * 1000.0).collect();
    assert_eq!(rec.tangential_n, kn);
    let report = rec.provenance.unwrap();
    assert!(
        report.layout.contains("no header line"),
        "{}",
        report.layout
    );
    assert_eq!(report.columns[1].column, "#2");
}

#[test]
fn semicolon_decimal_comma_without_time_named_by_columns() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(&dir, "log.txt", log_text(";", true, false).as_bytes());
    let mut map = ChannelMap {
        reader: ReaderOptions {
            columns: vec!["Fn_N".into(), "Ft_N".into()],
            ..Default::default()
        },
        sample_rate_hz: Some(100.0),
        ..Default::default()
    };
    let rec = read_recording(&p, &map).unwrap();
    assert_eq!(rec.normal_n, column(1));
    assert_eq!(rec.tangential_n, column(2));
    // time = k / fs
    let want: Vec<f64> = (0..5).map(|k| k as f64 * 0.01).collect();
    assert_eq!(rec.time_s, want);
    // without the sample rate, the error says how to give one
    map.sample_rate_hz = None;
    let e = read_recording(&p, &map).unwrap_err().to_string();
    assert!(e.contains("`sample_rate_hz`"), "{e}");
}

#[test]
fn tab_log_named_by_columns_and_by_number_alike() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(&dir, "log.tsv", log_text("\t", false, true).as_bytes());
    let named = ChannelMap {
        reader: ReaderOptions {
            columns: vec!["t_s".into(), "Fn_N".into(), "Ft_N".into()],
            ..Default::default()
        },
        ..Default::default()
    };
    let a = read_recording(&p, &named).unwrap();
    let b = read_recording(
        &p,
        &map_of(&["time=#1:s", "normal=#2:N", "tangential=#3:N"]),
    )
    .unwrap();
    assert_eq!(a.time_s, column(0));
    assert_eq!(a.tangential_n, column(2));
    assert_eq!((a.time_s, a.normal_n), (b.time_s, b.normal_n));
    // `#K` still finds a column after `--columns` named it
    let mut both = map_of(&["normal=#2"]);
    both.reader.columns = named.reader.columns.clone();
    assert_eq!(read_recording(&p, &both).unwrap().normal_n, column(1));
    // more names than columns, or a name twice, are errors naming the setting
    let mut bad = named.clone();
    bad.reader.columns.push("extra".into());
    let e = read_recording(&p, &bad).unwrap_err().to_string();
    assert!(
        e.contains("4 names given") && e.contains("3 columns"),
        "{e}"
    );
    bad.reader.columns = vec!["a".into(), "a".into()];
    let e = read_recording(&p, &bad).unwrap_err().to_string();
    assert!(e.contains("'a' is given twice"), "{e}");
}

#[test]
fn columns_rename_a_file_with_a_header_too() {
    let dir = tempfile::tempdir().unwrap();
    let text = format!("a,b,c\n{}", log_text(",", false, true));
    let p = write(&dir, "run.csv", text.as_bytes());
    let map = ChannelMap {
        reader: ReaderOptions {
            columns: vec!["time (s)".into(), "Fz (N)".into(), "Fx (N)".into()],
            ..Default::default()
        },
        ..Default::default()
    };
    let rec = read_recording(&p, &map).unwrap();
    assert_eq!(rec.normal_n, column(1));
}

#[test]
fn unresolved_headerless_log_lists_columns_with_samples() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(&dir, "log.csv", log_text(",", false, true).as_bytes());
    let e = read_recording(&p, &ChannelMap::default())
        .unwrap_err()
        .to_string();
    for want in [
        "without a header line",
        "#1: 0, 0.01, 0.02, 0.03, … (increasing: time?)",
        "#2: 12.5, 12, 12.25, 12.5, …",
        "#3: 3.25, 3.5, 3.75, 3.5, …",
        "`map` 'normal=#K:N'",
        "`map` 'time=#1:s'",
        "`columns`",
        "`sample_rate_hz`",
    ] {
        assert!(e.contains(want), "missing '{want}' in:\n{e}");
    }
    // a column number the file does not have
    let e = read_recording(&p, &map_of(&["normal=#7:N"]))
        .unwrap_err()
        .to_string();
    assert!(e.contains("'#7'") && e.contains("#1 to #3"), "{e}");
    assert!(!e.contains("line 0"), "{e}");
}

#[test]
fn format_from_content_not_name() {
    let dir = tempfile::tempdir().unwrap();
    let text = log_text(",", false, true);
    let map = map_of(&["time=#1:s", "normal=#2:N", "tangential=#3:N"]);
    for name in ["log", "log.log", "capture.out", "export.xls"] {
        let p = write(&dir, name, text.as_bytes());
        assert_eq!(RecordingFormat::detect(&p).unwrap(), RecordingFormat::Csv);
        let rec = read_recording(&p, &map).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(rec.normal_n, column(1), "{name}");
    }
    let signatures: [(&[u8], RecordingFormat); 4] = [
        (b"TDSm\x69\x12\x00\x00", RecordingFormat::Tdms),
        (b"PK\x03\x04\x14\x00", RecordingFormat::Spreadsheet),
        (
            &[0xD0, 0xCF, 0x11, 0xE0, 0xA1, 0xB1],
            RecordingFormat::Spreadsheet,
        ),
        (b"\xEF\xBB\xBFt;F\n", RecordingFormat::Csv),
    ];
    for (head, want) in signatures {
        assert_eq!(RecordingFormat::of_content(head), Some(want), "{head:?}");
        let p = write(&dir, "noext", head);
        assert_eq!(RecordingFormat::detect(&p).unwrap(), want);
    }
    // binary content of no known kind: a known name goes to its reader, which refuses it
    // with the file named; without a known name the format is unknown
    let p = write(&dir, "data.csv", &[0u8, 1, 2, 3, 0, 0, 7]);
    assert_eq!(RecordingFormat::detect(&p).unwrap(), RecordingFormat::Csv);
    let e = read_table(&p, &ChannelMap::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("data.csv"), "{e}");
    let p = write(&dir, "data.bin", &[0u8, 1, 2, 3, 0, 0, 7]);
    let e = read_table(&p, &ChannelMap::default())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("data.bin") && e.contains("unknown recording format"),
        "{e}"
    );
    // where the content tells nothing, a text name sends it to the text reader, which says why
    let p = write(&dir, "data.csv", &[0u8, 1, 2, 3, 0, 0, 7]);
    assert_eq!(RecordingFormat::detect(&p).unwrap(), RecordingFormat::Csv);
    assert!(read_table(&p, &ChannelMap::default()).is_err());
    // JSON and XML side files are text, but no recording
    for (name, text, what) in [
        ("run.provenance.json", "{\n  \"a\": 1\n}\n", "JSON text"),
        ("plot.svg", "<svg></svg>\n", "XML or HTML text"),
    ] {
        let p = write(&dir, name, text.as_bytes());
        let e = read_table(&p, &ChannelMap::default())
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("unknown recording format") && e.contains(what),
            "{e}"
        );
    }
}

#[test]
fn cof_column_is_never_offered_as_a_force() {
    let dir = tempfile::tempdir().unwrap();
    // a friction coefficient under a name the friction-force search would take
    let p = write(
        &dir,
        "cof.csv",
        b"Time (s),Load (N),Friction (-)\n0,10,0.2\n1,10,0.21\n2,10,0.22\n",
    );
    let e = read_recording(&p, &ChannelMap::default())
        .unwrap_err()
        .to_string();
    assert!(!e.contains("tangential=Friction"), "{e}");
    assert!(e.contains("`map` cof=Friction"), "{e}");
    // an unusual COF name is not among the force candidates, and is offered as cof
    let p = write(
        &dir,
        "cof2.csv",
        b"Time (s),Load (N),COF avg,Temp (K)\n0,10,0.2,300\n1,10,0.21,300\n2,10,0.22,300\n",
    );
    let e = read_recording(&p, &ChannelMap::default())
        .unwrap_err()
        .to_string();
    assert!(e.contains("candidates: 'Temp (K)'"), "{e}");
    assert!(e.contains("`map` 'cof=COF avg'"), "{e}");
    let rec = read_recording(&p, &map_of(&["cof=COF avg"])).unwrap();
    assert!((rec.tangential_n[2] - 2.2).abs() < 1e-12);
}

#[test]
fn missing_speed_note_names_the_constant_velocity_flag() {
    let dir = tempfile::tempdir().unwrap();
    let p = write(
        &dir,
        "run.csv",
        b"Time (s),Fz (N),Fx (N)\n0,10,2\n1,10,2\n2,10,2\n",
    );
    let rec = read_recording(&p, &ChannelMap::default()).unwrap();
    let notes = rec.provenance.unwrap().notes;
    assert!(
        notes
            .iter()
            .any(|n| n.contains("`constant_sliding_velocity_m_per_s`")),
        "{notes:?}"
    );
    // not when the user said the file has no speed, nor when a constant is given
    let rec = read_recording(&p, &map_of(&["speed="])).unwrap();
    assert!(rec.provenance.unwrap().notes.is_empty());
}

#[test]
fn micron_spellings_and_latin1_micro_sign() {
    let dir = tempfile::tempdir().unwrap();
    for unit in ["microns", "micron", "um", "µm"] {
        let text =
            format!("Time (s),Fz (N),Fx (N),Position ({unit})\n0,10,2,5\n1,10,2,10\n2,10,2,5\n");
        let p = write(&dir, "recip.csv", text.as_bytes());
        let rec = read_recording(&p, &map_of(&["position=Position"])).unwrap();
        let x = rec.position_m.unwrap()[1];
        assert!((x - 10e-6).abs() < 1e-18, "{unit}: {x}");
    }
    // µ as the single Latin-1 byte 0xB5
    let mut bytes = b"Time (s);Fz (N);Fx (N);Position (".to_vec();
    bytes.push(0xB5);
    bytes.extend_from_slice(b"m)\n0;10;2;5\n1;10;2;10\n2;10;2;5\n");
    let p = write(&dir, "recip_latin1.txt", &bytes);
    let rec = read_recording(&p, &map_of(&["position=Position"])).unwrap();
    assert!((rec.position_m.unwrap()[1] - 10e-6).abs() < 1e-18);
}

#[test]
fn quoted_headers_and_values_with_the_delimiter() {
    let dir = tempfile::tempdir().unwrap();
    let text = "\"Time, s\",\"Load, N\",\"Friction, N\"\n\"0,0\",\"10,5\",\"1,5\"\n\"0,1\",\"10,5\",\"1,25\"\n\"0,2\",\"10,5\",\"1,0\"\n";
    let p = write(&dir, "quoted.csv", text.as_bytes());
    // `Load, N` is the name Load in N: found by its usual name, unit from the header
    let rec = read_recording(&p, &ChannelMap::default()).unwrap();
    let report = rec.provenance.as_ref().unwrap();
    assert_eq!(report.columns[1].column, "Load, N");
    assert_eq!(report.columns[1].unit, "N");
    assert_eq!(rec.time_s, [0.0, 0.1, 0.2]);
    assert_eq!(rec.normal_n, [10.5; 3]);
    assert_eq!(rec.tangential_n, [1.5, 1.25, 1.0]);
}

/// A rig that logs only its μ, one number per line, with or without a header: read with the
/// sample rate and the dead weight stated, F_t = μ·F_N; without them, the error names both.
#[test]
fn a_one_column_cof_log_reads_with_its_rate_and_load() {
    let dir = tempfile::tempdir().unwrap();
    let mu = [0.31, 0.32, 0.30, 0.33];
    for (name, head) in [("cof.csv", "COF\r\n"), ("mu.txt", "")] {
        let text: String =
            head.to_string() + &mu.iter().map(|m| format!("{m}\r\n")).collect::<String>();
        let p = write(&dir, name, text.as_bytes());
        let map = ChannelMap {
            sample_rate_hz: Some(50.0),
            constant_normal_n: Some(10.0),
            ..map_of(if head.is_empty() { &["cof=#1"] } else { &[] })
        };
        let rec = read_recording(&p, &map).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(rec.normal_n, [10.0; 4], "{name}");
        let ft: Vec<f64> = mu.iter().map(|m| m * 10.0).collect();
        assert_eq!(rec.tangential_n, ft, "{name}");
        assert_eq!(rec.time_s, [0.0, 0.02, 0.04, 0.06], "{name}");
        let e = read_recording(&p, &map_of(&[])).unwrap_err().to_string();
        assert!(
            e.contains("sample_rate_hz") && e.contains("constant_normal_force_N"),
            "{name}: {e}"
        );
    }
}
