//! The RON front end: a parser into the syntax tree and a printer of it.

pub mod parse;
pub mod print;

use crate::diag::Diagnostics;
use crate::ir::Pipeline;
use crate::span::FileId;

/// Parse a pipeline file already added to the source map and lower it. Problems go to
/// `diags`; `None` means the file could not be turned into IR at all.
/// Parse RON text into the syntax tree. Syntax problems go to `diags`.
pub fn parse_tree(file: FileId, text: &str, diags: &mut Diagnostics) -> Option<crate::tree::Node> {
    parse::parse(file, text).map_err(|d| diags.push(d)).ok()
}

pub fn parse_pipeline(file: FileId, text: &str, diags: &mut Diagnostics) -> Option<Pipeline> {
    match parse::parse(file, text) {
        Ok(root) => crate::syntax::lower::pipeline(&root, diags),
        Err(d) => {
            diags.push(d);
            None
        }
    }
}
