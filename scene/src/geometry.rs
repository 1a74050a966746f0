//! Procedural geometry for the built-in scenes, and normal generation for meshes without.

use glam::{Vec2, Vec3};
use lightbench_compiler::abi::Vertex;

fn v(p: Vec3, n: Vec3, uv: Vec2, t: Vec3) -> Vertex {
    Vertex {
        position: p.to_array(),
        normal: n.to_array(),
        uv: uv.to_array(),
        tangent: [t.x, t.y, t.z, 1.0],
        uv1: uv.to_array(),
    }
}

/// A quad centred at `c` spanning `u` and `w` (half extents), facing `u × w`.
pub fn quad(c: Vec3, u: Vec3, w: Vec3, verts: &mut Vec<Vertex>, idx: &mut Vec<u32>) {
    let n = u.cross(w).normalize();
    let t = u.normalize();
    let base = verts.len() as u32;
    for (du, dw, uv) in [
        (-1.0, -1.0, Vec2::new(0.0, 1.0)),
        (1.0, -1.0, Vec2::new(1.0, 1.0)),
        (1.0, 1.0, Vec2::new(1.0, 0.0)),
        (-1.0, 1.0, Vec2::new(0.0, 0.0)),
    ] {
        verts.push(v(c + u * du + w * dw, n, uv, t));
    }
    idx.extend_from_slice(&[base, base + 1, base + 2, base, base + 2, base + 3]);
}

/// An axis-aligned box centred at the origin with half extents `h`, faces pointing out.
pub fn cuboid(h: Vec3) -> (Vec<Vertex>, Vec<u32>) {
    let (mut vs, mut is) = (vec![], vec![]);
    let (x, y, z) = (Vec3::X * h.x, Vec3::Y * h.y, Vec3::Z * h.z);
    quad(x, -z, y, &mut vs, &mut is);
    quad(-x, z, y, &mut vs, &mut is);
    quad(y, x, -z, &mut vs, &mut is);
    quad(-y, x, z, &mut vs, &mut is);
    quad(z, x, y, &mut vs, &mut is);
    quad(-z, -x, y, &mut vs, &mut is);
    (vs, is)
}

/// A UV sphere of radius `r`.
pub fn sphere(r: f32, rings: u32, segments: u32) -> (Vec<Vertex>, Vec<u32>) {
    let (mut vs, mut is) = (vec![], vec![]);
    for i in 0..=rings {
        let th = std::f32::consts::PI * i as f32 / rings as f32;
        for j in 0..=segments {
            let ph = std::f32::consts::TAU * j as f32 / segments as f32;
            let n = Vec3::new(th.sin() * ph.cos(), th.cos(), -th.sin() * ph.sin());
            let t = Vec3::new(-ph.sin(), 0.0, -ph.cos());
            vs.push(v(n * r, n, Vec2::new(j as f32 / segments as f32, i as f32 / rings as f32), t));
        }
    }
    let w = segments + 1;
    for i in 0..rings {
        for j in 0..segments {
            let a = i * w + j;
            is.extend_from_slice(&[a, a + w, a + 1, a + 1, a + w, a + w + 1]);
        }
    }
    (vs, is)
}

/// A capped cylinder along +Y from 0 to `height`.
pub fn cylinder(r: f32, height: f32, segments: u32) -> (Vec<Vertex>, Vec<u32>) {
    let (mut vs, mut is) = (vec![], vec![]);
    for j in 0..=segments {
        let ph = std::f32::consts::TAU * j as f32 / segments as f32;
        let n = Vec3::new(ph.cos(), 0.0, -ph.sin());
        let t = Vec3::new(-ph.sin(), 0.0, -ph.cos());
        let u = j as f32 / segments as f32;
        vs.push(v(n * r, n, Vec2::new(u, 1.0), t));
        vs.push(v(n * r + Vec3::Y * height, n, Vec2::new(u, 0.0), t));
    }
    for j in 0..segments {
        let a = 2 * j;
        is.extend_from_slice(&[a, a + 2, a + 1, a + 1, a + 2, a + 3]);
    }
    for (y, n) in [(height, Vec3::Y), (0.0, Vec3::NEG_Y)] {
        let c = vs.len() as u32;
        vs.push(v(Vec3::Y * y, n, Vec2::splat(0.5), Vec3::X));
        for j in 0..=segments {
            let ph = std::f32::consts::TAU * j as f32 / segments as f32;
            vs.push(v(
                Vec3::new(ph.cos() * r, y, -ph.sin() * r),
                n,
                Vec2::new(ph.cos() * 0.5 + 0.5, ph.sin() * 0.5 + 0.5),
                Vec3::X,
            ));
        }
        for j in 0..segments {
            if n.y > 0.0 {
                is.extend_from_slice(&[c, c + 1 + j, c + 2 + j]);
            } else {
                is.extend_from_slice(&[c, c + 2 + j, c + 1 + j]);
            }
        }
    }
    (vs, is)
}

/// Area-weighted smooth normals for meshes that come without (glTF makes them optional).
pub fn compute_normals(vertices: &mut [Vertex], indices: &[u32]) {
    let mut acc = vec![Vec3::ZERO; vertices.len()];
    for t in indices.chunks_exact(3) {
        let (a, b, c) = (t[0] as usize, t[1] as usize, t[2] as usize);
        if a >= vertices.len() || b >= vertices.len() || c >= vertices.len() {
            continue;
        }
        let (pa, pb, pc) = (
            Vec3::from(vertices[a].position),
            Vec3::from(vertices[b].position),
            Vec3::from(vertices[c].position),
        );
        let n = (pb - pa).cross(pc - pa);
        for i in [a, b, c] {
            acc[i] += n;
        }
    }
    for (v, n) in vertices.iter_mut().zip(acc) {
        v.normal = n.try_normalize().unwrap_or(Vec3::Y).to_array();
    }
}

/// Every index within `vertices` (a loaded model's and a host's meshes are checked alike).
pub fn check_indices(indices: &[u32], vertices: usize) -> Result<(), String> {
    match indices.iter().find(|&&i| i as usize >= vertices) {
        Some(bad) => Err(format!("index {bad} is out of range ({vertices} vertices)")),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cuboid_faces_point_outwards_and_wind_counter_clockwise() {
        let (vs, is) = cuboid(Vec3::new(1.0, 2.0, 3.0));
        assert_eq!((vs.len(), is.len()), (24, 36));
        for t in is.chunks_exact(3) {
            let p: Vec<Vec3> = t.iter().map(|&i| Vec3::from(vs[i as usize].position)).collect();
            let geo_n = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
            let centroid = (p[0] + p[1] + p[2]) / 3.0;
            assert!(geo_n.dot(centroid) > 0.0, "face points inwards");
            assert!(geo_n.dot(Vec3::from(vs[t[0] as usize].normal)) > 0.99);
        }
    }

    #[test]
    fn generated_normals_are_unit_length() {
        let (mut vs, is) = sphere(1.0, 8, 12);
        for v in vs.iter_mut() {
            v.normal = [0.0; 3];
        }
        compute_normals(&mut vs, &is);
        for v in &vs {
            let n = Vec3::from(v.normal);
            assert!((n.length() - 1.0).abs() < 1e-4);
        }
    }
}
