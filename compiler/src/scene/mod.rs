//! Scene descriptions: the one front end for scene files and built-in scenes. A scene file
//! (RON) is parsed into the syntax tree, lowered (`syntax::lower::scene`), value-checked
//! (`check::scene`) and merged with its `builtin:` base here, GPU-free. `check`, `plan`,
//! `render` and every later command read scenes through [`load`]; the runtime adds
//! geometry (built-in meshes, glTF models) to the description it returns. The types live
//! in `ir::scene`, beside the pipeline IR, so that every stage can name them.

mod load;

pub use crate::ir::scene::*;
pub use load::{file_kind, is_model, is_scene_text, load, load_text, opens_with, FileKind};
