//! Texture formats and what each allows: sample type, filtering, blending, depth, storage.
//! Mirrors the WebGPU/wgpu format tables so the compiler can derive layouts offline.

use crate::profile::{Feature, Profile};
use serde::{Deserialize, Serialize};

/// What a shader reads out of a format.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum ScalarKind {
    Float,
    Uint,
    Sint,
    Depth,
}

macro_rules! formats {
    ($( $name:ident => ($bytes:expr, $comps:expr, $kind:ident, $filter:expr, $blend:expr, $storage:expr) ),* $(,)?) => {
        #[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
        pub enum TextureFormat { $($name),* }

        impl TextureFormat {
            pub const ALL: &'static [TextureFormat] = &[$(TextureFormat::$name),*];
            pub const NAMES: &'static [&'static str] = &[$(stringify!($name)),*];
            pub fn name(self) -> &'static str {
                match self { $(TextureFormat::$name => stringify!($name)),* }
            }
            /// Bytes per texel.
            pub fn bytes(self) -> u32 {
                match self { $(TextureFormat::$name => $bytes),* }
            }
            pub fn components(self) -> u32 {
                match self { $(TextureFormat::$name => $comps),* }
            }
            pub fn kind(self) -> ScalarKind {
                match self { $(TextureFormat::$name => ScalarKind::$kind),* }
            }
            /// Filterable without optional features (32-bit floats need FLOAT32_FILTERABLE).
            fn base_filterable(self) -> bool {
                match self { $(TextureFormat::$name => $filter),* }
            }
            pub fn blendable(self) -> bool {
                match self { $(TextureFormat::$name => $blend),* }
            }
            /// Usable as a write-only storage texture.
            pub fn storage(self) -> bool {
                match self { $(TextureFormat::$name => $storage),* }
            }
        }
    };
}

formats! {
    R8Unorm => (1, 1, Float, true, true, false),
    Rg8Unorm => (2, 2, Float, true, true, false),
    Rgba8Unorm => (4, 4, Float, true, true, true),
    Rgba8UnormSrgb => (4, 4, Float, true, true, false),
    Bgra8Unorm => (4, 4, Float, true, true, false),
    Bgra8UnormSrgb => (4, 4, Float, true, true, false),
    Rgb10a2Unorm => (4, 4, Float, true, true, false),
    Rg11b10Ufloat => (4, 3, Float, true, true, false),
    R16Float => (2, 1, Float, true, true, false),
    Rg16Float => (4, 2, Float, true, true, false),
    Rgba16Float => (8, 4, Float, true, true, true),
    R32Float => (4, 1, Float, false, false, true),
    Rg32Float => (8, 2, Float, false, false, true),
    Rgba32Float => (16, 4, Float, false, false, true),
    R32Uint => (4, 1, Uint, false, false, true),
    Rg32Uint => (8, 2, Uint, false, false, true),
    Rgba32Uint => (16, 4, Uint, false, false, true),
    R32Sint => (4, 1, Sint, false, false, true),
    Rgba16Uint => (8, 4, Uint, false, false, true),
    Depth16Unorm => (2, 1, Depth, false, false, false),
    Depth24Plus => (4, 1, Depth, false, false, false),
    Depth32Float => (4, 1, Depth, false, false, false),
    Depth24PlusStencil8 => (4, 1, Depth, false, false, false),
}

impl TextureFormat {
    pub fn from_name(s: &str) -> Option<Self> {
        Self::NAMES.iter().position(|n| *n == s).map(|i| Self::ALL[i])
    }
    pub fn is_depth(self) -> bool {
        self.kind() == ScalarKind::Depth
    }
    pub fn is_32bit_float(self) -> bool {
        matches!(
            self,
            TextureFormat::R32Float | TextureFormat::Rg32Float | TextureFormat::Rgba32Float
        )
    }
    /// Can a filtering sampler read it on this profile?
    pub fn filterable(self, profile: &Profile) -> bool {
        self.base_filterable() || (self.is_32bit_float() && profile.has(Feature::Float32Filterable))
    }
    /// Usable as a color attachment on this profile.
    pub fn renderable(self, profile: &Profile) -> bool {
        !self.is_depth()
            && (self != TextureFormat::Rg11b10Ufloat || profile.has(Feature::Rg11b10UfloatRenderable))
            && (!self.is_32bit_float() || profile.has(Feature::Float32Renderable))
    }

    pub fn is_srgb(self) -> bool {
        matches!(self, TextureFormat::Rgba8UnormSrgb | TextureFormat::Bgra8UnormSrgb)
    }
}
