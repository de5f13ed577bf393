//! The interfaces and what acts on them: interface sides, areas, normals and laws
//! ([`interface`], METHOD §1, §5), their detection between substructures ([`detect`], with the
//! box sweep it searches through, [`box_sweep`]; non-matching faces coupled by dual mortar,
//! [`mortar`], on the facets of [`facet`], detected in [`non_matching`], seen by the
//! substructures' traces through [`mortar_trace`]), the search directions' shape
//! ([`search_direction`], METHOD §3), and the zones a study moves apart ([`zone`], split by
//! physical surface in [`surface_groups`]).

pub mod box_sweep;
pub mod detect;
pub mod facet;
pub mod interface;
pub mod mortar;
pub mod mortar_trace;
pub mod non_matching;
pub mod search_direction;
pub mod shared_normals;
pub mod surface_groups;
pub mod zone;
