//! Helpers for Lopin's cross-crate validation tests: 1D bars written as 3D scenes (one hexahedron
//! across, ν = 0, so the 3D discretization is exactly the 1D one of METHOD §12), an independent
//! monolithic 1D solver of the same discretization ([`mono1d`]), a writer of small Gmsh MSH 4.1
//! files ([`msh_writer`]), and small solve/compare helpers (a solve against the monolithic
//! reference among them).

pub mod bar1d;
pub mod mono1d;
pub mod msh_writer;

use bar1d::{Bar1d, Segment};
use lopin_core::post;
use lopin_core::problem::Problem;
use lopin_core::scene::spec::SolverSpec;
use lopin_core::scene::{self, SceneSpec};
use lopin_core::solver::batch::{step_together, Lane};
use lopin_core::time::time_function::TimeGrid;
use lopin_core::{Control, Parameter, Settings, Solution, Solver};
use lopin_judge::compare::{compare, Comparison};
use lopin_reference::monolithic::Monolithic;
use mono1d::{Chain, Contact};

/// Builds and solves a scene, with `tweak` applied to the default settings.
pub fn solve(spec: &SceneSpec, tweak: impl FnOnce(&mut Settings)) -> (Solver, Solution) {
    let problem = scene::problem_of(spec, &spec.name).expect("scene builds");
    solve_problem(problem, &spec.solver, tweak)
}

/// Solves a built problem with the settings its scene's `[solver]` table gives, changed by
/// `tweak`.
pub fn solve_problem(
    problem: Problem,
    spec: &SolverSpec,
    tweak: impl FnOnce(&mut Settings),
) -> (Solver, Solution) {
    let mut settings = Settings::for_problem(&problem, spec);
    tweak(&mut settings);
    let mut solver = Solver::new(problem, settings).expect("factorization");
    let sol = solver.solve(None).expect("solve");
    (solver, sol)
}

/// A LATIN solution against the monolithic reference of the same problem.
pub fn against_reference(solver: &Solver, sol: &Solution) -> Comparison {
    let reference = Monolithic::new(solver.problem().clone()).expect("reference");
    let mono = reference.solve().expect("reference solve");
    compare(solver, sol, &reference, &mono)
}

pub use lopin_core::post::velocity_history;

/// Path of a scene file of `assets/scenes/`.
pub fn asset(name: &str) -> String {
    format!(
        "{}/../assets/scenes/{name}.toml",
        env!("CARGO_MANIFEST_DIR")
    )
}

/// Writes each malformed variant of `good` to a file and checks that loading it fails with a
/// scene error naming the file, the field and the reason.
pub fn assert_clear_errors(good: &str, cases: &[(&str, String, &str, &str)], dir: &str) {
    let dir = std::env::temp_dir().join(format!("{dir}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    for (what, text, field, reason) in cases {
        assert_ne!(text, good, "{what}: the edit did not apply");
        let path = dir.join("bad.toml");
        std::fs::write(&path, text).expect("write");
        let err = scene::load(path.to_str().expect("utf8")).expect_err(what);
        let msg = err.to_string();
        assert!(
            matches!(
                err,
                lopin_core::LopinError::Scene { .. } | lopin_core::LopinError::TooLarge { .. }
            ),
            "{what}: {msg}"
        );
        assert!(msg.contains("bad.toml"), "{what}: no file name in `{msg}`");
        assert!(msg.contains(field), "{what}: no field `{field}` in `{msg}`");
        assert!(
            msg.contains(reason),
            "{what}: no reason `{reason}` in `{msg}`"
        );
    }
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

/// (σ_xx, mean v_x) of every element whose centre x lies in [lo, hi], at step m (1D bars).
pub fn elements_along_x(
    solver: &Solver,
    sol: &Solution,
    m: usize,
    lo: f64,
    hi: f64,
) -> Vec<(f64, f64)> {
    let fields = post::fields_at(solver, sol, m);
    let mut out = Vec::new();
    for (i, sub) in solver.problem().subs.iter().enumerate() {
        let stress = post::element_stress(solver, i, &fields[i].u);
        for (e, el) in sub.mesh.elements.iter().enumerate() {
            let nodes = el.nodes();
            let count = nodes.len() as f64;
            let xc = nodes.iter().map(|&k| sub.mesh.nodes[k][0]).sum::<f64>() / count;
            if (lo..=hi).contains(&xc) {
                let v = nodes.iter().map(|&k| fields[i].v[3 * k]).sum::<f64>() / count;
                out.push((stress[e][0], v));
            }
        }
    }
    assert!(!out.is_empty(), "no element in [{lo}, {hi}]");
    out
}

/// Mean σ_xx and mean v_x over the elements of [`elements_along_x`].
pub fn plateau(solver: &Solver, sol: &Solution, m: usize, lo: f64, hi: f64) -> (f64, f64) {
    let e = elements_along_x(solver, sol, m, lo, hi);
    let n = e.len() as f64;
    (
        e.iter().map(|x| x.0).sum::<f64>() / n,
        e.iter().map(|x| x.1).sum::<f64>() / n,
    )
}

/// The 1D impact of 2a: bars [0, 1] (v0 = 1) and [1.045, 2.045] at rest, 50 elements each,
/// 2 substructures per bar, Δt = h, N = 152, f = 0.
pub fn impact_2a() -> (Bar1d, Vec<Chain>, Contact) {
    let h = 0.02;
    let seg = |x0: f64, velocity: f64| Segment {
        x0,
        elements: 25,
        young: 1.0,
        density: 1.0,
        velocity,
    };
    let bar = Bar1d {
        h,
        segments: vec![
            seg(0.0, 1.0),
            seg(0.5, 1.0),
            seg(1.045, 0.0),
            seg(1.545, 0.0),
        ],
        time: TimeGrid { dt: h, steps: 152 },
        push: None,
        contacts: vec![(1, 0.05)],
    };
    let chains = vec![
        Chain::of_elements(&[(1.0, 1.0); 50], h, 1.0, 1.0),
        Chain::of_elements(&[(1.0, 1.0); 50], h, 1.0, 0.0),
    ];
    (
        bar,
        chains,
        Contact {
            a: (0, 50),
            b: (1, 0),
            gap: 0.045,
        },
    )
}

/// Two zones at their own friction (`zones`: each zone's target and value): the LATIN solution
/// at the solver's tolerance agrees with the monolithic reference of the same problem to 1e-6
/// (velocity and force), and its friction work lies strictly between the uniform runs' at the
/// two values. Leaves the solver at the second value everywhere.
pub fn two_frictions_against_reference_and_uniform(
    s: &mut Solver,
    zones: [(&lopin_core::study::Target, f64); 2],
) {
    for (t, f) in zones {
        s.set_parameter_in(t.parameter, t.zone, f).expect("zone");
        assert_eq!(t.parameter.current_in(s.problem(), t.zone), Some(f));
    }
    let mixed = s.solve(None).expect("mixed");
    assert!(mixed.converged, "eta {}", mixed.eta);
    let c = against_reference(s, &mixed);
    let label = format!(
        "{} {}, {} {}",
        zones[0].0.label, zones[0].1, zones[1].0.label, zones[1].1
    );
    println!(
        "{label}: {} iterations, velocity {:.2e}, force {:.2e} against the reference",
        mixed.iterations, c.rel_diff_velocity, c.rel_diff_force
    );
    assert!(
        c.rel_diff_velocity < 1e-6 && c.rel_diff_force < 1e-6,
        "{c:?}"
    );
    let w_mixed = lopin_core::dissipation::contact_work(s, &mixed).friction;
    let mut work = |f: f64| {
        s.set_parameter(lopin_core::Parameter::Friction, f)
            .expect("f");
        let sol = s.solve(None).expect("solve");
        lopin_core::dissipation::contact_work(s, &sol).friction
    };
    let (wa, wb) = (work(zones[0].1), work(zones[1].1));
    println!(
        "friction work: uniform {} {wa:.4e} J, {label} {w_mixed:.4e} J, uniform {} {wb:.4e} J",
        zones[0].1, zones[1].1
    );
    assert!(w_mixed > wa.min(wb) && w_mixed < wa.max(wb));
}

/// One contact node pair of a problem ([`contact_pairs`]).
#[derive(Debug, Clone, PartialEq)]
pub struct ContactPair {
    /// The interface holding it.
    pub interface: String,
    /// Its node on side 1 and on side 2.
    pub nodes: (usize, usize),
    /// Lumped area, m².
    pub area: f64,
    /// Unit normal (outward of side 1).
    pub normal: [f64; 3],
    /// Initial gap, m.
    pub gap: f64,
}

/// Every contact node pair of a problem, in the order of its interfaces and their nodes.
pub fn contact_pairs(p: &Problem) -> Vec<ContactPair> {
    let mut out = Vec::new();
    for iface in &p.interfaces {
        let lopin_core::interfaces::interface::Law::Contact(c) = &iface.law else {
            continue;
        };
        let sides = iface.sides[0].nodes.iter().zip(&iface.sides[1].nodes);
        for (j, (&a, &b)) in sides.enumerate() {
            out.push(ContactPair {
                interface: iface.name.clone(),
                nodes: (a, b),
                area: iface.area[3 * j],
                normal: c.normal[j],
                gap: c.gap[j],
            });
        }
    }
    out
}

/// Asserts that `split` holds the contact node pairs of `whole`, whichever interfaces hold them:
/// the same pairs, each with the same lumped area, normal and gap (a contact split by surface
/// is a partition of the unsplit one).
pub fn assert_same_contact_pairs(whole: &Problem, split: &Problem) {
    let by_node = |p: &Problem| {
        let mut v: Vec<_> = contact_pairs(p)
            .into_iter()
            .map(|c| (c.nodes, c.area, c.normal, c.gap))
            .collect();
        v.sort_by_key(|c| c.0);
        v
    };
    assert_eq!(
        by_node(whole),
        by_node(split),
        "the split partitions the contact"
    );
}

/// `bar` refined `r` times in x (and its step divided by `r`), its end x = 0 driven along x by
/// `drive`.
pub fn bar_driven(drive: lopin_core::scene::spec::ComponentSpec, r: usize) -> SceneSpec {
    let mut spec = scene::load("bar").expect("scene");
    spec.refine(r).expect("refine");
    spec.time.dt /= r as f64;
    spec.time.steps *= r;
    spec.boundaries[0].x = Some(drive);
    spec
}

/// The largest |scale × a − b| over the velocities of every step and substructure of two
/// solutions, and the largest |b|.
pub fn largest_difference(
    a: (&Solver, &Solution),
    b: (&Solver, &Solution),
    scale: f64,
) -> (f64, f64) {
    let (va, vb) = (
        post::velocity_history(a.0, a.1),
        post::velocity_history(b.0, b.1),
    );
    let (va, vb) = (va.iter().flatten().flatten(), vb.iter().flatten().flatten());
    va.zip(vb).fold((0.0f64, 0.0f64), |(d, p), (x, y)| {
        (d.max((scale * x - y).abs()), p.max(y.abs()))
    })
}

/// Solves `frictions` in lanes of one solver made from `base` (sharing its factors), from
/// `starts` (None: cold), all advanced together one iteration at a time.
pub fn solve_in_lanes(
    base: &Solver,
    frictions: &[f64],
    starts: &[Option<&lopin_core::state::InterfaceState>],
) -> Vec<Solution> {
    let mut solvers: Vec<Solver> = frictions
        .iter()
        .map(|&f| {
            let mut s = base.lane().expect("lane");
            s.set_parameter(Parameter::Friction, f).expect("friction");
            assert!(s.shares_factors(base));
            s
        })
        .collect();
    march_in_lanes(&mut solvers, starts)
}

/// The solves of `solvers` (lanes of one solver) from `starts`, advanced one iteration at a time
/// together ([`step_together`]) until each has ended.
pub fn march_in_lanes(
    solvers: &mut [Solver],
    starts: &[Option<&lopin_core::state::InterfaceState>],
) -> Vec<Solution> {
    let mut runs: Vec<_> = solvers
        .iter_mut()
        .zip(starts)
        .map(|(s, start)| s.begin(*start).expect("begin"))
        .collect();
    let mut ended = vec![false; solvers.len()];
    while ended.iter().any(|e| !e) {
        let mut lanes: Vec<Lane<'_>> = solvers
            .iter_mut()
            .zip(runs.iter_mut())
            .map(|(solver, run)| Lane { solver, run })
            .collect();
        ended = step_together(&mut lanes, &mut |_, _| Control::Continue);
    }
    solvers
        .iter()
        .zip(runs)
        .map(|(s, run)| s.conclude(run).expect("solution"))
        .collect()
}

/// Largest difference between two interface states, relative to the largest value of each
/// field (F and W apart).
pub fn state_difference(a: &Solution, b: &Solution) -> f64 {
    let mut worst: f64 = 0.0;
    for (x, y) in a.state.subs.iter().zip(&b.state.subs) {
        for (p, q) in [(&x.f, &y.f), (&x.w, &y.w)] {
            let scale = q.iter().fold(f64::MIN_POSITIVE, |m, v| m.max(v.abs()));
            let d = p
                .iter()
                .zip(q)
                .fold(0.0f64, |m, (u, v)| m.max((u - v).abs()));
            worst = worst.max(d / scale);
        }
    }
    worst
}
