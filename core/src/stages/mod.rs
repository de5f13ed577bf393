//! The two stages of a LATIN iteration and what judges and speeds it: the local stage, closed
//! forms per interface point and step ([`local_stage`], METHOD §5); the linear stage, one
//! substructure's march driven through the search direction ([`linear_stage`], METHOD §2, §4);
//! the guesses a single-precision solve is refined from ([`refinement`]); the error indicator η
//! ([`indicator`], METHOD §6); and Anderson mixing of the relaxation ([`acceleration`]).

pub mod acceleration;
pub mod indicator;
pub mod linear_stage;
pub mod local_stage;
pub mod refinement;
