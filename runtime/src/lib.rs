//! lightbench: run, measure and compare lighting pipelines. `check` and `plan` never create
//! a GPU device; `render` executes the compiled Plan with wgpu.

pub use error::{Error, Result};

pub mod blocks;
pub mod bundled;
pub mod cli;
pub mod diff;
pub mod error;
pub mod files;
pub mod gpu;
pub mod io;
pub mod lsp;
pub mod memory;
pub mod reference;
pub mod reload;
pub mod render;
pub mod scene;
pub mod sweep;
pub mod verify;
pub mod viewer;
