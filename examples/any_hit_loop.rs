//! A profiling loop for the any-hit walk (issue 25): the peer bench's camera rays over its
//! meshes (the box seen from inside, every ray along an edge or through a vertex, at 41 200
//! triangles or, `MESH=fine-box`, 363 600; and the 81 920-triangle irregular sphere), cast through
//! `Bvh::occluded` one ray at a time or `Bvh::occluded_packet` in 4x4 tiles, on one thread
//! (`TEST=alone`: one ray at a time, each walk from the top, the last blocker forgotten before
//! each ray). It prints the box and triangle tests a ray and the minimum and median time of the
//! repeats. `TEST=render` times the bench's primary row instead: the whole render, nearest hits,
//! in rayon's global pool. It compares raylab with itself only (two builds alternating, or under
//! `perf record` or `valgrind --tool=callgrind`); the ratios against Embree come from the peer
//! bench.
//!
//! ```text
//! MESH=box|fine-box|sphere TEST=one|alone|packets|render REPS=20 cargo run --release --example any_hit_loop
//! ```
//!
//! `THREADS=2` also times the same casts in a pool of two threads, in bands of four rows as the
//! peer bench casts them; `OBJ=path` writes the mesh there (for the peer scripts).

use std::time::Instant;

use raylab::render::generate::{mesh_hierarchy, to_obj};
use raylab::render::{Prepared, Ray, bvh::Bvh};

/// The bench's meshes and its casting, shared with it.
#[path = "../benches/peer/any_hit.rs"]
mod any_hit;
use any_hit::{Casting, TILE, fine_inside_box, inside_box, occluded_band, sphere};

/// Casts every ray (rows of `rays`) in bands of [`TILE`] rows, as the bench does; returns the
/// occluded rays.
fn cast(
    bvh: &Bvh,
    prepared: &Prepared,
    rays: &[Vec<Ray>],
    casting: Casting,
    (boxes, triangles): (&mut u64, &mut u64),
) -> usize {
    rays.chunks(TILE)
        .map(|band| occluded_band(bvh, prepared, band, casting, (&mut *boxes, &mut *triangles)))
        .sum()
}

/// (minimum, median) of `times`.
fn spread(mut times: Vec<f64>) -> (f64, f64) {
    times.sort_by(f64::total_cmp);
    (times[0], times[times.len() / 2])
}

fn main() {
    let var = |name: &str, default: &str| std::env::var(name).unwrap_or(default.into());
    let mesh = var("MESH", "box");
    let (casting, how) = match var("TEST", "one").as_str() {
        "packets" => (Casting::Packets, "4x4 packets"),
        "alone" => (Casting::OneRayAlone, "one ray at a time, no last blocker"),
        _ => (Casting::OneRay, "one ray at a time"),
    };
    let repeats: usize = var("REPS", "20").parse().unwrap_or(20).max(1);
    let (prepared, triangles) = match mesh.as_str() {
        "box" => inside_box(),
        "fine-box" => fine_inside_box(),
        _ => sphere(6),
    };
    if let Ok(path) = std::env::var("OBJ")
        && let Err(why) = std::fs::write(&path, to_obj(&triangles))
    {
        eprintln!("cannot write {path}: {why}");
    }
    if var("TEST", "one") == "render" {
        time_renders(&mesh, &prepared, repeats);
        return;
    }
    let Some(bvh) = mesh_hierarchy(&prepared) else {
        eprintln!("the scene has no mesh hierarchy");
        return;
    };
    let (width, height) = (prepared.width, prepared.height);
    let rays: Vec<Vec<Ray>> = (0..height)
        .map(|row| (0..width).map(|c| prepared.ray(row, c)).collect())
        .collect();
    let (mut boxes, mut tested) = (0u64, 0u64);
    let occluded = cast(bvh, &prepared, &rays, casting, (&mut boxes, &mut tested));
    let count = (width * height) as f64;
    println!(
        "{mesh}, {how}: {} rays, {occluded} occluded, {:.2} box tests and {:.3} triangle tests a ray",
        width * height,
        boxes as f64 / count,
        tested as f64 / count
    );
    let times = (0..repeats)
        .map(|_| {
            let clock = Instant::now();
            std::hint::black_box(cast(bvh, &prepared, &rays, casting, (&mut 0, &mut 0)));
            clock.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    let (least, median) = spread(times);
    println!("one thread: ms min {least:.3} median {median:.3}");
    if std::env::var("THREADS").is_ok() {
        two_threads(bvh, &prepared, &rays, repeats, (casting, how));
    }
}

/// `TEST=render`: the peer bench's primary row, the whole render (nearest hits, coverage), in
/// rayon's global pool (`RAYON_NUM_THREADS=1` for one thread).
fn time_renders(mesh: &str, prepared: &Prepared, repeats: usize) {
    let (image, stats) = raylab::render::render(prepared);
    let covered = image.covered_pixels();
    let rays = stats.rays.max(1) as f64;
    println!(
        "{mesh}, render: {:.2} box tests and {:.3} triangle tests a ray",
        stats.box_tests as f64 / rays,
        stats.triangle_tests as f64 / rays
    );
    let times = (0..repeats)
        .map(|_| {
            let clock = Instant::now();
            std::hint::black_box(raylab::render::render(prepared));
            clock.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    let (least, median) = spread(times);
    println!("{mesh}, render: {covered} pixels covered, ms min {least:.3} median {median:.3}");
}

/// The casts in a pool of two threads, bands of four rows in parallel.
fn two_threads(
    bvh: &Bvh,
    prepared: &Prepared,
    rays: &[Vec<Ray>],
    repeats: usize,
    (casting, how): (Casting, &str),
) {
    use rayon::prelude::*;
    let Ok(pool) = rayon::ThreadPoolBuilder::new().num_threads(2).build() else {
        eprintln!("no pool of two threads");
        return;
    };
    let bands: Vec<&[Vec<Ray>]> = rays.chunks(TILE).collect();
    let band = |band: &&[Vec<Ray>]| occluded_band(bvh, prepared, band, casting, (&mut 0, &mut 0));
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
    println!("two threads, {how}: ms min {least:.3} median {median:.3}");
}
