//! Substructures that share a factorization march in blocks (`core/src/solver/blocks.rs`): on
//! `granular-small --refine 2` (64 cells of 6³ hexahedra, 26 distinct factorizations, one-step
//! windows) the blocked replay of the converged fields gives every substructure's velocities at
//! every step as a replay of each substructure alone (single solves) does, to 1e-12 of the
//! largest velocity; the energy balance
//! from the blocked replay equals the one summed from lone replays to 1e-12 of the input work;
//! and the end energies the solve keeps from its linear stages (marched in the same blocks) are
//! the blocked replay's bit for bit.

use lopin_core::post;
use lopin_core::{scene, Settings, Solver};

#[test]
fn blocks_replay_what_lone_substructures_replay_and_keep_the_solves_end_energies() {
    let mut spec = scene::load("granular-small").expect("scene");
    spec.refine(2).expect("refine");
    let problem = scene::problem_of(&spec, "granular-small").expect("builds");
    let mut settings = Settings::for_problem(&problem, &spec.solver);
    settings.window = Some(1);
    let mut solver = Solver::new(problem, settings).expect("solver");
    let classes = solver.classes().count();
    let subs = solver.problem().subs.len();
    assert!(classes < subs, "{classes} factorizations for {subs} cells");
    let sol = solver.solve(None).expect("solve");
    assert!(sol.converged);
    let steps = solver.problem().time.steps;

    // every substructure's velocities: blocked replay against each alone
    let blocked = post::replay_blocks(
        &solver,
        &sol,
        steps,
        |_| Vec::new(),
        |v: &mut Vec<Vec<f64>>, _, st, _, _| v.push(st.v.clone()),
    );
    assert_eq!(blocked.len(), subs);
    let (mut worst, mut peak) = (0.0f64, 0.0f64);
    for (i, history) in &blocked {
        assert_eq!(history.len(), steps + 1);
        let mut m = 0;
        post::replay(&solver, &sol, *i, steps, &mut |_, st, _, _| {
            for (a, b) in st.v.iter().zip(&history[m]) {
                worst = worst.max((a - b).abs());
                peak = peak.max(a.abs());
            }
            m += 1;
        });
    }
    eprintln!("{subs} cells, {classes} factorizations: blocked against lone replays up to {worst:.2e} m/s, peak velocity {peak:.3e} m/s");
    assert!(peak > 0.1, "the cells move: {peak}");
    assert!(worst < 1e-12 * peak, "{worst:e} against {peak:e}");

    // the energy balance from lone replays (kinetic ½ vᵀMv, strain from the carried K u)
    let e = post::energy(&solver, &sol);
    let (mut kinetic, mut strain) = (0.0, 0.0);
    for (i, sub) in solver.problem().subs.iter().enumerate() {
        post::replay(&solver, &sol, i, steps, &mut |m, st, _, _| {
            if m == steps {
                kinetic += 0.5
                    * st.v
                        .iter()
                        .zip(&sub.mass)
                        .map(|(v, mm)| mm * v * v)
                        .sum::<f64>();
                strain += 0.5 * st.u.iter().zip(&st.ku).map(|(u, k)| u * k).sum::<f64>();
            }
        });
    }
    let scale = e.input_work[steps];
    eprintln!(
        "end energies: kinetic {:.6e} (lone {kinetic:.6e}), strain {:.6e} (lone {strain:.6e}), input {scale:.6e}",
        e.kinetic[steps], e.strain[steps]
    );
    assert!(scale > 0.0);
    assert!((e.kinetic[steps] - kinetic).abs() < 1e-12 * scale);
    assert!((e.strain[steps] - strain).abs() < 1e-12 * scale);

    // the solve's own end energies are those of the blocked replay
    let end = sol
        .end
        .expect("a single-scale solve keeps its end energies");
    assert_eq!(
        (end.kinetic, end.strain, end.input_work),
        (e.kinetic[steps], e.strain[steps], e.input_work[steps])
    );
}
