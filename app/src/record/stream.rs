//! A Rerun recording of Lopin runs (rerun SDK, behind the `rerun` feature): the scene and
//! settings as a text document; per LATIN iteration (METHOD §7) η and the stage times on the
//! `iteration` timeline; per time step (METHOD §2 grid, `time` timeline in seconds) the deformed
//! surface of each substructure coloured by von Mises stress, subsampled nodal velocity arrows,
//! and contact pressure, normal force and slip on every contact interface (METHOD §5); for
//! sweeps, the quantities of interest on the `parameter` timeline. Log from one thread: Rerun's
//! time cursor is per thread.

use super::steps;
use super::target::Target;
use super::StepsSummary;
use anyhow::Context;
use lopin_core::counters::IterationRecord;
use lopin_core::post::SubFields;
use lopin_core::{Solution, Solver};
use std::time::Duration;

/// Entity path of the text document describing the run.
pub const SCENE_DOC: &str = "scene";

/// An open recording.
pub struct Recorder {
    rec: rerun::RecordingStream,
    target: Target,
    /// Next index on the `iteration` timeline (cumulative over the solves recorded).
    next_iteration: i64,
    /// Surfaces whose triangles were logged (static), by problem name.
    topology: Option<String>,
}

impl Recorder {
    /// Opens a recording named `name` (checks a viewer address first).
    pub fn open(target: &Target, name: &str) -> anyhow::Result<Recorder> {
        target.check()?;
        let builder = rerun::RecordingStreamBuilder::new("lopin").recording_name(name);
        let rec = match target {
            Target::File(path) => builder
                .save(path)
                .with_context(|| format!("--rerun: cannot create {}", path.display()))?,
            Target::Connect { url, .. } => builder
                .connect_grpc_opts(url.clone())
                .with_context(|| format!("--rerun-connect: cannot stream to {url}"))?,
        };
        Ok(Recorder {
            rec,
            target: target.clone(),
            next_iteration: 0,
            topology: None,
        })
    }

    /// Where it records.
    pub fn target(&self) -> &Target {
        &self.target
    }

    /// Stores the description of the run (markdown: how it was made).
    pub fn describe(&self, markdown: &str) -> anyhow::Result<()> {
        self.rec
            .log_static(SCENE_DOC, &rerun::TextDocument::from_markdown(markdown))
            .context("rerun: logging the scene document")
    }

    /// Logs one LATIN iteration: η, local and linear stage seconds.
    pub fn iteration(&mut self, r: &IterationRecord) -> anyhow::Result<()> {
        self.eta(r.eta, Some((r.local_s, r.linear_s)))
    }

    /// Logs one iteration's η, and its local and linear stage seconds when known.
    pub fn eta(&mut self, eta: f64, stage_s: Option<(f64, f64)>) -> anyhow::Result<()> {
        self.rec.set_time_sequence("iteration", self.next_iteration);
        self.next_iteration += 1;
        let log = |path: &str, x: f64| self.rec.log(path, &rerun::Scalars::single(x));
        log("convergence/eta", eta)?;
        if let Some((local, linear)) = stage_s {
            log("convergence/local_s", local)?;
            log("convergence/linear_s", linear)?;
        }
        self.rec.disable_timeline("iteration");
        Ok(())
    }

    /// Logs every time step of a converged solution (`history`: `post::history` of it); `context` timelines (e.g. `parameter`,
    /// `solve`) are set on every row. Returns the colour range and scales used.
    pub fn solution(
        &mut self,
        solver: &Solver,
        sol: &Solution,
        history: &[Vec<SubFields>],
        context: &[(&'static str, i64)],
        deform: Option<f64>,
    ) -> anyhow::Result<StepsSummary> {
        let name = solver.problem().name.clone();
        let log_topology = self.topology.as_deref() != Some(name.as_str());
        let out = steps::log(
            &self.rec,
            solver,
            sol,
            history,
            context,
            deform,
            log_topology,
        )?;
        self.topology = Some(name);
        Ok(out)
    }

    /// Logs the quantities of one parameter value of a sweep (`parameter` timeline = index).
    pub fn parameter(&self, index: usize, quantities: &[(&str, f64)]) -> anyhow::Result<()> {
        self.rec.set_time_sequence("parameter", index as i64);
        for (name, value) in quantities {
            self.rec
                .log(format!("sweep/{name}"), &rerun::Scalars::single(*value))?;
        }
        self.rec.disable_timeline("parameter");
        Ok(())
    }

    /// Logs the parameters and outcome of one explorer solve (`solve` timeline = index).
    pub fn solve_parameters(&self, index: i64, values: &[(&str, f64)]) -> anyhow::Result<()> {
        self.rec.set_time_sequence("solve", index);
        for (name, value) in values {
            self.rec.log(
                format!("parameters/{name}"),
                &rerun::Scalars::single(*value),
            )?;
        }
        self.rec.disable_timeline("solve");
        Ok(())
    }

    /// Flushes and closes the recording (a file is complete when this returns); returns where
    /// it went.
    pub fn close(self, timeout: Duration) -> anyhow::Result<Target> {
        let Recorder { rec, target, .. } = self;
        rec.flush_with_timeout(timeout)
            .map_err(|e| anyhow::anyhow!("rerun: flushing to {}: {e}", target.describe()))?;
        drop(rec);
        Ok(target)
    }
}
