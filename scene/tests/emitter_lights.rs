//! Scene loading: the emissive meshes become Area lights after the punctual ones.

use glam::Vec3;
use lightbench_compiler::ir::LightKind;
use lightbench_scene::emitter_lights::MAX_EMITTER_LIGHTS;
use lightbench_scene::{load, Light};

/// The built-in lamp-lit box's panel is one Area light: at the panel's centre, facing down,
/// its area and radiance as the panel's; the punctual lights come first in the array.
#[test]
fn the_lamp_panel_is_one_area_light_after_the_punctual_ones() {
    let s = load("cornell_lamp").unwrap();
    let lights = s.light_array();
    let area: Vec<&Light> = lights.iter().filter(|l| l.kind == LightKind::Area).collect();
    assert_eq!(area.len(), 1, "{lights:?}");
    assert!(lights.iter().rev().take(1).all(|l| l.kind == LightKind::Area), "emitters last");
    let l = area[0];
    assert!((l.position - Vec3::new(0.0, 1.99, 0.0)).length() < 1e-5, "{}", l.position);
    assert!((l.direction - Vec3::NEG_Y).length() < 1e-5, "{}", l.direction);
    // A 0.47 × 0.38 panel.
    assert!((l.intensity - 0.47 * 0.38).abs() < 1e-5, "{}", l.intensity);
    assert_eq!(l.color, Vec3::new(17.0, 12.0, 4.0));
    assert!(!l.shadows);
}

/// Past `MAX_EMITTER_LIGHTS` emissive meshes the least powerful are left out.
#[test]
fn at_most_four_emitters_are_lights_the_most_powerful() {
    let mut s = load("cornell_lamp").unwrap();
    let lamp = s.meshes.iter().position(|m| m.name == "lamp").unwrap();
    let base = s.materials[s.meshes[lamp].material].clone();
    for k in 1..=5 {
        let mut m = base.clone();
        m.emissive = [k as f32; 3];
        s.materials.push(m);
        let mut mesh = s.meshes[lamp].clone();
        mesh.material = s.materials.len() - 1;
        s.meshes.push(mesh);
    }
    let area: Vec<Light> = s.emitter_lights();
    assert_eq!(area.len(), MAX_EMITTER_LIGHTS);
    // The panel (17, 12, 4) first, then radiance 5, 4, 3: 2 and 1 are dropped.
    let sums: Vec<f32> = area.iter().map(|l| l.color.x + l.color.y + l.color.z).collect();
    assert_eq!(sums, [33.0, 15.0, 12.0, 9.0]);
}
