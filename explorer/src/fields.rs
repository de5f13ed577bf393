//! Volume fields of one time step, computed only for the step on screen (METHOD §6 "at
//! convergence": one more linear stage driven by ŝ, replayed up to that step): nodal
//! displacement and velocity, and von Mises stress averaged from element centres to nodes.
//! Also the history of one node for the probe.

use lopin_core::elements::hex8;
use lopin_core::mesh::{Element, Mesh};
use lopin_core::post;
use lopin_core::{Solution, Solver};

/// Fields of one substructure at one step.
#[derive(Debug, Clone, PartialEq)]
pub struct SubStepFields {
    /// Nodal displacements (node-major), m.
    pub u: Vec<f64>,
    /// Nodal velocities (node-major), m/s.
    pub v: Vec<f64>,
    /// Von Mises stress averaged to nodes, Pa.
    pub von_mises: Vec<f64>,
}

/// Fields of every substructure at one step.
#[derive(Debug, Clone, PartialEq)]
pub struct StepFields {
    /// Generation of the solution (or live iterate) they come from.
    pub generation: u64,
    /// Time step.
    pub step: usize,
    /// Whether they come from an iterate still converging.
    pub live: bool,
    /// One per substructure.
    pub subs: Vec<SubStepFields>,
}

/// Fields of `sol` at `step`.
pub fn compute(
    solver: &Solver,
    sol: &Solution,
    step: usize,
    generation: u64,
    live: bool,
) -> StepFields {
    let step = step.min(solver.problem().time.steps);
    let raw = post::fields_at(solver, sol, step);
    let subs = raw
        .into_iter()
        .enumerate()
        .map(|(i, f)| {
            let vm = post::von_mises(solver, i, &f.u);
            let von_mises = element_to_nodes(&solver.problem().subs[i].mesh, &vm);
            SubStepFields {
                u: f.u,
                v: f.v,
                von_mises,
            }
        })
        .collect();
    StepFields {
        generation,
        step,
        live,
        subs,
    }
}

/// Averages element values to the nodes (each node: mean over the elements that hold it).
pub fn element_to_nodes(mesh: &Mesh, values: &[f64]) -> Vec<f64> {
    let mut sum = vec![0.0; mesh.nodes.len()];
    let mut count = vec![0u32; mesh.nodes.len()];
    for (e, &v) in mesh.elements.iter().zip(values) {
        for &n in e.nodes() {
            sum[n] += v;
            count[n] += 1;
        }
    }
    sum.iter()
        .zip(&count)
        .map(|(s, &c)| if c > 0 { s / c as f64 } else { 0.0 })
        .collect()
}

/// |v| and node-averaged von Mises stress of node `node` of substructure `sub`, at every step.
pub fn probe(solver: &Solver, sol: &Solution, sub: usize, node: usize) -> (Vec<f64>, Vec<f64>) {
    let p = solver.problem();
    let s = &p.subs[sub];
    let around: Vec<&Element> = s
        .mesh
        .elements
        .iter()
        .filter(|e| e.nodes().contains(&node))
        .collect();
    let mut speed = Vec::with_capacity(p.time.steps + 1);
    let mut vm = Vec::with_capacity(p.time.steps + 1);
    post::replay(solver, sol, sub, p.time.steps, &mut |_, st, _, _| {
        let v = &st.v[3 * node..3 * node + 3];
        speed.push((v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt());
        let mean = around
            .iter()
            .map(|e| hex8::von_mises(&post::stress_of(s, e, &st.u)))
            .sum::<f64>()
            / around.len().max(1) as f64;
        vm.push(mean);
    });
    (speed, vm)
}
