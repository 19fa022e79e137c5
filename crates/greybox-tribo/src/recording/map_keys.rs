//! The keys of a [`ChannelMap`](super::ChannelMap) as a study's `[recording]` writes them:
//! one flat table, the reader options beside the roles. Its own type so that the map can keep
//! its [`ReaderOptions`] apart while the file layout, its unknown-key errors (with the list of
//! known keys) and the position of a bad value stay those of one flat struct (a
//! `#[serde(flatten)]` field would lose both).

use super::reader_options::ReaderOptions;
use super::roles::ChannelSpec;
use greybox_core::units::TimeUnit;
use serde::{Deserialize, Serialize};

/// The flat keys of a channel map, in the order they are written (named like the map, for
/// the type named in serde's errors).
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub(super) struct ChannelMap {
    time: Option<String>,
    time_unit: Option<TimeUnit>,
    sample_rate_hz: Option<f64>,
    normal: Option<ChannelSpec>,
    tangential: Option<ChannelSpec>,
    radial: Option<ChannelSpec>,
    trigger: Option<String>,
    step: Option<String>,
    speed: Option<ChannelSpec>,
    radius: Option<ChannelSpec>,
    cof: Option<ChannelSpec>,
    position: Option<ChannelSpec>,
    constant_normal_n: Option<f64>,
    constant_sliding_m_s: Option<f64>,
    rig: Option<String>,
    track_radius_mm: Vec<f64>,
    auto: bool,
    ignore: Vec<String>,
    tdms_group: Option<String>,
    header_line: Option<u64>,
    delimiter: Option<crate::text_table::Delimiter>,
    decimal_comma: Option<bool>,
    sheet: Option<String>,
    columns: Vec<String>,
}

impl Default for ChannelMap {
    fn default() -> Self {
        super::ChannelMap::default().into()
    }
}

impl From<ChannelMap> for super::ChannelMap {
    fn from(k: ChannelMap) -> Self {
        super::ChannelMap {
            time: k.time,
            time_unit: k.time_unit,
            sample_rate_hz: k.sample_rate_hz,
            normal: k.normal,
            tangential: k.tangential,
            radial: k.radial,
            trigger: k.trigger,
            step: k.step,
            speed: k.speed,
            radius: k.radius,
            cof: k.cof,
            position: k.position,
            constant_normal_n: k.constant_normal_n,
            constant_sliding_m_s: k.constant_sliding_m_s,
            rig: k.rig,
            track_radius_mm: k.track_radius_mm,
            auto: k.auto,
            ignore: k.ignore,
            reader: ReaderOptions {
                tdms_group: k.tdms_group,
                header_line: k.header_line,
                delimiter: k.delimiter,
                decimal_comma: k.decimal_comma,
                sheet: k.sheet,
                columns: k.columns,
            },
        }
    }
}

impl From<super::ChannelMap> for ChannelMap {
    fn from(m: super::ChannelMap) -> Self {
        ChannelMap {
            time: m.time,
            time_unit: m.time_unit,
            sample_rate_hz: m.sample_rate_hz,
            normal: m.normal,
            tangential: m.tangential,
            radial: m.radial,
            trigger: m.trigger,
            step: m.step,
            speed: m.speed,
            radius: m.radius,
            cof: m.cof,
            position: m.position,
            constant_normal_n: m.constant_normal_n,
            constant_sliding_m_s: m.constant_sliding_m_s,
            rig: m.rig,
            track_radius_mm: m.track_radius_mm,
            auto: m.auto,
            ignore: m.ignore,
            tdms_group: m.reader.tdms_group,
            header_line: m.reader.header_line,
            delimiter: m.reader.delimiter,
            decimal_comma: m.reader.decimal_comma,
            sheet: m.reader.sheet,
            columns: m.reader.columns,
        }
    }
}
