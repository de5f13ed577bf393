//! Runs a study: its chains at once on threads, each with its own solver (one factorization per
//! chain, METHOD §4), each configuration warm-started as its [`Predictor`] says from what its
//! chain has solved (METHOD §8), or cold at a chain's start; every finished
//! configuration handed to the caller at once (files are the caller's, so a stopped study keeps
//! every finished configuration). A failure stops the other chains after their current
//! configuration.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;

use crate::counters::Instant;
use crate::error::Result;
use crate::solver::Solver;
use crate::study::{path::scaled, Chain, Chains, Design, Predictor, Quantities, Start};

/// One solved configuration.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Outcome {
    /// Index of the configuration in the design.
    pub index: usize,
    /// The chain that solved it.
    pub chain: usize,
    /// Its position along its chain.
    pub position: usize,
    /// The configuration it started from (None: cold).
    pub start: Option<usize>,
    /// The other two configurations of a parallelogram start (start + first − second).
    #[serde(default)]
    pub start_change: Option<(usize, usize)>,
    /// Scaled distance to that start.
    pub start_distance: Option<f64>,
    /// A projected start's ρ_Γ: of the nearest state alone, and of the start
    /// ([`super::projection`]).
    #[serde(default)]
    pub start_residual: Option<(f64, f64)>,
    pub iterations: usize,
    pub eta: f64,
    pub converged: bool,
    pub wall_s: f64,
    pub quantities: Quantities,
    /// Iterations of a cold solve of the same configuration (when asked).
    pub cold_iterations: Option<usize>,
}

/// How a study runs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct RunOptions {
    /// Every configuration cold (the baseline).
    pub cold: bool,
    /// Also solve every configuration cold and report its iterations.
    pub compare_cold: bool,
    /// What a warm configuration starts from.
    pub predictor: Predictor,
}

/// Runs `chains` of `design`: `make_solver` builds one solver per chain; `done(i)` says that
/// configuration i is finished already (a resumed study); `finished` receives every outcome as it
/// is solved. Returns the store's bytes per chain (the memory of the kept states).
pub fn run(
    make_solver: &(dyn Fn() -> Result<Solver> + Sync),
    design: &Design,
    chains: &Chains,
    options: RunOptions,
    done: &(dyn Fn(usize) -> bool + Sync),
    finished: &(dyn Fn(Outcome) -> Result<()> + Sync),
) -> Result<Vec<usize>> {
    let points = scaled(&design.points);
    let stop = AtomicBool::new(false);
    let first_error: Mutex<Option<crate::LopinError>> = Mutex::new(None);
    let bytes: Vec<usize> = std::thread::scope(|scope| {
        let handles: Vec<_> = chains
            .0
            .iter()
            .enumerate()
            .map(|(c, chain)| {
                let (points, stop, first_error) = (&points, &stop, &first_error);
                scope.spawn(move || {
                    let result = run_chain(
                        make_solver,
                        design,
                        points,
                        c,
                        chain,
                        options,
                        done,
                        finished,
                        stop,
                    );
                    match result {
                        Ok(b) => b,
                        Err(e) => {
                            stop.store(true, Ordering::Relaxed);
                            let mut slot = first_error.lock().unwrap_or_else(|p| p.into_inner());
                            slot.get_or_insert(e);
                            0
                        }
                    }
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap_or(0)).collect()
    });
    match first_error.into_inner().unwrap_or_else(|p| p.into_inner()) {
        Some(e) => Err(e),
        None => Ok(bytes),
    }
}

#[allow(clippy::too_many_arguments)]
fn run_chain(
    make_solver: &(dyn Fn() -> Result<Solver> + Sync),
    design: &Design,
    points: &[Vec<f64>],
    c: usize,
    chain: &[usize],
    options: RunOptions,
    done: &(dyn Fn(usize) -> bool + Sync),
    finished: &(dyn Fn(Outcome) -> Result<()> + Sync),
    stop: &AtomicBool,
) -> Result<usize> {
    if chain.iter().all(|&i| done(i)) {
        return Ok(0);
    }
    let mut solver = make_solver()?;
    let mut kept = Chain::new(options.predictor);
    for (position, &i) in chain.iter().enumerate() {
        if stop.load(Ordering::Relaxed) {
            break;
        }
        if done(i) {
            continue;
        }
        for (t, &x) in design.targets.iter().zip(&design.points[i]) {
            solver.set_parameter_in(t.parameter, t.zone, x)?;
        }
        // the wall time includes the start's making (a projection's local stages)
        let t = Instant::now();
        let start = if options.cold {
            Start::default()
        } else {
            kept.start(&points[i], &solver)
        };
        let sol = solver.solve(start.state.as_ref())?;
        let wall_s = t.elapsed().as_secs_f64();
        let quantities = Quantities::of(&solver, &sol);
        let cold_iterations = if options.compare_cold {
            Some(solver.solve(None)?.iterations)
        } else {
            None
        };
        if !options.cold {
            kept.converged(i, &points[i], &sol.state);
        }
        finished(Outcome {
            index: i,
            chain: c,
            position,
            start: start.from,
            start_change: start.change,
            start_residual: start.residual,
            start_distance: start.distance,
            iterations: sol.iterations,
            eta: sol.eta,
            converged: sol.converged,
            wall_s,
            quantities,
            cold_iterations,
        })?;
    }
    Ok(kept.bytes())
}
