//! `lopin bench --accuracy`: time to accuracy, the figure every speed change is judged by. For
//! each case (a scene at a refinement) and each setting (the defaults of one cold solve; the
//! same with every factor in double precision; the whole interval; the whole interval with the
//! dissipative scheme ρ∞ = 0.5, the setting the guide documents as the fewest iterations), LATIN is solved at tolerances 1e-1 … 1e-8 and its
//! nodal velocities over space–time compared with the converged solution of the same discrete
//! problem (the same scheme on one-step windows at η < 1e-9, or 1e-8 or 1e-7 where rounding
//! stops it above; the table says which): the wall time and the CPU time
//! (all threads) to reach a velocity error of 1e-3 and of 1e-6, setup included, are the first
//! tolerance's that reaches it. One-step-window rows are cold solves, one per tolerance;
//! whole-interval rows form one chain, each tolerance continuing from the previous one's state,
//! so a row's time is that of one solve stopped there. Printed as one table, written as JSON
//! with `--json`.

use lopin_core::counters::Instant;
use lopin_core::scene::settings::FactorPrecision;
use lopin_core::scene::spec::SolverSpec;
use lopin_core::window_choice::{Task, WindowRequest};
use lopin_core::{post, Settings, Solution, Solver};

use super::report::column_table;
use super::setup::{build, SceneArgs};

/// The cases: a scene at a refinement.
pub const CASES: [(&str, usize); 5] = [
    ("two-blocks", 1),
    ("two-blocks-ramp", 1),
    ("two-blocks", 2),
    ("granular-small", 1),
    ("granular-poly", 1),
];

/// The tolerances each setting is solved at, loosest first.
const TOLS: [f64; 8] = [1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8];

/// The tolerances tried for the converged solution the errors are measured against, tightest
/// first: rounding stops some scenes above 1e-9 (the granular ones), and a window that does not
/// converge ends its solve.
const CONVERGED: [f64; 3] = [1e-9, 1e-8, 1e-7];

/// The accuracies the table reports the time to.
const TARGETS: [f64; 2] = [1e-3, 1e-6];

/// A setting of the table.
#[derive(Debug, Clone, Copy)]
struct Setting {
    name: &'static str,
    window: Option<WindowRequest>,
    rho_inf: Option<f64>,
    factors: Option<FactorPrecision>,
}

const SETTINGS: [Setting; 4] = [
    Setting {
        name: "default",
        window: None,
        rho_inf: None,
        factors: None,
    },
    Setting {
        name: "double-precision factors",
        window: None,
        rho_inf: None,
        factors: Some(FactorPrecision::Double),
    },
    Setting {
        name: "whole",
        window: Some(WindowRequest::Whole),
        rho_inf: None,
        factors: None,
    },
    Setting {
        name: "whole, rho-inf 0.5",
        window: Some(WindowRequest::Whole),
        rho_inf: Some(0.5),
        factors: None,
    },
];

/// The time to one accuracy.
#[derive(Debug, Clone, Copy, serde::Serialize)]
pub struct Reached {
    /// The velocity error asked for.
    pub target: f64,
    /// The loosest tolerance whose solution reaches it.
    pub tol: f64,
    /// Its velocity error.
    pub error: f64,
    /// Wall time, setup included (s).
    pub wall_s: f64,
    /// CPU time of all threads, setup included (s; None where the system does not say).
    pub cpu_s: Option<f64>,
    /// LATIN iterations.
    pub iterations: usize,
}

/// One row: a case under a setting.
#[derive(Debug, Clone, serde::Serialize)]
pub struct AccuracyRow {
    pub scene: String,
    pub refine: usize,
    pub dofs: usize,
    pub setting: String,
    /// The tolerance the converged solution reached.
    pub converged_tol: f64,
    /// Each target's time, None where 1e-8 does not reach it.
    pub reached: Vec<Option<Reached>>,
    /// Every tolerance: (tol, velocity error, wall s, CPU s, iterations).
    pub points: Vec<(f64, f64, f64, Option<f64>, usize)>,
}

/// CPU seconds this process has used, all threads (Linux: `/proc/self/stat`).
fn cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    let rest = &stat[stat.rfind(')')? + 1..];
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let ticks = |i: usize| fields.get(i)?.parse::<f64>().ok();
    // utime and stime, fields 14 and 15 of the line (the rest starts at field 3), in
    // clock ticks of 1/100 s
    Some((ticks(11)? + ticks(12)?) / 100.0)
}

/// Largest nodal velocity difference over space–time relative to the largest velocity.
fn velocity_error(v: &[Vec<Vec<f64>>], reference: &[Vec<Vec<f64>>]) -> f64 {
    let (mut diff, mut scale) = (0.0f64, 0.0f64);
    for (a, b) in v.iter().flatten().zip(reference.iter().flatten()) {
        for (x, y) in a.iter().zip(b) {
            diff = diff.max((x - y).abs());
            scale = scale.max(y.abs());
        }
    }
    diff / scale.max(f64::MIN_POSITIVE)
}

/// The solver of `scene` at `refine` under the settings layer `spec`, for one cold solve.
fn solver_of(scene: &str, refine: usize, spec: SolverSpec) -> anyhow::Result<Solver> {
    let built = build(&SceneArgs::refined(scene, refine, spec, Task::Single))?;
    Ok(Solver::new(built.problem, built.settings)?)
}

/// Runs the table for the cases whose scene names `only` lists (all when empty); writes the
/// rows as JSON to `json` if given.
pub fn bench_accuracy(only: &[String], json: Option<&std::path::Path>) -> anyhow::Result<()> {
    let mut rows = Vec::new();
    let mut table = column_table([
        "scene",
        "refine",
        "dofs",
        "setting",
        "converged",
        "wall_1e-3",
        "cpu_1e-3",
        "iter_1e-3",
        "wall_1e-6",
        "cpu_1e-6",
        "iter_1e-6",
    ]);
    for (scene, refine) in CASES
        .iter()
        .filter(|(s, _)| only.is_empty() || only.iter().any(|o| o == s))
    {
        for setting in SETTINGS {
            let row = match measure(scene, *refine, setting) {
                Ok(row) => row,
                Err(e) => {
                    // one case that cannot be measured leaves the others in the table
                    eprintln!("{scene} refine {refine}, {}: {e:#}", setting.name);
                    continue;
                }
            };
            let cell = |r: &Option<Reached>, pick: &dyn Fn(&Reached) -> String| {
                r.as_ref().map_or("-".to_string(), pick)
            };
            let mut cells = vec![
                row.scene.clone(),
                refine.to_string(),
                row.dofs.to_string(),
                row.setting.clone(),
                format!("{:.0e}", row.converged_tol),
            ];
            for r in &row.reached {
                cells.push(cell(r, &|r| format!("{:.2}", r.wall_s)));
                cells.push(cell(r, &|r| {
                    r.cpu_s.map_or("-".to_string(), |c| format!("{c:.2}"))
                }));
                cells.push(cell(r, &|r| r.iterations.to_string()));
            }
            eprintln!("{}", cells.join(" | "));
            table.add_row(cells);
            rows.push(row);
        }
    }
    super::bench::print_table(&table, &rows, json)
}

/// One row: the converged solution, then the tolerances in turn.
fn measure(scene: &str, refine: usize, setting: Setting) -> anyhow::Result<AccuracyRow> {
    let converged_spec = SolverSpec {
        window: Some(WindowRequest::Steps(1)),
        rho_inf: setting.rho_inf,
        ..SolverSpec::default()
    };
    let mut converged = solver_of(scene, refine, converged_spec)?;
    let mut found = None;
    for tol in CONVERGED {
        converged.set_settings(Settings {
            tol,
            ..*converged.settings()
        })?;
        let sol = converged.solve(None)?;
        if sol.converged {
            found = Some((tol, sol));
            break;
        }
    }
    let Some((converged_tol, reference_sol)) = found else {
        anyhow::bail!(
            "no converged solution at η < {:e}",
            CONVERGED[CONVERGED.len() - 1]
        );
    };
    let reference = post::velocity_history(&converged, &reference_sol);
    let spec = SolverSpec {
        window: setting.window,
        rho_inf: setting.rho_inf,
        factors: setting.factors,
        ..SolverSpec::default()
    };
    let (wall0, cpu0) = (Instant::now(), cpu_seconds());
    let mut solver = solver_of(scene, refine, spec.clone())?;
    let setup = (
        wall0.elapsed().as_secs_f64(),
        cpu_seconds().zip(cpu0).map(|(a, b)| a - b),
    );
    let whole = solver.settings().window.is_none();
    let mut points = Vec::new();
    // the whole interval: one chain; one-step windows: cold solves
    let (mut wall, mut cpu, mut iterations) = (setup.0, setup.1, 0usize);
    let mut previous: Option<Solution> = None;
    for tol in TOLS {
        let settings = Settings {
            tol,
            ..*solver.settings()
        };
        solver.set_settings(settings)?;
        let (t, c) = (Instant::now(), cpu_seconds());
        let start = if whole { previous.as_ref() } else { None };
        let sol = solver.solve(start.map(|s| &s.state))?;
        let (dt, dc) = (
            t.elapsed().as_secs_f64(),
            cpu_seconds().zip(c).map(|(a, b)| a - b),
        );
        let error = velocity_error(&post::velocity_history(&solver, &sol), &reference);
        if whole {
            wall += dt;
            cpu = cpu.zip(dc).map(|(a, b)| a + b);
            iterations += sol.iterations;
        } else {
            wall = setup.0 + dt;
            cpu = setup.1.zip(dc).map(|(a, b)| a + b);
            iterations = sol.iterations;
        }
        points.push((tol, error, wall, cpu, iterations));
        previous = Some(sol);
    }
    let reached = TARGETS
        .iter()
        .map(|&target| {
            points
                .iter()
                .find(|p| p.1 <= target)
                .map(|&(tol, error, wall_s, cpu_s, iterations)| Reached {
                    target,
                    tol,
                    error,
                    wall_s,
                    cpu_s,
                    iterations,
                })
        })
        .collect();
    let p = solver.problem();
    Ok(AccuracyRow {
        scene: p.name.clone(),
        refine,
        dofs: p.dof_count(),
        setting: setting.name.to_string(),
        converged_tol,
        reached,
        points,
    })
}
