//! A profiling loop for the hierarchy's build (issue 25): the peer bench's irregular sphere at
//! `LEVEL` (8: 1 310 720 triangles, the bench's build row), built `REPS` times in a pool of
//! `THREADS` threads (default 2, as the bench). It prints each build's time and the hierarchy's
//! memory; `CHECK=1` also prints a hash of the whole hierarchy, so that two builds of the code can
//! be shown to make the same one. It compares raylab with itself only (two builds alternating, or
//! under `perf record`); the figures against Embree come from the peer bench's build row.
//!
//! ```text
//! LEVEL=8 REPS=3 THREADS=2 [CHECK=1] cargo run --release --example build_loop
//! ```

use raylab::render::bvh::Bvh;
use raylab::render::generate::irregular_sphere;
use raylab::render::objects::PreparedTriangle;

fn main() {
    let var = |name: &str, default: &str| std::env::var(name).unwrap_or(default.into());
    let level: u32 = var("LEVEL", "8").parse().unwrap_or(8);
    let repeats: usize = var("REPS", "3").parse().unwrap_or(3).max(1);
    let threads: usize = var("THREADS", "2").parse().unwrap_or(2).max(1);
    let triangles: Vec<PreparedTriangle> = irregular_sphere(level, 12)
        .iter()
        .map(|t| PreparedTriangle::new(*t))
        .collect();
    let pool = match rayon::ThreadPoolBuilder::new().num_threads(threads).build() {
        Ok(pool) => pool,
        Err(why) => return eprintln!("cannot make a pool of {threads} threads: {why}"),
    };
    for _ in 0..repeats {
        let start = std::time::Instant::now();
        let bvh = pool.install(|| Bvh::build(&triangles));
        let ms = start.elapsed().as_secs_f64() * 1e3;
        if std::env::var("CHECK").is_ok() {
            use std::hash::{Hash, Hasher};
            let mut hasher = std::collections::hash_map::DefaultHasher::new();
            format!("{bvh:?}").hash(&mut hasher);
            println!("hierarchy's hash {:016x}", hasher.finish());
        }
        println!(
            "{} triangles, {threads} threads: build {ms:.1} ms, {:.1} MiB ({:.0} bytes a triangle)",
            triangles.len(),
            bvh.held_bytes() as f64 / (1024.0 * 1024.0),
            bvh.held_bytes() as f64 / triangles.len() as f64,
        );
    }
}
