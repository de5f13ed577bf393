//! The substructures of a scene's bodies: box bodies meshed with hexahedra (or tetrahedra) and
//! split into a grid of boxes or cut by the graph partitioner, and bodies read from Gmsh files
//! ([`crate::scene::mesh_bodies`]), admitted once their sizes are known.

use crate::elements::material::Material;
use crate::error::{LopinError, Result};
use crate::mesh::{Mesh, Vec3};
use crate::scene::admission::{self, MeshSize, SolveShape};
use crate::scene::mesh_bodies::{self, MeshBodies};
use crate::scene::spec::{BodySpec, ElementKind, SceneSpec};
use crate::scene::validate::check_mesh_time_step;
use crate::substructure::Substructure;

use super::Assembly;

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

/// Assembles the substructures of the box bodies.
pub(super) fn add_boxes(spec: &SceneSpec, source: &str, assembly: &mut Assembly) -> Result<()> {
    let mut pieces: Vec<Piece> = Vec::new();
    for (body, b) in spec.bodies.iter().enumerate() {
        let first = pieces.len();
        if let Some(n) = b.substructures {
            let mesh = box_mesh(b, b.min, b.max, b.divisions);
            let parts = cut(mesh, n, source, &format!("body[{body}].substructures"))?;
            let count = parts.len();
            pieces.extend(parts.into_iter().enumerate().map(|(p, (mesh, _))| Piece {
                body,
                name: part_name(&b.name, p, count),
                mesh,
            }));
        } else {
            pieces.extend(split_boxes(body, b));
        }
        assembly.body_subs.push((first..pieces.len()).collect());
    }
    for piece in pieces {
        let b = &spec.bodies[piece.body];
        let material_id = assembly.material_id(&b.material);
        let sub = Substructure::assemble_cached(
            piece.name,
            b.name.clone(),
            material_id,
            piece.mesh,
            assembly.materials[material_id].material,
            b.velocity,
            &mut assembly.cache,
        );
        assembly.subs.push(sub);
    }
    Ok(())
}

/// The boxes of a body's `split` grid, x fastest.
fn split_boxes(body: usize, b: &BodySpec) -> Vec<Piece> {
    let [sx, sy, sz] = b.split;
    let div = [
        b.divisions[0] / sx,
        b.divisions[1] / sy,
        b.divisions[2] / sz,
    ];
    let mut pieces = Vec::with_capacity(sx * sy * sz);
    for iz in 0..sz {
        for iy in 0..sy {
            for ix in 0..sx {
                let cell = [ix, iy, iz];
                let lo = std::array::from_fn(|a| lerp(b.min[a], b.max[a], cell[a], b.split[a]));
                let hi = std::array::from_fn(|a| lerp(b.min[a], b.max[a], cell[a] + 1, b.split[a]));
                let name = if b.split == [1, 1, 1] {
                    b.name.clone()
                } else {
                    format!("{}[{ix},{iy},{iz}]", b.name)
                };
                pieces.push(Piece {
                    body,
                    name,
                    mesh: box_mesh(b, lo, hi, div),
                });
            }
        }
    }
    pieces
}

/// Reads the bodies from Gmsh files, admits their sizes, checks Δt against their smallest
/// element and assembles their substructures (one each, or the parts the partitioner cuts).
/// Returns the files read, whose surfaces the interfaces and boundaries look up.
pub(super) fn add_mesh_bodies(
    spec: &SceneSpec,
    source: &str,
    assembly: &mut Assembly,
) -> Result<MeshBodies> {
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
        .map(|(b, (mesh, _))| {
            let m = assembly.materials[assembly.material_id(&b.material)].material;
            (b.name.as_str(), m, mesh)
        })
        .collect();
    check_mesh_time_step(spec, source, &measured)?;
    for (i, (b, (mesh, file_node))) in spec.mesh_bodies.iter().zip(bodies).enumerate() {
        let material_id = assembly.material_id(&b.material);
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
            ids.push(assembly.subs.len());
            maps.push(origin.iter().map(|&o| file_node[o]).collect());
            let sub = Substructure::assemble_cached(
                part_name(&b.name, p, count),
                b.name.clone(),
                material_id,
                part,
                assembly.materials[material_id].material,
                b.velocity,
                &mut assembly.cache,
            );
            assembly.subs.push(sub);
        }
        assembly.body_subs.push(ids);
        assembly.file_nodes.push(maps);
    }
    Ok(meshes)
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
