//! Executor, lights replaced: a new Plan for the same geometry with other lights (added,
//! removed, of another kind or shadow casting) or other effects called for. The meshes,
//! textures and acceleration structure stay on the GPU; the light array and its buffer are
//! made again.

use super::{lights_buffer, Executor};
use crate::error::Result;
use crate::Gpu;
use lightbench_compiler::ir::Effect;
use lightbench_compiler::Executable;
use lightbench_scene::Light;

impl Executor {
    /// Take `exe`, compiled for this scene with `lights` (as `Scene::lights` holds them) and
    /// `effects`, at a frame boundary, without uploading the scene again (what
    /// `replace_scene` does). On failure the running Plan and its lights are left as they were.
    pub fn replace_lights(
        &mut self,
        gpu: &Gpu,
        exe: &Executable,
        (lights, effects): (Vec<Light>, std::collections::BTreeSet<Effect>),
    ) -> Result<super::ReloadReport> {
        let shared = &mut self.shared;
        let old_effects = std::mem::replace(&mut shared.scene.effects, effects);
        let old_lights = std::mem::replace(&mut shared.scene.lights, lights);
        let old_array = std::mem::replace(&mut shared.lights, shared.scene.light_array());
        let old_buf = std::mem::replace(&mut shared.lights_buf, lights_buffer(&gpu.device, shared.lights.len()));
        match self.replace(gpu, exe) {
            Ok(report) => {
                // Frame lights were checked against the old ones.
                self.inputs.lights = None;
                Ok(report)
            }
            Err(e) => {
                let shared = &mut self.shared;
                (shared.scene.lights, shared.lights, shared.lights_buf) = (old_lights, old_array, old_buf);
                shared.scene.effects = old_effects;
                Err(e)
            }
        }
    }
}
