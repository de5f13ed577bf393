//! `post::history` (every step replayed once per substructure, what exports read) gives the same
//! fields as `post::fields_at` at each step, and its velocity history starts at the initial
//! velocity field.

use lopin_core::{post, scene, Settings, Solver};

#[test]
fn history_equals_fields_at_every_checked_step() {
    let spec = scene::load("two-blocks").expect("scene");
    let problem = scene::problem_of(&spec, "two-blocks").expect("builds");
    let settings = Settings::for_problem(&problem, &spec.solver);
    let mut solver = Solver::new(problem, settings).expect("factorizes");
    let sol = solver.solve(None).expect("solves");
    let h = post::history(&solver, &sol);
    let p = solver.problem();
    assert_eq!(h.len(), p.subs.len());
    for steps in &h {
        assert_eq!(steps.len(), p.time.steps + 1);
    }
    for m in [0, 1, p.time.steps / 2, p.time.steps] {
        let f = post::fields_at(&solver, &sol, m);
        for (i, fi) in f.iter().enumerate() {
            // same replay, same arithmetic: identical to the last bit
            assert_eq!(h[i][m], *fi, "substructure {i}, step {m}");
        }
    }
    for (i, s) in p.subs.iter().enumerate() {
        assert_eq!(h[i][0].v, s.initial_velocity_field());
        assert!(h[i][0].u.iter().all(|&x| x == 0.0));
    }
    let moved = h
        .iter()
        .flatten()
        .flat_map(|f| &f.u)
        .any(|&x| x.abs() > 1e-9);
    assert!(moved, "the run displaces something");
}
