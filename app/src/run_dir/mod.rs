//! What a run or sweep directory holds besides its results, and how Lopin knows that what it
//! reads back is intact and belongs there: `run.json` (how it was made, [`run_json`]), the
//! binary interface fields with their fingerprint and checksum ([`solution_file`]), the
//! fingerprint of what a file belongs to and the crc32 checksums ([`fingerprint`]), and JSON
//! files that carry their own checksum ([`checked_json`], the sweep's header and records), and
//! the converged states a sweep or study resumes from ([`saved_states`]), and a run's stored
//! step fields for the explorer ([`fields_file`]).

pub mod checked_json;
pub mod fields_file;
pub mod fingerprint;
pub mod run_json;
pub mod saved_states;
pub mod solution_file;

use anyhow::Context;
use std::path::Path;

/// File name of a run's converged solution.
pub const SOLUTION_BIN: &str = "solution.bin";

/// Writes `path` through a temporary file and a rename, so a reader never sees half a file.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> anyhow::Result<()> {
    let name = path
        .file_name()
        .map_or("out".into(), |n| n.to_string_lossy().into_owned());
    let tmp = path.with_file_name(format!(".{name}.tmp"));
    std::fs::write(&tmp, bytes).with_context(|| format!("writing {}", tmp.display()))?;
    std::fs::rename(&tmp, path).with_context(|| format!("renaming to {}", path.display()))
}
