//! The elements: the trilinear hexahedron ([`hex8`]) and the linear tetrahedron ([`tet4`]),
//! with the isotropic elastic material their stiffness and lumped mass are built from
//! ([`material`]) (METHOD §1) and its Rayleigh damping ([`rayleigh`]).

pub mod hex8;
pub mod material;
pub mod rayleigh;
pub mod tet4;
