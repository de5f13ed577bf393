//! The outputs a solve can leave besides the terminal, shared by `run`, `sweep` and `export`:
//! clap options (`--out`, `--vtu`, `--rerun`, `--rerun-connect`, `--rerun-deform`), the Rerun
//! recorder they open, and the markdown that tells a recording how it was made.

use crate::build_info;
use crate::record::{Recorder, Target};
use clap::Args;
use lopin_core::scene::{self, SceneSpec};
use lopin_core::Solver;
use std::path::PathBuf;
use std::time::Duration;

/// How long the end of a recording may take to reach its file or viewer.
pub const FLUSH_TIMEOUT: Duration = Duration::from_secs(120);

/// Rerun recording options.
#[derive(Debug, Clone, Default, Args)]
pub struct RerunArgs {
    /// Save a Rerun recording to FILE.rrd: the deformed surfaces coloured by von Mises stress,
    /// velocity arrows and contact pressure per time step, η per iteration, and how the run was
    /// made.
    #[arg(long, value_name = "FILE.rrd")]
    pub rerun: Option<PathBuf>,
    /// Stream the same recording to a running Rerun viewer (HOST:PORT or
    /// rerun+http://HOST:PORT/proxy).
    #[arg(long, value_name = "ADDR", conflicts_with = "rerun")]
    pub rerun_connect: Option<String>,
    /// Displacement scale of the recorded surfaces (default: the largest displacement is drawn
    /// as 5 % of the scene's size).
    #[arg(long, value_name = "SCALE")]
    pub rerun_deform: Option<f64>,
}

impl RerunArgs {
    /// The chosen target, if any.
    pub fn target(&self) -> anyhow::Result<Option<Target>> {
        if let Some(s) = self.rerun_deform {
            anyhow::ensure!(
                s.is_finite() && s >= 0.0,
                "--rerun-deform must be a non-negative number, got {s}"
            );
        }
        match (&self.rerun, &self.rerun_connect) {
            (Some(f), _) => Ok(Some(Target::File(f.clone()))),
            (None, Some(a)) => Ok(Some(Target::connect(a)?)),
            (None, None) => Ok(None),
        }
    }

    /// Opens the recording (before the solve, so a bad target fails at once) and stores the
    /// description.
    pub fn open(&self, name: &str, description: &str) -> anyhow::Result<Option<Recorder>> {
        let Some(target) = self.target()? else {
            return Ok(None);
        };
        let rec = Recorder::open(&target, name)?;
        rec.describe(description)?;
        Ok(Some(rec))
    }
}

/// Where a run's results go.
#[derive(Debug, Clone, Default, Args)]
pub struct OutputArgs {
    /// Save the run in DIR (run.json: scene, settings, version, timings; solution.bin: the
    /// converged interface fields), so `lopin export DIR` can write VTU files or a recording
    /// later without solving again.
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Write one VTU file per substructure and time step, and run.pvd (the collection with the
    /// physical times), to DIR for ParaView.
    #[arg(long, value_name = "DIR")]
    pub vtu: Option<PathBuf>,
    /// With --out: also store every step's fields in DIR/fields.bin (displacement, velocity,
    /// von Mises stress in single precision, with the scene's surfaces), so `lopin view DIR`
    /// opens the run without its scene, factorizations or replay: for large runs.
    #[arg(long, requires = "out")]
    pub fields: bool,
    #[command(flatten)]
    pub rerun: RerunArgs,
}

impl OutputArgs {
    /// Checks before any solving that every output folder can be one: an existing path that
    /// is not a folder is an error naming the option and the path.
    pub fn check_paths(&self) -> anyhow::Result<()> {
        for (option, dir) in [("--out", &self.out), ("--vtu", &self.vtu)] {
            if let Some(dir) = dir {
                check_dir(option, dir)?;
            }
        }
        Ok(())
    }
}

/// An output folder option: a path that exists must be a folder.
pub fn check_dir(option: &str, dir: &std::path::Path) -> anyhow::Result<()> {
    if dir.exists() && !dir.is_dir() {
        anyhow::bail!(
            "{option} {}: exists and is not a folder (give a new or existing folder)",
            dir.display()
        );
    }
    Ok(())
}

/// The markdown a recording stores: provenance, command, settings, sizes and the scene.
pub fn describe(kind: &str, spec: &SceneSpec, solver: &Solver, extra: &str) -> String {
    let p = solver.problem();
    let s = solver.settings();
    let command: Vec<String> = std::env::args().collect();
    format!(
        "# Lopin {kind}: {}\n\n{}\n\nCommand: `{}`\n\n{extra}\n\n## Settings\n\n\
         k = {:.6e} Pa·s/m, μ = {}, tol = {:e}, max_iter = {}, window = {}\n\n\
         ## Problem\n\n{} substructures, {} interfaces ({} contact), {} dofs, {} steps × Δt = {:e} s\n\n\
         ## Scene (resolved)\n\n```toml\n{}```\n",
        spec.name,
        build_info::line(),
        command.join(" "),
        s.k,
        s.mu,
        s.tol,
        s.max_iter,
        s.window.map_or("whole interval".into(), |w| format!("{w} steps")),
        p.subs.len(),
        p.interfaces.len(),
        p.contact_count(),
        p.dof_count(),
        p.time.steps,
        p.time.dt,
        scene::to_toml(spec)
    )
}
