//! The name and version every table file carries (uniform, exact and adaptive tables alike).

/// `schema` of a table file.
pub const TABLE_SCHEMA: &str = "greybox-table";
/// Version 2 added `kind` (uniform, exact, adaptive); version-1 files are uniform tables and
/// still load.
pub const TABLE_SCHEMA_VERSION: u32 = 2;
