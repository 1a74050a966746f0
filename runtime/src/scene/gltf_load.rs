//! glTF 2.0 loading: node hierarchy transforms, indexed triangle meshes, metallic-roughness
//! materials with textures, KHR_lights_punctual lights. Every error names the file.

use super::geometry::compute_normals;
use super::{ImageData, Light, Material, Mesh};
use crate::blocks::Vertex;
use crate::error::{Error, Result};
use glam::{Mat4, Vec3};
use lightbench_compiler::ir::LightKind;
use std::path::Path;

/// Extensions we read; any other listed in `extensionsRequired` is an error.
pub const SUPPORTED_EXTENSIONS: [&str; 2] = ["KHR_lights_punctual", "KHR_materials_emissive_strength"];

pub struct Loaded {
    pub meshes: Vec<Mesh>,
    pub materials: Vec<Material>,
    pub textures: Vec<ImageData>,
    pub lights: Vec<Light>,
}

pub fn load(path: &Path) -> Result<Loaded> {
    let name = path.display().to_string();
    let err = |msg: String| Error::Scene(format!("{name}: {msg}"));
    // Read the document first so an unsupported required extension is reported as such,
    // before buffers or images are touched.
    regular_file(path).map_err(&err)?;
    let bytes = std::fs::read(path).map_err(|e| err(e.to_string()))?;
    let gltf = gltf::Gltf::from_slice_without_validation(&bytes).map_err(|e| err(format!("not a valid glTF file: {e}")))?;
    referenced_files(&gltf, path).map_err(&err)?;
    for ext in gltf.extensions_required() {
        if !SUPPORTED_EXTENSIONS.contains(&ext) {
            return Err(err(format!(
                "requires the unsupported extension `{ext}` (supported: {})",
                SUPPORTED_EXTENSIONS.join(", ")
            )));
        }
    }
    let (doc, buffers, images) = gltf::import(path).map_err(|e| err(describe(e)))?;
    validate_accessors(&doc, &buffers).map_err(|m| err(m.to_string()))?;

    let mut textures = vec![];
    let mut texture_of_image = std::collections::HashMap::new();
    let mut tex = |index: usize, srgb: bool, textures: &mut Vec<ImageData>| -> Result<usize> {
        if let Some(&i) = texture_of_image.get(&(index, srgb)) {
            return Ok(i);
        }
        let img = images.get(index).ok_or_else(|| err(format!("image {index} is missing")))?;
        let rgba = to_rgba8(img).ok_or_else(|| err(format!("image {index} has an unsupported pixel format {:?}", img.format)))?;
        textures.push(ImageData {
            width: img.width,
            height: img.height,
            rgba,
            srgb,
        });
        texture_of_image.insert((index, srgb), textures.len() - 1);
        Ok(textures.len() - 1)
    };

    let mut materials = vec![];
    for m in doc.materials() {
        let pbr = m.pbr_metallic_roughness();
        let e = m.emissive_factor();
        let strength = m.emissive_strength().unwrap_or(1.0);
        materials.push(Material {
            name: m.name().unwrap_or("material").to_string(),
            base_color: pbr.base_color_factor(),
            base_color_texture: pbr
                .base_color_texture()
                .map(|t| tex(t.texture().source().index(), true, &mut textures))
                .transpose()?,
            metallic: pbr.metallic_factor(),
            roughness: pbr.roughness_factor(),
            metallic_roughness_texture: pbr
                .metallic_roughness_texture()
                .map(|t| tex(t.texture().source().index(), false, &mut textures))
                .transpose()?,
            emissive: [e[0] * strength, e[1] * strength, e[2] * strength],
            emissive_texture: m
                .emissive_texture()
                .map(|t| tex(t.texture().source().index(), true, &mut textures))
                .transpose()?,
            normal_texture: m
                .normal_texture()
                .map(|t| tex(t.texture().source().index(), false, &mut textures))
                .transpose()?,
            normal_scale: m.normal_texture().map(|t| t.scale()).unwrap_or(1.0),
        });
    }
    let default_material = materials.len();
    materials.push(Material::color("default", [0.8, 0.8, 0.8], 0.6));

    let mut meshes = vec![];
    let mut lights = vec![];
    let scene = doc.default_scene().or_else(|| doc.scenes().next());
    let roots: Vec<gltf::Node> = match scene {
        Some(s) => s.nodes().collect(),
        None => doc.nodes().collect(),
    };
    let mut stack: Vec<(gltf::Node, Mat4, usize)> = roots.into_iter().map(|n| (n, Mat4::IDENTITY, 0)).collect();
    while let Some((node, parent, depth)) = stack.pop() {
        if depth > 64 {
            return Err(err("node hierarchy deeper than 64 levels (a cycle?)".into()));
        }
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        if let Some(mesh) = node.mesh() {
            for (pi, prim) in mesh.primitives().enumerate() {
                if prim.mode() != gltf::mesh::Mode::Triangles {
                    return Err(err(format!(
                        "mesh `{}` primitive {pi}: only triangle lists are supported, found {:?}",
                        mesh.name().unwrap_or("?"),
                        prim.mode()
                    )));
                }
                let reader = prim.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
                let positions: Vec<[f32; 3]> = reader
                    .read_positions()
                    .ok_or_else(|| err(format!("mesh `{}` primitive {pi} has no POSITION", mesh.name().unwrap_or("?"))))?
                    .collect();
                let normals: Option<Vec<[f32; 3]>> = reader.read_normals().map(|i| i.collect());
                let uvs: Option<Vec<[f32; 2]>> = reader.read_tex_coords(0).map(|i| i.into_f32().collect());
                let tangents: Option<Vec<[f32; 4]>> = reader.read_tangents().map(|i| i.collect());
                let indices: Vec<u32> = match reader.read_indices() {
                    Some(i) => i.into_u32().collect(),
                    None => (0..positions.len() as u32).collect(),
                };
                if let Some(bad) = indices.iter().find(|&&i| i as usize >= positions.len()) {
                    return Err(err(format!(
                        "mesh `{}` primitive {pi}: index {bad} is out of range ({} vertices)",
                        mesh.name().unwrap_or("?"),
                        positions.len()
                    )));
                }
                for (what, n) in [
                    ("NORMAL", normals.as_ref().map(|v| v.len())),
                    ("TEXCOORD_0", uvs.as_ref().map(|v| v.len())),
                    ("TANGENT", tangents.as_ref().map(|v| v.len())),
                ] {
                    if n.is_some_and(|n| n != positions.len()) {
                        return Err(err(format!(
                            "mesh `{}` primitive {pi}: {what} has {} entries, POSITION has {}",
                            mesh.name().unwrap_or("?"),
                            n.unwrap_or(0),
                            positions.len()
                        )));
                    }
                }
                let mut vertices: Vec<Vertex> = (0..positions.len())
                    .map(|i| Vertex {
                        position: positions[i],
                        normal: normals.as_ref().map(|n| n[i]).unwrap_or([0.0; 3]),
                        uv: uvs.as_ref().map(|u| u[i]).unwrap_or([0.0; 2]),
                        tangent: tangents.as_ref().map(|t| t[i]).unwrap_or([0.0; 4]),
                    })
                    .collect();
                if normals.is_none() {
                    compute_normals(&mut vertices, &indices);
                }
                meshes.push(Mesh {
                    name: format!("{}#{pi}", mesh.name().unwrap_or("mesh")),
                    vertices,
                    indices,
                    material: prim.material().index().unwrap_or(default_material),
                    transform: world,
                    triangle_fraction: 1.0,
                    reflective: false,
                });
            }
        }
        if let Some(l) = node.light() {
            let c = l.color();
            let color = Vec3::new(c[0], c[1], c[2]);
            let position = world.transform_point3(Vec3::ZERO);
            // Lights shine down their node's -Z.
            let direction = world.transform_vector3(Vec3::NEG_Z).normalize_or_zero();
            let range = l.range().unwrap_or(20.0);
            let mut light = match l.kind() {
                gltf::khr_lights_punctual::Kind::Directional => Light::directional(direction, color, l.intensity()),
                gltf::khr_lights_punctual::Kind::Point => Light::point(position, color, l.intensity(), range),
                gltf::khr_lights_punctual::Kind::Spot {
                    inner_cone_angle,
                    outer_cone_angle,
                } => Light::spot(
                    position,
                    direction,
                    inner_cone_angle.to_degrees(),
                    outer_cone_angle.to_degrees(),
                    color,
                    l.intensity(),
                    range,
                ),
            };
            if light.kind == LightKind::Directional {
                light.position = Vec3::ZERO;
            }
            lights.push(light);
        }
        for c in node.children() {
            stack.push((c, world, depth + 1));
        }
    }
    Ok(Loaded {
        meshes,
        materials,
        textures,
        lights,
    })
}

/// The largest glTF, buffer or image file read (a guard against devices and runaway files).
pub const MAX_MODEL_FILE_BYTES: u64 = 2 << 30;

/// Only regular files of bounded size are read: a FIFO would block and `/dev/zero` never end.
fn regular_file(path: &Path) -> std::result::Result<(), String> {
    let meta = std::fs::metadata(path).map_err(|e| format!("cannot read `{}`: {e}", path.display()))?;
    if !meta.is_file() {
        return Err(format!("`{}` is not a regular file (a directory, device or pipe)", path.display()));
    }
    if meta.len() > MAX_MODEL_FILE_BYTES {
        return Err(format!(
            "`{}` is larger than the {} GiB limit",
            path.display(),
            MAX_MODEL_FILE_BYTES >> 30
        ));
    }
    Ok(())
}

/// Buffers and images named by file URI (not `data:`), checked before the importer opens them.
fn referenced_files(gltf: &gltf::Gltf, path: &Path) -> std::result::Result<(), String> {
    let dir = path.parent().unwrap_or(Path::new("."));
    let buffers = gltf.buffers().filter_map(|b| match b.source() {
        gltf::buffer::Source::Uri(u) => Some(u),
        gltf::buffer::Source::Bin => None,
    });
    let images = gltf.images().filter_map(|i| match i.source() {
        gltf::image::Source::Uri { uri, .. } => Some(uri),
        gltf::image::Source::View { .. } => None,
    });
    for uri in buffers.chain(images).filter(|u| !u.starts_with("data:")) {
        let file = dir.join(uri.replace("%20", " "));
        // A file that is absent (or named with other escapes) is the importer's to report.
        if file.exists() {
            regular_file(&file)?;
        }
    }
    Ok(())
}

fn describe(e: gltf::Error) -> String {
    match e {
        gltf::Error::BufferLength { buffer, expected, actual } => {
            format!("buffer {buffer} is truncated: expected {expected} bytes, found {actual}")
        }
        gltf::Error::Io(e) => format!("cannot read a referenced file: {e}"),
        other => other.to_string(),
    }
}

/// Data that would be read past its end.
#[derive(Debug)]
struct AccessorError(String);

impl std::fmt::Display for AccessorError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

/// Every accessor must fit in its buffer view and every view in its buffer, or reading it
/// would run past the data.
fn validate_accessors(doc: &gltf::Document, buffers: &[gltf::buffer::Data]) -> std::result::Result<(), AccessorError> {
    for view in doc.views() {
        let len = buffers.get(view.buffer().index()).map(|b| b.0.len()).unwrap_or(0);
        if view.offset() + view.length() > len {
            return Err(AccessorError(format!(
                "buffer view {} (bytes {}..{}) runs past buffer {} ({len} bytes)",
                view.index(),
                view.offset(),
                view.offset() + view.length(),
                view.buffer().index()
            )));
        }
    }
    for a in doc.accessors() {
        let Some(view) = a.view() else { continue };
        if a.count() == 0 {
            continue;
        }
        let elem = a.size();
        let stride = view.stride().unwrap_or(elem);
        let need = a.offset() + stride * (a.count() - 1) + elem;
        if need > view.length() {
            return Err(AccessorError(format!(
                "accessor {} has count {} but its buffer view {} holds {} bytes (needs {need})",
                a.index(),
                a.count(),
                view.index(),
                view.length()
            )));
        }
    }
    Ok(())
}

fn to_rgba8(img: &gltf::image::Data) -> Option<Vec<u8>> {
    use gltf::image::Format as F;
    let px = &img.pixels;
    Some(match img.format {
        F::R8G8B8A8 => px.clone(),
        F::R8G8B8 => px.chunks_exact(3).flat_map(|c| [c[0], c[1], c[2], 255]).collect(),
        F::R8G8 => px.chunks_exact(2).flat_map(|c| [c[0], c[1], 0, 255]).collect(),
        F::R8 => px.iter().flat_map(|&c| [c, c, c, 255]).collect(),
        _ => return None,
    })
}
