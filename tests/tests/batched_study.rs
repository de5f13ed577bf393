//! Configurations solved together on one factorization (`core/src/solver/batch.rs`,
//! `core/src/study/batched.rs`): lanes of `two-blocks` at different friction coefficients and
//! gaps, advanced one iteration at a time with every linear stage solving all lanes'
//! right-hand sides in one pass through each factor, reach what each reaches alone (bit for bit
//! for a lone lane; the same iteration counts and the same interface fields to rounding for
//! several, on one-step windows and over the whole interval with its skip cache, warm and
//! cold), on the two-scale stage as on the single-scale one, both in one batch; a study in
//! batches gives each configuration the iterations (within one) and quantities (to the
//! tolerance) of the same chains solved one at a time. The end energies a single-scale solve
//! keeps (`core/src/solver/end_energy.rs`) are those of a replay, bit for bit.

use lopin_core::post;
use lopin_core::scene;
use lopin_core::solver::Solution;
use lopin_core::study::runner::{self, Outcome, RunOptions};
use lopin_core::study::{Design, Spread, Target};
use lopin_core::{Parameter, Settings, Solver};
use lopin_tests::{march_in_lanes, solve_in_lanes, state_difference};

/// `two-blocks` with its settings at tolerance `tol` on windows of `window` steps (over the
/// whole interval with the dissipative scheme ρ∞ = 0.5, which converges there in fewer
/// iterations).
fn opened(tol: f64, window: Option<usize>) -> (lopin_core::Problem, Settings) {
    let spec = scene::load("two-blocks").expect("scene");
    let problem = scene::problem_of(&spec, "two-blocks").expect("builds");
    let mut settings = Settings::for_problem(&problem, &spec.solver);
    settings.tol = tol;
    settings.window = window;
    if window.is_none() {
        settings.rho_inf = 0.5;
    }
    (problem, settings)
}

/// Each friction coefficient solved alone on a solver of its own, from `starts`.
fn alone(
    problem: &lopin_core::Problem,
    settings: Settings,
    frictions: &[f64],
    starts: &[Option<&lopin_core::state::InterfaceState>],
) -> Vec<Solution> {
    frictions
        .iter()
        .zip(starts)
        .map(|(&f, start)| {
            let mut s = Solver::new(problem.clone(), settings).expect("solver");
            s.set_parameter(Parameter::Friction, f).expect("friction");
            s.solve(*start).expect("solve")
        })
        .collect()
}

/// One lane marching alone in a batch is the solve of [`Solver::solve`] bit for bit; three
/// lanes at f = 0, 0.3 and 0.6 reach the iterates of three separate solves to rounding, with
/// the same iteration counts, cold and then warm (each from another's converged state), on
/// one-step windows and over the whole interval (where the skip cache replays unchanged
/// substructures). The end energies a solve keeps are its replay's: bit for bit alone, to
/// rounding in a lane.
#[test]
fn lanes_reach_what_each_configuration_reaches_alone() {
    for window in [Some(1), None] {
        let (problem, settings) = opened(1e-5, window);
        let base = Solver::new(problem.clone(), settings).expect("solver");
        let lone = solve_in_lanes(&base, &[0.3], &[None]);
        let single = alone(&problem, settings, &[0.3], &[None]);
        assert_eq!(lone[0].iterations, single[0].iterations);
        assert_eq!(lone[0].state, single[0].state, "window {window:?}");
        assert_eq!(lone[0].hats, single[0].hats);
        // a solve alone keeps the end energies of its replay bit for bit (trapezoidal rule)
        if window.is_some() {
            let mut s = base.lane().expect("lane");
            s.set_parameter(Parameter::Friction, 0.3).expect("friction");
            let e = post::energy(&s, &single[0]);
            let n = e.kinetic.len() - 1;
            let end = single[0].end.expect("end energies");
            assert_eq!(
                (end.kinetic, end.strain, end.input_work),
                (e.kinetic[n], e.strain[n], e.input_work[n])
            );
        }

        let frictions = [0.0, 0.3, 0.6];
        let cold = solve_in_lanes(&base, &frictions, &[None, None, None]);
        let reference = alone(&problem, settings, &frictions, &[None, None, None]);
        for (a, b) in cold.iter().zip(&reference) {
            assert!(a.converged && b.converged);
            assert_eq!(a.iterations, b.iterations, "window {window:?}");
            let d = state_difference(a, b);
            assert!(d < 1e-10, "window {window:?}: cold lanes differ by {d:e}");
        }
        // warm: each starts from the converged state of the next friction coefficient
        let starts = [
            Some(&reference[1].state),
            Some(&reference[2].state),
            Some(&reference[0].state),
        ];
        let warm = solve_in_lanes(&base, &frictions, &starts);
        let warm_reference = alone(&problem, settings, &frictions, &starts);
        for (a, b) in warm.iter().zip(&warm_reference) {
            assert!(a.converged);
            assert_eq!(a.iterations, b.iterations, "window {window:?}");
            let d = state_difference(a, b);
            assert!(d < 1e-10, "window {window:?}: warm lanes differ by {d:e}");
        }
        // the lanes' end energies are those of their own replays (trapezoidal rule; the
        // dissipative scheme's need a replay)
        for (sol, &f) in warm.iter().zip(&frictions) {
            if window.is_none() {
                assert!(sol.end.is_none(), "ρ∞ = 0.5 keeps no end energies");
                continue;
            }
            let mut s = base.lane().expect("lane");
            s.set_parameter(Parameter::Friction, f).expect("friction");
            let e = post::energy(&s, sol);
            let end = sol
                .end
                .expect("a single-scale solve keeps its end energies");
            let n = e.kinetic.len() - 1;
            let rel = |x: f64, y: f64| (x - y).abs() / y.abs().max(1e-30);
            assert!(rel(end.kinetic, e.kinetic[n]) < 1e-12);
            assert!(rel(end.strain, e.strain[n]) < 1e-12);
            assert!(rel(end.input_work, e.input_work[n]) < 1e-12);
        }
    }
}

/// Lanes on the two-scale stage (METHOD §9) march together beside the single-scale lanes of the
/// same batch: one lane alone is its own solve bit for bit; two two-scale lanes (f = 0.3 and
/// 0.6) and two single-scale ones (f = 0.1 and 0.4) in one batch each reach their own solve's
/// iterates to rounding, with the same iteration counts, cold and warm.
#[test]
fn two_scale_lanes_march_together_beside_the_single_scale_batch() {
    let (problem, settings) = opened(1e-6, Some(1));
    let two_scale = Settings {
        two_scale: true,
        ..settings
    };
    let base = Solver::new(problem.clone(), settings).expect("solver");
    let lane = |f: f64, two: bool| {
        let mut s = base.lane().expect("lane");
        if two {
            s.set_settings(two_scale).expect("two-scale");
        }
        s.set_parameter(Parameter::Friction, f).expect("friction");
        // the two-scale switch keeps the factorizations: the lane still shares them
        assert!(s.shares_factors(&base));
        s
    };
    let by_itself = |f: f64, two: bool, start: Option<&lopin_core::state::InterfaceState>| {
        let mut s =
            Solver::new(problem.clone(), if two { two_scale } else { settings }).expect("solver");
        s.set_parameter(Parameter::Friction, f).expect("friction");
        s.solve(start).expect("solve")
    };
    // one two-scale lane alone: its solve bit for bit
    let lone = march_in_lanes(&mut [lane(0.3, true)], &[None]);
    let reference = by_itself(0.3, true, None);
    assert_eq!(lone[0].iterations, reference.iterations);
    assert_eq!(lone[0].state, reference.state, "a lone two-scale lane");
    // a two-scale solve keeps no end energies (its fields carry the macro correction)
    assert!(lone[0].end.is_none());

    let cases = [(0.3, true), (0.1, false), (0.6, true), (0.4, false)];
    let cold: Vec<Solution> = cases.iter().map(|&(f, t)| by_itself(f, t, None)).collect();
    // cold, then warm from the converged state of the case after it
    let warm_starts: Vec<_> = (0..cases.len())
        .map(|c| Some(&cold[(c + 1) % cases.len()].state))
        .collect();
    for starts in [vec![None; cases.len()], warm_starts] {
        let mut solvers: Vec<Solver> = cases.iter().map(|&(f, t)| lane(f, t)).collect();
        let together = march_in_lanes(&mut solvers, &starts);
        for ((sol, &(f, two)), start) in together.iter().zip(&cases).zip(&starts) {
            let alone = by_itself(f, two, *start);
            assert!(sol.converged && alone.converged);
            assert_eq!(
                sol.iterations,
                alone.iterations,
                "f = {f}, two-scale {two}, warm {}",
                start.is_some()
            );
            let d = state_difference(sol, &alone);
            eprintln!(
                "f = {f}, two-scale {two}, warm {}: {} iterations, lanes against alone {d:.1e}",
                start.is_some(),
                sol.iterations
            );
            assert!(d < 1e-10, "f = {f}, two-scale {two}: lanes differ by {d:e}");
        }
    }
}

/// A study of `design` cut into `chains`, solved `batch` at a time.
fn study(
    problem: &lopin_core::Problem,
    settings: Settings,
    design: &Design,
    chains: usize,
    batch: usize,
) -> Vec<Outcome> {
    runner::run_gathered(
        &|| Solver::new(problem.clone(), settings),
        design,
        chains,
        RunOptions::warm(batch),
    )
    .expect("study")
}

/// The 6 × 2 grid of friction × gap on `two-blocks` (η < 1e-4) cut into three chains: solved
/// three at a time in lanes, every configuration takes the iterations of the same chains
/// solved one at a time on threads (within one), from the same start, with the same quantities
/// of interest to the tolerance, 1e-4 (a lane's multi-column solve rounds differently from a
/// lone solve: a window whose η lands that close to the tolerance stops one iteration apart, a
/// warm window's start carries the converged steps on, and a slip at the threshold of the
/// friction law can go the other way); on one-step windows and over the whole interval. Four
/// lanes on three chains leave one idle; of two lanes, the first done takes the third chain.
#[test]
fn a_study_in_batches_matches_its_chains_solved_one_at_a_time() {
    for window in [Some(1), None] {
        let (problem, settings) = opened(1e-4, window);
        let design = Design::grid(vec![
            (
                Target::parse("f", &problem).expect("f"),
                Spread::parse("0:0.5:0.1").expect("f values"),
            ),
            (
                Target::parse("gap", &problem).expect("gap"),
                Spread::parse("0,4e-6").expect("gap values"),
            ),
        ])
        .expect("grid");
        let one = study(&problem, settings, &design, 3, 1);
        for batch in [4, 2] {
            let together = study(&problem, settings, &design, 3, batch);
            assert_eq!(together.len(), 12, "batch {batch}");
            for (a, b) in together.iter().zip(&one) {
                assert_eq!(a.index, b.index);
                assert_eq!(
                    (a.chain, a.position, a.start),
                    (b.chain, b.position, b.start)
                );
                assert!(a.converged);
                assert!(
                    a.iterations.abs_diff(b.iterations) <= 1,
                    "window {window:?}, batch {batch}, configuration {}: {} iterations \
                     against {}",
                    a.index,
                    a.iterations,
                    b.iterations
                );
                for (k, (x, y)) in a
                    .quantities
                    .values()
                    .iter()
                    .zip(b.quantities.values())
                    .enumerate()
                {
                    let scale = y.abs().max(match k {
                        1 => 1e-5,
                        4 => 1e-2,
                        _ => 1e-30,
                    });
                    assert!(
                        (x - y).abs() <= 1e-4 * scale,
                        "window {window:?}, batch {batch}, configuration {}: quantity {k}: \
                         {x:e} against {y:e}",
                        a.index
                    );
                }
            }
        }
    }
}
