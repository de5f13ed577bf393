//! `run.json`: how a run or sweep directory was made, so it can be reproduced: the scene
//! (after --refine and --split), the parameter values set on its problem (--f, --set), the
//! LATIN settings (METHOD §10), the problem's sizes,
//! the Lopin version and commit, the command line, the outcome and the timings. `lopin export`
//! rebuilds the solver from it, and checks that `solution.bin` belongs to it: the file carries
//! the [`Fingerprint`] of run.json's scene and settings ([`RunRecord::fingerprint`]).
//! Writing run.json is the run directory's commit point: a `solution.bin` it lists is bound to
//! it then if it was written unbound.

use super::fingerprint::{self, Fingerprint};
use super::solution_file;
use crate::build_info;
use anyhow::Context;
use lopin_core::scene::{self, SceneSpec};
use lopin_core::target::Assignment;
use lopin_core::{Problem, Settings, Solution, Solver};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// File name in a run or sweep directory.
pub const RUN_JSON: &str = "run.json";

/// Which Lopin made it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Provenance {
    pub version: String,
    pub commit: String,
}

/// Sizes of the built problem.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ProblemFacts {
    pub substructures: usize,
    pub interfaces: usize,
    pub contact_interfaces: usize,
    pub dofs: usize,
    pub steps: usize,
    pub dt: f64,
    /// ρ∞ of the time scheme (1: the undamped trapezoidal rule).
    #[serde(default = "undamped")]
    pub rho_inf: f64,
}

fn undamped() -> f64 {
    1.0
}

impl ProblemFacts {
    pub fn of(p: &Problem) -> Self {
        ProblemFacts {
            substructures: p.subs.len(),
            interfaces: p.interfaces.len(),
            contact_interfaces: p.contact_count(),
            dofs: p.dof_count(),
            steps: p.time.steps,
            dt: p.time.dt,
            rho_inf: p.scheme.rho_inf,
        }
    }
}

/// Seconds per stage.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct Timings {
    pub wall: f64,
    pub setup: f64,
    pub local: f64,
    pub linear: f64,
    pub post: f64,
    /// Writing exports and recordings.
    pub outputs: f64,
}

/// How a solve ended.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Outcome {
    pub iterations: usize,
    pub eta: f64,
    pub converged: bool,
    pub eta_history: Vec<f64>,
}

/// A sweep's parameter, values, mode, predictor and progress.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SweepFacts {
    pub parameter: String,
    pub values: Vec<f64>,
    pub mode: String,
    pub predictor: String,
    /// Values finished so far.
    pub finished: usize,
    pub total_iterations: usize,
}

/// The content of run.json.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunRecord {
    /// "run" or "sweep".
    pub kind: String,
    pub lopin: Provenance,
    /// The command line that made it.
    pub command: Vec<String>,
    pub created_unix_s: u64,
    /// Scene as given (built-in name or file).
    pub scene_source: String,
    /// The scene, after `--refine` and `--split`.
    pub scene: SceneSpec,
    /// The parameter values set on its problem (`--f`, `--set`), in order.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub assignments: Vec<Assignment>,
    /// All LATIN settings.
    pub settings: Settings,
    pub problem: ProblemFacts,
    pub timings_s: Timings,
    /// A run's outcome.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub result: Option<Outcome>,
    /// A sweep's parameter, values and totals.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sweep: Option<SweepFacts>,
    /// Files of the directory, relative names.
    #[serde(default)]
    pub files: Vec<String>,
}

impl RunRecord {
    /// A record of `kind` for a solver built from `spec` with `assignments` set.
    pub fn new(
        kind: &str,
        scene_source: &str,
        spec: &SceneSpec,
        assignments: &[Assignment],
        solver: &Solver,
    ) -> Self {
        Self::of_problem(
            kind,
            scene_source,
            spec,
            assignments,
            solver.problem(),
            solver.settings(),
        )
    }

    /// A record of `kind` for `problem`, built from `spec` with `assignments` set, solved with
    /// `settings` (a study's, written before any solver exists).
    pub fn of_problem(
        kind: &str,
        scene_source: &str,
        spec: &SceneSpec,
        assignments: &[Assignment],
        problem: &Problem,
        settings: &Settings,
    ) -> Self {
        RunRecord {
            kind: kind.into(),
            lopin: Provenance {
                version: build_info::VERSION.into(),
                commit: build_info::COMMIT.into(),
            },
            command: std::env::args().collect(),
            created_unix_s: std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map_or(0, |d| d.as_secs()),
            scene_source: scene_source.into(),
            scene: spec.clone(),
            assignments: assignments.to_vec(),
            settings: *settings,
            problem: ProblemFacts::of(problem),
            timings_s: Timings::default(),
            result: None,
            sweep: None,
            files: Vec::new(),
        }
    }

    /// Fills the stage times from the solver's counters and the wall time.
    pub fn set_timings(&mut self, solver: &Solver, wall: f64, outputs: f64) {
        let st = solver.counters().stage_times();
        self.timings_s = Timings {
            wall,
            setup: st.setup,
            local: st.local,
            linear: st.linear,
            post: st.post,
            outputs,
        };
    }

    /// What this run's `solution.bin` belongs to: its scene and settings as read from
    /// run.json ([`fingerprint::of_run`]).
    pub fn fingerprint(&self) -> Fingerprint {
        fingerprint::of_run(&self.scene, &self.assignments, &self.settings)
    }

    /// [`Self::fingerprint`] of this record as a reader of its run.json will see it (numbers
    /// written in JSON may read back different in the last bit, so the record is hashed as
    /// read back).
    pub fn fingerprint_as_saved(&self) -> anyhow::Result<Fingerprint> {
        /// The part of run.json the fingerprint covers.
        #[derive(Serialize, Deserialize)]
        struct Identity {
            scene: SceneSpec,
            assignments: Vec<Assignment>,
            settings: Settings,
        }
        let text = serde_json::to_string(&Identity {
            scene: self.scene.clone(),
            assignments: self.assignments.clone(),
            settings: self.settings,
        })?;
        let back: Identity = serde_json::from_str(&text)
            .context("run.json's scene and settings do not read back")?;
        Ok(fingerprint::of_run(
            &back.scene,
            &back.assignments,
            &back.settings,
        ))
    }

    /// Writes `dir/run.json` (temporary file, then rename).
    pub fn write(&self, dir: &Path) -> anyhow::Result<()> {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
        super::write_atomic(
            &dir.join(RUN_JSON),
            serde_json::to_string_pretty(self)?.as_bytes(),
        )
    }

    /// Writes `dir/solution.bin` bound to this record, then `dir/run.json` listing it and the
    /// `others` files already written there.
    pub fn write_with_solution(
        &self,
        dir: &Path,
        solution: &Solution,
        others: &[&str],
    ) -> anyhow::Result<()> {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
        super::write_atomic(
            &dir.join(super::SOLUTION_BIN),
            &solution_file::encode_solution_for(solution, self.fingerprint_as_saved()?),
        )?;
        let mut r = self.clone();
        r.files = vec![super::SOLUTION_BIN.into()];
        r.files.extend(others.iter().map(|f| f.to_string()));
        r.write(dir)
    }

    /// Reads `dir/solution.bin`, which must belong to this record.
    pub fn read_solution(&self, dir: &Path) -> anyhow::Result<Solution> {
        solution_file::read_solution(&dir.join(super::SOLUTION_BIN), self.fingerprint())
    }

    /// Reads `dir/run.json`.
    pub fn read(dir: &Path) -> anyhow::Result<RunRecord> {
        let path = dir.join(RUN_JSON);
        let text = std::fs::read_to_string(&path).with_context(|| {
            format!(
                "reading {} (is {} a run directory made by `lopin run --out`?)",
                path.display(),
                dir.display()
            )
        })?;
        serde_json::from_str(&text)
            .with_context(|| format!("{}: not a Lopin run.json", path.display()))
    }

    /// Opens a run directory made by `lopin run --out`: its record, the solver rebuilt from it
    /// and the converged solution, checked to belong to it (fingerprint, shapes) with its η
    /// history; a directory of another kind, a damaged or a foreign file is an error naming it.
    pub fn open_run(dir: &Path) -> anyhow::Result<(RunRecord, Solver, Solution)> {
        let record = RunRecord::read(dir)?;
        anyhow::ensure!(
            record.kind == "run",
            "{}: run.json describes a {}, not a run (give a `lopin run --out` directory)",
            dir.display(),
            record.kind
        );
        let bin = dir.join(super::SOLUTION_BIN);
        let mut solution = record.read_solution(dir)?;
        let solver = record.solver()?;
        solution
            .state
            .check_fits(solver.problem())
            .with_context(|| format!("{}: does not fit run.json's scene", bin.display()))?;
        anyhow::ensure!(
            solution.hats.len() == solver.problem().interfaces.len(),
            "{}: {} interfaces stored, the scene has {}",
            bin.display(),
            solution.hats.len(),
            solver.problem().interfaces.len()
        );
        if let Some(o) = &record.result {
            solution.eta_history.clone_from(&o.eta_history);
        }
        Ok((record, solver, solution))
    }

    /// Rebuilds the problem and factorizes it with the recorded settings.
    pub fn solver(&self) -> anyhow::Result<Solver> {
        let opened = self.open_scene()?;
        Ok(Solver::new(opened.problem, opened.settings)?)
    }

    /// Rebuilds the problem, checked to be the one the record describes, with the recorded
    /// settings.
    pub fn open_scene(&self) -> anyhow::Result<scene::Opened> {
        let label = scene::source_label(&self.scene_source);
        // the scheme the run had (records without ρ∞ in their settings held it in the scene)
        let settings = Settings {
            rho_inf: self.problem.rho_inf,
            ..self.settings
        };
        let overrides = scene::Overrides {
            solver: scene::spec::SolverSpec {
                rho_inf: Some(settings.rho_inf),
                ..Default::default()
            },
            assignments: self.assignments.clone(),
            ..scene::Overrides::default()
        };
        let mut opened = scene::open(scene::Source::spec(self.scene.clone(), &label), &overrides)
            .with_context(|| format!("rebuilding {label} from run.json"))?;
        let facts = ProblemFacts::of(&opened.problem);
        anyhow::ensure!(
            facts == self.problem,
            "run.json: the scene rebuilds to {facts:?}, the run had {:?}",
            self.problem
        );
        opened.settings = settings;
        Ok(opened)
    }
}
