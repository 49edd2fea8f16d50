//! A profiling loop for the any-hit walk (issue 25): the peer bench's camera rays over its two
//! meshes (the 41 200-triangle box seen from inside, every ray along an edge or through a vertex,
//! and the 81 920-triangle irregular sphere), cast through `Bvh::occluded` one ray at a time or
//! `Bvh::occluded_packet` in 4x4 tiles, on one thread. It prints the box and triangle tests a ray
//! and the minimum and median time of the repeats. It compares raylab with itself only (two
//! builds alternating, or under `perf record` or `valgrind --tool=callgrind`); the ratios against
//! Embree come from the peer bench.
//!
//! ```text
//! MESH=box|sphere TEST=one|packets REPS=20 cargo run --release --example any_hit_loop
//! ```
//!
//! `THREADS=2` also times the one-ray casts in a pool of two threads, in bands of four rows as the
//! peer bench casts them; `OBJ=path` writes the mesh there (for the peer scripts).

use std::time::Instant;

use raylab::render::generate::{grid_box, irregular_sphere, mesh_scene, to_obj};
use raylab::render::objects::Geometry;
use raylab::render::{Prepared, Ray, bvh::Bvh};
use raylab::scene::render::Camera;

/// The scene the peer bench casts for `mesh`, and its triangles.
fn scene(mesh: &str) -> (Prepared, Vec<[[f64; 3]; 3]>) {
    if mesh == "box" {
        let (camera, side, triangles) = grid_box(100);
        (mesh_scene(&triangles, camera, side, side), triangles)
    } else {
        let triangles = irregular_sphere(6, 12);
        let camera = Camera::Pinhole {
            position: [0.3, -3.6, 0.5],
            target: [0.0, 0.0, 0.0],
            fov_y: 40.0,
        };
        (mesh_scene(&triangles, camera, 400, 400), triangles)
    }
}

/// Casts every ray (rows of `rays`), in 4x4 tiles with `packets`; returns the occluded rays.
fn cast(
    bvh: &Bvh,
    prepared: &Prepared,
    rays: &[Vec<Ray>],
    packets: bool,
    (boxes, triangles): (&mut u64, &mut u64),
) -> usize {
    let one = |ray: &Ray, boxes: &mut u64, triangles: &mut u64| {
        usize::from(bvh.occluded(prepared.simd, ray, (0.0, f64::INFINITY), boxes, triangles))
    };
    let mut occluded = 0;
    for band in rays.chunks(4) {
        let tiles = match packets && band.len() == 4 {
            true => band[0].len() / 4,
            false => 0,
        };
        for tile in 0..tiles {
            let packet: [Ray; 16] = std::array::from_fn(|k| band[k / 4][tile * 4 + k % 4]);
            let limits = [f64::INFINITY; 16];
            let found = bvh.occluded_packet(prepared.simd, &packet, limits, boxes, triangles);
            occluded += found.count_ones() as usize;
        }
        for row in band {
            for ray in &row[tiles * 4..] {
                occluded += one(ray, boxes, triangles);
            }
        }
    }
    occluded
}

/// (minimum, median) of `times`.
fn spread(mut times: Vec<f64>) -> (f64, f64) {
    times.sort_by(f64::total_cmp);
    (times[0], times[times.len() / 2])
}

fn main() {
    let var = |name: &str, default: &str| std::env::var(name).unwrap_or(default.into());
    let mesh = var("MESH", "box");
    let packets = var("TEST", "one") == "packets";
    let repeats: usize = var("REPS", "20").parse().unwrap_or(20).max(1);
    let (prepared, triangles) = scene(&mesh);
    if let Ok(path) = std::env::var("OBJ")
        && let Err(why) = std::fs::write(&path, to_obj(&triangles))
    {
        eprintln!("cannot write {path}: {why}");
    }
    let Some(Geometry::Triangles { bvh: Some(bvh), .. }) =
        prepared.objects.first().map(|o| &o.geometry)
    else {
        eprintln!("the scene has no mesh hierarchy");
        return;
    };
    let (width, height) = (prepared.width, prepared.height);
    let rays: Vec<Vec<Ray>> = (0..height)
        .map(|row| (0..width).map(|c| prepared.ray(row, c)).collect())
        .collect();
    let (mut boxes, mut tested) = (0u64, 0u64);
    let occluded = cast(bvh, &prepared, &rays, packets, (&mut boxes, &mut tested));
    let count = (width * height) as f64;
    println!(
        "{mesh}, {}: {} rays, {occluded} occluded, {:.2} box tests and {:.3} triangle tests a ray",
        if packets {
            "4x4 packets"
        } else {
            "one ray at a time"
        },
        width * height,
        boxes as f64 / count,
        tested as f64 / count
    );
    let times = (0..repeats)
        .map(|_| {
            let clock = Instant::now();
            std::hint::black_box(cast(bvh, &prepared, &rays, packets, (&mut 0, &mut 0)));
            clock.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    let (least, median) = spread(times);
    println!("one thread: ms min {least:.3} median {median:.3}");
    if std::env::var("THREADS").is_ok() {
        two_threads(bvh, &prepared, &rays, repeats);
    }
}

/// The one-ray casts in a pool of two threads, bands of four rows in parallel.
fn two_threads(bvh: &Bvh, prepared: &Prepared, rays: &[Vec<Ray>], repeats: usize) {
    use rayon::prelude::*;
    let Ok(pool) = rayon::ThreadPoolBuilder::new().num_threads(2).build() else {
        eprintln!("no pool of two threads");
        return;
    };
    let bands: Vec<&[Vec<Ray>]> = rays.chunks(4).collect();
    let band = |band: &&[Vec<Ray>]| cast(bvh, prepared, band, false, (&mut 0, &mut 0));
    let times = pool.install(|| {
        (0..repeats)
            .map(|_| {
                let clock = Instant::now();
                std::hint::black_box(bands.par_iter().map(band).sum::<usize>());
                clock.elapsed().as_secs_f64() * 1e3
            })
            .collect()
    });
    let (least, median) = spread(times);
    println!("two threads, one ray at a time: ms min {least:.3} median {median:.3}");
}
