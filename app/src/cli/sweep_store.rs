//! The on-disk form of a sweep: `sweep.json` (what was asked), one `value-NNN.json` record per
//! finished value and its interface state `value-NNN.state` (binary, [`crate::run_dir::solution_file`]), each
//! written atomically (temporary file, then rename; the record last), so that a sweep killed at
//! any moment loses nothing finished and `--resume` can continue it.

use std::fs;
use std::path::{Path, PathBuf};

use crate::run_dir::solution_file::{decode_state, encode_state};
use anyhow::{bail, Context};
use lopin_core::state::InterfaceState;
use serde::{Deserialize, Serialize};

/// What a sweep is: a resumed sweep must ask for exactly the same.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Header {
    pub scene: String,
    pub parameter: String,
    pub values: Vec<f64>,
    pub mode: String,
    pub predictor: String,
    pub tol: f64,
    pub k: f64,
    pub mu: f64,
    pub refine: usize,
    pub split: usize,
    pub skip_unchanged: bool,
}

/// The cold solve of a value (with `--compare-cold`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ColdRecord {
    pub iterations: usize,
    pub eta: f64,
    pub converged: bool,
    pub wall_s: f64,
}

/// One finished value.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ValueRecord {
    pub index: usize,
    pub parameter: String,
    pub value: f64,
    pub iterations: usize,
    pub eta: f64,
    pub converged: bool,
    pub wall_s: f64,
    pub skipped_solves: usize,
    pub peak_normal_force: f64,
    pub max_slip: f64,
    pub energy_end: f64,
    pub eta_history: Vec<f64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cold: Option<ColdRecord>,
    pub state_file: String,
}

/// A sweep directory.
pub struct Store {
    dir: PathBuf,
}

impl Store {
    /// Opens `dir` for `header`: a fresh directory is initialized; one holding a sweep is only
    /// reused with `resume` and the same header. Returns the finished records.
    pub fn open(
        dir: &Path,
        header: &Header,
        resume: bool,
    ) -> anyhow::Result<(Self, Vec<ValueRecord>)> {
        fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
        let store = Self {
            dir: dir.to_path_buf(),
        };
        let head = dir.join("sweep.json");
        if head.exists() {
            let text =
                fs::read_to_string(&head).with_context(|| format!("reading {}", head.display()))?;
            let old: Header = serde_json::from_str(&text)
                .with_context(|| format!("{}: not a sweep header", head.display()))?;
            let records = store.records(old.values.len())?;
            if !resume {
                bail!(
                    "{} already holds a sweep ({} of {} values finished): pass --resume to continue it, or choose another --out",
                    dir.display(),
                    records.len(),
                    old.values.len()
                );
            }
            if &old != header {
                bail!(
                    "{}: --resume asks for a different sweep than the one stored there (stored: {} {} over {:?}, mode {}, predictor {}, tol {}); rerun with the same options or another --out",
                    head.display(), old.scene, old.parameter, old.values, old.mode, old.predictor, old.tol
                );
            }
            return Ok((store, records));
        }
        if resume {
            bail!("{}: nothing to resume (no sweep.json)", dir.display());
        }
        store.write_atomic(
            "sweep.json",
            serde_json::to_string_pretty(header)?.as_bytes(),
        )?;
        Ok((store, Vec::new()))
    }

    /// The finished records 0, 1, … up to the first missing one.
    fn records(&self, n: usize) -> anyhow::Result<Vec<ValueRecord>> {
        let mut out = Vec::new();
        for i in 0..n {
            let path = self.dir.join(record_name(i));
            if !path.exists() {
                break;
            }
            let text =
                fs::read_to_string(&path).with_context(|| format!("reading {}", path.display()))?;
            let rec: ValueRecord = serde_json::from_str(&text)
                .with_context(|| format!("{}: not a sweep record", path.display()))?;
            out.push(rec);
        }
        Ok(out)
    }

    /// Writes a finished value: state first, then the record (the commit point).
    pub fn save(&self, record: &ValueRecord, state: &InterfaceState) -> anyhow::Result<()> {
        self.write_atomic(&record.state_file, &encode_state(state))?;
        self.write_atomic(
            &record_name(record.index),
            serde_json::to_string_pretty(record)?.as_bytes(),
        )
    }

    /// Reads the state of a finished record.
    pub fn load_state(&self, record: &ValueRecord) -> anyhow::Result<InterfaceState> {
        let path = self.dir.join(&record.state_file);
        let bytes = fs::read(&path).with_context(|| format!("reading {}", path.display()))?;
        decode_state(&bytes).with_context(|| format!("{}: corrupt state file", path.display()))
    }

    /// Path of a file in the sweep directory.
    pub fn path(&self, name: &str) -> PathBuf {
        self.dir.join(name)
    }

    fn write_atomic(&self, name: &str, bytes: &[u8]) -> anyhow::Result<()> {
        crate::run_dir::write_atomic(&self.dir.join(name), bytes)
    }
}

pub fn record_name(i: usize) -> String {
    format!("value-{i:03}.json")
}

pub fn state_name(i: usize) -> String {
    format!("value-{i:03}.state")
}
