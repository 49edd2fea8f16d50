//! A stable fuzz harness (no nightly): seeded mutations of real inputs fed to every input format's
//! reader, which must answer every input, in bounded time, with a result or an error, never a panic.
//!
//! Formats: the CLI's number and vector parser, batch lines, scene RON, OBJ text, PNG bytes and the
//! app's persisted state (RON). Each run replays `tests/fuzz_corpus/<format>/*` (every bad input ever
//! found, kept as regression cases), then tries new inputs from a fixed seed, so CI runs the same ones.
//! A panicking input is saved to the corpus folder; an input that runs past [`INPUT_LIMIT`] is saved
//! and the run stops. `RAYLAB_FUZZ_SEED=n` tries other inputs; `RAYLAB_FUZZ_SCALE=k` tries k times more.

// A test or benchmark fails by panicking: unwrap and expect are how it says so.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::time::{Duration, Instant};

use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use raylab::cli::batch::run_batch;
use raylab::cli::input::{Coords, Literal, ReadNumber};
use raylab::files::FileKind;
use raylab::geometry::{Precision, Real};
use raylab::math::exact::Exact;
use raylab::render::loading::assets::{AssetSource, FetchError, Texture, load_mesh};

/// The longest one input may run (debug build, a loaded machine) before the run counts it as a hang.
const INPUT_LIMIT: Duration = Duration::from_secs(10);

/// One input format: its seeds, words worth splicing in, how many new inputs to try, and its reader.
struct Target {
    name: &'static str,
    seeds: Vec<Vec<u8>>,
    words: &'static [&'static str],
    inputs: usize,
    run: fn(&[u8]),
}

fn corpus_dir(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/fuzz_corpus")
        .join(name)
}

fn save_to_corpus(name: &str, input: &[u8], prefix: &str) -> PathBuf {
    let dir = corpus_dir(name);
    let _ = std::fs::create_dir_all(&dir);
    // FNV-1a: a stable name, so the same input is saved once.
    let hash = input.iter().fold(0xcbf29ce484222325u64, |h, &b| {
        (h ^ b as u64).wrapping_mul(0x100000001b3)
    });
    let path = dir.join(format!("{prefix}{hash:016x}.bin"));
    let _ = std::fs::write(&path, input);
    path
}

/// Changes an input a little: flips, inserts, deletes, repeats, splices words or other seeds.
fn mutate(rng: &mut Pcg64, target: &Target) -> Vec<u8> {
    let mut input = target.seeds[rng.random_range(0..target.seeds.len())].clone();
    for _ in 0..rng.random_range(1..=4) {
        let len = input.len();
        let at = rng.random_range(0..=len);
        match rng.random_range(0..8) {
            0 if len > 0 => input[at.min(len - 1)] ^= 1 << rng.random_range(0..8),
            1 => input.insert(at, rng.random()),
            2 if len > 0 => {
                let end = (at + rng.random_range(1..=16)).min(len);
                input.drain(at.min(end)..end);
            }
            3 if len > 0 => {
                let start = rng.random_range(0..len);
                let end = (start + rng.random_range(1..=32)).min(len);
                let piece = input[start..end].to_vec();
                input.splice(at..at, piece);
            }
            4 | 5 if !target.words.is_empty() => {
                let word = target.words[rng.random_range(0..target.words.len())];
                input.splice(at..at, word.bytes());
            }
            6 => input.truncate(at),
            _ => {
                let other = &target.seeds[rng.random_range(0..target.seeds.len())];
                let start = rng.random_range(0..=other.len());
                input.truncate(at);
                input.extend_from_slice(&other[start..]);
            }
        }
    }
    input
}

/// What the watchdog watches: the input running now, and since when.
static RUNNING: Mutex<Vec<(&'static str, Instant, Vec<u8>)>> = Mutex::new(Vec::new());

fn watchdog() {
    std::thread::spawn(|| {
        loop {
            std::thread::sleep(Duration::from_millis(200));
            let running = RUNNING.lock().unwrap_or_else(|e| e.into_inner());
            for (name, since, input) in running.iter() {
                if since.elapsed() > INPUT_LIMIT {
                    let path = save_to_corpus(name, input, "hang-");
                    eprintln!("fuzz: {name}: an input ran past {INPUT_LIMIT:?}; saved to {path:?}");
                    std::process::abort();
                }
            }
        }
    });
}

/// Runs one input under the watchdog; true if it panicked (the input is then saved).
fn try_input(target: &Target, input: &[u8]) -> (bool, Duration) {
    let slot = {
        let mut running = RUNNING.lock().unwrap_or_else(|e| e.into_inner());
        running.push((target.name, Instant::now(), input.to_vec()));
        running.len() - 1
    };
    let clock = Instant::now();
    let panicked = catch_unwind(AssertUnwindSafe(|| (target.run)(input))).is_err();
    let took = clock.elapsed();
    let mut running = RUNNING.lock().unwrap_or_else(|e| e.into_inner());
    let mine = running
        .iter()
        .rposition(|(name, _, bytes)| *name == target.name && bytes == input)
        .unwrap_or(slot.min(running.len().saturating_sub(1)));
    running.remove(mine);
    drop(running);
    if panicked {
        let path = save_to_corpus(target.name, input, "panic-");
        eprintln!("fuzz: {}: a panic, input saved to {path:?}", target.name);
    }
    (panicked, took)
}

struct Tally {
    name: &'static str,
    tried: usize,
    replayed: usize,
    panics: usize,
    slowest: Duration,
    total: Duration,
}

fn fuzz(target: &Target, seed: u64, scale: usize) -> Tally {
    let mut tally = Tally {
        name: target.name,
        tried: 0,
        replayed: 0,
        panics: 0,
        slowest: Duration::ZERO,
        total: Duration::ZERO,
    };
    let mut count = |(panicked, took): (bool, Duration)| {
        tally.panics += usize::from(panicked);
        tally.slowest = tally.slowest.max(took);
        tally.total += took;
    };
    let mut corpus: Vec<PathBuf> = std::fs::read_dir(corpus_dir(target.name))
        .map(|dir| dir.filter_map(|e| e.ok().map(|e| e.path())).collect())
        .unwrap_or_default();
    corpus.sort();
    for path in &corpus {
        if let Ok(bytes) = std::fs::read(path) {
            count(try_input(target, &bytes));
            tally.replayed += 1;
        }
    }
    for seed_input in &target.seeds {
        count(try_input(target, seed_input));
        tally.tried += 1;
    }
    let mut rng = Pcg64::seed_from_u64(seed ^ fnv(target.name));
    for _ in 0..target.inputs * scale {
        let input = mutate(&mut rng, target);
        count(try_input(target, &input));
        tally.tried += 1;
    }
    tally
}

fn fnv(text: &str) -> u64 {
    text.bytes().fold(0xcbf29ce484222325u64, |h, b| {
        (h ^ b as u64).wrapping_mul(0x100000001b3)
    })
}

// ---- The readers -------------------------------------------------------------------------------

fn numbers(input: &[u8]) {
    let text = String::from_utf8_lossy(input);
    let _ = Literal::parse(&text);
    let _ = Coords::<2>::parse(&text);
    let _ = Coords::<3>::parse(&text);
    let f32_read = f32::read(&text);
    let f64_read = f64::read(&text);
    let exact = Exact::read(&text);
    // A float read straight from the text is the exact value rounded once.
    if let (Ok(value), Ok(exact)) = (&f64_read, &exact) {
        assert_eq!(*value, exact.to_f64(), "f64 of {text:?}");
    }
    if let (Ok(value), Ok(exact)) = (&f32_read, &exact) {
        assert_eq!(*value, f32::from_exact(exact), "f32 of {text:?}");
    }
}

fn batch_lines(input: &[u8]) {
    let precision = match input.first().map(|b| b % 3) {
        Some(0) => Precision::F32,
        Some(1) => Precision::F64,
        _ => Precision::Exact,
    };
    let with_trace = input.last().is_some_and(|b| b % 2 == 0);
    let mut out = Vec::new();
    run_batch(input, &mut out, std::io::sink(), precision, with_trace).expect("memory never fails");
    // Every answer is one line of JSON.
    for line in out.split(|&b| b == b'\n').filter(|l| !l.is_empty()) {
        serde_json::from_slice::<serde_json::Value>(line).expect("each answer is JSON");
    }
}

/// Assets for fuzzed scenes: a small mesh and a small texture, whatever the name.
struct SmallAssets;

impl AssetSource for SmallAssets {
    fn read(&self, name: &str, _kind: FileKind) -> Result<Vec<u8>, FetchError> {
        if name.ends_with(".png") {
            Ok(png_seeds().remove(0))
        } else if name.ends_with(".obj") {
            Ok(OBJ_CUBE.as_bytes().to_vec())
        } else {
            Err(FetchError::Other(format!("no file '{name}'")))
        }
    }
}

/// Rays a fuzzed scene's frame may cast at most: the frame is made smaller until its worst case
/// fits, or it is not rendered.
const FUZZ_FRAME_RAYS: f64 = 20_000.0;

fn scenes(input: &[u8]) {
    use raylab::render::budget::worst_case;
    let text = String::from_utf8_lossy(input);
    let Ok(scene) = raylab::scene::Scene::from_ron(&text, "fuzz.ron") else {
        return;
    };
    let _ = scene.to_ron();
    let raylab::scene::Problem::Render(render) = &scene.problem else {
        return;
    };
    let Ok(prepared) = raylab::render::Prepared::new(render, &SmallAssets) else {
        return;
    };
    // Its lights, materials and settings through the renderer: a quick frame (one sample a
    // pixel) small enough that its worst case stays within a few thousand rays.
    let frame = (1..=64)
        .map(|n| prepared.quick_frame(n))
        .find(|frame| worst_case(frame).rays <= FUZZ_FRAME_RAYS);
    if let Some(frame) = frame {
        let (image, _) = raylab::render::render(&frame);
        assert_eq!(image.width * image.height, frame.width * frame.height);
    }
}

/// Serves the input itself as the one asset.
struct Bytes<'a>(&'a [u8]);

impl AssetSource for Bytes<'_> {
    fn read(&self, _name: &str, _kind: FileKind) -> Result<Vec<u8>, FetchError> {
        Ok(self.0.to_vec())
    }
}

fn obj(input: &[u8]) {
    let _ = load_mesh(&Bytes(input), "fuzz.obj");
}

fn png(input: &[u8]) {
    if let Ok(texture) = Texture::load(&Bytes(input), "fuzz.png") {
        let _ = texture.sample(0.3, 0.7);
    }
}

fn app_state(input: &[u8]) {
    // What eframe does with the stored state at start-up.
    let text = String::from_utf8_lossy(input);
    if let Ok(state) = ron::from_str::<raylab::app::AppState>(&text) {
        let _ = ron::to_string(&state);
    }
}

// ---- The seeds ---------------------------------------------------------------------------------

/// A scene of several objects sharing one mesh and one texture, with lights, materials and settings.
const SHARED_FILES_SCENE: &str = r#"(title: "shared", note: "n", problem: Render((
    width: 24, height: 16,
    camera: Pinhole(position: (0.0, -5.0, 1.0), target: (0.0, 0.0, 0.0), fov_y: 50.0),
    objects: [
        (shape: Mesh(obj: "m.obj"), texture: Some("t.png"), material: Mirror(reflectance: 0.8)),
        (shape: Mesh(obj: "m.obj"), texture: Some("t.png"), transform: (translate: (2.0, 0.0, 0.0))),
        (shape: Mesh(obj: "m.obj"), transform: (scale: (0.5, 0.5, 0.5)), material: Glass(ior: 1.5)),
        (shape: Parallelogram(corner: (-3.0, -3.0, -1.0), e1: (6.0, 0.0, 0.0), e2: (0.0, 6.0, 0.0)), texture: Some("t.png")),
    ],
    effects: ["texture", "shadows", "reflections", "refraction", "ambient-occlusion", "antialiasing"],
    lights: [Point(position: (0.0, -3.0, 3.0), intensity: 0.8), Point(position: (2.0, 1.0, 3.0), intensity: 0.3)],
    settings: (max_depth: 3, occlusion_rays: 4, samples_per_side: 2, seed: 7, ambient: 0.2),
)))"#;

const OBJ_CUBE: &str = "# a cube\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\nvn 0 0 -1\n\
f 1/1/2 2/2/2 3/3/2 4/4/2\nf 5/1/1 6/2/1 7/3/1 8/4/1\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8\ng side\no other\nf -1 -2 -3\n";

fn png_seeds() -> Vec<Vec<u8>> {
    use image::{DynamicImage, ImageFormat};
    let rgb = image::RgbImage::from_fn(4, 3, |x, y| image::Rgb([x as u8 * 60, y as u8 * 80, 7]));
    let gray = image::GrayImage::from_fn(2, 2, |x, _| image::Luma([x as u8 * 255]));
    let rgba = image::RgbaImage::from_fn(3, 1, |x, _| image::Rgba([x as u8, 1, 2, 128]));
    let wide = image::ImageBuffer::<image::Rgb<u16>, _>::from_fn(2, 1, |x, _| {
        image::Rgb([x as u16 * 30000, 5, 65535])
    });
    [
        DynamicImage::from(rgb),
        DynamicImage::from(gray),
        DynamicImage::from(rgba),
        DynamicImage::from(wide),
    ]
    .iter()
    .map(|image| {
        let mut bytes = std::io::Cursor::new(Vec::new());
        image.write_to(&mut bytes, ImageFormat::Png).unwrap();
        bytes.into_inner()
    })
    .collect()
}

fn files(folder: &str, extension: &str) -> Vec<Vec<u8>> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join(folder);
    let mut paths: Vec<PathBuf> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == extension))
        .collect();
    paths.sort();
    paths.iter().map(|p| std::fs::read(p).unwrap()).collect()
}

fn targets() -> Vec<Target> {
    let number_seeds = [
        "3",
        "-2.5",
        "1e-3",
        "17/22",
        ".5",
        "+4.",
        "0.1,0.2,0.3",
        "1/3, -2/7",
        "1e400",
        "-1E-400",
        "123456789012345678901234567890",
        "1.0000000000000000000001",
        "nan",
        "inf",
        "5e10000",
        // Exact numbers whose size is in their exponents: refused by the size they would build.
        "1e10000/1e-10000",
        "-3e-9999/7e9999",
        "2.5e300/4e-300",
        "1e-400/3",
        "0.000001e-9990",
    ];
    let lecture =
        std::fs::read(Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/examples/lecture.jsonl"))
            .unwrap();
    let mut batch_seeds: Vec<Vec<u8>> = lecture
        .split(|&b| b == b'\n')
        .filter(|l| !l.is_empty())
        .map(|l| [l, b"\n"].concat())
        .collect();
    batch_seeds.push(lecture.clone());
    // Exact solves with exponents and fractions in their coordinates, past f64's range (exponents
    // of thousands are in the numbers target: a solve with them takes seconds in a debug build).
    batch_seeds.extend(
        [
            r#"{"kind":"triangle","a":"1e300/7,0,0","b":"0,3e-300,0","c":"0,0,1e400","origin":"0,0,0","dir":"1,1,1","precision":"exact"}"#,
            r#"{"kind":"segments","a1":"1e-400/3,2","a2":"6e350,1/7","b1":"2,6","b2":"5e-5,1","precision":"exact"}"#,
            r#"{"kind":"triangle","a":"6,0,0","b":"0,6,0","c":"0,0,6","origin":"1e50/1e-50,1,1","dir":"1,1e-300/3,1","precision":"f32"}"#,
        ]
        .map(|line| format!("{line}\n").into_bytes()),
    );
    let state = raylab::app::AppState::default();
    vec![
        Target {
            name: "numbers",
            seeds: number_seeds.iter().map(|s| s.as_bytes().to_vec()).collect(),
            words: &[
                "e",
                "E",
                "-",
                "+",
                ".",
                "/",
                ",",
                "0",
                "9",
                "e400",
                "e-400",
                "∞",
                " ",
                "1/0",
                "00000000000000000000",
                "e9999",
                "e-9999",
                "/1e",
                "e10000",
            ],
            inputs: 40_000,
            run: numbers,
        },
        Target {
            name: "batch",
            seeds: batch_seeds,
            words: &[
                "\"",
                "[",
                "]",
                "{",
                "}",
                ",",
                ":",
                "null",
                "1e400",
                "\"1/3\"",
                "\"precision\":\"exact\",",
                "\"precision\":\"f32\",",
                "\\u0000",
                "\n",
                "\u{ff}",
                "-0",
                "1e-400",
                "99999999999999999999",
                "/1e-300",
            ],
            inputs: 30_000,
            run: batch_lines,
        },
        Target {
            name: "scene",
            seeds: [
                files("assets/scenes", "ron"),
                vec![SHARED_FILES_SCENE.as_bytes().to_vec()],
            ]
            .concat(),
            words: &[
                "lights: [Point(position: (0.0, -3.0, 2.0), intensity: 0.7)],",
                "settings: (max_depth: 16, occlusion_rays: 1024, samples_per_side: 16),",
                "material: Glass(ior: 1.5),",
                "material: Mirror(reflectance: 0.9),",
                "\"shadows\", \"reflections\", \"refraction\", \"ambient-occlusion\", ",
                "(shape: Mesh(obj: \"meshes/octasphere.obj\"), texture: Some(\"t.png\")),",
                "(",
                ")",
                "[",
                "]",
                ",",
                ":",
                "Some(",
                "None",
                "1e308",
                "-1e308",
                "NaN",
                "inf",
                "0.0",
                "\"",
                "Mesh(obj: \"m.obj\")",
                "texture: Some(\"t.png\"),",
            ],
            inputs: 12_000,
            run: scenes,
        },
        Target {
            name: "obj",
            seeds: vec![OBJ_CUBE.as_bytes().to_vec()],
            words: &[
                "v ",
                "vt ",
                "vn ",
                "f ",
                "/",
                "//",
                "-1",
                "0",
                "1e308",
                "nan",
                "\n",
                "mtllib x.mtl\n",
                "usemtl m\n",
                "99999999999",
            ],
            inputs: 10_000,
            run: obj,
        },
        Target {
            name: "png",
            seeds: png_seeds(),
            words: &[
                "IHDR",
                "IDAT",
                "IEND",
                "PLTE",
                "tRNS",
                "\u{0}\u{0}\u{0}\u{0}",
                "\u{ff}\u{ff}\u{ff}\u{7f}",
            ],
            inputs: 5_000,
            run: png,
        },
        Target {
            name: "app-state",
            seeds: vec![
                ron::to_string(&state).unwrap().into_bytes(),
                ron::ser::to_string_pretty(&state, Default::default())
                    .unwrap()
                    .into_bytes(),
            ],
            words: &[
                "(", ")", "[", "]", ",", ":", "Some(", "None", "\"", "1e308", "NaN", "-1", "true",
            ],
            inputs: 5_000,
            run: app_state,
        },
    ]
}

#[test]
fn every_input_format_answers_any_input_without_panicking() {
    let seed = std::env::var("RAYLAB_FUZZ_SEED")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(15);
    let scale = std::env::var("RAYLAB_FUZZ_SCALE")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(1);
    watchdog();
    let clock = Instant::now();
    let targets = targets();
    let threads = std::thread::available_parallelism().map_or(2, |n| n.get().min(4));
    let next = std::sync::atomic::AtomicUsize::new(0);
    let tallies = Mutex::new(Vec::new());
    std::thread::scope(|scope| {
        for _ in 0..threads {
            scope.spawn(|| {
                loop {
                    let i = next.fetch_add(1, std::sync::atomic::Ordering::SeqCst);
                    let Some(target) = targets.get(i) else { break };
                    let tally = fuzz(target, seed, scale);
                    tallies.lock().unwrap().push(tally);
                }
            });
        }
    });
    let tallies = tallies.into_inner().unwrap();
    let (mut tried, mut panics) = (0, 0);
    for t in &tallies {
        println!(
            "fuzz {:>10}: {:>6} inputs (+{} from the corpus), {} panic(s), slowest {:.1} ms, {:.1} s in all",
            t.name,
            t.tried,
            t.replayed,
            t.panics,
            t.slowest.as_secs_f64() * 1e3,
            t.total.as_secs_f64()
        );
        tried += t.tried + t.replayed;
        panics += t.panics;
    }
    println!(
        "fuzz: {tried} inputs in {:.1} s, {panics} panic(s)",
        clock.elapsed().as_secs_f64()
    );
    assert!(tried >= 100_000 * scale, "only {tried} inputs");
    assert_eq!(panics, 0, "inputs that panicked are in tests/fuzz_corpus/");
}
