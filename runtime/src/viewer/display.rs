//! Sub-stage `display` of the viewer: any resource as an 8-bit image a person can read —
//! colour as it is (linear values sRGB-encoded), HDR colour tone-mapped (L/(1+L) per
//! channel), depth linearised with the camera's near and far planes (shadow maps have their
//! own, but the stretch below makes any perspective depth readable), then depth, integers and
//! one- or two-channel data stretched from their lowest to their highest value (one channel as
//! grey).

use crate::diff::images::{display_rgb8, value_range};
use crate::io::Image;
use lightbench_compiler::format::{ScalarKind, TextureFormat};

pub fn rgb8(img: &Image, format: TextureFormat, (near, far): (f32, f32)) -> Vec<u8> {
    let channels = format.components() as usize;
    let eight_bit = format.bytes() / format.components().max(1) == 1;
    let hdr_colour = channels >= 3 && !eight_bit && format.kind() == ScalarKind::Float && !format.is_depth();
    if hdr_colour {
        return display_rgb8(&img.tone_mapped(), channels, None);
    }
    if channels >= 3 && eight_bit {
        return display_rgb8(img, channels, None);
    }
    if format.is_depth() {
        // Perspective depth d in 0..1 back to view distance: n·f / (f − d·(f − n)).
        let mut lin = img.clone();
        for px in lin.rgba.chunks_mut(4) {
            px[0] = near * far / (far - px[0].clamp(0.0, 1.0) * (far - near)).max(1e-6);
        }
        return display_rgb8(&lin, 1, Some(value_range(&lin, &lin, 1)));
    }
    display_rgb8(img, channels, Some(value_range(img, img, channels)))
}
