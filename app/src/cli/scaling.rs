//! `lopin scaling`: LATIN iterations to η < tol against the number of substructures, with and
//! without the macro problem (METHOD §9, §12 case 4): one cube of matrix material (SCENES.md
//! `granular` matrix, no grains) meshed once, cut into n × n × n cells with perfect interfaces,
//! pushed on top and clamped below, then any named scenes (e.g. the granular ones). Prints a
//! Markdown table (comfy-table) when all are done; each row's two runs are on the same machine in the same process.

use std::process::ExitCode;

use clap::Args;
use lopin_core::counters::Instant;
use lopin_core::scene::spec::{
    BodySpec, BoundarySpec, ComponentSpec, MaterialSpec, SceneSpec, SolverSpec,
};
use lopin_core::time::time_function::TimeGrid;
use lopin_core::window_choice::Task;
use lopin_core::{scene, Solver};

use super::report::markdown_table;

/// Options of `lopin scaling`.
#[derive(Debug, Args)]
pub struct ScalingArgs {
    /// Cells per side of the cube (n: n³ substructures).
    #[arg(long, value_delimiter = ',', default_value = "2,4,6,8")]
    cells: Vec<usize>,
    /// Hexahedra per side of the whole cube (divisible by every n).
    #[arg(long, default_value_t = 24)]
    elements: usize,
    /// Time steps of the cube runs.
    #[arg(long, default_value_t = 60)]
    steps: usize,
    /// Further scenes (built-in names or files) run with and without the macro problem.
    #[arg(long, value_delimiter = ',', default_value = "granular-small")]
    scenes: Vec<String>,
    /// Stopping tolerance on η.
    #[arg(long, default_value_t = 1e-3)]
    tol: f64,
    /// Relaxation μ (default 0.8).
    #[arg(long)]
    mu: Option<f64>,
    /// Print one JSON array instead of the table.
    #[arg(long)]
    json: bool,
}

/// The cube cut into n³ cells (side 0.1 m, matrix material of SCENES.md `granular`).
pub fn cube(n: usize, elements: usize, steps: usize) -> SceneSpec {
    let h = 0.1 / elements as f64;
    // Δt = 0.5 h / c_p of the matrix (c_p = 3727 m/s), ramp over 10 steps
    let dt = 0.5 * h / 3727.0;
    SceneSpec {
        name: format!("cube-{n}"),
        description: format!("cube of {n}x{n}x{n} cells, perfect interfaces"),
        refine_axes: "xyz".into(),
        split_axes: "xyz".into(),
        time: TimeGrid { dt, steps },
        solver: SolverSpec::default(),
        materials: vec![MaterialSpec {
            name: "matrix".into(),
            young: 30e9,
            poisson: 0.2,
            density: 2400.0,
            ..MaterialSpec::default()
        }],
        mesh_bodies: Vec::new(),
        granular_poly: None,
        zones: Vec::new(),
        bodies: vec![BodySpec {
            name: "cube".into(),
            material: "matrix".into(),
            min: [0.0; 3],
            max: [0.1; 3],
            divisions: [elements; 3],
            split: [n; 3],
            velocity: [0.0; 3],
            elements: None,
            substructures: None,
        }],
        interfaces: vec![],
        boundaries: vec![
            BoundarySpec {
                body: "cube".into(),
                face: "z+".into(),
                surface: None,
                clamped: false,
                preload: false,
                x: None,
                y: None,
                z: Some(ComponentSpec::velocity(-10.0, 10.0 * dt)),
                normal: None,
            },
            BoundarySpec {
                body: "cube".into(),
                face: "z-".into(),
                surface: None,
                clamped: true,
                preload: false,
                x: None,
                y: None,
                z: None,
                normal: None,
            },
        ],
        granular: None,
    }
}

/// One row: a scene run without and with the macro problem.
#[derive(Debug, serde::Serialize)]
struct Row {
    scene: String,
    substructures: usize,
    interfaces: usize,
    contact: usize,
    dofs: usize,
    macro_dofs: usize,
    factorizations: usize,
    iterations_single: usize,
    iterations_two: usize,
    converged: bool,
    reduction_percent: f64,
    seconds_single: f64,
    seconds_two: f64,
    macro_seconds: f64,
    macro_factor_values: usize,
}

fn measure(spec: &SceneSpec, source: &str, args: &ScalingArgs) -> anyhow::Result<Row> {
    let overrides = scene::Overrides {
        solver: SolverSpec {
            tol: Some(args.tol),
            mu: args.mu,
            ..SolverSpec::default()
        },
        // the whole interval unless the scene names its windows
        task: Task::Interactive,
        ..scene::Overrides::default()
    };
    let scene::Opened {
        problem,
        mut settings,
        ..
    } = scene::open(scene::Source::spec(spec.clone(), source), &overrides)?;
    let (subs, interfaces, contact, dofs) = (
        problem.subs.len(),
        problem.interfaces.len(),
        problem.contact_count(),
        problem.dof_count(),
    );
    let mut solver = Solver::new(problem, settings)?;
    let start = Instant::now();
    let single = solver.solve(None)?;
    let seconds_single = start.elapsed().as_secs_f64();
    settings.two_scale = true;
    solver.set_settings(settings)?;
    let start = Instant::now();
    let two = solver.solve(None)?;
    let seconds_two = start.elapsed().as_secs_f64();
    let macro_dofs = solver.macro_problem().map_or(0, |m| m.size);
    let macro_factor_values = solver.macro_problem().map_or(0, |m| m.factor_nnz());
    let macro_seconds = solver.counters().iterations.iter().map(|r| r.macro_s).sum();
    Ok(Row {
        scene: spec.name.clone(),
        substructures: subs,
        interfaces,
        contact,
        dofs,
        macro_dofs,
        factorizations: solver.factors().len(),
        iterations_single: single.iterations,
        iterations_two: two.iterations,
        converged: single.converged && two.converged,
        reduction_percent: 100.0 * (1.0 - two.iterations as f64 / single.iterations as f64),
        seconds_single,
        seconds_two,
        macro_seconds,
        macro_factor_values,
    })
}

pub fn scaling(args: &ScalingArgs) -> anyhow::Result<ExitCode> {
    for &n in &args.cells {
        anyhow::ensure!(
            n >= 1 && args.elements.is_multiple_of(n),
            "--cells {n} does not divide --elements {}",
            args.elements
        );
    }
    let mut rows = Vec::new();
    let mut table = markdown_table([
        "scene",
        "substructures",
        "interfaces (contact)",
        "dofs",
        "macro dofs",
        "factorizations",
        "iterations single-scale",
        "iterations two-scale",
        "reduction",
        "time single / two-scale (of which macro solves)",
    ]);
    let mut runs: Vec<(SceneSpec, String)> = args
        .cells
        .iter()
        .map(|&n| {
            let s = cube(n, args.elements, args.steps);
            let name = s.name.clone();
            (s, name)
        })
        .collect();
    for name in args.scenes.iter().filter(|s| !s.is_empty()) {
        runs.push((scene::load(name)?, scene::source_label(name)));
    }
    for (spec, source) in &runs {
        let r = measure(spec, source, args)?;
        if !args.json {
            eprintln!("{}: done", r.scene);
        }
        table.add_row([
            r.scene.clone(),
            r.substructures.to_string(),
            format!("{} ({})", r.interfaces, r.contact),
            r.dofs.to_string(),
            r.macro_dofs.to_string(),
            r.factorizations.to_string(),
            r.iterations_single.to_string(),
            r.iterations_two.to_string(),
            format!(
                "{:.0} %{}",
                r.reduction_percent,
                if r.converged { "" } else { " (NOT converged)" }
            ),
            format!(
                "{:.2} s / {:.2} s ({:.2} s)",
                r.seconds_single, r.seconds_two, r.macro_seconds
            ),
        ]);
        rows.push(r);
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&rows)?);
    } else {
        println!("{}", table.trim_fmt());
    }
    Ok(ExitCode::SUCCESS)
}
