//! The keys of a [`ChannelMap`](super::ChannelMap) (converted there) as a study's `[recording]` writes them:
//! one flat table, the reader options beside the roles. Its own type so that the map can keep
//! its [`ReaderOptions`](super::ReaderOptions) apart while the file layout, its unknown-key errors (with the list of
//! known keys) and the position of a bad value stay those of one flat struct (a
//! `#[serde(flatten)]` field would lose both).

use super::roles::ChannelSpec;
use greybox_core::units::TimeUnit;
use serde::{Deserialize, Serialize};

/// The flat keys of a channel map, in the order they are written (named like the map, for
/// the type named in serde's errors).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub(super) struct ChannelMap {
    pub(super) time: Option<String>,
    pub(super) time_unit: Option<TimeUnit>,
    pub(super) sample_rate_hz: Option<f64>,
    pub(super) normal: Option<ChannelSpec>,
    pub(super) tangential: Option<ChannelSpec>,
    pub(super) radial: Option<ChannelSpec>,
    pub(super) trigger: Option<String>,
    pub(super) step: Option<String>,
    pub(super) speed: Option<ChannelSpec>,
    pub(super) radius: Option<ChannelSpec>,
    pub(super) cof: Option<ChannelSpec>,
    pub(super) position: Option<ChannelSpec>,
    pub(super) constant_normal_n: Option<f64>,
    pub(super) constant_sliding_m_s: Option<f64>,
    pub(super) rig: Option<String>,
    pub(super) track_radius_mm: Vec<f64>,
    pub(super) auto: bool,
    pub(super) ignore: Vec<String>,
    pub(super) tdms_group: Option<String>,
    pub(super) header_line: Option<u64>,
    pub(super) delimiter: Option<crate::text_table::Delimiter>,
    pub(super) decimal_comma: Option<bool>,
    pub(super) sheet: Option<String>,
    pub(super) columns: Vec<String>,
}
