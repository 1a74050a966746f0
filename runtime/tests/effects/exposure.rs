//! Exposure and tone mapping that keep colour: metered and compressed by each pixel's largest
//! channel, a saturated object keeps its faces apart and no channel clips; on greys the rule
//! is the seed's luminance rule exactly; `tonemap.by_luminance` brings the seed's back.

use crate::gpu_common;

use glam::{Mat4, Quat, Vec3};
use gpu_common::*;
use lightbench::io::Image;
use lightbench::scene::geometry::cuboid;
use lightbench::scene::{builtin, Camera, Light, Material, Scene};
use lightbench_compiler::ir::ParamValue;

/// A pure red box turned 40° on a black background, seen from above a corner so that three
/// faces show, lit by a key light and a fill; with the image points of the three face centres.
fn red_box() -> (Scene, [(u32, u32); 3]) {
    let turn = Quat::from_rotation_y(40f32.to_radians());
    let mut s = Scene {
        name: "red box".into(),
        size: (96, 96),
        camera: Camera {
            position: Vec3::new(0.0, 1.6, 2.6),
            yaw: 0.0,
            pitch: -30.0,
            fov: 45.0,
            near: 0.05,
            far: 20.0,
            animation: None,
        },
        meshes: vec![mesh("box", cuboid(Vec3::splat(0.5)), Mat4::from_quat(turn))],
        materials: vec![Material::color("red", [1.0, 0.0, 0.0], 1.0)],
        textures: vec![],
        lights: vec![
            Light::directional(Vec3::new(0.5, -1.0, -0.7), Vec3::ONE, 3.0),
            Light::directional(Vec3::new(-1.0, -0.2, -0.3), Vec3::ONE, 1.0),
        ],
        effects: Default::default(),
    };
    s.effects.insert(lightbench_compiler::ir::Effect::Shadows);
    let at = |p: Vec3| {
        let (x, y) = s.project(turn * p).unwrap();
        (x as u32, y as u32)
    };
    let faces = [at(Vec3::Y * 0.5), at(Vec3::NEG_X * 0.5), at(Vec3::Z * 0.5)];
    (s, faces)
}

fn ldr(s: &Scene, by_luminance: bool) -> Image {
    ldr_with(s, by_luminance, &[])
}

fn ldr_with(s: &Scene, by_luminance: bool, more: &[(&str, ParamValue)]) -> Image {
    let g = gpu();
    let (exe, _) = lightbench::render::compile(&g, &deferred(), None, s, &[]).unwrap();
    let mut params = vec![("tonemap.by_luminance".to_string(), ParamValue::Bool(by_luminance))];
    params.extend(more.iter().map(|(k, v)| (k.to_string(), v.clone())));
    let ex = lightbench::render::render_with(&g, &exe, s, 1, &params).unwrap();
    output(&g, &ex)
}

fn levels(p: [f32; 4]) -> [u8; 3] {
    [0, 1, 2].map(|c| (p[c].clamp(0.0, 1.0) * 255.0).round() as u8)
}

#[test]
fn a_red_box_keeps_three_distinct_faces_and_no_channel_clips() {
    let (s, faces) = red_box();
    let img = ldr(&s, false);
    let reds: Vec<[u8; 3]> = faces.iter().map(|&(x, y)| levels(img.pixel(x, y))).collect();
    eprintln!("faces (top, -x, +z): {reds:?}");
    for (i, a) in reds.iter().enumerate() {
        assert!(a[0] > 20, "face {i} is lit: {a:?}");
        // (sRGB levels: the specular lobe's 4% of white shows as a fifth of the red)
        assert!(a[1] <= a[0] / 4 && a[2] <= a[0] / 4, "face {i} stays red: {a:?}");
        for b in &reds[i + 1..] {
            assert!(a[0].abs_diff(b[0]) >= 8, "faces apart: {reds:?}");
        }
    }
    // Only the brightest face may reach Reinhard's white point (1 by its definition); no
    // channel is clamped, since the largest one is mapped and never exceeds it.
    assert!(reds.iter().filter(|p| p[0] == 255).count() <= 1, "{reds:?}");
    // The seed's rule, by luminance: a pure red's luminance is a fifth of its red, so the
    // faces clip to one red.
    let seed = ldr(&s, true);
    let clipped = faces.iter().filter(|&&(x, y)| levels(seed.pixel(x, y))[0] == 255).count();
    assert!(
        clipped >= 2,
        "by luminance the faces clip: {:?}",
        faces.map(|(x, y)| levels(seed.pixel(x, y)))
    );
}

/// On greys the largest channel is the luminance: the Cornell box in grey (materials, lights
/// and ambient light) renders the same either way.
#[test]
fn a_grey_scene_is_unchanged() {
    let mut s = builtin::cornell();
    s.size = (64, 64);
    for m in &mut s.materials {
        let grey = (m.base_color[0] + m.base_color[1] + m.base_color[2]) / 3.0;
        m.base_color = [grey, grey, grey, 1.0];
    }
    for l in &mut s.lights {
        l.color = Vec3::ONE;
    }
    let grey = [("ambient.color", ParamValue::Vec(vec![0.03, 0.03, 0.03]))];
    let (a, b) = (ldr_with(&s, false, &grey), ldr_with(&s, true, &grey));
    let worst = a.rgba.iter().zip(&b.rgba).map(|(x, y)| (x - y).abs()).fold(0.0, f32::max);
    assert!(worst <= 1.5 / 255.0, "largest difference {worst}");
}

/// The coloured Cornell box: the share of drawn pixels with a channel at 255 falls from the
/// seed's rule to the largest-channel rule.
#[test]
fn the_coloured_cornell_box_clips_less() {
    let mut s = builtin::cornell();
    s.size = (64, 64);
    let share = |img: &Image| {
        let n = img
            .rgba
            .chunks_exact(4)
            .filter(|p| p[..3].iter().any(|&v| v >= 254.5 / 255.0))
            .count();
        n as f64 / (img.width * img.height) as f64
    };
    let (ours, seed) = (share(&ldr(&s, false)), share(&ldr(&s, true)));
    eprintln!(
        "pixels with a channel at 255: {:.1}% (largest channel), {:.1}% (luminance)",
        ours * 100.0,
        seed * 100.0
    );
    assert!(ours < 0.01 && seed > ours, "{ours} vs {seed}");
}
