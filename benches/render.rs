//! What skipping an effect saves: whole-image renders of the same scene with all its effects, with each
//! one turned off, and with coverage only; and what the BVH saves over testing every triangle.
//!
//! Then the Render view's frames while the camera orbits: the full frame and the quick ones.
//!
//! `cargo bench --bench render` (about a minute and a half; renders run in parallel over rows).

// A test or benchmark fails by panicking: unwrap and expect are how it says so.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::time::Duration;

use criterion::{
    BenchmarkGroup, Criterion, SamplingMode, Throughput, criterion_group, criterion_main,
};
use raylab::render::inspect::cost::each_left_out;
use raylab::render::objects::Geometry;
use raylab::render::{Prepared, loading::assets::Embedded, render};
use raylab::scene::render::{Effect, RenderScene};
use raylab::scene::{Problem, Scene};

fn scene(file: &str) -> RenderScene {
    let path = format!("{}/assets/scenes/{file}", env!("CARGO_MANIFEST_DIR"));
    match Scene::load(std::path::Path::new(&path)).unwrap().problem {
        Problem::Render(scene) => scene,
        other => panic!("{file} is not a render scene: {other:?}"),
    }
}

fn names(effects: &[Effect]) -> String {
    effects
        .iter()
        .map(|e| e.name())
        .collect::<Vec<_>>()
        .join("+")
}

fn bench_render(
    group: &mut BenchmarkGroup<'_, criterion::measurement::WallTime>,
    id: &str,
    prepared: &Prepared,
) {
    group.throughput(Throughput::Elements(
        (prepared.width * prepared.height) as u64,
    ));
    group.bench_function(id, |b| b.iter(|| render(prepared).1.hits));
}

/// The effects labelled "all", then each one that `leave_out` picks left out ("without …").
fn all_and_each_left_out(
    effects: &[Effect],
    leave_out: impl Fn(&Effect) -> bool,
) -> Vec<(String, Vec<Effect>)> {
    let mut runs = vec![("all".to_string(), effects.to_vec())];
    for (off, rest) in each_left_out(effects).filter(|(off, _)| leave_out(off)) {
        runs.push((format!("without {}", off.name()), rest));
    }
    runs
}

/// Each scene with all its effects, each one left out, and coverage alone.
fn effects(c: &mut Criterion) {
    for file in [
        "render-transformed.ron",
        "render-textured-quad.ron",
        "seed003-barycentric.ron",
    ] {
        let scene = scene(file);
        let prepared = Prepared::new(&scene, &Embedded).unwrap();
        let mut subsets = all_and_each_left_out(&scene.effects, |_| true);
        subsets.push(("coverage only".into(), vec![Effect::Coverage]));
        let mut group = c.benchmark_group(format!("effects/{}", file.trim_end_matches(".ron")));
        let mut seen = Vec::new();
        for (label, effects) in subsets {
            // seed003-barycentric without barycentric-color is coverage only: time it once.
            if seen.contains(&effects) {
                continue;
            }
            let mut prepared = prepared.clone();
            prepared.effects = effects.clone();
            bench_render(
                &mut group,
                &format!("{label} ({})", names(&effects)),
                &prepared,
            );
            seen.push(effects);
        }
        group.finish();
    }
}

/// The meshes through their BVH and with every triangle tested (a smaller image: brute force is
/// slow), with coverage only, so the intersection is all that is timed.
fn bvh(c: &mut Criterion) {
    for (file, width, height) in [
        ("render-mesh.ron", 81, 81),
        ("render-transformed.ron", 120, 80),
    ] {
        let mut with_bvh = Prepared::new(&scene(file), &Embedded).unwrap();
        (with_bvh.width, with_bvh.height) = (width, height);
        with_bvh.effects = vec![Effect::Coverage];
        let mut brute = with_bvh.clone();
        for object in brute.objects_mut() {
            if let Geometry::Triangles { bvh, .. } = &mut object.geometry {
                *bvh = None;
            }
        }
        assert_eq!(render(&with_bvh).0, render(&brute).0, "{file}");
        let mut group = c.benchmark_group(format!("bvh/{}", file.trim_end_matches(".ron")));
        // A brute-force render takes a good part of a second: one render a sample.
        group.sampling_mode(SamplingMode::Flat);
        bench_render(&mut group, &format!("bvh {width}x{height}"), &with_bvh);
        bench_render(
            &mut group,
            &format!("every triangle {width}x{height}"),
            &brute,
        );
        group.finish();
    }
}

/// The effects past ray casting: for each shipped scene that declares one, one render with all its
/// effects and one with each of those left out in turn, timed once each and printed as a table with
/// the rays of each kind (`cargo bench --bench render -- cost-table` prints it and skips the rest).
fn cost_table(_: &mut Criterion) {
    use raylab::render::ray_kinds::RayKind;
    if !table_wanted("cost-table") {
        return;
    }
    let past_casting = Effect::PAST_CASTING;
    println!(
        "| scene | effects | time (ms) | primary | samples | shadow | reflection | refraction | occlusion |"
    );
    println!("|---|---|---:|---:|---:|---:|---:|---:|---:|");
    for file in raylab::render::ray_kinds::EFFECT_SCENES {
        let scene = scene(file);
        let prepared = Prepared::new(&scene, &Embedded).unwrap();
        let runs = all_and_each_left_out(&scene.effects, |e| past_casting.contains(e));
        for (label, effects) in runs {
            let mut prepared = prepared.clone();
            prepared.effects = effects;
            let clock = std::time::Instant::now();
            let (_, stats) = render(&prepared);
            let ms = clock.elapsed().as_secs_f64() * 1e3;
            let s = &stats.secondary;
            let kinds = [
                RayKind::Sample,
                RayKind::Shadow,
                RayKind::Reflection,
                RayKind::Refraction,
                RayKind::Occlusion,
            ]
            .map(|k| s.rays(k).to_string())
            .join(" | ");
            println!(
                "| {} | {label} | {ms:.1} | {} | {kinds} |",
                file.trim_end_matches(".ron"),
                stats.rays
            );
        }
    }
}

/// The Render view's frames while the camera orbits: for each shipped render scene, the full
/// frame, then quick frames as the view makes them (the divisor guessed from the full frame and
/// moved a step a frame towards [`QUICK_FRAME_SECONDS`]), each from a camera turned a little
/// further; printed as a table (`cargo bench --bench render -- orbit-table` prints it and skips
/// the rest). Renders run on the machine's threads, as the app's do.
fn orbit_table(_: &mut Criterion) {
    use raylab::render::{QUICK_FRAME_SECONDS, next_quick_divisor};
    if !table_wanted("orbit-table") {
        return;
    }
    println!(
        "\n| scene | full frame | full (ms) | quick frame | divisor | quick (ms, median of 9) | \
         quick frames/s |"
    );
    println!("|---|---|---:|---|---:|---:|---:|");
    let dir = format!("{}/assets/scenes", env!("CARGO_MANIFEST_DIR"));
    let mut files: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|entry| entry.ok()?.file_name().into_string().ok())
        .filter(|name| name.ends_with(".ron"))
        .collect();
    files.sort();
    for file in files {
        let Problem::Render(scene) = Scene::load(std::path::Path::new(&format!("{dir}/{file}")))
            .unwrap()
            .problem
        else {
            continue;
        };
        let prepared = Prepared::new(&scene, &Embedded).unwrap();
        let name = file.trim_end_matches(".ron");
        let full = timed(&prepared);
        if scene.camera.orbit_angles().is_none() {
            println!(
                "| {name} | {}x{} | {:.1} | (an image plane: the camera stays) | | | |",
                prepared.width,
                prepared.height,
                full * 1e3
            );
            continue;
        }
        let mut n = next_quick_divisor(None, full);
        let mut times = Vec::new();
        for step in 0..15 {
            let mut quick = prepared.quick_frame(n);
            quick.camera = scene.camera.orbited(0.02 * f64::from(step), 0.0);
            let seconds = timed(&quick);
            if step >= 6 {
                times.push(seconds);
            } else {
                n = next_quick_divisor(Some(n), seconds);
            }
        }
        times.sort_by(f64::total_cmp);
        let median = times[times.len() / 2];
        let quick = prepared.quick_frame(n);
        println!(
            "| {name} | {}x{} | {:.1} | {}x{} | {n} | {:.1} | {:.0} |",
            prepared.width,
            prepared.height,
            full * 1e3,
            quick.width,
            quick.height,
            median * 1e3,
            1.0 / median.max(1e-9),
        );
    }
    println!("(quick frames aim at {:.0} ms)", QUICK_FRAME_SECONDS * 1e3);
}

/// The app's render job against the command line's render, on the scenes with the most work: the
/// job renders the same image in bands on a worker thread (the app's way, so the UI stays live), the
/// command line in one parallel pass. Alternating, five of each, medians (`cargo bench --bench
/// render -- job-table`).
fn job_table(_: &mut Criterion) {
    use raylab::platform::Job;
    use raylab::render::RenderJob;
    if !table_wanted("job-table") {
        return;
    }
    println!("\n| scene | `raylab render` (ms) | the app's render job (ms) | job / render |");
    println!("|---|---:|---:|---:|");
    for file in [
        "render-cornell-box.ron",
        "effect-ambient-occlusion.ron",
        "render-transformed.ron",
    ] {
        let prepared = std::sync::Arc::new(Prepared::new(&scene(file), &Embedded).unwrap());
        let (mut direct, mut job) = (Vec::new(), Vec::new());
        for _ in 0..5 {
            direct.push(timed(&prepared));
            // As the app runs it: a worker thread stepping the job until it finishes.
            let clock = std::time::Instant::now();
            let (done, finished) = std::sync::mpsc::channel();
            let mut running = Job::start(
                "bench-render",
                RenderJob::new(prepared.clone()),
                move || {
                    let _ = done.send(());
                },
            )
            .unwrap();
            loop {
                if running.poll().is_some() {
                    break;
                }
                let _ = finished.recv_timeout(Duration::from_millis(50));
            }
            job.push(clock.elapsed().as_secs_f64());
        }
        let median = |mut v: Vec<f64>| {
            v.sort_by(f64::total_cmp);
            v[v.len() / 2]
        };
        let (direct, job) = (median(direct), median(job));
        println!(
            "| {} | {:.1} | {:.1} | {:.2} |",
            file.trim_end_matches(".ron"),
            direct * 1e3,
            job * 1e3,
            job / direct
        );
    }
}

/// True when the command line names no benchmark filter, or names this table.
fn table_wanted(name: &str) -> bool {
    let filters: Vec<String> = std::env::args()
        .skip(1)
        .filter(|arg| !arg.starts_with('-'))
        .collect();
    filters.is_empty() || filters.iter().any(|f| f == name)
}

/// Seconds one render takes.
fn timed(prepared: &Prepared) -> f64 {
    let clock = std::time::Instant::now();
    std::hint::black_box(render(prepared));
    clock.elapsed().as_secs_f64()
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(3));
    targets = cost_table, orbit_table, job_table, effects, bvh
}
criterion_main!(benches);
