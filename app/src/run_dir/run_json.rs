//! `run.json`: how a run or sweep directory was made, so it can be reproduced: the resolved
//! scene (after --refine, --split, --f), the LATIN settings (METHOD §10), the problem's sizes,
//! the Lopin version and commit, the command line, the outcome and the timings. `lopin export`
//! rebuilds the solver from it.

use crate::build_info;
use anyhow::Context;
use lopin_core::scene::{self, SceneSpec};
use lopin_core::{Problem, Settings, Solver};
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
    /// The resolved scene.
    pub scene: SceneSpec,
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
    /// A record of `kind` for a solver built from `spec`.
    pub fn new(kind: &str, scene_source: &str, spec: &SceneSpec, solver: &Solver) -> Self {
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
            settings: *solver.settings(),
            problem: ProblemFacts::of(solver.problem()),
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

    /// Writes `dir/run.json` (temporary file, then rename).
    pub fn write(&self, dir: &Path) -> anyhow::Result<()> {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
        super::write_atomic(
            &dir.join(RUN_JSON),
            serde_json::to_string_pretty(self)?.as_bytes(),
        )
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

    /// Rebuilds the problem and factorizes it with the recorded settings.
    pub fn solver(&self) -> anyhow::Result<Solver> {
        let label = scene::source_label(&self.scene_source);
        let problem = scene::build::build(&self.scene, &label)
            .with_context(|| format!("rebuilding {label} from run.json"))?;
        let facts = ProblemFacts::of(&problem);
        anyhow::ensure!(
            facts == self.problem,
            "run.json: the scene rebuilds to {facts:?}, the run had {:?}",
            self.problem
        );
        Ok(Solver::new(problem, self.settings)?)
    }
}
