//! Time: the uniform grid and the prescribed time functions ([`time_function`], METHOD §1, §10)
//! and the time scheme of every substructure and of the reference ([`time_scheme`], METHOD §2).

pub mod time_function;
pub mod time_scheme;
