//! lightbench: run, measure and compare lighting pipelines. This crate holds the CLI; the
//! GPU runtime (executing Plans with wgpu) lands here next. The GPU-free commands
//! (`check`, `plan`) never create a device.

pub mod cli;
