//! A coated tool mesh of one unit quad (nodes (0,0), (1,0), (1,1), (0,1)) whose element
//! set is named `COATING`: its boundary is four unit segments, 4 long in all.

/// The quad as an Abaqus deck, with `tail` (more keyword lines) appended.
pub fn unit_square_abaqus(tail: &str) -> String {
    format!(
        "*NODE\n1, 0, 0\n2, 1, 0\n3, 1, 1\n4, 0, 1\n*ELEMENT, TYPE=CPE4, ELSET=COATING\n1, 1, 2, 3, 4\n{tail}"
    )
}

/// The `$Nodes` body of the quad in Gmsh 4.1.
pub const GMSH_NODES: &str = "1 4 1 4\n2 1 0 4\n1\n2\n3\n4\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n";
/// The `$Elements` body of the quad in Gmsh 4.1.
pub const GMSH_ELEMENTS: &str = "1 1 1 1\n2 1 3 1\n1 1 2 3 4\n";

/// A Gmsh 4.1 file of one quad in a physical surface "COATING", with `nodes` and
/// `elements` as the sections' bodies ([`GMSH_NODES`], [`GMSH_ELEMENTS`] or mutants).
pub fn gmsh(nodes: &str, elements: &str) -> String {
    format!(
        "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n1\n2 1 \"COATING\"\n$EndPhysicalNames\n\
         $Entities\n0 0 1 0\n1 0 0 0 1 1 0 1 1 0\n$EndEntities\n\
         $Nodes\n{nodes}$EndNodes\n$Elements\n{elements}$EndElements\n"
    )
}
