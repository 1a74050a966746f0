//! lightbench: run, measure and compare lighting pipelines. `check` and `plan` never create
//! a GPU device; `render` executes the compiled Plan with wgpu.

pub mod cli;
pub mod gpu;
pub mod io;
pub mod render;
pub mod scene;
