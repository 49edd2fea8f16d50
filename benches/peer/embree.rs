//! **Meshes** against Intel Embree 4 (robust mode) through `../shared/peers/embree_render.py` (needs
//! python3 with `embreex` and `numpy`): coverage only, the same pinhole rays, 2 threads each (raylab in
//! a rayon pool of 2, the script with `--threads 2`), the median of 21 renders each, in one run. Each
//! side is measured in three alternating rounds (one for the 1.3-million-triangle sphere; five in the
//! shadow rows below, each after 250 ms of warm-up casts on both sides; eleven short ones side by
//! side in the rows per kind of ray, each after 200 ms); the row shows each side's median round,
//! the median of the rounds' ratios, and every round's ratio.
//!
//! Scenes: each shipped scene with a mesh (its objects written to a temporary OBJ in world space, with
//! their transforms applied; a parallelogram as its two triangles), an 81 920-triangle irregular sphere,
//! and a box seen from inside whose every ray runs along an edge or through a vertex, at 41 200
//! triangles (201x201) and finer at 363 600 (601x601). Then shadow rays: `Bvh::occluded` (any hit,
//! one ray at a time) and `Bvh::occluded_packet` (4x4 tiles of neighbouring rays) against Embree's
//! occlusion queries (`benches/peer/embree_occluded.py`) on the same camera rays, for the sphere and
//! both boxes. Then a row per kind of ray: the rays the tracer
//! casts in the Cornell box and each effect scene (`render::ray_log`), cast again by Embree
//! (`benches/peer/embree_rays.py`: intersect, or occluded up to t_max) and by raylab's own queries.
//! Then the hierarchy's build time and memory over the 1.3-million-triangle sphere
//! (`benches/peer/embree_build.py`). Then the scaling: irregular spheres from 1 280 to 1 310 720 triangles. Set `RAYLAB_PEER_REPEATS`
//! to change the 21 renders, `RAYLAB_PEER_MAX_LEVEL` (3 to 8) to cut the scaling series short, and
//! `RAYLAB_PEER_ONLY` (comma-separated parts of row names, e.g. `level 8,box`) to run only those rows.
//!
//! In the shadow rows and the rows per kind of ray, both sides' scripts are ours, and on Linux each
//! side's two worker threads run one on each CPU (`--pin` to the scripts, [`query_pool`] here); set
//! `RAYLAB_PEER_UNPINNED` to leave both to the scheduler.

use std::process::Command;

use super::any_hit::{Casting, TILE, fine_inside_box, inside_box, occluded_band, sphere};
use raylab::math::linalg::V3;
use raylab::render::generate::{irregular_sphere, mesh_hierarchy, to_obj};
use raylab::render::ray_log::{LoggedRay, rays_cast};
use raylab::render::{Prepared, Ray, loading::assets::Embedded, render, world_triangles};
use raylab::scene::render::{Camera, Effect};
use raylab::scene::{Problem, Scene};

/// A scene by name, prepared, with its world-space triangles for the script.
type Named = (String, Prepared, Vec<[V3<f64>; 3]>);

/// Threads for both sides.
const THREADS: usize = 2;

/// Milliseconds of casts on both threads before a query row's clock starts, on each side (the
/// scripts' `--warm-ms`, [`warm_up`] here). After the other side's turn, this process's workers
/// had sat idle for a second or more, and one warm-up cast was not enough: the Cornell box's
/// primary rays, 2.6–2.7 ms a cast in a busy loop, read 2.7–5.5 ms for the casts after a second's
/// sleep (a cast on one thread alone), and the bench's raylab side read 4.4 ms against the loop's
/// 2.7 ms in the same hour. After 200 ms of casts they read 2.6–3.0 ms again.
const WARM_MS: f64 = 250.0;

/// Calls `cast` until [`WARM_MS`] have passed, at least once (see there).
fn warm_up(cast: impl FnMut()) {
    warm_up_for(WARM_MS, cast);
}

/// Calls `cast` until `ms` milliseconds have passed, at least once.
fn warm_up_for(ms: f64, mut cast: impl FnMut()) {
    let clock = std::time::Instant::now();
    loop {
        cast();
        if clock.elapsed().as_secs_f64() * 1e3 >= ms {
            return;
        }
    }
}

fn repeats() -> usize {
    std::env::var("RAYLAB_PEER_REPEATS")
        .ok()
        .and_then(|r| r.parse().ok())
        .unwrap_or(21)
}

/// True when the row `name` is to run: `RAYLAB_PEER_ONLY` unset, or one of its comma-separated
/// parts in the name.
fn wanted(name: &str) -> bool {
    std::env::var("RAYLAB_PEER_ONLY").map_or(true, |only| {
        only.split(',').any(|part| name.contains(part.trim()))
    })
}

/// The script's path, if it is there.
fn script() -> Option<&'static str> {
    let script = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../shared/peers/embree_render.py"
    );
    std::path::Path::new(script).exists().then_some(script)
}

/// Embree's (median ms, covered pixels) for `triangles` seen by the scene's pinhole camera.
fn embree(
    script: &str,
    triangles: &[[V3<f64>; 3]],
    prepared: &Prepared,
    name: &str,
) -> Result<(f64, usize), String> {
    run_script(
        script,
        triangles,
        prepared,
        &format!("render-{name}"),
        false,
    )
}

/// Runs an Embree `script` on `triangles` (written to a temporary OBJ named after `tag`) with the
/// scene's pinhole camera, image size, [`THREADS`] and [`repeats`]; for one of our query scripts
/// (`query`), also `--warm-ms` [`WARM_MS`] and `--pin` where [`pinned`]: its median ms and its
/// count.
fn run_script(
    script: &str,
    triangles: &[[V3<f64>; 3]],
    prepared: &Prepared,
    tag: &str,
    query: bool,
) -> Result<(f64, usize), String> {
    let Camera::Pinhole {
        position,
        target,
        fov_y,
    } = &prepared.camera
    else {
        return Err("the script takes pinhole cameras only".into());
    };
    let path = std::env::temp_dir().join(format!("raylab-peer-{tag}-{}.obj", std::process::id()));
    std::fs::write(&path, to_obj(triangles)).map_err(|e| format!("cannot write the OBJ: {e}"))?;
    let join = |v: &[f64; 3]| format!("{:?},{:?},{:?}", v[0], v[1], v[2]);
    let output = Command::new("python3")
        .arg(script)
        .arg("--obj")
        .arg(&path)
        .args(["--eye", &join(position), "--target", &join(target)])
        .args(["--fov", &format!("{fov_y:?}")])
        .args(["--size", &format!("{}x{}", prepared.width, prepared.height)])
        .args(["--threads", &THREADS.to_string()])
        .args(["--reps", &repeats().to_string()])
        .args(
            query
                .then(|| ["--warm-ms".to_string(), WARM_MS.to_string()])
                .into_iter()
                .flatten(),
        )
        .args((query && pinned()).then_some("--pin"))
        .output();
    let _ = std::fs::remove_file(&path);
    let output = output.map_err(|e| format!("cannot run python3: {e}"))?;
    median_and_coverage(&output)
}

/// A peer script's median time (ms) and covered pixels, read from its output
/// ("… median 6.412 ms over 21 renders …, covered pixels 53449 …"), or why not.
pub fn median_and_coverage(output: &std::process::Output) -> Result<(f64, usize), String> {
    let text = String::from_utf8_lossy(&output.stdout);
    if !output.status.success() {
        return Err(format!(
            "the script failed: {}",
            String::from_utf8_lossy(&output.stderr).trim()
        ));
    }
    // "median 6.412 ms over 21 renders (2 threads), covered pixels 53449, 16.07 Mrays/s"
    match (
        number_after(&text, "median"),
        number_after(&text, "covered pixels"),
    ) {
        (Some(ms), Some(pixels)) => Ok((ms, pixels as usize)),
        _ => Err(format!("unexpected output: {text}")),
    }
}

/// raylab's (median ms, covered pixels) in a pool of [`THREADS`] threads.
fn raylab(pool: &rayon::ThreadPool, prepared: &Prepared) -> (f64, usize) {
    pool.install(|| {
        let covered = render(prepared).0.covered_pixels(); // also warms the pool
        let ms = super::median_ms(repeats(), || {
            std::hint::black_box(render(prepared));
        });
        (ms, covered)
    })
}

/// How many rounds each side is measured in, alternating (Embree, raylab, Embree, …), on a scene
/// of `triangles`: three, so that a slow spell of the shared machine weighs on both sides alike;
/// one for the largest meshes, whose OBJ alone takes the script seconds to read.
fn rounds(triangles: usize) -> usize {
    if triangles > 1_000_000 { 1 } else { 3 }
}

/// Rounds of the shadow rows, alternating: five. In this shared
/// machine's noisy spells a row's rounds read as far apart as 0.90x and 1.46x (the sphere's any-hit
/// rays in packets), and in three rounds two slow ones set the median; in five it takes three.
const QUERY_ROUNDS: usize = 5;

/// One row of the table: both sides on one scene, in alternating rounds: each side's median round,
/// the median of the rounds' ratios, and each round's ratio.
fn row(
    pool: &rayon::ThreadPool,
    script: &str,
    name: &str,
    prepared: &Prepared,
    triangles: &[[V3<f64>; 3]],
) -> Result<(), String> {
    let (mut peer, mut ours) = (Vec::new(), Vec::new());
    let (mut peer_pixels, mut our_pixels) = (0, 0);
    for _ in 0..rounds(triangles.len()) {
        let (peer_ms, pixels) = embree(script, triangles, prepared, name)?;
        peer.push(peer_ms);
        peer_pixels = pixels;
        let (ours_ms, pixels) = raylab(pool, prepared);
        ours.push(ours_ms);
        our_pixels = pixels;
    }
    // Each round's two measurements were taken a moment apart: the ratio is the median of the
    // rounds' ratios, not of the two sides' medians, which may come from different rounds.
    let ratios: Vec<f64> = peer.iter().zip(&ours).map(|(p, o)| p / o).collect();
    let each_round: Vec<String> = ratios.iter().map(|r| format!("{r:.2}")).collect();
    let ratio = super::median(ratios);
    let (peer_ms, ours_ms) = (super::median(peer), super::median(ours));
    println!(
        "{name:>24} {:>9} {:>9}   Embree {peer_ms:8.3} ms   raylab {ours_ms:8.3} ms   raylab/Embree speed \
         {:5.2}x (rounds {})   covered: Embree {peer_pixels}, raylab {our_pixels}{}",
        triangles.len(),
        format!("{}x{}", prepared.width, prepared.height),
        ratio,
        each_round.join(" "),
        if peer_pixels == our_pixels {
            " (equal)"
        } else {
            " (DIFFERENT)"
        }
    );
    Ok(())
}

/// raylab's any-hit queries on every camera ray of a one-mesh scene, in a pool of [`THREADS`]
/// threads (bands of [`TILE`] rows in parallel): (median ms, occluded rays). The rays are made
/// before the clock starts, as the script's are.
fn raylab_occluded(
    pool: &rayon::ThreadPool,
    prepared: &Prepared,
    casting: Casting,
) -> Option<(f64, usize)> {
    use rayon::prelude::*;
    let bvh = mesh_hierarchy(prepared)?;
    let bands: Vec<Vec<Vec<Ray>>> = (0..prepared.height)
        .step_by(TILE)
        .map(|top| {
            (top..(top + TILE).min(prepared.height))
                .map(|row| {
                    (0..prepared.width)
                        .map(|column| prepared.ray(row, column))
                        .collect()
                })
                .collect()
        })
        .collect();
    let band_count =
        |band: &Vec<Vec<Ray>>| occluded_band(bvh, prepared, band, casting, (&mut 0, &mut 0));
    let count = || bands.par_iter().map(band_count).sum::<usize>();
    Some(pool.install(|| {
        let occluded = count();
        warm_up(|| {
            std::hint::black_box(count());
        });
        let ms = super::median_ms(repeats(), || {
            std::hint::black_box(count());
        });
        (ms, occluded)
    }))
}

/// Embree's occlusion queries on the same rays: (median ms, occluded rays).
fn embree_occluded(
    triangles: &[[V3<f64>; 3]],
    prepared: &Prepared,
    name: &str,
) -> Result<(f64, usize), String> {
    let script = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/benches/peer/embree_occluded.py"
    );
    run_script(script, triangles, prepared, &format!("shadow-{name}"), true)
}

/// Shadow rays: both sides' any-hit queries on the generated meshes, in alternating rounds (Embree,
/// then raylab each way): each side's median round and the median of the rounds' ratios.
fn shadow_rays(pool: &rayon::ThreadPool, scenes: &[Named]) {
    println!(
        "\nshadow rays: any-hit (occlusion) queries on the camera rays, no distance limit, \
         {THREADS} threads each, alternating rounds"
    );
    for (name, prepared, triangles) in scenes.iter().skip(3) {
        // Rows named e.g. "shadow box from inside: 4x4 packets".
        let ways: Vec<_> = [
            (Casting::OneRay, "one ray at a time"),
            (Casting::OneRayAlone, "one ray at a time, no last blocker"),
            (Casting::Packets, "4x4 packets"),
        ]
        .into_iter()
        .filter(|(_, how)| wanted(&format!("shadow {name}: {how}")))
        .collect();
        if ways.is_empty() {
            continue;
        }
        // Per round, Embree's (ms, occluded), then raylab's for each way.
        let mut measured = Vec::new();
        for _ in 0..QUERY_ROUNDS {
            let Ok(peer) = embree_occluded(triangles, prepared, name)
                .inspect_err(|why| println!("Embree shadow peer skipped: {why}"))
            else {
                break;
            };
            let ours: Option<Vec<(f64, usize)>> = ways
                .iter()
                .map(|(casting, _)| raylab_occluded(pool, prepared, *casting))
                .collect();
            let Some(ours) = ours else { break };
            measured.push((peer, ours));
        }
        if measured.is_empty() {
            continue;
        }
        for (way, (_, how)) in ways.iter().enumerate() {
            let peer_ms: Vec<f64> = measured.iter().map(|(peer, _)| peer.0).collect();
            let ours_ms: Vec<f64> = measured.iter().map(|(_, ours)| ours[way].0).collect();
            let ratios: Vec<f64> = peer_ms.iter().zip(&ours_ms).map(|(p, o)| p / o).collect();
            let each_round: Vec<String> = ratios.iter().map(|r| format!("{r:.2}")).collect();
            let (peer, ours) = (measured[0].0.1, measured[0].1[way].1);
            println!(
                "{name:>24} {:>9}   Embree {:8.3} ms   raylab {:8.3} ms   raylab/Embree speed \
                 {:5.2}x (rounds {})   occluded: Embree {peer}, raylab {ours}   ({how})",
                triangles.len(),
                super::median(peer_ms),
                super::median(ours_ms),
                super::median(ratios),
                each_round.join(" "),
            );
        }
    }
}

/// Rounds of each kind-of-ray row: eleven, each side's a moment after the other's (Embree first
/// in even rounds, raylab first in odd ones), against one Embree process that loads the scene and
/// the rays once ([`ServedRays`]). With a process a round (the rows' first way), five rounds took
/// as long, and a slow spell of the machine fell on whole rounds of one side: the Cornell box's
/// refraction rays read 0.67x to 1.06x in one row. Side by side, both sides of a round see the
/// same moment of the machine (its slow spells slow raylab's walks more than Embree's: see
/// benches/README), and of eleven rounds it takes six to move the median.
const KIND_ROUNDS: usize = 11;

/// Milliseconds of warm-up casts before each round of a kind-of-ray row, on each side. The other
/// side's round before it left this side's workers asleep for up to a second (see [`WARM_MS`]);
/// 200 ms of casts brought the Cornell box's primary rays back to their busy-loop time.
const KIND_WARM_MS: f64 = 200.0;

/// How many times each side casts a row's `rays` rays in a round: `RAYLAB_PEER_RAY_REPEATS`, or
/// by default enough casts for 300 000 rays, at least 3 (the Cornell box's occlusion rays alone
/// are 3.5 million). A row of a few thousand rays takes a millisecond a cast: over five casts the
/// median moved by a third from round to round.
fn ray_repeats(rays: usize) -> usize {
    const RAYS_A_ROUND: usize = 300_000;
    std::env::var("RAYLAB_PEER_RAY_REPEATS")
        .ok()
        .and_then(|r| r.parse().ok())
        .unwrap_or_else(|| RAYS_A_ROUND.div_ceil(rays.max(1)).clamp(3, 500))
}

/// raylab's side of a kind-of-ray row: the rays in chunks, each put in the order the render casts
/// its rays before any clock starts (as Embree's arrays are made before its clock:
/// [`super::replay`]), cast through the queries the tracer used (primary rays in packets of
/// sixteen) in a pool of [`THREADS`] threads.
struct OurRays<'a> {
    pool: &'a rayon::ThreadPool,
    prepared: &'a Prepared,
    rays: Vec<LoggedRay>,
    chunk: usize,
}

impl<'a> OurRays<'a> {
    fn new(pool: &'a rayon::ThreadPool, prepared: &'a Prepared, rays: &[LoggedRay]) -> Self {
        let (rays, chunk) = super::replay::in_chunks(rays, THREADS);
        OurRays {
            pool,
            prepared,
            rays,
            chunk,
        }
    }

    /// The rays that met something.
    fn met(&self) -> usize {
        let count = || super::replay::cast_chunks(self.prepared, &self.rays, self.chunk);
        self.pool.install(count)
    }

    /// One round: [`KIND_WARM_MS`] of warm-up casts, then the median ms of `reps` casts.
    fn round(&self, reps: usize) -> f64 {
        let count = || super::replay::cast_chunks(self.prepared, &self.rays, self.chunk);
        self.pool.install(|| {
            warm_up_for(KIND_WARM_MS, || {
                std::hint::black_box(count());
            });
            let mut times = Vec::new();
            for _ in 0..reps {
                let start = std::time::Instant::now();
                std::hint::black_box(count());
                times.push(start.elapsed().as_secs_f64() * 1e3);
            }
            super::median(times)
        })
    }
}

/// Embree's side of a kind-of-ray row: `benches/peer/embree_rays.py --serve`, which loads the
/// scene's world-space triangles and the rays once and then casts a round whenever asked.
struct ServedRays {
    child: std::process::Child,
    asks: Option<std::process::ChildStdin>,
    answers: std::io::BufReader<std::process::ChildStdout>,
    rays_file: std::path::PathBuf,
    /// The rays that met something.
    met: usize,
}

impl ServedRays {
    /// Starts the script on `rays` against the triangles in `obj`, and waits until it is ready.
    fn start(obj: &std::path::Path, rays: &[LoggedRay], tag: &str) -> Result<Self, String> {
        use std::process::Stdio;
        let script = concat!(env!("CARGO_MANIFEST_DIR"), "/benches/peer/embree_rays.py");
        let rays_file =
            std::env::temp_dir().join(format!("raylab-peer-{tag}-{}.f32", std::process::id()));
        std::fs::write(&rays_file, raylab::render::ray_log::as_f32s(rays))
            .map_err(|e| format!("cannot write the rays: {e}"))?;
        let query = if rays[0].any_hit() {
            "occluded"
        } else {
            "intersect"
        };
        let spawned = Command::new("python3")
            .arg(script)
            .arg("--obj")
            .arg(obj)
            .arg("--rays")
            .arg(&rays_file)
            .args(["--query", query])
            .args(["--threads", &THREADS.to_string()])
            .args(pinned().then_some("--pin"))
            .arg("--serve")
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn();
        let mut child = match spawned {
            Ok(child) => child,
            Err(why) => {
                let _ = std::fs::remove_file(&rays_file);
                return Err(format!("cannot run python3: {why}"));
            }
        };
        let (Some(asks), Some(answers)) = (child.stdin.take(), child.stdout.take()) else {
            unreachable!("both were asked for as pipes");
        };
        let mut served = ServedRays {
            child,
            asks: Some(asks),
            answers: std::io::BufReader::new(answers),
            rays_file,
            met: 0,
        };
        let ready = served.answer()?;
        served.met = number_after(&ready, "covered pixels")
            .ok_or_else(|| format!("unexpected output: {ready}"))? as usize;
        Ok(served)
    }

    /// One round: `warm_ms` of warm-up casts, then the median ms of `reps` casts.
    fn round(&mut self, warm_ms: f64, reps: usize) -> Result<f64, String> {
        use std::io::Write;
        let asks = self.asks.as_mut().expect("open until dropped");
        writeln!(asks, "{warm_ms} {reps}")
            .and_then(|()| asks.flush())
            .map_err(|e| format!("the script stopped: {e}"))?;
        let answer = self.answer()?;
        number_after(&answer, "median").ok_or_else(|| format!("unexpected output: {answer}"))
    }

    /// The script's next line, or why there is none (with what it wrote to stderr).
    fn answer(&mut self) -> Result<String, String> {
        use std::io::{BufRead, Read};
        let mut line = String::new();
        match self.answers.read_line(&mut line) {
            Ok(n) if n > 0 => Ok(line),
            _ => {
                let _ = self.child.kill();
                let mut why = String::new();
                if let Some(mut stderr) = self.child.stderr.take() {
                    let _ = stderr.read_to_string(&mut why);
                }
                Err(format!("the script failed: {}", why.trim()))
            }
        }
    }
}

impl Drop for ServedRays {
    /// Ends the script's input, so that it exits, and waits for it.
    fn drop(&mut self) {
        drop(self.asks.take());
        let _ = self.child.wait();
        let _ = std::fs::remove_file(&self.rays_file);
    }
}

/// The number after `key` in a script's line ("median 6.412 ms …", "covered pixels 53449, …").
fn number_after(text: &str, key: &str) -> Option<f64> {
    let rest = &text[text.find(key)? + key.len()..];
    rest.split_whitespace()
        .next()?
        .trim_end_matches(',')
        .parse()
        .ok()
}

/// A row per kind of ray: the rays the tracer casts in the Cornell box and in each effect scene,
/// written out and cast again by both sides in [`KIND_ROUNDS`] alternating rounds (Embree's
/// `intersect` or `occluded`, raylab's nearest-hit or any-hit query), [`THREADS`] threads each:
/// each side's median round, the median of the rounds' ratios, and each round's ratio.
fn ray_kinds(pool: &rayon::ThreadPool) {
    use raylab::render::ray_kinds::RayKind;
    println!(
        "\nevery kind of ray: the rays the tracer casts, cast again by both sides, {THREADS} threads \
         each, median of the casts in a round (3, or enough for 300 000 rays, after {KIND_WARM_MS} \
         ms of warm-up casts), {KIND_ROUNDS} rounds side by side, alternating which goes first"
    );
    // Each with every effect it declares.
    for file in raylab::render::ray_kinds::EFFECT_SCENES {
        let name = file.trim_end_matches(".ron");
        let kinds: Vec<RayKind> = RayKind::ALL
            .into_iter()
            .filter(|kind| wanted(&format!("{name}: {}", kind.name())))
            .collect();
        if kinds.is_empty() {
            continue;
        }
        let mut prepared = shipped(file);
        prepared.effects = scene_effects(file);
        let logged = pool.install(|| rays_cast(&prepared));
        let triangles = world_triangles(&prepared);
        let obj =
            std::env::temp_dir().join(format!("raylab-peer-kinds-{}.obj", std::process::id()));
        if let Err(why) = std::fs::write(&obj, to_obj(&triangles)) {
            println!("Embree ray-kind peer skipped: cannot write the OBJ: {why}");
            return;
        }
        for kind in kinds {
            let rays: Vec<LoggedRay> = logged.iter().filter(|r| r.kind == kind).copied().collect();
            if rays.is_empty() {
                continue;
            }
            let mut embree = match ServedRays::start(&obj, &rays, name) {
                Ok(embree) => embree,
                Err(why) => {
                    println!("Embree ray-kind peer skipped: {why}");
                    let _ = std::fs::remove_file(&obj);
                    return;
                }
            };
            let ours_side = OurRays::new(pool, &prepared, &rays);
            let (peer_met, our_met) = (embree.met, ours_side.met());
            let reps = ray_repeats(rays.len());
            let (mut peer, mut ours) = (Vec::new(), Vec::new());
            for round in 0..KIND_ROUNDS {
                if round % 2 == 1 {
                    ours.push(ours_side.round(reps));
                }
                match embree.round(KIND_WARM_MS, reps) {
                    Ok(ms) => peer.push(ms),
                    Err(why) => {
                        println!("Embree ray-kind peer skipped: {why}");
                        let _ = std::fs::remove_file(&obj);
                        return;
                    }
                }
                if round % 2 == 0 {
                    ours.push(ours_side.round(reps));
                }
            }
            drop(embree);
            let ratios: Vec<f64> = peer.iter().zip(&ours).map(|(p, o)| p / o).collect();
            let each_round: Vec<String> = ratios.iter().map(|r| format!("{r:.2}")).collect();
            let query = if rays[0].any_hit() {
                "occluded"
            } else {
                "intersect"
            };
            println!(
                "{name:>26} {:>10} {:>9} rays ({query:>9})   Embree {:9.3} ms   raylab {:9.3} ms   \
                 raylab/Embree speed {:5.2}x (rounds {})   met something: Embree {peer_met}, raylab {our_met}",
                kind.name(),
                rays.len(),
                super::median(peer),
                super::median(ours),
                super::median(ratios),
                each_round.join(" "),
            );
        }
        let _ = std::fs::remove_file(&obj);
    }
}

/// The hierarchy over the 1.3-million-triangle sphere: each side's build time (median of three,
/// [`THREADS`] threads for raylab, every hardware thread for Embree: two here) and memory (raylab's
/// vectors' capacities; Embree's growth in resident memory across its first build).
fn build_row(pool: &rayon::ThreadPool) {
    use raylab::render::bvh::Bvh;
    use raylab::render::objects::PreparedTriangle;
    let name = "build sphere level 8";
    if !wanted(name) {
        return;
    }
    let world = irregular_sphere(8, 12);
    let triangles: Vec<PreparedTriangle> =
        world.iter().map(|t| PreparedTriangle::new(*t)).collect();
    let script = concat!(env!("CARGO_MANIFEST_DIR"), "/benches/peer/embree_build.py");
    let obj = std::env::temp_dir().join(format!("raylab-peer-build-{}.obj", std::process::id()));
    if let Err(why) = std::fs::write(&obj, to_obj(&world)) {
        println!("Embree build peer skipped: cannot write the OBJ: {why}");
        return;
    }
    let output = Command::new("python3")
        .arg(script)
        .arg("--obj")
        .arg(&obj)
        .args(["--reps", "3"])
        .output();
    let _ = std::fs::remove_file(&obj);
    let peer = match output {
        Ok(output) if output.status.success() => {
            String::from_utf8_lossy(&output.stdout).trim().to_string()
        }
        Ok(output) => format!("failed: {}", String::from_utf8_lossy(&output.stderr).trim()),
        Err(why) => format!("cannot run python3: {why}"),
    };
    let (ms, bvh) = pool.install(|| {
        let mut times = Vec::new();
        let mut bvh = None;
        for _ in 0..3 {
            let start = std::time::Instant::now();
            bvh = Some(std::hint::black_box(Bvh::build(&triangles)));
            times.push(start.elapsed().as_secs_f64() * 1e3);
        }
        (super::median(times), bvh.expect("three builds"))
    });
    let mib = |bytes: u64| bytes as f64 / (1024.0 * 1024.0);
    let geometry = (triangles.len() * std::mem::size_of::<PreparedTriangle>()) as u64;
    println!(
        "\nbuilding the hierarchy over the {}-triangle sphere\n  Embree: {peer}\n  raylab: median build \
         {ms:.1} ms over 3 builds ({THREADS} threads), BVH {:.1} MiB ({:.0} bytes a triangle), \
         triangles {:.1} MiB",
        triangles.len(),
        mib(bvh.held_bytes()),
        bvh.held_bytes() as f64 / triangles.len() as f64,
        mib(geometry),
    );
}

/// The effects a shipped scene declares.
fn scene_effects(file: &str) -> Vec<Effect> {
    let path = format!("{}/assets/scenes/{file}", env!("CARGO_MANIFEST_DIR"));
    match Scene::load(std::path::Path::new(&path)).map(|scene| scene.problem) {
        Ok(Problem::Render(scene)) => scene.effects,
        _ => panic!("{file} is a render scene"),
    }
}

/// A shipped scene, coverage only.
fn shipped(file: &str) -> Prepared {
    let path = format!("{}/assets/scenes/{file}", env!("CARGO_MANIFEST_DIR"));
    let Problem::Render(scene) = Scene::load(std::path::Path::new(&path))
        .expect("the shipped scene loads")
        .problem
    else {
        panic!("{file} is a render scene");
    };
    let mut prepared = Prepared::new(&scene, &Embedded).expect("the shipped scene prepares");
    prepared.effects = vec![Effect::Coverage];
    prepared
}

/// True when the query rows pin each side's workers, one to a CPU: on Linux, unless
/// `RAYLAB_PEER_UNPINNED` is set.
fn pinned() -> bool {
    cfg!(target_os = "linux") && std::env::var_os("RAYLAB_PEER_UNPINNED").is_none()
}

/// The pool for the rows whose both sides are ours (shadow rays, each kind of ray): [`THREADS`]
/// workers, each on its own CPU when [`pinned`]. Left to the scheduler, rayon's second worker, woken
/// by the first, was at times queued behind it on the first's CPU for whole rounds (its chunks ran
/// on CPU 0 beside the first's, or the first ran them all), and a millisecond's cast took its
/// one-thread time. The scripts' workers are pinned alike (`--pin`).
fn query_pool() -> rayon::ThreadPool {
    let cpus = if pinned() { allowed_cpus() } else { Vec::new() };
    rayon::ThreadPoolBuilder::new()
        .num_threads(THREADS)
        .start_handler(move |worker| {
            if let Some(&cpu) = cpus.get(worker % cpus.len().max(1)) {
                pin_this_thread(cpu);
            }
        })
        .build()
        .expect("a pool of 2 threads")
}

/// The CPUs this process may run on, in order (none where that cannot be read).
#[cfg(target_os = "linux")]
#[allow(unsafe_code)]
fn allowed_cpus() -> Vec<usize> {
    // SAFETY: an all-zero cpu_set_t is the empty set, and sched_getaffinity writes at most the
    // size it is given into it.
    unsafe {
        let mut set: libc::cpu_set_t = std::mem::zeroed();
        if libc::sched_getaffinity(0, std::mem::size_of::<libc::cpu_set_t>(), &mut set) != 0 {
            return Vec::new();
        }
        (0..libc::CPU_SETSIZE as usize)
            .filter(|&cpu| libc::CPU_ISSET(cpu, &set))
            .collect()
    }
}

#[cfg(not(target_os = "linux"))]
fn allowed_cpus() -> Vec<usize> {
    Vec::new()
}

/// Lets the calling thread run on `cpu` only (a failure leaves it as it was).
#[cfg(target_os = "linux")]
#[allow(unsafe_code)]
fn pin_this_thread(cpu: usize) {
    // SAFETY: CPU_SET writes one bit of a set it is given whole (it checks `cpu` against the set's
    // size), and sched_setaffinity reads the set's size from the set it is given.
    unsafe {
        let mut set: libc::cpu_set_t = std::mem::zeroed();
        libc::CPU_SET(cpu, &mut set);
        libc::sched_setaffinity(0, std::mem::size_of::<libc::cpu_set_t>(), &set);
    }
}

#[cfg(not(target_os = "linux"))]
fn pin_this_thread(_: usize) {}

/// Runs the comparison, or says why it skipped.
pub fn compare() {
    let Some(script) = script() else {
        println!("Embree peer skipped: ../shared/peers/embree_render.py is not there");
        return;
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(THREADS)
        .build()
        .expect("a pool of 2 threads");
    println!(
        "\nmeshes against Embree 4 (robust), coverage only, {THREADS} threads each, median of {} renders, \
         alternating rounds",
        repeats()
    );
    println!("{:>24} {:>9} {:>9}", "scene", "triangles", "image");
    let mut scenes: Vec<Named> = Vec::new();
    for file in [
        "render-mesh.ron",
        "render-transformed.ron",
        "render-common-bugs.ron",
    ] {
        let prepared = shipped(file);
        let triangles = world_triangles(&prepared);
        scenes.push((file.trim_end_matches(".ron").into(), prepared, triangles));
    }
    let (prepared, triangles) = sphere(6);
    scenes.push(("irregular sphere".into(), prepared, triangles));
    let (prepared, triangles) = inside_box();
    scenes.push(("box from inside".into(), prepared, triangles));
    let (prepared, triangles) = fine_inside_box();
    scenes.push(("fine box from inside".into(), prepared, triangles));
    for (name, prepared, triangles) in scenes.iter().filter(|(name, ..)| wanted(name)) {
        if let Err(why) = row(&pool, script, name, prepared, triangles) {
            println!("Embree peer skipped: {why} (it needs python3 with embreex and numpy)");
            return;
        }
    }
    let queries = query_pool();
    shadow_rays(&queries, &scenes);
    ray_kinds(&queries);
    build_row(&pool);
    let max_level = std::env::var("RAYLAB_PEER_MAX_LEVEL")
        .ok()
        .and_then(|l| l.parse().ok())
        .unwrap_or(8u32)
        .clamp(3, 8);
    println!("\nscaling: irregular spheres, 400x400, coverage only, {THREADS} threads each");
    for level in (3..=max_level).filter(|level| wanted(&format!("sphere level {level}"))) {
        let (prepared, triangles) = sphere(level);
        if let Err(why) = row(
            &pool,
            script,
            &format!("sphere level {level}"),
            &prepared,
            &triangles,
        ) {
            println!("Embree peer skipped: {why}");
            return;
        }
    }
}
