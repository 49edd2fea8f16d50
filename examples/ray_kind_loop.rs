//! A profiling loop for the peer bench's ray-kind rows (issue 25): the rays raylab's tracer casts
//! in a shipped scene with every effect it declares, one kind of them cast again as the bench
//! casts them (`ray_log::cast_run_again`, in the render's order), on one thread. It prints the box
//! and primitive (triangle and parallelogram) tests a ray and the minimum and median time of the repeats. It compares raylab
//! with itself only (two builds alternating, or under `perf record`); the ratios against Embree
//! come from the peer bench.
//!
//! ```text
//! SCENE=render-cornell-box KIND=reflection REPS=20 cargo run --release --example ray_kind_loop
//! ```
//!
//! `KIND` is one of primary, samples, shadow, reflection, refraction, occlusion; `THREADS=2` also
//! times the casts in a pool of two threads, in chunks as the bench casts them. `DUMP=DIR` also
//! writes the scene's world-space triangles to `DIR/scene.obj` and the kind's rays to
//! `DIR/KIND.f32`, as the bench hands them to Embree (`benches/peer/instructions.sh` counts both
//! sides' instructions on them). `AVX512=0` takes the packets' AVX2 box test on a processor with
//! AVX-512, to time the two in one build.

use std::time::Instant;

use raylab::render::generate::to_obj;
use raylab::render::loading::assets::Embedded;
use raylab::render::ray_kinds::RayKind;
use raylab::render::ray_log::{LoggedRay, as_f32s, cast_run_again, rays_cast};
use raylab::render::{Prepared, Stats, world_triangles};
use raylab::scene::{Problem, Scene};

/// The bench's ray-kind casting, shared with it.
#[path = "../benches/peer/replay.rs"]
mod replay;

fn main() {
    let var = |name: &str, default: &str| std::env::var(name).unwrap_or(default.into());
    let scene = var("SCENE", "render-cornell-box");
    let kind_name = var("KIND", "reflection");
    let repeats: usize = var("REPS", "20").parse().unwrap_or(20).max(1);
    let path = format!("{}/assets/scenes/{scene}.ron", env!("CARGO_MANIFEST_DIR"));
    let problem = match Scene::load(std::path::Path::new(&path)) {
        Ok(scene) => scene.problem,
        Err(why) => return eprintln!("cannot load {path}: {why}"),
    };
    let Problem::Render(render_scene) = problem else {
        return eprintln!("{path} is not a render scene");
    };
    let mut prepared = match Prepared::new(&render_scene, &Embedded) {
        Ok(prepared) => prepared,
        Err(why) => return eprintln!("cannot prepare {path}: {why}"),
    };
    if var("AVX512", "1") == "0" {
        prepared.simd = prepared.simd.map(|avx2| avx2.without_avx512());
    }
    let avx512 = prepared.simd.and_then(|avx2| avx2.avx512()).is_some();
    eprintln!(
        "packet box test: {}",
        if avx512 { "AVX-512" } else { "AVX2" }
    );
    let Some(kind) = RayKind::ALL.into_iter().find(|k| k.name() == kind_name) else {
        let names: Vec<&str> = RayKind::ALL.iter().map(|k| k.name()).collect();
        return eprintln!("KIND is one of {}", names.join(", "));
    };
    let logged: Vec<LoggedRay> = rays_cast(&prepared)
        .into_iter()
        .filter(|r| r.kind == kind)
        .collect();
    // Each chunk in the render's order, as the bench orders them (for two threads).
    let (rays, chunk) = replay::in_chunks(&logged, 2);
    // Chunk by chunk, as the bench's threads cast them. (Cast all at once, a kind's rays were
    // sorted by bounce again on every cast: chunks in casting order are not sorted as a whole.)
    let one_thread = |stats: &mut Stats| -> usize {
        rays.chunks(chunk)
            .map(|chunk| cast_run_again(&prepared, chunk, stats))
            .sum()
    };
    if let Ok(dir) = std::env::var("DUMP") {
        let dir = std::path::Path::new(&dir);
        let obj = to_obj(&world_triangles(&prepared));
        let written = std::fs::write(dir.join("scene.obj"), obj)
            .and_then(|()| std::fs::write(dir.join(format!("{kind_name}.f32")), as_f32s(&logged)));
        if let Err(why) = written {
            return eprintln!("cannot write to {}: {why}", dir.display());
        }
    }
    let mut stats = Stats::default();
    let met = one_thread(&mut stats);
    let count = rays.len().max(1) as f64;
    println!(
        "{scene}, {kind_name}: {} rays, {met} met something, {:.2} box tests and {:.3} primitive tests a ray",
        rays.len(),
        (stats.box_tests + stats.secondary.box_tests) as f64 / count,
        (stats.triangle_tests + stats.parallelogram_tests + stats.secondary.tests) as f64 / count,
    );
    let times: Vec<f64> = (0..repeats)
        .map(|_| {
            let clock = Instant::now();
            std::hint::black_box(one_thread(&mut Stats::default()));
            clock.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    let (least, median) = spread(times);
    println!("one thread: ms min {least:.3} median {median:.3}");
    if std::env::var("THREADS").is_ok() {
        two_threads(&prepared, (&rays, chunk), repeats);
    }
}

/// (minimum, median) of `times`.
fn spread(mut times: Vec<f64>) -> (f64, f64) {
    times.sort_by(f64::total_cmp);
    (times[0], times[times.len() / 2])
}

/// The casts in a pool of two threads (unpinned), in chunks as the peer bench casts them.
fn two_threads(prepared: &Prepared, (rays, chunk): (&[LoggedRay], usize), repeats: usize) {
    let Ok(pool) = rayon::ThreadPoolBuilder::new().num_threads(2).build() else {
        return eprintln!("no pool of two threads");
    };
    let count = || replay::cast_chunks(prepared, rays, chunk);
    let times = pool.install(|| {
        count();
        (0..repeats)
            .map(|_| {
                let clock = Instant::now();
                std::hint::black_box(count());
                clock.elapsed().as_secs_f64() * 1e3
            })
            .collect()
    });
    let (least, median) = spread(times);
    println!("two threads: ms min {least:.3} median {median:.3}");
}
