//! Front ends: each turns a pipeline file into the one IR.

pub mod comments;
pub mod lbp;
pub mod ron;
