//! Hostile and careless input (issue 30): every case runs the binary under an address-space
//! and a wall-clock limit (`greybox_limited`), must be refused cleanly with the file or field,
//! the cap and the option that raises it named (`refused_with`), and must leave nothing
//! behind. Before the fixes these were killed (`base = "/dev/zero"`, 10⁷ cases, a 2.9 TB
//! particle lattice, 80 M UBJSON nulls, a 3 GB xlsx sheet) or turned a value into a shell
//! command (the Slurm script).
mod common;
use common::{coarse_config, greybox_limited, listing, ok, refused_with};
use std::io::Write;
use std::path::Path;

/// Address-space limit of every run, MiB: far below what any fault asked for, with room
/// for the runtime's thread stacks and allocator arenas.
const MEMORY_MIB: u64 = 2048;
/// Wall-clock limit of every run, s.
const SECONDS: u64 = 60;

fn run(args: &[&str], cwd: &Path) -> std::process::Output {
    greybox_limited(args, cwd, MEMORY_MIB, SECONDS)
}

fn sweep_file(dir: &Path, name: &str, extra_sweep: &str, axes: &str, slurm: &str) {
    std::fs::write(
        dir.join(name),
        format!("[sweep]\nkind = \"cutting\"\nbase = \"cut.toml\"\nfraction = 0.3\n{extra_sweep}\n{axes}\n{slurm}\n"),
    )
    .unwrap();
}

const ONE_AXIS: &str = "[[axis]]\nfield = \"cutting_speed_m_s\"\nvalues = [2.5, 3.5]\n";

#[test]
fn slurm_script_values_never_become_commands() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    coarse_config(p, None);
    sweep_file(p, "sweep.toml", "", ONE_AXIS, "");
    let before = listing(p);
    // a quote, a command substitution and a newline in --out
    for out in ["o'; touch pwned; '", "o$(touch pwned)", "o\ntouch pwned"] {
        let r = run(
            &[
                "sweep",
                "run",
                "sweep.toml",
                "--out",
                out,
                "--executor",
                "slurm",
                "--dry-run",
            ],
            p,
        );
        refused_with(&r, &["--out", "#SBATCH", "only ASCII letters"]);
        assert_eq!(
            listing(p),
            before,
            "a refused sweep wrote nothing ({out:?})"
        );
    }
    // [slurm] values: each refused with its field
    for (field, slurm) in [
        (
            "[slurm] partition",
            "[slurm]\npartition = \"c'\\ntouch pwned\\n'\"\n",
        ),
        ("[slurm] account", "[slurm]\naccount = \"$(touch pwned)\"\n"),
        ("[slurm] time", "[slurm]\ntime = \"1:00 `touch pwned`\"\n"),
        (
            "[slurm] extra[0]",
            "[slurm]\nextra = [\"--qos=short\\ntouch pwned\"]\n",
        ),
        (
            "[slurm] extra[0]",
            "[slurm]\nextra = [\"--qos=a;touch pwned\"]\n",
        ),
    ] {
        sweep_file(p, "bad.toml", "", ONE_AXIS, slurm);
        let r = run(
            &[
                "sweep",
                "run",
                "bad.toml",
                "--out",
                "o",
                "--executor",
                "slurm",
                "--dry-run",
            ],
            p,
        );
        refused_with(&r, &[field, "bad.toml"]);
        assert!(!p.join("o").exists(), "{field}: nothing written");
    }
    // a sweep file named with a newline and a command: the name only reaches a comment,
    // escaped; the script's exec line quotes the output directory
    let name = "s\ntouch pwned\n.toml";
    sweep_file(p, name, "", ONE_AXIS, "");
    let script = ok(&run(
        &[
            "sweep",
            "run",
            name,
            "--out",
            "o",
            "--executor",
            "slurm",
            "--dry-run",
        ],
        p,
    ));
    assert!(
        !script.lines().any(|l| l.trim() == "touch pwned"),
        "{script}"
    );
    assert!(script.contains("s\\ntouch pwned\\n.toml"), "{script}");
    let exec = script.lines().find(|l| l.starts_with("exec ")).unwrap();
    assert!(
        exec.contains(&format!(
            "run-case '{}/o'",
            p.canonicalize().unwrap().display()
        )) || exec.contains(&format!("run-case '{}/o'", p.display())),
        "{exec}"
    );
    let syntax = std::process::Command::new("bash")
        .args(["-n", "-c", &script])
        .status()
        .unwrap();
    assert!(syntax.success(), "bash -n: {script}");
    assert!(!p.join("pwned").exists());
}

#[test]
fn a_device_as_base_configuration_is_refused_by_kind() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    std::fs::write(
        p.join("sweep.toml"),
        format!("[sweep]\nkind = \"cutting\"\nbase = \"/dev/zero\"\n{ONE_AXIS}"),
    )
    .unwrap();
    let before = listing(p);
    let r = run(&["sweep", "plan", "sweep.toml", "--out", "o"], p);
    refused_with(&r, &["/dev/zero", "character device", "not a regular file"]);
    // a configuration beyond max_input_bytes (a sparse 17 MiB file)
    let f = std::fs::File::create(p.join("huge.toml")).unwrap();
    f.set_len(17 << 20).unwrap();
    let r = run(
        &[
            "simulate",
            "cutting",
            "--config",
            "huge.toml",
            "--out",
            "run",
        ],
        p,
    );
    refused_with(&r, &["huge.toml", "max_input_bytes", "--max-input-mib"]);
    let mut after = listing(p);
    after.retain(|n| n != "huge.toml");
    assert_eq!(after, before, "nothing written");
}

#[test]
fn a_sweep_of_ten_million_cases_is_counted_before_it_is_expanded() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    coarse_config(p, None);
    let axes = "[[axis]]\nfield = \"cutting_speed_m_s\"\nrange = { start = 1.0, stop = 5.0, count = 10000 }\n[[axis]]\nfield = \"mu\"\nrange = { start = 0.1, stop = 0.5, count = 1000 }\n";
    sweep_file(p, "sweep.toml", "", axes, "");
    let before = listing(p);
    for cmd in ["plan", "run"] {
        let r = run(&["sweep", cmd, "sweep.toml", "--out", "o"], p);
        refused_with(
            &r,
            &[
                "sweep.toml",
                "10000000 cases (10000 × 1000)",
                "[sweep] max_cases = 10000",
                "max_cases = N",
            ],
        );
        assert_eq!(listing(p), before, "nothing written");
    }
}

/// The bundled cut with `spacing_m` replaced.
fn cut_with_spacing(dir: &Path, spacing: &str) {
    let base = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../examples/aisi1045-cut.toml"
    ))
    .unwrap();
    let text: String = base
        .lines()
        .map(|l| {
            if l.starts_with("spacing_m") {
                format!("spacing_m = {spacing}\n")
            } else {
                format!("{l}\n")
            }
        })
        .collect();
    std::fs::write(dir.join("cut.toml"), text).unwrap();
}

#[test]
fn a_nanometre_spacing_is_refused_before_particles_are_laid_out() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    cut_with_spacing(p, "1e-9");
    let before = listing(p);
    let r = run(
        &[
            "simulate", "cutting", "--config", "cut.toml", "--out", "run",
        ],
        p,
    );
    let e = refused_with(
        &r,
        &[
            "cut.toml",
            "spacing_m = 1e-9",
            "numerics.max_particles = 5000000",
            "1.47 PB",
        ],
    );
    assert!(e.contains("3.600e11 particles"), "{e}");
    // the same set-up as a sweep's base, and a sweep axis that refines the spacing
    sweep_file(p, "sweep.toml", "", ONE_AXIS, "");
    let r = run(&["sweep", "plan", "sweep.toml", "--out", "o"], p);
    refused_with(&r, &["sweep.toml", "numerics.max_particles"]);
    cut_with_spacing(p, "1.0e-5");
    sweep_file(
        p,
        "fine.toml",
        "",
        "[[axis]]\nfield = \"spacing_m\"\nvalues = [1e-5, 1e-9]\n",
        "",
    );
    let r = run(&["sweep", "plan", "fine.toml", "--out", "o"], p);
    refused_with(
        &r,
        &["case 2 (spacing_m = 0.000000001)", "numerics.max_particles"],
    );
    // the pin set-up, and the option that raises the cap
    let pin = [
        "simulate",
        "pin",
        "--depth-um",
        "20",
        "--spacing-um",
        "0.001",
        "--out",
        "pin",
    ];
    let r = run(&pin, p);
    refused_with(
        &r,
        &["pin set-up", "numerics.max_particles", "--max-particles"],
    );
    let mut after = listing(p);
    after.retain(|n| !n.ends_with(".toml"));
    let mut before = before;
    before.retain(|n| !n.ends_with(".toml"));
    assert_eq!(after, before, "nothing written");
}

#[test]
fn ubjson_null_arrays_are_capped_before_they_are_decoded() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    // {"learner": [$Z#l 80000000 … padded to 10 MB
    let mut b = vec![b'{', b'i', 7];
    b.extend(b"learner");
    b.extend([b'[', b'$', b'Z', b'#', b'l']);
    b.extend(80_000_000i32.to_be_bytes());
    b.resize(10 << 20, b'N');
    std::fs::write(p.join("m.ubj"), &b).unwrap();
    let r = run(
        &["import", "m.ubj", "--domain", "0:1,0:1", "--out", "m.json"],
        p,
    );
    refused_with(
        &r,
        &[
            "m.ubj",
            "byte",
            "80000000",
            "max_array_len",
            "--max-array-len",
        ],
    );
    assert_eq!(
        std::fs::read(p.join("m.ubj")).unwrap(),
        b,
        "input untouched"
    );
    assert_eq!(listing(p), ["m.ubj"], "nothing written");
}

/// An xlsx workbook whose one sheet is `head`, then `body` repeated `times`, then `tail`
/// (deflated: a repeated body compresses about 1000:1).
fn xlsx(path: &Path, head: &str, body: &str, times: usize, tail: &str) {
    use zip::write::SimpleFileOptions;
    let mut z = zip::ZipWriter::new(std::fs::File::create(path).unwrap());
    let o = SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated)
        .compression_level(Some(1))
        .large_file(true);
    let files = [
        (
            "[Content_Types].xml",
            r#"<?xml version="1.0" encoding="UTF-8"?><Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types"><Default Extension="rels" ContentType="application/vnd.openxmlformats-package.relationships+xml"/><Default Extension="xml" ContentType="application/xml"/><Override PartName="/xl/workbook.xml" ContentType="application/vnd.openxmlformats-officedocument.spreadsheetml.sheet.main+xml"/><Override PartName="/xl/worksheets/sheet1.xml" ContentType="application/vnd.openxmlformats-officedocument.spreadsheetml.worksheet+xml"/></Types>"#,
        ),
        (
            "_rels/.rels",
            r#"<?xml version="1.0" encoding="UTF-8"?><Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships"><Relationship Id="rId1" Type="http://schemas.openxmlformats.org/officeDocument/2006/relationships/officeDocument" Target="xl/workbook.xml"/></Relationships>"#,
        ),
        (
            "xl/workbook.xml",
            r#"<?xml version="1.0" encoding="UTF-8"?><workbook xmlns="http://schemas.openxmlformats.org/spreadsheetml/2006/main" xmlns:r="http://schemas.openxmlformats.org/officeDocument/2006/relationships"><sheets><sheet name="data" sheetId="1" r:id="rId1"/></sheets></workbook>"#,
        ),
        (
            "xl/_rels/workbook.xml.rels",
            r#"<?xml version="1.0" encoding="UTF-8"?><Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships"><Relationship Id="rId1" Type="http://schemas.openxmlformats.org/officeDocument/2006/relationships/worksheet" Target="worksheets/sheet1.xml"/></Relationships>"#,
        ),
    ];
    for (name, text) in files {
        z.start_file(name, o).unwrap();
        z.write_all(text.as_bytes()).unwrap();
    }
    z.start_file("xl/worksheets/sheet1.xml", o).unwrap();
    z.write_all(head.as_bytes()).unwrap();
    let chunk = body.repeat((1 << 20) / body.len().max(1));
    let per = (1 << 20) / body.len().max(1);
    let mut left = times;
    while left > 0 {
        let n = left.min(per);
        z.write_all(&chunk.as_bytes()[..n * body.len()]).unwrap();
        left -= n;
    }
    z.write_all(tail.as_bytes()).unwrap();
    z.finish().unwrap();
}

const SHEET: &str = r#"<?xml version="1.0" encoding="UTF-8"?><worksheet xmlns="http://schemas.openxmlformats.org/spreadsheetml/2006/main">"#;

#[test]
fn spreadsheet_bombs_are_measured_before_they_are_loaded() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let identify = |file: &str| {
        run(
            &[
                "identify",
                "--no-plan",
                "--recordings",
                file,
                "--out",
                "d.csv",
            ],
            p,
        )
    };
    // 1 GiB of rows behind a few MB: over max_uncompressed_bytes (512 MiB)
    let row = r#"<row><c t="n"><v>1</v></c><c t="n"><v>2</v></c></row>"#;
    xlsx(
        &p.join("bomb.xlsx"),
        &format!("{SHEET}<sheetData>"),
        row,
        (1 << 30) / row.len(),
        "</sheetData></worksheet>",
    );
    let size = std::fs::metadata(p.join("bomb.xlsx")).unwrap().len();
    assert!(size < 16 << 20, "{size}");
    let t0 = std::time::Instant::now();
    refused_with(
        &identify("bomb.xlsx"),
        &[
            "bomb.xlsx",
            "xl/worksheets/sheet1.xml",
            "max_uncompressed_bytes",
            "--max-uncompressed-mib",
        ],
    );
    assert!(t0.elapsed().as_secs() < 30, "{:?}", t0.elapsed());
    // a declared dimension of the whole sheet
    xlsx(
        &p.join("dim.xlsx"),
        &format!(r#"{SHEET}<dimension ref="A1:XFD1048576"/><sheetData>"#),
        "",
        0,
        "</sheetData></worksheet>",
    );
    refused_with(
        &identify("dim.xlsx"),
        &[
            "dim.xlsx",
            "1048576 rows × 16384 columns",
            "max_sheet_cells",
            "--max-sheet-cells",
        ],
    );
    // two cells at opposite corners, no dimension: calamine would hold 17·10⁹ cells
    xlsx(
        &p.join("box.xlsx"),
        &format!("{SHEET}<sheetData>"),
        r#"<row r="1"><c r="A1"><v>1</v></c></row><row r="1048576"><c r="XFD1048576"><v>1</v></c></row>"#,
        1,
        "</sheetData></worksheet>",
    );
    refused_with(
        &identify("box.xlsx"),
        &[
            "box.xlsx",
            "field 'data'",
            "cells span 1048576 rows × 16384 columns",
            "max_sheet_cells",
        ],
    );
    let mut names = listing(p);
    names.retain(|n| !n.ends_with(".xlsx"));
    assert!(names.is_empty(), "nothing written: {names:?}");
}

#[test]
fn a_recording_without_line_ends_is_refused_at_its_first_line() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    // 2 GiB of zeros, no newline (sparse)
    let f = std::fs::File::create(p.join("r.csv")).unwrap();
    f.set_len(2 << 30).unwrap();
    let r = greybox_limited(
        &[
            "identify",
            "--no-plan",
            "--recordings",
            "r.csv",
            "--out",
            "d.csv",
        ],
        p,
        MEMORY_MIB + 2048 + 512, // the recording is mapped, not read: address space, not memory
        SECONDS,
    );
    refused_with(&r, &["r.csv", "line 1", "max_line_bytes", "--max-line-kib"]);
    assert_eq!(listing(p), ["r.csv"], "nothing written");
}

/// A 3 GB recording (sparse, no newline) is refused by the recording cap before any byte is
/// read; with the cap raised, the line cap stops it at line 1 without reading the line whole.
#[test]
fn a_recording_over_the_recording_cap_is_refused_unread() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    let f = std::fs::File::create(p.join("r.csv")).unwrap();
    f.set_len(3_000_000_000).unwrap();
    let args = [
        "identify",
        "--no-plan",
        "--recordings",
        "r.csv",
        "--out",
        "d.csv",
    ];
    let r = run(&args, p);
    refused_with(
        &r,
        &[
            "r.csv",
            "3.00 GB",
            "max_recording_bytes",
            "--max-recording-mib",
        ],
    );
    assert_eq!(listing(p), ["r.csv"], "nothing written");
    let mut raised = vec!["--max-recording-mib", "4096"];
    raised.extend(args);
    let r = greybox_limited(&raised, p, MEMORY_MIB + 3072 + 512, SECONDS);
    refused_with(&r, &["r.csv", "line 1", "max_line_bytes"]);
    assert_eq!(listing(p), ["r.csv"], "nothing written");
}

/// A FIFO given as a recording is refused by kind at once, never opened (opening it would
/// wait for a writer until the time limit).
#[cfg(target_os = "linux")]
#[test]
fn a_fifo_recording_is_refused_without_waiting() {
    let d = tempfile::tempdir().unwrap();
    let p = d.path();
    for name in ["r.csv", "r.xlsx", "r.tdms"] {
        let status = std::process::Command::new("mkfifo")
            .arg(p.join(name))
            .status()
            .unwrap();
        assert!(status.success());
        let r = run(
            &[
                "identify",
                "--no-plan",
                "--recordings",
                name,
                "--out",
                "d.csv",
            ],
            p,
        );
        refused_with(&r, &[name, "FIFO", "not a regular file"]);
        std::fs::remove_file(p.join(name)).unwrap();
    }
    std::os::unix::fs::symlink("/dev/zero", p.join("z.csv")).unwrap();
    let r = run(
        &[
            "identify",
            "--no-plan",
            "--recordings",
            "z.csv",
            "--out",
            "d.csv",
        ],
        p,
    );
    refused_with(&r, &["z.csv", "character device"]);
}
