//! Test-only code shared by the integration tests.

pub mod old_svr;
