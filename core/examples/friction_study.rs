//! A friction study in a few lines: `two-blocks` solved cold at f = 0.3, then warm at each
//! friction coefficient from 0 to 0.6, each solve restarting from the previous converged
//! interface state (METHOD §8), with the peak normal contact force and the largest slip of each.
//!
//! `cargo run --release -p lopin-core --example friction_study`

use lopin_core::window_choice::WindowRequest;
use lopin_core::{post, scene, Parameter, Solver};

fn main() -> lopin_core::Result<()> {
    // every solve over the whole interval, each restarting from the previous one's
    let whole = scene::Overrides {
        solver: scene::spec::SolverSpec {
            window: Some(WindowRequest::Whole),
            ..Default::default()
        },
        ..Default::default()
    };
    let opened = scene::open("two-blocks", &whole)?;
    let mut solver = Solver::new(opened.problem, opened.settings)?;
    let mut state = solver.solve(None)?.state;
    println!("    f  iterations  peak normal force (N)  max slip (m)");
    for i in 0..=6 {
        let f = 0.1 * i as f64;
        solver.set_parameter(Parameter::Friction, f)?;
        let sol = solver.solve(Some(&state))?;
        let summary = post::summary(&solver, &sol);
        println!(
            "{f:5.2}  {:10}  {:21.4e}  {:12.4e}",
            sol.iterations, summary.peak_normal_force, summary.max_slip
        );
        state = sol.state;
    }
    Ok(())
}
