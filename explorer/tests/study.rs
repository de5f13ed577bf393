//! The explorer's background study: while the user is idle the worker solves the
//! friction grid nearest-first and stores every converged configuration, whose picture and
//! state equal a cold solve's within the sweep bound 30·tol; several values solved at once on
//! lanes sharing the factorizations store the same configurations as one at a time (the values
//! nearest first, each within 30·tol of a cold solve); a request for a stored value is
//! answered without solving; one between two stored values starts warm from their states'
//! interpolation in fewer iterations than from the nearer alone, one beyond them from the
//! nearest, each in fewer than cold; a user change cancels the background configuration;
//! the difference field of two stored pictures matches the difference of two cold solutions;
//! the pinned configuration is pictured at a new displayed step at once, paused or not.
//! The desktop's solver thread and the browser's inline mode are both checked where they differ.

use lopin_core::study::Quantities;
use lopin_core::{post, scene, Parameter, Settings, Solver};
use lopin_explorer::fields::{self, StepFields};
use lopin_explorer::geometry::SceneGeometry;
use lopin_explorer::mesh_build::{difference, nodal_values};
use lopin_explorer::params::Params;
use lopin_explorer::protocol::{Event, SolveReport, StoredConfig, StudyControl};
use lopin_explorer::quantity::Quantity;
use lopin_explorer::worker::Worker;
use std::sync::Arc;
use std::time::Duration;

fn two_blocks() -> (lopin_core::Problem, Settings) {
    let spec = scene::registry::builtin("two-blocks").expect("built-in scene");
    let problem = scene::problem_of(&spec, "scene two-blocks").expect("builds");
    let settings = Settings::for_problem(&problem, &spec.solver);
    (problem, settings)
}

type Spawn = fn(lopin_core::Problem, Settings) -> Worker;

fn threaded(problem: lopin_core::Problem, settings: Settings) -> Worker {
    Worker::spawn(problem, settings, Arc::new(|| {}), Default::default()).expect("worker")
}

fn inline(problem: lopin_core::Problem, settings: Settings) -> Worker {
    Worker::spawn_inline(problem, settings, Arc::new(|| {}), Default::default()).expect("worker")
}

/// Everything a worker said until `until` accepts an event (the events are kept in order).
fn collect(worker: &mut Worker, seen: &mut Vec<Event>, until: impl Fn(&Event) -> bool) {
    loop {
        let e = worker
            .wait(Duration::from_secs(120))
            .expect("an event within 120 s");
        if let Event::Error(msg) = &e {
            panic!("worker error: {msg}");
        }
        let stop = until(&e);
        seen.push(e);
        if stop {
            return;
        }
    }
}

/// Asks the worker to solve `params` and collects its events up to that solve's report:
/// (the request's generation, the events).
fn solve_until_report(worker: &mut Worker, params: &Params) -> (u64, Vec<Event>) {
    let g = worker.solve(params.clone());
    let mut events = Vec::new();
    collect(
        worker,
        &mut events,
        |e| matches!(e, Event::Finished(r) if r.generation == g),
    );
    (g, events)
}

fn report(events: &[Event], generation: u64) -> SolveReport {
    events
        .iter()
        .find_map(|e| match e {
            Event::Finished(r) if r.generation == generation => Some((**r).clone()),
            _ => None,
        })
        .expect("a report")
}

fn stored(events: &[Event]) -> Vec<Arc<StoredConfig>> {
    events
        .iter()
        .filter_map(|e| match e {
            Event::Stored(c) => Some(c.clone()),
            _ => None,
        })
        .collect()
}

/// A solve of two-blocks at friction `f` from `start` (None: cold): the solver and its
/// converged solution.
fn solve_at(
    problem: &lopin_core::Problem,
    settings: Settings,
    f: f64,
    start: Option<&lopin_core::state::InterfaceState>,
) -> (Solver, lopin_core::Solution) {
    let mut p = problem.clone();
    Parameter::Friction.apply(&mut p, f).expect("f");
    let mut solver = Solver::new(p, settings).expect("solver");
    let sol = solver.solve(start).expect("solve");
    assert!(sol.converged);
    (solver, sol)
}

/// A cold solve of two-blocks at friction `f`: the solver and its solution.
fn cold(
    problem: &lopin_core::Problem,
    settings: Settings,
    f: f64,
) -> (Solver, lopin_core::Solution) {
    solve_at(problem, settings, f, None)
}

fn max_abs(v: impl Iterator<Item = f64>) -> f64 {
    v.fold(0.0, |m, x| m.max(x.abs()))
}

/// The largest velocity difference between two sets of fields, relative to the peak of `b`.
fn velocity_gap(a: &StepFields, b: &StepFields) -> f64 {
    let peak = max_abs(b.subs.iter().flat_map(|s| s.v.iter().copied()));
    let d = max_abs(
        a.subs
            .iter()
            .zip(&b.subs)
            .flat_map(|(x, y)| x.v.iter().zip(&y.v).map(|(p, q)| p - q)),
    );
    assert!(peak > 1.0, "the impact drives the blocks: {peak}");
    d / peak
}

/// The background study held still.
fn paused() -> StudyControl {
    StudyControl {
        paused: true,
        idle_s: 0.0,
        ..StudyControl::default()
    }
}

/// Waits until the background study has stored `n` configurations, then pauses it.
fn store_then_pause(worker: &mut Worker, events: &mut Vec<Event>, n: usize) {
    collect(
        worker,
        events,
        |e| matches!(e, Event::Stored(c) if c.stored >= n),
    );
    worker.set_study(paused());
}

/// Starts a session with the background study running at once when idle; returns the worker,
/// its parameters and the events of the first (cold) solve.
fn session(spawn: Spawn, idle_s: f64) -> (Worker, Params, Vec<Event>) {
    session_in_lanes(spawn, idle_s, StudyControl::default().lanes)
}

/// [`session`] with the background study solving `lanes` values at once.
fn session_in_lanes(spawn: Spawn, idle_s: f64, lanes: usize) -> (Worker, Params, Vec<Event>) {
    let (problem, settings) = two_blocks();
    let mut worker = spawn(problem.clone(), settings);
    worker.set_display_step(problem.time.steps / 2);
    worker.set_study(StudyControl {
        paused: false,
        idle_s,
        lanes,
        ..StudyControl::default()
    });
    let params = Params::of(&problem, &settings);
    let (_, events) = solve_until_report(&mut worker, &params);
    (worker, params, events)
}

#[test]
fn the_background_study_stores_the_grid_nearest_first_equal_to_cold_solves() {
    let (problem, settings) = two_blocks();
    let tol = settings.tol;
    let (mut worker, params, mut events) = session_in_lanes(threaded, 0.0, 1);
    let grid = lopin_explorer::study::grid();
    let f0 = params.friction.expect("contact");
    collect(
        &mut worker,
        &mut events,
        |e| matches!(e, Event::Stored(c) if c.stored == grid.len()),
    );
    let all = stored(&events);
    // the user's converged solve is stored first, then the grid nearest-first from it
    assert!((all[0].value - f0).abs() < 1e-12 && !all[0].background);
    let order: Vec<f64> = all[1..].iter().map(|c| c.value).collect();
    eprintln!("background order: {order:?}");
    assert_eq!(order.len(), grid.len() - 1);
    for pair in order.windows(2) {
        assert!(
            (pair[0] - f0).abs() <= (pair[1] - f0).abs() + 1e-9,
            "nearest first: {order:?}"
        );
    }
    // each background solve started from a stored neighbour one grid step away
    for c in &all[1..] {
        let start = c.start.expect("warm");
        assert!(
            (start - c.value).abs() < 0.05 + 1e-9,
            "{} started from {start}",
            c.value
        );
        assert!(c.background && c.iterations > 0);
    }
    let last = all.last().expect("stored");
    assert!(last.store_bytes > 0 && last.picture.bytes() > 0);
    eprintln!(
        "{} configurations: states {} bytes, one picture {} bytes",
        last.stored,
        last.store_bytes,
        last.picture.bytes()
    );

    // a background configuration's picture and quantities equal a cold solve's
    let value = 0.6;
    let c = all
        .iter()
        .find(|c| (c.value - value).abs() < 1e-9)
        .expect("0.6 stored");
    let (solver, sol) = cold(&problem, settings, value);
    let step = c.picture.step;
    let cold_fields = fields::compute(&solver, &sol, step, 0, false);
    let rel = velocity_gap(&c.picture.fields(0, false), &cold_fields);
    eprintln!("f = {value}: stored picture vs cold at step {step}: {rel:.2e} of the peak");
    assert!(rel < 30.0 * tol, "{rel:.3e} > 30 tol");
    let q = Quantities::of(&solver, &sol);
    let peak = (c.quantities.peak_normal_force - q.peak_normal_force).abs() / q.peak_normal_force;
    assert!(peak < 30.0 * tol, "peak normal force differs by {peak:.2e}");

    // its stored state and solution: asked for again, it is shown without solving, and its
    // fields at other steps (replayed from the stored ŝ) equal the cold solve's
    let mut at = params.clone();
    at.friction = Some(value);
    let g = worker.solve(at);
    let mut again = Vec::new();
    collect(
        &mut worker,
        &mut again,
        |e| matches!(e, Event::Finished(r) if r.generation == g),
    );
    let r = report(&again, g);
    assert!(r.from_store && r.converged && r.iterations == 0, "{r:?}");
    assert!(
        !again
            .iter()
            .any(|e| matches!(e, Event::Progress { generation, .. } if *generation == g)),
        "no iteration was run"
    );
    for m in [problem.time.steps / 4, problem.time.steps] {
        worker.request_fields(m);
        let mut got = Vec::new();
        collect(
            &mut worker,
            &mut got,
            |e| matches!(e, Event::Fields(f) if !f.live && f.step == m),
        );
        let Some(Event::Fields(f)) = got.last() else {
            unreachable!("collect stops on fields")
        };
        assert_eq!(f.generation, g);
        let rel = velocity_gap(f, &fields::compute(&solver, &sol, m, 0, false));
        assert!(rel < 30.0 * tol, "step {m}: {rel:.3e} > 30 tol");
    }
}

#[test]
fn lanes_store_the_grid_nearest_first_equal_to_cold_solves_and_to_one_at_a_time() {
    let (problem, settings) = two_blocks();
    let tol = settings.tol;
    let grid = lopin_explorer::study::grid();
    let whole = |lanes: usize| {
        let (mut worker, params, mut events) = session_in_lanes(threaded, 0.0, lanes);
        collect(
            &mut worker,
            &mut events,
            |e| matches!(e, Event::Stored(c) if c.stored == grid.len()),
        );
        (params, events)
    };
    let (params, one) = whole(1);
    let lanes = 4;
    let (_, events) = whole(lanes);
    let f0 = params.friction.expect("contact");
    let (one, four) = (stored(&one), stored(&events));
    let iterations = |all: &[Arc<StoredConfig>]| all.iter().map(|c| c.iterations).sum::<usize>();
    eprintln!(
        "background study of {} values: {} iterations one at a time, {} in {lanes} lanes",
        grid.len() - 1,
        iterations(&one[1..]),
        iterations(&four[1..])
    );
    // the lanes began at once with the values nearest the user's, and never solved more
    let busy: Vec<&Vec<f64>> = events
        .iter()
        .filter_map(|e| match e {
            Event::Background(v) => Some(v),
            _ => None,
        })
        .collect();
    assert!(busy.iter().all(|v| v.len() <= lanes));
    let mut first = busy[0].clone();
    first.sort_by(f64::total_cmp);
    let nearest: Vec<f64> = [-2.0, -1.0, 1.0, 2.0].map(|k| f0 + 0.05 * k).to_vec();
    for (a, b) in first.iter().zip(&nearest) {
        assert!((a - b).abs() < 1e-9, "{first:?} against {nearest:?}");
    }
    for c in &four[1..] {
        assert!(c.background && c.iterations > 0);
        let start = c.start.expect("warm");
        assert!(
            (start - c.value).abs() < lanes as f64 * 0.05 + 1e-9,
            "{} started from {start}",
            c.value
        );
        // the same configuration as one at a time, both within 30·tol of a cold solve
        let alone = one
            .iter()
            .find(|o| (o.value - c.value).abs() < 1e-9)
            .expect("stored one at a time too");
        let (solver, sol) = cold(&problem, settings, c.value);
        let cold_fields = fields::compute(&solver, &sol, c.picture.step, 0, false);
        let rel = velocity_gap(&c.picture.fields(0, false), &cold_fields);
        let rel_alone = velocity_gap(&alone.picture.fields(0, false), &cold_fields);
        assert!(rel < 30.0 * tol, "f = {}: {rel:.3e} > 30 tol", c.value);
        assert!(rel_alone < 30.0 * tol, "f = {}: {rel_alone:.3e}", c.value);
        let q = Quantities::of(&solver, &sol);
        let peak =
            (c.quantities.peak_normal_force - q.peak_normal_force).abs() / q.peak_normal_force;
        assert!(peak < 30.0 * tol, "f = {}: peak force {peak:.2e}", c.value);
    }
}

#[test]
fn a_stored_value_is_shown_without_solving() {
    stored_value_shown_without_solving(threaded);
}

#[test]
fn inline_a_stored_value_is_shown_without_solving() {
    stored_value_shown_without_solving(inline);
}

fn stored_value_shown_without_solving(spawn: Spawn) {
    let (mut worker, mut params, mut events) = session(spawn, 0.0);
    store_then_pause(&mut worker, &mut events, 3);
    let values: Vec<f64> = stored(&events).iter().map(|c| c.value).collect();
    params.friction = Some(values[2]);
    let (g, after) = solve_until_report(&mut worker, &params);
    let r = report(&after, g);
    assert!(
        r.from_store && r.converged && r.warm && r.iterations == 0,
        "{r:?}"
    );
    assert_eq!(r.start, Some(values[2]));
    assert!(
        !after
            .iter()
            .any(|e| matches!(e, Event::Progress { generation, .. } if *generation == g)),
        "no iteration was run"
    );
    // its converged fields came before the report
    assert!(after
        .iter()
        .any(|e| matches!(e, Event::Fields(f) if !f.live && f.generation == g)));
}

#[test]
fn a_value_between_stored_ones_starts_from_their_interpolation_in_fewer_iterations() {
    let (problem, settings) = two_blocks();
    let (mut worker, mut params, mut events) = session_in_lanes(inline, 0.0, 1);
    // 0.30 (the scene's), then 0.25, 0.35, 0.20, 0.40 …
    store_then_pause(&mut worker, &mut events, 5);
    let mut solve = |target: f64| {
        params.friction = Some(target);
        let (g, mut after) = solve_until_report(&mut worker, &params);
        let r = report(&after, g);
        assert!(r.converged && r.warm && !r.from_store, "{r:?}");
        // the converged value is stored too
        collect(
            &mut worker,
            &mut after,
            |e| matches!(e, Event::Stored(c) if (c.value - target).abs() < 1e-12),
        );
        r
    };
    // 0.27 lies between the stored 0.25 and 0.30 (the user's newest state, 0.30, is farther
    // than 0.25): the two states interpolated, 0.4 of the way from 0.25
    let target = 0.27;
    let r = solve(target);
    assert_eq!(r.between, Some((0.25, 0.30)), "{r:?}");
    assert!((r.start.expect("warm") - 0.25).abs() < 1e-12, "{r:?}");
    let (_, c) = cold(&problem, settings, target);
    let (_, near) = cold(&problem, settings, 0.25);
    let from_nearest = solve_at(&problem, settings, target, Some(&near.state))
        .1
        .iterations;
    eprintln!(
        "f = {target}: {} iterations from the interpolation of 0.25 and 0.30, {from_nearest} \
         from 0.25 alone, {} cold",
        r.iterations, c.iterations
    );
    assert!(
        r.iterations < from_nearest && from_nearest < c.iterations,
        "{} vs {from_nearest} vs {}",
        r.iterations,
        c.iterations
    );
    // 0.415 is above every stored value: from the nearest, 0.40, alone
    let target = 0.415;
    let r = solve(target);
    assert_eq!(r.between, None, "{r:?}");
    assert!((r.start.expect("warm") - 0.4).abs() < 1e-12, "{r:?}");
    let (_, c) = cold(&problem, settings, target);
    eprintln!(
        "f = {target}: {} iterations from the stored 0.40, {} cold",
        r.iterations, c.iterations
    );
    assert!(
        r.iterations < c.iterations,
        "{} vs {}",
        r.iterations,
        c.iterations
    );
}

#[test]
fn a_user_change_cancels_the_background_configuration() {
    user_change_cancels_background(threaded);
}

#[test]
fn inline_a_user_change_cancels_the_background_configuration() {
    user_change_cancels_background(inline);
}

fn user_change_cancels_background(spawn: Spawn) {
    let (problem, mut settings) = two_blocks();
    // a tight tolerance: a background configuration takes many iterations
    settings.tol = 1e-6;
    let mut worker = spawn(problem.clone(), settings);
    worker.set_study(StudyControl {
        paused: false,
        idle_s: 0.0,
        ..StudyControl::default()
    });
    let mut params = Params::of(&problem, &settings);
    let g0 = worker.solve(params.clone());
    let mut events = Vec::new();
    collect(
        &mut worker,
        &mut events,
        |e| matches!(e, Event::Background(v) if !v.is_empty()),
    );
    assert!(report(&events, g0).converged);
    let Some(Event::Background(values)) = events.last().cloned() else {
        unreachable!("collect stops there")
    };
    // the user moves the slider to a value not stored: the background solve stops
    params.friction = Some(0.123);
    let g1 = worker.solve(params.clone());
    let mut after = Vec::new();
    collect(
        &mut worker,
        &mut after,
        |e| matches!(e, Event::Finished(r) if r.generation == g1),
    );
    let stop = after
        .iter()
        .position(|e| matches!(e, Event::Background(v) if v.is_empty()))
        .expect("the background solves stopped");
    let first_user = after
        .iter()
        .position(|e| matches!(e, Event::Progress { generation, .. } if *generation == g1))
        .expect("the user's solve iterated");
    assert!(
        stop < first_user,
        "cancelled before the user's first iteration"
    );
    assert!(
        !stored(&after)
            .iter()
            .any(|c| values.iter().any(|v| (c.value - v).abs() < 1e-12)),
        "the cancelled background values {values:?} were not stored"
    );
    let r = report(&after, g1);
    assert!(r.converged && r.warm && !r.cancelled, "{r:?}");
    assert!(r.iterations > 0);
}

#[test]
fn the_difference_of_two_stored_pictures_matches_the_difference_of_two_solutions() {
    let (problem, settings) = two_blocks();
    let tol = settings.tol;
    let geo = SceneGeometry::of(&problem);
    let (mut worker, _, mut events) = session(inline, 0.0);
    collect(
        &mut worker,
        &mut events,
        |e| matches!(e, Event::Stored(c) if (c.value - 0.2).abs() < 1e-9),
    );
    let all = stored(&events);
    let pick = |v: f64| {
        all.iter()
            .find(|c| (c.value - v).abs() < 1e-9)
            .expect("stored")
            .clone()
    };
    let (a, b) = (pick(0.3), pick(0.2));
    assert_eq!(a.picture.step, b.picture.step);
    let step = a.picture.step;
    for q in [Quantity::VonMises, Quantity::Velocity, Quantity::Pressure] {
        let values = |c: &StoredConfig| {
            let contact = c.picture.contact();
            nodal_values(&geo, &c.picture.fields(0, false), Some(&contact), q)
        };
        let (va, vb) = (values(&a), values(&b));
        // a value against itself: zero wherever it has a value
        let zero = difference(&va, &va);
        assert!(zero.iter().flatten().flatten().all(|&d| d == 0.0));
        assert_eq!(
            zero.iter().flatten().flatten().count(),
            va.iter().flatten().flatten().count()
        );
        // against another value: the difference of the two cold solutions
        let cold_values = |f: f64| {
            let (solver, sol) = cold(&problem, settings, f);
            let fl = fields::compute(&solver, &sol, step, 0, false);
            let contact = post::contact(&solver, &sol);
            nodal_values(&geo, &fl, Some(&contact), q)
        };
        let shown = difference(&vb, &va);
        let exact = difference(&cold_values(0.2), &cold_values(0.3));
        let scale = max_abs(vb.iter().flatten().flatten().copied());
        let gap = max_abs(
            shown
                .iter()
                .flatten()
                .zip(exact.iter().flatten())
                .map(|(s, e)| s.unwrap_or(0.0) - e.unwrap_or(0.0)),
        );
        let size = max_abs(exact.iter().flatten().flatten().copied());
        eprintln!(
            "{q:?}: difference up to {size:.3e}, shown vs cold {:.2e} of the field's peak",
            gap / scale
        );
        assert!(size > 0.0, "friction changes {q:?}");
        assert!(gap / scale < 30.0 * tol, "{q:?}: {:.3e}", gap / scale);
    }
}

#[test]
fn the_pinned_configuration_is_pictured_at_a_new_step_while_paused() {
    pinned_pictured_at_a_new_step(threaded);
}

#[test]
fn inline_the_pinned_configuration_is_pictured_at_a_new_step_while_paused() {
    pinned_pictured_at_a_new_step(inline);
}

/// With the study paused, a new displayed step gets no picture of a stored configuration until
/// it is pinned for comparison; then its picture at that step comes at once, equal to a cold
/// solve's fields there.
fn pinned_pictured_at_a_new_step(spawn: Spawn) {
    let (problem, settings) = two_blocks();
    let mut worker = spawn(problem.clone(), settings);
    let first = problem.time.steps / 2;
    worker.set_display_step(first);
    worker.set_study(paused());
    let params = Params::of(&problem, &settings);
    let f0 = params.friction.expect("contact");
    worker.solve(params);
    let mut events = Vec::new();
    collect(&mut worker, &mut events, |e| matches!(e, Event::Stored(_)));
    assert_eq!(stored(&events)[0].picture.step, first);
    // paused and nothing pinned: nothing more comes
    let next = 10;
    worker.set_display_step(next);
    worker.set_study(StudyControl {
        idle_s: 0.5,
        ..paused()
    });
    let quiet = worker.wait(Duration::from_millis(800));
    assert!(
        !matches!(quiet, Some(Event::Stored(_))),
        "a picture while paused: {quiet:?}"
    );
    // pinned: its picture at the displayed step
    worker.set_study(StudyControl {
        pinned: Some(f0),
        ..paused()
    });
    let mut after = Vec::new();
    collect(&mut worker, &mut after, |e| matches!(e, Event::Stored(_)));
    let c = stored(&after).pop().expect("a picture");
    assert!(
        (c.value - f0).abs() < 1e-12 && c.picture.step == next,
        "{c:?}"
    );
    let (solver, sol) = cold(&problem, settings, f0);
    let rel = velocity_gap(
        &c.picture.fields(0, false),
        &fields::compute(&solver, &sol, next, 0, false),
    );
    assert!(rel < 30.0 * settings.tol, "{rel:.3e} > 30 tol");
    // pictured once: nothing more comes
    let quiet = worker.wait(Duration::from_millis(300));
    assert!(
        !matches!(quiet, Some(Event::Stored(_))),
        "pictured again: {quiet:?}"
    );
}
