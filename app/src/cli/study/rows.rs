//! The files of a study: `study.json` (the plan, then the totals; written atomically) and
//! `study.csv` (one row per finished configuration, appended and synced at once, so a study
//! killed at any moment keeps every finished row). `--resume` reads both back: the plan must be
//! the same (scene, settings, parameters, design, chains), every row that parses and matches its
//! configuration's values is kept (a torn last line is dropped and solved again).
//!
//! A distributed study's rank r > 0 keeps its rows the same way in `rank-r/` ([`rank_dir`]);
//! rank 0 takes them into `study.csv` and removes the folder ([`absorb_ranks`]) at the end, or at
//! the start of a `--resume` after a kill.

use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Path as FsPath, PathBuf};

use anyhow::Context;
use lopin_core::study::runner::Outcome;
use lopin_core::study::{Design, Quantities};

use super::{Plan, Totals};

/// The rows of a study on disk and in memory.
pub struct Rows {
    dir: PathBuf,
    file: File,
    outcomes: Vec<Outcome>,
    have: Vec<bool>,
}

/// The CSV header for these parameters (also the column names of `study.parquet`).
pub(super) fn header(labels: &[String]) -> Vec<String> {
    let mut h: Vec<String> = ["index", "chain", "position"].map(String::from).to_vec();
    h.extend(labels.iter().cloned());
    h.extend(
        [
            "start",
            "start_distance",
            "start_change",
            "start_residual_nearest",
            "start_residual",
            "iterations",
            "eta",
            "converged",
            "wall_s",
            "cold_iterations",
        ]
        .map(String::from),
    );
    h.extend(Quantities::NAMES.iter().map(|(n, _)| n.to_string()));
    h
}

fn row(design: &Design, o: &Outcome) -> Vec<String> {
    let opt = |x: Option<String>| x.unwrap_or_default();
    let mut r = vec![
        o.index.to_string(),
        o.chain.to_string(),
        o.position.to_string(),
    ];
    r.extend(design.points[o.index].iter().map(f64::to_string));
    r.extend([
        opt(o.start.map(|s| s.to_string())),
        opt(o.start_distance.map(|d| d.to_string())),
        opt(o.start_change.map(|(k, l)| format!("{k}-{l}"))),
        opt(o.start_residual.map(|r| r.0.to_string())),
        opt(o.start_residual.map(|r| r.1.to_string())),
        o.iterations.to_string(),
        o.eta.to_string(),
        o.converged.to_string(),
        o.wall_s.to_string(),
        opt(o.cold_iterations.map(|c| c.to_string())),
    ]);
    r.extend(o.quantities.values().iter().map(f64::to_string));
    r
}

/// An outcome read back from a row (None: the row is damaged or does not match the design).
fn parse(design: &Design, fields: &csv::StringRecord) -> Option<Outcome> {
    let d = design.targets.len();
    let get = |k: usize| fields.get(k);
    let num = |k: usize| get(k)?.parse::<f64>().ok();
    let int = |k: usize| get(k)?.parse::<usize>().ok();
    let maybe = |k: usize| -> Option<Option<String>> {
        let s = get(k)?;
        Some((!s.is_empty()).then(|| s.to_string()))
    };
    if fields.len() != 13 + d + Quantities::NAMES.len() {
        return None;
    }
    let index = int(0)?;
    let point = design.points.get(index)?;
    for (k, &x) in point.iter().enumerate() {
        if num(3 + k)?.to_bits() != x.to_bits() {
            return None;
        }
    }
    let at = 3 + d;
    let q: Vec<f64> = (0..Quantities::NAMES.len())
        .map(|k| num(at + 10 + k))
        .collect::<Option<_>>()?;
    Some(Outcome {
        index,
        chain: int(1)?,
        position: int(2)?,
        start: match maybe(at)? {
            Some(s) => Some(s.parse().ok()?),
            None => None,
        },
        start_distance: match maybe(at + 1)? {
            Some(s) => Some(s.parse().ok()?),
            None => None,
        },
        start_change: match maybe(at + 2)? {
            Some(s) => {
                let (k, l) = s.split_once('-')?;
                Some((k.parse().ok()?, l.parse().ok()?))
            }
            None => None,
        },
        start_residual: match (maybe(at + 3)?, maybe(at + 4)?) {
            (Some(a), Some(b)) => Some((a.parse().ok()?, b.parse().ok()?)),
            (None, None) => None,
            _ => return None,
        },
        iterations: int(at + 5)?,
        eta: num(at + 6)?,
        converged: get(at + 7)?.parse().ok()?,
        wall_s: num(at + 8)?,
        cold_iterations: match maybe(at + 9)? {
            Some(s) => Some(s.parse().ok()?),
            None => None,
        },
        quantities: Quantities {
            peak_normal_force: q[0],
            max_slip: q[1],
            energy_end: q[2],
            input_work: q[3],
            friction_work: q[4],
            normal_work: q[5],
        },
    })
}

/// Writes `text` to `path` through a temporary file and a rename.
fn write_atomic(path: &FsPath, text: &str) -> anyhow::Result<()> {
    let tmp = path.with_extension("tmp");
    std::fs::write(&tmp, text).with_context(|| format!("{}: writing", tmp.display()))?;
    std::fs::rename(&tmp, path).with_context(|| format!("{}: renaming", path.display()))
}

fn csv_line(fields: &[String]) -> anyhow::Result<Vec<u8>> {
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record(fields)?;
    w.into_inner().map_err(|e| anyhow::anyhow!("{e}"))
}

/// The folder of rank `rank`'s rows in a distributed study in `dir`.
pub fn rank_dir(dir: &FsPath, rank: usize) -> PathBuf {
    dir.join(format!("rank-{rank}"))
}

/// Takes the rows the other ranks of a distributed study left in `dir` into `rows` (rank 0's
/// `study.csv`) and removes their folders; a new study (`keep` false) removes them unread.
pub fn absorb_ranks(
    dir: &FsPath,
    rows: &mut Rows,
    plan: &Plan,
    design: &Design,
    keep: bool,
) -> anyhow::Result<()> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Ok(());
    };
    let mut folders: Vec<PathBuf> = entries
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| {
            p.is_dir()
                && p.file_name()
                    .and_then(|n| n.to_str())
                    .and_then(|n| n.strip_prefix("rank-"))
                    .is_some_and(|r| r.parse::<usize>().is_ok())
        })
        .collect();
    folders.sort();
    for folder in folders {
        if keep && folder.join("study.json").exists() {
            let theirs = Rows::open(&folder, plan, design, true)
                .with_context(|| format!("{}: the rows of a rank", folder.display()))?;
            for o in theirs.done() {
                if !rows.has(o.index) {
                    rows.append(design, o)?;
                }
            }
        }
        std::fs::remove_dir_all(&folder)
            .with_context(|| format!("{}: removing", folder.display()))?;
    }
    Ok(())
}

impl Rows {
    /// Opens the study folder: a new study (refusing a folder that holds one), or with `resume`
    /// the study there, which must have the same plan.
    pub fn open(dir: &FsPath, plan: &Plan, design: &Design, resume: bool) -> anyhow::Result<Self> {
        let (json, csv_path) = (dir.join("study.json"), dir.join("study.csv"));
        let n = design.points.len();
        let mut outcomes = Vec::new();
        let mut have = vec![false; n];
        if resume {
            let text = std::fs::read_to_string(&json)
                .with_context(|| format!("--resume: {}: no study to resume", json.display()))?;
            let stored: serde_json::Value = serde_json::from_str(&text)
                .with_context(|| format!("{}: not a study file", json.display()))?;
            let stored: Plan = serde_json::from_value(stored["plan"].clone())
                .with_context(|| format!("{}: field `plan`", json.display()))?;
            let ours = serde_json::to_value(plan)?;
            let theirs = serde_json::to_value(&stored)?;
            if let (Some(a), Some(b)) = (ours.as_object(), theirs.as_object()) {
                if let Some(k) = a.keys().find(|k| a.get(*k) != b.get(*k)) {
                    anyhow::bail!(
                        "--resume: {}: field `{k}` differs from this study's ({} there, {} here): \
                         resume with the same scene, settings and options, or use another --out",
                        json.display(),
                        b.get(k).map_or("nothing".into(), |v| v.to_string()),
                        a.get(k).map_or("nothing".into(), |v| v.to_string())
                    );
                }
            }
            if let Ok(mut reader) = csv::ReaderBuilder::new()
                .flexible(true)
                .from_path(&csv_path)
            {
                for rec in reader.records().map_while(Result::ok) {
                    if let Some(o) = parse(design, &rec) {
                        if !have[o.index] {
                            have[o.index] = true;
                            outcomes.push(o);
                        }
                    }
                }
            }
        } else if csv_path.exists() {
            anyhow::bail!(
                "{}: a study is there already: --resume to continue it, or another --out",
                dir.display()
            );
        }
        std::fs::create_dir_all(dir).with_context(|| format!("{}: creating", dir.display()))?;
        write_atomic(
            &json,
            &serde_json::to_string_pretty(&serde_json::json!({ "plan": plan }))?,
        )?;
        // the kept rows, rewritten without any torn tail
        let mut text = csv_line(&header(&plan.parameters))?;
        for o in &outcomes {
            text.extend(csv_line(&row(design, o))?);
        }
        write_atomic(&csv_path, std::str::from_utf8(&text)?)?;
        let file = OpenOptions::new()
            .append(true)
            .open(&csv_path)
            .with_context(|| format!("{}: opening", csv_path.display()))?;
        Ok(Self {
            dir: dir.to_path_buf(),
            file,
            outcomes,
            have,
        })
    }

    /// Whether configuration i is finished.
    pub fn has(&self, i: usize) -> bool {
        self.have.get(i).copied().unwrap_or(false)
    }

    /// The finished configurations, in the order they finished.
    pub fn done(&self) -> &[Outcome] {
        &self.outcomes
    }

    /// Appends a finished configuration and syncs the file.
    pub fn append(&mut self, design: &Design, o: &Outcome) -> anyhow::Result<()> {
        let path = self.dir.join("study.csv");
        self.file
            .write_all(&csv_line(&row(design, o))?)
            .and_then(|()| self.file.sync_data())
            .with_context(|| format!("{}: appending a row", path.display()))?;
        if let Some(h) = self.have.get_mut(o.index) {
            *h = true;
        }
        self.outcomes.push(o.clone());
        Ok(())
    }

    /// Writes the totals into study.json.
    pub fn finish(&self, plan: &Plan, totals: &Totals) -> anyhow::Result<()> {
        write_atomic(
            &self.dir.join("study.json"),
            &serde_json::to_string_pretty(&serde_json::json!({ "plan": plan, "totals": totals }))?,
        )
    }
}
