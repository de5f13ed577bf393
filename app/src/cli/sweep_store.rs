//! The on-disk form of a sweep: `sweep.json` (what was asked), one `value-NNN.json` record per
//! finished value and its interface state `value-NNN.state` (binary, little-endian f64), each
//! written atomically (temporary file, then rename; the record last), so that a sweep killed at
//! any moment loses nothing finished and `--resume` can continue it.

use std::fs;
use std::path::{Path, PathBuf};

use anyhow::{bail, Context};
use lopin_core::state::{InterfaceState, TraceHistory};
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
        let tmp = self.dir.join(format!(".{name}.tmp"));
        let dst = self.dir.join(name);
        fs::write(&tmp, bytes).with_context(|| format!("writing {}", tmp.display()))?;
        fs::rename(&tmp, &dst).with_context(|| format!("renaming to {}", dst.display()))
    }
}

pub fn record_name(i: usize) -> String {
    format!("value-{i:03}.json")
}

pub fn state_name(i: usize) -> String {
    format!("value-{i:03}.state")
}

const MAGIC: &[u8; 8] = b"LOPINST1";

fn encode_state(s: &InterfaceState) -> Vec<u8> {
    let mut b = Vec::with_capacity(24 + 16 * s.size());
    b.extend_from_slice(MAGIC);
    b.extend_from_slice(&(s.steps as u64).to_le_bytes());
    b.extend_from_slice(&(s.subs.len() as u64).to_le_bytes());
    for h in &s.subs {
        b.extend_from_slice(&(h.len as u64).to_le_bytes());
    }
    for h in &s.subs {
        for x in h.f.iter().chain(&h.w) {
            b.extend_from_slice(&x.to_le_bytes());
        }
    }
    b
}

fn decode_state(b: &[u8]) -> anyhow::Result<InterfaceState> {
    let mut pos = 0;
    let mut take = |n: usize| -> anyhow::Result<&[u8]> {
        let s = b
            .get(pos..pos + n)
            .ok_or_else(|| anyhow::anyhow!("truncated at byte {pos}"))?;
        pos += n;
        Ok(s)
    };
    if take(8)? != MAGIC {
        bail!("bad magic");
    }
    let word = |s: &[u8]| u64::from_le_bytes(s.try_into().unwrap_or([0; 8])) as usize;
    let steps = word(take(8)?);
    let nsubs = word(take(8)?);
    let lens: Vec<usize> = (0..nsubs)
        .map(|_| take(8).map(word))
        .collect::<anyhow::Result<_>>()?;
    let mut subs = Vec::with_capacity(nsubs);
    for len in lens {
        let count = len * (steps + 1);
        let mut read = || -> anyhow::Result<Vec<f64>> {
            (0..count)
                .map(|_| take(8).map(|s| f64::from_le_bytes(s.try_into().unwrap_or([0; 8]))))
                .collect()
        };
        let f = read()?;
        let w = read()?;
        subs.push(TraceHistory { len, f, w });
    }
    Ok(InterfaceState { steps, subs })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn state_round_trips_and_truncation_is_an_error() {
        let s = InterfaceState {
            steps: 2,
            subs: vec![TraceHistory {
                len: 1,
                f: vec![0.0, 1.5, -2.0],
                w: vec![3.0, 4.0, 5e-300],
            }],
        };
        let b = encode_state(&s);
        assert_eq!(decode_state(&b).expect("decodes"), s);
        assert!(decode_state(&b[..b.len() - 1]).is_err());
    }
}
