//! `lopin bench --accuracy`: time to accuracy, the figure every speed change is judged by. For
//! each case (a scene at a refinement) and each setting (the defaults of one cold solve; the
//! same on windows of two steps, where a factor read for a step's solve is still in cache for
//! the next; the same with every factor in double precision; the whole interval; the whole
//! interval with the dissipative scheme ρ∞ = 0.5, the setting the guide documents as the fewest
//! iterations), LATIN is solved at tolerances 1e-1 … 1e-8 and its nodal velocities over
//! space–time compared with the converged solution of the same discrete problem (the same
//! scheme on one-step windows at η < 1e-9, or 1e-8 or 1e-7 where a slow window stops it, with
//! [`REFERENCE_MAX_ITER`] iterations a window where the scene's own limit does not reach 1e-8
//! or 1e-7; the table says which; solved once per case and scheme and shared by the settings
//! of that scheme): the wall time and the CPU time (all threads) to reach a velocity error of
//! 1e-3 and of 1e-6, setup included, are the first tolerance's that reaches it, among those
//! looser than the converged solution's own (a solve at that tolerance is that solution, not a
//! measurement against it). Rows on windows
//! of one or two steps are cold solves, one per tolerance; whole-interval rows form one chain,
//! each tolerance continuing from the previous one's state, so a row's time is that of one
//! solve stopped there. Each case ends with the rows of its friction sweep
//! ([`super::bench_accuracy_study`]). Printed as one table, written as JSON with `--json`.

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
pub(super) const TOLS: [f64; 8] = [1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8];

/// The tolerances tried for the converged solution the errors are measured against, tightest
/// first: the granular scenes' slowest windows do not reach 1e-9 within their iteration limit,
/// and a window that does not converge ends its solve.
const CONVERGED: [f64; 3] = [1e-9, 1e-8, 1e-7];

/// The iteration limit a window of the converged solution gets where the scene's own limit does
/// not reach a tolerance of [`CONVERGED`] but the tightest (`granular-poly`'s slow windows).
const REFERENCE_MAX_ITER: usize = 25_000;

/// The accuracies the table reports the time to.
pub(super) const TARGETS: [f64; 2] = [1e-3, 1e-6];

/// A setting of the table.
#[derive(Debug, Clone, Copy)]
struct Setting {
    name: &'static str,
    window: Option<WindowRequest>,
    rho_inf: Option<f64>,
    factors: Option<FactorPrecision>,
}

const SETTINGS: [Setting; 5] = [
    Setting {
        name: "default",
        window: None,
        rho_inf: None,
        factors: None,
    },
    Setting {
        name: "two-step windows",
        window: Some(WindowRequest::Steps(2)),
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
    /// The iteration limit a window of the converged solution had.
    pub converged_max_iter: usize,
    /// Each target's time, None where 1e-8 does not reach it.
    pub reached: Vec<Option<Reached>>,
    /// Every tolerance: (tol, velocity error, wall s, CPU s, iterations).
    pub points: Vec<Point>,
}

/// CPU seconds this process has used, all threads (Linux: `/proc/self/stat`).
pub(super) fn cpu_seconds() -> Option<f64> {
    let stat = std::fs::read_to_string("/proc/self/stat").ok()?;
    let rest = &stat[stat.rfind(')')? + 1..];
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let ticks = |i: usize| fields.get(i)?.parse::<f64>().ok();
    // utime and stime, fields 14 and 15 of the line (the rest starts at field 3), in
    // clock ticks of 1/100 s
    Some((ticks(11)? + ticks(12)?) / 100.0)
}

/// Largest nodal velocity difference over space–time relative to the largest velocity.
pub(super) fn velocity_error(v: &[Vec<Vec<f64>>], reference: &[Vec<Vec<f64>>]) -> f64 {
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

/// The converged solution a case's rows are measured against.
pub(super) struct Reference {
    pub(super) tol: f64,
    pub(super) max_iter: usize,
    pub(super) velocities: Vec<Vec<Vec<f64>>>,
}

/// The converged solution of `scene` at `refine` with the scheme of ρ∞ `rho_inf`, its
/// parameters set by `configure`: the first of [`reference_tries`] that converges.
pub(super) fn converged_solution(
    scene: &str,
    refine: usize,
    rho_inf: Option<f64>,
    configure: &dyn Fn(&mut Solver) -> anyhow::Result<()>,
) -> anyhow::Result<Reference> {
    let spec = SolverSpec {
        window: Some(WindowRequest::Steps(1)),
        rho_inf,
        ..SolverSpec::default()
    };
    let mut solver = solver_of(scene, refine, spec)?;
    configure(&mut solver)?;
    let own = solver.settings().max_iter;
    let loosest = CONVERGED[CONVERGED.len() - 1];
    for (tol, max_iter) in reference_tries(own) {
        solver.set_settings(Settings {
            tol,
            max_iter,
            ..*solver.settings()
        })?;
        let t = Instant::now();
        let sol = solver.solve(None)?;
        eprintln!(
            "{scene} refine {refine}, converged solution at η < {tol:e} ({max_iter} iterations a \
             window): {}, {} iterations, {:.1} s",
            if sol.converged {
                "converged"
            } else {
                "not converged"
            },
            sol.iterations,
            t.elapsed().as_secs_f64()
        );
        if sol.converged {
            return Ok(Reference {
                tol,
                max_iter,
                velocities: post::velocity_history(&solver, &sol),
            });
        }
    }
    anyhow::bail!(
        "no converged solution at η < {loosest:e} within {} iterations a window",
        own.max(REFERENCE_MAX_ITER)
    )
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
        // one converged solution per scheme, shared by the settings of that scheme; a failure
        // is kept too, so a case whose reference cannot be had is not solved again
        let mut references: Vec<(Option<f64>, Result<Reference, String>)> = Vec::new();
        for setting in SETTINGS {
            let at = match references.iter().position(|(r, _)| *r == setting.rho_inf) {
                Some(at) => at,
                None => {
                    let found = converged_solution(scene, *refine, setting.rho_inf, &|_| Ok(()))
                        .map_err(|e| format!("{e:#}"));
                    references.push((setting.rho_inf, found));
                    references.len() - 1
                }
            };
            let reference = match &references[at].1 {
                Ok(reference) => reference,
                Err(e) => {
                    eprintln!("{scene} refine {refine}, {}: {e}", setting.name);
                    continue;
                }
            };
            let row = match measure(scene, *refine, setting, reference) {
                Ok(row) => row,
                Err(e) => {
                    // one case that cannot be measured leaves the others in the table
                    eprintln!("{scene} refine {refine}, {}: {e:#}", setting.name);
                    continue;
                }
            };
            let cells = row_cells(&row);
            eprintln!("{}", cells.join(" | "));
            table.add_row(cells);
            rows.push(row);
        }
        for row in super::bench_accuracy_study::study_rows(scene, *refine) {
            let cells = row_cells(&row);
            eprintln!("{}", cells.join(" | "));
            table.add_row(cells);
            rows.push(row);
        }
    }
    super::bench::print_table(&table, &rows, json)
}

/// A row's cells in the table's columns.
fn row_cells(row: &AccuracyRow) -> Vec<String> {
    let cell = |r: &Option<Reached>, pick: &dyn Fn(&Reached) -> String| {
        r.as_ref().map_or("-".to_string(), pick)
    };
    let mut cells = vec![
        row.scene.clone(),
        row.refine.to_string(),
        row.dofs.to_string(),
        row.setting.clone(),
        converged_cell(row.converged_tol, row.converged_max_iter),
    ];
    for r in &row.reached {
        cells.push(cell(r, &|r| format!("{:.2}", r.wall_s)));
        cells.push(cell(r, &|r| {
            r.cpu_s.map_or("-".to_string(), |c| format!("{c:.2}"))
        }));
        cells.push(cell(r, &|r| r.iterations.to_string()));
    }
    cells
}

/// The (tolerance, iteration limit a window) tries of a converged solution, in order, for a
/// scene whose own limit is `own`: each tolerance of [`CONVERGED`] at the scene's limit, then,
/// but for the tightest, at [`REFERENCE_MAX_ITER`], so a scene whose windows converge slowly
/// still gets a converged solution two orders below the table's tightest accuracy (the slow
/// windows of the granular scenes are slowest at the tightest tolerance, which the table does
/// not need).
fn reference_tries(own: usize) -> Vec<(f64, usize)> {
    let mut tries = Vec::new();
    for (i, &tol) in CONVERGED.iter().enumerate() {
        tries.push((tol, own));
        if i > 0 && own < REFERENCE_MAX_ITER {
            tries.push((tol, REFERENCE_MAX_ITER));
        }
    }
    tries
}

/// The converged column: the tolerance, and the iteration limit where it is not the scene's own.
fn converged_cell(tol: f64, max_iter: usize) -> String {
    if max_iter == REFERENCE_MAX_ITER {
        format!("{tol:.0e} ({max_iter} it/window)")
    } else {
        format!("{tol:.0e}")
    }
}

/// One row: the tolerances in turn, each solution against the case's converged one.
fn measure(
    scene: &str,
    refine: usize,
    setting: Setting,
    reference: &Reference,
) -> anyhow::Result<AccuracyRow> {
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
    // the whole interval: one chain; windows of a few steps: cold solves
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
        let error = velocity_error(
            &post::velocity_history(&solver, &sol),
            &reference.velocities,
        );
        if whole {
            wall += dt;
            cpu = cpu.zip(dc).map(|(a, b)| a + b);
            iterations += sol.iterations;
        } else {
            wall = setup.0 + dt;
            cpu = setup.1.zip(dc).map(|(a, b)| a + b);
            iterations = sol.iterations;
        }
        eprintln!(
            "  {scene} refine {refine}, {}: η < {tol:e}: velocity error {error:.3e}, {} \
             iterations, {wall:.2} s{}",
            setting.name,
            iterations,
            if sol.converged {
                ""
            } else {
                " (not converged)"
            }
        );
        points.push((tol, error, wall, cpu, iterations));
        previous = Some(sol);
    }
    let reached = TARGETS
        .iter()
        .map(|&target| first_reaching(&points, target, reference.tol))
        .collect();
    let p = solver.problem();
    Ok(AccuracyRow {
        scene: p.name.clone(),
        refine,
        dofs: p.dof_count(),
        setting: setting.name.to_string(),
        converged_tol: reference.tol,
        converged_max_iter: reference.max_iter,
        reached,
        points,
    })
}

/// A setting's solves, loosest tolerance first: (tolerance, velocity error, wall, CPU,
/// iterations).
pub(super) type Point = (f64, f64, f64, Option<f64>, usize);

/// The first of `points` whose velocity error is within `target`, among the tolerances looser
/// than `converged_tol`, the converged solution's own.
pub(super) fn first_reaching(points: &[Point], target: f64, converged_tol: f64) -> Option<Reached> {
    points
        .iter()
        .find(|p| p.0 > converged_tol && p.1 <= target)
        .map(|&(tol, error, wall_s, cpu_s, iterations)| Reached {
            target,
            tol,
            error,
            wall_s,
            cpu_s,
            iterations,
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_velocity_error_is_the_largest_difference_over_the_largest_reference_velocity() {
        let reference = vec![vec![vec![1.0, -4.0], vec![2.0, 0.5]]];
        let v = vec![vec![vec![1.5, -4.0], vec![1.0, 0.5]]];
        assert!((velocity_error(&v, &reference) - 0.25).abs() < 1e-15);
        assert_eq!(velocity_error(&reference, &reference), 0.0);
    }

    #[test]
    fn a_solve_at_the_converged_tolerance_does_not_count() {
        let points = [
            (1e-5, 7e-4, 1.3, Some(2.0), 627),
            (1e-6, 1e-4, 4.4, Some(7.0), 1951),
            (1e-7, 0.0, 11.7, Some(21.0), 5437),
        ];
        let at = |target, converged| first_reaching(&points, target, converged).map(|r| r.tol);
        assert_eq!(at(1e-3, 1e-7), Some(1e-5));
        // η < 1e-7 is the converged solution itself: no tolerance reaches 1e-6 against it
        assert_eq!(at(1e-6, 1e-7), None);
        assert_eq!(at(1e-6, 1e-9), Some(1e-7));
    }

    #[test]
    fn a_slow_window_gets_the_raised_limit_before_a_looser_tolerance() {
        assert_eq!(
            reference_tries(2000),
            vec![
                (1e-9, 2000),
                (1e-8, 2000),
                (1e-8, REFERENCE_MAX_ITER),
                (1e-7, 2000),
                (1e-7, REFERENCE_MAX_ITER),
            ]
        );
        // a scene whose own limit is already that high tries each tolerance once
        assert_eq!(
            reference_tries(REFERENCE_MAX_ITER),
            vec![
                (1e-9, REFERENCE_MAX_ITER),
                (1e-8, REFERENCE_MAX_ITER),
                (1e-7, REFERENCE_MAX_ITER),
            ]
        );
    }

    #[test]
    fn the_converged_column_names_the_raised_iteration_limit_only() {
        assert_eq!(converged_cell(1e-9, 2000), "1e-9");
        assert_eq!(
            converged_cell(1e-7, REFERENCE_MAX_ITER),
            "1e-7 (25000 it/window)"
        );
    }
}
