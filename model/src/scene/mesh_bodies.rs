//! The bodies of a scene taken from Gmsh files (`[[mesh_body]]`): each is the
//! physical volume of an MSH 4.1 file (its path relative to the scene file; a `.geo` script is
//! meshed by gmsh first, [`crate::mesh::gmsh`]), one substructure (or the parts the partitioner cuts)
//! with its own copy of the nodes it shares with other bodies (so interface detection pairs
//! them on conforming faces, METHOD §1), and its boundary conditions sit on physical surfaces of
//! the same file. A file read by several bodies is read once. Without the `msh` feature (the web
//! build) a scene with mesh bodies is an error saying so.

use crate::error::{LopinError, Result};
use crate::interfaces::detect::boundary_interface_on;
use crate::interfaces::interface::{BoundaryLoad, Interface};
use crate::mesh::Mesh;
use crate::scene::spec::SceneSpec;
use crate::substructure::Substructure;

/// The meshes of a scene's mesh bodies, in the order of `spec.mesh_bodies`.
#[derive(Debug, Default)]
pub struct MeshBodies {
    /// Each body's mesh and, per node, the node of its file it copies.
    pub bodies: Vec<(Mesh, Vec<usize>)>,
    /// The files read, and which one each body comes from.
    #[cfg(feature = "msh")]
    files: Vec<crate::mesh::msh::MshMesh>,
    #[cfg(feature = "msh")]
    file_of: Vec<usize>,
}

/// Where a body's mesh file lies: `mesh` as given when absolute, else beside the scene file
/// (`source` is its path; a built-in scene has none, and the path is taken as given).
pub fn mesh_path(source: &str, mesh: &str) -> std::path::PathBuf {
    let m = std::path::Path::new(mesh);
    if m.is_absolute() {
        return m.to_path_buf();
    }
    match std::path::Path::new(source).parent() {
        Some(dir) if std::path::Path::new(source).is_file() => dir.join(m),
        _ => m.to_path_buf(),
    }
}

/// Reads the mesh bodies of `spec` (nothing when it has none).
pub fn read(spec: &SceneSpec, source: &str) -> Result<MeshBodies> {
    if spec.mesh_bodies.is_empty() {
        return Ok(MeshBodies::default());
    }
    read_files(spec, source)
}

#[cfg(not(feature = "msh"))]
fn read_files(spec: &SceneSpec, source: &str) -> Result<MeshBodies> {
    Err(LopinError::scene(
        source,
        "mesh_body[0].mesh",
        format!(
            "this build of Lopin reads no mesh files (the web build): run `{}` with the `lopin` \
             command line",
            spec.mesh_bodies[0].mesh
        ),
    ))
}

#[cfg(feature = "msh")]
fn read_files(spec: &SceneSpec, source: &str) -> Result<MeshBodies> {
    let mut out = MeshBodies::default();
    let mut paths: Vec<std::path::PathBuf> = Vec::new();
    for (i, b) in spec.mesh_bodies.iter().enumerate() {
        let path = mesh_path(source, &b.mesh);
        let file = match paths.iter().position(|p| *p == path) {
            Some(f) => f,
            None => {
                let field = || format!("mesh_body[{i}].mesh");
                // a gmsh script is meshed first (cached by its content)
                let msh = if path.extension().is_some_and(|e| e == "geo") {
                    crate::mesh::gmsh::mesh_geo_file(&path)
                        .map_err(|e| LopinError::scene(source, field(), e.to_string()))?
                } else {
                    path.clone()
                };
                let m = crate::mesh::msh::read(&msh)
                    .map_err(|e| LopinError::scene(source, field(), e.to_string()))?;
                paths.push(path);
                out.files.push(m);
                out.files.len() - 1
            }
        };
        let body = out.files[file].body(b.volume_name()).map_err(|e| {
            LopinError::scene(source, format!("mesh_body[{i}].volume"), e.to_string())
        })?;
        out.bodies.push(body);
        out.file_of.push(file);
    }
    Ok(out)
}

impl MeshBodies {
    /// The boundary interfaces of mesh body `i` on its physical surface `surface`, prescribing
    /// `dofs`: one per substructure of the body (`subs_of`, with per substructure the file node
    /// of each of its nodes in `file_nodes`) that has a face on it; the reason when the surface
    /// is unknown or has no face on the body.
    #[allow(clippy::too_many_arguments)]
    pub fn boundary(
        &self,
        spec: &SceneSpec,
        subs: &[Substructure],
        i: usize,
        subs_of: &[usize],
        file_nodes: &[Vec<usize>],
        surface: &str,
        load: &BoundaryLoad,
    ) -> std::result::Result<Vec<Interface>, String> {
        let name = &spec.mesh_bodies[i].name;
        #[cfg(feature = "msh")]
        {
            let file = &self.files[self.file_of[i]];
            let facets = file.surface(surface).map_err(|e| e.to_string())?;
            let mut found = Vec::new();
            for (&sub, file_node) in subs_of.iter().zip(file_nodes) {
                let selector = |face: &crate::mesh::Face| facets.holds(face, file_node);
                let label = format!("{}:{surface}", subs[sub].name);
                found.extend(boundary_interface_on(subs, sub, &selector, load, label));
            }
            if found.is_empty() {
                return Err(format!(
                    "physical surface `{surface}` of {} has no face on the boundary of body \
                     `{name}`",
                    file.source
                ));
            }
            Ok(found)
        }
        #[cfg(not(feature = "msh"))]
        {
            let _ = (subs, subs_of, file_nodes, load, boundary_interface_on);
            Err(format!(
                "body `{name}`: this build reads no mesh files (surface `{surface}`)"
            ))
        }
    }
}

/// The face groups of the physical surfaces zones name ([`crate::interfaces::surface_groups`]): per
/// substructure of a mesh body, the surfaces its file defines (group g for the g-th name) and
/// the file node of each of its nodes.
#[derive(Debug, Default)]
pub struct SurfaceLookup {
    #[cfg(feature = "msh")]
    per_sub: std::collections::HashMap<usize, (std::rc::Rc<SurfaceSet>, Vec<usize>)>,
}

/// The named surfaces of one mesh body's file: (group, facets).
#[cfg(feature = "msh")]
type SurfaceSet = Vec<(usize, crate::mesh::msh::SurfaceFacets)>;

impl SurfaceLookup {
    /// The group of a boundary face of substructure `sub` (0: on none of the named surfaces).
    pub fn group(&self, sub: usize, face: &crate::mesh::Face) -> usize {
        #[cfg(feature = "msh")]
        if let Some((set, file_node)) = self.per_sub.get(&sub) {
            return set
                .iter()
                .find(|(_, facets)| facets.holds(face, file_node))
                .map_or(0, |(g, _)| *g);
        }
        let _ = (sub, face);
        0
    }
}

impl MeshBodies {
    /// The lookup of the physical surfaces `names` (group g + 1 for `names[g]`) on the
    /// substructures of the mesh bodies (`body_subs[i]`, with per substructure the file node of
    /// each of its nodes in `file_nodes[i]`); the index of a name no mesh file of the scene
    /// defines, with the reason.
    pub fn surface_lookup(
        &self,
        names: &[&str],
        body_subs: &[&[usize]],
        file_nodes: &[Vec<Vec<usize>>],
    ) -> std::result::Result<SurfaceLookup, (usize, String)> {
        if names.is_empty() {
            return Ok(SurfaceLookup::default());
        }
        #[cfg(feature = "msh")]
        {
            if self.files.is_empty() {
                return Err((0, NO_MESH.to_string()));
            }
            let mut per_file: Vec<std::rc::Rc<SurfaceSet>> = Vec::new();
            for file in &self.files {
                let set = names
                    .iter()
                    .enumerate()
                    .filter_map(|(g, name)| Some((g + 1, file.surface(name).ok()?)))
                    .collect();
                per_file.push(std::rc::Rc::new(set));
            }
            if let Some(g) =
                (1..=names.len()).find(|&g| per_file.iter().all(|s| s.iter().all(|e| e.0 != g)))
            {
                let known: Vec<&str> = self
                    .files
                    .iter()
                    .flat_map(|f| &f.physicals)
                    .filter(|p| p.dim == 2)
                    .map(|p| p.name.as_str())
                    .collect();
                return Err((
                    g - 1,
                    format!(
                        "no mesh file of the scene has a physical surface named `{}` (they \
                         have: {})",
                        names[g - 1],
                        if known.is_empty() {
                            "none".to_string()
                        } else {
                            known.join(", ")
                        }
                    ),
                ));
            }
            let mut per_sub = std::collections::HashMap::new();
            for (i, subs) in body_subs.iter().enumerate() {
                let set = &per_file[self.file_of[i]];
                for (&sub, file_node) in subs.iter().zip(&file_nodes[i]) {
                    per_sub.insert(sub, (set.clone(), file_node.clone()));
                }
            }
            Ok(SurfaceLookup { per_sub })
        }
        #[cfg(not(feature = "msh"))]
        {
            let _ = (body_subs, file_nodes);
            Err((0, NO_MESH.to_string()))
        }
    }
}

/// Why a zone cannot name surfaces in a scene without mesh bodies.
const NO_MESH: &str = "physical surfaces come from Gmsh meshes (`[[mesh_body]]`), and this \
                       scene has none: select the zone's interfaces by `bodies` or by a box \
                       (`min`, `max`)";
