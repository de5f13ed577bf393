//! How the substructures are joined and held: the rule of each pair of bodies (perfect by
//! default, a `[[interface]]` override otherwise), the interfaces detected between faces that
//! meet (split by the physical surfaces zones name), the check that every override was found,
//! and the boundary interfaces of the `[[boundary]]` entries (METHOD §5 laws).

use std::collections::HashMap;

use crate::error::{LopinError, Result};
use crate::interfaces::detect::{boundary_interface, detect_interfaces_grouped, PairRule};
use crate::interfaces::interface::Interface;
use crate::scene::mesh_bodies::MeshBodies;
use crate::scene::spec::{face_of, InterfaceKind, SceneSpec};
use crate::scene::validate::{boundary_dofs, pair_key};
use crate::substructure::Substructure;

use super::Assembly;

/// The interfaces of the scene, and for each the physical surface it lies on (None: a box face
/// or no named surface).
pub(super) fn interfaces(
    spec: &SceneSpec,
    source: &str,
    assembly: &Assembly,
    meshes: &mut MeshBodies,
) -> Result<(Vec<Interface>, Vec<Option<String>>)> {
    // the override of each pair of bodies, looked up by pair (scenes have hundreds of bodies)
    let body_index: HashMap<&str, usize> = spec
        .bodies
        .iter()
        .map(|b| b.name.as_str())
        .chain(spec.mesh_bodies.iter().map(|b| b.name.as_str()))
        .enumerate()
        .map(|(i, name)| (name, i))
        .collect();
    let (mut interfaces, mut surface_of) = detect(spec, source, assembly, meshes, &body_index)?;
    check_overrides_found(spec, source, &assembly.subs, &interfaces)?;
    for (i, bc) in spec.boundaries.iter().enumerate() {
        let body = body_index
            .get(bc.body.as_str())
            .copied()
            .unwrap_or_default();
        let found = boundary(spec, source, assembly, meshes, (i, body))?;
        surface_of.extend(found.iter().map(|_| bc.surface.clone()));
        interfaces.extend(found);
    }
    Ok((interfaces, surface_of))
}

/// The rule of each pair of bodies with an override, and the farthest any rule pairs faces.
fn pair_rules(
    spec: &SceneSpec,
    body_index: &HashMap<&str, usize>,
) -> (HashMap<(usize, usize), PairRule>, f64) {
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
            (pair_key(body_index, &it.bodies), rule)
        })
        .collect();
    let search_bound = overrides
        .values()
        .map(|r| match r {
            PairRule::Contact { search, .. } => *search,
            _ => 0.0,
        })
        .fold(0.0f64, f64::max);
    (overrides, search_bound)
}

/// The interfaces between substructures, contacts split by the physical surfaces zones name
/// (each interface's surface kept, and appended to its name).
fn detect(
    spec: &SceneSpec,
    source: &str,
    assembly: &Assembly,
    meshes: &mut MeshBodies,
    body_index: &HashMap<&str, usize>,
) -> Result<(Vec<Interface>, Vec<Option<String>>)> {
    let (overrides, search_bound) = pair_rules(spec, body_index);
    let rule = |a: &str, b: &str| -> PairRule {
        let (Some(&i), Some(&j)) = (body_index.get(a), body_index.get(b)) else {
            return PairRule::Perfect;
        };
        overrides
            .get(&(i.min(j), i.max(j)))
            .copied()
            .unwrap_or(PairRule::Perfect)
    };
    let named = crate::interfaces::zone::surface_names(&spec.zones);
    let names: Vec<&str> = named.iter().map(|n| n.0).collect();
    let mesh_subs: Vec<&[usize]> = assembly.body_subs[spec.bodies.len()..]
        .iter()
        .map(Vec::as_slice)
        .collect();
    let lookup = meshes
        .surface_lookup(&names, &mesh_subs, &assembly.file_nodes)
        .map_err(|(g, reason)| LopinError::scene(source, named[g].1.clone(), reason))?;
    Ok(
        detect_interfaces_grouped(&assembly.subs, &rule, search_bound, &|s, face| {
            lookup.group(s, face)
        })
        .map_err(|e| e.in_source(source))?
        .into_iter()
        .map(|(mut iface, g)| {
            let surface = (g > 0).then(|| names[g - 1].to_string());
            if let Some(name) = &surface {
                iface.name = format!("{}@{name}", iface.name);
            }
            (iface, surface)
        })
        .unzip(),
    )
}

/// The boundary interfaces of boundary `i` on body `body`: on a physical surface of a mesh
/// body, or on a box face of each of the box body's substructures that reaches it.
fn boundary(
    spec: &SceneSpec,
    source: &str,
    assembly: &Assembly,
    meshes: &MeshBodies,
    (i, body): (usize, usize),
) -> Result<Vec<Interface>> {
    let bc = &spec.boundaries[i];
    let dofs = boundary_dofs(bc)
        .map_err(|(f, r)| LopinError::scene(source, format!("boundary[{i}].{f}"), r))?;
    let subs = &assembly.subs;
    if body >= spec.bodies.len() {
        let mesh_body = body - spec.bodies.len();
        return meshes
            .boundary(
                spec,
                subs,
                mesh_body,
                &assembly.body_subs[body],
                &assembly.file_nodes[mesh_body],
                bc.surface.as_deref().unwrap_or_default(),
                &dofs,
            )
            .map_err(|r| LopinError::scene(source, format!("boundary[{i}].surface"), r));
    }
    let (axis, sign) = face_of(&bc.face).unwrap_or((0, 1.0));
    let b = &spec.bodies[body];
    let value = if sign > 0.0 { b.max[axis] } else { b.min[axis] };
    Ok(assembly.body_subs[body]
        .iter()
        .filter_map(|&s| {
            let name = format!("{}:{}", subs[s].name, bc.face);
            boundary_interface(subs, s, axis, sign, value, &dofs, name)
        })
        .collect())
}

/// Every perfect or contact interface the file asks for between two bodies joins them: an
/// override whose bodies share no face (or none across the contact search distance) is an error
/// naming both bodies and how far apart they are, never a model without that interface.
fn check_overrides_found(
    spec: &SceneSpec,
    source: &str,
    subs: &[Substructure],
    interfaces: &[Interface],
) -> Result<()> {
    let joined: std::collections::HashSet<(&str, &str)> = interfaces
        .iter()
        .filter(|i| i.sides.len() == 2)
        .flat_map(|i| {
            let (a, b) = (
                subs[i.sides[0].sub].body.as_str(),
                subs[i.sides[1].sub].body.as_str(),
            );
            [(a, b), (b, a)]
        })
        .collect();
    for (i, it) in spec.interfaces.iter().enumerate() {
        if it.kind == InterfaceKind::Free
            || joined.contains(&(it.bodies[0].as_str(), it.bodies[1].as_str()))
        {
            continue;
        }
        let body = |name: &str| spec.bodies.iter().find(|b| b.name == name);
        let kind = match it.kind {
            InterfaceKind::Contact => "contact",
            _ => "perfect",
        };
        let (Some(a), Some(b)) = (body(&it.bodies[0]), body(&it.bodies[1])) else {
            // a mesh body: faces meet only where the file's meshes are conforming
            return Err(LopinError::scene(
                source,
                format!("interface[{i}]"),
                format!(
                    "a {kind} interface between `{}` and `{}` is asked for, but no face of one \
                     meets a face of the other (mesh bodies meet on conforming faces: fragment \
                     the volumes in gmsh so they share their nodes, or set `search` to pair \
                     faces across a gap)",
                    it.bodies[0], it.bodies[1]
                ),
            ));
        };
        let apart: f64 = (0..3)
            .map(|c| {
                (b.min[c] - a.max[c])
                    .max(a.min[c] - b.max[c])
                    .max(0.0)
                    .powi(2)
            })
            .sum::<f64>()
            .sqrt();
        return Err(LopinError::scene(
            source,
            format!("interface[{i}]"),
            format!(
                "a {kind} interface between `{}` and `{}` is asked for, but no face of one \
                 meets a face of the other{}: the bodies are {apart:.4e} m apart{}",
                it.bodies[0],
                it.bodies[1],
                match it.search {
                    Some(s) if s > 0.0 => format!(" within the search distance {s:e} m"),
                    _ => String::new(),
                },
                if apart > 0.0 && it.kind == InterfaceKind::Contact {
                    " (set `search` to at least that distance to pair faces across the gap)"
                } else {
                    ""
                }
            ),
        ));
    }
    Ok(())
}
