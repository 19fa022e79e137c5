//! Reading a TDMS file in two passes: the segments' lead-ins and metadata first
//! ([`super::segments`]), then every channel's raw data into place ([`super::raw_data`]).

use super::format::TdmsFile;
use super::segments::scan;
use super::source::{Source, Tuning};
use greybox_core::Result;
use std::path::Path;

impl TdmsFile {
    /// Read a TDMS file. Files of a megabyte or more are not loaded whole: after a first
    /// pass over the segments' lead-ins and metadata, every channel gets its exact number of
    /// values allocated once and its raw data is read straight into place (little-endian
    /// doubles without any conversion), large files on all cores.
    pub fn read(path: &Path) -> Result<Self> {
        Self::read_tuned(path, &Tuning::DEFAULT)
    }

    pub(super) fn read_tuned(path: &Path, tuning: &Tuning) -> Result<Self> {
        let source = path.display().to_string();
        let (file, len) = greybox_core::input::open_recording(path)?;
        #[cfg(any(unix, windows))]
        if len >= tuning.whole_read_max as u64 {
            if let Ok(len) = usize::try_from(len) {
                let src = Source::File {
                    file: &file,
                    path,
                    len,
                };
                return parse_source(&src, &source, tuning);
            }
        }
        drop(file);
        let bytes = greybox_core::input::read_recording_bytes(path)?;
        parse_source(&Source::Mem(&bytes), &source, tuning)
    }

    /// Parse a TDMS byte buffer. `source` names the file in errors.
    pub fn parse(bytes: &[u8], source: &str) -> Result<Self> {
        parse_source(&Source::Mem(bytes), source, &Tuning::DEFAULT)
    }
}

pub(super) fn parse_source(src: &Source, source: &str, tuning: &Tuning) -> Result<TdmsFile> {
    let (mut file, plan) = scan(src, source, tuning)?;
    plan.fill(src, source, &mut file.objects, tuning)?;
    Ok(file)
}
