//! The bundled effects rendered in process and asserted on pixels: lighting, shadows, AO,
//! indirect light, exposure, anti-aliasing, transparency, the G-buffer layouts, goldens, and
//! the ray-traced options against the reference.
//! One test binary per area; each file below is a module of it.

#[path = "../gpu_common/mod.rs"]
mod gpu_common;

mod ambient_occlusion;
mod antialiasing;
mod area_lights;
mod exposure;
mod gbuffer_layouts;
mod gpu_render;
mod indirect;
mod lighting_models;
mod luminance;
mod ray_traced;
mod scale_free;
mod shadow_acne;
mod sidedness;
mod transparency;
