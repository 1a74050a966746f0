//! The RON front end: text -> spanned RON tree -> IR.

mod lower;
pub mod print;
pub mod value;

pub use lower::geometry_error;

use crate::diag::Diagnostics;
use crate::ir::Pipeline;
use crate::span::FileId;

/// Parse a pipeline file already added to the source map. Problems go to `diags`;
/// `None` means the file could not be turned into IR at all.
pub fn parse_pipeline(file: FileId, text: &str, diags: &mut Diagnostics) -> Option<Pipeline> {
    let root = match value::parse(file, text) {
        Ok(n) => n,
        Err(d) => {
            diags.push(d);
            return None;
        }
    };
    let before = diags.error_count();
    let p = lower::Lowerer { diags }.pipeline(&root);
    if diags.error_count() > before {
        return None;
    }
    p
}
