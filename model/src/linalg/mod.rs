//! Linear algebra the model needs: small dense solves ([`dense`]), symmetric sparse matrices
//! from element triplets ([`sparse`]) and their sparse Cholesky factorization, computed once
//! ([`factor`], METHOD §4, §11) in a fill-reducing order ([`ordering`]).

pub mod dense;
pub mod factor;
pub mod ordering;
pub mod sparse;
