//! The files of a study: `study.json` (the plan, then the totals; written atomically) and
//! `study.csv` (one row per finished configuration, appended and synced at once, so a study
//! killed at any moment keeps every finished row).
//!
//! Every row ends with a `checksum` column: the crc32 (8 hexadecimal digits) of the row's text
//! before it, that is its other fields as written, joined by commas. `--resume` reads both
//! files back: the plan must be the same (scene, settings, parameters, design, chains), and
//! each row is checked in turn ([`check`]): its number of fields, its configuration index (one
//! of this study's), every field read as a number where it is one and finite, its parameter
//! values those of its configuration, the configurations it names as its start among this
//! study's, then its checksum; a configuration on more than one row keeps none of them. A row
//! that fails is dropped with one line saying which line, which configuration and why, and its
//! configuration is solved again; the other rows are kept as they are, and a line sums up
//! (kept, dropped, recomputed). The kept rows are written back, so the file holds checked rows
//! only, and a stale `study.parquet` is removed (the end of the study writes it again from the
//! checked rows). A `study.csv` of an older format, without the checksum column, cannot be
//! verified: each of its rows is solved again (the summary says so).
//!
//! A distributed study's rank r > 0 keeps its rows the same way in `rank-r/` ([`rank_dir`]);
//! rank 0 takes them into `study.csv` (checked the same way) and removes the folder
//! ([`absorb_ranks`]) at the end, or at the start of a `--resume` after a kill.

use std::fs::{File, OpenOptions};
use std::io::Write;
use std::path::{Path as FsPath, PathBuf};

use anyhow::Context;
use lopin_core::study::runner::Outcome;
use lopin_core::study::{Design, Quantities};

use super::{Plan, Totals};
use crate::run_dir::fingerprint::crc32;

/// The rows of a study on disk and in memory.
pub struct Rows {
    dir: PathBuf,
    file: File,
    outcomes: Vec<Outcome>,
    have: Vec<bool>,
    /// What the resume found wrong, one line each, then the summary (empty when every row
    /// was kept).
    report: Vec<String>,
}

/// Columns of a row before its parameters, and after them before the quantities.
const LEAD: usize = 3;
const MIDDLE: usize = 10;

/// The CSV header for these parameters (also the column names of `study.parquet`).
pub(super) fn header(labels: &[String]) -> Vec<String> {
    let mut h = header_without_checksum(labels);
    h.push("checksum".into());
    h
}

/// The header of a `study.csv` of the older format (no checksum column).
fn header_without_checksum(labels: &[String]) -> Vec<String> {
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

/// The checksum of a row whose fields before the checksum read `text`.
fn checksum(text: &str) -> String {
    format!("{:08x}", crc32(text.as_bytes()))
}

/// The fields of a row, its checksum last (also the cells of `study.parquet`).
pub(super) fn row(design: &Design, o: &Outcome) -> Vec<String> {
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
    let sum = checksum(&r.join(","));
    r.push(sum);
    r
}

/// A row's line: its fields (numbers, `true`/`false`, `k-l` or empty, none of which CSV
/// quotes) joined by commas.
fn line(fields: &[String]) -> String {
    let mut l = fields.join(",");
    l.push('\n');
    l
}

/// A field as a message quotes it: at most 32 characters of it.
fn shown(field: &str) -> String {
    match field.char_indices().nth(32) {
        Some((at, _)) => format!("{}…", &field[..at]),
        None => field.to_string(),
    }
}

/// Why a row is not kept.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct Damage {
    /// The configuration it names, when that is one of this study's.
    pub index: Option<usize>,
    pub why: String,
    /// Whether the row has too few or too many fields.
    pub short: bool,
}

/// Checks one row of `study.csv` (its text without the line end) against the design and reads
/// it back; `names` is the header. The error says the first thing wrong with it.
pub(super) fn check(design: &Design, names: &[String], text: &str) -> Result<Outcome, Damage> {
    let n = design.points.len();
    let d = design.targets.len();
    let fields: Vec<&str> = text.split(',').collect();
    let fail = |index: Option<usize>, why: String| Damage {
        index,
        why,
        short: false,
    };
    if fields.len() != names.len() {
        return Err(Damage {
            index: fields[0].parse::<usize>().ok().filter(|&i| i < n),
            why: format!("{} fields where a row has {}", fields.len(), names.len()),
            short: true,
        });
    }
    let index = match fields[0].parse::<usize>() {
        Ok(i) if i < n => i,
        Ok(i) => {
            return Err(fail(
                None,
                format!(
                    "configuration {i} is not one of this study's (0 to {})",
                    n - 1
                ),
            ))
        }
        Err(_) => {
            return Err(fail(
                None,
                format!("index `{}` is not a configuration number", shown(fields[0])),
            ))
        }
    };
    let bad = |k: usize, what: &str| {
        fail(
            Some(index),
            format!("{} is `{}`, not {what}", names[k], shown(fields[k])),
        )
    };
    let count = |k: usize| fields[k].parse::<usize>().map_err(|_| bad(k, "a count"));
    let num = |k: usize| -> Result<f64, Damage> {
        let x = fields[k].parse::<f64>().map_err(|_| bad(k, "a number"))?;
        if x.is_finite() {
            Ok(x)
        } else {
            Err(fail(
                Some(index),
                format!("{} is {x}, not a finite number", names[k]),
            ))
        }
    };
    let maybe = |k: usize| -> Option<&str> { (!fields[k].is_empty()).then_some(fields[k]) };
    let config = |k: usize| -> Result<usize, Damage> {
        let j = count(k)?;
        if j < n {
            Ok(j)
        } else {
            Err(fail(
                Some(index),
                format!(
                    "{} names configuration {j}, not one of this study's",
                    names[k]
                ),
            ))
        }
    };
    let (chain, position) = (count(1)?, count(2)?);
    for (k, &x) in design.points[index].iter().enumerate() {
        let v = num(LEAD + k)?;
        if v.to_bits() != x.to_bits() {
            return Err(fail(
                Some(index),
                format!(
                    "{} = {v} where configuration {index} has {x}",
                    names[LEAD + k]
                ),
            ));
        }
    }
    let at = LEAD + d;
    let start = maybe(at).map(|_| config(at)).transpose()?;
    let start_distance = maybe(at + 1).map(|_| num(at + 1)).transpose()?;
    let start_change = match maybe(at + 2) {
        None => None,
        Some(s) => {
            let pair = s.split_once('-').and_then(|(k, l)| {
                let (k, l) = (k.parse::<usize>().ok()?, l.parse::<usize>().ok()?);
                (k < n && l < n).then_some((k, l))
            });
            Some(pair.ok_or_else(|| bad(at + 2, "two of this study's configurations (k-l)"))?)
        }
    };
    let start_residual = match (maybe(at + 3), maybe(at + 4)) {
        (None, None) => None,
        (Some(_), Some(_)) => Some((num(at + 3)?, num(at + 4)?)),
        _ => {
            return Err(fail(
                Some(index),
                format!(
                    "{} and {} are not both given or both empty",
                    names[at + 3],
                    names[at + 4]
                ),
            ))
        }
    };
    let iterations = count(at + 5)?;
    let eta = num(at + 6)?;
    let converged = fields[at + 7]
        .parse::<bool>()
        .map_err(|_| bad(at + 7, "true or false"))?;
    let wall_s = num(at + 8)?;
    let cold_iterations = maybe(at + 9).map(|_| count(at + 9)).transpose()?;
    let q = (0..Quantities::NAMES.len())
        .map(|k| num(at + MIDDLE + k))
        .collect::<Result<Vec<f64>, Damage>>()?;
    let last = names.len() - 1;
    let body = &text[..text.len() - fields[last].len() - 1];
    let computed = checksum(body);
    if fields[last] != computed {
        return Err(fail(
            Some(index),
            format!(
                "checksum mismatch (stored `{}`, computed {computed}): the row was edited or \
                 damaged",
                shown(fields[last])
            ),
        ));
    }
    Ok(Outcome {
        index,
        chain,
        position,
        start,
        start_distance,
        start_change,
        start_residual,
        iterations,
        eta,
        converged,
        wall_s,
        cold_iterations,
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

/// What a resume reads back from a `study.csv`.
#[derive(Debug, Default)]
pub(super) struct Checked {
    /// The rows kept, in file order.
    pub kept: Vec<Outcome>,
    /// One line per row dropped, then the summary (empty when nothing was dropped).
    pub report: Vec<String>,
}

/// "3" or "3, 5 and 8".
fn listed(items: &[usize]) -> String {
    let words: Vec<String> = items.iter().map(usize::to_string).collect();
    match words.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
        _ => words.concat(),
    }
}

fn plural(n: usize, word: &str) -> String {
    format!("{n} {word}{}", if n == 1 { "" } else { "s" })
}

/// Checks the text of `study.csv` at `path` against the design ([`check`] on every row), drops
/// every configuration found on more than one row, and says what was dropped and why.
pub(super) fn read_back(design: &Design, labels: &[String], path: &FsPath, text: &str) -> Checked {
    let names = header(labels);
    let lines: Vec<(usize, &str)> = text
        .split('\n')
        .enumerate()
        .map(|(k, l)| (k + 1, l))
        .filter(|(_, l)| !l.is_empty())
        .collect();
    let Some((&(_, head), body)) = lines.split_first() else {
        return Checked::default();
    };
    let head_fields: Vec<String> = csv::ReaderBuilder::new()
        .has_headers(false)
        .from_reader(head.as_bytes())
        .records()
        .next()
        .and_then(Result::ok)
        .map(|r| r.iter().map(String::from).collect())
        .unwrap_or_default();
    let mut report = Vec::new();
    if head_fields != names {
        let why = if head_fields == header_without_checksum(labels) {
            "of an older format, without the checksum column"
        } else {
            "damaged: its header is not this study's columns"
        };
        let mut lost: Vec<usize> = body
            .iter()
            .filter_map(|(_, l)| l.split(',').next()?.parse::<usize>().ok())
            .filter(|&i| i < design.points.len())
            .collect();
        lost.sort_unstable();
        lost.dedup();
        report.push(format!(
            "{}: {why}: its {} cannot be verified: kept 0 rows, recomputing {}{}",
            path.display(),
            plural(body.len(), "row"),
            plural(lost.len(), "configuration"),
            if lost.is_empty() {
                String::new()
            } else {
                format!(" ({})", listed(&lost))
            }
        ));
        return Checked {
            kept: Vec::new(),
            report,
        };
    }
    let last_line = lines.last().map(|l| l.0);
    let torn = !text.ends_with('\n');
    let mut found: Vec<(usize, Outcome)> = Vec::new();
    let mut failed: Vec<(usize, Damage)> = Vec::new();
    for &(at, l) in body {
        match check(design, &names, l.strip_suffix('\r').unwrap_or(l)) {
            Ok(o) => found.push((at, o)),
            Err(mut d) => {
                if torn && Some(at) == last_line {
                    d.why.push_str(
                        " (the last line, cut short: the study was stopped while writing it)",
                    );
                } else if d.short {
                    d.why.push_str(" (a line cut short or joined to another)");
                }
                failed.push((at, d));
            }
        }
    }
    // a configuration on several rows keeps none of them
    let mut lines_of: Vec<Vec<usize>> = vec![Vec::new(); design.points.len()];
    for (at, o) in &found {
        lines_of[o.index].push(*at);
    }
    let mut kept = Vec::new();
    let mut dropped = failed.len();
    let mut lines_report: Vec<(usize, String)> = Vec::new();
    let mut recomputed: Vec<usize> = Vec::new();
    for (at, o) in found {
        let on = &lines_of[o.index];
        if on.len() == 1 {
            kept.push(o);
            continue;
        }
        dropped += 1;
        if on[0] == at {
            recomputed.push(o.index);
            lines_report.push((
                at,
                format!(
                "{} lines {}: configuration {} is on {} rows: every copy dropped, recomputing it",
                path.display(),
                listed(on),
                o.index,
                on.len()
            ),
            ));
        }
    }
    for (at, d) in failed {
        let what = match d.index {
            None => "dropped".to_string(),
            Some(i) if lines_of[i].len() == 1 => {
                format!(
                    "dropped (configuration {i} is kept from line {})",
                    lines_of[i][0]
                )
            }
            Some(i) => {
                recomputed.push(i);
                "dropped, recomputing it".to_string()
            }
        };
        lines_report.push((
            at,
            match d.index {
                Some(i) => format!(
                    "{} line {at}: configuration {i}: {}: {what}",
                    path.display(),
                    d.why
                ),
                None => format!("{} line {at}: {}: {what}", path.display(), d.why),
            },
        ));
    }
    lines_report.sort_by_key(|r| r.0);
    report.extend(lines_report.into_iter().map(|r| r.1));
    recomputed.sort_unstable();
    recomputed.dedup();
    if dropped > 0 {
        report.push(format!(
            "{}: kept {}, dropped {}, recomputing {}{}",
            path.display(),
            plural(kept.len(), "row"),
            plural(dropped, "damaged row"),
            plural(recomputed.len(), "configuration"),
            if recomputed.is_empty() {
                String::new()
            } else {
                format!(" ({})", listed(&recomputed))
            }
        ));
    }
    Checked { kept, report }
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
            let mut theirs = Rows::open(&folder, plan, design, true)
                .with_context(|| format!("{}: the rows of a rank", folder.display()))?;
            rows.report.extend(theirs.take_report());
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
        let mut report = Vec::new();
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
            match std::fs::read(&csv_path) {
                Ok(bytes) => {
                    let text = String::from_utf8_lossy(&bytes);
                    let checked = read_back(design, &plan.parameters, &csv_path, &text);
                    for o in checked.kept {
                        have[o.index] = true;
                        outcomes.push(o);
                    }
                    report = checked.report;
                }
                Err(e) if e.kind() == std::io::ErrorKind::NotFound => {}
                Err(e) => {
                    return Err(e)
                        .with_context(|| format!("--resume: {}: reading", csv_path.display()))
                }
            }
            // study.parquet is written again from the checked rows at the end
            let table = dir.join("study.parquet");
            if table.exists() {
                std::fs::remove_file(&table)
                    .with_context(|| format!("{}: removing the stale table", table.display()))?;
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
            text.extend(line(&row(design, o)).into_bytes());
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
            report,
        })
    }

    /// What the resume found wrong with the rows, one line each, then the summary; emptied.
    pub fn take_report(&mut self) -> Vec<String> {
        std::mem::take(&mut self.report)
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
            .write_all(line(&row(design, o)).as_bytes())
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

#[cfg(test)]
mod tests {
    use super::*;
    use lopin_core::study::{Spread, Target};

    fn design() -> Design {
        let problem = lopin_core::scene::problem_of(
            &lopin_core::scene::load("two-blocks").expect("scene"),
            "two-blocks",
        )
        .expect("builds");
        Design::grid(vec![(
            Target::parse("f", &problem).expect("test value"),
            Spread::parse("0,0.1,0.2").expect("test value"),
        )])
        .expect("grid")
    }

    fn outcome(index: usize) -> Outcome {
        Outcome {
            index,
            chain: 0,
            position: index,
            start: index.checked_sub(1),
            start_change: None,
            start_residual: (index == 2).then_some((0.5, 0.25)),
            start_distance: index.checked_sub(1).map(|_| 0.5),
            iterations: 10 + index,
            eta: 1e-4,
            converged: true,
            wall_s: 0.125,
            quantities: Quantities {
                peak_normal_force: 1.5e3 * (index as f64 + 1.0),
                max_slip: 1e-7,
                ..Quantities::default()
            },
            cold_iterations: None,
        }
    }

    /// study.csv of configurations 0, 1, 2 (header first), as lines.
    fn lines(design: &Design) -> Vec<String> {
        let labels = vec!["f".to_string()];
        let mut l = vec![header(&labels).join(",")];
        l.extend((0..3).map(|i| row(design, &outcome(i)).join(",")));
        l
    }

    fn read(design: &Design, lines: &[String], end: &str) -> Checked {
        let text = lines.join("\n") + end;
        read_back(design, &["f".into()], FsPath::new("s.csv"), &text)
    }

    #[test]
    fn rows_read_back_whole_and_every_damage_is_named() {
        let design = design();
        let good = lines(&design);
        let all = read(&design, &good, "\n");
        assert_eq!(all.kept, (0..3).map(outcome).collect::<Vec<_>>());
        assert!(all.report.is_empty());
        // Windows line ends change nothing
        let crlf: Vec<String> = good.iter().map(|l| format!("{l}\r")).collect();
        assert_eq!(read(&design, &crlf, "\n").kept.len(), 3);

        let with = |k: usize, edit: &dyn Fn(&str) -> String| {
            let mut l = good.clone();
            l[k] = edit(&l[k]);
            read(&design, &l, "\n")
        };
        let field = |name: &str| header(&["f".into()]).iter().position(|h| h == name);
        let set = |line: &str, name: &str, v: &str| {
            let mut f: Vec<String> = line.split(',').map(String::from).collect();
            f[field(name).expect("column")] = v.into();
            f.join(",")
        };
        for (name, value, why) in [
            ("eta", "NaN", "eta is NaN, not a finite number"),
            ("max_slip", "inf", "max_slip is inf, not a finite number"),
            ("f", "0.3", "f = 0.3 where configuration 1 has 0.1"),
            (
                "start",
                "9",
                "start names configuration 9, not one of this study's",
            ),
            ("iterations", "-3", "iterations is `-3`, not a count"),
            ("converged", "yes", "converged is `yes`, not true or false"),
        ] {
            let r = with(2, &|l| set(l, name, value));
            assert_eq!(
                r.report,
                [
                    format!("s.csv line 3: configuration 1: {why}: dropped, recomputing it"),
                    "s.csv: kept 2 rows, dropped 1 damaged row, recomputing 1 configuration (1)"
                        .to_string()
                ]
            );
            assert_eq!(r.kept.iter().map(|o| o.index).collect::<Vec<_>>(), [0, 2]);
        }
        // an edit the other checks let through: the checksum
        let r = with(3, &|l| set(l, "peak_normal_force", "9000"));
        assert!(
            r.report[0].starts_with("s.csv line 4: configuration 2: checksum mismatch (stored `")
                && r.report[0]
                    .ends_with("): the row was edited or damaged: dropped, recomputing it"),
            "{:?}",
            r.report
        );
        // a torn last line (no line end) names its configuration
        let mut torn = good.clone();
        torn[3].truncate(12);
        let r = read(&design, &torn, "");
        assert_eq!(
            r.report[0],
            format!(
                "s.csv line 4: configuration 2: {} fields where a row has 21 (the last line, cut \
                 short: the study was stopped while writing it): dropped, recomputing it",
                torn[3].split(',').count()
            )
        );
        // a row pasted onto another
        let r = with(1, &|l| format!("{l}{}", good[2]));
        assert!(
            r.report[0]
                .contains("41 fields where a row has 21 (a line cut short or joined to another)"),
            "{:?}",
            r.report
        );
        // a 1 MiB field is not echoed whole
        let r = with(1, &|l| set(l, "chain", &"7".repeat(1 << 20)));
        assert!(r.report[0].len() < 200, "{}", r.report[0].len());
        // a damaged copy beside a good one: the good one is kept
        let mut copy = good.clone();
        copy.push(set(&good[2], "eta", "NaN"));
        let r = read(&design, &copy, "\n");
        assert_eq!(r.kept.len(), 3);
        assert_eq!(
            r.report,
            [
                "s.csv line 5: configuration 1: eta is NaN, not a finite number: dropped \
                 (configuration 1 is kept from line 3)",
                "s.csv: kept 3 rows, dropped 1 damaged row, recomputing 0 configurations"
            ]
        );
        // a damaged header: nothing can be trusted
        let mut head = good.clone();
        head[0] = head[0].replace("eta", "beta");
        let r = read(&design, &head, "\n");
        assert!(r.kept.is_empty());
        assert_eq!(
            r.report,
            [
                "s.csv: damaged: its header is not this study's columns: its 3 rows cannot be \
              verified: kept 0 rows, recomputing 3 configurations (0, 1 and 2)"
            ]
        );
    }
}
