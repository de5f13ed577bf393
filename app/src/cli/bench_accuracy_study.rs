//! The study rows of `lopin bench --accuracy`: a friction sweep (f = 0:0.5:0.1, six values) at
//! the scene's study settings, solved every value cold (the baseline), one configuration at a
//! time along one warm chain (the sweep's way) and in four lanes ([`lopin_core::study::batched`]: four chains, each started
//! cold, solved together on one factorization). Each value has its converged solution (as the
//! table's single solves have theirs: one-step windows, the first of the references' tries that
//! converges, with the friction of that value); the study is solved at tolerances 1e-1 … 1e-8,
//! each a fresh study, and its velocity error at a tolerance is the largest over the values.
//! The wall time and CPU time to 1e-3 and 1e-6 are those of the first tolerance that reaches
//! it, the scene's build included, as the single solves count theirs.

use std::sync::Mutex;

use lopin_core::counters::Instant;
use lopin_core::study::runner::{self, Resumed, RunOptions};
use lopin_core::study::{Chains, Design, Path, Spread, Target};
use lopin_core::window_choice::Task;
use lopin_core::{post, Problem, Settings, Solution, Solver};

use super::bench_accuracy::{
    converged_solution, cpu_seconds, first_reaching, velocity_error, AccuracyRow, Point, Reference,
    TARGETS, TOLS,
};
use super::setup::problem_for;

/// The friction values of the sweep.
const SWEEP: &str = "0:0.5:0.1";

/// The ways the sweep is solved: the row's name, the chains, the lanes.
const WAYS: [Way; 3] = [
    Way {
        name: "sweep f = 0:0.5:0.1, each value cold",
        chains: 1,
        lanes: 1,
        cold: true,
    },
    Way {
        name: "sweep f = 0:0.5:0.1, one at a time",
        chains: 1,
        lanes: 1,
        cold: false,
    },
    Way {
        name: "sweep f = 0:0.5:0.1, 4 lanes",
        chains: 4,
        lanes: 4,
        cold: false,
    },
];

/// A way of solving the sweep.
#[derive(Debug, Clone, Copy)]
struct Way {
    name: &'static str,
    /// The chains the greedy path is cut into.
    chains: usize,
    /// The configurations solved together on one factorization.
    lanes: usize,
    /// Every value cold (the baseline the warm chains gain against).
    cold: bool,
}

/// The study rows of `scene` at `refine`; a way that cannot be measured is reported on stderr
/// and left out, the others kept.
pub fn study_rows(scene: &str, refine: usize) -> Vec<AccuracyRow> {
    let case = match StudyCase::new(scene, refine) {
        Ok(case) => case,
        Err(e) => {
            eprintln!("{scene} refine {refine}, sweep: {e:#}");
            return Vec::new();
        }
    };
    WAYS.iter()
        .filter_map(|&way| match case.measure(way) {
            Ok(row) => Some(row),
            Err(e) => {
                eprintln!("{scene} refine {refine}, {}: {e:#}", way.name);
                None
            }
        })
        .collect()
}

/// A scene's sweep: its problem at the study settings, and each value's converged solution.
struct StudyCase {
    scene: String,
    refine: usize,
    problem: Problem,
    settings: Settings,
    design: Design,
    /// Wall and CPU seconds of building the scene.
    build: (f64, Option<f64>),
    references: Vec<Reference>,
    /// A solver of the problem, to replay each solution's fields (the friction is not read).
    replay: Solver,
}

impl StudyCase {
    fn new(scene: &str, refine: usize) -> anyhow::Result<Self> {
        let (wall0, cpu0) = (Instant::now(), cpu_seconds());
        let (problem, settings) = problem_for(scene, refine, Task::Study)?;
        let build = (
            wall0.elapsed().as_secs_f64(),
            cpu_seconds().zip(cpu0).map(|(a, b)| a - b),
        );
        let target = Target::parse("f", &problem)?;
        let design = Design::grid(vec![(target.clone(), Spread::parse(SWEEP)?)])?;
        let mut references = Vec::with_capacity(design.points.len());
        for point in &design.points {
            eprintln!("{scene} refine {refine}, sweep: f = {}", point[0]);
            let x = point[0];
            let target = &target;
            references.push(converged_solution(scene, refine, None, &|solver| {
                Ok(solver.set_parameter_in(target.parameter, target.zone, x)?)
            })?);
        }
        let replay = Solver::new(problem.clone(), settings)?;
        Ok(Self {
            scene: scene.to_string(),
            refine,
            problem,
            settings,
            design,
            build,
            references,
            replay,
        })
    }

    /// The row of the sweep solved `way`.
    fn measure(&self, way: Way) -> anyhow::Result<AccuracyRow> {
        let name = way.name;
        let split = Chains::split(&Path::greedy(&self.design.points), way.chains);
        let options = RunOptions {
            cold: way.cold,
            ..RunOptions::warm(way.lanes)
        };
        let mut points: Vec<Point> = Vec::new();
        for tol in TOLS {
            let settings = Settings {
                tol,
                ..self.settings
            };
            let solved: Mutex<Vec<(usize, Solution)>> = Mutex::new(Vec::new());
            let (t, c) = (Instant::now(), cpu_seconds());
            runner::run(
                &|| Solver::new(self.problem.clone(), settings),
                &self.design,
                &split,
                options,
                Resumed::nothing(),
                &|o, solution| {
                    let mut s = solved.lock().unwrap_or_else(|p| p.into_inner());
                    s.push((o.index, solution.clone()));
                    Ok(())
                },
            )?;
            let wall = self.build.0 + t.elapsed().as_secs_f64();
            let cpu = cpu_seconds()
                .zip(c)
                .zip(self.build.1)
                .map(|((a, b), s)| a - b + s);
            let solved = solved.into_inner().unwrap_or_else(|p| p.into_inner());
            let (errors, iterations, converged) = self.errors(&solved);
            let (worst, error) = errors
                .iter()
                .copied()
                .enumerate()
                .fold((0, 0.0f64), |a, b| if b.1 > a.1 { b } else { a });
            eprintln!(
                "  {} refine {}, {name}: η < {tol:e}: velocity error {error:.3e} (the largest, \
                 at f = {}; every value: {}), {iterations} iterations, {wall:.2} s{}",
                self.scene,
                self.refine,
                self.design.points[worst][0],
                errors
                    .iter()
                    .map(|e| format!("{e:.1e}"))
                    .collect::<Vec<_>>()
                    .join(" "),
                if converged { "" } else { " (not converged)" }
            );
            points.push((tol, error, wall, cpu, iterations));
        }
        // the loosest of the values' converged solutions bounds the tolerances that count
        let converged_tol = self.references.iter().map(|r| r.tol).fold(0.0, f64::max);
        let converged_max_iter = self.references.iter().map(|r| r.max_iter).max();
        Ok(AccuracyRow {
            scene: self.problem.name.clone(),
            refine: self.refine,
            dofs: self.problem.dof_count(),
            setting: name.to_string(),
            converged_tol,
            converged_max_iter: converged_max_iter.unwrap_or(0),
            reached: TARGETS
                .iter()
                .map(|&target| first_reaching(&points, target, converged_tol))
                .collect(),
            points,
        })
    }

    /// The velocity error of each value against its converged solution (in the design's
    /// order), the iterations of all, and whether every value converged.
    fn errors(&self, solved: &[(usize, Solution)]) -> (Vec<f64>, usize, bool) {
        let mut errors = vec![0.0; self.design.points.len()];
        for (i, solution) in solved {
            let v = post::velocity_history(&self.replay, solution);
            errors[*i] = velocity_error(&v, &self.references[*i].velocities);
        }
        let iterations = solved.iter().map(|(_, s)| s.iterations).sum();
        let converged = solved.iter().all(|(_, s)| s.converged);
        (errors, iterations, converged)
    }
}
