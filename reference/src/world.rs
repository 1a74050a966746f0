//! Stage `world` of the reference renderer: the scene the raster passes draw, as world-space
//! triangles in a BVH, with the surface (position, normals, material) at any hit.
//!
//! BVH: `bvh.rs`, built by obvhs (PLOC, SAH-guided; it shares our glam 0.34 and needs no
//! other heavy dependency) and traversed there. bvh 0.13 returns every shape whose box a ray
//! crosses (a Vec per ray, no closest-hit early-out), which costs several times as much per
//! ray on scenes of more than a few hundred triangles.

use super::bvh::{Bvh, Ray};
use glam::{Vec2, Vec3A, Vec4};
use lightbench_scene::{AlphaMode, ImageData, Material, Mesh, Scene, Wrap};
use obvhs::triangle::Triangle;

/// A vertex's attributes, in world space (zero for an index past a mesh's vertices: the last
/// of the world's `vertices`).
#[derive(Clone, Copy, Default)]
struct Corner {
    normal: Vec3A,
    uv: Vec2,
    uv1: Vec2,
    tangent: Vec4,
}

/// The surface at a ray hit, its material evaluated as `lib/material.wgsl` does.
#[derive(Clone, Copy, Debug)]
pub struct Hit {
    pub t: f32,
    pub position: Vec3A,
    /// Shading normal (interpolated, normal-mapped), turned towards the ray's origin.
    pub n: Vec3A,
    /// Geometric normal, on the same side as `n`: rays leave along it.
    pub ng: Vec3A,
    pub albedo: Vec3A,
    pub metallic: f32,
    pub roughness: f32,
    pub emissive: Vec3A,
    /// The triangle hit (an index into the world's triangles).
    pub triangle: u32,
    /// The ray passed the back of a single-sided surface on its way here (camera and bounce
    /// rays do): what this surface emits is shadowed from the ray's origin, as an occlusion
    /// ray towards it would find.
    pub shadowed: bool,
}

/// Which faces a ray meets. The one sidedness rule, as the raster pipelines draw it: what
/// the camera sees, directly or by a bounce, is a surface's front, or either side of a
/// double-sided one (glTF `doubleSided`); what blocks light (shadows, occlusion) is every
/// surface, from either side.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Faces {
    /// Camera and bounce rays: the backs of single-sided surfaces let them through.
    Seen,
    /// Occlusion: every face.
    Both,
}

/// What `surface` knows of a triangle before a hit: its unit face normal, and its shading
/// normal where that is the same everywhere on it (its corners' normals are one: flat faces).
#[derive(Clone, Copy)]
struct Face {
    normal: Vec3A,
    /// Zero where the face is not flat (a unit vector otherwise; 32 bytes a face where an
    /// `Option` took 48).
    flat_normal: Vec3A,
}

/// A material as evaluated at a point (`lib/material.wgsl`): base colour, metallic and
/// roughness clamped, emission.
#[derive(Clone, Copy)]
struct Look {
    albedo: Vec3A,
    metallic: f32,
    roughness: f32,
    emissive: Vec3A,
}

impl Look {
    /// `mat` at a point of base colour `base` (the factor times the texture) and textures'
    /// values `mr` (metallic in z, roughness in y) and `emissive`.
    fn new(mat: &Material, base: Vec4, mr: Vec4, emissive: Vec4) -> Look {
        Look {
            albedo: Vec3A::from_vec4(base),
            metallic: (mat.metallic * mr.z).clamp(0.0, 1.0),
            roughness: (mat.roughness * mr.y).clamp(0.03, 1.0),
            emissive: Vec3A::from(mat.emissive) * Vec3A::from_vec4(emissive),
        }
    }

    /// The same everywhere: `mat` without textures (else none).
    fn plain(mat: &Material) -> Option<Look> {
        let textured = [
            mat.base_color_texture,
            mat.metallic_roughness_texture,
            mat.emissive_texture,
            mat.normal_texture,
        ];
        textured
            .iter()
            .all(Option::is_none)
            .then(|| Look::new(mat, Vec4::from(mat.base_color), Vec4::ONE, Vec4::ONE))
    }
}

const DOUBLE_SIDED: u8 = 1;
const OPAQUE: u8 = 2;

pub struct World {
    bvh: Bvh,
    /// Triangles in BVH order (so a hit's id indexes them directly).
    tris: Vec<Triangle>,
    /// Each triangle's corners: indices into `vertices`, which the meshes' triangles share as
    /// their vertices do (a copy per corner was 144 bytes per triangle; this is 12, plus 48
    /// per vertex).
    corners: Vec<[u32; 3]>,
    vertices: Vec<Corner>,
    faces: Vec<Face>,
    material: Vec<u32>,
    /// Each triangle's place in the scene's order, which stochastic transparency hashes (the
    /// same whatever order a BVH keeps them in).
    scene_index: Vec<u32>,
    /// Per triangle: `DOUBLE_SIDED` and `OPAQUE` of its material (no lookup while traversing).
    flags: Vec<u8>,
    materials: Vec<Material>,
    /// Per material, its look where it has no textures: a hit on a flat face of it needs no
    /// barycentrics.
    plain: Vec<Option<Look>>,
    textures: Vec<ImageData>,
    /// Some triangle's material is blended (`has_blended`).
    blended: bool,
}

impl Face {
    fn flat(&self) -> Option<Vec3A> {
        (self.flat_normal != Vec3A::ZERO).then_some(self.flat_normal)
    }

    fn new(t: &Triangle, c: [&Corner; 3]) -> Face {
        // The face normal as a hit worked it out before it was kept here (the same bits).
        let normal = (t.v1 - t.v0).cross(t.v2 - t.v0).normalize_or(Vec3A::Y);
        let same = c[1].normal == c[0].normal && c[2].normal == c[0].normal;
        Face {
            normal,
            flat_normal: if same {
                c[0].normal.try_normalize().unwrap_or(normal)
            } else {
                Vec3A::ZERO
            },
        }
    }
}

/// `v` in `order`, `v` dropped (its old order is not held beside the new).
fn reordered<T: Copy>(v: Vec<T>, order: &[usize]) -> Vec<T> {
    order.iter().map(|&i| v[i]).collect()
}

/// Mesh `m`'s drawn triangles (its `triangle_fraction`, as the raster draws it), each as
/// its three vertex indices: wound the other way under a mirroring transform (glTF §3.7.4:
/// it swaps the sides), so that the face normal always points out of the front.
fn drawn_triangles(m: &Mesh) -> impl Iterator<Item = [u32; 3]> + '_ {
    let mirrored = m.transform.determinant() < 0.0;
    (0..drawn_count(m)).map(move |t| triangle(m, t, mirrored))
}

fn drawn_count(m: &Mesh) -> usize {
    (m.drawn_indices() as usize).min(m.indices.len()) / 3
}

/// Triangle `t` of mesh `m`, wound the other way if `mirrored`.
fn triangle(m: &Mesh, t: usize, mirrored: bool) -> [u32; 3] {
    let i = &m.indices[t * 3..t * 3 + 3];
    if mirrored {
        [i[0], i[2], i[1]]
    } else {
        [i[0], i[1], i[2]]
    }
}

/// Every drawn triangle of the scene in world space, in the scene's order: what the BVH is
/// built from (an index past its mesh's vertices reads a zero vertex).
fn positions(scene: &Scene) -> Vec<Triangle> {
    let mut tris = Vec::with_capacity(scene.meshes.iter().map(drawn_count).sum());
    for m in &scene.meshes {
        for idx in drawn_triangles(m) {
            let vs = idx.map(|i| m.vertices.get(i as usize).copied().unwrap_or_else(bytemuck::Zeroable::zeroed));
            let p = vs.map(|v| m.transform.transform_point3a(Vec3A::from(v.position)));
            tris.push(Triangle {
                v0: p[0],
                v1: p[1],
                v2: p[2],
            });
        }
    }
    tris
}

/// What triangles: each triangle's corners (indices into the vertices' world-space attributes,
/// which follow; the last one zero, for an index past its mesh's vertices) and material.
type Attributes = (Vec<[u32; 3]>, Vec<Corner>, Vec<u32>);

/// The triangles' `Attributes` in `order` (the BVH's): gathered after the BVH is built, so
/// that they are not held while it is (the build's peak). A mesh's material index out of
/// range is the one past the scene's (white).
fn attributes(scene: &Scene, order: &[usize]) -> Attributes {
    let zero = scene.meshes.iter().map(|m| m.vertices.len()).sum::<usize>() as u32;
    let (mut vertices, mut first, mut starts, mut mirrored) = (vec![], vec![], vec![], vec![]);
    let mut triangles = 0;
    for m in &scene.meshes {
        let normal_matrix = m.transform.inverse().transpose();
        first.push(vertices.len() as u32);
        starts.push(triangles);
        mirrored.push(m.transform.determinant() < 0.0);
        triangles += drawn_count(m);
        vertices.extend(m.vertices.iter().map(|v| {
            Corner {
                normal: normal_matrix.transform_vector3a(Vec3A::from(v.normal)),
                uv: Vec2::from(v.uv),
                uv1: Vec2::from(v.uv1),
                tangent: m
                    .transform
                    .transform_vector3a(Vec3A::from_slice(&v.tangent[..3]))
                    .extend(v.tangent[3]),
            }
        }));
    }
    vertices.push(Corner::default());
    let (mut corners, mut material) = (Vec::with_capacity(order.len()), Vec::with_capacity(order.len()));
    for &t in order {
        let k = starts.partition_point(|&s| s <= t) - 1;
        let m = &scene.meshes[k];
        let idx = triangle(m, t - starts[k], mirrored[k]);
        corners.push(idx.map(|i| if (i as usize) < m.vertices.len() { first[k] + i } else { zero }));
        material.push((m.material as u32).min(scene.materials.len() as u32));
    }
    (corners, vertices, material)
}

impl World {
    /// Every drawn triangle of the scene (each mesh's `triangle_fraction` as the raster draws
    /// it), with its mesh's transform applied.
    pub fn new(scene: &Scene) -> World {
        let tris = positions(scene);
        // Reordered so that the BVH's hit ids index the arrays without an indirection.
        let (bvh, order) = Bvh::build(&tris);
        let tris = reordered(tris, &order);
        let (corners, vertices, material) = attributes(scene, &order);
        // One past the scene's: white, for a mesh whose material index is out of range.
        let materials: Vec<Material> = scene
            .materials
            .iter()
            .cloned()
            .chain([Material::color("default", [1.0; 3], 1.0)])
            .collect();
        let flags = material
            .iter()
            .map(|&m| {
                let m = &materials[m as usize];
                (m.double_sided as u8 * DOUBLE_SIDED) | ((m.alpha == AlphaMode::Opaque) as u8 * OPAQUE)
            })
            .collect();
        let blended = material.iter().any(|&m| materials[m as usize].alpha == AlphaMode::Blend);
        let faces = tris
            .iter()
            .zip(&corners)
            .map(|(t, c)| Face::new(t, c.map(|k| &vertices[k as usize])))
            .collect();
        World {
            bvh,
            faces,
            plain: materials.iter().map(Look::plain).collect(),
            tris,
            corners,
            vertices,
            material,
            scene_index: order.iter().map(|&i| i as u32).collect(),
            flags,
            materials,
            textures: scene.textures.clone(),
            blended,
        }
    }

    /// Triangle `i`'s corners' attributes.
    fn attributes(&self, i: usize) -> [&Corner; 3] {
        self.corners[i].map(|k| &self.vertices[k as usize])
    }

    pub fn triangles(&self) -> usize {
        self.tris.len()
    }

    /// Triangle `i`'s place in the scene's order (the meshes' drawn triangles one after another).
    pub fn scene_triangle(&self, i: u32) -> u32 {
        self.scene_index[i as usize]
    }

    /// Whether a hit on triangle `i` at `t` (determinant `det`) counts: cut-out texels (alpha
    /// mask) and, with the probability of their transparency, blended ones let the ray
    /// through. With `Faces::Seen` so does the back of a single-sided surface, whose distance
    /// goes to `back` (the nearest such).
    fn counts(&self, ray: &Ray, (i, t, det): (usize, f32, f32), (faces, coin): (Faces, u32), back: &mut f32) -> bool {
        let flags = self.flags[i];
        if flags & OPAQUE == 0 && self.cut_out(ray, i, t, coin) {
            return false;
        }
        // det < 0: the ray meets the face from behind (det = −d · (e1 × e2)).
        if faces == Faces::Seen && flags & DOUBLE_SIDED == 0 && det < 0.0 {
            *back = back.min(t);
            return false;
        }
        true
    }

    /// Whether the ray passes triangle `i` at `t`: a cut-out texel, or a blended one by the
    /// probability of its transparency. Kept out of line: it is the rare case, and without
    /// it `counts`, run for every triangle a ray meets, is inlined into the traversal (1.6%
    /// fewer instructions per path on the Cornell box).
    #[inline(never)]
    fn cut_out(&self, ray: &Ray, i: usize, t: f32, coin: u32) -> bool {
        let mat = &self.materials[self.material[i] as usize];
        let cutoff = match mat.alpha {
            AlphaMode::Opaque => return false,
            AlphaMode::Mask(c) => c,
            AlphaMode::Blend if coin == super::sample::SOLID_BLEND => return false,
            // Stochastic transparency, decided by a hash of the ray, the triangle and the
            // caller's coin: the same query always meets the same surfaces (bit-identical
            // reruns), and a camera ray repeated per sample gets a coin per sample.
            AlphaMode::Blend => {
                let key = [
                    ray.origin.x,
                    ray.origin.y,
                    ray.dir.z,
                    self.scene_index[i] as f32,
                    t,
                    f32::from_bits(coin),
                ];
                super::sample::unit_hash(&key)
            }
        };
        let bary = self.barycentrics(i, ray.origin + ray.dir * t);
        self.base_color(mat, self.uv_at(i, bary, 0)).w < cutoff
    }

    /// The nearest surface along `dir` from `origin` between `tmin` and `tmax`, of the
    /// `faces` asked for.
    pub fn trace(&self, origin: Vec3A, dir: Vec3A, range: (f32, f32), faces: Faces) -> Option<Hit> {
        self.trace_with_coin(origin, dir, range, faces, 0)
    }

    /// `trace`, blended surfaces passed or met by `coin` as well as by the ray.
    pub fn trace_with_coin(&self, origin: Vec3A, dir: Vec3A, (tmin, tmax): (f32, f32), faces: Faces, coin: u32) -> Option<Hit> {
        let ray = Ray::new(origin, dir, tmin, tmax);
        let mut back = f32::INFINITY;
        let (i, t) = self
            .bvh
            .closest(&ray, &mut |i, t, det| self.counts(&ray, (i, t, det), (faces, coin), &mut back))?;
        let mut h = self.surface(i as usize, origin, dir, t);
        h.shadowed = back < t;
        Some(h)
    }

    /// Whether anything lies along `dir` from `origin` between `tmin` and `tmax`.
    pub fn occluded(&self, origin: Vec3A, dir: Vec3A, tmin: f32, tmax: f32) -> bool {
        self.occluded_with_coin(origin, dir, (tmin, tmax), 0)
    }

    /// `occluded`, blended surfaces passed or met by `coin` as well as by the ray.
    pub fn occluded_with_coin(&self, origin: Vec3A, dir: Vec3A, (tmin, tmax): (f32, f32), coin: u32) -> bool {
        let ray = Ray::new(origin, dir, tmin, tmax);
        let mut back = f32::INFINITY;
        self.bvh.any(&ray, &mut |i, t, det| {
            self.counts(&ray, (i, t, det), (Faces::Both, coin), &mut back)
        })
    }

    /// Whether some material is blended: then what a camera ray meets differs between samples
    /// (each with its own coin), and no term is exact with one sample.
    pub fn has_blended(&self) -> bool {
        self.blended
    }

    /// Triangle `i`'s corners.
    pub fn corners(&self, i: usize) -> [Vec3A; 3] {
        let t = &self.tris[i];
        [t.v0, t.v1, t.v2]
    }

    pub fn double_sided(&self, i: usize) -> bool {
        self.flags[i] & DOUBLE_SIDED != 0
    }

    /// What triangle `i` emits at barycentric weights `w` (the emissive factor, times the
    /// emissive map there).
    pub fn emission(&self, i: usize, w: Vec3A) -> Vec3A {
        let mat = &self.materials[self.material[i] as usize];
        Vec3A::from(mat.emissive) * Vec3A::from_vec4(self.emissive_map(mat, i, w))
    }

    /// The most triangle `i` can emit on average per channel, as a power estimate: the
    /// emissive factor times the emissive map's mean (0 only where it emits nothing).
    pub fn emission_bound(&self, i: usize, map_means: &[Vec3A]) -> Vec3A {
        let mat = &self.materials[self.material[i] as usize];
        let mean = mat.emissive_texture.and_then(|t| map_means.get(t).copied()).unwrap_or(Vec3A::ONE);
        Vec3A::from(mat.emissive) * mean
    }

    /// Mean linear colour of each texture (for `emission_bound`).
    pub fn texture_means(&self) -> Vec<Vec3A> {
        self.textures.iter().map(texture_mean).collect()
    }

    fn emissive_map(&self, mat: &Material, i: usize, w: Vec3A) -> Vec4 {
        let uv = self.uv_at(i, w, (mat.uv_sets >> 3) & 1);
        mat.emissive_texture
            .and_then(|t| self.textures.get(t))
            .map_or(Vec4::ONE, |tex| sample(tex, mat, self.transform_uv(mat, uv)))
    }

    /// Barycentric weights of `p` on triangle `i`.
    fn barycentrics(&self, i: usize, p: Vec3A) -> Vec3A {
        let t = &self.tris[i];
        let (a, b, c) = (t.v0, t.v1, t.v2);
        let n = (b - a).cross(c - a);
        let area = n.length_squared().max(1e-30);
        let wb = (p - a).cross(c - a).dot(n) / area;
        let wc = (b - a).cross(p - a).dot(n) / area;
        Vec3A::new(1.0 - wb - wc, wb, wc)
    }

    fn uv_at(&self, i: usize, w: Vec3A, set: u32) -> Vec2 {
        let c = self.attributes(i);
        let (a, b, d) = if set == 0 {
            (c[0].uv, c[1].uv, c[2].uv)
        } else {
            (c[0].uv1, c[1].uv1, c[2].uv1)
        };
        a * w.x + b * w.y + d * w.z
    }

    fn surface(&self, i: usize, origin: Vec3A, dir: Vec3A, t: f32) -> Hit {
        let position = origin + dir * t;
        let ng = self.faces[i].normal;
        let (n, look) = match (self.faces[i].flat(), self.plain[self.material[i] as usize]) {
            (Some(n), Some(look)) => (n, look),
            _ => self.look_at(i, position, ng),
        };
        // Normals face the incoming ray: a back is hit only where it is seen (double-sided)
        // or by an occlusion ray.
        let (ng, n) = if ng.dot(dir) > 0.0 {
            (-ng, if n.dot(dir) > 0.0 { -n } else { n })
        } else {
            (ng, if n.dot(ng) < 0.0 { -n } else { n })
        };
        Hit {
            t,
            position,
            n,
            ng,
            albedo: look.albedo,
            metallic: look.metallic,
            roughness: look.roughness,
            emissive: look.emissive,
            triangle: i as u32,
            shadowed: false,
        }
    }

    /// The shading normal and material at `position` on triangle `i` (unit face normal
    /// `ng`): vertex normals interpolated, textures sampled.
    fn look_at(&self, i: usize, position: Vec3A, ng: Vec3A) -> (Vec3A, Look) {
        let w = self.barycentrics(i, position);
        let c = self.attributes(i);
        let interpolated = c[0].normal * w.x + c[1].normal * w.y + c[2].normal * w.z;
        // Zero-length vertex normals: the face normal stands in (as in the shaders).
        let mut n = interpolated.try_normalize().unwrap_or(ng);
        let mat = &self.materials[self.material[i] as usize];
        let map = |k: u32| self.uv_at(i, w, (mat.uv_sets >> k) & 1);
        if let Some(tex) = mat.normal_texture.and_then(|t| self.textures.get(t)) {
            let tangent = c[0].tangent * w.x + c[1].tangent * w.y + c[2].tangent * w.z;
            n = normal_mapped(
                n,
                tangent,
                Vec3A::from_vec4(sample(tex, mat, self.transform_uv(mat, map(2)))),
                mat.normal_scale,
            );
        }
        let base = self.base_color(mat, map(0));
        let mr = mat
            .metallic_roughness_texture
            .and_then(|t| self.textures.get(t))
            .map_or(Vec4::ONE, |tex| sample(tex, mat, self.transform_uv(mat, map(1))));
        let emissive = self.emissive_map(mat, i, w);
        (n, Look::new(mat, base, mr, emissive))
    }

    fn transform_uv(&self, mat: &Material, uv: Vec2) -> Vec2 {
        let [r0, r1] = mat.uv_transform;
        Vec2::new(r0[0] * uv.x + r0[1] * uv.y + r0[2], r1[0] * uv.x + r1[1] * uv.y + r1[2])
    }

    fn base_color(&self, mat: &Material, uv: Vec2) -> Vec4 {
        let tex = mat
            .base_color_texture
            .and_then(|t| self.textures.get(t))
            .map_or(Vec4::ONE, |tex| sample(tex, mat, self.transform_uv(mat, uv)));
        Vec4::from(mat.base_color) * tex
    }
}

/// Mean of a texture's texels, sRGB colour decoded to linear.
fn texture_mean(img: &ImageData) -> Vec3A {
    let n = (img.rgba.len() / 4).max(1) as f32;
    let f = |v: u8| {
        let v = v as f32 / 255.0;
        if img.srgb {
            lightbench_scene::io::srgb_to_linear(v)
        } else {
            v
        }
    };
    img.rgba
        .chunks_exact(4)
        .fold(Vec3A::ZERO, |s, p| s + Vec3A::new(f(p[0]), f(p[1]), f(p[2])))
        / n
}

/// The tangent-space normal map applied as `lib/material.wgsl` applies it.
fn normal_mapped(n: Vec3A, tangent: Vec4, texel: Vec3A, scale: f32) -> Vec3A {
    let t_len = Vec3A::from_vec4(tangent).length();
    if t_len <= 1e-6 {
        return n;
    }
    let t = (Vec3A::from_vec4(tangent) - n * n.dot(Vec3A::from_vec4(tangent))).normalize_or_zero();
    let b = n.cross(t) * tangent.w;
    let k = texel * 2.0 - 1.0;
    (t * k.x * scale + b * k.y * scale + n * k.z).try_normalize().unwrap_or(n)
}

/// Bilinear texel fetch with the material's wrap modes; sRGB textures are decoded to linear.
fn sample(img: &ImageData, mat: &Material, uv: Vec2) -> Vec4 {
    let (w, h) = (img.width.max(1) as i64, img.height.max(1) as i64);
    let x = uv.x * w as f32 - 0.5;
    let y = uv.y * h as f32 - 0.5;
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let texel = |xi: i64, yi: i64| -> Vec4 {
        let (xi, yi) = (wrap(xi, w, mat.sampler.wrap[0]), wrap(yi, h, mat.sampler.wrap[1]));
        let o = ((yi * w + xi) * 4) as usize;
        let px = img.rgba.get(o..o + 4).unwrap_or(&[255; 4]);
        let f = |v: u8, colour: bool| {
            let v = v as f32 / 255.0;
            if colour && img.srgb {
                lightbench_scene::io::srgb_to_linear(v)
            } else {
                v
            }
        };
        Vec4::new(f(px[0], true), f(px[1], true), f(px[2], true), f(px[3], false))
    };
    let (x0, y0) = (x0 as i64, y0 as i64);
    let top = texel(x0, y0).lerp(texel(x0 + 1, y0), fx);
    let bottom = texel(x0, y0 + 1).lerp(texel(x0 + 1, y0 + 1), fx);
    top.lerp(bottom, fy)
}

fn wrap(i: i64, n: i64, mode: Wrap) -> i64 {
    match mode {
        Wrap::Repeat => i.rem_euclid(n),
        Wrap::Clamp => i.clamp(0, n - 1),
        Wrap::Mirror => {
            let m = i.rem_euclid(2 * n);
            if m < n {
                m
            } else {
                2 * n - 1 - m
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The scenes bundled with the project: every `.ron` under `scenes/` and `scenes/hard/`,
    /// and the built-in ones.
    fn bundled() -> Vec<Scene> {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../scenes");
        let mut files: Vec<_> = [root.clone(), root.join("hard")]
            .iter()
            .flat_map(|d| std::fs::read_dir(d).unwrap().map(|e| e.unwrap().path()))
            .filter(|p| p.extension().is_some_and(|e| e == "ron"))
            .collect();
        files.sort();
        let loaded = files
            .iter()
            .map(|f| lightbench_scene::load::load_sized(f.to_str().unwrap(), None, &[]).unwrap());
        loaded
            .chain(
                lightbench_scene::builtin::NAMES
                    .iter()
                    .filter_map(|n| lightbench_scene::builtin::by_name(n)),
            )
            .collect()
    }

    /// A hit on a flat face of a material without textures skips interpolation: what it takes
    /// is what interpolating gives (the normal to rounding, the material exactly), and a
    /// material without textures looks the same on every face, flat or not.
    #[test]
    fn the_flat_face_shortcut_is_what_interpolation_gives() {
        let scenes = bundled();
        assert!(scenes.len() > 30);
        let (mut flat, mut smooth) = (0, 0);
        for s in &scenes {
            let w = World::new(s);
            for i in 0..w.triangles() {
                let t = &w.tris[i];
                let centre = (t.v0 + t.v1 + t.v2) / 3.0;
                let (n, look) = w.look_at(i, centre, w.faces[i].normal);
                let Some(plain) = w.plain[w.material[i] as usize] else { continue };
                let same =
                    |a: Look, b: Look| (a.albedo, a.metallic, a.roughness, a.emissive) == (b.albedo, b.metallic, b.roughness, b.emissive);
                assert!(same(look, plain), "{}: triangle {i}", s.name);
                match w.faces[i].flat() {
                    Some(shortcut) => {
                        assert!((shortcut - n).length() < 1e-5, "{}: triangle {i}: {shortcut} against {n}", s.name);
                        flat += 1;
                    }
                    None => smooth += 1,
                }
            }
        }
        // Both kinds were met: the check is not vacuous.
        assert!(flat > 100 && smooth > 100, "{flat} flat, {smooth} smooth");
    }
}
