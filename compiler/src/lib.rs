//! lightbench-compiler: pipeline file -> syntax tree -> IR -> checks -> Plan, with no GPU.
//!
//! ```text
//! pipeline file --front end (ron | lbp: parsers only)--> syntax tree --lower--> IR
//! IR --checks (named stages, naga-validated shaders)--> Checked
//! Checked + scene features + variant choice + capability profile --plan (named stages)--> Plan
//! ```
//!
//! A long-running process (watcher, viewer) holds a [`Workspace`]: a virtual file system, a
//! content-hashed cache of compiled shader modules, and per compilation the set of files the
//! result depended on.

pub mod abi;
pub mod check;
pub mod data;
pub mod diag;
pub mod format;
pub mod front;
pub mod ir;
pub mod layout;
pub mod memo;
pub mod plan;
pub mod profile;
pub mod scene;
pub mod shader;
pub mod span;
pub mod syntax;
pub mod tree;
pub mod vfs;
pub mod workspace;

pub use workspace::{files_below, pipeline_files, shader_root_for, Executable, Session, Workspace};
