//! `lopin view FOLDER`: a result folder read for the explorer ([`OpenedFolder`]): a run
//! (`run.json` and `solution.bin`, also an MPI run's folder, which rank 0 writes whole), a sweep
//! (`sweep.json`, `run.json`, `value-NNN.json` records and their states) or a study
//! (`study.json`, `run.json`, `study.csv` and `states/config-NNNN.state`); a run folder that
//! holds `fields.bin` (`lopin run --out DIR --fields`) opens from its stored step fields
//! without its scene ([`StoredRun`]). The scene is rebuilt
//! from run.json and checked to be the one the folder's files belong to (fingerprints); each
//! configuration's row comes from the folder's records, checked as a resume checks them (a
//! run's solution, a sweep's record, a study row's checksum), and its state is read by the loader when
//! the explorer shows it, checked whole (checksum, fingerprint, finite values, the problem's
//! layout). Every error names the file and the reason.

use std::path::Path;
use std::sync::{Arc, Mutex};

use anyhow::{bail, Context};
use lopin_core::study::Quantities;
use lopin_core::target::Target;
use lopin_core::Problem;
use lopin_explorer::result_folder::{
    Assigned, FolderKind, ResultRow, ResultTable, StateLoader, StoredResult,
};
use lopin_explorer::stored_run::StoredRun;
use lopin_explorer::{FolderOpener, Loaded, OpenedFolder};

use crate::cli::study::{state_name as study_state, Plan};
use crate::cli::sweep::records::{Header, Store, SWEEP_JSON};
use crate::run_dir::fields_file::{self, FIELDS_BIN};
use crate::run_dir::fingerprint::{self, crc32};
use crate::run_dir::run_json::{RunRecord, RUN_JSON};
use crate::run_dir::saved_states::SavedStates;
use crate::run_dir::SOLUTION_BIN;

/// The opener the desktop explorer uses.
pub fn opener() -> FolderOpener {
    FolderOpener::new(|path| open(path).map_err(|e| format!("{e:#}")))
}

/// Opens a run, sweep or study folder; a run folder with stored step fields opens from them,
/// without its scene.
pub fn open(dir: &Path) -> anyhow::Result<Loaded> {
    anyhow::ensure!(dir.is_dir(), "{}: not a folder", dir.display());
    if dir.join("study.json").exists() {
        return open_study(dir).map(|f| Loaded::Folder(Box::new(f)));
    }
    if dir.join(SWEEP_JSON).exists() {
        return open_sweep(dir).map(|f| Loaded::Folder(Box::new(f)));
    }
    if dir.join(RUN_JSON).exists() {
        if dir.join(FIELDS_BIN).exists() {
            return open_stored(dir).map(|r| Loaded::Stored(Box::new(r)));
        }
        return open_run(dir).map(|f| Loaded::Folder(Box::new(f)));
    }
    bail!(
        "{}: not a result folder: it holds no {RUN_JSON}, {SWEEP_JSON} or study.json (the \
         explorer opens the folders of `lopin run --out`, `lopin sweep --out` and `lopin study \
         --out`)",
        dir.display()
    )
}

/// A run folder with `fields.bin`: its geometry and outcome read, its steps read when shown.
fn open_stored(dir: &Path) -> anyhow::Result<StoredRun> {
    let record = RunRecord::read(dir)?;
    anyhow::ensure!(
        record.kind == "run",
        "{}: run.json describes a {}, not a run, beside {FIELDS_BIN}",
        dir.display(),
        record.kind
    );
    let (head, file) = fields_file::open(&dir.join(FIELDS_BIN), record.fingerprint())?;
    fields_file::stored_run(dir, head, file)
}

/// A run folder: its solution, shown as stored.
fn open_run(dir: &Path) -> anyhow::Result<OpenedFolder> {
    let record = RunRecord::read(dir)?;
    anyhow::ensure!(
        record.kind == "run",
        "{}: run.json describes a {}, but the folder has no {}",
        dir.display(),
        record.kind,
        if record.kind == "sweep" {
            SWEEP_JSON
        } else {
            "study.json"
        }
    );
    let scene = record.open_scene()?;
    // the solution checked now: a damaged or foreign file is refused before anything opens
    let solution = read_run_solution(dir, &record, &scene.problem)?;
    let table = ResultTable::single_run(solution.iterations, solution.converged);
    let folder = dir.to_path_buf();
    // the first show takes the solution read here; a later one reads the file again
    let checked = Mutex::new(Some(solution));
    let loader: StateLoader = Arc::new(move |_, problem: &Problem| {
        let first = checked.lock().map_or(None, |mut s| s.take());
        first
            .map_or_else(|| read_run_solution(&folder, &record, problem), Ok)
            .map(|s| StoredResult::Solution(Box::new(s)))
            .map_err(|e| format!("{e:#}"))
    });
    Ok(OpenedFolder {
        path: dir.to_path_buf(),
        kind: FolderKind::Run,
        scene,
        table,
        loader,
        first: 0,
    })
}

/// A run's `solution.bin`, checked against run.json and the problem.
fn read_run_solution(
    dir: &Path,
    record: &RunRecord,
    problem: &Problem,
) -> anyhow::Result<lopin_core::Solution> {
    let mut solution = record.read_solution(dir)?;
    let bin = dir.join(SOLUTION_BIN);
    solution
        .state
        .check_fits(problem)
        .with_context(|| format!("{}: does not fit run.json's scene", bin.display()))?;
    anyhow::ensure!(
        solution.hats.len() == problem.interfaces.len(),
        "{}: {} interfaces stored, the scene has {}",
        bin.display(),
        solution.hats.len(),
        problem.interfaces.len()
    );
    if let Some(o) = &record.result {
        solution.eta_history.clone_from(&o.eta_history);
    }
    Ok(solution)
}

/// A sweep folder: its finished values, each warm-solved from its stored state when shown.
fn open_sweep(dir: &Path) -> anyhow::Result<OpenedFolder> {
    let header: Header = Store::read_header(dir)?;
    let record = RunRecord::read(dir)?;
    let scene = record.open_scene()?;
    let target = Target::parse(&header.parameter, &scene.problem)
        .with_context(|| format!("{}: field `parameter`", dir.join(SWEEP_JSON).display()))?;
    let store = Store::follow(dir, &header);
    let mut rows = Vec::new();
    let mut values = Vec::new();
    let mut damaged = Vec::new();
    for i in (0..header.values.len()).filter(|&i| store.has_record(i)) {
        match store.read_record(i) {
            Ok(r) => {
                rows.push(ResultRow {
                    name: format!("value {i}"),
                    assigned: vec![Assigned {
                        parameter: target.parameter,
                        zone: target.zone,
                        value: r.value,
                    }],
                    quantities: vec![r.peak_normal_force, r.max_slip, r.energy_end],
                    iterations: Some(r.iterations),
                    converged: r.converged,
                });
                values.push(i);
            }
            Err(e) => damaged.push(e),
        }
    }
    if rows.is_empty() {
        bail!(
            "{}: no finished value can be read{}",
            dir.display(),
            damaged
                .first()
                .map_or(String::new(), |e| format!(" (first: {e})"))
        );
    }
    let folder = dir.to_path_buf();
    let loader: StateLoader = Arc::new(move |row, problem: &Problem| {
        let i = *values.get(row).ok_or_else(|| format!("no row {row}"))?;
        Store::follow(&folder, &header)
            .read_value(i, problem)
            .map(|(_, state)| StoredResult::State(state))
    });
    Ok(OpenedFolder {
        path: dir.to_path_buf(),
        kind: FolderKind::Sweep,
        scene,
        table: ResultTable {
            parameters: vec![target.label],
            quantities: headers(&Quantities::NAMES[..3]),
            rows,
        },
        loader,
        first: 0,
    })
}

/// Column headers of quantities: name and unit.
fn headers(names: &[(&str, &str)]) -> Vec<String> {
    names.iter().map(|(n, u)| format!("{n} ({u})")).collect()
}

/// A study folder: its configurations, each warm-solved from its stored state when shown.
fn open_study(dir: &Path) -> anyhow::Result<OpenedFolder> {
    let json = dir.join("study.json");
    let text =
        std::fs::read_to_string(&json).with_context(|| format!("reading {}", json.display()))?;
    let value: serde_json::Value = serde_json::from_str(&text)
        .with_context(|| format!("{}: not JSON: the file is damaged", json.display()))?;
    let plan: Plan = serde_json::from_value(value["plan"].clone())
        .with_context(|| format!("{}: field `plan`", json.display()))?;
    let record = RunRecord::read(dir).with_context(|| {
        format!(
            "{}: a study folder without its {RUN_JSON} (studies made before the explorer \
             opened them do not hold one: run the study again)",
            dir.display()
        )
    })?;
    let saved = record.fingerprint_as_saved()?.to_string();
    anyhow::ensure!(
        saved == plan.fingerprint,
        "{}: belongs to another study (fingerprint {saved}, study.json has {})",
        dir.join(RUN_JSON).display(),
        plan.fingerprint
    );
    let scene = record.open_scene()?;
    let targets = plan
        .parameters
        .iter()
        .map(|l| Target::parse(l, &scene.problem))
        .collect::<Result<Vec<_>, _>>()
        .with_context(|| format!("{}: field `plan.parameters`", json.display()))?;
    let (rows, indices) = study_rows(&dir.join("study.csv"), &plan, &targets)?;
    let states = SavedStates::new(dir, fingerprint::of_json("study plan", &plan));
    let loader: StateLoader = Arc::new(move |row, problem: &Problem| {
        let i = *indices.get(row).ok_or_else(|| format!("no row {row}"))?;
        states
            .load(&study_state(i), None, problem)
            .map(StoredResult::State)
            .map_err(|u| format!("{}: {} (configuration {i})", u.path.display(), u.reason))
    });
    Ok(OpenedFolder {
        path: dir.to_path_buf(),
        kind: FolderKind::Study,
        scene,
        table: ResultTable {
            parameters: plan.parameters.clone(),
            quantities: headers(&Quantities::NAMES),
            rows,
        },
        loader,
        first: 0,
    })
}

/// The rows of `study.csv` whose checksum holds, with their configuration indices, by index;
/// a file without a readable row is an error naming it.
fn study_rows(
    path: &Path,
    plan: &Plan,
    targets: &[Target],
) -> anyhow::Result<(Vec<ResultRow>, Vec<usize>)> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    let mut lines = text.lines();
    let head: Vec<&str> = lines
        .next()
        .with_context(|| format!("{}: empty", path.display()))?
        .split(',')
        .collect();
    let column = |name: &str| -> anyhow::Result<usize> {
        head.iter()
            .position(|h| *h == name)
            .with_context(|| format!("{}: no column `{name}`", path.display()))
    };
    let index_col = column("index")?;
    let params: Vec<usize> = plan
        .parameters
        .iter()
        .map(|p| column(p))
        .collect::<anyhow::Result<_>>()?;
    let quantities: Vec<usize> = Quantities::NAMES
        .iter()
        .map(|(n, _)| column(n))
        .collect::<anyhow::Result<_>>()?;
    let (iterations, converged) = (column("iterations")?, column("converged")?);
    anyhow::ensure!(
        head.last() == Some(&"checksum"),
        "{}: of an older format, without the checksum column: its rows cannot be verified",
        path.display()
    );
    let mut found: Vec<(usize, ResultRow)> = Vec::new();
    for line in lines.filter(|l| !l.is_empty()) {
        let Some((body, sum)) = line.rsplit_once(',') else {
            continue;
        };
        let fields: Vec<&str> = line.split(',').collect();
        if fields.len() != head.len() || format!("{:08x}", crc32(body.as_bytes())) != sum {
            continue;
        }
        let number = |c: usize| fields[c].parse::<f64>().unwrap_or(f64::NAN);
        let Ok(index) = fields[index_col].parse::<usize>() else {
            continue;
        };
        if index >= plan.configurations || found.iter().any(|(i, _)| *i == index) {
            continue;
        }
        let assigned: Vec<Assigned> = targets
            .iter()
            .zip(&params)
            .map(|(t, &c)| Assigned {
                parameter: t.parameter,
                zone: t.zone,
                value: number(c),
            })
            .collect();
        if assigned.iter().any(|a| !a.value.is_finite()) {
            continue;
        }
        found.push((
            index,
            ResultRow {
                name: format!("config {index}"),
                assigned,
                quantities: quantities.iter().map(|&c| number(c)).collect(),
                iterations: fields[iterations].parse().ok(),
                converged: fields[converged] == "true",
            },
        ));
    }
    anyhow::ensure!(
        !found.is_empty(),
        "{}: no row whose checksum holds",
        path.display()
    );
    found.sort_by_key(|(i, _)| *i);
    let indices = found.iter().map(|(i, _)| *i).collect();
    Ok((found.into_iter().map(|(_, r)| r).collect(), indices))
}
