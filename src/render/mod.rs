//! A CPU ray caster that simulates only the effects a scene calls for (seed 003, seed 004).
//!
//! One ray per pixel goes through the core's intersection methods; the nearest hit wins. What happens
//! after the hit depends on the scene's effects: without an effect that needs barycentrics, none are
//! interpolated; without shading, nothing is shaded. [`Stats`] counts the work so tests can check that
//! an effect not called for costs nothing.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::accuracy::{Case, Method};
use crate::geometry::linalg::{V3, cross, dot, sub};

/// A camera: seed 003's image plane, or a pinhole looking at a target.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum Camera {
    /// Seed 003: pixel (row, column) is the point (x, y, z) of a plane, x from `x.0` (left) to `x.1`
    /// (right), y from `y.0` (top) to `y.1` (bottom), both ends included; the ray starts there and goes
    /// along that point's direction from the origin, normalised.
    ImagePlane {
        /// x at the left and right columns.
        x: (f64, f64),
        /// y at the top and bottom rows.
        y: (f64, f64),
        /// The plane's z.
        z: f64,
    },
    /// A pinhole at `position` looking at `target`, z up, with a vertical field of view in degrees.
    Pinhole {
        /// The eye.
        position: [f64; 3],
        /// The point at the image's centre.
        target: [f64; 3],
        /// Vertical field of view, degrees.
        fov_y: f64,
    },
}

/// The effects a scene can call for; scene files name them as strings (`"facing-ratio"`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", try_from = "String", into = "String")]
pub enum Effect {
    /// White where a triangle is hit (a hit mask).
    Coverage,
    /// Grey by distance: near is bright.
    Depth,
    /// The object's colour times the facing ratio n̂ · (−ê) (seed 003).
    FacingRatio,
    /// Per-vertex colours interpolated with the barycentrics (seed 003, seed 004).
    BarycentricColor,
}

impl Effect {
    /// Every effect.
    pub const ALL: [Effect; 4] = [
        Effect::Coverage,
        Effect::Depth,
        Effect::FacingRatio,
        Effect::BarycentricColor,
    ];

    /// The name in scene files.
    pub fn name(self) -> &'static str {
        match self {
            Effect::Coverage => "coverage",
            Effect::Depth => "depth",
            Effect::FacingRatio => "facing-ratio",
            Effect::BarycentricColor => "barycentric-color",
        }
    }
}

impl TryFrom<String> for Effect {
    type Error = String;
    fn try_from(name: String) -> Result<Effect, String> {
        Effect::ALL
            .into_iter()
            .find(|e| e.name() == name)
            .ok_or_else(|| {
                let names: Vec<&str> = Effect::ALL.iter().map(|e| e.name()).collect();
                format!(
                    "unknown effect '{name}' (expected one of {})",
                    names.join(", ")
                )
            })
    }
}

impl From<Effect> for String {
    fn from(effect: Effect) -> String {
        effect.name().into()
    }
}

/// A triangle with an optional colour per vertex.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Triangle {
    /// The vertices A, B, C.
    pub vertices: [[f64; 3]; 3],
    /// The colour of A, B and C (for `barycentric-color`).
    #[serde(default)]
    pub colors: Option<[[f64; 3]; 3]>,
    /// The flat colour (for `facing-ratio`).
    #[serde(default = "default_color")]
    pub color: [f64; 3],
}

fn default_color() -> [f64; 3] {
    [0.8, 0.8, 0.8]
}

/// A scene to render.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct RenderScene {
    /// Shown in menus.
    pub title: String,
    /// One line on what it shows.
    pub note: String,
    /// Image width in pixels.
    pub width: usize,
    /// Image height in pixels.
    pub height: usize,
    /// The camera.
    pub camera: Camera,
    /// The triangles.
    pub triangles: Vec<Triangle>,
    /// What to compute at a hit.
    pub effects: Vec<Effect>,
}

/// Work done by a render.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct Stats {
    /// Rays cast (one per pixel).
    pub rays: u64,
    /// Ray–triangle tests.
    pub triangle_tests: u64,
    /// Pixels whose ray hit something.
    pub hits: u64,
    /// Barycentric interpolations of vertex attributes.
    pub interpolations: u64,
    /// Facing-ratio shading evaluations.
    pub shading: u64,
}

impl Stats {
    fn add(self, other: Stats) -> Stats {
        Stats {
            rays: self.rays + other.rays,
            triangle_tests: self.triangle_tests + other.triangle_tests,
            hits: self.hits + other.hits,
            interpolations: self.interpolations + other.interpolations,
            shading: self.shading + other.shading,
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

/// The ray through pixel (row, column): origin and direction.
pub fn camera_ray(
    camera: &Camera,
    width: usize,
    height: usize,
    row: usize,
    column: usize,
) -> (V3<f64>, V3<f64>) {
    // Pixel centres at both ends, as numpy's mgrid with a complex step count places them.
    let along = |from: f64, to: f64, i: usize, n: usize| {
        if n <= 1 {
            from
        } else {
            from + (to - from) * i as f64 / (n - 1) as f64
        }
    };
    match camera {
        Camera::ImagePlane { x, y, z } => {
            let point = [
                along(x.0, x.1, column, width),
                along(y.0, y.1, row, height),
                *z,
            ];
            let length = dot(&point, &point).sqrt();
            (point, point.map(|c| c / length))
        }
        Camera::Pinhole {
            position,
            target,
            fov_y,
        } => {
            let forward = normalize(sub(target, position));
            let right = normalize(cross(&forward, &[0.0, 0.0, 1.0]));
            let up = cross(&right, &forward);
            let half_height = (fov_y.to_radians() / 2.0).tan();
            let half_width = half_height * width as f64 / height.max(1) as f64;
            let u = (column as f64 + 0.5) / width as f64 * 2.0 - 1.0;
            let v = 1.0 - (row as f64 + 0.5) / height as f64 * 2.0;
            let dir: V3<f64> = std::array::from_fn(|k| {
                forward[k] + right[k] * u * half_width + up[k] * v * half_height
            });
            (*position, dir)
        }
    }
}

fn normalize(v: V3<f64>) -> V3<f64> {
    let length = dot(&v, &v).sqrt();
    if length == 0.0 {
        v
    } else {
        v.map(|c| c / length)
    }
}

/// Renders the scene with a method, computing only what its effects need.
///
/// `moller-trumbore` takes the batched path: each row's rays are tested against each triangle by the
/// vectorised f32 kernel ([`crate::accuracy::batch::intersect_rays`]). Every other method tests ray by
/// ray in f64 through the study's implementation.
pub fn render(scene: &RenderScene, method: Method) -> (Image, Stats) {
    if method == Method::MollerTrumbore {
        return render_batched(scene);
    }
    let (width, height) = (scene.width, scene.height);
    let shader = Shader::new(scene);
    let rows: Vec<Row> = (0..height)
        .into_par_iter()
        .map(|row| {
            let mut stats = Stats::default();
            let mut pixels = Vec::with_capacity(width);
            let mut covered = Vec::with_capacity(width);
            for column in 0..width {
                let (origin, dir) = camera_ray(&scene.camera, width, height, row, column);
                stats.rays += 1;
                let hit = nearest_hit(scene, method, origin, dir, &mut stats);
                covered.push(hit.is_some());
                pixels.push(match hit {
                    None => [0.0; 3],
                    Some(hit) => {
                        stats.hits += 1;
                        shader.shade(scene, &hit, dir, &mut stats)
                    }
                });
            }
            (pixels, covered, stats)
        })
        .collect();
    assemble(width, height, rows)
}

fn assemble(width: usize, height: usize, rows: Vec<Row>) -> (Image, Stats) {
    let mut image = Image {
        width,
        height,
        pixels: Vec::with_capacity(width * height),
        covered: Vec::with_capacity(width * height),
    };
    let mut stats = Stats::default();
    for (pixels, covered, row_stats) in rows {
        image.pixels.extend(pixels);
        image.covered.extend(covered);
        stats = stats.add(row_stats);
    }
    (image, stats)
}

/// One rendered row: colours, coverage, and the work it took.
type Row = (Vec<[f32; 3]>, Vec<bool>, Stats);

/// One row of rays in f32, as structures of arrays.
struct RowRays {
    origin: [Vec<f32>; 3],
    dir: [Vec<f32>; 3],
}

fn fill_row_rays(camera: &Camera, width: usize, height: usize, row: usize, rays: &mut RowRays) {
    match camera {
        // The image plane row in one vectorisable loop: x moves, y and z are fixed.
        Camera::ImagePlane { x, y, z } => {
            let along_y = if height <= 1 {
                y.0
            } else {
                y.0 + (y.1 - y.0) * row as f64 / (height - 1) as f64
            };
            let step = if width <= 1 {
                0.0
            } else {
                (x.1 - x.0) / (width - 1) as f64
            };
            let (py, pz) = (along_y as f32, *z as f32);
            let [ox, oy, oz] = &mut rays.origin;
            let [dx, dy, dz] = &mut rays.dir;
            // Every slice exactly `width` long, so the loop has no bounds checks and vectorises.
            let (ox, oy, oz) = (&mut ox[..width], &mut oy[..width], &mut oz[..width]);
            let (dx, dy, dz) = (&mut dx[..width], &mut dy[..width], &mut dz[..width]);
            for i in 0..width {
                let px = (x.0 + step * i as f64) as f32;
                let inverse_length = 1.0 / (px * px + py * py + pz * pz).sqrt();
                ox[i] = px;
                oy[i] = py;
                oz[i] = pz;
                dx[i] = px * inverse_length;
                dy[i] = py * inverse_length;
                dz[i] = pz * inverse_length;
            }
        }
        Camera::Pinhole { .. } => {
            for column in 0..width {
                let (origin, dir) = camera_ray(camera, width, height, row, column);
                for k in 0..3 {
                    rays.origin[k][column] = origin[k] as f32;
                    rays.dir[k][column] = dir[k] as f32;
                }
            }
        }
    }
}

/// The batched path: rows in parallel, each row's rays against each triangle in one vector loop.
fn render_batched(scene: &RenderScene) -> (Image, Stats) {
    use crate::accuracy::batch::{Nearest, RayBatch, intersect_rays};
    let (width, height) = (scene.width, scene.height);
    let shader = Shader::new(scene);
    let triangles: Vec<[[f32; 3]; 3]> = scene
        .triangles
        .iter()
        .map(|t| t.vertices.map(|v| v.map(|c| c as f32)))
        .collect();
    let mut pixels = vec![[0.0f32; 3]; width * height];
    let mut covered = vec![false; width * height];
    // Rows write straight into the image; each worker thread reuses one set of row buffers.
    let stats = pixels
        .par_chunks_mut(width.max(1))
        .zip(covered.par_chunks_mut(width.max(1)))
        .enumerate()
        .map_init(
            || RowBuffers::new(width),
            |buffers, (row, (pixels, covered))| {
                buffers.reset();
                fill_row_rays(&scene.camera, width, height, row, &mut buffers.rays);
                let rays = &buffers.rays;
                let batch = RayBatch {
                    origin: [&rays.origin[0], &rays.origin[1], &rays.origin[2]],
                    dir: [&rays.dir[0], &rays.dir[1], &rays.dir[2]],
                };
                let mut nearest = Nearest {
                    t: &mut buffers.t,
                    beta: &mut buffers.beta,
                    gamma: &mut buffers.gamma,
                    index: &mut buffers.index,
                };
                for (i, triangle) in triangles.iter().enumerate() {
                    intersect_rays(*triangle, i as u32, &batch, &mut nearest);
                }
                let mut stats = Stats {
                    rays: width as u64,
                    triangle_tests: (width * triangles.len()) as u64,
                    ..Stats::default()
                };
                for column in 0..width {
                    let index = buffers.index[column];
                    covered[column] = index != u32::MAX;
                    if index != u32::MAX {
                        stats.hits += 1;
                        let hit = Hit {
                            triangle: index as usize,
                            t: buffers.t[column] as f64,
                            beta: buffers.beta[column] as f64,
                            gamma: buffers.gamma[column] as f64,
                        };
                        let dir = [
                            rays.dir[0][column],
                            rays.dir[1][column],
                            rays.dir[2][column],
                        ]
                        .map(f64::from);
                        pixels[column] = shader.shade(scene, &hit, dir, &mut stats);
                    }
                }
                stats
            },
        )
        .reduce(Stats::default, |a, b| a.add(b));
    (
        Image {
            width,
            height,
            pixels,
            covered,
        },
        stats,
    )
}

/// One worker's buffers for a row: its rays and the nearest hits so far.
struct RowBuffers {
    rays: RowRays,
    t: Vec<f32>,
    beta: Vec<f32>,
    gamma: Vec<f32>,
    index: Vec<u32>,
}

impl RowBuffers {
    fn new(width: usize) -> RowBuffers {
        RowBuffers {
            rays: RowRays {
                origin: std::array::from_fn(|_| vec![0.0; width]),
                dir: std::array::from_fn(|_| vec![0.0; width]),
            },
            t: vec![f32::INFINITY; width],
            beta: vec![0.0; width],
            gamma: vec![0.0; width],
            index: vec![u32::MAX; width],
        }
    }

    fn reset(&mut self) {
        self.t.fill(f32::INFINITY);
        self.index.fill(u32::MAX);
    }
}

/// The nearest hit along a ray.
struct Hit {
    triangle: usize,
    t: f64,
    beta: f64,
    gamma: f64,
}

fn nearest_hit(
    scene: &RenderScene,
    method: Method,
    origin: V3<f64>,
    dir: V3<f64>,
    stats: &mut Stats,
) -> Option<Hit> {
    let mut best: Option<Hit> = None;
    for (index, triangle) in scene.triangles.iter().enumerate() {
        stats.triangle_tests += 1;
        let case = Case {
            tri: triangle.vertices,
            origin,
            dir,
        };
        let answer = method.run(&case);
        if let (true, Some([t, beta, gamma])) = (answer.hit, answer.values)
            && best.as_ref().is_none_or(|b| t < b.t)
        {
            best = Some(Hit {
                triangle: index,
                t,
                beta,
                gamma,
            });
        }
    }
    best
}

/// What the effects need at a hit, decided once per render: which effects, and each triangle's unit
/// normal (only when facing-ratio is called for).
struct Shader {
    depth: bool,
    color: bool,
    facing: bool,
    normals: Vec<V3<f64>>,
}

impl Shader {
    fn new(scene: &RenderScene) -> Shader {
        let wants = |e: Effect| scene.effects.contains(&e);
        let facing = wants(Effect::FacingRatio);
        let normals = if facing {
            scene
                .triangles
                .iter()
                .map(|t| {
                    let [a, b, c] = &t.vertices;
                    normalize(cross(&sub(b, a), &sub(c, a)))
                })
                .collect()
        } else {
            Vec::new()
        };
        Shader {
            depth: wants(Effect::Depth),
            color: wants(Effect::BarycentricColor),
            facing,
            normals,
        }
    }

    /// The colour of a hit; counts the interpolations and shading it does.
    fn shade(&self, scene: &RenderScene, hit: &Hit, dir: V3<f64>, stats: &mut Stats) -> [f32; 3] {
        let triangle = &scene.triangles[hit.triangle];
        let mut color = [1.0f64; 3];
        if self.depth {
            let distance = hit.t * dot(&dir, &dir).sqrt();
            color = [1.0 / (1.0 + 0.1 * distance); 3];
        }
        if self.color
            && let Some(colors) = triangle.colors
        {
            stats.interpolations += 1;
            let alpha = 1.0 - hit.beta - hit.gamma;
            color = std::array::from_fn(|k| {
                alpha * colors[0][k] + hit.beta * colors[1][k] + hit.gamma * colors[2][k]
            });
        }
        if self.facing {
            stats.shading += 1;
            // The facing ratio n̂ · (−ê) of seed 003, with ê the unit ray direction.
            let facing = -dot(&self.normals[hit.triangle], &dir) / dot(&dir, &dir).sqrt();
            color = std::array::from_fn(|k| triangle.color[k] * facing.max(0.0));
        }
        color.map(|c| c as f32)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn one_triangle(effects: Vec<Effect>) -> RenderScene {
        RenderScene {
            title: "t".into(),
            note: "n".into(),
            width: 32,
            height: 16,
            camera: Camera::ImagePlane {
                x: (1.0, -1.0),
                y: (0.5, -0.5),
                z: 1.0,
            },
            triangles: vec![Triangle {
                vertices: [[0.0, 1.25, 3.0], [2.0, -1.25, 3.0], [-2.0, -1.25, 3.0]],
                colors: Some([[1.0, 0.0, 0.4], [0.4, 1.0, 0.0], [0.0, 0.4, 1.0]]),
                color: [0.15, 0.35, 0.9],
            }],
            effects,
        }
    }

    #[test]
    fn effects_not_called_for_cost_nothing() {
        let (image, coverage) = render(&one_triangle(vec![Effect::Coverage]), Method::Watertight);
        assert!(image.covered_pixels() > 0);
        assert_eq!(coverage.rays, 32 * 16);
        assert_eq!(coverage.triangle_tests, 32 * 16);
        assert_eq!((coverage.interpolations, coverage.shading), (0, 0));
        let (_, colored) = render(
            &one_triangle(vec![Effect::BarycentricColor]),
            Method::Watertight,
        );
        assert_eq!(colored.interpolations, colored.hits);
        assert_eq!(colored.shading, 0);
        let (_, shaded) = render(&one_triangle(vec![Effect::FacingRatio]), Method::Watertight);
        assert_eq!((shaded.interpolations, shaded.shading), (0, shaded.hits));
    }

    #[test]
    fn image_plane_rays_match_seed_003() {
        let camera = Camera::ImagePlane {
            x: (1.0, -1.0),
            y: (0.5, -0.5),
            z: 1.0,
        };
        let (origin, dir) = camera_ray(&camera, 512, 256, 0, 0);
        assert_eq!(origin, [1.0, 0.5, 1.0]);
        assert!((dot(&dir, &dir) - 1.0).abs() < 1e-15);
        let (origin, _) = camera_ray(&camera, 512, 256, 255, 511);
        assert_eq!(origin, [-1.0, -0.5, 1.0]);
    }
}
