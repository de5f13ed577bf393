//! Regression tests of the reliability cases an independent fuzzing campaign found, one per
//! case and named after it: values that made a run meaningless (a ramp that never starts, a
//! friction coefficient of 1e300), silent acceptance (a repeated `[[boundary]]`, a mesh body's
//! velocity beyond small strains), and messages that echoed a megabyte of input. Each is now a
//! clear error naming the file and the field.

use lopin_core::scene;
use lopin_tests::asset;
use lopin_tests::msh_writer::{stacked_cubes, write};

/// Writes `text` as `NAME.toml` in a fresh temporary folder and loads it; the error's text.
fn load_error(dir: &str, text: &str) -> String {
    let dir = std::env::temp_dir().join(format!("lopin-reliability-{dir}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    let path = dir.join("bad.toml");
    std::fs::write(&path, text).expect("write");
    let path = path.display().to_string();
    let e = scene::load(&path).expect_err("refused").to_string();
    println!("{e}");
    assert!(e.starts_with(&path), "the file is named first: {e}");
    e
}

/// Two mesh bodies `lower` and `upper` from `column.msh` ([`stacked_cubes`]), the lower one
/// clamped at the bottom, the upper one pushed down at the top; `lower` takes the extra line
/// `lower_extra`, `upper` is cut into `upper_parts` substructures.
fn column_scene(lower_extra: &str, upper_parts: usize) -> String {
    format!(
        r#"
name = "column"
[time]
dt = 0.25e-6
steps = 20
[[material]]
name = "steel"
young = 210e9
poisson = 0.3
density = 7800.0
[[mesh_body]]
name = "lower"
material = "steel"
mesh = "column.msh"
{lower_extra}
[[mesh_body]]
name = "upper"
material = "steel"
mesh = "column.msh"
substructures = {upper_parts}
[[boundary]]
body = "lower"
surface = "bottom"
clamped = true
[[boundary]]
body = "upper"
surface = "top"
z = {{ velocity = -1.0, ramp = "cosine", ramp_time = 2e-6 }}
"#
    )
}

fn text(name: &str) -> String {
    std::fs::read_to_string(asset(name)).expect("asset")
}

#[test]
fn granular_ramp_steps_2_pow_63_is_refused_against_the_run() {
    let good = text("granular-small");
    scene::load(&asset("granular-small")).expect("the scene as shipped loads");
    let e = load_error(
        "ramp",
        &good.replace("ramp_steps = 10", "ramp_steps = 9223372036854775807"),
    );
    assert!(
        e.contains("granular.ramp_steps")
            && e.contains("longer than the run's 40 steps")
            && e.contains("at most 40"),
        "{e}"
    );
    // the whole run as a ramp is still accepted
    let dir = std::env::temp_dir().join(format!("lopin-reliability-ok-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let path = dir.join("ramp40.toml");
    std::fs::write(&path, good.replace("ramp_steps = 10", "ramp_steps = 40")).expect("write");
    scene::load(&path.display().to_string()).expect("a ramp over the whole run loads");
}

#[test]
fn boundary_ramp_time_1e300_is_refused_against_the_run() {
    let good = text("two-blocks");
    let e = load_error(
        "ramp-time",
        &good.replace("ramp_time = 2.5e-6", "ramp_time = 1e300"),
    );
    assert!(
        e.contains("boundary[0].z.ramp_time")
            && e.contains("longer than the run (1.5e-5 s")
            && e.contains("at most 1.5e-5 s"),
        "{e}"
    );
}

#[test]
fn friction_1e300_is_refused_naming_the_range() {
    let e = load_error(
        "friction-granular",
        &text("granular-small").replace("friction = 0.3", "friction = 1e300"),
    );
    assert!(
        e.contains("granular.friction") && e.contains("lies in [0, 10]") && e.contains("1e300"),
        "{e}"
    );
    let e = load_error(
        "friction-interface",
        &text("two-blocks").replace("friction = 0.3", "friction = 11.0"),
    );
    assert!(
        e.contains("interface[0].friction") && e.contains("lies in [0, 10]"),
        "{e}"
    );
    let e = load_error(
        "friction-poly",
        &text("granular-poly").replace("friction = 0.3", "friction = 1e300"),
    );
    assert!(
        e.contains("granular_poly.friction") && e.contains("lies in [0, 10]"),
        "{e}"
    );
}

#[test]
fn duplicated_boundary_is_refused() {
    let good = text("two-blocks");
    let first = good.find("[[boundary]]").expect("a boundary");
    let end = good[first + 1..]
        .find("[[")
        .map_or(good.len(), |e| first + 1 + e);
    let entry = &good[first..end];
    let twice = format!("{good}\n{entry}");
    let e = load_error("boundary", &twice);
    assert!(
        e.contains("boundary[2]")
            && e.contains("repeats boundary[0]")
            && e.contains("face z+ of `A`"),
        "{e}"
    );
}

#[test]
fn mesh_body_velocity_1e10_is_refused_as_box_bodies_are() {
    let dir = std::env::temp_dir().join(format!("lopin-reliability-mesh-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    std::fs::write(
        dir.join("column.msh"),
        write(&stacked_cubes(1, 0.01), false),
    )
    .expect("msh");
    let scene = |velocity: &str| column_scene(&format!("velocity = {velocity}"), 1);
    let path = dir.join("column.toml");
    std::fs::write(&path, scene("[1.0, 0.0, 0.0]")).expect("scene");
    scene::load(&path.display().to_string()).expect("1 m/s loads");
    std::fs::write(&path, scene("[1e10, 0.0, 0.0]")).expect("scene");
    let e = scene::load(&path.display().to_string())
        .expect_err("refused")
        .to_string();
    assert!(
        e.contains("mesh_body[0].velocity") && e.contains("slowest wave speed"),
        "{e}"
    );
}

#[test]
fn a_megabyte_input_line_is_not_echoed_whole() {
    let good = text("two-blocks");
    let long = "9".repeat(1 << 20);
    for bad in [
        good.replace("friction = 0.3", &format!("friction = \"{long}\"")),
        good.replace("steps = 60", &format!("steps = 60{long}x")),
        format!("{good}\n{long} = 1\n"),
    ] {
        let e = load_error("long", &bad);
        assert!(e.len() < 1_000, "{} bytes: {}", e.len(), &e[..300]);
        assert!(e.contains("(1048"), "the length is said: {e}");
    }
    // an unknown key a megabyte long (in the last [[boundary]]): the message still lists the
    // keys that are known
    let e = load_error("long-key", &format!("{good}\n{long} = 1\n"));
    assert!(
        e.contains("expected one of") && e.contains("`clamped`"),
        "{e}"
    );
}

#[test]
fn granular_poly_side_1e300_and_vertices_64_are_refused_from_their_numbers() {
    let good = text("granular-poly");
    for (from, to, field, reason) in [
        (
            "side = 0.1 ",
            "side = 1e300 ",
            "granular_poly.side",
            "lies in [1e-4, 1e2] m",
        ),
        (
            "vertices = 12 ",
            "vertices = 64 ",
            "granular_poly.vertices",
            "at most 24",
        ),
        (
            "grains = 10",
            "grains = 2000",
            "granular_poly.grains",
            "at most 500",
        ),
        (
            "grains = 10",
            "grains = 1000000000",
            "granular_poly.grains",
            "at most 500",
        ),
        (
            "radius = [0.012, 0.02]",
            "radius = [1e-9, 0.02]",
            "granular_poly.radius",
            "at least 1e-3 of the cube side",
        ),
        (
            "radius = [0.012, 0.02]",
            "radius = [0.002, 0.02]",
            "granular_poly.radius",
            "below half the mesh size",
        ),
        (
            "gap = 0.004 ",
            "gap = 0.001 ",
            "granular_poly.gap",
            "below a quarter of the mesh size",
        ),
    ] {
        let bad = good.replace(from, to);
        assert_ne!(bad, good, "{from}");
        let e = load_error("poly", &bad);
        assert!(e.contains(field) && e.contains(reason), "{to}: {e}");
    }
}

#[test]
fn granular_grain_cells_2_pow_63_is_refused_against_the_grid() {
    let good = text("granular-small");
    let e = load_error(
        "grain-cells",
        &good.replace(
            "grain_cells = [1, 3]",
            "grain_cells = [1, 9223372036854775807]",
        ),
    );
    assert!(
        e.contains("granular.grain_cells") && e.contains("at most 64"),
        "{e}"
    );
    // the largest grain the grid holds is accepted, and the layout is drawn at once: one grain
    // of up to every cell on a 20³ grid
    let mut spec = scene::load(&asset("granular-small")).expect("scene");
    let g = spec.granular.as_mut().expect("table");
    g.grid = [20, 20, 20];
    g.grains = 1;
    g.grain_cells = [1, 8000];
    let layout = scene::granular::layout(g, "big.toml").expect("one grain fits");
    assert_eq!(layout.grains.len(), 1);
    let n = layout.grains[0].len();
    assert!((1..=8000).contains(&n), "{n}");
}

#[test]
fn granular_40_cubed_one_hexahedron_is_admitted_from_its_numbers() {
    let mut spec = scene::load(&asset("granular-small")).expect("scene");
    let g = spec.granular.as_mut().expect("table");
    g.grid = [40, 40, 40];
    g.cell_elements = 1;
    use lopin_core::scene::admission::{footprint, SolveShape};
    let shape = SolveShape::smallest();
    let counted = footprint(&spec, "g40.toml", shape).expect("counts from the table");
    // the expanded scene (one body per cell) is counted too, each face against its neighbours
    // only: the same substructures, elements and nodes
    let expanded = scene::granular::expand(&spec, "g40.toml").expect("expands");
    assert_eq!(expanded.bodies.len(), 64_000);
    let listed = footprint(&expanded, "g40.toml", shape).expect("counts the listed bodies");
    assert_eq!(counted.substructures, 64_000);
    assert_eq!(listed.substructures, counted.substructures);
    assert_eq!(listed.elements, counted.elements);
    assert_eq!(listed.nodes, counted.nodes);
    // every inner face is touched on both sides: 3 · 39 · 40² inner faces of 4 nodes, 6
    // entries per node pair; the top and bottom faces carry one and three components
    let inner = 3 * 39 * 40 * 40 * 4 * 6;
    let loaded = 40 * 40 * 4 * (1 + 3);
    assert_eq!(listed.trace_entries, inner + loaded);
    assert_eq!(counted.trace_entries, listed.trace_entries);
    // and about the same memory: identical cells share their stiffness and their
    // factorizations (at most 27 per material), listed or generated; the table counts every
    // grain at its largest size, an upper bound of the grains drawn
    assert!(
        (27..=counted.factorizations).contains(&listed.factorizations),
        "{} listed, {} from the table",
        listed.factorizations,
        counted.factorizations
    );
    let bytes = listed.total_bytes() as f64 / counted.total_bytes() as f64;
    println!(
        "40³ cells: counted from the table {} B, from the listed bodies {} B",
        counted.total_bytes(),
        listed.total_bytes()
    );
    assert!((0.9..=1.0).contains(&bytes), "listed/table {bytes}");
}

#[test]
fn divisions_100000_1_1_is_refused_as_too_elongated() {
    let good = text("two-blocks");
    let e = load_error(
        "aspect",
        &good.replacen("divisions = [10, 10, 5]", "divisions = [100000, 1, 1]", 1),
    );
    assert!(
        e.contains("body[0].divisions") && e.contains("times longer than wide"),
        "{e}"
    );
}

#[test]
fn a_failed_factorization_names_the_body_node_and_elements() {
    use lopin_core::{Settings, Solver};
    let spec = scene::load("two-blocks").expect("scene");
    let mut problem = scene::problem_of(&spec, "two-blocks").expect("builds");
    let body = problem.subs[0].body.clone();
    let x = problem.subs[0].mesh.nodes[17];
    // a negative lumped mass on node 17, y: S is no longer positive definite there
    problem.subs[0].mass[3 * 17 + 1] = -1e3;
    let settings = Settings::for_problem(&problem, &spec.solver);
    let e = Solver::new(problem, settings)
        .expect_err("not positive definite")
        .to_string();
    println!("{e}");
    assert!(
        e.contains("not positive definite at node 17")
            && e.contains(&format!("{:.6e}", x[0]))
            && e.contains(&format!("of body `{body}`"))
            && e.contains("component y")
            && e.contains("element")
            && e.contains("lumped mass -1e3 kg"),
        "{e}"
    );
}

#[test]
fn mesh_body_scenes_are_counted_by_admission_not_as_zero_bytes() {
    use lopin_core::estimate::Estimate;
    use lopin_core::scene::admission::{footprint, footprint_with_meshes, MeshSize, SolveShape};
    use lopin_core::{Settings, Solver};
    let dir = std::env::temp_dir().join(format!("lopin-reliability-count-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    std::fs::write(dir.join("column.msh"), write(&stacked_cubes(6, 0.01), true)).expect("msh");
    let path = dir.join("column.toml");
    let scene_text = column_scene("", 2);
    std::fs::write(&path, &scene_text).expect("scene");
    let source = path.display().to_string();
    let spec = scene::load(&source).expect("loads");
    let problem = scene::problem_of(&spec, &source).expect("builds");
    let shape = SolveShape::smallest();
    // before the files are read: each body counted with every node its file announces
    let announced = footprint(&spec, &source, shape).expect("counts");
    let sizes: Vec<MeshSize> = spec
        .mesh_bodies
        .iter()
        .map(|b| {
            let subs: Vec<_> = problem.subs.iter().filter(|s| s.body == b.name).collect();
            MeshSize {
                nodes: subs.iter().map(|s| s.mesh.nodes.len()).sum(),
                substructures: subs.len(),
            }
        })
        .collect();
    assert_eq!(sizes[1].substructures, 2);
    let fp = footprint_with_meshes(&spec, &source, shape, &sizes).expect("counts the meshes");
    let settings = Settings::for_problem(&problem, &spec.solver);
    let built = Estimate::of(&problem, &settings);
    let solver = Solver::new(problem, settings).expect("factorizes");
    let measured = Estimate::of_solver(&solver);
    let dofs = fp.dofs as f64 / built.dofs as f64;
    let ops = fp.operator_bytes as f64 / built.operator_bytes as f64;
    let factors = fp.factor_bytes as f64 / measured.factor_bytes.expect("factors") as f64;
    let trace = fp.trace_entries as f64 / built.trace_entries as f64;
    println!(
        "mesh bodies counted/built: dofs {dofs:.2}, operators {ops:.2}, trace {trace:.2}, \
         factors estimated/measured {factors:.2}"
    );
    // counted as cubes of hexahedra holding the same nodes: the dofs within 25 %, and no part
    // of the memory under-counted by more than a factor of 2
    assert!((0.75..=1.25).contains(&dofs), "dofs {dofs}");
    assert!(ops >= 0.5, "operators {ops}");
    assert!(trace >= 1.0, "trace {trace}");
    assert!(factors >= 0.5, "factors {factors}");
    // the announced count bounds the count from the meshes read (both bodies share one file)
    assert!(
        announced.dofs >= fp.dofs && announced.total_bytes() >= fp.total_bytes(),
        "announced {announced:?}, read {fp:?}"
    );
}
