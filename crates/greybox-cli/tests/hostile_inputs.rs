//! One way to open every input (issue 62, mechanism 1): every command that reads a file is
//! given, in that file's place, each hostile kind — a FIFO (a plain open waits for a writer
//! for ever), a link to `/dev/zero` (read until memory runs out), a directory, and a file over
//! its size cap — under an address-space and a wall-clock limit. Each must be refused by
//! itself (not killed, no panic) with the file and its kind or cap named; a missing file is
//! "not found", never "malformed". The list below is every file-reading option of every
//! command; `cli_source_rules.rs::every_input_is_opened_through_the_one_safe_open` finds a
//! reader that bypasses the shared open.

mod common;
use common::{greybox, greybox_limited, ok, refused_with};
use std::path::Path;

const MIB: u64 = 1024;
const SECONDS: u64 = 30;

/// One file-reading input of one command: its arguments with `IN` where the hostile file
/// goes, and whether a directory is a legitimate value there (a directory of recordings).
struct Reader {
    args: &'static [&'static str],
    takes_directory: bool,
}

const fn r(args: &'static [&'static str]) -> Reader {
    Reader {
        args,
        takes_directory: false,
    }
}

/// Every command's file inputs. The other files they name (`m.json`, `ds.csv`, `cut.toml`,
/// …) are valid ones made by [`valid_inputs`], so the hostile one is what is refused.
#[rustfmt::skip]
const READERS: &[Reader] = &[
    r(&["plan", "--study", "IN", "--out", "o"]),
    r(&["synth", "--study", "IN", "--out", "o"]),
    Reader { args: &["identify", "--recordings", "IN", "--out", "o.csv"], takes_directory: true },
    r(&["identify", "--recordings", "rec.csv", "--plan-steps", "IN", "--out", "o.csv"]),
    r(&["adhesive", "--data", "IN", "--out", "o.csv"]),
    r(&["adhesive", "--data", "ds.csv", "--track-widths-csv", "IN", "--out", "o.csv"]),
    r(&["fit", "--data", "IN", "--out", "o"]),
    r(&["law", "--model", "IN", "--out", "l.json"]),
    r(&["import", "IN", "--domain", "150:2000,20:250", "--out", "o.json"]),
    r(&["import", "booster.json", "--training-data", "IN", "--out", "o.json"]),
    r(&["import", "booster.json", "--domain", "150:2000,20:250", "--calibration", "IN", "--out", "o.json"]),
    r(&["predict", "--model", "IN", "--csv", "pts.csv"]),
    r(&["predict", "--model", "m.json", "--csv", "IN"]),
    r(&["export", "--law", "IN", "--format", "csv", "--out", "t.csv"]),
    r(&["characterize", "--recording", "IN", "--hammer", "h", "--response", "a"]),
    r(&["wear", "--tests", "IN"]),
    r(&["wear", "--height-map", "IN", "--force-N", "100", "--velocity-m-per-min", "60", "--duration-s", "30"]),
    r(&["windows", "--mesh", "IN", "--out", "w.json"]),
    r(&["couple", "--deck", "IN", "--segment", "ex/segment.inp", "--law", "ex/law.json", "--ccx", "/bin/false", "--work", "wk"]),
    r(&["couple", "--deck", "ex/model.inp", "--segment", "IN", "--law", "ex/law.json", "--ccx", "/bin/false", "--work", "wk"]),
    r(&["couple", "--deck", "ex/model.inp", "--segment", "ex/segment.inp", "--law", "IN", "--ccx", "/bin/false", "--work", "wk"]),
    r(&["simulate", "cutting", "--config", "IN", "--out", "o"]),
    r(&["simulate", "cutting", "--config", "cut.toml", "--resume", "IN", "--out", "o"]),
    r(&["material", "fit", "--curves", "IN", "--out", "o.json"]),
    r(&["sweep", "plan", "IN", "--out", "sw"]),
    r(&["sweep", "calibrate", "sweep.toml", "--measured", "IN", "--out", "cal"]),
    r(&["bench", "validate", "--suite", "IN", "--out", "v"]),
];

/// Valid files for the inputs a case does not make hostile.
fn valid_inputs(d: &Path) {
    greybox_testkit::dataset::write_dataset(
        &d.join("ds.csv"),
        &[(100.0, 0.32), (200.0, 0.30), (300.0, 0.31)],
    );
    common::imported_model(d);
    std::fs::write(
        d.join("pts.csv"),
        "hertz_pressure_MPa,sliding_velocity_m_per_min\n500,100\n",
    )
    .unwrap();
    std::fs::write(
        d.join("rec.csv"),
        "time_s,normal_force_N,friction_force_N\n0,1,0.3\n",
    )
    .unwrap();
    ok(&greybox(&["couple", "--example", "ex"], d));
    common::coarse_config(d, None);
    std::fs::write(
        d.join("sweep.toml"),
        "[sweep]\nkind = \"cutting\"\nbase = \"cut.toml\"\nfraction = 0.4\n[[axis]]\nfield = \"insert.rake_deg\"\nvalues = [0.0, 6.0]\n",
    )
    .unwrap();
}

/// The hostile kinds, each made at `path`, with what the refusal must say.
#[derive(Clone, Copy, Debug)]
enum Kind {
    Fifo,
    DevZero,
    Directory,
    OverCap,
    Missing,
}

impl Kind {
    fn make(self, path: &Path) {
        match self {
            Kind::Fifo => {
                let st = std::process::Command::new("mkfifo")
                    .arg(path)
                    .status()
                    .unwrap();
                assert!(st.success());
            }
            Kind::DevZero => std::os::unix::fs::symlink("/dev/zero", path).unwrap(),
            Kind::Directory => std::fs::create_dir(path).unwrap(),
            // sparse: 2 MiB against caps of 1 MiB ([`CAPS`])
            Kind::OverCap => std::fs::File::create(path)
                .unwrap()
                .set_len(2 << 20)
                .unwrap(),
            Kind::Missing => {}
        }
    }
    fn needles(self) -> &'static [&'static str] {
        match self {
            Kind::Fifo => &["FIFO", "not a regular file"],
            Kind::DevZero => &["character device", "not a regular file"],
            Kind::Directory => &["directory"],
            Kind::OverCap => &["above the cap"],
            Kind::Missing => &["not found"],
        }
    }
}

/// Every cap at 1 MiB, so that a 2 MiB file is over whichever applies.
const CAPS: [&str; 6] = [
    "--max-input-mib",
    "1",
    "--max-data-mib",
    "1",
    "--max-recording-mib",
    "1",
];

fn refuse_every_kind(reader: &Reader, name: &str) {
    for kind in [
        Kind::Fifo,
        Kind::DevZero,
        Kind::Directory,
        Kind::OverCap,
        Kind::Missing,
    ] {
        if matches!(kind, Kind::Directory) && reader.takes_directory {
            continue;
        }
        let dir = tempfile::tempdir().unwrap();
        let d = dir.path();
        valid_inputs(d);
        kind.make(&d.join(name));
        let mut args: Vec<&str> = reader
            .args
            .iter()
            .map(|a| if *a == "IN" { name } else { a })
            .collect();
        args.extend_from_slice(&CAPS);
        let out = greybox_limited(&args, d, MIB, SECONDS);
        let mut needles = vec![name];
        needles.extend_from_slice(kind.needles());
        let context = format!("{:?} as {kind:?}", reader.args);
        let stderr = std::panic::catch_unwind(|| refused_with(&out, &needles))
            .unwrap_or_else(|_| panic!("{context}: {}", String::from_utf8_lossy(&out.stderr)));
        assert!(
            !stderr.contains("malformed"),
            "{context}: a hostile file called malformed: {stderr}"
        );
    }
}

#[test]
fn every_reader_refuses_fifos_devices_directories_oversize_and_missing_files() {
    for (k, reader) in READERS.iter().enumerate() {
        // a name per case, with the extension its reader expects
        let at = reader.args.iter().position(|a| *a == "IN").unwrap();
        let ext = match reader.args[at - 1] {
            "--law" | "--model" | "--resume" | "import" => "json",
            "--study" | "--config" | "--suite" | "plan" => "toml",
            "--mesh" => "msh",
            "--deck" | "--segment" => "inp",
            _ => "csv",
        };
        let name = format!("in{k}.{ext}");
        refuse_every_kind(reader, &name);
    }
}
