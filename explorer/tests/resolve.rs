//! The explorer's background re-solve: a parameter change gives a converged warm re-solve equal
//! to a cold solve at the new value within the tolerance bound, and a change during a re-solve
//! cancels it (METHOD §8). Every way of running the solver is checked: the desktop's solver
//! thread, the browser's inline mode (a few iterations per poll) and the browser's worker link
//! (every message crossing as bytes, here over a thread), which must give the same iterates bit
//! for bit.

use lopin_core::interfaces::search_direction::Directions;
use lopin_core::{post, scene, Parameter, Settings, Solver};
use lopin_explorer::fields::StepFields;
use lopin_explorer::params::{FrictionTargets, Params};
use lopin_explorer::protocol::{Event, SolveReport};
use lopin_explorer::remote::thread_connector;
use lopin_explorer::wire::Start;
use lopin_explorer::worker::Worker;
use std::sync::Arc;
use std::time::Duration;

fn two_blocks() -> (lopin_core::Problem, Settings) {
    let spec = scene::registry::builtin("two-blocks").expect("built-in scene");
    let problem = scene::problem_of(&spec, "scene two-blocks").expect("builds");
    let settings = Settings::for_problem(&problem, &spec.solver);
    (problem, settings)
}

/// Waits for the report of `generation`, collecting the non-live fields that arrive.
fn finish(worker: &mut Worker, generation: u64, fields: &mut Vec<Arc<StepFields>>) -> SolveReport {
    loop {
        match worker.wait(Duration::from_secs(120)) {
            Some(Event::Finished(r)) if r.generation == generation => return *r,
            Some(Event::Fields(f)) if !f.live && f.generation == generation => fields.push(f),
            Some(Event::Error(e)) => panic!("worker error: {e}"),
            Some(_) => {}
            None => panic!("no report for generation {generation} within 120 s"),
        }
    }
}

/// The desktop worker (solver thread).
fn threaded(problem: lopin_core::Problem, settings: Settings) -> Worker {
    Worker::spawn(problem, settings, Arc::new(|| {}), Default::default()).expect("worker")
}

/// The browser's worker (no thread: advanced inside poll/wait).
fn inline(problem: lopin_core::Problem, settings: Settings) -> Worker {
    Worker::spawn_inline(problem, settings, Arc::new(|| {}), Default::default()).expect("worker")
}

/// The browser's worker link, over a thread: the solver side opens two-blocks itself (the
/// problem given is the UI side's copy).
fn linked(_: lopin_core::Problem, _: Settings) -> Worker {
    let start = Start {
        scene: "two-blocks".into(),
        two_scale: None,
    };
    Worker::spawn_remote(start, Arc::new(|_| {}), &thread_connector()).expect("worker link")
}

type Spawn = fn(lopin_core::Problem, Settings) -> Worker;

fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0, |m, x| m.max(x.abs()))
}

#[test]
fn a_slider_change_converges_warm_to_the_cold_solution() {
    slider_change_converges_warm(threaded);
}

#[test]
fn inline_a_slider_change_converges_warm_to_the_cold_solution() {
    slider_change_converges_warm(inline);
}

#[test]
fn linked_a_slider_change_converges_warm_to_the_cold_solution() {
    slider_change_converges_warm(linked);
}

fn slider_change_converges_warm(spawn: Spawn) {
    let (problem, settings) = two_blocks();
    let mut worker = spawn(problem.clone(), settings);
    let mut params = Params::of(&problem, &settings);
    let tol = params.settings.tol;
    let g0 = worker.solve(params.clone());
    let r0 = finish(&mut worker, g0, &mut Vec::new());
    assert!(r0.converged && !r0.warm, "{r0:?}");

    params.friction = Some(0.1);
    let g1 = worker.solve(params.clone());
    let r1 = finish(&mut worker, g1, &mut Vec::new());
    assert!(r1.converged && r1.warm && r1.eta < tol, "{r1:?}");
    let steps = problem.time.steps;
    let probe_steps = [steps / 4, steps / 2, 3 * steps / 4, steps];
    let mut warm = Vec::new();
    for m in probe_steps {
        worker.request_fields(m);
        loop {
            match worker.wait(Duration::from_secs(60)).expect("fields arrive") {
                Event::Fields(f) if !f.live && f.step == m => {
                    assert_eq!(f.generation, g1);
                    warm.push(f);
                    break;
                }
                _ => {}
            }
        }
    }

    // cold solve at f = 0.1 with the same settings
    let mut cold_problem = problem.clone();
    Parameter::Friction
        .apply(&mut cold_problem, 0.1)
        .expect("f");
    let mut solver = Solver::new(cold_problem, settings).expect("solver");
    let cold = solver.solve(None).expect("cold solve");
    assert!(cold.converged);
    let mut peak: f64 = 0.0;
    let mut diff: f64 = 0.0;
    for (w, &m) in warm.iter().zip(&probe_steps) {
        let c = post::fields_at(&solver, &cold, m);
        for (ws, cs) in w.subs.iter().zip(&c) {
            peak = peak.max(max_abs(&cs.v));
            let d: Vec<f64> = ws.v.iter().zip(&cs.v).map(|(a, b)| a - b).collect();
            diff = diff.max(max_abs(&d));
        }
    }
    let rel = diff / peak;
    eprintln!(
        "warm {} iterations vs cold {}; max velocity difference {rel:.2e} of the peak",
        r1.iterations, cold.iterations
    );
    // the bound of the sweep validation: 30 tol on the peak-relative difference
    assert!(
        rel < 30.0 * tol,
        "warm and cold differ by {rel:.3e} > 30 tol"
    );
    assert!(
        peak > 1.0,
        "the impact drives the blocks: peak |v| = {peak}"
    );
}

#[test]
fn a_change_during_a_re_solve_cancels_it() {
    change_during_re_solve_cancels(threaded);
}

#[test]
fn inline_a_change_during_a_re_solve_cancels_it() {
    change_during_re_solve_cancels(inline);
}

#[test]
fn linked_a_change_during_a_re_solve_cancels_it() {
    change_during_re_solve_cancels(linked);
}

fn change_during_re_solve_cancels(spawn: Spawn) {
    let (problem, settings) = two_blocks();
    let mut worker = spawn(problem.clone(), settings);
    let mut slow = Params::of(&problem, &settings);
    slow.settings.tol = 1e-10;
    slow.friction = Some(0.1);
    let g1 = worker.solve(slow.clone());
    // let it run a few iterations
    let mut seen = 0;
    while seen < 3 {
        match worker.wait(Duration::from_secs(60)).expect("progress") {
            Event::Progress { generation, .. } if generation == g1 => seen += 1,
            Event::Error(e) => panic!("{e}"),
            _ => {}
        }
    }
    let mut fast = slow.clone();
    fast.settings.tol = 1e-3;
    fast.friction = Some(0.2);
    let g2 = worker.solve(fast);
    let r1 = finish(&mut worker, g1, &mut Vec::new());
    assert!(r1.cancelled && !r1.converged, "{r1:?}");
    assert!(
        r1.iterations < 100,
        "cancelled promptly: {} iterations",
        r1.iterations
    );
    let mut fields = Vec::new();
    let r2 = finish(&mut worker, g2, &mut fields);
    assert!(r2.converged && r2.warm && !r2.cancelled, "{r2:?}");
    assert_eq!(r2.params.friction, Some(0.2));
    // the converged solve sent the fields of the displayed step
    assert!(fields.iter().any(|f| f.generation == g2));
}

/// Reports and converged fields of a cold solve then two warm re-solves, with the displayed
/// step at 30.
fn session(spawn: Spawn) -> (Vec<SolveReport>, Vec<Arc<StepFields>>) {
    let (problem, settings) = two_blocks();
    let mut worker = spawn(problem.clone(), settings);
    worker.set_display_step(30);
    let mut params = Params::of(&problem, &settings);
    let mut reports = Vec::new();
    let mut fields = Vec::new();
    for f in [None, Some(0.1), Some(0.45)] {
        if f.is_some() {
            params.friction = f;
        }
        let g = worker.solve(params.clone());
        reports.push(finish(&mut worker, g, &mut fields));
    }
    (reports, fields)
}

#[test]
fn the_browser_s_inline_worker_gives_the_thread_s_iterates_bit_for_bit() {
    same_iterates(inline);
}

#[test]
fn the_browser_s_worker_link_gives_the_thread_s_iterates_bit_for_bit() {
    same_iterates(linked);
}

fn same_iterates(spawn: Spawn) {
    let (thread_reports, thread_fields) = session(threaded);
    let (inline_reports, inline_fields) = session(spawn);
    assert!(
        thread_fields.iter().all(|f| f.step == 30),
        "fields at the displayed step"
    );
    assert_eq!(thread_reports.len(), 3);
    for (t, i) in thread_reports.iter().zip(&inline_reports) {
        assert!(t.converged && i.converged, "{t:?} {i:?}");
        assert_eq!(t.iterations, i.iterations);
        assert_eq!(t.eta.to_bits(), i.eta.to_bits(), "η {} vs {}", t.eta, i.eta);
        assert_eq!(t.warm, i.warm);
    }
    assert!(inline_reports[1].warm && !inline_reports[0].warm);
    assert_eq!(thread_fields.len(), inline_fields.len());
    for (t, i) in thread_fields.iter().zip(&inline_fields) {
        assert_eq!(t.step, i.step);
        for (ts, is) in t.subs.iter().zip(&i.subs) {
            assert_eq!(ts.v, is.v, "velocity at step {}", t.step);
        }
    }
}

/// ρ∞ and the wave-matched direction set in the panel reach the solver: a cold solve asked for
/// with them takes exactly the iterations of the engine built with them (ρ∞ = 0.5 and the wave
/// direction iterate differently from the defaults), and moving ρ∞ back re-solves warm to η < tol.
#[test]
fn the_scheme_and_direction_controls_reach_the_solver() {
    let (problem, mut settings) = two_blocks();
    settings.tol = 1e-4;
    let engine_problem = problem.clone();
    let mut engine_settings = settings;
    engine_settings.rho_inf = 0.5;
    engine_settings.directions = Directions::Wave;
    let engine = Solver::new(engine_problem, engine_settings)
        .expect("engine")
        .solve(None)
        .expect("engine solve");
    let default = Solver::new(problem.clone(), settings)
        .expect("default")
        .solve(None)
        .expect("default solve");
    assert_ne!(engine.iterations, default.iterations);

    let mut worker = threaded(problem.clone(), settings);
    let mut params = Params::of(&problem, &settings);
    assert_eq!(
        (params.settings.rho_inf, params.settings.directions),
        (1.0, Directions::Isotropic)
    );
    params.settings.rho_inf = 0.5;
    params.settings.directions = Directions::Wave;
    let g = worker.solve(params.clone());
    let r = finish(&mut worker, g, &mut Vec::new());
    assert!(r.converged && !r.warm, "{r:?}");
    assert_eq!(r.iterations, engine.iterations);

    params.settings.rho_inf = 1.0;
    let g = worker.solve(params.clone());
    let r = finish(&mut worker, g, &mut Vec::new());
    assert!(
        r.converged && r.warm && r.eta < settings.tol && r.iterations > 0,
        "{r:?}"
    );
}

#[test]
fn a_held_solve_waits_for_its_release() {
    held_solve_waits(threaded);
}

#[test]
fn inline_a_held_solve_waits_for_its_release() {
    held_solve_waits(inline);
}

/// A slider move's solve is held while the frame with the stand-in picture is drawn: nothing
/// of it (no iteration, no report) comes before its release, and after it the solve converges
/// warm; a release of an older generation releases nothing.
fn held_solve_waits(spawn: Spawn) {
    let (problem, settings) = two_blocks();
    let mut worker = spawn(problem.clone(), settings);
    let mut params = Params::of(&problem, &settings);
    let g0 = worker.solve(params.clone());
    let r0 = finish(&mut worker, g0, &mut Vec::new());
    params.friction = Some(0.15);
    let g1 = worker.solve_held(params.clone());
    worker.release(g0);
    // the solve of 0.15 would take a few tens of ms: 0.5 s of silence shows it is held
    let deadline = std::time::Instant::now() + Duration::from_millis(500);
    while let Some(left) = deadline.checked_duration_since(std::time::Instant::now()) {
        match worker.wait(left.min(Duration::from_millis(50))) {
            Some(Event::Progress { generation, .. }) if generation == g1 => {
                panic!("the held solve iterated before its release")
            }
            Some(Event::Finished(r)) if r.generation == g1 => {
                panic!("the held solve finished before its release: {r:?}")
            }
            _ => {}
        }
    }
    worker.release(g1);
    let r1 = finish(&mut worker, g1, &mut Vec::new());
    assert!(r1.converged && r1.warm && r1.iterations > 0, "{r1:?}");
    assert!(r0.converged && r1.eta < params.settings.tol, "{r1:?}");
}

/// The friction work of a converged solve, J.
fn friction_work(solver: &Solver, sol: &lopin_core::Solution) -> f64 {
    lopin_core::dissipation::contact_work(solver, sol).friction
}

/// On a scene with zones, the friction slider pointed at one zone (`FrictionTargets`) moves
/// that zone alone, also after the background study solved a value on every contact: at η < 1e-5 the warm re-solve's friction work is the cold solve's with
/// f@upper = 0.1 and f@lower left at 0.3 within 0.1 %, and 5 % or more away from the uniform
/// f = 0.1's.
#[test]
fn the_friction_slider_pointed_at_a_zone_moves_that_zone_alone() {
    let path = format!(
        "{}/../assets/scenes/test/mini-stack-zones.toml",
        env!("CARGO_MANIFEST_DIR")
    );
    let spec = scene::load(&path).expect("scene");
    let problem = scene::problem_of(&spec, &path).expect("builds");
    let mut settings = Settings::for_problem(&problem, &spec.solver);
    settings.tol = 1e-5;
    let mut worker = threaded(problem.clone(), settings);
    let mut params = Params::of(&problem, &settings);
    let mut targets = FrictionTargets::of(&problem);
    assert_eq!(&*params.zones, ["upper".to_string(), "lower".to_string()]);
    assert_eq!(targets.zones().collect::<Vec<_>>(), vec![0, 1]);
    let g0 = worker.solve(params.clone());
    assert!(finish(&mut worker, g0, &mut Vec::new()).converged);
    // the background study solves a value of f on every contact first: the zone's move must
    // not keep that value on the other zone
    loop {
        match worker.wait(Duration::from_secs(120)) {
            Some(Event::Stored(c)) if c.background => break,
            Some(Event::Error(e)) => panic!("worker error: {e}"),
            Some(_) => {}
            None => panic!("no background value within 120 s"),
        }
    }

    targets.switch(&mut params, Some(0));
    params.friction = Some(0.1);
    targets.moved(&params);
    let g1 = worker.solve(params.clone());
    // the report, and the quantities of the configuration stored from it
    let (mut report, mut stored) = (None, None);
    while report.is_none() || stored.is_none() {
        match worker.wait(Duration::from_secs(120)) {
            Some(Event::Finished(r)) if r.generation == g1 => report = Some(*r),
            Some(Event::Stored(c)) if !c.background && c.value == 0.1 => stored = Some(c),
            Some(Event::Error(e)) => panic!("worker error: {e}"),
            Some(_) => {}
            None => panic!("no report or stored configuration within 120 s"),
        }
    }
    let (r1, stored) = (report.expect("report"), stored.expect("stored"));
    assert!(r1.converged && r1.warm, "{r1:?}");
    assert_eq!(r1.params.friction_label(), "f@upper");
    let warm = stored.quantities.friction_work;

    let cold = |zone: Option<usize>| {
        let mut p = problem.clone();
        Parameter::Friction.apply_in(&mut p, zone, 0.1).expect("f");
        let mut solver = Solver::new(p, settings).expect("solver");
        let sol = solver.solve(None).expect("cold");
        assert!(sol.converged);
        friction_work(&solver, &sol)
    };
    let (zoned, uniform) = (cold(Some(0)), cold(None));
    eprintln!(
        "friction work: slider on f@upper = 0.1 {warm:.5e} J ({} iterations warm), cold \
         f@upper = 0.1 {zoned:.5e} J, cold f = 0.1 everywhere {uniform:.5e} J",
        r1.iterations
    );
    assert!((warm - zoned).abs() < 1e-3 * zoned, "{warm} {zoned}");
    assert!((uniform - zoned).abs() > 0.05 * zoned, "{uniform} {zoned}");
}
