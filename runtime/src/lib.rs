//! lightbench, the application: the command line (`check`, `plan`, `render`, `reference`,
//! `sweep`, `diff`, `verify`, `view`, `lsp`) over the library crates — the compiler
//! (`lightbench-compiler`, GPU-free), scenes (`lightbench-scene`), the executor
//! (`lightbench-executor`, wgpu) and the reference path tracer (`lightbench-reference`), re-exported
//! here under the module names the commands use.

pub use error::{Error, Result};
pub use lightbench_compiler::abi as blocks;
pub use lightbench_executor::{self as gpu, reload, render};
pub use lightbench_reference as reference;
pub use lightbench_scene::{self as scene, files, io};

pub mod bundled;
pub mod cli;
pub mod diff;
pub mod error;
pub mod gpu_reference;
pub mod lsp;
pub mod memory;
pub mod notes;
pub mod regions;
pub mod sweep;
pub mod verify;
pub mod viewer;
