//! Lopin in the browser: the wasm-bindgen entry point that starts the desktop explorer's
//! [`lopin_explorer::ExplorerApp`] on the page's canvas (eframe's web runner, wgpu on WebGL2),
//! and mirrors the explorer's state into the page (title and `#lopin-status` attributes, see
//! [`lopin_explorer::page_report`]) so scripts and end-to-end tests can follow it. The solver
//! runs in a Web Worker ([`solver_worker`]), so its iterations do not wait for frames. On the desktop this crate is
//! empty.

#[cfg(target_arch = "wasm32")]
mod entry;
#[cfg(target_arch = "wasm32")]
mod page;
#[cfg(target_arch = "wasm32")]
mod solver_worker;
