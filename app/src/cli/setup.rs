//! Shared setup of a solve from command-line options: scene lookup, refine/split, solver
//! overrides, problem build and factorization (timed into the setup counter).

use anyhow::Context;
use clap::Args;
use lopin_core::counters::Instant;
use lopin_core::estimate::Estimate;
use lopin_core::interfaces::search_direction::Directions;
use lopin_core::scene::admission::{admit, Footprint, SolveShape};
use lopin_core::scene::settings::WindowStart;
use lopin_core::stages::indicator::StopTest;
use lopin_core::window_choice::{choose, Task, WindowChoice, WindowRequest};
use lopin_core::{scene, LopinError, Parameter, Problem, Settings, Solver};

fn parse_directions(s: &str) -> Result<Directions, String> {
    Directions::parse(s)
}

fn parse_window_start(s: &str) -> Result<WindowStart, String> {
    WindowStart::parse(s).map_err(|e| e.to_string())
}

fn parse_stop(s: &str) -> Result<StopTest, String> {
    StopTest::parse(s).map_err(|e| e.to_string())
}

/// Options shared by the commands that solve a scene.
#[derive(Debug, Clone, Args)]
pub struct SceneArgs {
    /// Built-in scene name (see `lopin scenes`) or path to a .toml scene file.
    pub scene: String,
    /// Friction coefficient of every contact interface.
    #[arg(long = "f", allow_hyphen_values = true)]
    pub friction: Option<f64>,
    /// Stopping tolerance on the error indicator η (default 1e-3).
    #[arg(long, allow_hyphen_values = true)]
    pub tol: Option<f64>,
    /// Search direction k in Pa·s/m (default: mean of sqrt(rho E) over the materials).
    #[arg(long, allow_hyphen_values = true)]
    pub k: Option<f64>,
    /// Relaxation μ in (0, 1] (default 0.8).
    #[arg(long, allow_hyphen_values = true)]
    pub mu: Option<f64>,
    /// Spectral radius at infinite frequency of the time scheme in [0, 1]: 1 is the undamped
    /// trapezoidal rule, smaller damps the highest frequencies (default: the scene's
    /// `solver.rho_inf`, else 1).
    #[arg(long = "rho-inf", allow_hyphen_values = true)]
    pub rho_inf: Option<f64>,
    /// Shape of the search direction: `isotropic` (the scalar k on every dof) or `wave` (the
    /// P-wave impedance along the interface normal, the S-wave impedance across it; default:
    /// the scene's `solver.directions`, else isotropic).
    #[arg(long, value_parser = parse_directions)]
    pub directions: Option<Directions>,
    /// Which indicator ends a window: `eta` (the fields themselves, METHOD §6) or `smooth` (η̄,
    /// the same measure on step-averaged fields, blind to the undamped rule's alternating mode;
    /// default: the scene's `solver.stop`, else eta).
    #[arg(long, value_parser = parse_stop)]
    pub stop: Option<StopTest>,
    /// Depth of the Anderson acceleration of the relaxation (0: plain relaxation; default: the
    /// scene's `solver.anderson`, else 0).
    #[arg(long, allow_negative_numbers = true)]
    pub anderson: Option<usize>,
    /// Multiply the mesh divisions by K.
    #[arg(long, default_value_t = 1, allow_negative_numbers = true)]
    pub refine: usize,
    /// Multiply the number of substructures per body by N (along the scene's split axes).
    #[arg(long, default_value_t = 1, allow_negative_numbers = true)]
    pub split: usize,
    /// Time windows: a length in steps (1 = incremental), `whole` (the whole interval) or `auto`
    /// (the default: the scene's `solver.window`, else chosen for the command: one-step windows
    /// for one solve or a study of a scene with contact, the whole interval without contact;
    /// the report says which).
    #[arg(long, allow_negative_numbers = true, value_parser = WindowRequest::parse)]
    pub window: Option<WindowRequest>,
    /// Where a cold time window's iteration starts: `smooth` (extrapolate the mean change of
    /// the last two converged steps), `linear` (the last step's change), `hold` (the last step
    /// held constant), `zero`, or `auto` (smooth at --tol 1e-3 and tighter, hold above; default:
    /// the scene's `solver.window_start`, else auto).
    #[arg(long = "window-start", value_parser = parse_window_start)]
    pub window_start: Option<WindowStart>,
    /// What the solve is for (set by the command, not an option).
    #[arg(skip)]
    pub task: Task,
    /// Iteration limit (per window).
    #[arg(long, allow_negative_numbers = true)]
    pub max_iter: Option<usize>,
    /// Two-scale linear stage with the macro problem of METHOD §9 (default: the scene's
    /// `solver.macro`, else off).
    #[arg(long = "macro", value_enum)]
    pub two_scale: Option<Switch>,
}

impl SceneArgs {
    /// The time windows of the solve and why ([`choose`]).
    pub fn windows(&self, spec: &scene::SceneSpec) -> WindowChoice {
        choose(
            self.task,
            self.window.unwrap_or_default(),
            spec.solver.window,
            spec.has_contact(),
        )
    }

    /// These options for another task (a sweep's solves are a warm-started study).
    pub fn for_task(&self, task: Task) -> Self {
        Self {
            task,
            ..self.clone()
        }
    }

    /// How the solve will run, as far as memory is concerned: the options, else the scene's
    /// `[solver]` table.
    pub fn shape(&self, spec: &scene::SceneSpec) -> SolveShape {
        let mut shape = SolveShape::of_scene(spec);
        shape.window = self.windows(spec).window;
        if let Some(s) = self.two_scale {
            shape.two_scale = s == Switch::On;
        }
        shape
    }
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
    /// The time windows chosen and why.
    pub windows: WindowChoice,
    pub solver: Solver,
}

/// A built problem, its resolved scene and the LATIN settings the options ask for.
pub struct Built {
    pub spec: scene::SceneSpec,
    /// The time windows chosen and why.
    pub windows: WindowChoice,
    /// The sizes and memory of the solve, counted from the scene before building it.
    pub footprint: Footprint,
    pub problem: Problem,
    pub settings: Settings,
    /// Seconds spent loading and building.
    pub build_s: f64,
}

/// A scene loaded, refined and split, and admitted: its footprint fits this machine.
pub struct Admitted {
    pub spec: scene::SceneSpec,
    /// How errors name the scene (`scene NAME` or the file path).
    pub source: String,
    pub footprint: Footprint,
}

/// Loads the scene, applies `--refine`, `--split` and `--f`, and counts what a solve will hold
/// from the scene alone ([`admit`]): nothing large is allocated before the request is known to
/// fit, and a refusal gives the numbers and what would fit.
pub fn admitted(args: &SceneArgs) -> anyhow::Result<Admitted> {
    let mut spec = scene::load(&args.scene)?;
    anyhow::ensure!(args.refine >= 1, "--refine must be at least 1");
    anyhow::ensure!(args.split >= 1, "--split must be at least 1");
    spec.refine(args.refine)
        .with_context(|| format!("--refine {}", args.refine))?;
    spec.split(args.split)
        .with_context(|| format!("--split {}", args.split))?;
    let source = scene::source_label(&args.scene);
    // nothing large is allocated before the request is known to fit; loading validated the
    // scene as written, so only a refined or split one is validated again
    let resized = args.refine != 1 || args.split != 1;
    let footprint = (if resized {
        scene::build::validate(&spec, &source)
    } else {
        Ok(())
    })
    .and_then(|()| admit(&spec, &source, args.shape(&spec)))
    .map_err(|e| match &e {
        LopinError::TooLarge { .. } => match largest_refine_that_fits(args) {
            Some(r) => anyhow::anyhow!("{e}; with this scene, --refine {r} fits"),
            None => anyhow::Error::new(e),
        },
        _ => anyhow::Error::new(e),
    })?;
    if let Some(f) = args.friction {
        Parameter::Friction.check(f).map_err(|e| match e {
            lopin_core::LopinError::Setting { reason, .. } => anyhow::anyhow!("--f: {reason}"),
            other => anyhow::Error::new(other),
        })?;
        spec.set_friction(f);
    }
    // into the scene, so that run.json, `lopin export` and a sweep's resume check carry it
    if let Some(r) = args.rho_inf {
        lopin_core::time::time_scheme::TimeScheme::new(r)
            .check()
            .map_err(|reason| anyhow::anyhow!("--rho-inf {r}: {reason}"))?;
        spec.solver.rho_inf = Some(r);
    }
    Ok(Admitted {
        spec,
        source,
        footprint,
    })
}

/// The largest `--refine` below the one asked for whose solve fits this machine (None when the
/// request has no refinement to lower or even `--refine 1` does not fit).
fn largest_refine_that_fits(args: &SceneArgs) -> Option<usize> {
    let base = scene::load(&args.scene).ok()?;
    let source = scene::source_label(&args.scene);
    let fits = |r: usize| {
        let mut spec = base.clone();
        spec.refine(r).is_ok()
            && spec.split(args.split).is_ok()
            && admit(&spec, &source, args.shape(&spec)).is_ok()
    };
    if args.refine <= 1 || !fits(1) {
        return None;
    }
    // the memory grows with the refinement: bisect between a fitting and a refused value
    let (mut lo, mut hi) = (1, args.refine);
    while hi - lo > 1 {
        let mid = lo + (hi - lo) / 2;
        if fits(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some(lo)
}

/// Loads and builds the problem and resolves the settings (no factorization).
pub fn build(args: &SceneArgs) -> anyhow::Result<Built> {
    let start = Instant::now();
    let admitted = admitted(args)?;
    build_admitted(args, admitted, start)
}

/// [`build`] from a scene already loaded and admitted (`estimate` counts it first), timing the
/// build from `start`.
pub fn build_admitted(
    args: &SceneArgs,
    Admitted {
        spec,
        source,
        footprint,
    }: Admitted,
    start: Instant,
) -> anyhow::Result<Built> {
    let problem = scene::build::build(&spec, &source)?;
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
    let windows = args.windows(&spec);
    settings.window = windows.window;
    if let Some(v) = args.max_iter {
        settings.max_iter = v;
    }
    if let Some(v) = args.two_scale {
        settings.two_scale = v == Switch::On;
    }
    if let Some(v) = args.directions {
        settings.directions = v;
    }
    if let Some(v) = args.stop {
        settings.stop = v;
    }
    if let Some(v) = args.anderson {
        settings.anderson = v;
    }
    if let Some(v) = args.window_start {
        settings.window_start = v;
    }
    Ok(Built {
        spec,
        windows,
        footprint,
        problem,
        settings,
        build_s: start.elapsed().as_secs_f64(),
    })
}

/// Loads, builds and factorizes. A large problem (over 200,000 dofs or 1 GiB) gets its memory
/// estimate printed on stderr before the factorization, and its time estimate after.
///
/// Under `mpirun` ([`crate::ranks`]) every rank builds the problem description and makes the
/// solver of its rank, which factorizes only its substructures; an error on any rank ends every
/// rank, reported once.
pub fn prepare(args: &SceneArgs) -> anyhow::Result<Prepared> {
    let built = crate::ranks::agree(build(args))?;
    let counted = &built.footprint;
    let root = crate::ranks::is_root();
    let large = root && (counted.dofs > 200_000 || counted.total_bytes() > 1 << 30);
    if large {
        for line in counted.lines() {
            eprintln!("estimate: {line}");
        }
    }
    let source = scene::source_label(&args.scene);
    let solver = match crate::ranks::current() {
        None => Solver::new(built.problem, built.settings),
        Some(r) => Solver::new_distributed(built.problem, built.settings, r),
    };
    let mut solver =
        crate::ranks::agree(solver.with_context(|| format!("{source}: setting up the solver")))?;
    solver.add_setup_time(built.build_s);
    if large && solver.distribution().is_single() {
        for line in Estimate::of_solver(&solver).lines().iter().skip(1) {
            eprintln!("estimate: {line}");
        }
    }
    Ok(Prepared {
        spec: built.spec,
        windows: built.windows,
        solver,
    })
}
