//! greybox-couple: getting greybox's friction into external FE engines.
//!
//! * [`mesh`] — 2D tool meshes from Gmsh (`.msh` v4 ASCII) and Abaqus (`.inp`) files, with
//!   element sets (Gmsh physical groups, Abaqus `*ELSET`).
//! * [`windows`] — the article's friction windows (digest §8): the coating is one element thick,
//!   so its elements on the tool's outer boundary define the surface; one 4-point window per
//!   boundary segment (or per group of segments), extending outward and inward; writers for
//!   JSON, CSV, DEFORM `FRCWIN` (with a reader for round trips) and VTK polygons.
//! * [`engine`] — the restart loop behind an `Engine` trait; [`calculix`] — CalculiX as the
//!   engine; [`example`] — a generated example deck.
//! * [`pin3d`] — the article's inverse pin route in 3D: the spherical pin pressed into and slid
//!   over an elastic-plastic disk in CalculiX, and the search for the adhesive μ.

pub mod calculix;
pub mod engine;
pub mod example;
pub mod mesh;
pub mod pin3d;
pub mod windows;
