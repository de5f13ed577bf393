//! Linear algebra the model needs: small dense solves ([`dense`]), symmetric sparse matrices
//! from element triplets ([`sparse`]) and their sparse Cholesky factorization, computed once
//! ([`factor`], METHOD §4, §11) in a fill-reducing order ([`ordering`]), solved for several
//! right-hand sides in one pass ([`supernodal_solve`]).

pub mod dense;
pub mod factor;
pub mod ordering;
pub mod sparse;
pub mod supernodal_solve;
