//! Write a scene as glTF 2.0 (`.gltf` JSON with a `.bin` beside it), so built-in scenes go
//! through the same loader as user files. Lights use KHR_lights_punctual. Files are written
//! atomically.

use super::Scene;
use crate::io::write_atomic;
use lightbench_compiler::ir::LightKind;
use serde_json::json;
use std::path::Path;

pub fn export(scene: &Scene, out: &Path) -> Result<(), String> {
    if !scene.textures.is_empty() {
        return Err(format!("{}: exporting textured scenes is not supported yet", out.display()));
    }
    let bin_name = format!("{}.bin", out.file_stem().and_then(|s| s.to_str()).unwrap_or("scene"));
    let mut bin: Vec<u8> = vec![];
    let (mut accessors, mut views, mut meshes, mut nodes) = (vec![], vec![], vec![], vec![]);
    let mut push_view = |bin: &mut Vec<u8>, data: &[u8], target: u32| {
        while bin.len() % 4 != 0 {
            bin.push(0);
        }
        let offset = bin.len();
        bin.extend_from_slice(data);
        views.push(json!({"buffer": 0, "byteOffset": offset, "byteLength": data.len(), "target": target}));
        views.len() - 1
    };
    for (i, m) in scene.meshes.iter().enumerate() {
        let mut lo = [f32::INFINITY; 3];
        let mut hi = [f32::NEG_INFINITY; 3];
        for v in &m.vertices {
            for k in 0..3 {
                lo[k] = lo[k].min(v.position[k]);
                hi[k] = hi[k].max(v.position[k]);
            }
        }
        let n = m.vertices.len();
        let pos: Vec<f32> = m.vertices.iter().flat_map(|v| v.position).collect();
        let nor: Vec<f32> = m.vertices.iter().flat_map(|v| v.normal).collect();
        let uv: Vec<f32> = m.vertices.iter().flat_map(|v| v.uv).collect();
        let tan: Vec<f32> = m.vertices.iter().flat_map(|v| v.tangent).collect();
        let attr = |bin: &mut Vec<u8>,
                    data: &[f32],
                    ty: &str,
                    accessors: &mut Vec<serde_json::Value>,
                    push_view: &mut dyn FnMut(&mut Vec<u8>, &[u8], u32) -> usize,
                    minmax: bool| {
            let view = push_view(bin, bytemuck::cast_slice(data), 34962);
            let mut a = json!({"bufferView": view, "componentType": 5126, "count": n, "type": ty});
            if minmax {
                a["min"] = json!(lo);
                a["max"] = json!(hi);
            }
            accessors.push(a);
            accessors.len() - 1
        };
        let p = attr(&mut bin, &pos, "VEC3", &mut accessors, &mut push_view, true);
        let no = attr(&mut bin, &nor, "VEC3", &mut accessors, &mut push_view, false);
        let t = attr(&mut bin, &uv, "VEC2", &mut accessors, &mut push_view, false);
        let ta = attr(&mut bin, &tan, "VEC4", &mut accessors, &mut push_view, false);
        let iv = push_view(&mut bin, bytemuck::cast_slice(&m.indices), 34963);
        accessors.push(json!({"bufferView": iv, "componentType": 5125, "count": m.indices.len(), "type": "SCALAR"}));
        let idx = accessors.len() - 1;
        meshes.push(json!({"name": m.name, "primitives": [{"attributes": {"POSITION": p, "NORMAL": no, "TEXCOORD_0": t, "TANGENT": ta}, "indices": idx, "material": m.material}]}));
        nodes.push(json!({"name": m.name, "mesh": i, "matrix": m.transform.to_cols_array()}));
    }
    let materials: Vec<serde_json::Value> = scene
        .materials
        .iter()
        .map(|m| json!({"name": m.name, "pbrMetallicRoughness": {"baseColorFactor": m.base_color, "metallicFactor": m.metallic, "roughnessFactor": m.roughness}, "emissiveFactor": m.emissive}))
        .collect();
    let mut lights = vec![];
    for l in &scene.lights {
        if !l.on {
            continue; // the glTF extension has no "off"
        }
        let mut j = json!({"color": l.color.to_array(), "intensity": l.intensity});
        match l.kind {
            LightKind::Directional => j["type"] = json!("directional"),
            LightKind::Point => {
                j["type"] = json!("point");
                j["range"] = json!(l.range);
            }
            LightKind::Spot => {
                j["type"] = json!("spot");
                j["range"] = json!(l.range);
                j["spot"] = json!({"innerConeAngle": l.inner_angle.to_radians(), "outerConeAngle": l.outer_angle.to_radians()});
            }
        }
        lights.push(j);
        // Orient the node so that its -Z is the light direction.
        let d = l.direction.normalize_or_zero();
        let rot = glam::Quat::from_rotation_arc(glam::Vec3::NEG_Z, if d == glam::Vec3::ZERO { glam::Vec3::NEG_Y } else { d });
        nodes.push(json!({"name": format!("light_{}", lights.len() - 1), "translation": l.position.to_array(), "rotation": rot.to_array(), "extensions": {"KHR_lights_punctual": {"light": lights.len() - 1}}}));
    }
    let doc = json!({
        "asset": {"version": "2.0", "generator": "lightbench"},
        "extensionsUsed": if lights.is_empty() { json!([]) } else { json!(["KHR_lights_punctual"]) },
        "extensions": {"KHR_lights_punctual": {"lights": lights}},
        "scene": 0,
        "scenes": [{"name": scene.name, "nodes": (0..nodes.len()).collect::<Vec<_>>()}],
        "nodes": nodes,
        "meshes": meshes,
        "materials": materials,
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [{"uri": bin_name, "byteLength": bin.len()}],
    });
    let dir = out.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    write_atomic(&dir.join(&bin_name), &bin)?;
    let text = serde_json::to_string_pretty(&doc).map_err(|e| e.to_string())?;
    write_atomic(out, text.as_bytes())
}
