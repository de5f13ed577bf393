//! Each field of a scene checked on its own: the time grid, the `[solver]` table, the
//! materials, the box bodies and the mesh bodies (ranges in [`super::ranges`]).

use std::collections::HashMap;

use crate::error::{LopinError, Result};
use crate::scene::spec::{ElementKind, MaterialSpec, SceneSpec, SolverSpec};

use super::ranges::{check_substructures, in_range, DENSITY_RANGE, YOUNG_RANGE};

/// The time grid and the refinement axes.
pub(super) fn check_time(spec: &SceneSpec, source: &str) -> Result<()> {
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
    Ok(())
}

/// The `[solver]` table: each setting within its range (k against the materials is checked
/// with the relations, [`super::relations`]).
pub(super) fn check_solver(s: &SolverSpec, source: &str) -> Result<()> {
    let err = |field: String, reason: String| Err(LopinError::scene(source, field, reason));
    let positive = |x: f64| x.is_finite() && x > 0.0;
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
    if s.window == Some(crate::window_choice::WindowRequest::Steps(0)) {
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
    Ok(())
}

/// The materials: at least one, names unique, E, ν and ρ in range.
pub(super) fn check_materials(spec: &SceneSpec, source: &str) -> Result<()> {
    let err = |field: String, reason: String| Err(LopinError::scene(source, field, reason));
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
        check_damping(m, &|key, reason| {
            LopinError::scene(source, format!("material[{i}].{key}"), reason)
        })?;
    }
    Ok(())
}

/// A material's Rayleigh damping: `alpha` and `beta` finite and ≥ 0, or `damping_ratio` in
/// (0, 1) with a `damping_band` of two positive frequencies in increasing order, not both ways.
fn check_damping(m: &MaterialSpec, err: &dyn Fn(&str, String) -> LopinError) -> Result<()> {
    let by_ratio = m.damping_ratio.is_some() || m.damping_band.is_some();
    if by_ratio && (m.alpha.is_some() || m.beta.is_some()) {
        let key = if m.alpha.is_some() { "alpha" } else { "beta" };
        return Err(err(
            key,
            "give the damping either as `alpha`/`beta` or as `damping_ratio` with \
             `damping_band`, not both"
                .into(),
        ));
    }
    if let Some(z) = m.damping_ratio {
        if !(z.is_finite() && z > 0.0 && z < 1.0) {
            return Err(err(
                "damping_ratio",
                format!("must lie in (0, 1), got {z:?}"),
            ));
        }
    }
    if let Some([f1, f2]) = m.damping_band {
        if !(f1.is_finite() && f2.is_finite() && f1 > 0.0 && f2 > f1) {
            return Err(err(
                "damping_band",
                format!("must be two frequencies in Hz with 0 < f1 < f2, got [{f1:?}, {f2:?}]"),
            ));
        }
    }
    match (m.damping_ratio, m.damping_band) {
        (Some(_), None) => {
            return Err(err(
                "damping_ratio",
                "needs `damping_band = [f1, f2]`, the two frequencies (Hz) where the ratio holds"
                    .into(),
            ))
        }
        (None, Some(_)) => {
            return Err(err(
                "damping_band",
                "needs `damping_ratio`, the ratio ζ at both frequencies".into(),
            ))
        }
        _ => {}
    }
    for (key, x) in [("alpha", m.alpha), ("beta", m.beta)] {
        if let Some(x) = x {
            if !(x.is_finite() && x >= 0.0) {
                return Err(err(
                    key,
                    format!("must be a finite number ≥ 0 (C = alpha M + beta K), got {x:?}"),
                ));
            }
        }
    }
    Ok(())
}

/// The box bodies: names unique, materials known, boxes non-empty, divisions and splits
/// consistent. Returns the index of each body name (box bodies first).
pub(super) fn check_boxes<'a>(
    spec: &'a SceneSpec,
    source: &str,
) -> Result<HashMap<&'a str, usize>> {
    let err = |field: String, reason: String| Err(LopinError::scene(source, field, reason));
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
    Ok(body_index)
}

/// The mesh bodies: names unique among all bodies (added to `body_index`), materials known,
/// a file named, velocities finite.
pub(super) fn check_mesh_bodies<'a>(
    spec: &'a SceneSpec,
    source: &str,
    body_index: &mut HashMap<&'a str, usize>,
) -> Result<()> {
    let err = |field: String, reason: String| Err(LopinError::scene(source, field, reason));
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
    Ok(())
}
