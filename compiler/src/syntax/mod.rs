//! The syntax layer shared by every front end: one spanned tree, one table of defaults,
//! one lowering (tree -> IR) and one raise (IR -> tree) that both printers print.

pub mod defaults;
pub mod lower;
pub mod raise;
pub mod tree;
