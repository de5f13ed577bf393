//! Distributed runs (`core/src/distributed/distribution.rs`, `core/src/distributed/ranks.rs`) on ranks that
//! are threads of this process (`core/src/distributed/thread_ranks.rs`): the same scene solved on 1, 2, 3
//! and 4 ranks takes the same number of iterations, reaches the same η and gives the same
//! interface fields (F, W) and ŝ, bit for bit, as the solver on one machine: on
//! `two-blocks --split 2` (the whole interval and one-step windows), on `granular-small`
//! single- and two-scale, on `two-blocks-nonmatching` with A in four substructures (mortar
//! interfaces across ranks), and over a 3-value friction sweep with warm starts. The energy
//! balance and the summary (contact histories summed over the ranks) equal the one-machine ones
//! too. While it iterates no rank stores the whole s and ŝ (memory falls with the ranks); the
//! solution gathered on rank 0 is compared. The same comparison runs under `mpirun` in
//! `app/tests/mpi.rs`.

use std::sync::Arc;

use lopin_core::distributed::ranks::Ranks;
use lopin_core::distributed::thread_ranks;
use lopin_core::post;
use lopin_core::scene::{self, SceneSpec};
use lopin_core::{Parameter, Settings, Solution, Solver};

fn spec(name: &str, split: usize) -> SceneSpec {
    let mut spec = scene::registry::builtin(name).expect("scene");
    if split > 1 {
        spec.split(split).expect("split");
    }
    spec
}

/// Solves `spec` on `ranks` thread ranks (None: the plain solver) for every value of the
/// friction in `friction` (warm-starting each from the previous), and returns rank 0's
/// solutions with the energy of the last one.
fn solve_on(
    spec: &SceneSpec,
    ranks: Option<usize>,
    tweak: &(dyn Fn(&mut Settings) + Sync),
    friction: &[f64],
) -> (Vec<Solution>, f64, post::Summary) {
    let problem = scene::problem_of(spec, &spec.name).expect("builds");
    let mut settings = Settings::for_problem(&problem, &spec.solver);
    tweak(&mut settings);
    // what one rank stores of s and ŝ, in doubles, against the whole solution
    let stored = |s: &Solution| {
        let hats: usize = s.hats.iter().flatten().map(|h| h.f.len() + h.w.len()).sum();
        s.state.size() + hats
    };
    let sweep = |mut solver: Solver| {
        let mut out: Vec<Solution> = Vec::new();
        let mut kept = Vec::new();
        for &f in friction {
            solver
                .set_parameter(Parameter::Friction, f)
                .expect("friction");
            let start = out.last().map(|s| s.state.clone());
            let mut sol = solver.solve(start.as_ref()).expect("solve");
            kept.push(stored(&sol));
            solver.gather_to_root(&mut sol);
            out.push(sol);
        }
        let last = out.last().expect("a value");
        let e = post::energy(&solver, last);
        let n = e.kinetic.len() - 1;
        let summary = post::summary(&solver, last);
        (
            out,
            e.kinetic[n] + e.strain[n] - e.input_work[n],
            summary,
            kept,
        )
    };
    match ranks {
        None => {
            let (out, e, summary, _) = sweep(Solver::new(problem, settings).expect("solver"));
            (out, e, summary)
        }
        Some(p) => {
            let mut all = thread_ranks::run(p, |r| {
                let r: Arc<dyn Ranks> = r;
                sweep(Solver::new_distributed(problem.clone(), settings, r).expect("solver"))
            });
            let whole = stored(&all[0].0[0]);
            let first = all.remove(0);
            for (r, other) in all.iter().enumerate() {
                assert_eq!(other.0.len(), first.0.len());
                for (a, b) in other.0.iter().zip(&first.0) {
                    assert_eq!(a.iterations, b.iterations);
                }
                // every rank has the same summary (contact histories summed over the ranks)
                assert_eq!(
                    format!("{:?}", other.2),
                    format!("{:?}", first.2),
                    "rank {} disagrees on the summary",
                    r + 1
                );
            }
            // no rank stores the whole solution while it iterates: memory falls with P
            if p > 1 {
                for (r, kept) in std::iter::once(&first.3)
                    .chain(all.iter().map(|x| &x.3))
                    .enumerate()
                {
                    for &k in kept {
                        assert!(
                            k < whole,
                            "rank {r} of {p} stores {k} of the {whole} values of s and ŝ"
                        );
                    }
                }
                let largest = std::iter::once(&first.3)
                    .chain(all.iter().map(|x| &x.3))
                    .flatten()
                    .max()
                    .copied()
                    .unwrap_or(0);
                println!(
                    "{p} ranks: the largest rank stores {:.0} % of s and ŝ",
                    100.0 * largest as f64 / whole as f64
                );
            }
            (first.0, first.1, first.2)
        }
    }
}

/// Where two solutions differ in any bit of s or ŝ (None: nowhere).
fn first_difference(a: &Solution, b: &Solution) -> Option<String> {
    let same = |x: &[f64], y: &[f64]| {
        x.len() == y.len() && x.iter().zip(y).all(|(p, q)| p.to_bits() == q.to_bits())
    };
    for (i, (x, y)) in a.state.subs.iter().zip(&b.state.subs).enumerate() {
        if !same(&x.f, &y.f) || !same(&x.w, &y.w) {
            return Some(format!("s of substructure {i}"));
        }
    }
    for (i, (x, y)) in a.hats.iter().zip(&b.hats).enumerate() {
        for (j, (p, q)) in x.iter().zip(y).enumerate() {
            if !same(&p.f, &q.f) || !same(&p.w, &q.w) {
                let k =
                    p.f.iter()
                        .zip(&q.f)
                        .position(|(u, v)| u.to_bits() != v.to_bits());
                let v = k.map(|k| (p.f[k], q.f[k], p.f.len(), p.len));
                return Some(format!("ŝ of interface {i} side {j} at entry {k:?}: {v:?}"));
            }
        }
    }
    None
}

fn same_as_one_machine(
    label: &str,
    spec: &SceneSpec,
    tweak: &(dyn Fn(&mut Settings) + Sync),
    friction: &[f64],
) {
    same_as_on_ranks(label, spec, tweak, friction, 4);
}

/// [`same_as_one_machine`] on 1 to `max_ranks` ranks.
fn same_as_on_ranks(
    label: &str,
    spec: &SceneSpec,
    tweak: &(dyn Fn(&mut Settings) + Sync),
    friction: &[f64],
    max_ranks: usize,
) {
    let (serial, energy, summary) = solve_on(spec, None, tweak, friction);
    for p in 1..=max_ranks {
        let (dist, e, sum) = solve_on(spec, Some(p), tweak, friction);
        assert_eq!(
            format!("{sum:?}"),
            format!("{summary:?}"),
            "{label}, {p} ranks: the summary"
        );
        for (v, (a, b)) in dist.iter().zip(&serial).enumerate() {
            assert!(a.converged && b.converged, "{label}, {p} ranks, value {v}");
            assert_eq!(a.iterations, b.iterations, "{label}, {p} ranks, value {v}");
            assert_eq!(a.eta.to_bits(), b.eta.to_bits(), "{label}, {p} ranks");
            assert_eq!(a.eta_history, b.eta_history, "{label}, {p} ranks");
            assert_eq!(first_difference(a, b), None, "{label}, {p} ranks");
        }
        assert_eq!(e.to_bits(), energy.to_bits(), "{label}, {p} ranks: energy");
        println!(
            "{label}: {p} ranks, iterations {:?}, bit-identical",
            dist.iter().map(|s| s.iterations).collect::<Vec<_>>()
        );
    }
}

#[test]
fn two_blocks_split_in_two_is_the_same_on_one_to_four_ranks() {
    let spec = spec("two-blocks", 2);
    same_as_one_machine(
        "two-blocks --split 2, whole interval",
        &spec,
        &|s| s.window = None,
        &[0.3],
    );
    same_as_one_machine(
        "two-blocks --split 2, one-step windows",
        &spec,
        &|s| s.window = Some(1),
        &[0.3],
    );
}

#[test]
fn granular_small_single_and_two_scale_is_the_same_on_one_to_four_ranks() {
    let spec = spec("granular-small", 1);
    same_as_one_machine(
        "granular-small",
        &spec,
        &|s| {
            s.two_scale = false;
            s.window = Some(1);
        },
        &[0.3],
    );
    same_as_one_machine(
        "granular-small two-scale",
        &spec,
        &|s| s.two_scale = true,
        &[0.3],
    );
}

/// A non-matching contact (A cut in 2 × 2 substructures on B's other mesh, B one
/// substructure as heavy as A's four): four mortar interfaces whose sides lie on different
/// ranks, on one to three ranks.
#[test]
fn a_non_matching_contact_is_the_same_on_one_to_three_ranks() {
    let mut spec = spec("two-blocks-nonmatching", 1);
    spec.bodies[0].split = [2, 2, 1];
    same_as_on_ranks(
        "two-blocks-nonmatching, A in 4",
        &spec,
        &|s| s.window = Some(1),
        &[0.3],
        3,
    );
}

#[test]
fn a_three_value_sweep_is_the_same_on_one_to_four_ranks() {
    let spec = spec("two-blocks", 2);
    same_as_one_machine("sweep on f", &spec, &|_| {}, &[0.1, 0.3, 0.5]);
}

#[test]
fn anderson_and_too_many_ranks_are_refused_on_every_rank() {
    let spec = spec("two-blocks", 1);
    let problem = scene::problem_of(&spec, &spec.name).expect("builds");
    let mut settings = Settings::for_problem(&problem, &spec.solver);
    // every rank refuses, with the same reason
    let refused = |ranks: usize, settings: Settings, reason: &str| {
        let errors = thread_ranks::run(ranks, |r| {
            let r: Arc<dyn Ranks> = r;
            Solver::new_distributed(problem.clone(), settings, r)
                .expect_err(reason)
                .to_string()
        });
        for e in errors {
            assert!(e.contains(reason), "{e}");
        }
    };
    refused(
        problem.subs.len() + 1,
        settings,
        "at most one rank per substructure",
    );
    settings.anderson = 3;
    refused(2, settings, "anderson");
}
