//! The peer bench's camera any-hit rows, kept in one place for the bench (`embree.rs`) and the
//! profiling loop (`examples/any_hit_loop.rs`): their meshes, seen as the bench sees them, and
//! how raylab casts a band of their rays.

use raylab::math::linalg::V3;
use raylab::render::bvh::Bvh;
use raylab::render::generate::{grid_box, irregular_sphere, mesh_scene};
use raylab::render::{Prepared, Ray};
use raylab::scene::render::Camera;

/// Rows of rays in a packet tile, and rays in a tile's row.
pub const TILE: usize = 4;

/// The irregular sphere of `level` seen from outside on a 400x400 image.
pub fn sphere(level: u32) -> (Prepared, Vec<[V3<f64>; 3]>) {
    let triangles = irregular_sphere(level, 12);
    let camera = Camera::Pinhole {
        position: [0.3, -3.6, 0.5],
        target: [0.0, 0.0, 0.0],
        fov_y: 40.0,
    };
    (mesh_scene(&triangles, camera, 400, 400), triangles)
}

/// The 41 200-triangle box seen from inside, every camera ray along an edge or through a vertex.
pub fn inside_box() -> (Prepared, Vec<[V3<f64>; 3]>) {
    inside_grid_box(100)
}

/// The 363 600-triangle box seen from inside (300 cells a side, a 601x601 image), every camera ray
/// along an edge or through a vertex: the box's rays at a finer tessellation.
pub fn fine_inside_box() -> (Prepared, Vec<[V3<f64>; 3]>) {
    inside_grid_box(300)
}

fn inside_grid_box(cells: usize) -> (Prepared, Vec<[V3<f64>; 3]>) {
    let (camera, side, triangles) = grid_box(cells);
    (mesh_scene(&triangles, camera, side, side), triangles)
}

/// How raylab casts a band's rays.
#[derive(Clone, Copy, PartialEq)]
pub enum Casting {
    /// `Bvh::occluded`, one ray at a time.
    OneRay,
    /// `Bvh::occluded`, one ray at a time, each walk from the top: this thread's last blocker
    /// forgotten before each ray (`Bvh::forget_last_blocker`).
    OneRayAlone,
    /// `Bvh::occluded_packet`, tiles of 4x4 neighbouring rays (the rest one at a time).
    Packets,
}

/// Casts a band of up to [`TILE`] rows of rays through `bvh`'s any-hit queries: in packets with
/// a full band, `Bvh::occluded_packet` on each 4x4 tile and `Bvh::occluded` on the columns left
/// over, else `Bvh::occluded` one ray at a time. Returns the occluded rays, and adds the box and
/// triangle tests to `counts`.
pub fn occluded_band(
    bvh: &Bvh,
    prepared: &Prepared,
    band: &[Vec<Ray>],
    casting: Casting,
    (boxes, triangles): (&mut u64, &mut u64),
) -> usize {
    let tiles = match casting == Casting::Packets && band.len() == TILE {
        true => prepared.width / TILE,
        false => 0,
    };
    let mut occluded = 0;
    for tile in 0..tiles {
        let rays: [Ray; TILE * TILE] =
            std::array::from_fn(|k| band[k / TILE][tile * TILE + k % TILE]);
        let limits = [f64::INFINITY; TILE * TILE];
        let found = bvh.occluded_packet(prepared.simd, &rays, limits, boxes, triangles);
        occluded += found.count_ones() as usize;
    }
    for row in band {
        for ray in &row[tiles * TILE..] {
            if casting == Casting::OneRayAlone {
                Bvh::forget_last_blocker();
            }
            let limits = (0.0, f64::INFINITY);
            occluded += usize::from(bvh.occluded(prepared.simd, ray, limits, boxes, triangles));
        }
    }
    occluded
}
