//! glTF 2.0 loading: node hierarchy transforms, indexed triangle meshes, metallic-roughness
//! materials with textures, KHR_lights_punctual lights. Every error names the file.

use super::geometry::compute_normals;
use super::{AlphaMode, ImageData, Light, Material, Mesh, SamplerDesc, Wrap, IDENTITY_UV};
use crate::error::{Error, Result};
use crate::texture_cache::{Got, Key, Progress, Texels, TextureCache};
use glam::{Mat4, Vec3};
use lightbench_compiler::abi::Vertex;
use std::path::Path;

/// Extensions we read; any other listed in `extensionsRequired` is an error.
pub const SUPPORTED_EXTENSIONS: [&str; 3] = ["KHR_lights_punctual", "KHR_materials_emissive_strength", "KHR_texture_transform"];

#[derive(Clone)]
pub struct Loaded {
    pub meshes: Vec<Mesh>,
    pub materials: Vec<Material>,
    pub textures: Vec<ImageData>,
    pub lights: Vec<Light>,
    /// What was loaded only in part (skipped primitives), for the caller to report.
    pub warnings: Vec<String>,
}

pub fn load(path: &Path) -> Result<Loaded> {
    load_with(path, &TextureCache::from_env())
}

/// `load`, its images kept decoded in `cache` (or read from it).
pub fn load_with(path: &Path, cache: &TextureCache) -> Result<Loaded> {
    let err = |msg: String| Error::Scene(format!("{}: {msg}", path.display()));
    let (doc, buffers, images, mut warnings) = open(path, cache).map_err(err)?;
    let mut textures = Textures::new(images);
    let mut materials = vec![];
    for m in doc.materials() {
        materials.push(material(&m, &mut textures).map_err(err)?);
        material_warnings(&m, &mut warnings);
    }
    materials.push(Material::color("default", [0.8, 0.8, 0.8], 0.6));
    let mut loaded = Loaded {
        meshes: vec![],
        materials,
        textures: vec![],
        lights: vec![],
        warnings,
    };
    walk_nodes(&doc, &buffers, &mut loaded).map_err(err)?;
    loaded.textures = textures.out;
    Ok(loaded)
}

/// A model's document, buffers, images and the warnings of their decoding.
type Opened = (gltf::Document, Vec<gltf::buffer::Data>, Vec<Texels>, Vec<String>);

/// Checks before anything large is read (a regular file, glTF, supported required
/// extensions, referenced files present), then the buffers, accessor bounds and images.
fn open(path: &Path, cache: &TextureCache) -> std::result::Result<Opened, String> {
    document(path)?;
    let bytes = lightbench_compiler::vfs::read_bytes(path, MAX_MODEL_FILE_BYTES).map_err(|e| unreadable(path, e))?;
    let gltf::Gltf { document, blob } = gltf::Gltf::from_slice(&bytes).map_err(describe)?;
    drop(bytes);
    let base = path.parent().unwrap_or(Path::new("."));
    let buffers = gltf::import_buffers(&document, Some(base), blob).map_err(describe)?;
    validate_accessors(&document, &buffers).map_err(|m| m.to_string())?;
    let (images, warnings) = decode_images(&document, base, &buffers, cache)?;
    Ok((document, buffers, images, warnings))
}

/// Every image of the document as RGBA8 texels: read from `cache`, else decoded and kept
/// there; on rayon's threads, each distinct encoding once (two images of the same bytes share
/// the work and the texels are copied). The encoded bytes are not held to be hashed: a file's
/// are hashed as they are read. An entry that could not be written is a warning, once.
fn decode_images(
    doc: &gltf::Document,
    base: &Path,
    buffers: &[gltf::buffer::Data],
    cache: &TextureCache,
) -> std::result::Result<(Vec<Texels>, Vec<String>), String> {
    use rayon::prelude::*;
    let images: Vec<gltf::Image> = doc.images().collect();
    let keys = images
        .par_iter()
        .map(|i| key_of(i, base, buffers))
        .collect::<std::result::Result<Vec<_>, _>>()?;
    let mut first = std::collections::HashMap::new();
    let firsts: Vec<usize> = keys.iter().enumerate().map(|(i, k)| *first.entry(*k).or_insert(i)).collect();
    let progress = Counted::new(firsts.iter().enumerate().filter(|(i, f)| i == *f).count());
    let mut decoded: Vec<Option<(Texels, Got)>> = (0..images.len())
        .into_par_iter()
        .map(|i| {
            let decode = || decode(&images[i], base, buffers);
            let got = (firsts[i] == i).then(|| cache.get(keys[i], decode));
            progress.count(got.as_ref());
            got.transpose().map_err(|e| format!("image {i}{}{e}", image_name(&images[i])))
        })
        .collect::<std::result::Result<Vec<_>, _>>()?;
    let mut warnings = vec![];
    if let Some(e) = decoded.iter().flatten().find_map(|(_, got)| match got {
        Got::NotKept(e) => Some(e),
        _ => None,
    }) {
        warnings.push(format!("decoded textures are not kept for the next run: {e}"));
    }
    let copies: Vec<Option<Texels>> = (0..images.len())
        .map(|i| {
            (firsts[i] != i)
                .then(|| decoded[firsts[i]].as_ref().map(|(t, _)| t.clone()))
                .flatten()
        })
        .collect();
    let texels = copies
        .into_iter()
        .zip(decoded.iter_mut())
        .map(|(copy, own)| copy.or_else(|| own.take().map(|(t, _)| t)))
        .collect::<Option<Vec<_>>>()
        .ok_or("an image was not decoded")?;
    Ok((texels, warnings))
}

/// Images done and decoded so far, told to the progress observer (`texture_cache::on_progress`).
struct Counted {
    total: usize,
    done: std::sync::atomic::AtomicUsize,
    decoded: std::sync::atomic::AtomicUsize,
}

impl Counted {
    fn new(total: usize) -> Counted {
        if total > 0 {
            crate::texture_cache::report(Progress {
                done: 0,
                total,
                decoded: 0,
            });
        }
        let zero = || std::sync::atomic::AtomicUsize::new(0);
        Counted {
            total,
            done: zero(),
            decoded: zero(),
        }
    }

    /// One image's outcome (`None`: a copy of another, not counted).
    fn count(&self, got: Option<&std::result::Result<(Texels, Got), String>>) {
        use std::sync::atomic::Ordering::SeqCst;
        let Some(got) = got else { return };
        let now = matches!(got, Ok((_, Got::Decoded | Got::NotKept(_))));
        let decoded = self.decoded.fetch_add(now as usize, SeqCst) + now as usize;
        let done = self.done.fetch_add(1, SeqCst) + 1;
        crate::texture_cache::report(Progress {
            done,
            total: self.total,
            decoded,
        });
    }
}

/// An image's key in the texture cache: of its encoded bytes and what chooses its decoder (its
/// declared MIME type, else its URI) — a buffer view's slice, a file's contents (hashed as they
/// are read, not held), or a `data:` URI itself.
fn key_of(image: &gltf::Image, base: &Path, buffers: &[gltf::buffer::Data]) -> std::result::Result<Key, String> {
    match image.source() {
        gltf::image::Source::View { view, mime_type } => {
            let data = &buffers[view.buffer().index()].0;
            Ok(Key::of(mime_type, &data[view.offset()..view.offset() + view.length()]))
        }
        gltf::image::Source::Uri { uri, mime_type } => {
            let kind = mime_type.unwrap_or(uri.rsplit('.').next().unwrap_or_default());
            if uri.starts_with("data:") {
                return Ok(Key::of(kind, uri.as_bytes()));
            }
            let file = base.join(percent_decode(uri));
            let read = || {
                lightbench_compiler::vfs::regular_file(&file, MAX_MODEL_FILE_BYTES)?;
                Key::of_read(kind, std::fs::File::open(&file)?, MAX_MODEL_FILE_BYTES)
            };
            read().map_err(|e| unreadable(&file, e))
        }
    }
}

/// An image decoded as glTF's importer decodes it (by its own reading of the file: on a cache
/// miss a file is read twice, once to hash it; the decoding, not the reading, is the cost),
/// then made 8-bit RGBA.
fn decode(image: &gltf::Image, base: &Path, buffers: &[gltf::buffer::Data]) -> std::result::Result<Texels, String> {
    let img = gltf::image::Data::from_source(image.source(), Some(base), buffers).map_err(|e| match e {
        gltf::Error::Image(e) => format!("cannot be decoded: {e}"),
        other => describe(other),
    })?;
    let (format, width, height) = (img.format, img.width, img.height);
    let rgba = to_rgba8(img).ok_or(format!("has an unsupported pixel format {format:?}"))?;
    Ok(Texels {
        width,
        height,
        rgba: rgba.into(),
    })
}

/// How an error names an image: by its file where it has one.
fn image_name(image: &gltf::Image) -> String {
    match image.source() {
        gltf::image::Source::Uri { uri, .. } if !uri.starts_with("data:") => format!(" (`{uri}`) "),
        _ => " ".to_string(),
    }
}

/// The model's JSON document, checked as `open` checks it before importing: a regular glTF
/// file, supported required extensions, referenced files present. Of a binary glTF only the
/// JSON chunk is read: what planning needs without the geometry.
fn document(path: &Path) -> std::result::Result<gltf::Gltf, String> {
    let ext = path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase);
    if !matches!(ext.as_deref(), Some("gltf" | "glb")) {
        let hint = "models must be glTF 2.0 (.gltf or .glb); convert other formats (e.g. .obj, .fbx) with Blender's glTF exporter";
        return Err(format!("not a glTF file: {hint}"));
    }
    let bytes = json_bytes(path).map_err(|e| unreadable(path, e))?;
    let gltf = gltf::Gltf::from_slice_without_validation(&bytes).map_err(|e| format!("not a valid glTF file: {e}"))?;
    referenced_files(&gltf, path)?;
    if let Some(ext) = gltf.extensions_required().find(|e| !SUPPORTED_EXTENSIONS.contains(e)) {
        return Err(format!(
            "requires the unsupported extension `{ext}` (supported: {})",
            SUPPORTED_EXTENSIONS.join(", ")
        ));
    }
    Ok(gltf)
}

/// The JSON of a glTF file: the whole of a `.gltf`, the first chunk of a binary one (its
/// 12-byte header, then the chunk's length and type; anything else is left to the parser).
fn json_bytes(path: &Path) -> std::io::Result<Vec<u8>> {
    use std::io::Read;
    lightbench_compiler::vfs::regular_file(path, MAX_MODEL_FILE_BYTES)?;
    let mut file = std::fs::File::open(path)?;
    let mut head = [0u8; 20];
    let n = file.read(&mut head)?;
    let word = |i: usize| u32::from_le_bytes([head[i], head[i + 1], head[i + 2], head[i + 3]]);
    if n < 20 || &head[..4] != b"glTF" || &head[16..20] != b"JSON" {
        return lightbench_compiler::vfs::read_bytes(path, MAX_MODEL_FILE_BYTES);
    }
    let mut json = vec![];
    file.take(word(12) as u64).read_to_end(&mut json)?;
    Ok(json)
}

/// What planning needs of a model, read from its JSON alone (no buffer or image is read):
/// its lights, placed as `load` places them, whether it draws a primitive, whether a drawn
/// primitive blends, how many drawn primitives emit (each a mesh when loaded), and the
/// warnings `load` gives (skipped primitives, material modes).
pub struct Outline {
    pub lights: Vec<Light>,
    pub draws: bool,
    pub blended: bool,
    pub emitters: usize,
    pub warnings: Vec<String>,
}

pub fn outline(path: &Path) -> Result<Outline> {
    let err = |msg: String| Error::Scene(format!("{}: {msg}", path.display()));
    let gltf = document(path).map_err(err)?;
    let mut out = Outline {
        lights: vec![],
        draws: false,
        blended: false,
        emitters: 0,
        warnings: vec![],
    };
    for m in gltf.document.materials() {
        material_warnings(&m, &mut out.warnings);
    }
    each_node(&gltf.document, |node, world| {
        if let Some(mesh) = node.mesh() {
            for (pi, prim) in mesh.primitives().enumerate() {
                if !drawn(prim.mode()) {
                    out.warnings.push(skipped(&mesh, pi, &prim));
                    continue;
                }
                out.draws = true;
                let m = prim.material();
                out.blended |= m.alpha_mode() == gltf::material::AlphaMode::Blend;
                out.emitters += emissive(&m).iter().any(|c| *c > 0.0) as usize;
            }
        }
        out.lights.extend(node.light().map(|l| node_light(&l, world)));
        Ok(())
    })
    .map_err(err)?;
    Ok(out)
}

/// Decoded images become textures on first use: each image's texels are moved into its
/// first texture, and shared only by a texture of the other colour space (a copy, or the same
/// mapped cache entry).
struct Textures {
    images: Vec<Option<Texels>>,
    out: Vec<ImageData>,
    of_image: std::collections::HashMap<(usize, bool), usize>,
}

impl Textures {
    fn new(images: Vec<Texels>) -> Self {
        Textures {
            images: images.into_iter().map(Some).collect(),
            out: vec![],
            of_image: Default::default(),
        }
    }

    /// The texture of image `index` as sRGB or linear data.
    fn get(&mut self, index: usize, srgb: bool) -> std::result::Result<usize, String> {
        if let Some(&i) = self.of_image.get(&(index, srgb)) {
            return Ok(i);
        }
        let data = match self.of_image.get(&(index, !srgb)) {
            // The same image already converted for the other colour space: share its texels.
            Some(&i) => ImageData {
                srgb,
                ..self.out[i].clone()
            },
            None => {
                let Texels { width, height, rgba } = self
                    .images
                    .get_mut(index)
                    .and_then(Option::take)
                    .ok_or(format!("image {index} is missing"))?;
                ImageData { width, height, rgba, srgb }
            }
        };
        self.out.push(data);
        self.of_image.insert((index, srgb), self.out.len() - 1);
        Ok(self.out.len() - 1)
    }

    fn of(&mut self, t: Option<gltf::texture::Texture>, srgb: bool) -> std::result::Result<Option<usize>, String> {
        t.map(|t| self.get(t.source().index(), srgb)).transpose()
    }
}

/// A glTF metallic-roughness material with its textures.
fn material(m: &gltf::Material, textures: &mut Textures) -> std::result::Result<Material, String> {
    let pbr = m.pbr_metallic_roughness();
    let e = emissive(m);
    Ok(Material {
        name: m.name().unwrap_or("material").to_string(),
        base_color: pbr.base_color_factor(),
        base_color_texture: textures.of(pbr.base_color_texture().map(|t| t.texture()), true)?,
        metallic: pbr.metallic_factor(),
        roughness: pbr.roughness_factor(),
        metallic_roughness_texture: textures.of(pbr.metallic_roughness_texture().map(|t| t.texture()), false)?,
        emissive: e,
        emissive_texture: textures.of(m.emissive_texture().map(|t| t.texture()), true)?,
        normal_texture: textures.of(m.normal_texture().map(|t| t.texture()), false)?,
        normal_scale: m.normal_texture().map(|t| t.scale()).unwrap_or(1.0),
        occlusion_texture: textures.of(m.occlusion_texture().map(|t| t.texture()), false)?,
        occlusion_strength: m.occlusion_texture().map(|t| t.strength()).unwrap_or(1.0),
        uv_transform: uv_transform(m),
        alpha: match m.alpha_mode() {
            gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
            gltf::material::AlphaMode::Mask => AlphaMode::Mask(m.alpha_cutoff().unwrap_or(0.5)),
            gltf::material::AlphaMode::Blend => AlphaMode::Blend,
        },
        sampler: material_sampler(m),
        uv_sets: uv_sets(m),
        double_sided: m.double_sided(),
    })
}

/// The node hierarchy of the default scene: meshes and lights with their world transforms.
/// Primitives without a material use the last (default) material.
/// Every node of the default scene (else the first, else all nodes) with its world
/// transform, parents first.
fn each_node(
    doc: &gltf::Document,
    mut f: impl FnMut(&gltf::Node, Mat4) -> std::result::Result<(), String>,
) -> std::result::Result<(), String> {
    let roots: Vec<gltf::Node> = match doc.default_scene().or_else(|| doc.scenes().next()) {
        Some(s) => s.nodes().collect(),
        None => doc.nodes().collect(),
    };
    let mut stack: Vec<(gltf::Node, Mat4, usize)> = roots.into_iter().map(|n| (n, Mat4::IDENTITY, 0)).collect();
    while let Some((node, parent, depth)) = stack.pop() {
        if depth > 64 {
            return Err("node hierarchy deeper than 64 levels (a cycle?)".into());
        }
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        f(&node, world)?;
        stack.extend(node.children().map(|c| (c, world, depth + 1)));
    }
    Ok(())
}

/// A material's emitted radiance: its factor times KHR_materials_emissive_strength.
fn emissive(m: &gltf::Material) -> [f32; 3] {
    let (e, strength) = (m.emissive_factor(), m.emissive_strength().unwrap_or(1.0));
    e.map(|c| c * strength)
}

/// The warning for a primitive that is not drawn.
fn skipped(mesh: &gltf::Mesh, pi: usize, prim: &gltf::Primitive) -> String {
    let (name, mode) = (mesh.name().unwrap_or("?"), prim.mode());
    format!("mesh `{name}` primitive {pi} is {mode:?}, which is not drawn (only triangles are); skipped")
}

/// Whether primitives of this mode are drawn (triangles; points and lines are skipped).
fn drawn(mode: gltf::mesh::Mode) -> bool {
    use gltf::mesh::Mode;
    matches!(mode, Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan)
}

fn walk_nodes(doc: &gltf::Document, buffers: &[gltf::buffer::Data], out: &mut Loaded) -> std::result::Result<(), String> {
    let default_material = out.materials.len() - 1;
    each_node(doc, |node, world| {
        if let Some(mesh) = node.mesh() {
            for (pi, prim) in mesh.primitives().enumerate() {
                let Some((vertices, indices)) = primitive(&mesh, pi, &prim, buffers)? else {
                    out.warnings.push(skipped(&mesh, pi, &prim));
                    continue;
                };
                let material = prim.material().index().unwrap_or(default_material);
                let name = format!("{}#{pi}", mesh.name().unwrap_or("mesh"));
                out.meshes.push(Mesh::new(&name, vertices, indices, material, world));
            }
        }
        if let Some(l) = node.light() {
            out.lights.push(node_light(&l, world));
        }
        Ok(())
    })
}

/// Vertices and triangle-list indices.
type Geometry = (Vec<Vertex>, Vec<u32>);

/// A primitive's vertices and triangle-list indices; `None` for points and lines.
fn primitive(
    mesh: &gltf::Mesh,
    pi: usize,
    prim: &gltf::Primitive,
    buffers: &[gltf::buffer::Data],
) -> std::result::Result<Option<Geometry>, String> {
    if !drawn(prim.mode()) {
        return Ok(None);
    }
    let at = format!("mesh `{}` primitive {pi}", mesh.name().unwrap_or("?"));
    let reader = prim.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
    let positions: Vec<[f32; 3]> = reader.read_positions().ok_or(format!("{at} has no POSITION"))?.collect();
    let normals: Option<Vec<[f32; 3]>> = reader.read_normals().map(|i| i.collect());
    let uvs: Option<Vec<[f32; 2]>> = reader.read_tex_coords(0).map(|i| i.into_f32().collect());
    let uvs1: Option<Vec<[f32; 2]>> = reader.read_tex_coords(1).map(|i| i.into_f32().collect());
    let tangents: Option<Vec<[f32; 4]>> = reader.read_tangents().map(|i| i.collect());
    let indices = match reader.read_indices() {
        Some(i) => i.into_u32().collect(),
        None => (0..positions.len() as u32).collect(),
    };
    let indices = triangle_list(prim.mode(), indices);
    super::geometry::check_indices(&indices, positions.len()).map_err(|e| format!("{at}: {e}"))?;
    for (what, n) in [
        ("NORMAL", normals.as_ref().map(|v| v.len())),
        ("TEXCOORD_0", uvs.as_ref().map(|v| v.len())),
        ("TEXCOORD_1", uvs1.as_ref().map(|v| v.len())),
        ("TANGENT", tangents.as_ref().map(|v| v.len())),
    ] {
        if let Some(n) = n.filter(|n| *n != positions.len()) {
            return Err(format!("{at}: {what} has {n} entries, POSITION has {}", positions.len()));
        }
    }
    let mut vertices: Vec<Vertex> = (0..positions.len())
        .map(|i| Vertex {
            position: positions[i],
            normal: normals.as_ref().map(|n| n[i]).unwrap_or([0.0; 3]),
            uv: uvs.as_ref().map(|u| u[i]).unwrap_or([0.0; 2]),
            tangent: tangents.as_ref().map(|t| t[i]).unwrap_or([0.0; 4]),
            uv1: uvs1.as_ref().or(uvs.as_ref()).map(|u| u[i]).unwrap_or([0.0; 2]),
        })
        .collect();
    if normals.is_none() {
        compute_normals(&mut vertices, &indices);
    }
    Ok(Some((vertices, indices)))
}

/// A KHR_lights_punctual light placed by its node (lights shine down the node's -Z).
fn node_light(l: &gltf::khr_lights_punctual::Light, world: Mat4) -> Light {
    let c = l.color();
    let color = Vec3::new(c[0], c[1], c[2]);
    let position = world.transform_point3(Vec3::ZERO);
    let direction = world.transform_vector3(Vec3::NEG_Z).normalize_or_zero();
    let range = l.range().unwrap_or(20.0);
    match l.kind() {
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
    }
}

/// The textures of a material, in the order their settings are looked for.
fn texture_infos<'a>(m: &gltf::Material<'a>) -> Vec<gltf::texture::Texture<'a>> {
    let pbr = m.pbr_metallic_roughness();
    [
        pbr.base_color_texture().map(|t| t.texture()),
        pbr.metallic_roughness_texture().map(|t| t.texture()),
        m.normal_texture().map(|t| t.texture()),
        m.occlusion_texture().map(|t| t.texture()),
        m.emissive_texture().map(|t| t.texture()),
    ]
    .into_iter()
    .flatten()
    .collect()
}

/// KHR_texture_transform of the material's base colour texture (else its emissive one) as
/// the rows of uv' = offset + rotation · scale · uv (the extension's matrix). One transform
/// serves every map of a material: exporters write the same on each.
fn uv_transform(m: &gltf::Material) -> [[f32; 3]; 2] {
    let pbr = m.pbr_metallic_roughness();
    let t = pbr
        .base_color_texture()
        .and_then(|i| i.texture_transform())
        .or_else(|| m.emissive_texture().and_then(|i| i.texture_transform()));
    let Some(t) = t else { return IDENTITY_UV };
    let ([ox, oy], r, [sx, sy]) = (t.offset(), t.rotation(), t.scale());
    let (sin, cos) = r.sin_cos();
    [[cos * sx, -sin * sy, ox], [sin * sx, cos * sy, oy]]
}

/// The sampler of the material's first texture (glTF allows one per texture; one per
/// material is what the G-buffer binds).
fn material_sampler(m: &gltf::Material) -> SamplerDesc {
    use gltf::texture::{MagFilter, MinFilter, WrappingMode};
    let Some(t) = texture_infos(m).into_iter().next() else {
        return SamplerDesc::default();
    };
    let s = t.sampler();
    let wrap = |w: WrappingMode| match w {
        WrappingMode::Repeat => Wrap::Repeat,
        WrappingMode::ClampToEdge => Wrap::Clamp,
        WrappingMode::MirroredRepeat => Wrap::Mirror,
    };
    let min = s.min_filter().unwrap_or(MinFilter::LinearMipmapLinear);
    SamplerDesc {
        wrap: [wrap(s.wrap_s()), wrap(s.wrap_t())],
        mag_linear: s.mag_filter() != Some(MagFilter::Nearest),
        min_linear: matches!(
            min,
            MinFilter::Linear | MinFilter::LinearMipmapNearest | MinFilter::LinearMipmapLinear
        ),
        mip_linear: matches!(
            min,
            MinFilter::NearestMipmapLinear | MinFilter::LinearMipmapLinear | MinFilter::Linear
        ),
    }
}

/// The UV set of each map (base colour, metallic-roughness, normal, emissive, occlusion).
fn map_sets(m: &gltf::Material) -> [Option<u32>; 5] {
    let pbr = m.pbr_metallic_roughness();
    [
        pbr.base_color_texture().map(|t| t.tex_coord()),
        pbr.metallic_roughness_texture().map(|t| t.tex_coord()),
        m.normal_texture().map(|t| t.tex_coord()),
        m.emissive_texture().map(|t| t.tex_coord()),
        m.occlusion_texture().map(|t| t.tex_coord()),
    ]
}

/// Bit k set: map k reads TEXCOORD_1 (the material block's `uv_sets`).
fn uv_sets(m: &gltf::Material) -> u32 {
    map_sets(m)
        .iter()
        .enumerate()
        .filter(|(_, s)| **s == Some(1))
        .map(|(k, _)| 1 << k)
        .sum()
}

/// What a material asks for that is not drawn as asked.
fn material_warnings(m: &gltf::Material, warnings: &mut Vec<String>) {
    let name = m.name().unwrap_or("?");
    if map_sets(m).iter().flatten().any(|c| *c > 1) {
        warnings.push(format!("material `{name}` samples TEXCOORD_2 or higher, read as TEXCOORD_0"));
    }
}

/// Strips and fans as triangle lists, by the glTF specification's vertex order (§3.7.2.1).
fn triangle_list(mode: gltf::mesh::Mode, idx: Vec<u32>) -> Vec<u32> {
    use gltf::mesh::Mode;
    let n = idx.len();
    match mode {
        Mode::TriangleStrip if n >= 3 => (0..n - 2).flat_map(|i| [idx[i], idx[i + 1 + i % 2], idx[i + 2 - i % 2]]).collect(),
        Mode::TriangleFan if n >= 3 => (0..n - 2).flat_map(|i| [idx[i + 1], idx[i + 2], idx[0]]).collect(),
        Mode::TriangleStrip | Mode::TriangleFan => vec![],
        _ => idx,
    }
}

/// The largest glTF, buffer or image file read (a guard against devices and runaway files).
pub const MAX_MODEL_FILE_BYTES: u64 = 2 << 30;

/// A failed read, naming the file (only regular files of bounded size are read: a FIFO
/// would block and `/dev/zero` never end).
fn unreadable(path: &Path, e: std::io::Error) -> String {
    format!("`{}`: {e}", path.display())
}

/// The model file and the files it refers to (external buffers and images): what a watcher
/// watches for it. A model whose JSON cannot be read is its file alone (loading it says why).
pub fn files(path: &Path) -> Vec<std::path::PathBuf> {
    let mut out = vec![path.to_path_buf()];
    let Ok(bytes) = json_bytes(path) else { return out };
    if let Ok(gltf) = gltf::Gltf::from_slice_without_validation(&bytes) {
        out.extend(referenced(&gltf, path).into_iter().map(|(_, _, file)| file));
    }
    out
}

/// Buffers and images named by file URI (not `data:`): what each is, its index, its file.
fn referenced(gltf: &gltf::Gltf, path: &Path) -> Vec<(&'static str, usize, std::path::PathBuf)> {
    let dir = path.parent().unwrap_or(Path::new("."));
    let buffers = gltf.buffers().filter_map(|b| match b.source() {
        gltf::buffer::Source::Uri(u) => Some(("buffer", b.index(), u)),
        gltf::buffer::Source::Bin => None,
    });
    let images = gltf.images().filter_map(|i| match i.source() {
        gltf::image::Source::Uri { uri, .. } => Some(("image", i.index(), uri)),
        gltf::image::Source::View { .. } => None,
    });
    buffers
        .chain(images)
        .filter(|(_, _, u)| !u.starts_with("data:"))
        .map(|(what, index, uri)| (what, index, dir.join(percent_decode(uri))))
        .collect()
}

/// Buffers and images named by file URI (not `data:`), checked before the importer opens
/// them, so that a missing or special file is named (the importer says only "not found").
fn referenced_files(gltf: &gltf::Gltf, path: &Path) -> std::result::Result<(), String> {
    for (what, index, file) in referenced(gltf, path) {
        if !file.exists() {
            return Err(format!("{what} {index} refers to `{}`, which does not exist", file.display()));
        }
        lightbench_compiler::vfs::regular_file(&file, MAX_MODEL_FILE_BYTES).map_err(|e| unreadable(&file, e))?;
    }
    Ok(())
}

/// `%XX` escapes of a URI path (glTF URIs are URI-encoded: `my%20texture.png`).
fn percent_decode(uri: &str) -> String {
    let b = uri.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        let hex = |c: u8| (c as char).to_digit(16);
        match (b[i], b.get(i + 1).copied().and_then(hex), b.get(i + 2).copied().and_then(hex)) {
            (b'%', Some(h), Some(l)) => {
                out.push((h * 16 + l) as u8);
                i += 3;
            }
            (c, _, _) => {
                out.push(c);
                i += 1;
            }
        }
    }
    String::from_utf8_lossy(&out).into_owned()
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

/// Any decoded image as 8-bit RGBA: 8- and 16-bit (rounded) and float (clamped to 0..1)
/// channels; one channel is grey, two are grey and alpha (PNG has no red-green format).
fn to_rgba8(img: gltf::image::Data) -> Option<Vec<u8>> {
    use gltf::image::Format as F;
    if img.format == F::R8G8B8A8 && img.pixels.len() == (img.width as usize) * (img.height as usize) * 4 {
        return Some(img.pixels);
    }
    let (channels, bytes) = match img.format {
        F::R8 => (1, 1),
        F::R8G8 => (2, 1),
        F::R8G8B8 => (3, 1),
        F::R8G8B8A8 => (4, 1),
        F::R16 => (1, 2),
        F::R16G16 => (2, 2),
        F::R16G16B16 => (3, 2),
        F::R16G16B16A16 => (4, 2),
        F::R32G32B32FLOAT => (3, 4),
        F::R32G32B32A32FLOAT => (4, 4),
    };
    let value = |c: &[u8]| -> u8 {
        match bytes {
            1 => c[0],
            2 => ((u16::from_ne_bytes([c[0], c[1]]) as u32 + 128) / 257) as u8,
            _ => (f32::from_ne_bytes([c[0], c[1], c[2], c[3]]).clamp(0.0, 1.0) * 255.0).round() as u8,
        }
    };
    let texel = channels * bytes;
    if img.pixels.len() != (img.width as usize) * (img.height as usize) * texel {
        return None;
    }
    let texels = img.pixels.chunks_exact(texel).flat_map(|px| {
        let mut v = [0u8; 4];
        for (o, c) in v.iter_mut().zip(px.chunks_exact(bytes)) {
            *o = value(c);
        }
        match channels {
            1 => [v[0], v[0], v[0], 255],
            2 => [v[0], v[0], v[0], v[1]],
            3 => [v[0], v[1], v[2], 255],
            _ => v,
        }
    });
    // Exactly level 0: the upload grows it in place for the mip chain (a large realloc remaps
    // pages; reserving the chain here measured a higher peak in `--bench assets`).
    let mut out = Vec::with_capacity(img.pixels.len() / texel * 4);
    out.extend(texels);
    Some(out)
}
