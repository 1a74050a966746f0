//! ABI: the standard blocks an executor writes for every pass, byte-for-byte as declared in
//! `shaders/lib/frame.wgsl` and `shaders/lib/mesh.wgsl` (a test checks them against naga's
//! layout of those structs).

use bytemuck::{Pod, Zeroable};

pub const LIGHT_DIRECTIONAL: u32 = 0;
pub const LIGHT_SPOT: u32 = 1;
pub const LIGHT_POINT: u32 = 2;
/// An emissive mesh as a light (`LightKind::Area`): `direction.w` holds its area.
pub const LIGHT_AREA: u32 = 3;

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct FrameBlock {
    pub view: [[f32; 4]; 4],
    pub proj: [[f32; 4]; 4],
    pub view_proj: [[f32; 4]; 4],
    pub inv_view_proj: [[f32; 4]; 4],
    pub prev_view_proj: [[f32; 4]; 4],
    pub prev_inv_view_proj: [[f32; 4]; 4],
    pub camera_pos: [f32; 4],
    pub resolution: [f32; 4],
    pub jitter: [f32; 4],
    pub time: f32,
    pub frame_index: u32,
    pub light_count: u32,
    /// The scene's bounding-sphere radius: the length unit of scale-free parameters.
    pub scene_radius: f32,
}

/// A field of the frame block, named as `shaders/lib/frame.wgsl` names it. What a pass reads
/// of the block is found by the bytes it reads (`FrameField::overlapping`), so a shader whose
/// own struct names the members otherwise still depends on what it reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FrameField {
    View,
    Proj,
    ViewProj,
    InvViewProj,
    PrevViewProj,
    PrevInvViewProj,
    CameraPos,
    Resolution,
    Jitter,
    Time,
    FrameIndex,
    LightCount,
    SceneRadius,
}

impl FrameField {
    pub const ALL: [FrameField; 13] = [
        FrameField::View,
        FrameField::Proj,
        FrameField::ViewProj,
        FrameField::InvViewProj,
        FrameField::PrevViewProj,
        FrameField::PrevInvViewProj,
        FrameField::CameraPos,
        FrameField::Resolution,
        FrameField::Jitter,
        FrameField::Time,
        FrameField::FrameIndex,
        FrameField::LightCount,
        FrameField::SceneRadius,
    ];

    /// Its bytes in `FrameBlock`: offset and size.
    pub fn bytes(self) -> (usize, usize) {
        use std::mem::{offset_of, size_of};
        let (mat, vec) = (size_of::<[[f32; 4]; 4]>(), size_of::<[f32; 4]>());
        match self {
            FrameField::View => (offset_of!(FrameBlock, view), mat),
            FrameField::Proj => (offset_of!(FrameBlock, proj), mat),
            FrameField::ViewProj => (offset_of!(FrameBlock, view_proj), mat),
            FrameField::InvViewProj => (offset_of!(FrameBlock, inv_view_proj), mat),
            FrameField::PrevViewProj => (offset_of!(FrameBlock, prev_view_proj), mat),
            FrameField::PrevInvViewProj => (offset_of!(FrameBlock, prev_inv_view_proj), mat),
            FrameField::CameraPos => (offset_of!(FrameBlock, camera_pos), vec),
            FrameField::Resolution => (offset_of!(FrameBlock, resolution), vec),
            FrameField::Jitter => (offset_of!(FrameBlock, jitter), vec),
            FrameField::Time => (offset_of!(FrameBlock, time), 4),
            FrameField::FrameIndex => (offset_of!(FrameBlock, frame_index), 4),
            FrameField::LightCount => (offset_of!(FrameBlock, light_count), 4),
            FrameField::SceneRadius => (offset_of!(FrameBlock, scene_radius), 4),
        }
    }

    /// The fields whose bytes `offset..offset + size` of the block touch.
    pub fn overlapping(offset: usize, size: usize) -> impl Iterator<Item = FrameField> {
        FrameField::ALL.into_iter().filter(move |f| {
            let (at, n) = f.bytes();
            at < offset + size && offset < at + n
        })
    }

    /// Its name in `shaders/lib/frame.wgsl` (and in the Plan's JSON).
    pub fn name(self) -> &'static str {
        const NAMES: [&str; 13] = [
            "view",
            "proj",
            "view_proj",
            "inv_view_proj",
            "prev_view_proj",
            "prev_inv_view_proj",
            "camera_pos",
            "resolution",
            "jitter",
            "time",
            "frame_index",
            "light_count",
            "scene_radius",
        ];
        NAMES[self as usize]
    }
}

impl std::fmt::Display for FrameField {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct LightBlock {
    pub color: [f32; 4],
    pub position: [f32; 4],
    pub direction: [f32; 4],
    pub cone: [f32; 4],
    pub kind: u32,
    pub casts_shadows: u32,
    pub _pad0: u32,
    pub _pad1: u32,
    pub view_proj: [[f32; 4]; 4],
    pub face_view_proj: [[[f32; 4]; 4]; 6],
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable)]
pub struct InstanceBlock {
    pub light: u32,
    pub face: u32,
    pub view_count: u32,
    /// The mip level of this repetition of a `per_mip` pass (else 0).
    pub mip: u32,
    /// The pass's own target size in pixels (its first attachment, or the texture a compute
    /// dispatch is sized from; else the output size), then the reciprocals.
    pub target_size: [f32; 4],
    /// Which run of a `repeat` pass this is, from 0 (else 0).
    pub repetition: u32,
    pub _pad: [u32; 3],
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct MeshBlock {
    pub model: [[f32; 4]; 4],
    pub normal_matrix: [[f32; 4]; 4],
}

#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct MaterialBlock {
    pub base_color: [f32; 4],
    pub emissive: [f32; 4],
    /// Rows of the 2×3 UV transform (KHR_texture_transform); w unused.
    pub uv_row0: [f32; 4],
    pub uv_row1: [f32; 4],
    pub metallic: f32,
    pub roughness: f32,
    pub normal_scale: f32,
    pub has_normal_map: u32,
    /// Fragments with alpha below this are discarded (0: opaque, nothing is).
    pub alpha_cutoff: f32,
    pub occlusion_strength: f32,
    /// Bit k set: map k (base colour, metallic-roughness, normal, emissive, occlusion) reads
    /// the second UV set.
    pub uv_sets: u32,
    /// 1: glTF `doubleSided` (back faces are drawn, their normal flipped); 0: back faces
    /// are not seen.
    pub double_sided: u32,
}

/// One area light of the standard `area_lights` binding (`shaders/lib/area_light.wgsl`): an
/// emissive triangle's corners in world space, counter-clockwise seen from the emitting side,
/// and its radiance (w: 1 when both sides emit).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct AreaLightBlock {
    pub corners: [[f32; 4]; 3],
    pub radiance: [f32; 4],
}

/// One traced triangle of the standard `hit_triangles` table (4 texels,
/// `shaders/lib/hit.wgsl`): its corners' shading normals in world space (unit), the front's
/// geometric normal (the side its counter-clockwise winding faces, swapped under a mirroring
/// transform), its material's index into `hit_materials`, whether both sides are seen, and its
/// index into `hit_emitters` (`NO_EMITTER` when it emits nothing).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct HitTriangle {
    pub n0: [f32; 3],
    pub material: u32,
    pub n1: [f32; 3],
    pub double_sided: u32,
    pub n2: [f32; 3],
    pub emitter: u32,
    pub ng: [f32; 3],
    pub _pad1: u32,
}

/// `HitTriangle::emitter` of a triangle that emits nothing.
pub const NO_EMITTER: u32 = u32::MAX;

/// One emissive traced triangle of the standard `hit_emitters` table (4 texels after the
/// one holding their count, `shaders/lib/hit_emitters.wgsl`): its world corners in its own
/// order, its index among the traced triangles (its front, sidedness and material: a point's
/// emission is looked up there); its radiance with its emissive map's mean (what its power
/// is weighed with); its area; its probability of being chosen (its power, area × brightest
/// channel, over all of theirs) and the cumulative probability of it and those before it
/// (what a uniform number is searched in). With none, one entry of probability 0.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct HitEmitter {
    pub p0: [f32; 3],
    pub prob: f32,
    pub p1: [f32; 3],
    pub cdf: f32,
    pub p2: [f32; 3],
    pub triangle: u32,
    pub radiance: [f32; 3],
    pub area: f32,
}

/// `HitMaterial::maps` entry of a material without that map.
pub const NO_MAP: u32 = u32::MAX;

/// One material of the standard `hit_materials` binding: what a ray's hit is shaded with —
/// its values with each map's mean (its 1×1 mip level) for passes that do not look maps up,
/// and its factors, maps (indices into `hit_maps`), UV sets and transform, wrap modes and
/// alpha cutoff for those that do (`shaders/lib/hit_maps.wgsl`, as the reference does).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct HitMaterial {
    /// Linear base colour × the base-colour map's mean; a: alpha.
    pub albedo: [f32; 4],
    /// Emitted radiance (factor × strength × the emissive map's mean); w unused.
    pub emissive: [f32; 4],
    pub metallic: f32,
    pub roughness: f32,
    /// Alpha below which a masked surface is cut out (0: opaque; −1: blended, cut out where
    /// its alpha is below a coin tossed per ray and triangle).
    pub cutoff: f32,
    /// Bit k: map k (base colour, metallic-roughness, normal, emissive) reads TEXCOORD_1.
    pub uv_sets: u32,
    /// The factors the maps multiply: base colour (a: alpha), emission.
    pub base_factor: [f32; 4],
    pub emissive_factor: [f32; 3],
    /// Wrap mode per axis (bits 0–1: u, 2–3: v; 0 repeat, 1 clamp, 2 mirror).
    pub wrap: u32,
    pub metallic_factor: f32,
    pub roughness_factor: f32,
    pub normal_scale: f32,
    pub _pad: f32,
    /// Base colour, metallic-roughness, normal and emissive maps (`NO_MAP`: none).
    pub maps: [u32; 4],
    /// The UV transform's rows (KHR_texture_transform; w unused).
    pub uv_row0: [f32; 4],
    pub uv_row1: [f32; 4],
}

/// One traced triangle's corners in the standard `hit_corners` table (6 texels): per corner
/// (u, v) of TEXCOORD_0 and of TEXCOORD_1, and its tangent in world space (w: the bitangent's
/// sign).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, Pod, Zeroable, PartialEq)]
pub struct HitCorners {
    pub uv: [[f32; 4]; 3],
    pub tangent: [[f32; 4]; 3],
}

/// Interleaved scene vertex: locations 0..4 of the standard vertex layout.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable, PartialEq)]
pub struct Vertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    pub uv: [f32; 2],
    pub tangent: [f32; 4],
    /// The second texture coordinate set (glTF TEXCOORD_1; the first when absent).
    pub uv1: [f32; 2],
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Parse the shader library and compare naga's layout of each struct with ours.
    #[test]
    fn blocks_match_the_wgsl_declarations() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../shaders/lib");
        let read = |f: &str| std::fs::read_to_string(root.join(f)).unwrap();
        // area_light.wgsl's bindings read tables its includer binds: the structs alone.
        let area = read("area_light.wgsl");
        let area_struct = &area[area.find("struct AreaLight").unwrap()..area.find("@group").unwrap()];
        let hit = read("hit.wgsl");
        let hit_structs = &hit[hit.find("struct HitTriangle").unwrap()..hit.find("@group").unwrap()];
        let emit = read("hit_emitters.wgsl");
        let emit_struct = &emit[emit.find("struct HitEmitter").unwrap()..emit.find("@group").unwrap()];
        let maps = read("hit_maps.wgsl");
        let maps_struct = &maps[maps.find("struct HitCorners").unwrap()..maps.find("@group").unwrap()];
        // mesh.wgsl's one `#include` spliced in by hand.
        let mesh = read("mesh.wgsl").replace("#include \"lib/map_slots.wgsl\"", &read("map_slots.wgsl"));
        let src = read("frame.wgsl") + &mesh + area_struct + hit_structs + emit_struct + maps_struct;
        let module = naga::front::wgsl::parse_str(&src).unwrap();
        let mut layouter = naga::proc::Layouter::default();
        layouter.update(module.to_ctx()).unwrap();
        let size_of = |name: &str| {
            let (h, _) = module.types.iter().find(|(_, t)| t.name.as_deref() == Some(name)).unwrap();
            layouter[h].size as usize
        };
        assert_eq!(size_of("Frame"), std::mem::size_of::<FrameBlock>());
        assert_eq!(size_of("Light"), std::mem::size_of::<LightBlock>());
        assert_eq!(size_of("Instance"), std::mem::size_of::<InstanceBlock>());
        assert_eq!(size_of("Mesh"), std::mem::size_of::<MeshBlock>());
        assert_eq!(size_of("Material"), std::mem::size_of::<MaterialBlock>());
        assert_eq!(size_of("AreaLight"), std::mem::size_of::<AreaLightBlock>());
        assert_eq!(size_of("HitTriangle"), std::mem::size_of::<HitTriangle>());
        assert_eq!(size_of("HitMaterial"), std::mem::size_of::<HitMaterial>());
        assert_eq!(size_of("HitEmitter"), std::mem::size_of::<HitEmitter>());
        assert_eq!(size_of("HitCorners"), std::mem::size_of::<HitCorners>());
        // Member offsets of the light block, the most intricate one.
        let (_, light) = module.types.iter().find(|(_, t)| t.name.as_deref() == Some("Light")).unwrap();
        let naga::TypeInner::Struct { members, .. } = &light.inner else {
            panic!()
        };
        let offsets: Vec<u32> = members.iter().map(|m| m.offset).collect();
        assert_eq!(offsets, vec![0, 16, 32, 48, 64, 68, 72, 76, 80, 144]);
        // The frame block's fields: each member of `Frame`, by name and offset, in order.
        let (_, frame) = module.types.iter().find(|(_, t)| t.name.as_deref() == Some("Frame")).unwrap();
        let naga::TypeInner::Struct { members, .. } = &frame.inner else {
            panic!()
        };
        let wgsl: Vec<(&str, usize)> = members.iter().map(|m| (m.name.as_deref().unwrap(), m.offset as usize)).collect();
        let ours: Vec<(&str, usize)> = FrameField::ALL.iter().map(|f| (f.name(), f.bytes().0)).collect();
        assert_eq!(wgsl, ours);
        assert_eq!(
            serde_json::to_string(&FrameField::PrevInvViewProj).unwrap(),
            "\"prev_inv_view_proj\""
        );
    }

    /// The bytes a member spans name the fields under them: one, several, or none past the end.
    #[test]
    fn frame_fields_are_found_by_the_bytes_read() {
        let time = FrameField::Time.bytes().0;
        assert_eq!(FrameField::overlapping(time, 4).collect::<Vec<_>>(), [FrameField::Time]);
        assert_eq!(
            FrameField::overlapping(time, 8).collect::<Vec<_>>(),
            [FrameField::Time, FrameField::FrameIndex]
        );
        assert_eq!(FrameField::overlapping(0, 1).collect::<Vec<_>>(), [FrameField::View]);
        assert_eq!(FrameField::overlapping(std::mem::size_of::<FrameBlock>(), 16).count(), 0);
    }
}
