//! Helpers for Lopin's cross-crate validation tests: 1D bars written as 3D scenes (one hexahedron
//! across, ν = 0, so the 3D discretization is exactly the 1D one of METHOD §12), an independent
//! monolithic 1D solver of the same discretization ([`mono1d`]), and small solve/compare helpers.

pub mod bar1d;
pub mod mono1d;

use lopin_core::post;
use lopin_core::scene::{self, SceneSpec};
use lopin_core::{Settings, Solution, Solver};

/// Builds and solves a scene, with `tweak` applied to the default settings.
pub fn solve(spec: &SceneSpec, tweak: impl FnOnce(&mut Settings)) -> (Solver, Solution) {
    let problem = scene::build::build(spec, &spec.name).expect("scene builds");
    let mut settings = Settings::for_problem(&problem, &spec.solver);
    tweak(&mut settings);
    let mut solver = Solver::new(problem, settings).expect("factorization");
    let sol = solver.solve(None).expect("solve");
    (solver, sol)
}

/// Nodal velocities of every substructure at every step: `[m][sub][dof]`.
pub fn velocity_history(solver: &Solver, sol: &Solution) -> Vec<Vec<Vec<f64>>> {
    let p = solver.problem();
    let n = p.time.steps;
    let mut out = vec![vec![Vec::new(); p.subs.len()]; n + 1];
    for i in 0..p.subs.len() {
        post::replay(solver, sol, i, n, &mut |m, st, _, _| {
            out[m][i] = st.v.clone()
        });
    }
    out
}

/// max over space-time of |a − b| / max |b| for two velocity histories of the same problem.
pub fn rel_diff(a: &[Vec<Vec<f64>>], b: &[Vec<Vec<f64>>]) -> f64 {
    let mut diff: f64 = 0.0;
    let mut scale: f64 = 0.0;
    for (am, bm) in a.iter().zip(b) {
        for (x, y) in am.iter().flatten().zip(bm.iter().flatten()) {
            diff = diff.max((x - y).abs());
            scale = scale.max(y.abs());
        }
    }
    diff / scale
}
