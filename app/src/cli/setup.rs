//! Shared setup of a solve from command-line options: scene lookup, refine/split, solver
//! overrides, problem build and factorization (timed into the setup counter).

use anyhow::Context;
use clap::Args;
use lopin_core::counters::Instant;
use lopin_core::estimate::Estimate;
use lopin_core::{scene, Parameter, Problem, Settings, Solver};

/// Options shared by the commands that solve a scene.
#[derive(Debug, Clone, Args)]
pub struct SceneArgs {
    /// Built-in scene name (see `lopin scenes`) or path to a .toml scene file.
    pub scene: String,
    /// Friction coefficient of every contact interface.
    #[arg(long = "f")]
    pub friction: Option<f64>,
    /// Stopping tolerance on the error indicator η (default 1e-3).
    #[arg(long)]
    pub tol: Option<f64>,
    /// Search direction k in Pa·s/m (default: mean of sqrt(rho E) over the materials).
    #[arg(long)]
    pub k: Option<f64>,
    /// Relaxation μ in (0, 1] (default 0.8).
    #[arg(long)]
    pub mu: Option<f64>,
    /// Multiply the mesh divisions by K.
    #[arg(long, default_value_t = 1)]
    pub refine: usize,
    /// Multiply the number of substructures per body by N (along the scene's split axes).
    #[arg(long, default_value_t = 1)]
    pub split: usize,
    /// Time-window length in steps (1 = incremental; default: whole interval).
    #[arg(long)]
    pub window: Option<usize>,
    /// Iteration limit (per window).
    #[arg(long)]
    pub max_iter: Option<usize>,
    /// Two-scale linear stage with the macro problem of METHOD §9 (default: the scene's
    /// `solver.macro`, else off).
    #[arg(long = "macro", value_enum)]
    pub two_scale: Option<Switch>,
}

/// An on/off command-line switch.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Switch {
    /// Enabled.
    On,
    /// Disabled.
    Off,
}

/// A ready solver and the resolved scene.
pub struct Prepared {
    pub spec: scene::SceneSpec,
    pub solver: Solver,
}

/// A built problem, its resolved scene and the LATIN settings the options ask for.
pub struct Built {
    pub spec: scene::SceneSpec,
    pub problem: Problem,
    pub settings: Settings,
    /// Seconds spent loading and building.
    pub build_s: f64,
}

/// Loads and builds the problem and resolves the settings (no factorization).
pub fn build(args: &SceneArgs) -> anyhow::Result<Built> {
    let start = Instant::now();
    let mut spec = scene::load(&args.scene)?;
    anyhow::ensure!(args.refine >= 1, "--refine must be at least 1");
    anyhow::ensure!(args.split >= 1, "--split must be at least 1");
    spec.refine(args.refine);
    spec.split(args.split);
    if let Some(f) = args.friction {
        Parameter::Friction
            .check(f)
            .map_err(|_| anyhow::anyhow!("--f must be a non-negative number, got {f}"))?;
        spec.set_friction(f);
    }
    let problem = scene::build::build(&spec, &scene::source_label(&args.scene))?;
    let mut settings = Settings::for_problem(&problem, &spec.solver);
    if let Some(v) = args.tol {
        settings.tol = v;
    }
    if let Some(v) = args.k {
        settings.k = v;
    }
    if let Some(v) = args.mu {
        settings.mu = v;
    }
    if let Some(v) = args.window {
        settings.window = Some(v);
    }
    if let Some(v) = args.max_iter {
        settings.max_iter = v;
    }
    if let Some(v) = args.two_scale {
        settings.two_scale = v == Switch::On;
    }
    Ok(Built {
        spec,
        problem,
        settings,
        build_s: start.elapsed().as_secs_f64(),
    })
}

/// Loads, builds and factorizes. A large problem (over 200,000 dofs or 1 GiB) gets its memory
/// estimate printed on stderr before the factorization, and its time estimate after.
pub fn prepare(args: &SceneArgs) -> anyhow::Result<Prepared> {
    let built = build(args)?;
    let early = Estimate::of(&built.problem, &built.settings);
    let large = early.is_large();
    if large {
        for line in early.lines() {
            eprintln!("estimate: {line}");
        }
    }
    let mut solver = Solver::new(built.problem, built.settings).context("setting up the solver")?;
    solver.add_setup_time(built.build_s);
    if large {
        for line in Estimate::of_solver(&solver).lines().iter().skip(1) {
            eprintln!("estimate: {line}");
        }
    }
    Ok(Prepared {
        spec: built.spec,
        solver,
    })
}
