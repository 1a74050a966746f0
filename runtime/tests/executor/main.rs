//! The executor: aliased transient memory, frames in flight, reload of a running Plan, hot
//! reload from files on disk, and a second, small executor that runs a Plan alone.
//! One test binary per area; each file below is a module of it.

#[path = "../gpu_common/mod.rs"]
mod gpu_common;

mod aliasing;
mod embedding;
mod hot_reload;
mod in_flight;
mod limits;
mod plan_only;
mod reload;
