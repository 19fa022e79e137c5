//! Text layouts of real rig exports (the corpus in ../shared/data/real-rigs; SOURCES.md and
//! manifest.toml in tests/data/real-rigs): each file is read by the reader and checked against what this test finds in the
//! file's bytes on its own (line splitting, header names, data lines, first and last values).

use greybox_recording::readers::RecordingFormat;
use greybox_recording::table::Table;
use greybox_recording::text_table::{read_text_table, TextOptions};

#[path = "../../../tests/support/real_rigs.rs"]
mod real_rigs;

/// The corpus directory with a trailing slash (the raw exports live outside the project, in
/// `../shared/data/real-rigs`; see `real_rigs_dir`).
fn dir() -> String {
    let d = real_rigs::real_rigs_dir().expect("checked by the test");
    format!("{}/", d.display())
}

/// The file's lines, whatever the line ends (CRLF, LF or bare CR), without a final empty one.
fn lines_of(path: &str) -> Vec<String> {
    let bytes = std::fs::read(format!("{}{path}", dir())).unwrap();
    let text: String = bytes.iter().map(|&b| b as char).collect(); // latin-1
    let mut lines: Vec<String> = text
        .replace("\r\n", "\n")
        .replace('\r', "\n")
        .split('\n')
        .map(str::to_string)
        .collect();
    if lines.last().is_some_and(|l| l.is_empty()) {
        lines.pop();
    }
    lines
}

fn fields(line: &str, delim: char) -> Vec<String> {
    line.split(delim).map(|f| f.trim().to_string()).collect()
}

fn number(field: &str, decimal_comma: bool) -> Option<f64> {
    let f = if decimal_comma {
        field.replace(',', ".")
    } else {
        field.to_string()
    };
    f.parse::<f64>().ok()
}

fn read(path: &str) -> Table {
    let p = std::path::PathBuf::from(format!("{}{path}", dir()));
    assert_eq!(
        RecordingFormat::of_path(&p),
        Some(RecordingFormat::Csv),
        "{path}"
    );
    read_text_table(&p, &TextOptions::default()).unwrap_or_else(|e| panic!("{path}: {e}"))
}

/// Check one table against the header line and data lines found independently: row count,
/// the columns kept (the named or unnamed ones with at least one value), their headers, and
/// the first and last value of every numeric column.
fn check_table(t: &Table, header: &str, data: &[&String], delim: char, dc: bool, what: &str) {
    let mut names = fields(header, delim);
    while names.last().is_some_and(|n| n.is_empty()) {
        names.pop();
    }
    let rows: Vec<Vec<String>> = data.iter().map(|l| fields(l, delim)).collect();
    let kept: Vec<usize> = (0..names.len())
        .filter(|&k| rows.iter().any(|r| r.get(k).is_some_and(|f| !f.is_empty())))
        .collect();
    assert_eq!(t.rows, rows.len(), "{what}: rows");
    assert_eq!(t.columns.len(), kept.len(), "{what}: columns");
    let positions: Vec<usize> = kept.iter().map(|k| k + 1).collect();
    assert_eq!(t.positions, positions, "{what}: positions");
    for (col, &k) in t.columns.iter().zip(&kept) {
        assert_eq!(col.header, names[k], "{what}: header of column {}", k + 1);
        let (first, last) = (&rows[0][k], &rows[rows.len() - 1][k]);
        if let (Some(a), Some(b)) = (number(first, dc), number(last, dc)) {
            if rows.iter().all(|r| number(&r[k], dc).is_some()) {
                let v = col.values(&t.source).unwrap();
                assert_eq!((v[0], v[v.len() - 1]), (a, b), "{what}: {}", col.header);
            }
        }
    }
}

/// A single table: header on 0-based line `h`, `footer` lines at the end.
fn check_single(path: &str, h: usize, footer: usize, delim: char, dc: bool) -> Table {
    let lines = lines_of(path);
    let data: Vec<&String> = lines[h + 1..lines.len() - footer]
        .iter()
        .filter(|l| !l.trim().is_empty())
        .collect();
    let t = read(path);
    assert_eq!(t.header_line, h as u64 + 1, "{path}");
    check_table(&t, &lines[h], &data, delim, dc, path);
    assert!(t.block_starts.is_empty(), "{path}");
    let footer_lines = lines[lines.len() - footer..]
        .iter()
        .filter(|l| !l.trim().is_empty())
        .count();
    assert_eq!(t.footer.len(), footer_lines, "{path}");
    t
}

#[test]
fn phoenix_te67_compend() {
    if real_rigs::real_rigs_dir().is_none() {
        return;
    }
    for f in [
        "PPS_60N_1.tsv",
        "PPS_100N_1.tsv",
        "PPS+30PTFE_100N_200RPM_30MINS_1.tsv",
    ] {
        let t = check_single(&format!("phoenix-te/{f}"), 15, 1, '\t', true);
        // the empty leading column is left out; the repeated `Friction Force` is told apart
        let ff: Vec<usize> = (0..t.columns.len())
            .filter(|&k| t.columns[k].header == "Friction Force")
            .collect();
        assert_eq!(ff.len(), 2, "{f}");
        assert_eq!(t.columns[ff[1]].name, "Friction Force #2");
        assert!(t
            .column_label(ff[0])
            .ends_with("the first of 2 with that name"));
        assert!(
            t.notes.iter().any(|n| n.contains("Friction Force")),
            "{:?}",
            t.notes
        );
        assert!(t.layout.contains("decimal comma"), "{}", t.layout);
    }
}

#[test]
fn pin_on_disc_dwf_bare_cr() {
    if real_rigs::real_rigs_dir().is_none() {
        return;
    }
    for f in [
        "9-Al10Cu-50N-140m-328.dwf",
        "1-2-MoS2-2.5-Al2O3-Al10Cu-50N-130m-353.dwf",
        "3-2-MoS2-7.5-Al2O3-Al10Cu-50N-.dwf",
    ] {
        let t = check_single(&format!("custom-pod-dwf/{f}"), 0, 0, ';', true);
        assert_eq!(t.columns.len(), 2);
        assert_eq!(
            (t.columns[0].name.as_str(), t.columns[1].name.as_str()),
            ("TIME", "FF")
        );
        assert!(t.layout.contains("CR line ends"), "{}", t.layout);
    }
}

#[test]
fn pcs_mtm_single_step() {
    if real_rigs::real_rigs_dir().is_none() {
        return;
    }
    for f in ["demo_7.txt", "demo_8.txt", "demo_5.txt"] {
        let t = check_single(&format!("pcs-mtm/{f}"), 13, 2, '\t', false);
        let tf = t
            .columns
            .iter()
            .position(|c| c.header == "Traction Force (N)")
            .unwrap();
        assert_eq!(t.columns[tf].unit.as_deref(), Some("N"));
        assert_eq!(
            t.columns
                .iter()
                .filter(|c| c.header == "Step Time (s)")
                .count(),
            2
        );
        assert!(
            t.columns.iter().all(|c| !c.name.starts_with("column ")),
            "{f}"
        );
    }
}

#[test]
fn pcs_mtm_profile_of_blocks() {
    if real_rigs::real_rigs_dir().is_none() {
        return;
    }
    let path = "pcs-mtm/demo-mtm-output.txt";
    let lines = lines_of(path);
    let headers: Vec<usize> = (0..lines.len())
        .filter(|&i| lines[i].starts_with("Step Time (s)\t"))
        .collect();
    assert_eq!(headers.len(), 24, "the manifest's 24 BOD_TIMED steps");
    // each block: the lines after its header up to the first blank one
    let mut data: Vec<&String> = Vec::new();
    let mut starts = Vec::new();
    let mut step_of_block = Vec::new();
    for &h in &headers {
        starts.push(data.len());
        data.extend(lines[h + 1..].iter().take_while(|l| !l.trim().is_empty()));
        let step = (0..h)
            .rev()
            .find(|&i| lines[i].starts_with("Step ") && lines[i].contains(" started at "))
            .unwrap();
        step_of_block.push(lines[step].clone());
    }
    let t = read(path);
    check_table(&t, &lines[headers[0]], &data, '\t', false, path);
    assert_eq!(t.block_starts, starts);
    assert_eq!(t.block_preambles.len(), 24);
    for (b, step) in step_of_block.iter().enumerate().skip(1) {
        assert!(
            t.block_preambles[b].contains(&step.trim().to_string()),
            "block {b}: {:?}",
            t.block_preambles[b]
        );
    }
    // step time restarts in every block
    let time = t.columns[0].values(&t.source).unwrap();
    for &s in &t.block_starts {
        let first = data[s].split('\t').next().unwrap().parse::<f64>().unwrap();
        assert_eq!(time[s], first);
        assert!(s == 0 || time[s] < time[s - 1]);
    }
    assert!(t
        .footer
        .iter()
        .any(|(_, l)| l.starts_with("All steps completed")));
}
