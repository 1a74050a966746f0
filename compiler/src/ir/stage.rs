//! Shader stages: one enum shared by the IR, the Plan and the runtime.

use serde::{Deserialize, Serialize};

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub enum Stage {
    Vertex,
    Fragment,
    Compute,
}

impl Stage {
    pub const ALL: [Stage; 3] = [Stage::Vertex, Stage::Fragment, Stage::Compute];

    /// The lower-case word used in messages and plans: `vertex`, `fragment`, `compute`.
    pub fn word(self) -> &'static str {
        match self {
            Stage::Vertex => "vertex",
            Stage::Fragment => "fragment",
            Stage::Compute => "compute",
        }
    }

    pub fn naga(self) -> naga::ShaderStage {
        match self {
            Stage::Vertex => naga::ShaderStage::Vertex,
            Stage::Fragment => naga::ShaderStage::Fragment,
            Stage::Compute => naga::ShaderStage::Compute,
        }
    }

    /// `None` for stages lightbench does not run (task, mesh).
    pub fn from_naga(s: naga::ShaderStage) -> Option<Stage> {
        match s {
            naga::ShaderStage::Vertex => Some(Stage::Vertex),
            naga::ShaderStage::Fragment => Some(Stage::Fragment),
            naga::ShaderStage::Compute => Some(Stage::Compute),
            _ => None,
        }
    }
}

/// How naga names a stage in messages (`mesh/task` for those lightbench does not run).
pub fn naga_stage_word(s: naga::ShaderStage) -> &'static str {
    Stage::from_naga(s).map(Stage::word).unwrap_or("mesh/task")
}
