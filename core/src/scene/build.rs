//! Turns a scene description into a [`Problem`]: validates every field (errors name the source,
//! the field and the reason), expands a `[granular]` table ([`granular::expand`]), meshes the
//! bodies, cuts them into substructures, detects the interfaces and places the boundary
//! conditions.

use std::collections::HashMap;

use crate::detect::{assemble_traces, boundary_interface, detect_interfaces, PairRule};
use crate::error::{LopinError, Result};
use crate::interface::{BoundaryDof, DofLaw};
use crate::material::Material;
use crate::mesh::{Mesh, Vec3};
use crate::problem::{NamedMaterial, Problem};
use crate::scene::granular;
use crate::scene::spec::{BoundarySpec, ComponentSpec, InterfaceKind, SceneSpec};
use crate::substructure::{StiffnessCache, Substructure};
use crate::time_function::TimeFunction;

/// Faces of a box by name: (axis, sign).
pub fn face_of(name: &str) -> Option<(usize, f64)> {
    match name {
        "x-" => Some((0, -1.0)),
        "x+" => Some((0, 1.0)),
        "y-" => Some((1, -1.0)),
        "y+" => Some((1, 1.0)),
        "z-" => Some((2, -1.0)),
        "z+" => Some((2, 1.0)),
        _ => None,
    }
}

/// Checks every field of a scene; `source` names the file or built-in scene in errors. A
/// granular scene is checked as its `[granular]` table, then as the scene it expands to.
pub fn validate(spec: &SceneSpec, source: &str) -> Result<()> {
    if spec.granular.is_some() {
        return validate_expanded(&granular::expand(spec, source)?, source);
    }
    validate_expanded(spec, source)
}

/// Checks a scene whose bodies are listed.
fn validate_expanded(spec: &SceneSpec, source: &str) -> Result<()> {
    let err = |field: String, reason: String| Err(LopinError::scene(source, field, reason));
    let positive = |x: f64| x.is_finite() && x > 0.0;
    if !positive(spec.time.dt) {
        return err(
            "time.dt".into(),
            format!("must be a positive number of seconds, got {}", spec.time.dt),
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
    if s.window == Some(0) {
        return err("solver.window".into(), "must be at least 1 step".into());
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
        if !positive(m.young) {
            return err(
                format!("material[{i}].young"),
                format!("must be positive, got {}", m.young),
            );
        }
        if !(m.poisson.is_finite() && m.poisson > -1.0 && m.poisson < 0.5) {
            return err(
                format!("material[{i}].poisson"),
                format!("must lie in (-1, 0.5), got {}", m.poisson),
            );
        }
        if !positive(m.density) {
            return err(
                format!("material[{i}].density"),
                format!("must be positive, got {}", m.density),
            );
        }
    }
    if spec.bodies.is_empty() {
        return err(
            "body".into(),
            "at least one [[body]] (or a [granular] table) is needed".into(),
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
                        "max.{axis} = {} must exceed min.{axis} = {}",
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
    }
    let mut pairs: HashMap<(usize, usize), usize> = HashMap::with_capacity(spec.interfaces.len());
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
            }
        }
    }
    for (i, bc) in spec.boundaries.iter().enumerate() {
        if !body_index.contains_key(bc.body.as_str()) {
            return err(
                format!("boundary[{i}].body"),
                format!("no body named `{}`", bc.body),
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
    Ok(())
}

/// The prescribed dofs of a boundary, or (field, reason).
fn boundary_dofs(bc: &BoundarySpec) -> std::result::Result<Vec<BoundaryDof>, (String, String)> {
    let comps = [&bc.x, &bc.y, &bc.z];
    if bc.clamped {
        if comps.iter().any(|c| c.is_some()) {
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
    for (component, c) in comps.iter().enumerate() {
        let Some(c) = c else { continue };
        let axis = ["x", "y", "z"][component];
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

fn component_law(c: &ComponentSpec) -> std::result::Result<DofLaw, String> {
    if !(c.ramp_time.is_finite() && c.ramp_time >= 0.0) {
        return Err(format!(
            "ramp_time must be a non-negative number, got {}",
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
fn pair_key(body_index: &HashMap<&str, usize>, bodies: &[String; 2]) -> (usize, usize) {
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

/// One substructure of a body before assembly: a box of hexahedra.
struct Piece {
    /// Index of the body.
    body: usize,
    /// Substructure name (`body` or `body[i,j,k]` when the body is split).
    name: String,
    /// Lower and upper corners.
    min: Vec3,
    max: Vec3,
    /// Elements along x, y, z.
    divisions: [usize; 3],
}

/// Builds the discrete problem of a scene (validated first; a `[granular]` table is expanded).
pub fn build(spec: &SceneSpec, source: &str) -> Result<Problem> {
    if spec.granular.is_some() {
        return build(&granular::expand(spec, source)?, source);
    }
    validate(spec, source)?;
    let materials: Vec<NamedMaterial> = spec
        .materials
        .iter()
        .map(|m| NamedMaterial {
            name: m.name.clone(),
            material: Material {
                young: m.young,
                poisson: m.poisson,
                density: m.density,
            },
        })
        .collect();
    // the substructures to assemble
    let mut pieces: Vec<Piece> = Vec::new();
    let mut body_subs: Vec<Vec<usize>> = Vec::new();
    for (body, b) in spec.bodies.iter().enumerate() {
        let [sx, sy, sz] = b.split;
        let div = [
            b.divisions[0] / sx,
            b.divisions[1] / sy,
            b.divisions[2] / sz,
        ];
        let mut ids = Vec::new();
        for iz in 0..sz {
            for iy in 0..sy {
                for ix in 0..sx {
                    let cell = [ix, iy, iz];
                    let lo = std::array::from_fn(|a| lerp(b.min[a], b.max[a], cell[a], b.split[a]));
                    let hi =
                        std::array::from_fn(|a| lerp(b.min[a], b.max[a], cell[a] + 1, b.split[a]));
                    let name = if b.split == [1, 1, 1] {
                        b.name.clone()
                    } else {
                        format!("{}[{ix},{iy},{iz}]", b.name)
                    };
                    ids.push(pieces.len());
                    pieces.push(Piece {
                        body,
                        name,
                        min: lo,
                        max: hi,
                        divisions: div,
                    });
                }
            }
        }
        body_subs.push(ids);
    }
    let material_of: Vec<usize> = spec
        .bodies
        .iter()
        .map(|b| {
            materials
                .iter()
                .position(|m| m.name == b.material)
                .unwrap_or_default()
        })
        .collect();
    // cells equal up to a translation share one assembled stiffness (a granular cube of 648
    // cells assembles a handful)
    let mut cache = StiffnessCache::default();
    let mut subs: Vec<Substructure> = pieces
        .iter()
        .map(|piece| {
            let b = &spec.bodies[piece.body];
            let material_id = material_of[piece.body];
            Substructure::assemble_cached(
                piece.name.clone(),
                b.name.clone(),
                material_id,
                Mesh::hex_box(piece.min, piece.max, piece.divisions),
                materials[material_id].material,
                b.velocity,
                &mut cache,
            )
        })
        .collect();
    // the override of each pair of bodies, looked up by pair (scenes have hundreds of bodies)
    let body_index: HashMap<&str, usize> = spec
        .bodies
        .iter()
        .enumerate()
        .map(|(i, b)| (b.name.as_str(), i))
        .collect();
    let overrides: HashMap<(usize, usize), PairRule> = spec
        .interfaces
        .iter()
        .map(|it| {
            let rule = match it.kind {
                InterfaceKind::Perfect => PairRule::Perfect,
                InterfaceKind::Free => PairRule::Free,
                InterfaceKind::Contact => PairRule::Contact {
                    friction: it.friction.unwrap_or(0.0),
                    gap: it.gap,
                    search: it.search.unwrap_or(0.0),
                },
            };
            (pair_key(&body_index, &it.bodies), rule)
        })
        .collect();
    let rule = |a: &str, b: &str| -> PairRule {
        let (Some(&i), Some(&j)) = (body_index.get(a), body_index.get(b)) else {
            return PairRule::Perfect;
        };
        overrides
            .get(&(i.min(j), i.max(j)))
            .copied()
            .unwrap_or(PairRule::Perfect)
    };
    let mut interfaces = detect_interfaces(&subs, &rule)?;
    for (i, bc) in spec.boundaries.iter().enumerate() {
        let (axis, sign) = face_of(&bc.face).unwrap_or((0, 1.0));
        let body = body_index
            .get(bc.body.as_str())
            .copied()
            .unwrap_or_default();
        let b = &spec.bodies[body];
        let value = if sign > 0.0 { b.max[axis] } else { b.min[axis] };
        let dofs = boundary_dofs(bc)
            .map_err(|(f, r)| LopinError::scene(source, format!("boundary[{i}].{f}"), r))?;
        for &s in &body_subs[body] {
            let name = format!("{}:{}", subs[s].name, bc.face);
            if let Some(it) = boundary_interface(&subs, s, axis, sign, value, &dofs, name) {
                interfaces.push(it);
            }
        }
    }
    assemble_traces(&mut subs, &mut interfaces);
    let mut problem = Problem {
        name: spec.name.clone(),
        materials,
        subs,
        interfaces,
        time: spec.time,
        velocity_signs: Vec::new(),
    };
    problem.record_velocity_signs();
    Ok(problem)
}

fn lerp(a: f64, b: f64, i: usize, n: usize) -> f64 {
    if i == n {
        b
    } else {
        a + (b - a) * i as f64 / n as f64
    }
}
