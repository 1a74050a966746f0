// Shading a ray's hit with the definitions the G-buffer and the reference use: the traced
// triangle's interpolated shading normal, its front, and its material (standard bindings
// `hit_triangles`, a table of lib/table.wgsl, and `hit_materials`, built with the
// acceleration structure). Included by
// lib/hit_maps.wgsl, which looks the maps up where a ray met a surface (here each map stands
// in by its mean), and through it by lib/ray.wgsl.
#include "lib/math.wgsl"
#include "lib/surface.wgsl"
#include "lib/table.wgsl"

struct HitTriangle {
    // The corners' shading normals (world, unit).
    n0: vec3<f32>,
    material: u32,
    n1: vec3<f32>,
    // 1: both sides are seen (glTF doubleSided)
    double_sided: u32,
    n2: vec3<f32>,
    // Its index into `hit_emitters` (lib/hit_emitters.wgsl), NO_EMITTER if it emits nothing.
    emitter: u32,
    // The front's geometric normal (world, unit).
    ng: vec3<f32>,
    _pad1: u32,
};

struct HitMaterial {
    // Linear base colour × the base-colour map's mean; a: alpha
    albedo: vec4<f32>,
    // Emitted radiance; w unused
    emissive: vec4<f32>,
    metallic: f32,
    roughness: f32,
    // What lib/hit_maps.wgsl looks maps up with: the alpha cutoff (0: opaque, −1: blended), the UV
    // set of each map (bit k), the factors the maps multiply, the wrap modes (2 bits per
    // axis), the maps (base colour, metallic-roughness, normal, emissive) and UV transform.
    cutoff: f32,
    uv_sets: u32,
    base_factor: vec4<f32>,
    emissive_factor: vec3<f32>,
    wrap: u32,
    metallic_factor: f32,
    roughness_factor: f32,
    normal_scale: f32,
    _pad: f32,
    maps: vec4<u32>,
    uv_row0: vec4<f32>,
    uv_row1: vec4<f32>,
};

// 4 texels per triangle (its `HitTriangle`'s words).
@group(0) @binding(5) var hit_triangles: texture_2d_array<u32>;
@group(0) @binding(6) var<storage, read> hit_materials: array<HitMaterial>;

const NO_EMITTER: u32 = 0xffffffffu;

// What a ray met: the surface's point, its shading and geometric normals turned to face the
// ray, its material, whether the ray met its front, its triangle's emitter index, and
// whether the ray passed the back of a single-sided surface on its way (then what this one
// emits is shadowed from the ray's origin, as the reference's `Hit::shadowed`).
struct RayHit {
    found: bool,
    t: f32,
    world: vec3<f32>,
    n: vec3<f32>,
    ng: vec3<f32>,
    albedo: vec3<f32>,
    metallic: f32,
    roughness: f32,
    emissive: vec3<f32>,
    front: bool,
    emitter: u32,
    shadowed: bool,
    // The triangle met (an index into the `hit_triangles` table) and where on it.
    triangle: u32,
    bary: vec2<f32>,
};

// Traced triangle `index`'s hit data.
fn hit_triangle_at(index: u32) -> HitTriangle {
    let a = table_texel(hit_triangles, 4u * index);
    let b = table_texel(hit_triangles, 4u * index + 1u);
    let c = table_texel(hit_triangles, 4u * index + 2u);
    let d = table_texel(hit_triangles, 4u * index + 3u);
    return HitTriangle(bitcast<vec3<f32>>(a.xyz), a.w, bitcast<vec3<f32>>(b.xyz), b.w, bitcast<vec3<f32>>(c.xyz), c.w, bitcast<vec3<f32>>(d.xyz), d.w);
}

fn hit_triangle(i: RayIntersection) -> HitTriangle {
    return hit_triangle_at(i.instance_custom_data + i.primitive_index);
}

// A traced triangle's sides: its front's normal and whether both sides are seen — two of the
// four texels `hit_triangle_at` reads, for the loops that test every candidate a ray meets.
struct HitSides {
    ng: vec3<f32>,
    double_sided: u32,
};

fn hit_sides_at(index: u32) -> HitSides {
    let ng = bitcast<vec3<f32>>(table_texel(hit_triangles, 4u * index + 3u).xyz);
    return HitSides(ng, table_texel(hit_triangles, 4u * index + 1u).w);
}

// Traced triangle `index`'s material: one texel's word, an index into `hit_materials`.
fn hit_material_at(index: u32) -> HitMaterial {
    return hit_materials[table_texel(hit_triangles, 4u * index).w];
}

// Camera and bounce rays see the front of a single-sided surface and both sides of a
// double-sided one (the sidedness rule of docs/scenes.md).
fn seen_along(tri: HitSides, dir: vec3<f32>) -> bool {
    return tri.double_sided != 0u || dot(tri.ng, dir) < 0.0;
}

// A hit as the surface lib/lighting.wgsl shades, seen from `v`.
fn hit_surface(h: RayHit, v: vec3<f32>) -> Surface {
    return Surface(h.world, h.n, v, h.albedo, h.metallic, h.roughness, h.found);
}

// The committed intersection as a surface to shade.
fn ray_hit(i: RayIntersection, origin: vec3<f32>, dir: vec3<f32>) -> RayHit {
    var h: RayHit;
    h.found = i.kind == RAY_QUERY_INTERSECTION_TRIANGLE;
    if !h.found {
        return h;
    }
    let tri = hit_triangle(i);
    let m = hit_materials[tri.material];
    h.triangle = i.instance_custom_data + i.primitive_index;
    h.bary = i.barycentrics;
    let b = i.barycentrics;
    let interpolated = tri.n0 * (1.0 - b.x - b.y) + tri.n1 * b.x + tri.n2 * b.y;
    h.front = dot(tri.ng, dir) < 0.0;
    // Facing the ray: a double-sided surface's back is lit as its own side. The shading
    // normal is turned to the geometric one's side (on a front) or towards the ray (on a back),
    // as the reference turns it, so that corner normals pointing the other way (a flipped
    // winding) shade the side that is seen.
    let n = safe_normalize(interpolated, tri.ng);
    h.ng = select(-tri.ng, tri.ng, h.front);
    h.n = select(select(n, -n, dot(n, dir) > 0.0), select(n, -n, dot(n, tri.ng) < 0.0), h.front);
    h.emitter = tri.emitter;
    h.t = i.t;
    h.world = origin + dir * i.t;
    h.albedo = m.albedo.rgb;
    h.metallic = m.metallic;
    h.roughness = m.roughness;
    h.emissive = select(vec3<f32>(0.0), m.emissive.rgb, h.front || tri.double_sided != 0u);
    return h;
}
