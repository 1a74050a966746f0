//! Executing Plans with wgpu.

pub mod blocks;
pub mod convert;
pub mod device;
pub mod executor;
pub mod pool;
pub mod readback;
pub mod scene_gpu;

pub use device::{DeviceOptions, Gpu};
pub use executor::{Executor, PassTiming};
