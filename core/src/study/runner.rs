//! Runs a study: its chains at once on threads, each with its own solver (one factorization per
//! chain, METHOD §4), each configuration warm-started as its [`Predictor`] says from what its
//! chain has solved (METHOD §8), or cold at a chain's start; every finished
//! configuration handed to the caller at once with its converged state (files are the
//! caller's, so a stopped study keeps every finished configuration); a resumed study's chains
//! seeded with the states the caller kept of their finished configurations ([`Resumed`]), so
//! the rest start where they would have without the stop. A failure stops the other chains
//! after their current configuration.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;

use crate::counters::{Instant, IterationRecord};
use crate::error::Result;
use crate::solver::{Control, Solution, Solver};
use crate::state::InterfaceState;
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

impl Outcome {
    /// The outcome of configuration `solved` of chain `chain`, solved by `solver` (and solved
    /// again cold when `compare_cold`).
    pub(super) fn of(
        solver: &mut Solver,
        solved: &Solved,
        chain: usize,
        compare_cold: bool,
    ) -> Result<Self> {
        let quantities = Quantities::of(solver, &solved.solution);
        let cold_iterations = if compare_cold {
            Some(solver.solve(None)?.iterations)
        } else {
            None
        };
        let sol = &solved.solution;
        Ok(Outcome {
            index: solved.index,
            chain,
            position: solved.position,
            start: solved.start.from,
            start_change: solved.start.change,
            start_residual: solved.start.residual,
            start_distance: solved.start.distance,
            iterations: sol.iterations,
            eta: sol.eta,
            converged: sol.converged,
            wall_s: solved.wall_s,
            quantities,
            cold_iterations,
        })
    }
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
    /// Configurations solved together on one factorization ([`super::batched`]; 1: each chain
    /// on a thread with a solver of its own).
    pub batch: usize,
}

impl RunOptions {
    /// Warm from the nearest solved configuration, `batch` at a time.
    pub fn warm(batch: usize) -> Self {
        Self {
            cold: false,
            compare_cold: false,
            predictor: Predictor::Nearest,
            batch,
        }
    }
}

/// What a resumed study holds already.
#[derive(Clone, Copy)]
pub struct Resumed<'a> {
    /// Whether configuration i is finished.
    pub done: &'a (dyn Fn(usize) -> bool + Sync),
    /// The converged state of finished configuration i, where the caller kept it (None: its
    /// chain goes on without it).
    pub state: &'a (dyn Fn(usize) -> Option<InterfaceState> + Sync),
}

impl Resumed<'static> {
    /// A study started afresh.
    pub fn nothing() -> Self {
        Resumed {
            done: &|_| false,
            state: &|_| None,
        }
    }
}

/// Runs `chains` of `design`: `make_solver` builds one solver per chain; `resumed` says which
/// configurations are finished already and gives their states; `finished` receives every
/// outcome as it is solved, with its solution (the converged state a warm start
/// restarts from, and ŝ, which post-processing replays). Returns the store's bytes per chain (the
/// memory of the kept states).
pub fn run(
    make_solver: &(dyn Fn() -> Result<Solver> + Sync),
    design: &Design,
    chains: &Chains,
    options: RunOptions,
    resumed: Resumed<'_>,
    finished: &(dyn Fn(Outcome, &Solution) -> Result<()> + Sync),
) -> Result<Vec<usize>> {
    if options.batch > 1 {
        return super::batched::run(make_solver, design, chains, options, resumed, finished);
    }
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
                        resumed,
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

/// [`run`] of a study started afresh along the greedy path through `design` cut into `chains`
/// chains ([`super::path`]), every outcome gathered and returned in configuration order (for
/// callers that read them all at the end: benchmarks, tests).
pub fn run_gathered(
    make_solver: &(dyn Fn() -> Result<Solver> + Sync),
    design: &Design,
    chains: usize,
    options: RunOptions,
) -> Result<Vec<Outcome>> {
    let path = super::path::Path::greedy(&design.points);
    let out = Mutex::new(Vec::new());
    run(
        make_solver,
        design,
        &Chains::split(&path, chains),
        options,
        Resumed::nothing(),
        &|o, _| {
            out.lock().unwrap_or_else(|p| p.into_inner()).push(o);
            Ok(())
        },
    )?;
    let mut out = out.into_inner().unwrap_or_else(|p| p.into_inner());
    out.sort_by_key(|o| o.index);
    Ok(out)
}

/// The store of a chain about to be solved: empty, or (warm) seeded with the converged states
/// the caller kept of the chain's finished configurations.
pub(super) fn seeded_chain(
    chain: &[usize],
    points: &[Vec<f64>],
    options: RunOptions,
    resumed: Resumed<'_>,
) -> Chain {
    let mut kept = Chain::new(options.predictor);
    if !options.cold {
        for &i in chain.iter().filter(|&&i| (resumed.done)(i)) {
            if let Some(state) = (resumed.state)(i) {
                kept.converged(i, &points[i], &state);
            }
        }
    }
    kept
}

/// Sets configuration `i`'s parameters on `solver` through [`crate::Parameter`].
pub(super) fn set_configuration(solver: &mut Solver, design: &Design, i: usize) -> Result<()> {
    for (t, &x) in design.targets.iter().zip(&design.points[i]) {
        solver.set_parameter_in(t.parameter, t.zone, x)?;
    }
    Ok(())
}

/// The start of the configuration at scaled point `point` from what `kept` converged to, or
/// cold.
pub(super) fn start_of(kept: &Chain, point: &[f64], solver: &Solver, cold: bool) -> Start {
    if cold {
        Start::default()
    } else {
        kept.start(point, solver)
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
    resumed: Resumed<'_>,
    finished: &(dyn Fn(Outcome, &Solution) -> Result<()> + Sync),
    stop: &AtomicBool,
) -> Result<usize> {
    let done = resumed.done;
    if chain.iter().all(|&i| done(i)) {
        return Ok(0);
    }
    let mut solver = make_solver()?;
    let mut kept = seeded_chain(chain, points, options, resumed);
    let visit = Visit {
        design,
        points,
        chain,
        cold: options.cold,
        done,
        go_on: &|| !stop.load(Ordering::Relaxed),
    };
    visit.solve(
        &mut solver,
        &mut kept,
        &mut |_, _| Control::Continue,
        &mut |solver, solved| {
            let outcome = Outcome::of(solver, solved, c, options.compare_cold)?;
            finished(outcome, &solved.solution)
        },
        &|failure| failure.error,
    )?;
    Ok(kept.bytes())
}

/// One configuration of a chain, solved: what the caller records before the chain keeps its
/// state.
#[derive(Debug)]
pub struct Solved {
    /// Index of the configuration in the design.
    pub index: usize,
    /// Its position along its chain.
    pub position: usize,
    /// Where it started (its state dropped once solved).
    pub start: Start,
    /// The solution (the caller may gather it onto one rank; the chain keeps its state as the
    /// caller leaves it).
    pub solution: Solution,
    /// Seconds of its start's making and its solve.
    pub wall_s: f64,
    /// The substructure solves the skip cache saved in this solve (cumulative over the
    /// solver's life, read right after it).
    pub skipped_solves: usize,
}

/// A configuration of a chain that could not be set or solved.
#[derive(Debug)]
pub struct Failure {
    /// Index of the configuration in the design.
    pub index: usize,
    /// Whether it failed while its parameters were set (else while it was solved).
    pub setting: bool,
    /// Why.
    pub error: crate::LopinError,
}

/// The visit of one chain of a study: which configurations, in which order, which are done
/// already (a resumed study or sweep) and whether to go on.
pub struct Visit<'a> {
    /// The configurations.
    pub design: &'a Design,
    /// Their scaled points ([`scaled`]).
    pub points: &'a [Vec<f64>],
    /// The indices of the chain's configurations, in visiting order.
    pub chain: &'a [usize],
    /// Every configuration cold.
    pub cold: bool,
    /// Whether a configuration is finished already.
    pub done: &'a dyn Fn(usize) -> bool,
    /// Asked before each configuration: false stops the visit.
    pub go_on: &'a dyn Fn() -> bool,
}

impl Visit<'_> {
    /// Solves the chain's configurations in order on `solver`: each one's parameters set
    /// through [`crate::Parameter`], its start from `kept` (cold when the visit is, or nothing
    /// converged yet), its iterations shown to `observer` (with its index), the result handed
    /// to `finished`
    /// (which may solve again, gather or write), then its state kept in `kept`. A configuration
    /// that cannot be set or solved ends the visit with `on_failure`'s error.
    pub fn solve<E>(
        &self,
        solver: &mut Solver,
        kept: &mut Chain,
        observer: &mut dyn FnMut(usize, &IterationRecord) -> Control,
        finished: &mut dyn FnMut(&mut Solver, &mut Solved) -> std::result::Result<(), E>,
        on_failure: &dyn Fn(Failure) -> E,
    ) -> std::result::Result<(), E> {
        for (position, &i) in self.chain.iter().enumerate() {
            if !(self.go_on)() {
                break;
            }
            if (self.done)(i) {
                continue;
            }
            let fail = |setting: bool| {
                move |error| {
                    on_failure(Failure {
                        index: i,
                        setting,
                        error,
                    })
                }
            };
            set_configuration(solver, self.design, i).map_err(fail(true))?;
            // the wall time includes the start's making (a projection's local stages)
            let t = Instant::now();
            let mut start = start_of(kept, &self.points[i], solver, self.cold);
            let solution = solver
                .solve_with(start.state.as_ref(), &mut |r| observer(i, r))
                .map_err(fail(false))?;
            start.state = None;
            let mut solved = Solved {
                index: i,
                position,
                start,
                solution,
                wall_s: t.elapsed().as_secs_f64(),
                skipped_solves: solver.counters().skipped_solves(),
            };
            finished(solver, &mut solved)?;
            if !self.cold {
                kept.converged(i, &self.points[i], &solved.solution.state);
            }
        }
        Ok(())
    }
}
