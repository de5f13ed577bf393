//! Scenes, from text to a built problem. The schema ([`spec`], with the generator tables in
//! [`tables`]) and the built-in registry ([`registry`]) describe a scene; [`reading`] parses it;
//! the front door [`open`] takes it the rest of the way, each step once: the generators
//! ([`granular`], [`granular_poly`]) expand their tables, [`validate`] checks every field,
//! [`admission`] counts what a solve will hold, [`build`] meshes, detects and assembles the
//! [`crate::Problem`], and the settings resolve ([`crate::settings`]). [`settings`] holds the
//! settings a scene names besides numbers; [`mesh_bodies`] reads bodies from Gmsh files and
//! [`time_tables`] the CSV tables of time functions.

pub mod admission;
mod build;
mod cell_set;
mod exact;
mod face_index;
pub mod granular;
pub mod granular_poly;
pub mod mesh_bodies;
pub mod open;
pub mod reading;
#[cfg(feature = "schema")]
pub mod reference;
pub mod registry;
pub mod settings;
pub mod spec;
pub mod tables;
pub mod time_tables;
pub mod validate;

pub use open::{
    admit, check, from_toml, load, open, problem_of, read, source_label, Admitted, Opened,
    Overrides, Source,
};
pub use reading::to_toml;
pub use spec::SceneSpec;
