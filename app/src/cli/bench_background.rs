//! `lopin bench --background 1,4`: the explorer's background study (its friction grid, solved
//! nearest-first around the scene's value, each value warm from the stored ones beside it) with
//! L values solved at once on lanes that share the factorizations, against one at a time. For
//! each refinement, at the explorer's settings: a headless worker solves the scene's value, then
//! the background study fills the grid; the row gives the background's iterations (all values)
//! and its wall time, from the first solve's report to the last value stored. Ratios are taken
//! within one run; the table (comfy-table) is printed at the end, and written as JSON with
//! `--json`.

use std::sync::Arc;
use std::time::Duration;

use lopin_core::counters::Instant;
use lopin_core::window_choice::Task;
use lopin_core::{Problem, Settings};
use lopin_explorer::params::Params;
use lopin_explorer::protocol::{Event, StudyControl};
use lopin_explorer::study;
use lopin_explorer::worker::Worker;

use super::report::column_table;
use super::setup::problem_for;

/// One row of the table.
#[derive(Debug, Clone, serde::Serialize)]
pub struct BackgroundRow {
    pub scene: String,
    pub refine: usize,
    pub dofs: usize,
    /// Grid values the background study solved.
    pub values: usize,
    pub lanes: usize,
    /// Iterations of all background values.
    pub iterations: usize,
    /// Wall time from the first solve's report to the last value stored.
    pub wall_s: f64,
    /// `wall_s` against one lane.
    pub ratio: f64,
}

/// Runs the table for `scene` at `refines` and the lane counts `lanes`; writes the rows as JSON
/// to `json` if given.
pub fn bench_background(
    scene: &str,
    refines: &[usize],
    lanes: &[usize],
    json: Option<&std::path::Path>,
) -> anyhow::Result<()> {
    if lanes.contains(&0) {
        anyhow::bail!("--background: lane counts must be at least 1");
    }
    let mut table = column_table([
        "scene",
        "refine",
        "dofs",
        "values",
        "lanes",
        "iterations",
        "wall_s",
        "vs_one",
    ]);
    let mut rows: Vec<BackgroundRow> = Vec::new();
    for &refine in refines {
        let (problem, settings) = problem_for(scene, refine, Task::Interactive)?;
        let mut one = None;
        for &l in lanes {
            let (values, iterations, wall_s) = timed(&problem, settings, l)?;
            let first = *one.get_or_insert(wall_s);
            eprintln!("refine {refine}, {l} lanes: {wall_s:.2} s");
            let row = BackgroundRow {
                scene: problem.name.clone(),
                refine,
                dofs: problem.dof_count(),
                values,
                lanes: l,
                iterations,
                wall_s,
                ratio: wall_s / first,
            };
            table.add_row([
                row.scene.clone(),
                refine.to_string(),
                row.dofs.to_string(),
                values.to_string(),
                l.to_string(),
                iterations.to_string(),
                format!("{wall_s:.2}"),
                format!("{:.2}", row.ratio),
            ]);
            rows.push(row);
        }
    }
    super::bench::print_table(&table, &rows, json)
}

/// The background study of `problem` in `lanes` lanes: the values it solved, their iterations
/// and its wall time.
fn timed(
    problem: &Problem,
    settings: Settings,
    lanes: usize,
) -> anyhow::Result<(usize, usize, f64)> {
    let params = Params::of(problem, &settings);
    if params.friction.is_none() {
        anyhow::bail!("--background: the scene has no contact (no friction to study)");
    }
    let mut worker = Worker::spawn(
        problem.clone(),
        settings,
        Arc::new(|| {}),
        Default::default(),
    )?;
    worker.set_display_step(problem.time.steps / 2);
    worker.set_study(StudyControl {
        paused: false,
        idle_s: 0.0,
        lanes,
        ..StudyControl::default()
    });
    let generation = worker.solve(params);
    let grid = study::grid().len();
    let (mut began, mut iterations, mut values) = (None, 0, 0);
    loop {
        let Some(event) = worker.wait(Duration::from_secs(600)) else {
            anyhow::bail!("the background study stored nothing for 600 s before the grid was full");
        };
        match event {
            Event::Error(e) => anyhow::bail!("{e}"),
            Event::Finished(r) if r.generation == generation => began = Some(Instant::now()),
            Event::Stored(c) if c.background => {
                iterations += c.iterations;
                values += 1;
                if c.stored == grid {
                    break;
                }
            }
            _ => {}
        }
    }
    let wall = began.map_or(0.0, |b| b.elapsed().as_secs_f64());
    Ok((values, iterations, wall))
}
