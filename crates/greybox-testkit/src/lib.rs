//! Test fixtures shared by greybox's test suites. A dev-only crate (`publish = false`):
//! crates name it under `[dev-dependencies]` only, never in their libraries.
//!
//! | module | what |
//! |---|---|
//! | [`law`] | tiny law files in a temporary directory |
//! | [`dataset`] | a friction dataset CSV from (force, μ) rows |
//! | [`mesh`] | a one-quad coated tool mesh (Abaqus, Gmsh) |
//! | [`hammer`] | a virtual impact-hammer recording as CSV |
//! | [`files`] | the files under a directory |
//! | [`calculix`] | whether CalculiX (`ccx`) is installed, for tests that need it |

pub mod calculix;
pub mod dataset;
pub mod files;
pub mod hammer;
pub mod law;
pub mod mesh;
