//! Turns a validated scene whose bodies are listed into a [`Problem`] (the front door
//! [`crate::scene::open`] validates and expands first): meshes the bodies and cuts them into
//! substructures ([`bodies`]), detects the interfaces (every perfect or contact interface the
//! file asks for must be found: a model never silently lacks one) and places the boundary
//! conditions ([`joining`]), then resolves the zones.

mod bodies;
mod joining;

use crate::error::Result;
use crate::interfaces::detect::assemble_traces;
use crate::problem::{NamedMaterial, Problem};
use crate::scene::spec::SceneSpec;
use crate::substructure::{StiffnessCache, Substructure};
use crate::time::time_scheme::TimeScheme;

/// What building has assembled so far: the substructures, each body's substructures (box
/// bodies first, then mesh bodies), and per mesh body and substructure the file node of each of
/// its nodes.
struct Assembly {
    materials: Vec<NamedMaterial>,
    subs: Vec<Substructure>,
    body_subs: Vec<Vec<usize>>,
    file_nodes: Vec<Vec<Vec<usize>>>,
    /// Cells equal up to a translation share one assembled stiffness (a granular cube of 648
    /// cells assembles a handful).
    cache: StiffnessCache,
}

impl Assembly {
    /// The index of the material a body names (validation has checked that it exists).
    fn material_id(&self, name: &str) -> usize {
        self.materials
            .iter()
            .position(|m| m.name == name)
            .unwrap_or_default()
    }
}

/// Builds the discrete problem of a validated scene whose bodies are listed, with the time
/// scheme of spectral radius `rho_inf` (METHOD §2).
pub(crate) fn build_expanded(spec: &SceneSpec, source: &str, rho_inf: f64) -> Result<Problem> {
    let mut assembly = Assembly {
        materials: materials(spec),
        subs: Vec::new(),
        body_subs: Vec::new(),
        file_nodes: Vec::new(),
        cache: StiffnessCache::default(),
    };
    bodies::add_boxes(spec, source, &mut assembly)?;
    let mut meshes = bodies::add_mesh_bodies(spec, source, &mut assembly)?;
    let (mut interfaces, surface_of) = joining::interfaces(spec, source, &assembly, &mut meshes)?;
    let Assembly {
        materials,
        mut subs,
        ..
    } = assembly;
    assemble_traces(&mut subs, &mut interfaces);
    let zones =
        crate::interfaces::zone::resolve(&spec.zones, &subs, &interfaces, &surface_of, source)?;
    let mut problem = Problem {
        name: spec.name.clone(),
        materials,
        subs,
        interfaces,
        time: spec.time,
        scheme: TimeScheme::new(rho_inf),
        load_signs: Vec::new(),
        zones,
        statics: false,
    };
    problem.record_load_signs();
    problem.integrate_accelerations();
    Ok(problem)
}

/// The scene's materials, by name.
fn materials(spec: &SceneSpec) -> Vec<NamedMaterial> {
    spec.materials
        .iter()
        .map(|m| NamedMaterial {
            name: m.name.clone(),
            material: m.material(),
        })
        .collect()
}
