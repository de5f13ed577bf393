//! Volume fields of one time step, computed only for the step on screen (METHOD §6 "at
//! convergence": one more linear stage driven by ŝ, replayed up to that step): nodal
//! displacement and velocity, and von Mises stress averaged from element centres to nodes.
//! Also the history of one node for the probe, with the shock response spectrum of its
//! acceleration (`lopin_core::shock_spectrum`).

use lopin_core::elements::hex8;
use lopin_core::mesh::{Element, Mesh};
use lopin_core::post;
use lopin_core::shock_spectrum;
use lopin_core::{Solution, Solver};

/// Fields of one substructure at one step.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct SubStepFields {
    /// Nodal displacements (node-major), m.
    pub u: Vec<f64>,
    /// Nodal velocities (node-major), m/s.
    pub v: Vec<f64>,
    /// Von Mises stress averaged to nodes, Pa.
    pub von_mises: Vec<f64>,
}

/// Fields of every substructure at one step.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
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
        .map(|(i, f)| SubStepFields {
            von_mises: nodal_von_mises(solver, i, &f.u),
            u: f.u,
            v: f.v,
        })
        .collect();
    StepFields {
        generation,
        step,
        live,
        subs,
    }
}

/// Von Mises stress of substructure `i` under displacements `u`, averaged from the elements to
/// the nodes.
pub fn nodal_von_mises(solver: &Solver, i: usize, u: &[f64]) -> Vec<f64> {
    element_to_nodes(
        &solver.problem().subs[i].mesh,
        &post::von_mises(solver, i, u),
    )
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

/// Quality factor of the probe's shock response spectrum.
pub const PROBE_Q: f64 = 10.0;

/// The probe's histories: |v|, node-averaged von Mises stress and |a| (step-averaged), and the
/// shock response spectrum of its acceleration at Q = [`PROBE_Q`] over 1/T to 1/(10Δt), 12
/// frequencies per octave.
pub struct ProbeSeries {
    /// |v| per step.
    pub speed: Vec<f64>,
    /// Von Mises stress per step.
    pub von_mises: Vec<f64>,
    /// |a| per step m ≥ 1.
    pub acceleration: Vec<f64>,
    /// (frequency, maximax per component).
    pub spectrum: Vec<(f64, [f64; 3])>,
}

/// The histories and spectrum of node `node` of substructure `sub`.
pub fn probe(solver: &Solver, sol: &Solution, sub: usize, node: usize) -> ProbeSeries {
    let p = solver.problem();
    let (von_mises, velocity) = probe_steps(solver, sol, sub, node);
    probe_series(&velocity, von_mises, p.time.dt, p.time.end())
}

/// The probe's histories and spectrum from a node's velocity and von Mises stress at every
/// step m = 0..=N of an interval of length `end` in steps of `dt`.
pub fn probe_series(velocity: &[[f64; 3]], von_mises: Vec<f64>, dt: f64, end: f64) -> ProbeSeries {
    let speed = velocity
        .iter()
        .map(|v| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt())
        .collect();
    let steps = shock_spectrum::step_accelerations(velocity, dt);
    let acceleration = steps
        .iter()
        .map(|a| (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt())
        .collect();
    let (low, high) = shock_spectrum::default_band(dt, end);
    let freqs = shock_spectrum::frequencies(low, high, 12);
    let zeta = shock_spectrum::ratio_of_quality(PROBE_Q);
    let spectrum = freqs
        .iter()
        .copied()
        .zip(shock_spectrum::component_spectra(&steps, dt, &freqs, zeta))
        .collect();
    ProbeSeries {
        speed,
        von_mises,
        acceleration,
        spectrum,
    }
}

/// Node-averaged von Mises stress and velocity of node `node` of substructure `sub`, at every
/// step.
fn probe_steps(
    solver: &Solver,
    sol: &Solution,
    sub: usize,
    node: usize,
) -> (Vec<f64>, Vec<[f64; 3]>) {
    let p = solver.problem();
    let s = &p.subs[sub];
    let around: Vec<&Element> = s
        .mesh
        .elements
        .iter()
        .filter(|e| e.nodes().contains(&node))
        .collect();
    let mut vm = Vec::with_capacity(p.time.steps + 1);
    let mut velocity = Vec::with_capacity(p.time.steps + 1);
    post::replay(solver, sol, sub, p.time.steps, &mut |_, st, _, _| {
        let v = &st.v[3 * node..3 * node + 3];
        velocity.push([v[0], v[1], v[2]]);
        let mean = around
            .iter()
            .map(|e| hex8::von_mises(&post::stress_of(s, e, &st.u)))
            .sum::<f64>()
            / around.len().max(1) as f64;
        vm.push(mean);
    });
    (vm, velocity)
}

#[cfg(test)]
mod tests {
    use super::*;
    use lopin_core::scene;

    /// The probe on a node of A's top face of `two-blocks`, driven down by a (1 − cos) ramp of
    /// 10 m/s over 2.5 µs (10 steps): its |a| peaks at the ramp's largest step-averaged
    /// acceleration (to 1e-6), and its spectrum is the one `lopin srs` computes from the same node's
    /// velocity history (to 1e-12).
    #[test]
    fn the_probe_spectrum_is_the_clis_and_the_driven_face_has_the_ramps_acceleration() {
        let spec = scene::load("two-blocks").expect("scene");
        let problem = scene::problem_of(&spec, "two-blocks").expect("builds");
        let mut settings = lopin_core::Settings::for_problem(&problem, &spec.solver);
        settings.tol = 1e-9;
        settings.window = Some(1);
        let mut solver = Solver::new(problem, settings).expect("setup");
        let sol = solver.solve(None).expect("solves");
        let (sub, node, _) =
            post::nearest_node(solver.problem(), [0.02, 0.02, 0.04]).expect("a node");
        let h = probe(&solver, &sol, sub, node);
        let peak = h.acceleration.iter().copied().fold(0.0, f64::max);
        let dt = solver.problem().time.dt;
        let v = |t: f64| 5.0 * (1.0 - (std::f64::consts::PI * t.min(2.5e-6) / 2.5e-6).cos());
        let ramp = (1..=10)
            .map(|m| (v(m as f64 * dt) - v((m - 1) as f64 * dt)) / dt)
            .fold(0.0, f64::max);
        assert!((peak / ramp - 1.0).abs() < 1e-6, "{peak} against {ramp}");
        let steps =
            shock_spectrum::step_accelerations(&post::node_velocity(&solver, &sol, sub, node), dt);
        let z: Vec<f64> = steps.iter().map(|a| a[2]).collect();
        let freqs: Vec<f64> = h.spectrum.iter().map(|s| s.0).collect();
        let again = shock_spectrum::spectrum(&z, dt, &freqs, 0.5 / PROBE_Q);
        for ((_, s), e) in h.spectrum.iter().zip(&again) {
            assert!((s[2] - e).abs() <= 1e-12 * e, "{} against {e}", s[2]);
        }
    }
}
