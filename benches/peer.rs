//! raylab's renderer against its peers, side by side in one run: `cargo bench --bench peer`.
//!
//! **Seed 003** (`../shared/peers/seed003_render.py`):
//! The script renders seed 003's 512x256 facing-ratio scene with numpy and prints the median of its
//! in-process render times and its covered pixels; this bench runs it (`facing`, 3 renders, and the
//! vectorised `facing-einsum`, 21 renders), then times raylab's in-process render of the same scene the
//! same way, and prints both, the ratios, and whether the covered pixels agree. Without python3 and
//! numpy it says it skipped.

// A test or benchmark fails by panicking: unwrap and expect are how it says so.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::process::Command;

use raylab::platform::Stopwatch;
use raylab::render::{Prepared, loading::assets::Embedded, render};
use raylab::scene::{Problem, Scene};

#[path = "peer/any_hit.rs"]
mod any_hit;
#[path = "peer/embree.rs"]
mod embree;
#[path = "peer/replay.rs"]
mod replay;

/// One peer run: (median ms, covered pixels).
fn peer(script: &str, variant: &str, repeats: u32) -> Result<(f64, usize), String> {
    let output = Command::new("python3")
        .args([script, variant, &repeats.to_string()])
        .output()
        .map_err(|e| format!("cannot run python3: {e}"))?;
    embree::median_and_coverage(&output)
}

/// raylab's median in-process render time over `repeats` renders, and its covered pixels.
fn raylab(repeats: u32) -> (f64, usize) {
    let text = include_str!("../assets/scenes/seed003-facing.ron");
    let Problem::Render(scene) = Scene::from_ron(text, "seed003-facing.ron")
        .expect("the shipped scene parses")
        .problem
    else {
        panic!("seed003-facing.ron is a render scene");
    };
    let prepared = Prepared::new(&scene, &Embedded).expect("the shipped scene prepares");
    let covered = render(&prepared).0.covered_pixels(); // also warms the thread pool
    let ms = median_ms(repeats as usize, || {
        std::hint::black_box(render(&prepared));
    });
    (ms, covered)
}

/// The median of some numbers (the upper one of an even count).
fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

/// The median wall-clock milliseconds of `runs` calls of `once`.
fn median_ms(runs: usize, mut once: impl FnMut()) -> f64 {
    median(
        (0..runs)
            .map(|_| {
                let clock = Stopwatch::start();
                once();
                clock.seconds() * 1e3
            })
            .collect(),
    )
}

fn main() {
    seed_003();
    embree::compare();
}

fn seed_003() {
    let script = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../shared/peers/seed003_render.py"
    );
    if !std::path::Path::new(script).exists() {
        println!("peer bench skipped: {script} is not there");
        return;
    }
    println!("seed 003's facing-ratio scene, 512x256, median in-process render time");
    for (variant, repeats) in [("facing", 3), ("facing-einsum", 21)] {
        let (peer_ms, peer_pixels) = match peer(script, variant, repeats) {
            Ok(result) => result,
            Err(why) => {
                println!("peer bench skipped ({variant}): {why} (it needs python3 and numpy)");
                return;
            }
        };
        let (ours_ms, our_pixels) = raylab(21);
        println!(
            "{variant:>14}: peer {peer_ms:9.2} ms   raylab {ours_ms:6.3} ms   raylab is {:7.0}x faster   \
             covered pixels: peer {peer_pixels}, raylab {our_pixels}{}",
            peer_ms / ours_ms,
            if peer_pixels == our_pixels {
                " (equal)"
            } else {
                " (DIFFERENT)"
            }
        );
    }
}
