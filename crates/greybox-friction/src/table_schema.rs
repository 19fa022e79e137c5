//! The name, version and kinds of table files (uniform, exact and adaptive tables alike).

/// `schema` of a table file.
pub const TABLE_SCHEMA: &str = "greybox-table";
/// Version 2 added `kind` (uniform, exact, adaptive); version-1 files are uniform tables and
/// still load.
pub const TABLE_SCHEMA_VERSION: u32 = 2;

/// The kinds of table (a version-2 file's `kind`, by its name).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TableKind {
    /// Uniform grid, bilinear/trilinear ([`TabulatedLaw`](crate::table::TabulatedLaw)).
    Uniform,
    /// Cells between a piecewise-constant law's thresholds ([`ExactTable`](crate::exact_table::ExactTable)).
    Exact,
    /// Non-uniform grid refined to a tolerance, bilinear/trilinear ([`AdaptiveTable`](crate::adaptive::AdaptiveTable)).
    Adaptive,
}

impl TableKind {
    /// The kind's name (its [`Choice`](greybox_core::choice::Choice) name).
    pub fn name(self) -> &'static str {
        greybox_core::choice::Choice::name(self)
    }
}

greybox_core::choice!(
    TableKind,
    "table_kind",
    [Exact => "exact", Adaptive => "adaptive", Uniform => "uniform"]
);
