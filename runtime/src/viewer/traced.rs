//! Sub-stage `traced` of the viewer: the path-traced view beside the raster one — the GPU
//! path tracer (`pipelines/pathtrace.lbp`, what `reference --device gpu` runs) on the same
//! scene, camera and lights, its image refining frame by frame while nothing changes, and
//! starting again when the camera, a light or the scene does.

use crate::error::{Error, Result};
use crate::gpu::{Executor, Gpu};
use crate::scene::{Camera, Light, Scene};
use lightbench_compiler::ir::ParamValue;

pub struct Traced {
    pub ex: Executor,
    /// Paths per pixel behind the image shown.
    pub samples: u32,
    /// Paths each frame adds, and where the accumulation stops (the pipeline's parameters).
    per_frame: u32,
    max: u32,
    /// The last frame's view and projection (view matrix, fov, near, far): the path tracer
    /// starts again when they change.
    camera: Option<(glam::Mat4, [f32; 3])>,
}

/// The pipeline's value of an integer parameter.
fn int_param(ex: &Executor, name: &str) -> u32 {
    let inputs = ex.inputs(0.0);
    match ex.plan().params.iter().find(|p| p.name == name).map(|p| inputs.params.value_of(p)) {
        Some(ParamValue::Int(v)) => (*v).clamp(1, u32::MAX as i64) as u32,
        _ => 1,
    }
}

impl Traced {
    /// The path tracer on `scene`; refused by name on an adapter without ray queries.
    pub fn new(gpu: &Gpu, scene: &Scene) -> Result<Traced> {
        if !gpu.device.features().contains(wgpu::Features::EXPERIMENTAL_RAY_QUERY) {
            return Err(Error::adapter(format!(
                "the path-traced view needs ray queries (wgpu feature EXPERIMENTAL_RAY_QUERY), which `{}` lacks",
                gpu.info.name
            )));
        }
        let (pipeline, ws) = crate::gpu_reference::source(None)?;
        let (exe, _) = crate::render::compile_in(&ws, gpu, &pipeline, None, scene, &[])?;
        let ex = Executor::new(gpu, &exe, scene)?;
        let (per_frame, max) = (int_param(&ex, "pt.samples"), int_param(&ex, "pt.max_samples"));
        Ok(Traced {
            ex,
            samples: 0,
            per_frame,
            max,
            camera: None,
        })
    }

    /// One frame from `camera` with `lights`: more paths, or the first of a new image where
    /// the camera moved (the shader restarts then, comparing this frame's view with the last).
    pub fn frame(&mut self, gpu: &Gpu, camera: &Camera, lights: &[Light]) -> Result<()> {
        let mut inputs = self.ex.inputs(0.0);
        inputs.camera = camera.clone();
        inputs.lights = Some(lights.to_vec());
        self.ex.render_frame(gpu, &inputs)?;
        let seen = Some((camera.view(), [camera.fov, camera.near, camera.far]));
        if self.camera != seen {
            self.samples = 0;
        }
        self.camera = seen;
        self.samples = (self.samples + self.per_frame).min(self.max);
        Ok(())
    }

    /// The caption of the image shown.
    pub fn caption(&self) -> String {
        format!("path traced, {} paths per pixel", self.samples)
    }
}
