//! The on-disk form of a sweep, format 3, and its checks on `--resume`.
//!
//! - `sweep.json`: what was asked ([`Header`]: scene, the fingerprints of the resolved scene
//!   and of the settings, parameter, values, mode, predictor, LATIN settings), its `format`
//!   and its own `checksum` ([`crate::run_dir::checked_json`]). A damaged header is an error
//!   naming the file; a resume whose scene resolves differently (the scene file was edited) or
//!   that asks for another sweep is refused.
//! - one `value-NNN.json` record per finished value ([`ValueRecord`] plus `format`,
//!   `sweep_hash` (the header's fingerprint), `state_checksum` (the state file's checksum:
//!   crc32 of the file before its own trailing crc32) and its own `checksum`), and its
//!   converged interface state `value-NNN.state`, kept as a study keeps its configurations'
//!   ([`SavedStates`], bound to the header's fingerprint).
//!
//! Each file is written atomically (temporary file, then rename; the record last), so that a
//! sweep killed at any moment loses nothing finished. On `--resume` ([`Store::verify`]) every
//! record and its state are checked in order: the record parses, its checksum, its sweep
//! fingerprint, its numbers finite, the state file readable, its checksum against the
//! record's, the state decoding whole (finite values, right fingerprint) and fitting the
//! problem's layout. The first value that fails is reported with the file and the reason, and
//! the sweep recomputes from it on (the values after it warm-start from it); the values
//! before it are kept.

use std::fs;
use std::path::{Path, PathBuf};

use crate::run_dir::checked_json::{self, PLACEHOLDER};
use crate::run_dir::fingerprint::{self, Fingerprint};
use crate::run_dir::saved_states::SavedStates;
use anyhow::{bail, Context};
use lopin_core::state::InterfaceState;
use lopin_core::study::{Chain, Predictor};
use lopin_core::Problem;
use serde::{Deserialize, Serialize};

/// Format of the sweep directory's files (the state files' magic says `LOPINST3` too).
pub const SWEEP_FORMAT: u32 = 3;

/// File name of the header.
pub const SWEEP_JSON: &str = "sweep.json";

/// What a sweep is: a resumed sweep must ask for exactly the same.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Header {
    pub scene: String,
    /// Fingerprint of the resolved scene (its TOML, after --refine, --split, --f).
    pub scene_hash: Fingerprint,
    /// Fingerprint of all the LATIN settings (window, iteration limit, two-scale, …).
    pub settings_hash: Fingerprint,
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

impl Header {
    /// What the sweep's records and states belong to.
    pub fn fingerprint(&self) -> Fingerprint {
        fingerprint::of_json("sweep header", self)
    }

    /// The header as it reads back from sweep.json (numbers may differ in the last bit).
    fn as_saved(&self) -> anyhow::Result<Header> {
        let file = HeaderFile {
            format: SWEEP_FORMAT,
            header: self.clone(),
            checksum: PLACEHOLDER.into(),
        };
        let back: HeaderFile = serde_json::from_str(&serde_json::to_string(&file)?)?;
        Ok(back.header)
    }
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

impl ValueRecord {
    /// Its numbers are finite; the error names the first that is not.
    fn check_finite(&self) -> Result<(), String> {
        let mut named = vec![
            ("value", self.value),
            ("eta", self.eta),
            ("wall_s", self.wall_s),
            ("peak_normal_force", self.peak_normal_force),
            ("max_slip", self.max_slip),
            ("energy_end", self.energy_end),
        ];
        if let Some(c) = &self.cold {
            named.extend([("cold.eta", c.eta), ("cold.wall_s", c.wall_s)]);
        }
        if let Some((name, v)) = named.into_iter().find(|(_, v)| !v.is_finite()) {
            return Err(format!("non-finite {name} {v}"));
        }
        if let Some(i) = self.eta_history.iter().position(|v| !v.is_finite()) {
            return Err(format!(
                "non-finite eta_history[{i}] {}",
                self.eta_history[i]
            ));
        }
        Ok(())
    }
}

/// sweep.json.
#[derive(Serialize, Deserialize)]
struct HeaderFile {
    format: u32,
    #[serde(flatten)]
    header: Header,
    checksum: String,
}

/// value-NNN.json.
#[derive(Serialize, Deserialize)]
struct RecordFile {
    format: u32,
    #[serde(flatten)]
    record: ValueRecord,
    sweep_hash: Fingerprint,
    state_checksum: String,
    checksum: String,
}

/// The fields read before the rest: format and checksum.
#[derive(Deserialize)]
struct Seal {
    format: Option<u32>,
    checksum: Option<String>,
}

/// Parses `text` as a JSON file of format 3 with its checksum, then as `T`. The errors say
/// what is wrong, without the file name.
fn read_checked<T: for<'de> Deserialize<'de>>(text: &str, what: &str) -> Result<T, String> {
    let seal: Seal =
        serde_json::from_str(text).map_err(|e| format!("not JSON ({e}): the file is damaged"))?;
    match seal.format {
        Some(SWEEP_FORMAT) => {}
        Some(f) => {
            return Err(format!(
                "a {what} of format {f}, this Lopin reads format {SWEEP_FORMAT}: remake it"
            ))
        }
        None => {
            return Err(format!(
                "a {what} of an older format (no format field, no checksum), this Lopin reads \
                 format {SWEEP_FORMAT}: remake it"
            ))
        }
    }
    let Some(stored) = seal.checksum else {
        return Err("no checksum field: the file is damaged or was edited".into());
    };
    checked_json::verify(text, &stored)?;
    serde_json::from_str(text).map_err(|e| format!("not a {what} ({e})"))
}

/// The first value of a resumed sweep that failed its checks.
#[derive(Debug, Clone)]
pub struct Damage {
    /// The file that failed (a record or a state).
    pub path: PathBuf,
    /// Why.
    pub reason: String,
    /// Its value index: the sweep recomputes from here on.
    pub from: usize,
}

/// The finished values a resumed sweep keeps.
#[derive(Debug, Default)]
pub struct Resumed {
    /// Records 0, 1, … up to the first missing or damaged one, all checked.
    pub records: Vec<ValueRecord>,
    /// The chain of converged states the study engine starts the next values from, seeded
    /// with theirs.
    pub chain: Chain,
    /// The first value that failed its checks, if one did.
    pub damage: Option<Damage>,
}

/// A sweep directory.
pub struct Store {
    dir: PathBuf,
    /// The header's fingerprint: what every record and state must belong to.
    sweep_hash: Fingerprint,
    /// Whether this process writes the folder (rank 0 of a distributed sweep, or the only one).
    writes: bool,
    /// The values' converged states.
    states: SavedStates,
}

impl Store {
    /// Opens `dir` for `header` (of the scene given as `scene_source`): a fresh directory is
    /// initialized; one holding a sweep is only reused with `resume` and the same header, the
    /// scene resolving as it did. Its records are checked by [`Store::verify`].
    pub fn open(
        dir: &Path,
        header: &Header,
        scene_source: &str,
        resume: bool,
    ) -> anyhow::Result<Self> {
        fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
        let store = Self::in_dir(dir, header, true);
        let head = dir.join(SWEEP_JSON);
        if head.exists() {
            let text =
                fs::read_to_string(&head).with_context(|| format!("reading {}", head.display()))?;
            let old = read_checked::<HeaderFile>(&text, "sweep header")
                .map_err(|e| anyhow::anyhow!("{}: {e}", head.display()))?
                .header;
            if !resume {
                let finished = (0..old.values.len())
                    .take_while(|&i| dir.join(record_name(i)).exists())
                    .count();
                bail!(
                    "{} already holds a sweep ({} of {} values finished): pass --resume to continue it, or choose another --out",
                    dir.display(),
                    finished,
                    old.values.len()
                );
            }
            if old.scene_hash != header.scene_hash {
                bail!(
                    "{}: the scene changed since this sweep was made: {} now resolves to hash {}, \
                     the sweep was made with hash {}; resume with the scene as it was, or sweep \
                     it into another --out",
                    head.display(),
                    scene_source,
                    header.scene_hash,
                    old.scene_hash
                );
            }
            let now = header.as_saved()?;
            let same_but_settings = Header {
                settings_hash: now.settings_hash,
                ..old.clone()
            } == now;
            if old.settings_hash != now.settings_hash && same_but_settings {
                bail!(
                    "{}: --resume asks for other solver settings than the sweep stored there \
                     (--window, --max-iter or --macro); rerun with the same options or another \
                     --out",
                    head.display()
                );
            }
            if old != now {
                bail!(
                    "{}: --resume asks for a different sweep than the one stored there (stored: {} {} over {:?}, mode {}, predictor {}, tol {}); rerun with the same options or another --out",
                    head.display(), old.scene, old.parameter, old.values, old.mode, old.predictor, old.tol
                );
            }
            return Ok(store);
        }
        if resume {
            bail!("{}: nothing to resume (no {SWEEP_JSON})", dir.display());
        }
        let file = HeaderFile {
            format: SWEEP_FORMAT,
            header: header.clone(),
            checksum: PLACEHOLDER.into(),
        };
        store.write_atomic(SWEEP_JSON, checked_json::seal(&file)?.as_bytes())?;
        Ok(store)
    }

    /// Checks the finished values 0, 1, … of a sweep of `n` values on `problem`, up to the
    /// first missing one or the first that fails (see the module doc).
    pub fn verify(&self, n: usize, problem: &Problem, predictor: Predictor) -> Resumed {
        let mut out = Resumed {
            chain: Chain::new(predictor),
            ..Resumed::default()
        };
        for i in 0..n {
            if !self.dir.join(record_name(i)).exists() {
                if let Some(j) = (i + 1..n).find(|&j| self.dir.join(record_name(j)).exists()) {
                    out.damage = Some(Damage {
                        path: self.dir.join(record_name(i)),
                        reason: format!("missing, while {} is there", record_name(j)),
                        from: i,
                    });
                }
                break;
            }
            match self.check_value(i, problem) {
                Ok((record, state)) => {
                    out.chain.converged(i, &[record.value], &state);
                    out.records.push(record);
                }
                Err((path, reason)) => {
                    out.damage = Some(Damage {
                        path,
                        reason,
                        from: i,
                    });
                    break;
                }
            }
        }
        out
    }

    /// Reads the header of the sweep in `dir`, checked (format, checksum).
    pub fn read_header(dir: &Path) -> anyhow::Result<Header> {
        let head = dir.join(SWEEP_JSON);
        let text =
            fs::read_to_string(&head).with_context(|| format!("reading {}", head.display()))?;
        read_checked::<HeaderFile>(&text, "sweep header")
            .map(|h| h.header)
            .map_err(|e| anyhow::anyhow!("{}: {e}", head.display()))
    }

    /// Whether value `i` has a record.
    pub fn has_record(&self, i: usize) -> bool {
        self.dir.join(record_name(i)).exists()
    }

    /// Value `i`'s record, checked as a resume checks it (its state is not read); the error
    /// names the file and why.
    pub fn read_record(&self, i: usize) -> Result<ValueRecord, String> {
        self.check_record(i)
            .map(|(record, _)| record)
            .map_err(|(path, reason)| format!("{}: {reason}", path.display()))
    }

    /// Value `i`'s record and its state, checked as a resume checks them; the error names the
    /// file that failed and why.
    pub fn read_value(
        &self,
        i: usize,
        problem: &Problem,
    ) -> Result<(ValueRecord, InterfaceState), String> {
        self.check_value(i, problem)
            .map_err(|(path, reason)| format!("{}: {reason}", path.display()))
    }

    /// The checks of value `i`: its record, then its state. The error names the file that
    /// failed and why.
    fn check_value(
        &self,
        i: usize,
        problem: &Problem,
    ) -> Result<(ValueRecord, InterfaceState), (PathBuf, String)> {
        let (record, state_checksum) = self.check_record(i)?;
        let state = self
            .states
            .load(&record.state_file, Some(&state_checksum), problem)
            .map_err(|u| (u.path, u.reason))?;
        Ok((record, state))
    }

    /// The checks of value `i`'s record; gives it back with the checksum of its state file.
    fn check_record(&self, i: usize) -> Result<(ValueRecord, String), (PathBuf, String)> {
        let path = self.dir.join(record_name(i));
        let fail = |path: &Path, reason: String| (path.to_path_buf(), reason);
        let text =
            fs::read_to_string(&path).map_err(|e| fail(&path, format!("unreadable: {e}")))?;
        let file: RecordFile = read_checked(&text, "sweep record").map_err(|e| fail(&path, e))?;
        if file.sweep_hash != self.sweep_hash {
            return Err(fail(
                &path,
                format!(
                    "belongs to another sweep (hash {}, expected {})",
                    file.sweep_hash, self.sweep_hash
                ),
            ));
        }
        let record = file.record;
        if record.index != i || record.state_file != state_name(i) {
            return Err(fail(
                &path,
                format!(
                    "holds value {} with state file `{}`, expected value {i} with {}",
                    record.index,
                    record.state_file,
                    state_name(i)
                ),
            ));
        }
        record.check_finite().map_err(|e| fail(&path, e))?;
        Ok((record, file.state_checksum))
    }

    /// Writes a finished value: state first, then the record (the commit point), both bound
    /// to the sweep's header.
    pub fn save(&self, record: &ValueRecord, state: &InterfaceState) -> anyhow::Result<()> {
        if !self.writes {
            return Ok(());
        }
        let state_checksum = self.states.save(&record.state_file, state)?;
        let file = RecordFile {
            format: SWEEP_FORMAT,
            record: record.clone(),
            sweep_hash: self.sweep_hash,
            state_checksum,
            checksum: PLACEHOLDER.into(),
        };
        self.write_atomic(
            &record_name(record.index),
            checked_json::seal(&file)?.as_bytes(),
        )
    }

    /// The folder of `header` as another rank than rank 0 of a distributed sweep sees it: it
    /// reads the records rank 0 checked (after rank 0 has opened the folder), and writes nothing.
    pub fn follow(dir: &Path, header: &Header) -> Self {
        Self::in_dir(dir, header, false)
    }

    fn in_dir(dir: &Path, header: &Header, writes: bool) -> Self {
        let sweep_hash = header.fingerprint();
        Self {
            dir: dir.to_path_buf(),
            sweep_hash,
            writes,
            states: SavedStates::new(dir, sweep_hash),
        }
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
