//! Regression tests of the hardening issue, one per case a careless or hurried user found, each
//! named after it: sizes that cannot fit are refused from the scene alone before anything is
//! allocated; the model is what the file says or an error (no silently dropped contact, no
//! overlapping bodies, arrays of exactly their length); absurd values are refused naming the
//! field that holds them; a non-finite value stops the solve where it appears. The footprint
//! counted from the scene is checked against the built problem's own estimate.

use lopin_core::estimate::Estimate;
use lopin_core::interfaces::interface::{DofLaw, Law};
use lopin_core::scene::admission::{admit, footprint, SolveShape};
use lopin_core::{scene, LopinError, Parameter, Settings, Solver};
use lopin_tests::{assert_clear_errors, asset};

fn text(name: &str) -> String {
    std::fs::read_to_string(asset(name)).expect("asset")
}

#[test]
fn estimate_of_a_10_12_element_scene_is_refused_from_the_scene_alone() {
    let mut spec = scene::load("two-blocks").expect("scene");
    for b in &mut spec.bodies {
        b.divisions = [10_000, 10_000, 5_000];
    }
    // counted, not built: 2 × 5·10¹¹ hexahedra
    let fp = footprint(&spec, "big.toml", SolveShape::of_scene(&spec)).expect("counts");
    assert_eq!(fp.elements, 1_000_000_000_000);
    assert_eq!(fp.dofs, 2 * 3 * 10_001 * 10_001 * 5_001);
    assert!(fp.total_bytes() > 1 << 50, "{fp:?}");
    let err = admit(&spec, "big.toml", SolveShape::of_scene(&spec)).expect_err("refused");
    let msg = err.to_string();
    assert!(matches!(err, LopinError::TooLarge { .. }), "{msg}");
    for part in [
        "big.toml",
        "1000000000000 hexahedra",
        "TiB",
        "What would fit",
        "coarser mesh",
    ] {
        assert!(msg.contains(part), "no `{part}` in: {msg}");
    }
    // the same through validation (what `lopin estimate FILE` and `lopin run FILE` meet first)
    let err = scene::check(&spec, "big.toml").expect_err("refused");
    assert!(matches!(err, LopinError::TooLarge { .. }), "{err}");
}

#[test]
fn refine_that_overflows_is_an_error_not_a_silent_wrap() {
    for k in [4_611_686_018_427_387_905usize, usize::MAX] {
        let mut spec = scene::load("two-blocks").expect("scene");
        let before = spec.clone();
        let err = spec.refine(k).expect_err("overflow").to_string();
        assert!(
            err.contains("refine") && err.contains("does not fit"),
            "{err}"
        );
        assert_eq!(spec, before, "a failed refine changes nothing");
    }
    let mut spec = scene::load("two-blocks").expect("scene");
    spec.split(usize::MAX)
        .expect("one substructure times the largest count fits");
    assert!(spec.split(2).is_err());
}

#[test]
fn steps_near_2_pow_63_are_refused_before_any_allocation() {
    let mut spec = scene::load("two-blocks").expect("scene");
    spec.time.steps = (1usize << 63) - 1;
    let msg = scene::check(&spec, "steps.toml")
        .expect_err("refused")
        .to_string();
    assert!(msg.contains("steps.toml"), "{msg}");
    assert!(
        msg.contains("time.steps") || msg.contains("fewer steps"),
        "{msg}"
    );
}

#[test]
fn a_solve_that_cannot_fit_says_what_would() {
    let mut spec = scene::load("two-blocks").expect("scene");
    spec.time.steps = 2_000_000;
    let fp = footprint(&spec, "long.toml", SolveShape::of_scene(&spec)).expect("counts");
    // 4 GiB is not enough for two million steps of two-blocks' interface fields
    assert!(fp.interface_bytes > 4 << 30, "{fp:?}");
    std::env::set_var("LOPIN_MEMORY_LIMIT", "4GiB");
    let err = admit(&spec, "long.toml", SolveShape::of_scene(&spec));
    std::env::remove_var("LOPIN_MEMORY_LIMIT");
    let msg = err.expect_err("refused").to_string();
    assert!(
        msg.contains("LOPIN_MEMORY_LIMIT") && msg.contains("`time.steps` at most"),
        "{msg}"
    );
    // the number of steps it proposes does fit
    let most: usize = msg
        .split("`time.steps` at most ")
        .nth(1)
        .and_then(|r| r.split_whitespace().next())
        .and_then(|n| n.parse().ok())
        .expect("a number of steps");
    spec.time.steps = most;
    let fp = footprint(&spec, "long.toml", SolveShape::of_scene(&spec)).expect("counts");
    assert!(
        fp.total_bytes() as f64 <= 0.9 * (4u64 << 30) as f64,
        "{fp:?}"
    );
}

#[test]
fn footprint_counted_from_the_scene_matches_the_built_problem() {
    // (scene, split): the sizes are exact; the factorization is an estimate within 3×
    for (name, split) in [
        ("two-blocks", 1),
        ("two-blocks", 2),
        ("gap-impact", 1),
        ("bar", 1),
        ("granular-small", 1),
    ] {
        let mut spec = scene::load(name).expect("scene");
        spec.split(split).expect("split");
        let shape = SolveShape::of_scene(&spec);
        let fp = footprint(&spec, name, shape).expect("counts");
        let problem = scene::problem_of(&spec, name).expect("builds");
        let settings = Settings::for_problem(&problem, &spec.solver);
        let built = Estimate::of(&problem, &settings);
        assert_eq!(fp.dofs, built.dofs, "{name}");
        assert_eq!(fp.substructures, built.substructures, "{name}");
        assert_eq!(
            fp.trace_entries, built.trace_entries,
            "{name} split {split}"
        );
        assert_eq!(fp.interface_bytes as usize, built.interface_bytes, "{name}");
        assert_eq!(fp.cache_bytes as usize, built.cache_bytes, "{name}");
        let ops = fp.operator_bytes as f64 / built.operator_bytes as f64;
        let solver = Solver::new(problem, settings).expect("factorizes");
        let measured = Estimate::of_solver(&solver);
        let factors = fp.factor_bytes as f64 / measured.factor_bytes.expect("factors") as f64;
        println!(
            "{name} split {split}: operators counted/built {ops:.3}, factors estimated/measured \
             {factors:.2}, factorizations {} / {}",
            fp.factorizations,
            measured.factorizations.expect("count")
        );
        assert!((0.9..=1.1).contains(&ops), "{name}: operators {ops}");
        assert!(
            (1.0 / 3.0..=3.0).contains(&factors),
            "{name}: factors {factors}"
        );
    }
}

#[test]
fn contact_face_made_non_matching_by_divisions_is_coupled_not_dropped() {
    // gap-impact's contact faces face each other across 0.1 mm; with 4 × 4 elements on B's top
    // face against A's 5 × 5 they cannot pair node to node: once the model silently had no
    // contact at all and the cube fell through; now they are one non-matching contact over the
    // whole face, with the gap between them
    let mut spec = scene::load("gap-impact").expect("scene");
    spec.bodies[1].divisions = [4, 4, 5];
    let problem = scene::problem_of(&spec, "gap-impact").expect("a non-matching contact");
    let contacts: Vec<_> = problem
        .interfaces
        .iter()
        .filter(|i| i.is_contact())
        .collect();
    assert_eq!(contacts.len(), 1);
    let area: f64 = contacts[0].area.iter().step_by(3).sum();
    assert!((area / 0.02f64.powi(2) - 1.0).abs() < 1e-9, "{area}");
    let lopin_core::interfaces::interface::Law::Contact(c) = &contacts[0].law else {
        unreachable!()
    };
    assert!(
        c.gap.iter().all(|g| (g - 1e-4).abs() < 1e-12),
        "{:?}",
        c.gap
    );
    // faces overlapping with no facet of either wholly covered by the other: reported, naming
    // both bodies
    let mut spec = scene::load("gap-impact").expect("scene");
    for b in &mut spec.bodies {
        b.divisions = [1, 1, 5];
    }
    for c in 0..2 {
        spec.bodies[1].min[c] += 0.01;
        spec.bodies[1].max[c] += 0.01;
    }
    let err = scene::problem_of(&spec, "gap-impact").expect_err("cannot be coupled");
    assert!(matches!(err, LopinError::NonConforming { .. }), "{err}");
    let msg = err.to_string();
    assert!(
        msg.starts_with("gap-impact: ") && msg.contains("`A`") && msg.contains("`B`"),
        "{msg}"
    );
}

#[test]
fn contact_asked_for_between_bodies_that_never_meet_is_an_error() {
    let good = text("two-blocks");
    let lifted = good
        .replace("min = [0.0, 0.0, 0.02]", "min = [0.0, 0.0, 0.021]")
        .replace("max = [0.04, 0.04, 0.04]", "max = [0.04, 0.04, 0.041]");
    let dir = std::env::temp_dir().join(format!("lopin-lifted-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let path = dir.join("lifted.toml");
    std::fs::write(&path, &lifted).expect("write");
    let path = path.to_str().expect("utf8");
    let spec = scene::load(path).expect("the file itself is valid");
    let msg = scene::problem_of(&spec, path)
        .expect_err("no contact interface")
        .to_string();
    for part in [
        "lifted.toml",
        "interface[0]",
        "`A` and `B`",
        "1.0000e-3 m apart",
        "search",
    ] {
        assert!(msg.contains(part), "no `{part}` in: {msg}");
    }
}

#[test]
fn overlapping_bodies_and_arrays_of_the_wrong_length_are_errors() {
    let good = text("two-blocks");
    let cases: [(&str, String, &str, &str); 4] = [
        (
            "overlapping bodies",
            good.replace("min = [0.0, 0.0, 0.02]", "min = [0.0, 0.0, 0.019]"),
            "body[1]",
            "bodies `A` and `B` overlap",
        ),
        (
            "four divisions",
            good.replacen("divisions = [10, 10, 5]", "divisions = [10, 10, 5, 7]", 1),
            "divisions = [10, 10, 5, 7]",
            "expected exactly 3 values (x, y, z), got 4",
        ),
        (
            "two coordinates",
            good.replace("min = [0.0, 0.0, 0.0]", "min = [0.0, 0.0]"),
            "min = [0.0, 0.0]",
            "expected exactly 3 values (x, y, z), got 2",
        ),
        (
            "three bodies in an interface",
            good.replace("bodies = [\"A\", \"B\"]", "bodies = [\"A\", \"B\", \"A\"]"),
            "bodies",
            "expected exactly 2 values, got 3",
        ),
    ];
    assert_clear_errors(&good, &cases, "lopin-hardening-model");
}

#[test]
fn absurd_finite_values_are_refused_naming_their_field() {
    let blocks = text("two-blocks");
    let cases: [(&str, String, &str, &str); 7] = [
        (
            "dt 5e-324",
            blocks.replace("dt = 0.25e-6", "dt = 5e-324"),
            "time.dt",
            "times the time a P wave takes to cross the smallest element",
        ),
        (
            "density 1e300",
            blocks.replace("density = 7800.0", "density = 1e300"),
            "material[0].density",
            "must be positive, within",
        ),
        (
            "Young's modulus 1e300",
            blocks.replace("young = 70e9", "young = 1e300"),
            "material[1].young",
            "must be positive, within",
        ),
        (
            "boundary velocity 1e300",
            blocks.replace("velocity = -10.0", "velocity = -1e300"),
            "boundary[0].z.velocity",
            "faster than the slowest wave speed",
        ),
        (
            "max_iter = 0",
            blocks.replace("[time]", "[solver]\nmax_iter = 0\n\n[time]"),
            "solver.max_iter",
            "at least 1",
        ),
        (
            "gap larger than the model",
            blocks.replace("gap = 0.0", "gap = 1e3"),
            "interface[0].gap",
            "exceeds the size of the whole model",
        ),
        (
            "coordinates beyond 1e5 m",
            blocks.replace("max = [0.04, 0.04, 0.02]", "max = [1e300, 0.04, 0.02]"),
            "body[1].max",
            "lies beyond",
        ),
    ];
    assert_clear_errors(&blocks, &cases, "lopin-hardening-values");
    let impact = text("gap-impact");
    let cases: [(&str, String, &str, &str); 1] = [(
        "body velocity 1e300",
        impact.replace(
            "velocity = [0.0, 0.0, -5.0]",
            "velocity = [0.0, 0.0, -5e300]",
        ),
        "body[0].velocity",
        "faster than the slowest wave speed",
    )];
    assert_clear_errors(&impact, &cases, "lopin-hardening-impact");
}

#[test]
fn k_1e300_is_refused_naming_k_and_the_impedance() {
    let spec = scene::load("two-blocks").expect("scene");
    let problem = scene::problem_of(&spec, "two-blocks").expect("builds");
    let mut settings = Settings::for_problem(&problem, &spec.solver);
    settings.k = 1e300;
    let msg = Solver::new(problem, settings)
        .expect_err("refused")
        .to_string();
    assert!(
        msg.contains("`k`") && msg.contains("impedance") && msg.contains("1e300"),
        "{msg}"
    );
}

#[test]
fn sweep_values_that_break_small_strains_are_refused_before_solving() {
    let spec = scene::load("bar").expect("scene");
    let problem = scene::problem_of(&spec, "bar").expect("builds");
    let settings = Settings::for_problem(&problem, &spec.solver);
    let mut solver = Solver::new(problem, settings).expect("factorizes");
    let msg = solver
        .set_parameter(Parameter::VelocityAmplitude, 1e300)
        .expect_err("v0 = 1e300")
        .to_string();
    assert!(
        msg.contains("v0") && msg.contains("slowest wave speed"),
        "{msg}"
    );
    let spec = scene::load("two-blocks").expect("scene");
    let problem = scene::problem_of(&spec, "two-blocks").expect("builds");
    let settings = Settings::for_problem(&problem, &spec.solver);
    let mut solver = Solver::new(problem, settings).expect("factorizes");
    let msg = solver
        .set_parameter(Parameter::Gap, 1e300)
        .expect_err("gap = 1e300")
        .to_string();
    assert!(
        msg.contains("gap") && msg.contains("size of the whole model"),
        "{msg}"
    );
    // values in range still apply
    solver
        .set_parameter(Parameter::Gap, 1e-5)
        .expect("a 10 µm gap");
}

#[test]
fn a_non_finite_value_stops_the_solve_naming_where_and_which_input() {
    let spec = scene::load("two-blocks").expect("scene");
    let mut problem = scene::problem_of(&spec, "two-blocks").expect("builds");
    // a NaN prescribed velocity, set behind validation's back
    let top = problem
        .interfaces
        .iter()
        .position(|i| i.name.ends_with(":z+"))
        .expect("A's top face");
    let name = problem.interfaces[top].name.clone();
    if let Law::Boundary(dofs) = &mut problem.interfaces[top].law {
        for d in dofs {
            if let DofLaw::Velocity(f) = &mut d.law {
                f.amplitude = f64::NAN;
            }
        }
    }
    let settings = Settings::for_problem(&problem, &spec.solver);
    let mut solver = Solver::new(problem, settings).expect("factorizes");
    let mut seen = Vec::new();
    let err = solver
        .solve_with(None, &mut |r| {
            seen.push(r.eta);
            lopin_core::Control::Continue
        })
        .expect_err("non-finite");
    let msg = err.to_string();
    assert!(matches!(err, LopinError::NonFinite(_)), "{msg}");
    for part in [
        "local stage",
        "iteration 1",
        "step 1 ",
        name.as_str(),
        "velocity NaN",
    ] {
        assert!(msg.contains(part), "no `{part}` in: {msg}");
    }
    // stopped at once: no observer ever saw a non-finite η
    assert!(seen.iter().all(|e| e.is_finite()), "{seen:?}");
}
