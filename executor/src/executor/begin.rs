//! A frame begins: the caller's inputs checked against the Plan, the frame and light blocks
//! written, and which repetitions of each pass run decided (reuse of unchanged work).

use super::{halton_jitter, Executor, FrameInputs};
use crate::error::{Error, Result};
use crate::reuse::{hash_bytes, FrameKeys, PassInputs};
use crate::Gpu;
use lightbench_compiler::abi::{FrameBlock, LightBlock};
use lightbench_scene::Light;

impl Executor {
    /// Write the frame and light blocks; returns what changed-detection compares.
    fn write_frame_blocks(&mut self, gpu: &Gpu, inputs: &FrameInputs) -> FrameKeys {
        let (w, h) = self.state.plan.resolution;
        let (view, proj) = inputs.view_proj(w as f32 / h.max(1) as f32);
        let eye = inputs.eye();
        let jitter = if self.state.plan.jitter {
            halton_jitter(self.frame_index)
        } else {
            [0.0, 0.0]
        };
        // A pixel offset in NDC: x right, y up (pixels count down).
        let shift = glam::Mat4::from_translation(glam::Vec3::new(2.0 * jitter[0] / w as f32, -2.0 * jitter[1] / h as f32, 0.0));
        let proj = shift * proj;
        let vp = proj * view;
        let (prev_vp, prev_jitter) = self.previous.unwrap_or((vp, jitter));
        self.previous = Some((vp, jitter));
        let frame = FrameBlock {
            view: view.to_cols_array_2d(),
            proj: proj.to_cols_array_2d(),
            view_proj: vp.to_cols_array_2d(),
            inv_view_proj: vp.inverse().to_cols_array_2d(),
            prev_view_proj: prev_vp.to_cols_array_2d(),
            prev_inv_view_proj: prev_vp.inverse().to_cols_array_2d(),
            camera_pos: [eye.x, eye.y, eye.z, 1.0],
            resolution: [w as f32, h as f32, 1.0 / w as f32, 1.0 / h as f32],
            jitter: [jitter[0], jitter[1], prev_jitter[0], prev_jitter[1]],
            time: inputs.time,
            frame_index: self.frame_index as u32,
            light_count: self.shared.punctual().len() as u32,
            scene_radius: ((self.shared.bounds.1 - self.shared.bounds.0).length() * 0.5).max(1e-6),
        };
        gpu.queue.write_buffer(&self.shared.frame_buf, 0, bytemuck::bytes_of(&frame));
        let blocks = self.write_light_blocks(gpu, inputs);
        let camera = [frame.view, frame.proj, frame.prev_view_proj];
        FrameKeys {
            camera: hash_bytes(bytemuck::cast_slice(
                &[bytemuck::cast::<_, [f32; 48]>(camera).as_slice(), &frame.camera_pos, &frame.jitter].concat(),
            )),
            time: inputs.time.to_bits() as u64,
            frame_index: self.frame_index,
            lights: hash_bytes(bytemuck::cast_slice(&blocks)),
            light: blocks.iter().map(|b| hash_bytes(bytemuck::bytes_of(b))).collect(),
        }
    }

    /// Write the light array: the frame's punctual lights (or the scene's, animated), then
    /// the scene's emitters.
    fn write_light_blocks(&self, gpu: &Gpu, inputs: &FrameInputs) -> Vec<LightBlock> {
        let punctual = inputs.lights.as_deref().unwrap_or(self.shared.punctual());
        let emitters = &self.shared.lights[self.shared.punctual().len()..];
        let blocks: Vec<LightBlock> = punctual
            .iter()
            .chain(emitters)
            .map(|l| l.at(inputs.time).block(self.shared.bounds))
            .collect();
        if !blocks.is_empty() {
            gpu.queue.write_buffer(&self.shared.lights_buf, 0, bytemuck::cast_slice(&blocks));
        }
        blocks
    }

    /// Checks and per-frame blocks before a frame's passes; returns which repetitions run.
    pub(super) fn begin_frame(&mut self, gpu: &Gpu, inputs: &FrameInputs) -> Result<Vec<Vec<bool>>> {
        // External resources are the caller's to fill: never render them as zeros.
        if let Some(r) = self
            .state
            .plan
            .resources
            .iter()
            .find(|r| r.external && !self.supplied.contains(&r.name))
        {
            return Err(Error::Unsupplied(r.name.clone()));
        }
        if let Some(lights) = &inputs.lights {
            self.check_lights(lights)?;
        }
        self.apply_params(gpu, &inputs.params)?;
        self.inputs = inputs.clone();
        let keys = self.write_frame_blocks(gpu, inputs);
        Ok(self.decide_runs(&keys))
    }

    /// Frame lights must be the scene's in number, kind and shadow casting (the Plan's
    /// repetitions and shadow resources were made for those).
    fn check_lights(&self, lights: &[Light]) -> Result<()> {
        let scene = self.shared.punctual();
        if lights.len() != scene.len() {
            return Err(Error::Request(format!(
                "FrameInputs::lights has {} lights; the Plan was compiled for the scene's {}: compile for a scene with these lights (Executor::replace_scene)",
                lights.len(),
                scene.len()
            )));
        }
        for (i, (l, s)) in lights.iter().zip(scene).enumerate() {
            if l.kind != s.kind || l.shadows != s.shadows {
                return Err(Error::Request(format!(
                    "FrameInputs::lights[{i}] is a {:?} light{} where the Plan was compiled for a {:?} light{}: compile for a scene with these lights (Executor::replace_scene)",
                    l.kind,
                    if l.shadows { " with shadows" } else { "" },
                    s.kind,
                    if s.shadows { " with shadows" } else { "" },
                )));
            }
        }
        Ok(())
    }

    /// Which repetitions of each pass run this frame (see `reuse`).
    fn decide_runs(&mut self, keys: &FrameKeys) -> Vec<Vec<bool>> {
        let state = &self.state;
        let inputs: Vec<PassInputs> = state
            .passes
            .iter()
            .zip(&state.params)
            .map(|(p, blocks)| PassInputs {
                plan: &p.plan,
                params: {
                    let mut h = std::collections::hash_map::DefaultHasher::new();
                    blocks.iter().for_each(|(_, b)| std::hash::Hash::hash(b, &mut h));
                    std::hash::Hasher::finish(&h)
                },
                rep_lights: p.reps.iter().map(|r| r.light).collect(),
            })
            .collect();
        self.reuse.decide(&state.graph, keys, &inputs)
    }
}
