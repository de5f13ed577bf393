//! A load along the faces' normal (`normal = { pressure = … }`, `lopin_core::interfaces::
//! interface::BoundaryLoad::Normal`): on a curved, faceted surface (the top of a column of
//! tetrahedra bulged by a quarter of its width) the nodal forces add up to the pressure times
//! the projected area (to 1e-12); the column, free, pushed by that pressure, gains the momentum
//! the net force gives (to 1e-9) and LATIN agrees with the monolithic reference (1e-6 at
//! η < 1e-9); on a plane box face a pressure is exactly the traction −p along its axis; bad
//! input is refused naming the field.

use lopin_core::interfaces::interface::Law;
use lopin_core::scene::spec::ComponentSpec;
use lopin_core::{post, scene, Problem};
use lopin_tests::msh_writer::{stacked_cubes, write};
use lopin_tests::{against_reference, largest_difference, solve, solve_problem};

/// Side of each cube of the column (m) and the pressure (Pa).
const SIZE: f64 = 0.01;
const PRESSURE: f64 = 1e6;

/// The column of [`stacked_cubes`] (3 cells per side) with its top bulged up by a quarter of its
/// width, z' = z + (z/2a) (a/4) sin(πx/a) sin(πy/a): the top `top` is curved, its edges stay at
/// z = 2a; written with a scene that pushes it with a (1 − cos) pressure over 2 µs and leaves
/// the column free.
fn curved_column(tag: &str) -> String {
    let dir = std::env::temp_dir().join(format!("lopin-pressure-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let mut d = stacked_cubes(3, SIZE);
    for p in &mut d.nodes {
        let bump =
            (std::f64::consts::PI * p[0] / SIZE).sin() * (std::f64::consts::PI * p[1] / SIZE).sin();
        p[2] += p[2] / (2.0 * SIZE) * 0.25 * SIZE * bump;
    }
    std::fs::write(dir.join("column.msh"), write(&d, false)).expect("msh");
    let scene = format!(
        "name = \"curved\"\n[time]\ndt = 0.25e-6\nsteps = 40\n\
         [[material]]\nname = \"steel\"\nyoung = 210e9\npoisson = 0.3\ndensity = 7800.0\n\
         [[mesh_body]]\nname = \"lower\"\nmaterial = \"steel\"\nmesh = \"column.msh\"\n\
         [[mesh_body]]\nname = \"upper\"\nmaterial = \"steel\"\nmesh = \"column.msh\"\n\
         [[boundary]]\nbody = \"upper\"\nsurface = \"top\"\n\
         normal = {{ pressure = {PRESSURE:e}, ramp = \"cosine\", ramp_time = 2e-6 }}\n"
    );
    let path = dir.join("curved.toml");
    std::fs::write(&path, scene).expect("scene");
    path.display().to_string()
}

/// Σ over the boundary dofs of A × scale × amplitude, per component: the net force of the
/// loads at their full amplitude; and the largest |n_x| of a dof.
fn net_force(p: &Problem) -> ([f64; 3], f64) {
    let (mut f, mut tilt) = ([0.0; 3], 0.0f64);
    for iface in &p.interfaces {
        if let Law::Boundary(dofs) = &iface.law {
            for (j, d) in dofs.iter().enumerate() {
                let (lopin_core::interfaces::interface::DofLaw::Traction(t)
                | lopin_core::interfaces::interface::DofLaw::Velocity(t)) = &d.law;
                f[d.component] += iface.area[j] * d.scale * t.amplitude;
                if d.component == 0 {
                    tilt = tilt.max(d.scale.abs());
                }
            }
        }
    }
    (f, tilt)
}

#[test]
fn the_pressure_on_a_curved_surface_adds_up_to_p_times_the_projected_area() {
    let path = curved_column("net");
    let spec = scene::load(&path).expect("loads");
    let problem = scene::problem_of(&spec, &path).expect("builds");
    let (f, tilt) = net_force(&problem);
    let expected = -PRESSURE * SIZE * SIZE;
    println!("net force {f:?} N against [0, 0, {expected:e}], facets tilted up to n_x = {tilt:.3}");
    assert!(tilt > 0.2, "the surface is not curved: {tilt}");
    let scale = expected.abs();
    assert!(
        f[0].abs() <= 1e-12 * scale && f[1].abs() <= 1e-12 * scale,
        "{f:?}"
    );
    assert!((f[2] - expected).abs() <= 1e-12 * scale, "{f:?}");
}

/// The free column pushed by the pressure: the momentum it holds at the end is the net force
/// times the trapezoidal integral of the ramp (the scheme's impulse), to 1e-9; across it, none;
/// and LATIN agrees with the reference at η < 1e-9 (1e-6).
#[test]
fn a_free_body_under_pressure_gains_the_impulse_and_agrees_with_the_reference() {
    let path = curved_column("momentum");
    let spec = scene::load(&path).expect("loads");
    let problem = scene::problem_of(&spec, &path).expect("builds");
    let (solver, sol) = solve_problem(problem, &spec.solver, |s| {
        s.tol = 1e-9;
        s.max_iter = 20_000;
    });
    assert!(sol.converged);
    let p = solver.problem();
    let (n, dt) = (p.time.steps, p.time.dt);
    let v = post::velocity_history(&solver, &sol);
    let momentum: [f64; 3] = std::array::from_fn(|c| {
        p.subs
            .iter()
            .zip(&v[n])
            .map(|(s, v)| {
                (0..s.ndof())
                    .filter(|d| d % 3 == c)
                    .map(|d| s.mass[d] * v[d])
                    .sum::<f64>()
            })
            .sum()
    });
    let ramp = |t: f64| 0.5 * (1.0 - (std::f64::consts::PI * (t / 2e-6).min(1.0)).cos());
    let impulse: f64 = (1..=n)
        .map(|m| 0.5 * dt * (ramp(m as f64 * dt) + ramp((m - 1) as f64 * dt)))
        .sum::<f64>()
        * -PRESSURE
        * SIZE
        * SIZE;
    println!("momentum {momentum:?} against [0, 0, {impulse:e}] N·s");
    assert!((momentum[2] / impulse - 1.0).abs() < 1e-9, "{momentum:?}");
    assert!(momentum[0].abs() < 1e-6 * impulse.abs(), "{momentum:?}");
    assert!(momentum[1].abs() < 1e-6 * impulse.abs(), "{momentum:?}");
    let c = against_reference(&solver, &sol);
    println!(
        "curved column: {} iterations, velocity {:.3e}, force {:.3e}",
        sol.iterations, c.rel_diff_velocity, c.rel_diff_force
    );
    assert!(
        c.rel_diff_velocity <= 1e-6 && c.rel_diff_force <= 1e-6,
        "{c:?}"
    );
}

/// On a plane box face, `normal = { pressure = p }` is `z = { traction = −p }`: the same fields
/// bit for bit (the node's normal is the face's to the last bit).
#[test]
fn on_a_plane_face_a_pressure_is_the_traction_along_its_axis() {
    let mut spec = scene::load("two-blocks").expect("scene");
    let ramp = ComponentSpec {
        ramp_time: 2.5e-6,
        ..ComponentSpec::default()
    };
    spec.boundaries[0].z = Some(ComponentSpec {
        traction: Some(-1e8),
        ..ramp.clone()
    });
    let (a, sa) = solve(&spec, |_| {});
    spec.boundaries[0].z = None;
    spec.boundaries[0].normal = Some(ComponentSpec {
        pressure: Some(1e8),
        ..ramp
    });
    let (b, sb) = solve(&spec, |_| {});
    let (diff, peak) = largest_difference((&a, &sa), (&b, &sb), 1.0);
    println!("pressure against traction: {diff:e} of {peak:e}");
    assert!(peak > 1.0 && diff == 0.0, "{diff:e}");
    assert_eq!(sa.iterations, sb.iterations);
}

/// A pressure on a component, a `normal` load with a velocity or beside a component are
/// refused with the file and field.
#[test]
fn bad_normal_loads_are_refused_naming_the_field() {
    let good = std::fs::read_to_string(lopin_tests::asset("two-blocks")).expect("scene");
    let top = "z = { velocity = -10.0, ramp = \"cosine\", ramp_time = 2.5e-6 }";
    assert!(good.contains(top));
    let with = |s: &str| good.replace(top, s);
    let cases = [
        (
            "pressure on z",
            with("z = { pressure = 1e6 }"),
            "boundary[0].z.pressure",
            "normal = { pressure",
        ),
        (
            "normal velocity",
            with("normal = { velocity = 1.0 }"),
            "boundary[0].normal",
            "not a velocity",
        ),
        (
            "normal and z",
            with(&format!("{top}\nnormal = {{ pressure = 1e6 }}")),
            "boundary[0].normal",
            "cannot be combined",
        ),
        (
            "too large",
            with("normal = { pressure = 1e12 }"),
            "boundary[0].normal.pressure",
            "exceeds the Young's modulus",
        ),
    ];
    lopin_tests::assert_clear_errors(&good, &cases, "lopin-bad-normal");
}
