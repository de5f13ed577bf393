//! A study's chains solved in lanes that share one factorization (METHOD §8 with §4, §11):
//! [`RunOptions::batch`] lanes ([`crate::solver::batch`]), each walking a chain as
//! [`super::runner`] does (its configurations in order, each warm-started from what the chain
//! has converged to), all advanced one iteration at a time together, so that every linear stage
//! solves the right-hand sides of all lanes in one pass through each substructure's factor. A
//! lane that finishes a configuration hands it to the caller at once and starts its chain's
//! next one; a lane whose chain is done takes the next chain nobody has started. One thread
//! drives the batch; the substructures and interfaces run in parallel inside each stage. A
//! failure stops the study after the configurations in progress.

use crate::counters::Instant;
use crate::error::Result;
use crate::solver::batch::{step_together, Lane};
use crate::solver::{Control, Solution, SolveRun, Solver};
use crate::state::InterfaceState;
use crate::study::runner::{
    seeded_chain, set_configuration, start_of, Outcome, Resumed, RunOptions, Solved,
};
use crate::study::{path::scaled, Chain, Chains, Design, Start};

/// A configuration in progress on a lane.
struct Current {
    index: usize,
    position: usize,
    start: Start,
    run: SolveRun,
    began: Instant,
}

/// What one lane is doing: which chain, how far along it, what that chain has converged to.
struct LaneWork {
    chain: usize,
    next: usize,
    kept: Chain,
    current: Option<Current>,
}

/// Runs `chains` of `design` in `options.batch` lanes (see the module doc); the arguments and
/// the result are [`super::runner::run`]'s.
pub fn run(
    make_solver: &(dyn Fn() -> Result<Solver> + Sync),
    design: &Design,
    chains: &Chains,
    options: RunOptions,
    resumed: Resumed<'_>,
    finished: &(dyn Fn(Outcome, &Solution) -> Result<()> + Sync),
) -> Result<Vec<usize>> {
    let points = scaled(&design.points);
    let done = resumed.done;
    let mut bytes = vec![0; chains.0.len()];
    let mut queue = (0..chains.0.len()).filter(|&c| !chains.0[c].iter().all(|&i| done(i)));
    let lanes = options.batch.clamp(1, chains.0.len().max(1));
    let mut solvers: Vec<Solver> = Vec::with_capacity(lanes);
    let mut work: Vec<Option<LaneWork>> = (0..lanes).map(|_| None).collect();
    let mut first_error = None;
    loop {
        // every idle lane takes its chain's next configuration, or the next chain
        for l in 0..lanes {
            while first_error.is_none() && work[l].as_ref().is_none_or(|w| w.current.is_none()) {
                let w = match &mut work[l] {
                    Some(w) if w.next < chains.0[w.chain].len() => w,
                    slot => {
                        if let Some(w) = slot.take() {
                            bytes[w.chain] = w.kept.bytes();
                        }
                        let Some(c) = queue.next() else {
                            break;
                        };
                        slot.insert(LaneWork {
                            chain: c,
                            next: 0,
                            kept: seeded_chain(&chains.0[c], &points, options, resumed),
                            current: None,
                        })
                    }
                };
                let position = w.next;
                w.next += 1;
                let i = chains.0[w.chain][position];
                if done(i) {
                    continue;
                }
                if solvers.len() <= l {
                    let solver = match solvers.first() {
                        None => make_solver(),
                        Some(s) => s.lane(),
                    };
                    match solver {
                        Ok(s) => solvers.push(s),
                        Err(e) => {
                            first_error = Some(e);
                            break;
                        }
                    }
                }
                match begin(
                    &mut solvers[l],
                    design,
                    &points[i],
                    i,
                    &w.kept,
                    options.cold,
                ) {
                    Ok((start, run, began)) => {
                        w.current = Some(Current {
                            index: i,
                            position,
                            start,
                            run,
                            began,
                        })
                    }
                    Err(e) => first_error = Some(e),
                }
            }
        }
        let busy: Vec<usize> = (0..lanes)
            .filter(|&l| work[l].as_ref().is_some_and(|w| w.current.is_some()))
            .collect();
        if busy.is_empty() {
            break;
        }
        let ended = {
            let mut runs: Vec<Option<&mut SolveRun>> = work
                .iter_mut()
                .map(|w| {
                    w.as_mut()
                        .and_then(|w| w.current.as_mut())
                        .map(|c| &mut c.run)
                })
                .collect();
            let mut batch: Vec<Lane<'_>> = solvers
                .iter_mut()
                .zip(runs.iter_mut())
                .filter_map(|(solver, run)| {
                    Some(Lane {
                        solver,
                        run: run.take()?,
                    })
                })
                .collect();
            step_together(&mut batch, &mut |_, _| Control::Continue)
        };
        for (&l, ended) in busy.iter().zip(ended) {
            if !ended {
                continue;
            }
            let Some(w) = work[l].as_mut() else {
                continue;
            };
            let Some(current) = w.current.take() else {
                continue;
            };
            let solver = &mut solvers[l];
            let result = conclude(solver, current, w.chain, options, finished);
            match result {
                Ok((index, state)) => {
                    if !options.cold {
                        w.kept.converged(index, &points[index], &state);
                    }
                }
                Err(e) => {
                    first_error.get_or_insert(e);
                }
            }
        }
    }
    for w in work.into_iter().flatten() {
        bytes[w.chain] = w.kept.bytes();
    }
    match first_error {
        Some(e) => Err(e),
        None => Ok(bytes),
    }
}

/// Sets configuration `i`'s parameters on `solver` and begins its solve from its chain's start.
fn begin(
    solver: &mut Solver,
    design: &Design,
    point: &[f64],
    i: usize,
    kept: &Chain,
    cold: bool,
) -> Result<(Start, SolveRun, Instant)> {
    set_configuration(solver, design, i)?;
    let began = Instant::now();
    let mut start = start_of(kept, point, solver, cold);
    let run = solver.begin(start.state.as_ref())?;
    start.state = None;
    Ok((start, run, began))
}

/// Ends a configuration's solve: its outcome handed to `finished`, its state returned for the
/// chain to keep.
fn conclude(
    solver: &mut Solver,
    current: Current,
    chain: usize,
    options: RunOptions,
    finished: &(dyn Fn(Outcome, &Solution) -> Result<()> + Sync),
) -> Result<(usize, InterfaceState)> {
    let solution = solver.conclude(current.run)?;
    let solved = Solved {
        index: current.index,
        position: current.position,
        start: current.start,
        solution,
        wall_s: current.began.elapsed().as_secs_f64(),
        skipped_solves: solver.counters().skipped_solves(),
    };
    let outcome = Outcome::of(solver, &solved, chain, options.compare_cold)?;
    finished(outcome, &solved.solution)?;
    Ok((solved.index, solved.solution.state))
}
