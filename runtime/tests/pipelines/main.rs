//! The pipeline language rendered: choices inside a pass, specialisation constants, pipelines
//! as data (user pipelines, shaders and data resources), the language's forms.
//! One test binary per area; each file below is a module of it.

#[path = "../cli_common/mod.rs"]
mod cli_common;
#[path = "../gpu_common/mod.rs"]
mod gpu_common;

mod choices;
mod constants;
mod mutants;
mod pipeline_language;
mod pipelines_as_data;
