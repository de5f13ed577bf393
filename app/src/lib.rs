//! The `lopin` program as a library: the command line ([`cli`]), ParaView export ([`export`]),
//! Rerun recordings ([`record`]) and run directories ([`run_dir`]). The binary (`main.rs`) only
//! parses the arguments; tests drive the same code, e.g. the explorer with the real recorder.

pub mod build_info;
pub mod cli;
pub mod export;
pub mod ranks;
pub mod record;
pub mod result_folder;
pub mod run_dir;
