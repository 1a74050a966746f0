//! Tests that need no GPU adapter: the commands that check, plan, convert and format, the
//! command line against hostile use, sweep specs, and the language server (in process, over
//! stdio and from Neovim).
//! One test binary per area; each file below is a module of it.

#[path = "../cli_common/mod.rs"]
mod cli_common;
#[path = "../mutate/mod.rs"]
mod mutate;

mod cli;
mod cli_safety;
mod lsp;
mod lsp_editing;
mod lsp_mutants;
mod lsp_neovim;
mod manual;
mod sweep_spec_mutants;
