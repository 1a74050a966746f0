//! Write a scene as glTF 2.0 (`.gltf` JSON with a `.bin` beside it), so built-in scenes go
//! through the same loader as user files. Lights use KHR_lights_punctual. Files are written
//! atomically.

use super::Scene;
use crate::error::{Error, Result};
use crate::files::write_atomic_all;
use lightbench_compiler::ir::LightKind;
use serde_json::{json, Value};
use std::path::Path;

const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;
const FLOAT: u32 = 5126;
const UNSIGNED_INT: u32 = 5125;

/// The binary buffer with its views and accessors, filled as meshes are added.
#[derive(Default)]
struct Buffers {
    bin: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Buffers {
    fn view(&mut self, data: &[u8], target: u32) -> usize {
        while !self.bin.len().is_multiple_of(4) {
            self.bin.push(0);
        }
        self.views
            .push(json!({"buffer": 0, "byteOffset": self.bin.len(), "byteLength": data.len(), "target": target}));
        self.bin.extend_from_slice(data);
        self.views.len() - 1
    }

    fn accessor(
        &mut self,
        data: &[u8],
        target: u32,
        component: u32,
        count: usize,
        ty: &str,
        bounds: Option<([f32; 3], [f32; 3])>,
    ) -> usize {
        let view = self.view(data, target);
        let mut a = json!({"bufferView": view, "componentType": component, "count": count, "type": ty});
        if let Some((lo, hi)) = bounds {
            a["min"] = json!(lo);
            a["max"] = json!(hi);
        }
        self.accessors.push(a);
        self.accessors.len() - 1
    }
}

pub fn export(scene: &Scene, out: &Path) -> Result<()> {
    if !scene.textures.is_empty() {
        return Err(Error::io(out, "exporting textured scenes is not supported yet"));
    }
    let bin_name = format!("{}.bin", out.file_stem().and_then(|s| s.to_str()).unwrap_or("scene"));
    let mut b = Buffers::default();
    let (mut meshes, mut nodes) = (vec![], vec![]);
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
        let p = b.accessor(bytemuck::cast_slice(&pos), ARRAY_BUFFER, FLOAT, n, "VEC3", Some((lo, hi)));
        let no = b.accessor(bytemuck::cast_slice(&nor), ARRAY_BUFFER, FLOAT, n, "VEC3", None);
        let t = b.accessor(bytemuck::cast_slice(&uv), ARRAY_BUFFER, FLOAT, n, "VEC2", None);
        let ta = b.accessor(bytemuck::cast_slice(&tan), ARRAY_BUFFER, FLOAT, n, "VEC4", None);
        let idx = b.accessor(
            bytemuck::cast_slice(&m.indices),
            ELEMENT_ARRAY_BUFFER,
            UNSIGNED_INT,
            m.indices.len(),
            "SCALAR",
            None,
        );
        meshes.push(json!({"name": m.name, "primitives": [{"attributes": {"POSITION": p, "NORMAL": no, "TEXCOORD_0": t, "TANGENT": ta}, "indices": idx, "material": m.material}]}));
        nodes.push(json!({"name": m.name, "mesh": i, "matrix": m.transform.to_cols_array()}));
    }
    let materials: Vec<Value> = scene
        .materials
        .iter()
        .map(|m| {
            // glTF holds emissive factors within 0..1: brighter emission is a strength
            // (KHR_materials_emissive_strength) times the factor.
            let strength = m.emissive.iter().copied().fold(1.0f32, f32::max);
            let factor = m.emissive.map(|c| c / strength);
            let mut v = json!({"name": m.name, "pbrMetallicRoughness": {"baseColorFactor": m.base_color, "metallicFactor": m.metallic, "roughnessFactor": m.roughness}, "emissiveFactor": factor, "doubleSided": m.double_sided});
            if strength > 1.0 {
                v["extensions"] = json!({"KHR_materials_emissive_strength": {"emissiveStrength": strength}});
            }
            v
        })
        .collect();
    let mut lights = vec![];
    for l in scene.lights.iter().filter(|l| l.on && l.kind.punctual()) {
        // The glTF extension has no "off": switched-off lights are left out.
        let mut j = json!({"color": l.color.to_array(), "intensity": l.intensity});
        match l.kind {
            LightKind::Directional => j["type"] = json!("directional"),
            LightKind::Point => {
                j["type"] = json!("point");
                j["range"] = json!(l.range);
            }
            LightKind::Spot | LightKind::Area => {
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
        "extensionsUsed": extensions_used(!lights.is_empty(), materials.iter().any(|m| m.get("extensions").is_some())),
        "extensions": {"KHR_lights_punctual": {"lights": lights}},
        "scene": 0,
        "scenes": [{"name": scene.name, "nodes": (0..nodes.len()).collect::<Vec<_>>()}],
        "nodes": nodes,
        "meshes": meshes,
        "materials": materials,
        "accessors": b.accessors,
        "bufferViews": b.views,
        "buffers": [{"uri": bin_name, "byteLength": b.bin.len()}],
    });
    let dir = out.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    let text = serde_json::to_string_pretty(&doc).map_err(|e| Error::io(out, e))?;
    // Both or neither: a buffer left without its glTF file (a full disk) is litter.
    write_atomic_all(&[(&dir.join(&bin_name), &b.bin), (out, text.as_bytes())])
}

/// The extensions a written file uses: punctual lights, emissive strength.
fn extensions_used(lights: bool, strength: bool) -> Value {
    let used: Vec<&str> = [(lights, "KHR_lights_punctual"), (strength, "KHR_materials_emissive_strength")]
        .iter()
        .filter(|(on, _)| *on)
        .map(|(_, e)| *e)
        .collect();
    json!(used)
}
