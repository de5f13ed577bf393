//! The interfaces and what acts on them: interface sides, areas, normals and laws
//! ([`interface`], METHOD §1, §5), their detection between substructures ([`detect`], with the
//! box sweep it searches through, [`box_sweep`]), the search directions' shape
//! ([`search_direction`], METHOD §3), and the zones a study moves apart ([`zone`], split by
//! physical surface in [`surface_groups`]).

pub mod box_sweep;
pub mod detect;
pub mod interface;
pub mod search_direction;
pub mod surface_groups;
pub mod zone;
