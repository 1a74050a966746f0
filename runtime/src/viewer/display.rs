//! Sub-stage `display` of the viewer: any resource as an 8-bit image a person can read —
//! colour as it is (linear values sRGB-encoded), HDR colour tone-mapped (L/(1+L) per
//! channel), depth, integers and one- or two-channel data stretched from their lowest to their
//! highest value (one channel as grey).

use crate::diff::images::{display_rgb8, value_range};
use crate::io::Image;
use lightbench_compiler::format::{ScalarKind, TextureFormat};

pub fn rgb8(img: &Image, format: TextureFormat) -> Vec<u8> {
    let channels = format.components() as usize;
    let eight_bit = format.bytes() / format.components().max(1) == 1;
    let hdr_colour = channels >= 3 && !eight_bit && format.kind() == ScalarKind::Float && !format.is_depth();
    if hdr_colour {
        let mut mapped = img.clone();
        for (i, v) in mapped.rgba.iter_mut().enumerate() {
            if i % 4 != 3 {
                *v = if v.is_finite() { v.max(0.0) / (1.0 + v.max(0.0)) } else { 1.0 };
            }
        }
        return display_rgb8(&mapped, channels, None);
    }
    if channels >= 3 && eight_bit {
        return display_rgb8(img, channels, None);
    }
    display_rgb8(img, channels, Some(value_range(img, img, channels)))
}
