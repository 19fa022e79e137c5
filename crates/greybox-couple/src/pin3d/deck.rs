//! The CalculiX input deck of one pin run (units N, mm, MPa).
//!
//! Two static steps with geometric nonlinearity: the press (every pin node moved down by d,
//! automatic increments) and the slide (moved by the slide length in x at depth d, at most
//! 1/`increments` of it per increment). Contact: penalty face-to-face (`SURFACE TO SURFACE`),
//! the disk's top faces in the band slave, the pin's sphere faces master; the slope is
//! [`PENALTY_PER_E_OVER_H`]·E/h, so the overclosure at a pressure p is p·h/(6E) (0.2 µm at
//! 2 GPa at article scale, under 1 % of the depth). Coulomb friction μ with a stick slope of
//! 0.5·E/h. Output per increment: the pin's total reaction force (`*NODE PRINT`, `TOTALS=ONLY`)
//! and the contact statistics (`*CONTACT PRINT`, `CF`: area, normal and shear force).

use super::mesh::PinMesh;
use std::fmt::Write;

/// Penalty slope of the contact, in units of E/h.
pub const PENALTY_PER_E_OVER_H: f64 = 6.0;
/// Stick slope of the friction (tangential penalty), in units of E/h: the elastic slip before
/// sliding is τ h/(0.05 E), about 2 µm at article scale against a slide of 1.5 mm. A ten
/// times stiffer slope gave the same F_t/F_N to 10⁻⁴ at 2000 N but made the contact chatter
/// (too many cutbacks) at the slide's start at 356 N.
pub const STICK_PER_E_OVER_H: f64 = 0.05;

/// What the deck states besides the mesh.
#[derive(Debug, Clone, PartialEq)]
pub struct DeckSpec {
    /// Pin depth d, mm.
    pub depth: f64,
    /// Slide length, mm (0: press only).
    pub slide: f64,
    /// Coulomb μ on the pin (0: frictionless).
    pub mu: f64,
    /// Young's modulus, MPa, and Poisson's ratio of the disk.
    pub youngs_modulus: f64,
    pub poisson_ratio: f64,
    /// Flow curve (flow stress MPa, plastic strain), strain from 0 up; empty: elastic disk.
    pub flow_curve: Vec<(f64, f64)>,
    /// Element size h in the band, mm (sets the penalty slope).
    pub element: f64,
    /// Number of slide increments (at most 1/increments of the slide each).
    pub increments: usize,
}

fn node_set(out: &mut String, name: &str, ids: &[usize]) {
    let _ = writeln!(out, "*NSET, NSET={name}");
    for chunk in ids.chunks(16) {
        let line: Vec<String> = chunk.iter().map(|n| n.to_string()).collect();
        let _ = writeln!(out, "{}", line.join(","));
    }
}

fn nodes(out: &mut String, set: &str, first: usize, xyz: &[[f64; 3]]) {
    let _ = writeln!(out, "*NODE, NSET={set}");
    for (k, p) in xyz.iter().enumerate() {
        let _ = writeln!(
            out,
            "{},{:.12e},{:.12e},{:.12e}",
            first + k,
            p[0],
            p[1],
            p[2]
        );
    }
}

fn elements(out: &mut String, set: &str, first: usize, bricks: &[[usize; 8]]) {
    let _ = writeln!(out, "*ELEMENT, TYPE=C3D8, ELSET={set}");
    for (k, e) in bricks.iter().enumerate() {
        let ids: Vec<String> = e.iter().map(|n| n.to_string()).collect();
        let _ = writeln!(out, "{},{}", first + k, ids.join(","));
    }
}

/// The output requests after each step's boundary conditions.
const OUTPUT: &str = "*NODE PRINT, NSET=NPIN, TOTALS=ONLY\nRF\n*CONTACT PRINT, SLAVE=SDISK, MASTER=SPIN\nCF\n*END STEP\n";

impl DeckSpec {
    /// The whole deck for `mesh`.
    pub fn write(&self, mesh: &PinMesh, heading: &str) -> String {
        let mut o = String::new();
        let _ = writeln!(o, "*HEADING\n{heading}");
        nodes(&mut o, "NDISK", 1, &mesh.disk_nodes);
        elements(&mut o, "EDISK", 1, &mesh.disk_elements);
        nodes(&mut o, "NPIN", mesh.disk_nodes.len() + 1, &mesh.pin_nodes);
        elements(
            &mut o,
            "EPIN",
            mesh.disk_elements.len() + 1,
            &mesh.pin_elements,
        );
        node_set(&mut o, "NBOT", &mesh.bottom);
        node_set(&mut o, "NSYM", &mesh.symmetry);
        node_set(&mut o, "NXEND", &mesh.x_ends);
        node_set(&mut o, "NYEND", &mesh.y_end);
        let _ = writeln!(o, "*SURFACE, NAME=SDISK, TYPE=ELEMENT");
        for e in &mesh.contact_faces {
            let _ = writeln!(o, "{e},S2");
        }
        let _ = writeln!(o, "*SURFACE, NAME=SPIN, TYPE=ELEMENT");
        for k in 0..mesh.pin_elements.len() {
            let _ = writeln!(o, "{},S1", mesh.disk_elements.len() + 1 + k);
        }
        let (e, nu) = (self.youngs_modulus, self.poisson_ratio);
        let _ = writeln!(o, "*MATERIAL, NAME=DISK\n*ELASTIC\n{e:.10e},{nu}");
        if !self.flow_curve.is_empty() {
            let _ = writeln!(o, "*PLASTIC");
            for (s, eps) in &self.flow_curve {
                let _ = writeln!(o, "{s:.10e},{eps:.6e}");
            }
        }
        let _ = writeln!(o, "*MATERIAL, NAME=PIN\n*ELASTIC\n{e:.10e},{nu}");
        let _ = writeln!(o, "*SOLID SECTION, ELSET=EDISK, MATERIAL=DISK");
        let _ = writeln!(o, "*SOLID SECTION, ELSET=EPIN, MATERIAL=PIN");
        let _ = writeln!(
            o,
            "*CONTACT PAIR, INTERACTION=SI, TYPE=SURFACE TO SURFACE\nSDISK,SPIN"
        );
        let slope = e / self.element;
        let _ = writeln!(
            o,
            "*SURFACE INTERACTION, NAME=SI\n*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE=LINEAR\n{:.10e},100.",
            PENALTY_PER_E_OVER_H * slope
        );
        if self.mu > 0.0 {
            let _ = writeln!(
                o,
                "*FRICTION\n{:.12e},{:.10e}",
                self.mu,
                STICK_PER_E_OVER_H * slope
            );
        }
        let _ = writeln!(o, "*BOUNDARY\nNBOT,1,3\nNSYM,2,2\nNXEND,1,1\nNYEND,2,2");
        let d = self.depth;
        let _ = write!(
            o,
            "*STEP, NLGEOM, INC=1000\n*STATIC\n0.1,1.,1e-5,0.25\n*BOUNDARY\nNPIN,1,2,0.\nNPIN,3,3,{:.12e}\n{OUTPUT}",
            -d
        );
        if self.slide > 0.0 {
            let inc = 1.0 / self.increments.max(1) as f64;
            let _ = write!(
                o,
                "*STEP, NLGEOM, INC=1000\n*STATIC\n{inc:.12e},1.,1e-5,{inc:.12e}\n*BOUNDARY\nNPIN,1,1,{:.12e}\nNPIN,2,2,0.\nNPIN,3,3,{:.12e}\n{OUTPUT}",
                self.slide, -d
            );
        }
        o
    }
}
