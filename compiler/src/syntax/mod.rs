//! The syntax layer shared by every front end: one table of defaults, one lowering
//! (`crate::tree` -> IR) and one raise (IR -> tree) that both printers print.

pub mod compose;
pub mod defaults;
pub mod groups;
pub mod light_choices;
pub mod lower;
pub mod raise;
