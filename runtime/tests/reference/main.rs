//! The reference path tracer: against the raster pipelines, analytic answers and the goldens
//! of the renderer before emitters; emissive surfaces as lights.
//! One test binary per area; each file below is a module of it.

#[path = "../cli_common/mod.rs"]
mod cli_common;
#[path = "../gpu_common/mod.rs"]
mod gpu_common;

mod agreement;
mod gpu_reference;
mod gpu_reference_cli;
mod gpu_reference_viewer;
mod integrators;
mod reference;
mod reference_emitters;
