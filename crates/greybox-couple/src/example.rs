//! The bundled coupling example (`greybox couple --example DIR`): a deformable block pressed
//! onto a tool plate and dragged along it. The tool's top surface is split into friction
//! windows (one `*CONTACT PAIR` each); the pressure on the block rises from window to window,
//! so the pressure-dependent grey-box law ends with a different μ in every window. Units: N, mm, MPa, and
//! analysis time 1 per segment. CalculiX deck syntax as in fe-engine-interfaces.md §4.2.

use greybox_core::atomic::write_string_atomic;
use greybox_core::Result;
use std::fmt::Write as _;
use std::path::Path;

/// Drag per segment, mm.
pub const DRAG_PER_SEGMENT_MM: f64 = 0.002;

fn contact_prints(n: usize) -> String {
    let mut s = String::from("*CONTACT PRINT\nCDIS\n");
    for i in 1..=n {
        let _ = writeln!(s, "*CONTACT PRINT,SLAVE=SWORK,MASTER=STOOL{i}\nCF,CFN,CFS");
    }
    s
}

/// The tool (n elements, one per window) and the block above it: nodes, elements and the
/// node sets NTOOL, NTOP and NBLOCK. Node grids are indexed `[i][j][k]` (x, y, z).
fn write_mesh(s: &mut String, n: usize) {
    let mut id = 0;
    let mut tool = vec![vec![vec![0; 2]; 2]; n + 1];
    for (k, z) in [-0.2, 0.0].iter().enumerate() {
        for (j, y) in [0.0, 1.0].iter().enumerate() {
            for (i, t) in tool.iter_mut().enumerate() {
                id += 1;
                t[j][k] = id;
                let _ = writeln!(s, "{id}, {}, {y}, {z}", i as f64);
            }
        }
    }
    let mut blk = vec![vec![vec![0; 2]; 2]; n + 1];
    let width = (n as f64 - 0.5) / n as f64;
    for (k, z) in [0.0, 0.5].iter().enumerate() {
        for (j, y) in [0.0, 1.0].iter().enumerate() {
            for (i, b) in blk.iter_mut().enumerate() {
                id += 1;
                b[j][k] = id;
                let _ = writeln!(s, "{id}, {}, {y}, {z}", 0.25 + width * i as f64);
            }
        }
    }
    let hexa = |m: &Vec<Vec<Vec<usize>>>, i: usize| {
        [
            m[i][0][0],
            m[i + 1][0][0],
            m[i + 1][1][0],
            m[i][1][0],
            m[i][0][1],
            m[i + 1][0][1],
            m[i + 1][1][1],
            m[i][1][1],
        ]
    };
    s.push_str("*ELEMENT,TYPE=C3D8,ELSET=TOOL\n");
    for i in 0..n {
        let h = hexa(&tool, i);
        let _ = writeln!(s, "{}, {}", i + 1, h.map(|x| x.to_string()).join(", "));
    }
    s.push_str("*ELEMENT,TYPE=C3D8,ELSET=BLOCK\n");
    for i in 0..n {
        let h = hexa(&blk, i);
        let _ = writeln!(s, "{}, {}", 101 + i, h.map(|x| x.to_string()).join(", "));
    }
    s.push_str("*NSET,NSET=NTOOL\n");
    for t in &tool {
        for row in t {
            for v in row {
                let _ = writeln!(s, "{v}");
            }
        }
    }
    s.push_str("*NSET,NSET=NTOP\n");
    for b in &blk {
        for row in b {
            let _ = writeln!(s, "{}", row[1]);
        }
    }
    s.push_str("*NSET,NSET=NBLOCK\n");
    for b in &blk {
        for row in b {
            for v in row {
                let _ = writeln!(s, "{v}");
            }
        }
    }
}

/// The surfaces, one contact pair per window and their surface interactions (with the
/// initial μ and stick slope).
fn write_contact(s: &mut String, n: usize, initial_mu: f64) {
    s.push_str("*SURFACE,NAME=SWORK\n");
    for i in 0..n {
        let _ = writeln!(s, "{},S1", 101 + i);
    }
    for i in 1..=n {
        let _ = writeln!(s, "*SURFACE,NAME=STOOL{i}\n{i},S2");
    }
    for i in 1..=n {
        let _ = writeln!(
            s,
            "*CONTACT PAIR,INTERACTION=SI{i},TYPE=SURFACE TO SURFACE\nSWORK,STOOL{i}"
        );
    }
    for i in 1..=n {
        let _ = writeln!(s, "*SURFACE INTERACTION,NAME=SI{i}\n*SURFACE BEHAVIOR,PRESSURE-OVERCLOSURE=LINEAR\n1.e6\n*FRICTION\n{initial_mu:?},1.e5");
    }
}

/// The base deck (model, press step, first drag segment) and the segment template.
pub fn deck(windows: usize, initial_mu: f64) -> (String, String) {
    let n = windows.max(1);
    let mut s = String::from("** greybox coupling example: block dragged over a tool split into friction windows\n*HEADING\ngreybox coupling example\n*NODE\n");
    write_mesh(&mut s, n);
    write_contact(&mut s, n, initial_mu);
    let _ = writeln!(
        s,
        "*AMPLITUDE,NAME=DRAG,TIME=TOTAL TIME\n0.,0.,1.,0.,1001.,{:?}",
        1000.0 * DRAG_PER_SEGMENT_MM
    );
    s.push_str("*MATERIAL,NAME=STEEL\n*ELASTIC\n210000.,0.3\n*SOLID SECTION,ELSET=TOOL,MATERIAL=STEEL\n*SOLID SECTION,ELSET=BLOCK,MATERIAL=STEEL\n");
    s.push_str("*BOUNDARY\nNTOOL,1,3,0.\nNBLOCK,2,2,0.\n");
    // step 1: press, the pressure rising from window to window
    s.push_str("*STEP,NLGEOM\n*STATIC\n0.1,1.\n*BOUNDARY\nNTOP,1,1,0.\n*DLOAD\n");
    for i in 0..n {
        let _ = writeln!(s, "{},P2,{:?}", 101 + i, 20.0 * (i + 1) as f64);
    }
    s.push_str(&contact_prints(n));
    s.push_str("*RESTART,WRITE,OVERLAY\n*END STEP\n");
    let segment = format!(
        "** one drag segment; greybox puts *CHANGE FRICTION for every window at the placeholder below\n*STEP,NLGEOM,INC=1000\n*STATIC\n0.1,1.\n{{{{FRICTION}}}}*BOUNDARY,AMPLITUDE=DRAG\nNTOP,1,1,1.\n{}*RESTART,WRITE,OVERLAY\n*END STEP\n",
        contact_prints(n)
    );
    // the base deck also runs the first drag segment, with the deck's own friction
    s.push_str(&segment.replace("{{FRICTION}}", ""));
    (s, segment)
}

/// A pressure-dependent law for the example: Usui/Childs with μ = 0.5, m = 1, k = 20 MPa
/// (effective μ from ≈ 0.45 at 10 MPa to ≈ 0.25 at 80 MPa).
pub const EXAMPLE_LAW: &str =
    r#"{"law": "usui-childs", "mu": 0.5, "m": 1.0, "n": 1.0, "k_MPa": 20}"#;

/// Friction windows of the example problem.
pub type ExampleWindows = greybox_core::count::Count<1, 1_000>;

/// Write model.inp, segment.inp and law.json into `dir`.
pub fn write_example(dir: &Path, windows: usize) -> Result<()> {
    let (deck, segment) = deck(windows, 0.3);
    write_string_atomic(&dir.join("model.inp"), &deck)?;
    write_string_atomic(&dir.join("segment.inp"), &segment)?;
    write_string_atomic(&dir.join("law.json"), EXAMPLE_LAW)?;
    Ok(())
}
