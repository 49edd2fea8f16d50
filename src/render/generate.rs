//! Generated closed meshes for the crack tests and the peer bench: a box seen from inside whose every
//! camera ray runs exactly along an edge or through a vertex, and irregular spheres of any size.

use std::collections::HashMap;
use std::fmt::Write;

use glam::{DAffine3, DMat3};
use rand::{Rng, SeedableRng};

use super::bvh::Bvh;
use super::objects::{Geometry, PreparedObject, PreparedTriangle};
use super::{Camera, Effect, Prepared, camera_ray};
use crate::math::linalg::V3;

/// A closed box around a pinhole camera at the origin looking along +y, seen on a square image of
/// `2·cells + 1` pixels a side (returned with the camera and the triangles).
///
/// The front face (y = 1) is a grid whose vertices are the pixels' ray directions themselves: the ray
/// through pixel (column, row) reaches that vertex at t = 1 exactly. Even columns and rows are the
/// cells' corners, odd ones their centres, and each cell is a fan of four triangles around its centre;
/// so a pixel with both indices even or both odd goes through a vertex, and one with one index even
/// runs along an edge. Four sides and a back face (a fan) close the box.
pub fn grid_box(cells: usize) -> (Camera, usize, Vec<[V3<f64>; 3]>) {
    let cells = cells.max(1);
    let side = 2 * cells + 1;
    let camera = Camera::Pinhole {
        position: [0.0; 3],
        target: [0.0, 1.0, 0.0],
        fov_y: 60.0,
    };
    let grid = |column: usize, row: usize| camera_ray(&camera, side, side, row, column).dir;
    let mut triangles = Vec::with_capacity(4 * cells * cells + 12 * cells);
    for a in 0..cells {
        for b in 0..cells {
            let (c, r) = (2 * a, 2 * b);
            let centre = grid(c + 1, r + 1);
            let ring = [
                grid(c, r),
                grid(c + 2, r),
                grid(c + 2, r + 2),
                grid(c, r + 2),
            ];
            for k in 0..4 {
                triangles.push([centre, ring[k], ring[(k + 1) % 4]]);
            }
        }
    }
    // The front face's boundary, corner vertices only, once around; each joined to its copy at y = −1.
    let mut boundary = Vec::new();
    let even = |i: usize| 2 * i;
    for i in 0..cells {
        boundary.push(grid(even(i), 0));
    }
    for i in 0..cells {
        boundary.push(grid(side - 1, even(i)));
    }
    for i in (1..=cells).rev() {
        boundary.push(grid(even(i), side - 1));
    }
    for i in (1..=cells).rev() {
        boundary.push(grid(0, even(i)));
    }
    let back = |p: V3<f64>| [p[0], -1.0, p[2]];
    let back_centre = [0.0, -1.0, 0.0];
    for k in 0..boundary.len() {
        let (p, q) = (boundary[k], boundary[(k + 1) % boundary.len()]);
        triangles.push([p, back(p), q]);
        triangles.push([q, back(p), back(q)]);
        triangles.push([back_centre, back(q), back(p)]);
    }
    (camera, side, triangles)
}

/// An icosahedron subdivided `level` times (20·4^level triangles), each vertex pushed to a radius
/// between 0.9 and 1.1 and moved sideways a little, seeded: closed, irregular, no two edges aligned.
pub fn irregular_sphere(level: u32, seed: u64) -> Vec<[V3<f64>; 3]> {
    let t = (1.0 + 5f64.sqrt()) / 2.0;
    let mut vertices: Vec<V3<f64>> = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ]
    .map(normalized)
    .to_vec();
    let mut faces: Vec<[usize; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..level {
        let mut middles: HashMap<(usize, usize), usize> = HashMap::new();
        let mut middle = |a: usize, b: usize, vertices: &mut Vec<V3<f64>>| {
            *middles.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let (p, q) = (vertices[a], vertices[b]);
                vertices.push(normalized(std::array::from_fn(|k| (p[k] + q[k]) / 2.0)));
                vertices.len() - 1
            })
        };
        let mut next = Vec::with_capacity(faces.len() * 4);
        for [a, b, c] in faces {
            let (ab, bc, ca) = (
                middle(a, b, &mut vertices),
                middle(b, c, &mut vertices),
                middle(c, a, &mut vertices),
            );
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        faces = next;
    }
    // Sideways moves stay well below the edge length (about 1.1 / 2^level) so no triangle folds over.
    let edge = 1.1 / (1u64 << level) as f64;
    let mut random = rand_pcg::Pcg64::seed_from_u64(seed);
    for v in &mut vertices {
        let nudge: V3<f64> = std::array::from_fn(|_| random.random_range(-0.15..0.15) * edge);
        let radius = random.random_range(0.9..1.1);
        let moved = normalized(std::array::from_fn(|k| v[k] + nudge[k]));
        *v = moved.map(|c| c * radius);
    }
    faces.iter().map(|f| f.map(|i| vertices[i])).collect()
}

fn normalized(v: V3<f64>) -> V3<f64> {
    let length = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    v.map(|c| c / length)
}

/// An OBJ grid of `n` × `n` unit squares (2n² triangles, as quads) in the plane z = 5, from (0, 0)
/// to (n, n): a large mesh written in moments, for load and memory tests.
pub fn grid_obj(n: usize) -> String {
    let mut text = String::new();
    for row in 0..=n {
        for column in 0..=n {
            let _ = writeln!(text, "v {column} {row} 5");
        }
    }
    let at = |row: usize, column: usize| row * (n + 1) + column + 1;
    for row in 0..n {
        for column in 0..n {
            let (a, b) = (at(row, column), at(row, column + 1));
            let (c, d) = (at(row + 1, column + 1), at(row + 1, column));
            let _ = writeln!(text, "f {a} {b} {c} {d}");
        }
    }
    text
}

/// The triangles as an OBJ file, vertices shared where their coordinates are equal (printed with
/// Rust's shortest round-trip formatting, so they read back exactly).
pub fn to_obj(triangles: &[[V3<f64>; 3]]) -> String {
    let mut index: HashMap<[u64; 3], usize> = HashMap::new();
    let mut vertices = String::new();
    let mut faces = String::new();
    for triangle in triangles {
        let mut ids = [0; 3];
        for (id, v) in ids.iter_mut().zip(triangle) {
            let next = index.len() + 1;
            *id = *index.entry(v.map(f64::to_bits)).or_insert_with(|| {
                let _ = writeln!(vertices, "v {:?} {:?} {:?}", v[0], v[1], v[2]);
                next
            });
        }
        let _ = writeln!(faces, "f {} {} {}", ids[0], ids[1], ids[2]);
    }
    vertices + &faces
}

/// A scene of one untransformed mesh seen by `camera` on a `width`×`height` image, coverage only,
/// with the renderer's default method (its BVH built here).
pub fn mesh_scene(
    triangles: &[[V3<f64>; 3]],
    camera: Camera,
    width: usize,
    height: usize,
) -> Prepared {
    let triangles: Vec<PreparedTriangle> = triangles
        .iter()
        .map(|t| PreparedTriangle::new(*t))
        .collect();
    let bvh = Some(std::sync::Arc::new(Bvh::build(&triangles)));
    let triangles = triangles.into();
    Prepared {
        width,
        height,
        camera,
        method: None,
        effects: vec![Effect::Coverage],
        bug: None,
        objects: std::sync::Arc::new([PreparedObject {
            geometry: Geometry::Triangles { triangles, bvh },
            object_from_world: None,
            world_from_object: DAffine3::IDENTITY,
            normal_to_world: DMat3::IDENTITY,
            color: [0.8; 3],
            texture: None,
            is_mesh: true,
        }]),
        lighting: Default::default(),
        simd: crate::render::kernels::Avx2::detect(),
        index: Default::default(),
    }
}

/// The hierarchy of the first object of `prepared` (a [`mesh_scene`]'s mesh), if it has one.
pub fn mesh_hierarchy(prepared: &Prepared) -> Option<&Bvh> {
    match &prepared.objects.first()?.geometry {
        Geometry::Triangles { bvh: Some(bvh), .. } => Some(bvh),
        _ => None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every edge of the generated meshes is shared by exactly two triangles: they are closed.
    #[test]
    fn the_generated_meshes_are_closed() {
        for mesh in [grid_box(5).2, irregular_sphere(2, 1)] {
            let mut edges: HashMap<[[u64; 3]; 2], usize> = HashMap::new();
            for t in &mesh {
                for k in 0..3 {
                    let (p, q) = (t[k].map(f64::to_bits), t[(k + 1) % 3].map(f64::to_bits));
                    *edges.entry([p.min(q), p.max(q)]).or_default() += 1;
                }
            }
            assert!(edges.values().all(|n| *n == 2), "{edges:?}");
        }
        assert_eq!(irregular_sphere(3, 1).len(), 20 * 64);
    }
}
