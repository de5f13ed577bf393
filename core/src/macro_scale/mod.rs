//! The two-scale linear stage's macro problem (METHOD §9): the macro space of each interface
//! ([`macro_basis`]), the homogenized operators and the global macro operator
//! ([`macro_problem`]), and which substructures share one factorization and one homogenized
//! operator ([`operator_classes`]).

pub mod macro_basis;
pub mod macro_problem;
pub mod operator_classes;
