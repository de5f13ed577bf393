//! Studies over several parameters (`core/src/study/`): a 6 × 2 grid of friction ×
//! gap on `two-blocks` along the greedy path (friction first), warm-started from the nearest
//! solved configuration or from a parallelogram of three, against cold solves of every
//! configuration: fewer iterations, and the same quantities of interest within the tolerance's
//! reach, on the whole interval and on one-step windows (the default of a study with contact);
//! two chains solve every configuration once with two cold starts; on Latin-hypercube draws
//! around a design point, projected starts save over the nearest state and cold solves.

use lopin_core::scene;
use lopin_core::study::runner::{self, Outcome, RunOptions};
use lopin_core::study::Predictor;
use lopin_core::study::{projection, Design, Sampling, Spread, Target};
use lopin_core::{Settings, Solver};

fn run(chains: usize, cold: bool) -> Vec<Outcome> {
    run_with(chains, cold, Predictor::Nearest)
}

fn run_with(chains: usize, cold: bool, predictor: Predictor) -> Vec<Outcome> {
    run_grid(chains, cold, predictor, "0:0.5:0.1", "0,4e-6")
}

/// A study of the grid `f` × `gap` on two-blocks (ρ∞ = 0.5, η < 1e-4) over the whole interval
/// (`--window whole`), where each start is one state for every step.
fn run_grid(chains: usize, cold: bool, predictor: Predictor, f: &str, gap: &str) -> Vec<Outcome> {
    run_windows(chains, cold, predictor, f, gap, None)
}

/// [`run_grid`] on windows of `window` steps (None: the whole interval).
fn run_windows(
    chains: usize,
    cold: bool,
    predictor: Predictor,
    f: &str,
    gap: &str,
    window: Option<usize>,
) -> Vec<Outcome> {
    let spec = scene::load("two-blocks").expect("scene");
    let problem = scene::problem_of(&spec, "two-blocks").expect("builds");
    let mut settings = Settings::for_problem(&problem, &spec.solver);
    settings.rho_inf = 0.5;
    settings.tol = 1e-4;
    settings.window = window;
    let design = Design::grid(vec![
        (
            Target::parse("f", &problem).expect("f"),
            Spread::parse(f).expect("f values"),
        ),
        (
            Target::parse("gap", &problem).expect("gap"),
            Spread::parse(gap).expect("gap values"),
        ),
    ])
    .expect("grid");
    solve_design(&problem, settings, &design, chains, cold, predictor)
}

/// Every configuration of `design` along the greedy path cut into `chains`, rows in index order.
fn solve_design(
    problem: &lopin_core::Problem,
    settings: Settings,
    design: &Design,
    chains: usize,
    cold: bool,
    predictor: Predictor,
) -> Vec<Outcome> {
    runner::run_gathered(
        &|| Solver::new(problem.clone(), settings),
        design,
        chains,
        RunOptions {
            cold,
            compare_cold: false,
            batch: 1,
            predictor,
        },
    )
    .expect("study")
}

/// A study of `samples` Latin-hypercube draws of f ~ normal(0.3, 0.05) and gap ~ normal(10 µm,
/// 2 µm) on two-blocks (ρ∞ = 0.5, η < 1e-3, the whole interval, seed 1): an uncertainty study
/// around a design point.
fn run_sampled(samples: usize, cold: bool, predictor: Predictor) -> Vec<Outcome> {
    let spec = scene::load("two-blocks").expect("scene");
    let problem = scene::problem_of(&spec, "two-blocks").expect("builds");
    let mut settings = Settings::for_problem(&problem, &spec.solver);
    settings.rho_inf = 0.5;
    settings.window = None;
    let design = Design::sample(
        vec![
            (
                Target::parse("f", &problem).expect("f"),
                Spread::parse("normal(0.3,0.05)").expect("f spread"),
            ),
            (
                Target::parse("gap", &problem).expect("gap"),
                Spread::parse("normal(10e-6,2e-6)").expect("gap spread"),
            ),
        ],
        samples,
        Sampling::LatinHypercube,
        1,
    )
    .expect("samples");
    solve_design(&problem, settings, &design, 1, cold, predictor)
}

/// The quantities of interest of two studies of the same design agree configuration by
/// configuration to `rel` of their size.
fn agree(a: &[Outcome], b: &[Outcome], rel: f64) {
    assert_eq!(a.len(), b.len());
    for (a, b) in a.iter().zip(b) {
        assert_eq!(a.index, b.index);
        let (qa, qb) = (a.quantities.values(), b.quantities.values());
        for (k, (x, y)) in qa.iter().zip(&qb).enumerate() {
            // slip and friction work vanish at full stick: compare them on their largest value
            let scale = x.abs().max(y.abs()).max(match k {
                1 => 1e-5,
                4 => 1e-2,
                _ => 1e-30,
            });
            assert!(
                (x - y).abs() <= rel * scale,
                "configuration {}: quantity {k}: {x:e} against {y:e}",
                a.index
            );
        }
    }
}

/// Total iterations of a study.
fn total(o: &[Outcome]) -> usize {
    o.iter().map(|o| o.iterations).sum()
}

#[test]
fn a_warm_grid_costs_a_fraction_of_cold_solves_and_agrees_with_them() {
    let warm = run(1, false);
    let para = run_with(1, false, Predictor::Parallelogram);
    let cold = run(1, true);
    assert_eq!(warm.len(), 12);
    let (w, p, c) = (total(&warm), total(&para), total(&cold));
    println!(
        "6 x 2 f x gap: warm {w} iterations ({:.2} of cold), parallelogram {p} ({:.2}), cold {c}",
        w as f64 / c as f64,
        p as f64 / c as f64
    );
    assert!(warm.iter().chain(&para).chain(&cold).all(|o| o.converged));
    assert!(10 * w <= 8 * c, "warm {w} against cold {c}");
    assert!(10 * p <= 8 * c, "parallelogram {p} against cold {c}");
    // exactly one cold start, every other from a solved neighbour one grid step away; the path
    // moves the gap once
    assert_eq!(warm.iter().filter(|o| o.start.is_none()).count(), 1);
    for o in warm.iter().filter(|o| o.start.is_some()) {
        // one grid step: 0.2 of the scaled f range, or the whole (two-value) gap range
        let d = o.start_distance.expect("distance");
        assert!((d - 0.2).abs() < 1e-12 || (d - 1.0).abs() < 1e-12, "{o:?}");
    }
    let gap_steps = warm
        .iter()
        .filter(|o| o.start.is_some_and(|s| s % 2 != o.index % 2))
        .count();
    assert_eq!(gap_steps, 1);
    // the parallelogram starts close: start + first − second lands on the configuration
    let points = |i: usize| -> [f64; 2] { [0.1 * (i / 2) as f64, 4e-6 * (i % 2) as f64] };
    let mut closed = 0;
    for o in &para {
        if let (Some(j), Some((k, l))) = (o.start, o.start_change) {
            closed += 1;
            for d in 0..2 {
                let x = points(j)[d] + points(k)[d] - points(l)[d];
                assert!((x - points(o.index)[d]).abs() < 1e-12, "{o:?}");
            }
        }
    }
    assert!(closed >= 4, "{closed} parallelogram starts");
    agree(&warm, &cold, 2e-2);
    agree(&para, &cold, 2e-2);
    // no friction work without friction, some with it while the interface slips
    for o in &warm {
        let q = o.quantities;
        if points(o.index)[0] == 0.0 {
            assert_eq!(q.friction_work, 0.0);
        } else if q.max_slip > 1e-6 {
            assert!(q.friction_work > 0.0, "{o:?}");
        }
    }
}

#[test]
fn on_an_evenly_spaced_grid_each_configuration_starts_from_its_friction_neighbour() {
    // f and gap steps are equally long in scaled space (a third of each range): a friction
    // neighbour and the previous row's configuration are equally near, and the start goes to
    // the friction step, so the gap moves only between rows
    let (f, gap) = ("0:0.3:0.1", "0:6e-6:2e-6");
    let warm = run_grid(1, false, Predictor::Nearest, f, gap);
    let cold = run_grid(1, true, Predictor::Nearest, f, gap);
    assert_eq!(warm.len(), 16);
    assert!(warm.iter().chain(&cold).all(|o| o.converged));
    // index = 4 f-position + gap-position
    let gap_of = |i: usize| i % 4;
    let gap_steps: Vec<usize> = warm
        .iter()
        .filter(|o| o.start.is_some_and(|s| gap_of(s) != gap_of(o.index)))
        .map(|o| o.index)
        .collect();
    assert_eq!(gap_steps.len(), 3, "gap steps into {gap_steps:?}");
    for o in warm.iter().filter(|o| o.start.is_some()) {
        let d = o.start_distance.expect("distance");
        assert!((d - 1.0 / 3.0).abs() < 1e-12, "{o:?}");
    }
    let (w, c) = (total(&warm), total(&cold));
    let row_entries: usize = warm
        .iter()
        .filter(|o| gap_steps.contains(&o.index) || o.start.is_none())
        .map(|o| o.iterations)
        .sum();
    println!("4 x 4 f x gap: warm {w} ({row_entries} entering the rows), cold {c}");
    // measured 326 against 405 (ρ∞ = 0.5, η < 1e-4: cold solves are cheap here); a friction
    // step costs 19.3 iterations on average against 25.3 for a cold solve
    assert!(w < c, "warm {w} against cold {c}");
    let per_step = (w - row_entries) as f64 / 12.0;
    let per_cold = c as f64 / 16.0;
    assert!(
        per_step <= 0.85 * per_cold,
        "a friction step {per_step} against cold {per_cold}"
    );
}

#[test]
fn two_chains_solve_every_configuration_once_with_two_cold_starts() {
    let two = run(2, false);
    let indices: Vec<usize> = two.iter().map(|o| o.index).collect();
    assert_eq!(indices, (0..12).collect::<Vec<_>>());
    assert_eq!(two.iter().filter(|o| o.start.is_none()).count(), 2);
    assert_eq!(two.iter().filter(|o| o.chain == 1).count(), 6);
}

#[test]
fn on_one_step_windows_a_warm_study_saves_iterations_and_agrees_with_the_whole_interval() {
    // the default of a study with contact: one-step windows, each started from the nearest
    // solved configuration's converged steps
    let (f, gap) = ("0:0.5:0.1", "0,4e-6");
    let warm = run_windows(1, false, Predictor::Nearest, f, gap, Some(1));
    let cold = run_windows(1, true, Predictor::Nearest, f, gap, Some(1));
    let whole = run_grid(1, true, Predictor::Nearest, f, gap);
    assert!(warm.iter().chain(&cold).all(|o| o.converged));
    let (w, c) = (total(&warm), total(&cold));
    println!("6 x 2 f x gap on one-step windows: warm {w}, cold {c}");
    assert!(10 * w <= 8 * c, "warm {w} against cold {c}");
    // one-step windows and the whole interval converge to the same discrete solution
    agree(&warm, &cold, 2e-2);
    agree(&warm, &whole, 2e-2);
}

#[test]
fn a_projected_start_saves_iterations_over_the_nearest_state_and_agrees_with_cold_solves() {
    // the same 6 x 2 grid (ρ∞ = 0.5, η < 1e-4, whole interval): every warm start projected on
    // the nearest stored states (core/src/study/projection.rs)
    let (f, gap) = ("0:0.5:0.1", "0,4e-6");
    let projected = run_grid(1, false, Predictor::Projection, f, gap);
    let nearest = run_grid(1, false, Predictor::Nearest, f, gap);
    let cold = run_grid(1, true, Predictor::Nearest, f, gap);
    assert!(projected.iter().chain(&cold).all(|o| o.converged));
    let (p, n, c) = (total(&projected), total(&nearest), total(&cold));
    println!("6 x 2 f x gap: projected {p}, nearest {n}, cold {c}");
    // measured 189 against 199 from the nearest state and 290 cold
    assert!(
        p < n && 10 * p <= 7 * c,
        "projected {p}, nearest {n}, cold {c}"
    );
    for o in &projected {
        match (o.start, o.start_residual) {
            (None, r) => assert!(r.is_none(), "{o:?}"),
            // the start is never farther from the laws than the nearest state alone
            (Some(_), Some((near, start))) => assert!(start <= near, "{o:?}"),
            (Some(_), None) => panic!("a warm start without its projection: {o:?}"),
        }
    }
    let improved = projected
        .iter()
        .filter_map(|o| o.start_residual)
        .filter(|(near, start)| *start < 0.8 * near)
        .count();
    assert!(improved >= 5, "{improved} starts at least 20 % closer");
    agree(&projected, &cold, 2e-2);
}

#[test]
fn where_the_response_is_linear_in_the_gap_the_projection_finds_the_midpoint() {
    // gap 8.00 and 8.02 µm, solved tightly (η < 1e-8), then 8.01 µm: so close that the
    // response is linear in the gap between them (no contact status changes), so the best
    // admissible combination is their midpoint, α = 1/2, and it is nearly exact
    let spec = scene::load("two-blocks").expect("scene");
    let problem = scene::problem_of(&spec, "two-blocks").expect("builds");
    let mut settings = Settings::for_problem(&problem, &spec.solver);
    settings.rho_inf = 0.5;
    settings.window = None;
    settings.tol = 1e-8;
    let mut solver = Solver::new(problem, settings).expect("solver");
    let gap = lopin_core::parameter::Parameter::parse("gap").expect("gap");
    let mut at = |g: f64, start: Option<&lopin_core::InterfaceState>| {
        solver.set_parameter(gap, g).expect("gap");
        solver.solve(start).expect("solves")
    };
    let a = at(8.00e-6, None);
    let b = at(8.02e-6, Some(&a.state));
    solver.set_parameter(gap, 8.01e-6).expect("gap");
    let p = projection::project(&solver, &a.state, std::slice::from_ref(&b.state), 2);
    println!(
        "gap 8.01 µm from 8.00 and 8.02: α = {:.4}, start residual {:.2e} (nearest {:.2e})",
        p.weights[0], p.residual, p.residual_nearest
    );
    assert!((p.weights[0] - 0.5).abs() < 0.02, "α = {}", p.weights[0]);
    assert!(p.residual < 0.1 * p.residual_nearest, "{p:?}");
    // and a solve from it converges at once, where the nearest state needs more
    let mut tight = *solver.settings();
    tight.tol = 1e-5;
    solver.set_settings(tight).expect("settings");
    let from_projection = solver.solve(Some(&p.state)).expect("solves");
    let from_nearest = solver.solve(Some(&a.state)).expect("solves");
    println!(
        "to η < 1e-5: {} iterations from the projection, {} from the nearest",
        from_projection.iterations, from_nearest.iterations
    );
    assert!(from_projection.converged && from_nearest.converged);
    assert!(from_projection.iterations < from_nearest.iterations);
}

#[test]
fn on_samples_around_a_design_point_projected_starts_save_over_nearest_and_cold() {
    // 30 draws of (f, gap) around f = 0.3, gap = 10 µm: every step of the path moves both
    // parameters, none of them on a grid line, so no two stored states differ in one parameter
    let projected = run_sampled(30, false, Predictor::Projection);
    let nearest = run_sampled(30, false, Predictor::Nearest);
    let cold = run_sampled(30, true, Predictor::Nearest);
    assert!(projected
        .iter()
        .chain(&nearest)
        .chain(&cold)
        .all(|o| o.converged));
    let (p, n, c) = (total(&projected), total(&nearest), total(&cold));
    println!(
        "30 samples around (0.3, 10 µm): projected {p} ({:.3} of cold), nearest {n} ({:.3}), cold {c}",
        p as f64 / c as f64,
        n as f64 / c as f64
    );
    // measured 265 projected, 348 nearest, 544 cold (0.49 and 0.64); the 100-draw study of the
    // the guide takes 594 against 901 and 1,823 (0.326)
    assert!(10 * p <= 9 * n, "projected {p} against nearest {n}");
    assert!(10 * p <= 6 * c, "projected {p} against cold {c}");
    for o in &projected {
        if let Some((near, start)) = o.start_residual {
            assert!(start <= near, "{o:?}");
        }
    }
    // at η < 1e-3 the quantities of warm and cold solves agree to the tolerance's reach; the
    // slip and the friction work, small differences of large motions and works, are the
    // loosest (measured worst: 7.2e-4, 2.3e-2, 2.3e-4, 7.5e-5, 4.6e-2, 6.9e-4)
    let bounds = [1e-2, 5e-2, 1e-2, 1e-2, 1e-1, 1e-2];
    for (a, b) in projected.iter().zip(&cold) {
        let (qa, qb) = (a.quantities.values(), b.quantities.values());
        for (k, bound) in bounds.iter().enumerate() {
            let (x, y) = (qa[k], qb[k]);
            let rel = (x - y).abs() / x.abs().max(y.abs()).max(1e-30);
            assert!(
                rel <= *bound,
                "configuration {}: quantity {k}: {x:e} against {y:e}",
                a.index
            );
        }
    }
}
