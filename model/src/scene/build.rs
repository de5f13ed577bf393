//! Turns a scene description into a [`Problem`]: validates it first ([`super::validate`]),
//! expands a `[granular]` table ([`granular::expand`]), meshes the bodies, cuts them into
//! substructures, detects the interfaces (every perfect or contact interface the file asks for
//! must be found: a model never silently lacks one) and places the boundary conditions.

use std::collections::HashMap;

use crate::elements::material::Material;
use crate::error::{LopinError, Result};
use crate::interfaces::detect::{
    assemble_traces, boundary_interface, detect_interfaces_grouped, PairRule,
};
use crate::interfaces::interface::Interface;
use crate::mesh::{Mesh, Vec3};
use crate::problem::{NamedMaterial, Problem};
use crate::scene::admission::{self, MeshSize, SolveShape};
use crate::scene::granular;
use crate::scene::granular_poly;
use crate::scene::mesh_bodies;
use crate::scene::spec::{BodySpec, ElementKind, InterfaceKind, SceneSpec};
pub use crate::scene::validate::validate;
use crate::scene::validate::{boundary_dofs, pair_key};
use crate::substructure::{StiffnessCache, Substructure};

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

/// One substructure of a body before assembly.
struct Piece {
    /// Index of the body.
    body: usize,
    /// Substructure name (`body`, `body[i,j,k]` for a split box, `body[p]` for a partitioned
    /// body).
    name: String,
    /// Its mesh.
    mesh: Mesh,
}

/// Builds the discrete problem of a scene (validated first; a `[granular]` table is expanded).
pub fn build(spec: &SceneSpec, source: &str) -> Result<Problem> {
    if spec.granular.is_some() {
        return build(&granular::expand(spec, source)?, source);
    }
    if spec.granular_poly.is_some() {
        return build(&granular_poly::expand(spec, source)?, source);
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
        let mut ids = Vec::new();
        if let Some(n) = b.substructures {
            let mesh = box_mesh(b, b.min, b.max, b.divisions);
            let parts = cut(mesh, n, source, &format!("body[{body}].substructures"))?;
            let count = parts.len();
            for (p, (mesh, _)) in parts.into_iter().enumerate() {
                ids.push(pieces.len());
                pieces.push(Piece {
                    body,
                    name: part_name(&b.name, p, count),
                    mesh,
                });
            }
            body_subs.push(ids);
            continue;
        }
        let [sx, sy, sz] = b.split;
        let div = [
            b.divisions[0] / sx,
            b.divisions[1] / sy,
            b.divisions[2] / sz,
        ];
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
                        mesh: box_mesh(b, lo, hi, div),
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
        .into_iter()
        .map(|piece| {
            let b = &spec.bodies[piece.body];
            let material_id = material_of[piece.body];
            Substructure::assemble_cached(
                piece.name,
                b.name.clone(),
                material_id,
                piece.mesh,
                materials[material_id].material,
                b.velocity,
                &mut cache,
            )
        })
        .collect();
    // bodies from Gmsh files: one substructure each, or the parts the partitioner cuts
    // per mesh body and substructure, the file node of each of its nodes
    let mut meshes = mesh_bodies::read(spec, source)?;
    let bodies = std::mem::take(&mut meshes.bodies);
    if !bodies.is_empty() {
        // the mesh bodies' sizes are known now: admitted before anything is assembled
        let sizes: Vec<MeshSize> = spec
            .mesh_bodies
            .iter()
            .zip(&bodies)
            .map(|(b, (mesh, _))| MeshSize {
                nodes: mesh.nodes.len(),
                substructures: b.substructures.unwrap_or(1),
            })
            .collect();
        admission::admit_with_meshes(spec, source, SolveShape::smallest(), &sizes)?;
    }
    let measured: Vec<(&str, Material, &Mesh)> = spec
        .mesh_bodies
        .iter()
        .zip(&bodies)
        .filter_map(|(b, (mesh, _))| {
            let m = materials.iter().find(|m| m.name == b.material)?;
            Some((b.name.as_str(), m.material, mesh))
        })
        .collect();
    crate::scene::validate::check_mesh_time_step(spec, source, &measured)?;
    let mut file_nodes: Vec<Vec<Vec<usize>>> = Vec::new();
    for (i, (b, (mesh, file_node))) in spec.mesh_bodies.iter().zip(bodies).enumerate() {
        let material_id = materials
            .iter()
            .position(|m| m.name == b.material)
            .unwrap_or_default();
        let parts = cut(
            mesh,
            b.substructures.unwrap_or(1),
            source,
            &format!("mesh_body[{i}].substructures"),
        )?;
        let count = parts.len();
        let mut ids = Vec::new();
        let mut maps = Vec::new();
        for (p, (part, origin)) in parts.into_iter().enumerate() {
            ids.push(subs.len());
            maps.push(origin.iter().map(|&o| file_node[o]).collect());
            subs.push(Substructure::assemble_cached(
                part_name(&b.name, p, count),
                b.name.clone(),
                material_id,
                part,
                materials[material_id].material,
                b.velocity,
                &mut cache,
            ));
        }
        body_subs.push(ids);
        file_nodes.push(maps);
    }
    // the override of each pair of bodies, looked up by pair (scenes have hundreds of bodies)
    let body_index: HashMap<&str, usize> = spec
        .bodies
        .iter()
        .map(|b| b.name.as_str())
        .chain(spec.mesh_bodies.iter().map(|b| b.name.as_str()))
        .enumerate()
        .map(|(i, name)| (name, i))
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
    // the farthest any rule pairs faces (detection looks no farther)
    let search_bound = overrides
        .values()
        .map(|r| match r {
            PairRule::Contact { search, .. } => *search,
            _ => 0.0,
        })
        .fold(0.0f64, f64::max);
    // contacts split by the physical surfaces zones name (each interface's surface kept)
    let named = crate::interfaces::zone::surface_names(&spec.zones);
    let names: Vec<&str> = named.iter().map(|n| n.0).collect();
    let mesh_subs: Vec<&[usize]> = body_subs[spec.bodies.len()..]
        .iter()
        .map(Vec::as_slice)
        .collect();
    let lookup = meshes
        .surface_lookup(&names, &mesh_subs, &file_nodes)
        .map_err(|(g, reason)| LopinError::scene(source, named[g].1.clone(), reason))?;
    let (mut interfaces, mut surface_of): (Vec<Interface>, Vec<Option<String>>) =
        detect_interfaces_grouped(&subs, &rule, search_bound, &|s, face| lookup.group(s, face))
            .map_err(|e| e.in_source(source))?
            .into_iter()
            .map(|(mut iface, g)| {
                let surface = (g > 0).then(|| names[g - 1].to_string());
                if let Some(name) = &surface {
                    iface.name = format!("{}@{name}", iface.name);
                }
                (iface, surface)
            })
            .unzip();
    check_overrides_found(spec, source, &subs, &interfaces)?;
    for (i, bc) in spec.boundaries.iter().enumerate() {
        let body = body_index
            .get(bc.body.as_str())
            .copied()
            .unwrap_or_default();
        if body >= spec.bodies.len() {
            let dofs = boundary_dofs(bc)
                .map_err(|(f, r)| LopinError::scene(source, format!("boundary[{i}].{f}"), r))?;
            let found = meshes
                .boundary(
                    spec,
                    &subs,
                    body - spec.bodies.len(),
                    &body_subs[body],
                    &file_nodes[body - spec.bodies.len()],
                    bc.surface.as_deref().unwrap_or_default(),
                    &dofs,
                )
                .map_err(|r| LopinError::scene(source, format!("boundary[{i}].surface"), r))?;
            surface_of.extend(found.iter().map(|_| bc.surface.clone()));
            interfaces.extend(found);
            continue;
        }
        let (axis, sign) = face_of(&bc.face).unwrap_or((0, 1.0));
        let b = &spec.bodies[body];
        let value = if sign > 0.0 { b.max[axis] } else { b.min[axis] };
        let dofs = boundary_dofs(bc)
            .map_err(|(f, r)| LopinError::scene(source, format!("boundary[{i}].{f}"), r))?;
        for &s in &body_subs[body] {
            let name = format!("{}:{}", subs[s].name, bc.face);
            if let Some(it) = boundary_interface(&subs, s, axis, sign, value, &dofs, name) {
                interfaces.push(it);
                surface_of.push(None);
            }
        }
    }
    assemble_traces(&mut subs, &mut interfaces);
    let zones =
        crate::interfaces::zone::resolve(&spec.zones, &subs, &interfaces, &surface_of, source)?;
    let mut problem = Problem {
        name: spec.name.clone(),
        materials,
        subs,
        interfaces,
        time: spec.time,
        scheme: crate::time::time_scheme::TimeScheme::new(spec.solver.rho_inf.unwrap_or(1.0)),
        velocity_signs: Vec::new(),
        zones,
    };
    problem.record_velocity_signs();
    Ok(problem)
}

/// Every perfect or contact interface the file asks for between two bodies joins them: an
/// override whose bodies share no face (or none across the contact search distance) is an error
/// naming both bodies and how far apart they are, never a model without that interface.
fn check_overrides_found(
    spec: &SceneSpec,
    source: &str,
    subs: &[Substructure],
    interfaces: &[crate::interfaces::interface::Interface],
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

/// The mesh of a box body (or of one of its split boxes).
fn box_mesh(b: &BodySpec, min: Vec3, max: Vec3, divisions: [usize; 3]) -> Mesh {
    let mesh = Mesh::hex_box(min, max, divisions);
    match b.elements.unwrap_or_default() {
        ElementKind::Hex8 => mesh,
        ElementKind::Tet4 => mesh.split_into_tets(),
    }
}

/// The name of part `p` of `count` cut from body `body`.
fn part_name(body: &str, p: usize, count: usize) -> String {
    if count == 1 {
        body.to_string()
    } else {
        format!("{body}[{p}]")
    }
}

/// A body's mesh cut into `n` substructures by the graph partitioner (each part's mesh, and per
/// node the body node it copies); `field` names the scene field in errors.
fn cut(mesh: Mesh, n: usize, source: &str, field: &str) -> Result<Vec<(Mesh, Vec<usize>)>> {
    if n <= 1 {
        let all = (0..mesh.nodes.len()).collect();
        return Ok(vec![(mesh, all)]);
    }
    #[cfg(feature = "partition")]
    {
        crate::mesh::partition::partition(&mesh, n)
            .map(|p| p.parts)
            .map_err(|r| LopinError::scene(source, field, r))
    }
    #[cfg(not(feature = "partition"))]
    {
        Err(LopinError::scene(
            source,
            field,
            "this build of Lopin has no graph partitioner (the web build): use `split`, or run \
             the scene with the `lopin` command line",
        ))
    }
}

fn lerp(a: f64, b: f64, i: usize, n: usize) -> f64 {
    if i == n {
        b
    } else {
        a + (b - a) * i as f64 / n as f64
    }
}
