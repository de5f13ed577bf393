//! The checks that relate fields to each other: sizes and coordinates in range, Δt against the
//! wave transit time of the smallest element, velocities against the slowest wave speed (small
//! strains), tractions against E, gaps against the model size, k against the impedance √(ρE)
//! (METHOD §10), ramps within the run, and bodies that touch without overlapping.

use crate::elements::material::{self, Material};
use crate::error::{LopinError, Result};
use crate::interfaces::detect::model_diameter;
use crate::scene::spec::{MaterialSpec, SceneSpec};

use super::ranges::{check_k_against, in_range, short, COURANT_RANGE, LENGTH_RANGE, MAX_ASPECT};

/// The checks that relate fields to each other, in this order: box sizes and coordinates in
/// range, the time step against the wave transit time of the smallest box element, velocities
/// against the slowest wave speed (small strains), tractions against the stiffness, gaps and
/// search distances against the model size.
pub(super) fn check_physics(spec: &SceneSpec, source: &str) -> Result<()> {
    let h_min = check_box_sizes(spec, source)?;
    check_box_time_step(spec, source, h_min)?;
    check_loads(spec, source)?;
    check_distances(spec, source)
}

/// The material named `name`, if the scene has one.
fn material_of(spec: &SceneSpec, name: &str) -> Option<Material> {
    spec.materials
        .iter()
        .find(|m| m.name == name)
        .map(MaterialSpec::material)
}

/// The materials of the bodies, by name, in body order (box bodies first).
fn body_materials(spec: &SceneSpec) -> impl Iterator<Item = &str> + Clone {
    spec.bodies
        .iter()
        .map(|b| b.material.as_str())
        .chain(spec.mesh_bodies.iter().map(|b| b.material.as_str()))
}

/// Box coordinates within the length range, element edges above its lower end and not too
/// elongated; returns the smallest box element edge (infinite without box bodies).
fn check_box_sizes(spec: &SceneSpec, source: &str) -> Result<f64> {
    let err = |field: String, reason: String| Err(LopinError::scene(source, field, reason));
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
    Ok(h_min)
}

/// Δt against the wave transit time of the smallest box element (the elements of mesh bodies
/// are known once their files are read: they are measured by [`check_mesh_time_step`] when the
/// scene is built).
fn check_box_time_step(spec: &SceneSpec, source: &str, h_min: f64) -> Result<()> {
    let err = |field: String, reason: String| Err(LopinError::scene(source, field, reason));
    let material = |name: &str| material_of(spec, name);
    let used: Vec<Material> = body_materials(spec).filter_map(material).collect();
    let c_max = used.iter().map(Material::p_wave_speed).fold(0.0, f64::max);
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
    Ok(())
}

/// Initial and prescribed velocities below the slowest wave speed (small strains), tractions
/// below the Young's modulus of the body's material.
fn check_loads(spec: &SceneSpec, source: &str) -> Result<()> {
    let err = |field: String, reason: String| Err(LopinError::scene(source, field, reason));
    let material = |name: &str| material_of(spec, name);
    let slowest = material::slowest(
        body_materials(spec).filter_map(|name| material(name).map(|m| (m.bar_speed(), name))),
    );
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
        if let Some(n) = &bc.normal {
            for (key, value) in [("pressure", n.pressure), ("traction", n.traction)] {
                if let Some(t) = value.filter(|t| t.abs() > young) {
                    return err(
                        format!("boundary[{i}].normal.{key}"),
                        format!(
                            "{t:?} Pa exceeds the Young's modulus {young:e} Pa of the body's \
                             material: the strains would not be small"
                        ),
                    );
                }
            }
        }
        for (k, (axis, c)) in bc.components().into_iter().enumerate() {
            let Some(c) = c else { continue };
            if let Some(v) = c.velocity {
                material::check_small_strain_speed(v, slowest).map_err(|r| {
                    LopinError::scene(source, format!("boundary[{i}].{axis}.velocity"), r)
                })?;
            }
            if c.acceleration.is_some() {
                let start = spec
                    .bodies
                    .iter()
                    .map(|b| (&b.name, b.velocity))
                    .chain(spec.mesh_bodies.iter().map(|b| (&b.name, b.velocity)))
                    .find(|(name, _)| **name == bc.body)
                    .map_or(0.0, |(_, v)| v[k]);
                if start != 0.0 {
                    return err(
                        format!("boundary[{i}].{axis}.acceleration"),
                        format!(
                            "a prescribed acceleration starts from rest, but body `{}` starts \
                             at {start:?} m/s along {axis}",
                            bc.body
                        ),
                    );
                }
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
    Ok(())
}

/// Gaps and search distances no larger than the whole model.
fn check_distances(spec: &SceneSpec, source: &str) -> Result<()> {
    let err = |field: String, reason: String| Err(LopinError::scene(source, field, reason));
    let boxes: Vec<_> = spec.bodies.iter().map(|b| (b.min, b.max)).collect();
    let diameter = model_diameter(&boxes);
    for (i, it) in spec.interfaces.iter().enumerate() {
        for (field, value) in [("gap", it.gap), ("search", it.search)] {
            if let Some(v) = value.filter(|v| v.abs() > diameter) {
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
pub(super) fn check_k(spec: &SceneSpec, source: &str, k: f64) -> Result<()> {
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

/// Bodies may touch but not overlap: a positive-volume intersection of two boxes is an error
/// naming both bodies and the overlap (bodies sorted along x, each compared with those whose x
/// ranges meet it).
pub(super) fn check_overlaps(spec: &SceneSpec, source: &str) -> Result<()> {
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
pub(super) fn check_ramps(spec: &SceneSpec, source: &str) -> Result<()> {
    let duration = spec.time.steps as f64 * spec.time.dt;
    let run = short(duration);
    for (i, bc) in spec.boundaries.iter().enumerate() {
        for (axis, c) in bc.components() {
            let Some(c) = c else { continue };
            #[cfg(feature = "shock")]
            if let Some(d) = c.duration {
                super::ranges::check_pulse_duration(d, duration).map_err(|reason| {
                    LopinError::scene(source, format!("boundary[{i}].{axis}.duration"), reason)
                })?;
            }
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
