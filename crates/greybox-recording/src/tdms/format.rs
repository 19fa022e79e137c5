//! The TDMS model: table-of-contents flags, data type codes, property values, objects and the file,
//! with the paths that name groups and channels.

pub(super) const TOC_META_DATA: u32 = 1 << 1;

pub(super) const TOC_NEW_OBJ_LIST: u32 = 1 << 2;

pub(super) const TOC_RAW_DATA: u32 = 1 << 3;

pub(super) const TOC_INTERLEAVED: u32 = 1 << 5;

pub(super) const TOC_BIG_ENDIAN: u32 = 1 << 6;

pub(super) const TOC_DAQMX: u32 = 1 << 7;

pub(super) const LEAD_IN: usize = 28;

pub(super) const NO_RAW_DATA: u32 = 0xFFFF_FFFF;

pub(super) const SAME_AS_PREVIOUS: u32 = 0;

pub(super) const T_STRING: u32 = 0x20;

pub(super) const T_BOOL: u32 = 0x21;

pub(super) const T_TIMESTAMP: u32 = 0x44;

pub(super) const T_F64: u32 = 10;

/// A property value.
#[derive(Debug, Clone, PartialEq)]
pub enum PropValue {
    Int(i64),
    UInt(u64),
    Float(f64),
    Str(String),
    Bool(bool),
    /// Seconds since 1904-01-01 00:00 UTC.
    Timestamp(f64),
}

impl PropValue {
    pub fn as_f64(&self) -> Option<f64> {
        match self {
            PropValue::Int(v) => Some(*v as f64),
            PropValue::UInt(v) => Some(*v as f64),
            PropValue::Float(v) => Some(*v),
            PropValue::Timestamp(v) => Some(*v),
            _ => None,
        }
    }
    pub fn as_str(&self) -> Option<&str> {
        match self {
            PropValue::Str(s) => Some(s),
            _ => None,
        }
    }
}

/// A TDMS object (root, group or channel) with its properties and numeric data.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TdmsObject {
    pub path: String,
    pub properties: Vec<(String, PropValue)>,
    /// TDMS data type code of the raw data, if the object has any.
    pub data_type: Option<u32>,
    /// Numeric raw data converted to f64.
    pub data: Vec<f64>,
}

impl TdmsObject {
    pub fn property(&self, name: &str) -> Option<&PropValue> {
        self.properties
            .iter()
            .rev()
            .find(|(n, _)| n == name)
            .map(|(_, v)| v)
    }
    pub(super) fn set_property(&mut self, name: String, value: PropValue) {
        match self.properties.iter_mut().find(|(n, _)| *n == name) {
            Some(slot) => slot.1 = value,
            None => self.properties.push((name, value)),
        }
    }
}

/// A whole TDMS file in memory.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TdmsFile {
    pub source: String,
    pub objects: Vec<TdmsObject>,
}

/// Object path of a channel: `/'group'/'channel'` (single quotes doubled inside names).
pub fn channel_path(group: &str, channel: &str) -> String {
    format!(
        "/'{}'/'{}'",
        group.replace('\'', "''"),
        channel.replace('\'', "''")
    )
}

pub fn group_path(group: &str) -> String {
    format!("/'{}'", group.replace('\'', "''"))
}

impl TdmsFile {
    pub fn object(&self, path: &str) -> Option<&TdmsObject> {
        self.objects.iter().find(|o| o.path == path)
    }
    pub fn channel(&self, group: &str, channel: &str) -> Option<&TdmsObject> {
        self.object(&channel_path(group, channel))
    }
    /// Names of the channels of a group.
    pub fn channel_names(&self, group: &str) -> Vec<String> {
        let prefix = format!("{}/", group_path(group));
        self.objects
            .iter()
            .filter_map(|o| o.path.strip_prefix(&prefix))
            .map(|c| c.trim_matches('\'').replace("''", "'"))
            .collect()
    }
}
