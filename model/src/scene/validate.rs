//! Validation of a scene before anything is built: every field checked, errors naming the
//! source (file or built-in scene), the field and the reason. Besides each field's own range
//! (positive, finite, Poisson's ratio in (−1, 0.5), counts of at least 1, arrays of exactly
//! their length through [`super::exact`]), the dimensional inputs lie in ranges wide enough for
//! SI models from gels to diamond and for dimensionless ones, and fields are judged against each
//! other: Δt against the wave transit time of the smallest element, velocities against the
//! slowest wave speed (small strains), tractions against E, gaps against the model size, k
//! against the impedance √(ρE) (METHOD §10); bodies may touch but not overlap; and the smallest
//! solve the scene allows must fit this machine ([`admission`]), so that nothing too large is
//! expanded or meshed.

use std::collections::HashMap;

use crate::elements::material::{self, Material};
use crate::error::{LopinError, Result};
use crate::interfaces::detect::model_diameter;
use crate::interfaces::interface::{BoundaryDof, DofLaw};
use crate::scene::admission::{self, SolveShape};
use crate::scene::build::face_of;
use crate::scene::granular;
use crate::scene::granular_poly;
use crate::scene::spec::{BoundarySpec, ComponentSpec, ElementKind, InterfaceKind, SceneSpec};
use crate::time::time_function::TimeFunction;

/// Checks every field of a scene; `source` names the file or built-in scene in errors. A
/// granular scene is checked as its `[granular]` table, then as the scene it expands to.
pub fn validate(spec: &SceneSpec, source: &str) -> Result<()> {
    if spec.granular_poly.is_some() {
        // the table alone: the generated scene is checked when it is built (after meshing)
        return granular_poly::validate(spec, source);
    }
    if spec.granular.is_some() {
        // counted and admitted before the table is expanded into one body per cell
        granular::validate(spec, source)?;
        admission::admit(spec, source, SolveShape::smallest())?;
        // a generated body, interface or boundary is the [granular] table's doing: say so
        return validate_expanded(&granular::expand(spec, source)?, source, Generated::Yes)
            .map_err(|e| match e {
                LopinError::Scene {
                    source_name,
                    field,
                    reason,
                } if ["body", "interface", "boundary"]
                    .iter()
                    .any(|p| field.starts_with(p)) =>
                {
                    LopinError::Scene {
                        source_name,
                        field: format!("granular (generated {field})"),
                        reason,
                    }
                }
                other => other,
            });
    }
    validate_expanded(spec, source, Generated::No)
}

/// Whether the bodies of a scene were generated (by a `[granular]` table, admitted before its
/// expansion and laid out without overlaps) or listed by the user.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Generated {
    Yes,
    No,
}

/// Ranges of the dimensional inputs: wide enough for SI models from gels to diamond and for
/// dimensionless models (E = ρ = 1), narrow enough that no product the solver forms overflows.
const YOUNG_RANGE: (f64, f64) = (1e-3, 1e13);
const DENSITY_RANGE: (f64, f64) = (1e-3, 1e5);
const LENGTH_RANGE: (f64, f64) = (1e-9, 1e5);
/// Largest ratio of a box body's element edges (longest over shortest).
const MAX_ASPECT: f64 = 1e3;
/// The time step relative to the wave transit time of the smallest element, h_min / c_max (the
/// trapezoidal rule is stable for any Δt; outside this range the time grid is absurd for the
/// mesh: every wave crosses 10⁴ elements per step, or needs 10⁴ steps to cross one).
const COURANT_RANGE: (f64, f64) = (1e-4, 1e4);

/// The friction coefficients a contact accepts: measured Coulomb coefficients of engineering
/// pairs lie below about 1.5 (clean metals in vacuum reach a few); beyond 10 every contact
/// sticks, and a larger value only slows the iteration (the local stage's slip threshold f·|F_n|
/// outgrows every tangential force it is compared with).
pub const FRICTION_RANGE: (f64, f64) = (0.0, 10.0);

/// Checks a friction coefficient against [`FRICTION_RANGE`]; the reason names the range.
pub fn check_friction(f: f64) -> std::result::Result<(), String> {
    if f.is_finite() && (FRICTION_RANGE.0..=FRICTION_RANGE.1).contains(&f) {
        return Ok(());
    }
    Err(format!(
        "a friction coefficient lies in [{}, {}], got {f:?}",
        FRICTION_RANGE.0, FRICTION_RANGE.1
    ))
}

/// The search direction k relative to the impedance scale k0 = mean √(ρE) of the materials in
/// use (METHOD §10) that a solve accepts (the stress suite converges from 10⁻³ to 10³ k0, slowly
/// at the ends).
pub const K_RANGE: (f64, f64) = (1e-6, 1e6);

/// Checks a scene whose bodies are listed.
fn validate_expanded(spec: &SceneSpec, source: &str, generated: Generated) -> Result<()> {
    let err = |field: String, reason: String| Err(LopinError::scene(source, field, reason));
    let positive = |x: f64| x.is_finite() && x > 0.0;
    if !positive(spec.time.dt) {
        return err(
            "time.dt".into(),
            format!(
                "must be a positive number of seconds, got {:?}",
                spec.time.dt
            ),
        );
    }
    if spec.time.steps == 0 {
        return err("time.steps".into(), "must be at least 1".into());
    }
    for (name, axes) in [
        ("refine_axes", &spec.refine_axes),
        ("split_axes", &spec.split_axes),
    ] {
        if axes.chars().any(|c| !"xyz".contains(c)) {
            return err(
                name.into(),
                format!("only the letters x, y, z are allowed, got `{axes}`"),
            );
        }
    }
    let s = &spec.solver;
    if let Some(tol) = s.tol {
        if !positive(tol) {
            return err("solver.tol".into(), format!("must be positive, got {tol}"));
        }
    }
    if let Some(mu) = s.mu {
        if !(mu > 0.0 && mu <= 1.0) {
            return err("solver.mu".into(), format!("must lie in (0, 1], got {mu}"));
        }
    }
    if let Some(k) = s.k {
        if !positive(k) {
            return err("solver.k".into(), format!("must be positive, got {k}"));
        }
    }
    if let Some(r) = s.rho_inf {
        if let Err(reason) = crate::time::time_scheme::TimeScheme::new(r).check() {
            return err("solver.rho_inf".into(), reason);
        }
    }
    if s.window == Some(0) {
        return err("solver.window".into(), "must be at least 1 step".into());
    }
    if s.max_iter == Some(0) {
        return err(
            "solver.max_iter".into(),
            "must be at least 1 iteration".into(),
        );
    }
    if let Some(tol) = s.tol {
        if tol >= 1.0 {
            return err(
                "solver.tol".into(),
                format!("must be below 1 (η is a relative error), got {tol}"),
            );
        }
    }
    if spec.materials.is_empty() {
        return err(
            "material".into(),
            "at least one [[material]] is needed".into(),
        );
    }
    for (i, m) in spec.materials.iter().enumerate() {
        if spec.materials[..i].iter().any(|o| o.name == m.name) {
            return err(
                format!("material[{i}].name"),
                format!("duplicate material name `{}`", m.name),
            );
        }
        if !in_range(m.young, YOUNG_RANGE) {
            return err(
                format!("material[{i}].young"),
                format!(
                    "must be positive, within [{:e}, {:e}] Pa, got {:?}",
                    YOUNG_RANGE.0, YOUNG_RANGE.1, m.young
                ),
            );
        }
        if !(m.poisson.is_finite() && m.poisson > -1.0 && m.poisson < 0.5) {
            return err(
                format!("material[{i}].poisson"),
                format!("must lie in (-1, 0.5), got {:?}", m.poisson),
            );
        }
        if !in_range(m.density, DENSITY_RANGE) {
            return err(
                format!("material[{i}].density"),
                format!(
                    "must be positive, within [{:e}, {:e}] kg/m³, got {:?}",
                    DENSITY_RANGE.0, DENSITY_RANGE.1, m.density
                ),
            );
        }
    }
    if spec.bodies.is_empty() && spec.mesh_bodies.is_empty() {
        return err(
            "body".into(),
            "at least one [[body]] or [[mesh_body]] (or a [granular] table) is needed".into(),
        );
    }
    let mut body_index: HashMap<&str, usize> = HashMap::with_capacity(spec.bodies.len());
    for (i, b) in spec.bodies.iter().enumerate() {
        if body_index.insert(&b.name, i).is_some() {
            return err(
                format!("body[{i}].name"),
                format!("duplicate body name `{}`", b.name),
            );
        }
        if !spec.materials.iter().any(|m| m.name == b.material) {
            return err(
                format!("body[{i}].material"),
                format!("no material named `{}`", b.material),
            );
        }
        for a in 0..3 {
            let axis = ["x", "y", "z"][a];
            if !(b.min[a].is_finite() && b.max[a].is_finite() && b.max[a] > b.min[a]) {
                return err(
                    format!("body[{i}].max"),
                    format!(
                        "max.{axis} = {:?} must exceed min.{axis} = {:?}",
                        b.max[a], b.min[a]
                    ),
                );
            }
            if b.divisions[a] == 0 {
                return err(
                    format!("body[{i}].divisions"),
                    format!("{axis} division must be at least 1"),
                );
            }
            if b.split[a] == 0 || b.divisions[a] % b.split[a] != 0 {
                return err(
                    format!("body[{i}].split"),
                    format!(
                        "{axis}: {} substructures do not divide {} hexahedra",
                        b.split[a], b.divisions[a]
                    ),
                );
            }
        }
        if b.velocity.iter().any(|v| !v.is_finite()) {
            return err(format!("body[{i}].velocity"), "must be finite".into());
        }
        if let Some(n) = b.substructures {
            let elements = b.divisions.iter().product::<usize>()
                * match b.elements.unwrap_or_default() {
                    ElementKind::Hex8 => 1,
                    ElementKind::Tet4 => 6,
                };
            check_substructures(n, elements)
                .map_err(|r| LopinError::scene(source, format!("body[{i}].substructures"), r))?;
            if b.split != [1, 1, 1] {
                return err(
                    format!("body[{i}].substructures"),
                    "give either `split` (a grid of boxes) or `substructures` (cut by the graph \
                     partitioner), not both"
                        .into(),
                );
            }
        }
    }
    let mut pairs: HashMap<(usize, usize), usize> = HashMap::with_capacity(spec.interfaces.len());
    for (i, b) in spec.mesh_bodies.iter().enumerate() {
        if body_index.insert(&b.name, spec.bodies.len() + i).is_some() {
            return err(
                format!("mesh_body[{i}].name"),
                format!("duplicate body name `{}`", b.name),
            );
        }
        if !spec.materials.iter().any(|m| m.name == b.material) {
            return err(
                format!("mesh_body[{i}].material"),
                format!("no material named `{}`", b.material),
            );
        }
        if b.mesh.trim().is_empty() {
            return err(
                format!("mesh_body[{i}].mesh"),
                "give the .msh file (relative to the scene file)".into(),
            );
        }
        if !b.velocity.iter().all(|v| v.is_finite()) {
            return err(
                format!("mesh_body[{i}].velocity"),
                format!("must be finite, got {:?}", b.velocity),
            );
        }
        if let Some(n) = b.substructures {
            check_substructures(n, usize::MAX).map_err(|r| {
                LopinError::scene(source, format!("mesh_body[{i}].substructures"), r)
            })?;
        }
    }
    for (i, it) in spec.interfaces.iter().enumerate() {
        for (j, name) in it.bodies.iter().enumerate() {
            if !body_index.contains_key(name.as_str()) {
                return err(
                    format!("interface[{i}].bodies[{j}]"),
                    format!("no body named `{name}`"),
                );
            }
        }
        if it.bodies[0] == it.bodies[1] {
            return err(
                format!("interface[{i}].bodies"),
                "the two bodies must differ".into(),
            );
        }
        if let Some(first) = pairs.insert(pair_key(&body_index, &it.bodies), i) {
            return err(
                format!("interface[{i}].bodies"),
                format!(
                    "bodies `{}` and `{}` already have an override (interface[{first}])",
                    it.bodies[0], it.bodies[1]
                ),
            );
        }
        let contact = it.kind == InterfaceKind::Contact;
        for (field, value) in [
            ("friction", it.friction),
            ("gap", it.gap),
            ("search", it.search),
        ] {
            if let Some(v) = value {
                if !contact {
                    return err(
                        format!("interface[{i}].{field}"),
                        format!("only a contact interface takes `{field}`"),
                    );
                }
                if !(v.is_finite() && v >= 0.0) {
                    return err(
                        format!("interface[{i}].{field}"),
                        format!("must be a non-negative number, got {v}"),
                    );
                }
                if field == "friction" {
                    check_friction(v).map_err(|r| {
                        LopinError::scene(source, format!("interface[{i}].friction"), r)
                    })?;
                }
            }
        }
    }
    let mut boundary_places: HashMap<(&str, &str, Option<&str>), usize> = HashMap::new();
    for (i, bc) in spec.boundaries.iter().enumerate() {
        let place = (bc.body.as_str(), bc.face.as_str(), bc.surface.as_deref());
        if let Some(first) = boundary_places.insert(place, i) {
            return err(
                format!("boundary[{i}]"),
                format!(
                    "repeats boundary[{first}]: both act on {} of `{}`; give each face or \
                     surface one [[boundary]] entry (its x, y and z components together)",
                    bc.surface
                        .as_ref()
                        .map_or_else(|| format!("face {}", bc.face), |s| format!("surface `{s}`")),
                    bc.body
                ),
            );
        }
        let Some(&body) = body_index.get(bc.body.as_str()) else {
            return err(
                format!("boundary[{i}].body"),
                format!("no body named `{}`", bc.body),
            );
        };
        if body >= spec.bodies.len() {
            // a mesh body: a physical surface, not a box face
            if bc.surface.is_none() || !bc.face.is_empty() {
                return err(
                    format!("boundary[{i}].surface"),
                    format!(
                        "`{}` is a mesh body: name a physical surface of its file with `surface = \"...\"` (not a box `face`)",
                        bc.body
                    ),
                );
            }
            boundary_dofs(bc).map_err(|(field, reason)| {
                LopinError::scene(source, format!("boundary[{i}].{field}"), reason)
            })?;
            continue;
        }
        if bc.surface.is_some() {
            return err(
                format!("boundary[{i}].surface"),
                format!(
                    "`{}` is a box body: its boundaries name a `face` (x-, x+, y-, y+, z-, z+); \
                     physical surfaces belong to [[mesh_body]] bodies",
                    bc.body
                ),
            );
        }
        if face_of(&bc.face).is_none() {
            return err(
                format!("boundary[{i}].face"),
                format!("expected one of x-, x+, y-, y+, z-, z+, got `{}`", bc.face),
            );
        }
        boundary_dofs(bc).map_err(|(field, reason)| {
            LopinError::scene(source, format!("boundary[{i}].{field}"), reason)
        })?;
    }
    check_physics(spec, source)?;
    check_ramps(spec, source)?;
    if let Some(k) = spec.solver.k {
        check_k(spec, source, k)?;
    }
    if generated == Generated::No {
        check_overlaps(spec, source)?;
        admission::admit(spec, source, SolveShape::smallest())?;
    }
    Ok(())
}

/// The checks that relate fields to each other: sizes and coordinates in range, the time step
/// against the wave transit time of the smallest element, velocities against the slowest wave
/// speed (small strains), tractions against the stiffness, gaps against the model size.
fn check_physics(spec: &SceneSpec, source: &str) -> Result<()> {
    let err = |field: String, reason: String| Err(LopinError::scene(source, field, reason));
    let material = |name: &str| {
        spec.materials
            .iter()
            .find(|m| m.name == name)
            .map(|m| Material {
                young: m.young,
                poisson: m.poisson,
                density: m.density,
            })
    };
    let mut h_min = f64::INFINITY;
    for (i, b) in spec.bodies.iter().enumerate() {
        let edges: [f64; 3] =
            std::array::from_fn(|a| (b.max[a] - b.min[a]) / b.divisions[a] as f64);
        for a in 0..3 {
            for (field, x) in [("min", b.min[a]), ("max", b.max[a])] {
                if x.abs() > LENGTH_RANGE.1 {
                    return err(
                        format!("body[{i}].{field}"),
                        format!(
                            "{field}.{} = {x:?} m lies beyond ±{:e} m",
                            ["x", "y", "z"][a],
                            LENGTH_RANGE.1
                        ),
                    );
                }
            }
            let h = edges[a];
            if h < LENGTH_RANGE.0 {
                return err(
                    format!("body[{i}].divisions"),
                    format!(
                        "{} hexahedra along {} make elements of {h:e} m, below {:e} m",
                        b.divisions[a],
                        ["x", "y", "z"][a],
                        LENGTH_RANGE.0
                    ),
                );
            }
            h_min = h_min.min(h);
        }
        let aspect = edges.iter().fold(0.0f64, |m, &x| m.max(x))
            / edges.iter().fold(f64::MAX, |m, &x| m.min(x));
        if aspect > MAX_ASPECT {
            return err(
                format!("body[{i}].divisions"),
                format!(
                    "{:?} hexahedra make elements {aspect:.3e} times longer than wide ({:.3e} × \
                     {:.3e} × {:.3e} m); Lopin accepts at most {MAX_ASPECT:e} (a trilinear \
                     element that elongated locks): divide the axes in proportion to the lengths",
                    b.divisions, edges[0], edges[1], edges[2]
                ),
            );
        }
    }
    let boxes: Vec<_> = spec.bodies.iter().map(|b| (b.min, b.max)).collect();
    let diameter = model_diameter(&boxes);
    let body_materials = || {
        spec.bodies
            .iter()
            .map(|b| b.material.as_str())
            .chain(spec.mesh_bodies.iter().map(|b| b.material.as_str()))
    };
    let used: Vec<Material> = body_materials().filter_map(material).collect();
    let c_max = used.iter().map(Material::p_wave_speed).fold(0.0, f64::max);
    let slowest = material::slowest(
        body_materials().filter_map(|name| material(name).map(|m| (m.bar_speed(), name))),
    );
    let transit = h_min / c_max;
    let courant = spec.time.dt / transit;
    // (the elements of mesh bodies are known once their files are read: they are measured by
    // [`check_mesh_time_step`] when the scene is built)
    if h_min.is_finite() && !in_range(courant, COURANT_RANGE) {
        return err(
            "time.dt".into(),
            format!(
                "{:?} s is {courant:.3e} times the time a P wave takes to cross the smallest \
                 element ({transit:.3e} s = {h_min:.3e} m / {c_max:.3e} m/s); Lopin accepts {:e} \
                 to {:e} times it",
                spec.time.dt, COURANT_RANGE.0, COURANT_RANGE.1
            ),
        );
    }
    for (i, b) in spec.bodies.iter().enumerate() {
        for &v in &b.velocity {
            material::check_small_strain_speed(v, slowest)
                .map_err(|r| LopinError::scene(source, format!("body[{i}].velocity"), r))?;
        }
    }
    for (i, b) in spec.mesh_bodies.iter().enumerate() {
        for &v in &b.velocity {
            material::check_small_strain_speed(v, slowest)
                .map_err(|r| LopinError::scene(source, format!("mesh_body[{i}].velocity"), r))?;
        }
    }
    for (i, bc) in spec.boundaries.iter().enumerate() {
        let young = spec
            .bodies
            .iter()
            .find(|b| b.name == bc.body)
            .and_then(|b| material(&b.material))
            .map_or(f64::INFINITY, |m| m.young);
        for (axis, c) in bc.components() {
            let Some(c) = c else { continue };
            if let Some(v) = c.velocity {
                material::check_small_strain_speed(v, slowest).map_err(|r| {
                    LopinError::scene(source, format!("boundary[{i}].{axis}.velocity"), r)
                })?;
            }
            if let Some(t) = c.traction.filter(|t| t.abs() > young) {
                return err(
                    format!("boundary[{i}].{axis}.traction"),
                    format!(
                        "{t:?} Pa exceeds the Young's modulus {young:e} Pa of the body's \
                         material: the strains would not be small"
                    ),
                );
            }
        }
    }
    for (i, it) in spec.interfaces.iter().enumerate() {
        for (field, value) in [("gap", it.gap), ("search", it.search)] {
            if let Some(v) = value.filter(|v| *v > diameter) {
                return err(
                    format!("interface[{i}].{field}"),
                    format!("{v:?} m exceeds the size of the whole model ({diameter:.4e} m)"),
                );
            }
        }
    }
    Ok(())
}

/// `solver.k` within [`K_RANGE`] times k0, the mean √(ρE) of the materials the bodies use.
fn check_k(spec: &SceneSpec, source: &str, k: f64) -> Result<()> {
    let mut used: Vec<&str> = spec
        .bodies
        .iter()
        .map(|b| b.material.as_str())
        .chain(spec.mesh_bodies.iter().map(|b| b.material.as_str()))
        .collect();
    used.sort_unstable();
    used.dedup();
    let impedances: Vec<f64> = spec
        .materials
        .iter()
        .filter(|m| used.contains(&m.name.as_str()))
        .map(|m| (m.density * m.young).sqrt())
        .collect();
    let k0 = impedances.iter().sum::<f64>() / impedances.len().max(1) as f64;
    check_k_against(k, k0).map_err(|reason| LopinError::scene(source, "solver.k", reason))
}

/// The search direction k against the impedance scale k0: within [`K_RANGE`] times it, or the
/// reason it is not (shared by the scene check and the solver's settings check).
pub fn check_k_against(k: f64, k0: f64) -> std::result::Result<(), String> {
    let ratio = k / k0;
    if ratio >= K_RANGE.0 && ratio <= K_RANGE.1 {
        return Ok(());
    }
    Err(format!(
        "{k:?} Pa·s/m is {ratio:.3e} times the model's impedance √(ρE) = {k0:.4e} Pa·s/m; \
         LATIN needs k within {:e} to {:e} times it",
        K_RANGE.0, K_RANGE.1
    ))
}

/// Bodies may touch but not overlap: a positive-volume intersection of two boxes is an error
/// naming both bodies and the overlap (bodies sorted along x, each compared with those whose x
/// ranges meet it).
fn check_overlaps(spec: &SceneSpec, source: &str) -> Result<()> {
    let mut order: Vec<usize> = (0..spec.bodies.len()).collect();
    order.sort_by(|&a, &b| spec.bodies[a].min[0].total_cmp(&spec.bodies[b].min[0]));
    for (k, &i) in order.iter().enumerate() {
        let a = &spec.bodies[i];
        for &j in &order[k + 1..] {
            let b = &spec.bodies[j];
            if b.min[0] >= a.max[0] {
                break;
            }
            let overlap: [(f64, f64); 3] =
                std::array::from_fn(|c| (a.min[c].max(b.min[c]), a.max[c].min(b.max[c])));
            let tol = |c: usize| 1e-9 * (a.max[c] - a.min[c]).min(b.max[c] - b.min[c]);
            if (0..3).all(|c| overlap[c].1 - overlap[c].0 > tol(c)) {
                let (first, second) = (i.min(j), i.max(j));
                return Err(LopinError::scene(
                    source,
                    format!("body[{second}]"),
                    format!(
                        "bodies `{}` and `{}` overlap over [{:?}, {:?}] × [{:?}, {:?}] × [{:?}, \
                         {:?}] m (bodies may touch, not overlap)",
                        spec.bodies[first].name,
                        spec.bodies[second].name,
                        overlap[0].0,
                        overlap[0].1,
                        overlap[1].0,
                        overlap[1].1,
                        overlap[2].0,
                        overlap[2].1
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// The prescribed dofs of a boundary, or (field, reason).
pub(crate) fn boundary_dofs(
    bc: &BoundarySpec,
) -> std::result::Result<Vec<BoundaryDof>, (String, String)> {
    let comps = bc.components();
    if bc.clamped {
        if comps.iter().any(|(_, c)| c.is_some()) {
            return Err((
                "clamped".into(),
                "clamped = true cannot be combined with x, y or z".into(),
            ));
        }
        return Ok((0..3)
            .map(|component| BoundaryDof {
                component,
                law: DofLaw::Velocity(TimeFunction::constant(0.0)),
            })
            .collect());
    }
    let mut dofs = Vec::new();
    for (component, (axis, c)) in comps.into_iter().enumerate() {
        let Some(c) = c else { continue };
        dofs.push(BoundaryDof {
            component,
            law: component_law(c).map_err(|r| (axis.to_string(), r))?,
        });
    }
    if dofs.is_empty() {
        return Err((
            "x".into(),
            "a boundary must prescribe at least one component (or clamped = true)".into(),
        ));
    }
    Ok(dofs)
}

/// Checks Δt against the wave transit time of the smallest element of the mesh bodies (known
/// once their files are read; box bodies are checked by [`validate`]): `meshes` holds each mesh
/// body's name, material and mesh. The error names `time.dt`, the body and the element size.
pub fn check_mesh_time_step(
    spec: &SceneSpec,
    source: &str,
    meshes: &[(&str, Material, &crate::mesh::Mesh)],
) -> Result<()> {
    let mut smallest: Option<(f64, &str)> = None;
    let mut c_max: f64 = 0.0;
    for &(body, material, mesh) in meshes {
        c_max = c_max.max(material.p_wave_speed());
        for e in &mesh.elements {
            let n = e.nodes();
            for (i, &a) in n.iter().enumerate() {
                for &b in &n[i + 1..] {
                    let d = crate::mesh::norm(crate::mesh::sub(mesh.nodes[a], mesh.nodes[b]));
                    if smallest.is_none_or(|(h, _)| d < h) {
                        smallest = Some((d, body));
                    }
                }
            }
        }
    }
    let Some((h_min, body)) = smallest else {
        return Ok(());
    };
    let transit = h_min / c_max;
    let courant = spec.time.dt / transit;
    if !in_range(courant, COURANT_RANGE) {
        return Err(LopinError::scene(
            source,
            "time.dt",
            format!(
                "{:?} s is {courant:.3e} times the time a P wave takes to cross the smallest \
                 element edge of mesh body `{body}` ({transit:.3e} s = {h_min:.3e} m / \
                 {c_max:.3e} m/s); Lopin accepts {:e} to {:e} times it",
                spec.time.dt, COURANT_RANGE.0, COURANT_RANGE.1
            ),
        ));
    }
    Ok(())
}

/// Every boundary ramp ends within the run: a ramp the run never finishes leaves the load at a
/// fraction of its value, or never starts it (checked after the time step is).
fn check_ramps(spec: &SceneSpec, source: &str) -> Result<()> {
    let duration = spec.time.steps as f64 * spec.time.dt;
    let run = short(duration);
    for (i, bc) in spec.boundaries.iter().enumerate() {
        for (axis, c) in bc.components() {
            let Some(c) = c else { continue };
            if c.ramp_time > duration * (1.0 + 1e-9) {
                return Err(LopinError::scene(
                    source,
                    format!("boundary[{i}].{axis}.ramp_time"),
                    format!(
                        "a ramp of {:?} s is longer than the run ({} s = time.steps × \
                         time.dt): the load would never reach its value; at most {} s",
                        c.ramp_time, run, run
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// `x` with at most 6 significant digits, in the shortest form that keeps them.
fn short(x: f64) -> String {
    format!("{:?}", format!("{x:.5e}").parse::<f64>().unwrap_or(x))
}

/// The reason when `n` substructures cannot be cut from a body of `elements` elements (a build
/// without the graph partitioner, the web build, refuses n > 1 when it builds the scene).
fn check_substructures(n: usize, elements: usize) -> std::result::Result<(), String> {
    if n == 0 {
        return Err("must be at least 1".into());
    }
    if n > elements {
        return Err(format!(
            "{n} substructures asked of a body of {elements} elements (at most one per element)"
        ));
    }
    Ok(())
}

fn component_law(c: &ComponentSpec) -> std::result::Result<DofLaw, String> {
    if !(c.ramp_time.is_finite() && c.ramp_time >= 0.0) {
        return Err(format!(
            "ramp_time must be a non-negative number, got {:?}",
            c.ramp_time
        ));
    }
    let f = |amplitude: f64| TimeFunction {
        amplitude,
        ramp: c.ramp,
        ramp_time: c.ramp_time,
    };
    match (c.velocity, c.traction) {
        (Some(v), None) if v.is_finite() => Ok(DofLaw::Velocity(f(v))),
        (None, Some(t)) if t.is_finite() => Ok(DofLaw::Traction(f(t))),
        (Some(_), Some(_)) => Err("give either `velocity` or `traction`, not both".into()),
        (None, None) => Err("give `velocity` or `traction`".into()),
        _ => Err("value must be finite".into()),
    }
}

/// The unordered pair of two (existing) body names as ordered body indices.
pub(crate) fn pair_key(body_index: &HashMap<&str, usize>, bodies: &[String; 2]) -> (usize, usize) {
    let a = body_index
        .get(bodies[0].as_str())
        .copied()
        .unwrap_or_default();
    let b = body_index
        .get(bodies[1].as_str())
        .copied()
        .unwrap_or_default();
    (a.min(b), a.max(b))
}

fn in_range(x: f64, (lo, hi): (f64, f64)) -> bool {
    x.is_finite() && x >= lo && x <= hi
}
