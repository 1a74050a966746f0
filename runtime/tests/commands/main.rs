//! The GPU commands as a user runs them (`render`, `diff`, `sweep`, `verify`, `view`): the
//! binary on lavapipe, exit codes, outputs and reports.
//! One test binary per area; each file below is a module of it.

#[path = "../cli_common/mod.rs"]
mod cli_common;
#[path = "../gpu_common/mod.rs"]
mod gpu_common;
#[path = "../mutate/mod.rs"]
mod mutate;

mod cli_render;
mod diff;
mod examples;
mod sweep;
mod tutorial;
mod verify;
mod view_script_mutants;
mod viewer;
mod viewer_display;
mod viewer_lights;
