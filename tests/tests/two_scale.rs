//! The two-scale linear stage (METHOD §9): the converged two-scale solution equals the
//! single-scale one and the monolithic reference, the macro forces balance on every internal
//! interface after every linear stage (perfect and contact interfaces), and identical
//! substructures share one factorization and one homogenized operator.

use lopin_core::interfaces::interface::Law;
use lopin_core::scene::{self, SceneSpec};
use lopin_core::{Control, InterfaceState, Settings, Solver};
use lopin_judge::compare::compare;
use lopin_reference::monolithic::Monolithic;
use lopin_tests::{rel_diff, velocity_history};

/// Largest |Êᵀ A F₁ + Êᵀ A F₂| over internal interfaces and steps 1..N, relative to the largest
/// |Êᵀ A F| of a side.
fn macro_imbalance(solver: &Solver, s: &InterfaceState) -> f64 {
    let p = solver.problem();
    let mp = solver.macro_problem().expect("macro problem");
    let (mut worst, mut scale) = (0.0f64, 0.0f64);
    for (i, iface) in p.interfaces.iter().enumerate() {
        let Some(b) = &mp.bases[i] else { continue };
        for m in 1..=p.time.steps {
            let mut sum = vec![0.0; b.count];
            for side in &iface.sides {
                let h = &s.subs[side.sub];
                let r = h.at(m);
                let f = &h.f[r.start + side.offset..][..iface.len];
                let mut one = vec![0.0; b.count];
                b.project_add(&iface.area, f, 1.0, &mut one);
                scale = one.iter().fold(scale, |a, x| a.max(x.abs()));
                sum.iter_mut().zip(&one).for_each(|(a, x)| *a += x);
            }
            worst = sum.iter().fold(worst, |a, x| a.max(x.abs()));
        }
    }
    worst / scale
}

fn settings(spec: &SceneSpec, tol: f64, two_scale: bool) -> (lopin_core::Problem, Settings) {
    let problem = scene::problem_of(spec, &spec.name).expect("scene builds");
    let mut s = Settings::for_problem(&problem, &spec.solver);
    s.tol = tol;
    s.max_iter = 20_000;
    s.two_scale = two_scale;
    (problem, s)
}

/// The reference solution, a single-scale solve and a two-scale solver (not yet solved) of a
/// scene at tolerance `tol`.
struct Three {
    reference: Monolithic,
    mono: lopin_reference::monolithic::MonoSolution,
    single: Solver,
    single_sol: lopin_core::Solution,
    two: Solver,
}

fn three(spec: &SceneSpec, tol: f64) -> Three {
    let (problem, two) = settings(spec, tol, true);
    let (_, one) = settings(spec, tol, false);
    let reference = Monolithic::new(problem.clone()).expect("reference");
    let mono = reference.solve().expect("reference solve");
    let mut single = Solver::new(problem.clone(), one).expect("single-scale setup");
    let single_sol = single.solve(None).expect("single-scale");
    let two = Solver::new(problem, two).expect("two-scale setup");
    Three {
        reference,
        mono,
        single,
        single_sol,
        two,
    }
}

/// two-blocks cut 2 × 2 per block: 8 substructures, perfect and contact interfaces. At
/// η < 1e-9 two-scale = single-scale = monolithic to 1e-6 of the peak velocity; the macro
/// imbalance stays below 1e-10 at every iteration.
#[test]
fn two_scale_equals_single_scale_and_the_reference_with_contact() {
    let mut spec = scene::load("two-blocks").expect("scene");
    spec.split(2).expect("split");
    let Three {
        reference,
        mono,
        single,
        single_sol,
        two: mut solver,
    } = three(&spec, 1e-9);
    let mp = solver.macro_problem().expect("macro problem");
    let internal = solver
        .problem()
        .interfaces
        .iter()
        .filter(|i| i.sides.len() == 2)
        .count();
    let contact = solver
        .problem()
        .interfaces
        .iter()
        .filter(|i| matches!(i.law, Law::Contact(_)))
        .count();
    assert_eq!(
        mp.size,
        9 * internal,
        "9 macro functions per planar interface"
    );
    let mut worst = 0.0f64;
    let sol = solver
        .solve_observed(None, &mut |it| {
            worst = worst.max(macro_imbalance(it.solver, it.state));
            Control::Continue
        })
        .expect("two-scale");
    assert!(sol.converged && single_sol.converged);
    let c = compare(&solver, &sol, &reference, &mono);
    let d = rel_diff(
        &velocity_history(&solver, &sol),
        &velocity_history(&single, &single_sol),
    );
    println!(
        "two-blocks split 2: {internal} internal interfaces ({contact} contact), {} macro dofs; \
         two-scale {} it, single-scale {} it; two vs reference v {:.2e} F {:.2e}; two vs single \
         {d:.2e}; macro imbalance max {worst:.2e}",
        9 * internal,
        sol.iterations,
        single_sol.iterations,
        c.rel_diff_velocity,
        c.rel_diff_force
    );
    assert!(contact > 0);
    assert!(
        c.rel_diff_velocity <= 1e-6 && c.rel_diff_force <= 1e-6,
        "{c:?}"
    );
    assert!(d <= 1e-6, "two-scale vs single-scale {d:.3e}");
    assert!(worst <= 1e-10, "macro imbalance {worst:.3e}");
}

/// The single-scale iterates do not balance the macro forces (so the check above can fail).
#[test]
fn single_scale_iterates_leave_a_macro_imbalance() {
    let mut spec = scene::load("two-blocks").expect("scene");
    spec.split(2).expect("split");
    let (problem, mut s) = settings(&spec, 1e-3, true);
    let mut solver = Solver::new(problem, s).expect("setup");
    s.two_scale = false;
    solver.set_settings(s).expect("settings");
    let mut first = None;
    solver
        .solve_observed(None, &mut |it| {
            first.get_or_insert(macro_imbalance(it.solver, it.state));
            Control::Stop
        })
        .expect("solve");
    let first = first.expect("one iteration");
    println!("single-scale first iterate: macro imbalance {first:.2e}");
    assert!(first > 1e-3, "{first:.3e}");
}

/// A steel cube cut into 4 × 4 × 4 identical cells with perfect interfaces, pushed on top and
/// clamped below. A cell's S depends on where its trace lies: along x and y a cell is at the low
/// end (free face below), inside, or at the high end (3 kinds each); along z the clamp below a
/// bottom cell weighs its face exactly like the perfect interface below an inner cell, while the
/// top cells carry only a z velocity (2 kinds): 3 · 3 · 2 = 18 factorizations for 64 cells. The
/// homogenized operator also sees that the clamp carries no macro unknowns: 3 · 3 · 3 = 27.
/// Two-scale = single-scale at η < 1e-8.
#[test]
fn identical_cells_share_factorizations_and_homogenized_operators() {
    let text = r#"
name = "cube-4"
split_axes = "xyz"
[time]
dt = 0.5e-6
steps = 30
[[material]]
name = "steel"
young = 210e9
poisson = 0.3
density = 7800.0
[[body]]
name = "cube"
material = "steel"
min = [0.0, 0.0, 0.0]
max = [0.04, 0.04, 0.04]
divisions = [8, 8, 8]
split = [4, 4, 4]
[[boundary]]
body = "cube"
face = "z+"
z = { velocity = -10.0, ramp_time = 5e-6 }
[[boundary]]
body = "cube"
face = "z-"
clamped = true
"#;
    let spec = scene::from_toml(text, "cube-4").expect("scene");
    let Three {
        reference,
        mono,
        single,
        single_sol,
        two: mut solver,
    } = three(&spec, 1e-8);
    let sol = solver.solve(None).expect("two-scale solve");
    let factors = solver.classes().count();
    // shared factorizations give the reference's solution
    let c = compare(&single, &single_sol, &reference, &mono);
    assert!(c.rel_diff_velocity <= 1e-6, "{c:?}");
    let homogenized = solver.macro_problem().expect("macro").classes.count();
    let d = rel_diff(
        &velocity_history(&solver, &sol),
        &velocity_history(&single, &single_sol),
    );
    println!(
        "cube 4x4x4: {factors} factorizations, {homogenized} homogenized operators for 64 cells; \
         two-scale {} it, single-scale {} it, difference {d:.2e}; single-scale vs reference \
         {:.2e}",
        sol.iterations, single_sol.iterations, c.rel_diff_velocity
    );
    assert_eq!(factors, 18);
    assert_eq!(homogenized, 27);
    assert!(sol.converged && single_sol.converged);
    assert!(d <= 1e-6, "{d:.3e}");
}

/// The memory estimate printed before large runs counts exactly the interface fields a solve
/// holds (s, the unrelaxed linear-stage output, ŝ: METHOD §11), and the factorization count is
/// the solver's.
#[test]
fn the_estimate_counts_the_interface_fields_and_factorizations() {
    use lopin_core::estimate::Estimate;
    let spec = scene::load("granular-small").expect("scene");
    let (problem, mut s) = settings(&spec, 1e-3, false);
    s.window = Some(1);
    let e = Estimate::of(&problem, &s);
    let state = InterfaceState::cold(&problem);
    let sides: usize = problem
        .interfaces
        .iter()
        .map(|i| 2 * i.len * i.sides.len() * (problem.time.steps + 1))
        .sum();
    assert_eq!(e.interface_bytes, 8 * (2 * state.size() + sides));
    assert_eq!(e.cache_bytes, 0, "windowed runs keep no skip cache");
    let solver = Solver::new(problem, s).expect("setup");
    let full = Estimate::of_solver(&solver);
    println!("granular-small: {}", full.lines().join("; "));
    assert_eq!(full.factorizations, Some(solver.factors().len()));
    assert!(solver.factors().len() < solver.problem().subs.len() / 2);
    assert!(full.iteration_s.is_some_and(|t| t > 0.0 && t.is_finite()));
    assert!(!full.is_large());
}
