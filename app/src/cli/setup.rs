//! Shared setup of a solve from command-line options: the options as the front door's
//! overrides ([`scene::open`]: refine/split, the settings layer, parameter values), the
//! refinement that fits when a request does not, and the factorization (timed into the setup
//! counter).

use anyhow::Context;
use clap::Args;
use lopin_core::counters::Instant;
use lopin_core::estimate::Estimate;
use lopin_core::scene::admission::{Footprint, SolveShape};
use lopin_core::scene::spec::SolverSpec;
use lopin_core::scene::Overrides;
use lopin_core::target::Assignment;
use lopin_core::window_choice::{Task, WindowChoice};
use lopin_core::{scene, LopinError, Parameter, Problem, Settings, Solver};

fn parse_assignment(s: &str) -> Result<Assignment, String> {
    Assignment::parse(s).map_err(|e| e.to_string())
}

/// Options shared by the commands that solve a scene.
#[derive(Debug, Clone, Args)]
pub struct SceneArgs {
    /// Built-in scene name (see `lopin scenes`) or path to a .toml scene file.
    pub scene: String,
    /// Friction coefficient of every contact interface (`--set f=VALUE`).
    #[arg(long = "f", allow_hyphen_values = true)]
    pub friction: Option<f64>,
    /// A parameter of the interface laws set on the built problem, on every interface it
    /// applies to or on one zone: `f=0.3`, `gap=1e-5`, `v0=2`, `f@top=0.2` (repeatable; applied
    /// in order, after `--f`).
    #[arg(long = "set", value_name = "NAME[@ZONE]=VALUE", value_parser = parse_assignment)]
    pub set: Vec<Assignment>,
    /// The solver settings, over the scene's `[solver]` table.
    #[command(flatten)]
    pub solver: SolverSpec,
    /// Multiply the mesh divisions by K.
    #[arg(long, default_value_t = 1, allow_negative_numbers = true)]
    pub refine: usize,
    /// Multiply the number of substructures per body by N (along the scene's split axes).
    #[arg(long, default_value_t = 1, allow_negative_numbers = true)]
    pub split: usize,
    /// What the solve is for (set by the command, not an option).
    #[arg(skip)]
    pub task: Task,
}

impl SceneArgs {
    /// A built-in or file scene at `refine` for `task`, under the settings layer `solver` and
    /// nothing else (what the benchmarks open).
    pub fn refined(scene: &str, refine: usize, solver: SolverSpec, task: Task) -> Self {
        SceneArgs {
            scene: scene.to_string(),
            friction: None,
            set: Vec::new(),
            solver,
            refine,
            split: 1,
            task,
        }
    }

    /// These options as the front door reads them ([`scene::Overrides`]); `--f` is checked
    /// here so that its error names it.
    pub fn overrides(&self) -> anyhow::Result<Overrides> {
        if let Some(f) = self.friction {
            Parameter::Friction.check(f).map_err(|e| match e {
                LopinError::Setting { reason, .. } => anyhow::anyhow!("--f: {reason}"),
                other => anyhow::Error::new(other),
            })?;
        }
        Ok(self.unchecked_overrides())
    }

    /// [`Self::overrides`] without the check of `--f`.
    fn unchecked_overrides(&self) -> Overrides {
        let friction = self.friction.map(|value| Assignment {
            target: "f".into(),
            value,
        });
        Overrides {
            refine: self.refine,
            split: self.split,
            solver: self.solver.clone(),
            task: self.task,
            assignments: friction
                .into_iter()
                .chain(self.set.iter().cloned())
                .collect(),
        }
    }

    /// These options for another task (a sweep's solves are a warm-started study).
    pub fn for_task(&self, task: Task) -> Self {
        Self {
            task,
            ..self.clone()
        }
    }

    /// How the solve will run, as far as memory is concerned ([`Overrides::shape`]).
    pub fn shape(&self, spec: &scene::SceneSpec) -> SolveShape {
        self.unchecked_overrides().shape(spec)
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

/// A ready solver and its scene.
pub struct Prepared {
    /// The scene as written, after `--refine` and `--split`.
    pub spec: scene::SceneSpec,
    /// The parameter values set on the problem (`--f`, `--set`).
    pub assignments: Vec<Assignment>,
    /// The time windows chosen and why.
    pub windows: WindowChoice,
    pub solver: Solver,
}

/// A built problem, its scene and the LATIN settings the options ask for.
pub struct Built {
    /// The scene as written, after `--refine` and `--split`.
    pub spec: scene::SceneSpec,
    /// The time windows chosen and why.
    pub windows: WindowChoice,
    /// The sizes and memory of the solve, counted from the scene before building it.
    pub footprint: Footprint,
    pub problem: Problem,
    pub settings: Settings,
    /// The parameter values set on the problem (`--f`, `--set`).
    pub assignments: Vec<Assignment>,
    /// Seconds spent loading and building.
    pub build_s: f64,
}

/// Reads the scene with `--refine`, `--split` and the settings, and counts what a solve will
/// hold from the scene alone ([`scene::admit`]): nothing large is allocated before the request
/// is known to fit, and a refusal gives the numbers and what would fit.
pub fn admitted(args: &SceneArgs) -> anyhow::Result<scene::Admitted> {
    anyhow::ensure!(args.refine >= 1, "--refine must be at least 1");
    anyhow::ensure!(args.split >= 1, "--split must be at least 1");
    if let Some(r) = args.solver.rho_inf {
        lopin_core::time::time_scheme::TimeScheme::new(r)
            .check()
            .map_err(|reason| anyhow::anyhow!("--rho-inf {r}: {reason}"))?;
    }
    let overrides = args.overrides()?;
    scene::admit(&args.scene, &overrides).map_err(|e| match &e {
        LopinError::TooLarge { .. } => match largest_refine_that_fits(args, &overrides) {
            Some(r) => anyhow::anyhow!("{e}; with this scene, --refine {r} fits"),
            None => anyhow::Error::new(e),
        },
        LopinError::Setting { field, .. } if field == "refine" || field == "split" => {
            let flag = format!(
                "--{field} {}",
                if field == "refine" {
                    args.refine
                } else {
                    args.split
                }
            );
            anyhow::Error::new(e).context(flag)
        }
        _ => anyhow::Error::new(e),
    })
}

/// The largest `--refine` below the one asked for whose solve fits this machine (None when the
/// request has no refinement to lower or even `--refine 1` does not fit).
fn largest_refine_that_fits(args: &SceneArgs, overrides: &Overrides) -> Option<usize> {
    let fits = |refine: usize| {
        let at = Overrides {
            refine,
            ..overrides.clone()
        };
        scene::admit(&args.scene, &at).is_ok()
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

/// Reads and builds the problem and resolves the settings (no factorization).
pub fn build(args: &SceneArgs) -> anyhow::Result<Built> {
    let start = Instant::now();
    let admitted = admitted(args)?;
    build_admitted(admitted, start)
}

/// The problem and settings of built-in or file scene `scene` at `refine`, with the default
/// solver options for `task` (the benchmarks' way of building a case).
pub fn problem_for(scene: &str, refine: usize, task: Task) -> anyhow::Result<(Problem, Settings)> {
    let built = build(&SceneArgs::refined(
        scene,
        refine,
        SolverSpec::default(),
        task,
    ))?;
    Ok((built.problem, built.settings))
}

/// [`build`] from a scene already admitted (`estimate` counts it first), timing the build from
/// `start`.
pub fn build_admitted(admitted: scene::Admitted, start: Instant) -> anyhow::Result<Built> {
    let opened = admitted.build()?;
    Ok(Built {
        spec: opened.spec,
        windows: opened.windows,
        footprint: opened.footprint,
        problem: opened.problem,
        settings: opened.settings,
        assignments: opened.assignments,
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
        assignments: built.assignments,
        windows: built.windows,
        solver,
    })
}
