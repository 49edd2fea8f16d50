//! A CPU ray caster that simulates only the effects a scene calls for (seed 003, seed 004).
//!
//! One ray per pixel goes into each object's space, through a BVH for meshes (neighbouring pixels as
//! a packet), through the core's intersection method or, for `watertight`, the crack-free test of
//! [`crack_free`]; the nearest hit wins. What happens after the hit depends on the scene's
//! effects: without an effect that needs barycentrics, none are interpolated; without shading, nothing
//! is shaded. [`Stats`] counts the work so tests can check that an effect not called for costs nothing.

pub mod budget;
pub mod bug;
pub mod bvh;
pub mod cast;
mod coverage_rows;
pub mod crack_free;
#[cfg(any(test, feature = "test-meshes"))]
pub mod generate;
pub mod inspect;
pub mod kernels;
pub mod loading;
pub mod object_index;
pub mod objects;
pub mod ray;
pub mod ray_kinds;
pub mod ray_log;
pub mod secondary;
pub mod shading;

use std::sync::{Arc, OnceLock};

use rayon::prelude::*;
use serde::Serialize;

use crate::intersect::Method;
use crate::math::linalg::{V3, cross, dot, sub};
use crate::platform::{Progress, Sliced, Stopwatch};
use crate::scene::render::{Camera, Effect, RenderScene};
pub use bug::Bug;
use loading::assets::AssetSource;
use objects::{Geometry, PreparedObject, unit};
pub use objects::{ObjectError, PrepareError};
pub use ray::{At, Hit, ParallelogramHit, Ray, TriangleHit};
use shading::light::Lighting;
use shading::shade::Shader;

/// Rays traced together through a mesh's BVH: neighbouring pixels, a tile of [`TILE_ROWS`] rows by
/// [`TILE_COLUMNS`] columns, or of one row.
const PACKET: usize = 16;
/// A tile's rows.
const TILE_ROWS: usize = 4;
/// A tile's columns.
const TILE_COLUMNS: usize = PACKET / TILE_ROWS;

/// Work done by a render.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct Stats {
    /// Rays cast (one per pixel).
    pub rays: u64,
    /// Ray–triangle tests.
    pub triangle_tests: u64,
    /// Ray–parallelogram tests.
    pub parallelogram_tests: u64,
    /// Ray–box tests in BVHs.
    pub box_tests: u64,
    /// Rays taken into an object's space.
    pub transforms: u64,
    /// Pixels whose ray hit something.
    pub hits: u64,
    /// Vertex colours interpolated (`barycentric-color`).
    pub color_interpolations: u64,
    /// Vertex normals interpolated (`smooth-normals`).
    pub normal_interpolations: u64,
    /// Texture lookups (`texture`).
    pub texture_samples: u64,
    /// Facing-ratio evaluations (`facing-ratio`, `smooth-normals`).
    pub shading: u64,
    /// Distance fades (`depth`).
    pub depth_fades: u64,
    /// The effects past ray casting: their rays by kind and the work those rays did (the counters
    /// above count only the primary ray through each pixel's centre).
    pub secondary: ray_kinds::Secondary,
}

impl Stats {
    /// The rays of `kind` the render cast (the primary rays are [`Stats::rays`]).
    pub fn rays_of(&self, kind: ray_kinds::RayKind) -> u64 {
        match kind {
            ray_kinds::RayKind::Primary => self.rays,
            _ => self.secondary.rays(kind),
        }
    }

    /// Every ray the render cast, of every kind.
    pub fn all_rays(&self) -> u64 {
        ray_kinds::RayKind::ALL
            .iter()
            .map(|&kind| self.rays_of(kind))
            .sum()
    }

    /// Each counter with its name, for printing.
    pub fn counters(&self) -> [(&'static str, u64); 11] {
        [
            ("rays", self.rays),
            ("triangle tests", self.triangle_tests),
            ("parallelogram tests", self.parallelogram_tests),
            ("box tests", self.box_tests),
            ("transforms", self.transforms),
            ("hits", self.hits),
            ("colour interpolations", self.color_interpolations),
            ("normal interpolations", self.normal_interpolations),
            ("texture samples", self.texture_samples),
            ("shading", self.shading),
            ("depth fades", self.depth_fades),
        ]
    }

    fn add(self, other: Stats) -> Stats {
        Stats {
            rays: self.rays + other.rays,
            triangle_tests: self.triangle_tests + other.triangle_tests,
            parallelogram_tests: self.parallelogram_tests + other.parallelogram_tests,
            box_tests: self.box_tests + other.box_tests,
            transforms: self.transforms + other.transforms,
            hits: self.hits + other.hits,
            color_interpolations: self.color_interpolations + other.color_interpolations,
            normal_interpolations: self.normal_interpolations + other.normal_interpolations,
            texture_samples: self.texture_samples + other.texture_samples,
            shading: self.shading + other.shading,
            depth_fades: self.depth_fades + other.depth_fades,
            secondary: self.secondary.plus(other.secondary),
        }
    }
}

/// A rendered image: linear RGB in [0, 1], row-major, and the hit mask.
#[derive(Clone, Debug, PartialEq)]
pub struct Image {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// RGB per pixel.
    pub pixels: Vec<[f32; 3]>,
    /// True where a triangle was hit.
    pub covered: Vec<bool>,
}

impl Image {
    fn black(width: usize, height: usize) -> Image {
        Image {
            width,
            height,
            pixels: vec![[0.0; 3]; width * height],
            covered: vec![false; width * height],
        }
    }

    /// How many pixels a triangle covers.
    pub fn covered_pixels(&self) -> usize {
        self.covered.iter().filter(|c| **c).count()
    }

    /// 8-bit RGB bytes, row-major.
    pub fn to_rgb8(&self) -> Vec<u8> {
        self.pixels
            .iter()
            .flat_map(|p| p.map(|c| (c.clamp(0.0, 1.0) * 255.0).round() as u8))
            .collect()
    }
}

/// A scene ready to render: objects prepared, method and effects chosen. The app changes `effects`,
/// `method` and `bug` between renders without preparing again.
#[derive(Clone, Debug)]
pub struct Prepared {
    /// Image width.
    pub width: usize,
    /// Image height.
    pub height: usize,
    /// The camera.
    pub camera: Camera,
    /// The method for every object; `None`: watertight for meshes, Möller–Trumbore otherwise.
    /// `watertight` renders with the crack-free test ([`crack_free`]); `watertight-exact` with the
    /// exact-deciding one.
    pub method: Option<Method>,
    /// The effects to compute.
    pub effects: Vec<Effect>,
    /// A common bug to render with, if any.
    pub bug: Option<Bug>,
    /// The objects, shared: a render with other effects, another method or a bug is a new
    /// `Prepared` over the same objects (a million-triangle mesh is not copied).
    pub objects: Arc<[PreparedObject]>,
    /// Lights, materials and the parameters of the effects past ray casting.
    pub lighting: Lighting,
    /// The proof that this processor runs the AVX2 kernels ([`kernels`]), detected when the scene
    /// is prepared; `None` renders with the scalar paths alone (the same image to the bit).
    pub simd: Option<kernels::Avx2>,
    /// The objects' world-space boxes in a hierarchy ([`object_index`]), built at the first
    /// secondary ray and shared like `objects`; [`Prepared::objects_mut`] drops it.
    pub index: Arc<OnceLock<object_index::ObjectIndex>>,
}

impl Prepared {
    /// Reads the scene's meshes and textures and inverts its transforms; the files may hold at
    /// most [`budget::MEMORY_BUDGET_BYTES`] together.
    pub fn new(scene: &RenderScene, assets: &dyn AssetSource) -> Result<Prepared, PrepareError> {
        Prepared::within(scene, assets, budget::MEMORY_BUDGET_BYTES)
    }

    /// [`Prepared::new`], its meshes and textures holding at most `memory` bytes together (each
    /// file once, however many objects name it).
    pub fn within(
        scene: &RenderScene,
        assets: &dyn AssetSource,
        memory: u64,
    ) -> Result<Prepared, PrepareError> {
        scene.check().map_err(PrepareError::Scene)?;
        let mut shared = objects::SharedFiles::new(memory);
        let objects = scene
            .objects
            .iter()
            .enumerate()
            .map(|(i, o)| {
                objects::prepare(o, assets, &mut shared).map_err(|error| match error {
                    objects::ObjectError::Memory(over) => PrepareError::Memory(over),
                    error => PrepareError::Object {
                        index: i + 1,
                        error,
                    },
                })
            })
            .collect::<Result<Arc<[_]>, _>>()?;
        Ok(Prepared {
            width: scene.width,
            height: scene.height,
            camera: scene.camera.clone(),
            method: scene.method.map(|m| m.0),
            effects: scene.effects.clone(),
            bug: None,
            objects,
            lighting: Lighting::of(scene),
            simd: kernels::Avx2::detect(),
            index: Arc::default(),
        })
    }

    /// The objects, to change (copied first if another `Prepared` shares them).
    pub fn objects_mut(&mut self) -> &mut [PreparedObject] {
        self.index = Arc::default();
        if Arc::get_mut(&mut self.objects).is_none() {
            self.objects = self.objects.iter().cloned().collect();
        }
        match Arc::get_mut(&mut self.objects) {
            Some(objects) => objects,
            None => &mut [],
        }
    }

    /// The objects' index of world-space boxes, built the first time it is asked for.
    pub fn object_index(&self) -> &object_index::ObjectIndex {
        self.index
            .get_or_init(|| object_index::ObjectIndex::new(&self.objects))
    }

    /// The method an object is tested with.
    pub fn method_for(&self, object: &PreparedObject) -> Method {
        match self.method {
            Some(method) => method,
            None if object.is_mesh => Method::Watertight,
            None => Method::MollerTrumbore,
        }
    }

    /// The method named for display: the scene's, or the per-object default.
    pub fn method_label(&self) -> String {
        match self.method {
            Some(method) => method.name().into(),
            None => "default (watertight for meshes, moller-trumbore otherwise)".into(),
        }
    }

    /// The ray through pixel (row, column).
    pub fn ray(&self, row: usize, column: usize) -> Ray {
        camera_ray(&self.camera, self.width, self.height, row, column)
    }

    /// Renders rows `first..first + pixels.len() / width` into the given slices of the image.
    fn render_rows(&self, first: usize, pixels: &mut [[f32; 3]], covered: &mut [bool]) -> Stats {
        let width = self.width;
        if secondary::applies(self) {
            return secondary::SecondaryCaster::new(self).render_rows(first, pixels, covered);
        }
        if coverage_rows::applies(self) {
            return coverage_rows::render_rows(self, first, pixels, covered);
        }
        let shader = Shader::new(&self.effects);
        // The pinhole's frame once, not once a pixel.
        let basis = pinhole_basis(&self.camera, width, self.height);
        let mut stats = Stats::default();
        let rows = first..first + pixels.len() / width;
        // Each pixel shaded as soon as its packet is cast, while its numbers are at hand.
        self.cast_rows_each(
            rows,
            basis.as_ref(),
            &mut stats,
            |(row, column), Ray { dir, .. }, hit, stats| {
                let at = (row - first) * width + column;
                (pixels[at], covered[at]) = self.shade(&shader, hit, &dir, stats);
            },
        );
        stats
    }

    /// The primary rays of rows `rows` and their nearest hits, row after row, cast as
    /// [`Prepared::render_rows`] casts them (packets of neighbouring pixels where a mesh takes the
    /// crack-free test), so the counters of ray casting are the same with or without the effects
    /// past it. Counts rays and hits.
    pub fn cast_rows(
        &self,
        rows: std::ops::Range<usize>,
        basis: Option<&Basis>,
        stats: &mut Stats,
    ) -> Vec<(Ray, Option<Hit>)> {
        let (first, width) = (rows.start, self.width);
        let mut out = vec![(Ray::new([0.0; 3], [0.0; 3]), None); rows.len() * width];
        self.cast_rows_each(rows, basis, stats, |(row, column), ray, hit, _| {
            out[(row - first) * width + column] = (ray, hit);
        });
        out
    }

    /// Casts rows `rows` as [`Prepared::cast_rows`] does, handing each pixel's (row, column), ray
    /// and hit to `each`, a packet at a time. A band of [`TILE_ROWS`] rows goes in square tiles of
    /// neighbouring pixels (their rays stay closer together through the hierarchy than a row's);
    /// other bands, a row at a time. Counts rays and hits.
    #[inline(always)]
    fn cast_rows_each(
        &self,
        rows: std::ops::Range<usize>,
        basis: Option<&Basis>,
        stats: &mut Stats,
        mut each: impl FnMut((usize, usize), Ray, Option<Hit>, &mut Stats),
    ) {
        let (width, size) = (self.width, (self.width, self.height));
        // The rays are made in place, each inlined (`camera_ray_in`), in plain loops: through a
        // closure or `array::from_fn` they were left as calls, a pixel at a time.
        let mut rays = [Ray::new([0.0; 3], [0.0; 3]); PACKET];
        let packets = cast::packets_pay(self);
        let mut hits = 0;
        let mut deliver = |pixel, ray, hit: Option<Hit>, stats: &mut Stats| {
            hits += u64::from(hit.is_some());
            each(pixel, ray, hit, stats);
        };
        // Neighbouring pixels in packets (the same hits as one at a time), the rest alone.
        let (tiles, packed) = match (packets, rows.len() == TILE_ROWS) {
            (false, _) => (false, 0),
            (true, true) => (true, width / TILE_COLUMNS * TILE_COLUMNS),
            (true, false) => (false, width / PACKET * PACKET),
        };
        // Each packet's hits, written in place.
        let mut found = [None; PACKET];
        if tiles {
            for start in (0..packed).step_by(TILE_COLUMNS) {
                let pixel = |k| (rows.start + k / TILE_COLUMNS, start + k % TILE_COLUMNS);
                for (k, ray) in rays.iter_mut().enumerate() {
                    let (row, column) = pixel(k);
                    *ray = camera_ray_in(&self.camera, basis, size, row, column);
                }
                cast::nearest_hits(self, &rays, stats, &mut found);
                for (k, hit) in found.iter().enumerate() {
                    deliver(pixel(k), rays[k], *hit, stats);
                }
            }
        }
        for row in rows.clone() {
            if !tiles {
                for start in (0..packed).step_by(PACKET) {
                    for (k, ray) in rays.iter_mut().enumerate() {
                        *ray = camera_ray_in(&self.camera, basis, size, row, start + k);
                    }
                    cast::nearest_hits(self, &rays, stats, &mut found);
                    for (k, hit) in found.iter().enumerate() {
                        deliver((row, start + k), rays[k], *hit, stats);
                    }
                }
            }
            for column in packed..width {
                let ray = camera_ray_in(&self.camera, basis, size, row, column);
                let hit = cast::nearest_hit(self, ray, stats);
                deliver((row, column), ray, hit, stats);
            }
        }
        stats.rays += (rows.len() * width) as u64;
        stats.hits += hits;
    }

    /// A pixel's colour and coverage from its nearest hit (the ray and hit counted by the caster).
    #[inline]
    fn shade(
        &self,
        shader: &Shader,
        hit: Option<Hit>,
        dir: &V3<f64>,
        stats: &mut Stats,
    ) -> ([f32; 3], bool) {
        let Some(hit) = hit else {
            return ([0.0; 3], false);
        };
        let object = &self.objects[hit.object];
        let inverse_length = 1.0 / dot(dir, dir).sqrt();
        let colour = shader.shade(object, &hit, dir, inverse_length, stats).color;
        (colour, true)
    }

    /// Renders rows `rows` in parallel (a band of `ROWS_PER_TASK`-row tasks).
    fn render_band(&self, rows: std::ops::Range<usize>, image: &mut Image) -> Stats {
        // A task's rows are a tile's.
        const ROWS_PER_TASK: usize = TILE_ROWS;
        let width = self.width;
        let span = rows.start * width..rows.end * width;
        image.pixels[span.clone()]
            .par_chunks_mut(width * ROWS_PER_TASK)
            .zip(image.covered[span].par_chunks_mut(width * ROWS_PER_TASK))
            .enumerate()
            .map(|(task, (pixels, covered))| {
                self.render_rows(rows.start + task * ROWS_PER_TASK, pixels, covered)
            })
            .reduce(Stats::default, Stats::add)
    }
}

/// Renders the whole image, rows in parallel.
pub fn render(prepared: &Prepared) -> (Image, Stats) {
    let mut image = Image::black(prepared.width, prepared.height);
    let stats = prepared.render_band(0..prepared.height, &mut image);
    (image, stats)
}

/// Every shipped render scene (`assets/scenes/`), named by its file and shrunk to at most `width` ×
/// `height` so a debug build renders it quickly: for the tests that go through them all.
#[cfg(test)]
pub(crate) fn shipped_scenes(width: usize, height: usize) -> Vec<(String, Prepared)> {
    use crate::scene::{Problem, Scene};
    let folder = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes");
    let mut files: Vec<_> = std::fs::read_dir(folder)
        .expect("the scenes folder")
        .map(|entry| entry.expect("a folder entry").path())
        .collect();
    files.sort();
    let mut scenes = Vec::new();
    for path in files {
        let Ok(Problem::Render(mut scene)) = Scene::load(&path).map(|s| s.problem) else {
            continue;
        };
        scene.width = scene.width.min(width);
        scene.height = scene.height.min(height);
        let name = path
            .file_name()
            .unwrap_or_default()
            .to_string_lossy()
            .into_owned();
        let prepared = Prepared::new(&scene, &loading::assets::Embedded);
        scenes.push((name, prepared.expect("a shipped scene prepares")));
    }
    scenes
}

/// The time a quick frame aims at while the camera moves (the Render view's orbit): 40 frames a
/// second, with room left for the app's own drawing.
pub const QUICK_FRAME_SECONDS: f64 = 0.025;

/// The most a quick frame divides the image's sides by.
pub const MAX_QUICK_DIVISOR: u32 = 16;

/// The least a quick frame divides the image's sides by: a frame while the camera moves is
/// always smaller than the image (and says so), even where the full image would keep up.
pub const MIN_QUICK_DIVISOR: u32 = 2;

impl Prepared {
    /// Camera rays a pixel: k² with antialiasing (k = samples_per_side), else one.
    pub fn samples_per_pixel(&self) -> usize {
        if self
            .effects
            .contains(&crate::scene::render::Effect::Antialiasing)
        {
            let k = self.lighting.settings.samples_per_side.max(1) as usize;
            k * k
        } else {
            1
        }
    }

    /// A quick frame of this render, for a moving camera: 1/`n` of its sides (rounded up), one
    /// sample a pixel; the same scene, effects and method.
    pub fn quick_frame(&self, n: u32) -> Prepared {
        let n = n.clamp(1, MAX_QUICK_DIVISOR) as usize;
        let mut quick = self.clone();
        quick.width = self.width.div_ceil(n);
        quick.height = self.height.div_ceil(n);
        quick.lighting.settings.samples_per_side = 1;
        quick
    }
}

/// The divisor of the next quick frame after a frame that took `seconds`: a quick frame of
/// divisor `n` (`Some(n)`) moves it one step towards frames of [`QUICK_FRAME_SECONDS`]; a full
/// frame (`None`) gives the first guess, as a frame's time falls with its pixels (n² fewer).
/// Within [`MIN_QUICK_DIVISOR`] to [`MAX_QUICK_DIVISOR`].
pub fn next_quick_divisor(last: Option<u32>, seconds: f64) -> u32 {
    let n = match last {
        Some(n) if seconds > 1.3 * QUICK_FRAME_SECONDS => n + 1,
        Some(n) if seconds < 0.4 * QUICK_FRAME_SECONDS => n.saturating_sub(1),
        Some(n) => n,
        None => (seconds / QUICK_FRAME_SECONDS).sqrt().ceil() as u32,
    };
    n.clamp(MIN_QUICK_DIVISOR, MAX_QUICK_DIVISOR)
}

/// A finished render: the image, the work, and the seconds it took.
pub struct Rendered {
    /// The image.
    pub image: Image,
    /// The work done.
    pub stats: Stats,
    /// Wall-clock seconds.
    pub seconds: f64,
}

/// A render cut into bands of rows, for [`crate::platform::Job`]: on a thread natively, a band per
/// frame on the web.
pub struct RenderJob {
    prepared: Arc<Prepared>,
    image: Image,
    stats: Stats,
    next_row: usize,
    seconds: f64,
    /// Rows a step renders, when set (one band a step); else bands of about 64k samples for 8 ms.
    rows_per_step: Option<usize>,
}

impl RenderJob {
    /// A job for the whole image.
    pub fn new(prepared: Arc<Prepared>) -> RenderJob {
        RenderJob {
            image: Image::black(prepared.width, prepared.height),
            prepared,
            stats: Stats::default(),
            next_row: 0,
            seconds: 0.0,
            rows_per_step: None,
        }
    }

    /// Each step renders one band of `rows` rows (a trial that must stop on time checks the
    /// clock between them).
    pub fn rows_per_step(mut self, rows: usize) -> RenderJob {
        self.rows_per_step = Some(rows.max(1));
        self
    }

    /// The work done so far.
    pub fn stats(&self) -> Stats {
        self.stats
    }
}

impl Sliced for RenderJob {
    type Output = Rendered;

    fn step(&mut self) -> Progress<Rendered> {
        // Bands until about 8 ms have passed: a slice stays short on the web's one thread, and a
        // thread's progress bar moves.
        // Bands of about 64k samples (at least two tasks of rows, for two threads): a heavy
        // scene's band stays short, so Cancel and Ctrl-C stop it soon. (16k samples cost the
        // Cornell box's job 7% against `raylab render` in the job-table bench: more joins.)
        let samples = self.prepared.width.max(1) * self.prepared.samples_per_pixel();
        let rows = self
            .rows_per_step
            .unwrap_or((65_536 / samples).max(2 * TILE_ROWS));
        let one_band = self.rows_per_step.is_some();
        let clock = Stopwatch::start();
        let mut end = self.next_row;
        while end < self.prepared.height
            && (end == self.next_row || (!one_band && clock.seconds() < 0.008))
        {
            let band_end = (end + rows).min(self.prepared.height);
            let band = self.prepared.render_band(end..band_end, &mut self.image);
            self.stats = self.stats.add(band);
            end = band_end;
        }
        self.seconds += clock.seconds();
        self.next_row = end;
        if end < self.prepared.height {
            return Progress::Working {
                done: end,
                total: self.prepared.height,
            };
        }
        Progress::Finished(Rendered {
            image: std::mem::replace(&mut self.image, Image::black(0, 0)),
            stats: self.stats,
            seconds: self.seconds,
        })
    }
}

/// A pinhole camera's frame: the ray through a pixel at (u, v) in [−1, 1]² is
/// forward + u·half_width·right + v·half_height·up.
pub struct Basis {
    /// The eye.
    pub origin: V3<f64>,
    /// Unit vector to the target.
    pub forward: V3<f64>,
    /// Unit vector to the image's right.
    pub right: V3<f64>,
    /// Unit vector up the image.
    pub up: V3<f64>,
    /// tan(fov/2) × width/height.
    pub half_width: f64,
    /// tan(fov/2).
    pub half_height: f64,
}

/// The frame of a pinhole camera (`None` for the image plane).
pub fn pinhole_basis(camera: &Camera, width: usize, height: usize) -> Option<Basis> {
    let Camera::Pinhole {
        position,
        target,
        fov_y,
    } = camera
    else {
        return None;
    };
    let forward = unit(sub(target, position));
    let right = unit(cross(&forward, &[0.0, 0.0, 1.0]));
    let up = cross(&right, &forward);
    let half_height = (fov_y.to_radians() / 2.0).tan();
    Some(Basis {
        origin: *position,
        forward,
        right,
        up,
        half_width: half_height * width as f64 / height.max(1) as f64,
        half_height,
    })
}

/// The ray through pixel (row, column): origin and direction.
pub fn camera_ray(camera: &Camera, width: usize, height: usize, row: usize, column: usize) -> Ray {
    let basis = pinhole_basis(camera, width, height);
    camera_ray_in(camera, basis.as_ref(), (width, height), row, column)
}

/// [`camera_ray`] with the pinhole's frame already made (`None` for the image plane). Always
/// inlined: the casters make a packet's rays in place.
#[inline(always)]
pub fn camera_ray_in(
    camera: &Camera,
    basis: Option<&Basis>,
    (width, height): (usize, usize),
    row: usize,
    column: usize,
) -> Ray {
    camera_ray_at(camera, basis, (width, height), row as f64, column as f64)
}

/// The ray through the fractional pixel position (row, column), pixel centres at whole numbers
/// (antialiasing's samples lie between them).
#[inline(always)]
pub fn camera_ray_at(
    camera: &Camera,
    basis: Option<&Basis>,
    (width, height): (usize, usize),
    row: f64,
    column: f64,
) -> Ray {
    // Pixel centres at both ends, as numpy's mgrid with a complex step count places them.
    let along = |from: f64, to: f64, i: f64, n: usize| {
        if n <= 1 {
            from
        } else {
            from + (to - from) * i / (n - 1) as f64
        }
    };
    match camera {
        Camera::ImagePlane { x, y, z } => {
            let point = [
                along(x.0, x.1, column, width),
                along(y.0, y.1, row, height),
                *z,
            ];
            Ray::new(point, unit(point))
        }
        Camera::Pinhole { .. } => {
            let Some(b) = basis else {
                return Ray::new([0.0; 3], [0.0; 3]);
            };
            let u = (column + 0.5) / width as f64 * 2.0 - 1.0;
            let v = 1.0 - (row + 0.5) / height as f64 * 2.0;
            let dir: V3<f64> = std::array::from_fn(|k| {
                b.forward[k] + b.right[k] * u * b.half_width + b.up[k] * v * b.half_height
            });
            Ray::new(b.origin, dir)
        }
    }
}

/// The world-space vertices of an object's triangle (for the pixel probe and the transform view).
pub fn world_triangle(object: &PreparedObject, primitive: usize) -> Option<[V3<f64>; 3]> {
    match &object.geometry {
        Geometry::Triangles { triangles, .. } => Some(triangles[primitive].vertices.map(|v| {
            object
                .world_from_object
                .transform_point3(v.into())
                .to_array()
        })),
        Geometry::Parallelogram { .. } => None,
    }
}

/// Every object's triangles in world space, a parallelogram as two: the scene as the peers (Embree)
/// take it.
pub fn world_triangles(prepared: &Prepared) -> Vec<[V3<f64>; 3]> {
    let mut out = Vec::new();
    for object in prepared.objects.iter() {
        match &object.geometry {
            Geometry::Triangles { triangles, .. } => {
                out.extend((0..triangles.len()).filter_map(|i| world_triangle(object, i)));
            }
            Geometry::Parallelogram { corner, e1, e2, .. } => {
                let at = |a: f64, b: f64| -> V3<f64> {
                    let local: V3<f64> = std::array::from_fn(|k| corner[k] + a * e1[k] + b * e2[k]);
                    object
                        .world_from_object
                        .transform_point3(local.into())
                        .to_array()
                };
                let (p, q, r, s) = (at(0.0, 0.0), at(1.0, 0.0), at(1.0, 1.0), at(0.0, 1.0));
                out.extend([[p, q, r], [p, r, s]]);
            }
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::render::{Object, SceneMethod, Shape, Transform};

    /// A quick frame is the render at 1/n of its sides, one sample a pixel; its divisor starts from
    /// the full frame's time (n² fewer pixels) and moves a step at a time towards the frame time,
    /// within 2 to 16.
    #[test]
    fn quick_frames_divide_the_image_towards_their_frame_time() {
        let mut prepared = one_triangle(vec![Effect::Coverage, Effect::Antialiasing]);
        (prepared.width, prepared.height) = (240, 101);
        prepared.lighting.settings.samples_per_side = 4;
        let quick = prepared.quick_frame(4);
        assert_eq!((quick.width, quick.height), (60, 26));
        assert_eq!(quick.lighting.settings.samples_per_side, 1);
        assert_eq!(quick.effects, prepared.effects);
        assert_eq!(render(&quick).0.width, 60);
        let frame = QUICK_FRAME_SECONDS;
        assert_eq!(next_quick_divisor(None, 16.0 * frame), 4);
        // A full frame that keeps up still moves as a smaller one.
        assert_eq!(next_quick_divisor(None, 0.5 * frame), MIN_QUICK_DIVISOR);
        assert_eq!(next_quick_divisor(None, 1e6), MAX_QUICK_DIVISOR);
        assert_eq!(next_quick_divisor(Some(4), 2.0 * frame), 5);
        assert_eq!(next_quick_divisor(Some(4), 0.2 * frame), 3);
        assert_eq!(next_quick_divisor(Some(4), frame), 4);
        assert_eq!(next_quick_divisor(Some(2), 0.0), MIN_QUICK_DIVISOR);
        assert_eq!(
            next_quick_divisor(Some(MAX_QUICK_DIVISOR), 1.0),
            MAX_QUICK_DIVISOR
        );
    }

    fn one_triangle(effects: Vec<Effect>) -> Prepared {
        let triangle = Object {
            shape: Shape::Triangle {
                vertices: [[0.0, 1.25, 3.0], [2.0, -1.25, 3.0], [-2.0, -1.25, 3.0]],
                colors: Some([[1.0, 0.0, 0.4], [0.4, 1.0, 0.0], [0.0, 0.4, 1.0]]),
                normals: Some([[0.0, 0.0, -1.0], [0.2, 0.0, -1.0], [-0.2, 0.0, -1.0]]),
                uvs: None,
            },
            color: [0.15, 0.35, 0.9],
            texture: Some("textures/checker.png".into()),
            transform: Transform::default(),
        };
        Prepared::new(
            &scene_of(vec![triangle], effects),
            &loading::assets::Embedded,
        )
        .unwrap()
    }

    /// A 32x16 watertight scene of `objects` seen through seed 003's image plane.
    fn scene_of(objects: Vec<Object>, effects: Vec<Effect>) -> RenderScene {
        RenderScene {
            width: 32,
            height: 16,
            camera: Camera::ImagePlane {
                x: (1.0, -1.0),
                y: (0.5, -0.5),
                z: 1.0,
            },
            method: Some(SceneMethod(Method::Watertight)),
            objects,
            effects,
            lights: vec![],
            materials: vec![],
            settings: Default::default(),
        }
    }

    /// The peers' triangle soup: a triangle as it is, a moved parallelogram as its two halves,
    /// corner to corner, in world space.
    #[test]
    fn world_triangles_give_a_parallelogram_as_two_halves() {
        let object = |shape, translate| Object {
            shape,
            color: [1.0; 3],
            texture: None,
            transform: Transform {
                translate,
                ..Transform::default()
            },
        };
        let triangle = Shape::Triangle {
            vertices: [[0.0, 1.25, 3.0], [2.0, -1.25, 3.0], [-2.0, -1.25, 3.0]],
            colors: None,
            normals: None,
            uvs: None,
        };
        let parallelogram = Shape::Parallelogram {
            corner: [0.0, 0.0, 5.0],
            e1: [1.0, 0.0, 0.0],
            e2: [0.0, 2.0, 0.0],
        };
        let objects = vec![
            object(triangle, [0.0; 3]),
            object(parallelogram, [10.0, 0.0, 0.0]),
        ];
        let scene = scene_of(objects, vec![Effect::Coverage]);
        let prepared = Prepared::new(&scene, &loading::assets::Embedded).unwrap();
        let triangles = world_triangles(&prepared);
        assert_eq!(triangles.len(), 3);
        assert_eq!(
            triangles[0],
            [[0.0, 1.25, 3.0], [2.0, -1.25, 3.0], [-2.0, -1.25, 3.0]]
        );
        let (p, q, r, s) = (
            [10.0, 0.0, 5.0],
            [11.0, 0.0, 5.0],
            [11.0, 2.0, 5.0],
            [10.0, 2.0, 5.0],
        );
        assert_eq!(triangles[1..], [[p, q, r], [p, r, s]]);
    }

    #[test]
    fn effects_not_called_for_cost_nothing() {
        let (image, coverage) = render(&one_triangle(vec![Effect::Coverage]));
        assert!(image.covered_pixels() > 0);
        assert_eq!(coverage.rays, 32 * 16);
        assert_eq!(coverage.triangle_tests, 32 * 16);
        let work = |s: &Stats| {
            [
                s.color_interpolations,
                s.normal_interpolations,
                s.texture_samples,
                s.shading,
                s.depth_fades,
            ]
        };
        assert_eq!(work(&coverage), [0; 5]);
        let hits = coverage.hits;
        for (effect, expected) in [
            (Effect::Depth, [0, 0, 0, 0, hits]),
            (Effect::BarycentricColor, [hits, 0, 0, 0, 0]),
            (Effect::SmoothNormals, [0, hits, 0, hits, 0]),
            (Effect::Texture, [0, 0, hits, 0, 0]),
            (Effect::FacingRatio, [0, 0, 0, hits, 0]),
        ] {
            let (_, stats) = render(&one_triangle(vec![effect]));
            assert_eq!(stats.hits, hits);
            assert_eq!(work(&stats), expected, "{}", effect.name());
        }
    }

    #[test]
    fn image_plane_rays_match_seed_003() {
        let camera = Camera::ImagePlane {
            x: (1.0, -1.0),
            y: (0.5, -0.5),
            z: 1.0,
        };
        let Ray { origin, dir } = camera_ray(&camera, 512, 256, 0, 0);
        assert_eq!(origin, [1.0, 0.5, 1.0]);
        assert!((crate::math::linalg::dot(&dir, &dir).sqrt() - 1.0).abs() < 1e-15);
        let Ray { origin, .. } = camera_ray(&camera, 512, 256, 255, 511);
        assert_eq!(origin, [-1.0, -0.5, 1.0]);
    }

    #[test]
    fn a_job_renders_what_render_renders() {
        let prepared = Arc::new(one_triangle(vec![Effect::BarycentricColor]));
        let mut job = RenderJob::new(prepared.clone());
        let rendered = loop {
            if let Progress::Finished(rendered) = job.step() {
                break rendered;
            }
        };
        let (image, stats) = render(&prepared);
        assert_eq!((rendered.image, rendered.stats), (image, stats));
    }
}
