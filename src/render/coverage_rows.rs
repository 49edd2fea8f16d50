//! The coverage rows: when every object is an untransformed triangle tested by
//! Möller–Trumbore, a row's rays go through the vectorised f32 kernel
//! ([`crate::intersect::soa::intersect_rays`]) one triangle at a time, and only the hits are shaded.

use std::cell::RefCell;

use super::objects::Geometry;
use super::shading::shade::Shader;
use super::{At, Hit, Ray};
use std::ops::Range;

use super::{Basis, Camera, Prepared, Stats, camera_ray, pinhole_basis};
use crate::intersect::Method;
use crate::intersect::soa::{Nearest, RaysSoA, intersect_rays};
use crate::math::linalg::dot;

/// True when the scene can take the coverage rows.
pub fn applies(prepared: &Prepared) -> bool {
    prepared.bug.is_none()
        && prepared.objects.iter().all(|object| {
            object.object_from_world.is_none()
                && matches!(&object.geometry, Geometry::Triangles { bvh: None, .. })
                && prepared.method_for(object) == Method::MollerTrumbore
        })
}

/// One row of rays in f32, as structures of arrays, and the nearest hits so far.
#[derive(Default)]
struct RowBuffers {
    origin: [Vec<f32>; 3],
    dir: [Vec<f32>; 3],
    /// 1/|dir| per ray, for shading.
    inverse_length: Vec<f32>,
    t: Vec<f32>,
    beta: Vec<f32>,
    gamma: Vec<f32>,
    index: Vec<u32>,
}

impl RowBuffers {
    /// Tests the rays in `columns` against one triangle (kernel index `k`), keeping the nearest hits.
    #[inline(always)]
    fn intersect(&mut self, triangle: [[f32; 3]; 3], k: u32, columns: Range<usize>) {
        let s = columns;
        let (origin, dir) = (&self.origin, &self.dir);
        let rays = RaysSoA {
            origin: [
                &origin[0][s.clone()],
                &origin[1][s.clone()],
                &origin[2][s.clone()],
            ],
            dir: [&dir[0][s.clone()], &dir[1][s.clone()], &dir[2][s.clone()]],
        };
        let mut nearest = Nearest {
            t: &mut self.t[s.clone()],
            beta: &mut self.beta[s.clone()],
            gamma: &mut self.gamma[s.clone()],
            index: &mut self.index[s],
        };
        intersect_rays(triangle, k, &rays, &mut nearest);
    }

    /// Sized for `width` rays, with no hits yet.
    fn reset(&mut self, width: usize) {
        for v in self.origin.iter_mut().chain(self.dir.iter_mut()) {
            v.resize(width, 0.0);
        }
        for v in [&mut self.beta, &mut self.gamma, &mut self.inverse_length] {
            v.resize(width, 0.0);
        }
        self.t.clear();
        self.t.resize(width, f32::INFINITY);
        self.index.clear();
        self.index.resize(width, u32::MAX);
    }
}

thread_local! {
    /// Each worker thread reuses one set of row buffers.
    static BUFFERS: RefCell<RowBuffers> = const {
        RefCell::new(RowBuffers {
            origin: [Vec::new(), Vec::new(), Vec::new()],
            dir: [Vec::new(), Vec::new(), Vec::new()],
            inverse_length: Vec::new(),
            t: Vec::new(),
            beta: Vec::new(),
            gamma: Vec::new(),
            index: Vec::new(),
        })
    };
}

/// Fills a row's rays in f32, for the columns in `columns` (the others are not tested).
#[inline(always)]
fn fill_row_rays(
    camera: &Camera,
    (width, height): (usize, usize),
    row: usize,
    columns: Range<usize>,
    rays: &mut RowBuffers,
) {
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
            // Every slice exactly as long as the range, so the loop has no bounds checks and vectorises.
            let c = columns.clone();
            let (ox, oy, oz) = (&mut ox[c.clone()], &mut oy[c.clone()], &mut oz[c.clone()]);
            let (dx, dy, dz) = (&mut dx[c.clone()], &mut dy[c.clone()], &mut dz[c.clone()]);
            // The directions are unit by construction.
            rays.inverse_length[c].fill(1.0);
            for i in 0..columns.len() {
                let px = (x.0 + step * (columns.start + i) as f64) as f32;
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
            for column in columns {
                let Ray { origin, dir } = camera_ray(camera, width, height, row, column);
                for k in 0..3 {
                    rays.origin[k][column] = origin[k] as f32;
                    rays.dir[k][column] = dir[k] as f32;
                }
            }
            inverse_lengths(rays);
        }
    }
}

/// Where a triangle's vertices land on the image, in (column, row) units, when every ray passes
/// through one point (the pinhole, or the origin for seed 003's image plane, whose rays are the lines
/// from the origin through each pixel) and the triangle is wholly in front of it; `None` otherwise
/// (then every column is tested).
pub fn projected(
    camera: &Camera,
    (width, height): (usize, usize),
    vertices: &[[f64; 3]; 3],
) -> Option<[[f64; 2]; 3]> {
    let corner = |v: &[f64; 3]| -> Option<[f64; 2]> {
        match camera {
            Camera::ImagePlane { x, y, z } => {
                if *z <= 0.0 || v[2] <= 0.0 || x.0 == x.1 || y.0 == y.1 || width < 2 || height < 2 {
                    return None;
                }
                let (px, py) = (v[0] * z / v[2], v[1] * z / v[2]);
                Some([
                    (px - x.0) / (x.1 - x.0) * (width - 1) as f64,
                    (py - y.0) / (y.1 - y.0) * (height - 1) as f64,
                ])
            }
            Camera::Pinhole { .. } => {
                // The pixel's ray is forward + u·half_width·right + v·half_height·up.
                let Basis {
                    origin,
                    forward,
                    right,
                    up,
                    half_width,
                    half_height,
                } = pinhole_basis(camera, width, height)?;
                let d: [f64; 3] = std::array::from_fn(|k| v[k] - origin[k]);
                let depth = dot(&d, &forward);
                if depth <= 0.0 {
                    return None;
                }
                let u = dot(&d, &right) / (depth * half_width);
                let v = dot(&d, &up) / (depth * half_height);
                Some([
                    (u + 1.0) / 2.0 * width as f64 - 0.5,
                    (1.0 - v) / 2.0 * height as f64 - 0.5,
                ])
            }
        }
    };
    let [a, b, c] = vertices;
    let corners = [corner(a)?, corner(b)?, corner(c)?];
    corners
        .iter()
        .flatten()
        .all(|c| c.is_finite())
        .then_some(corners)
}

/// The columns whose rays can hit a triangle whose corners land at `corners`, in `row`: the columns
/// the triangle spans within one row either side, two more each side for rounding.
pub fn column_span(corners: &[[f64; 2]; 3], row: usize, width: usize) -> Range<usize> {
    let (low, high) = (row as f64 - 1.0, row as f64 + 1.0);
    let (mut left, mut right) = (f64::INFINITY, f64::NEG_INFINITY);
    for k in 0..3 {
        let ([xa, ya], [xb, yb]) = (corners[k], corners[(k + 1) % 3]);
        // The part of edge a→b inside the band low ≤ y ≤ high, as parameters s in [0, 1].
        let (s0, s1) = if ya == yb {
            if ya < low || ya > high {
                continue;
            }
            (0.0, 1.0)
        } else {
            let (sl, sh) = ((low - ya) / (yb - ya), (high - ya) / (yb - ya));
            (sl.min(sh).max(0.0), sl.max(sh).min(1.0))
        };
        if s0 > s1 {
            continue;
        }
        for s in [s0, s1] {
            let x = xa + (xb - xa) * s;
            left = left.min(x);
            right = right.max(x);
        }
    }
    if left > right {
        return 0..0;
    }
    let start = (left.floor() - 2.0).clamp(0.0, width as f64) as usize;
    let end = (right.ceil() + 3.0).clamp(0.0, width as f64) as usize;
    start..end.max(start)
}

/// 1/|dir| for a row of rays, in one vector loop (shading divides by it for every hit).
#[inline(always)]
fn inverse_lengths(rays: &mut RowBuffers) {
    let n = rays.inverse_length.len();
    let [dx, dy, dz] = &rays.dir;
    let (dx, dy, dz) = (&dx[..n], &dy[..n], &dz[..n]);
    for (i, out) in rays.inverse_length.iter_mut().enumerate() {
        *out = 1.0 / (dx[i] * dx[i] + dy[i] * dy[i] + dz[i] * dz[i]).sqrt();
    }
}

/// Renders rows from `first` into `pixels` and `covered` (whole rows): with 8-wide AVX2 vectors where
/// [`Prepared::simd`] proves the processor has them (the same arithmetic, so the same image), else
/// with the baseline's 4-wide.
pub fn render_rows(
    prepared: &Prepared,
    first: usize,
    pixels: &mut [[f32; 3]],
    covered: &mut [bool],
) -> Stats {
    match prepared.simd {
        #[cfg(target_arch = "x86_64")]
        // SAFETY: an `Avx2` exists only on a processor with AVX2 (and FMA).
        #[allow(unsafe_code)]
        Some(avx2) => unsafe { render_rows_avx2(avx2, prepared, first, pixels, covered) },
        _ => render_rows_inlined(prepared, first, pixels, covered),
    }
}

/// The row loop compiled with AVX2 (a kernel: see [`super::kernels`]). FMA is left off, as it
/// always was here: the loop's arithmetic is the baseline's.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn render_rows_avx2(
    _: super::kernels::Avx2,
    prepared: &Prepared,
    first: usize,
    pixels: &mut [[f32; 3]],
    covered: &mut [bool],
) -> Stats {
    render_rows_inlined(prepared, first, pixels, covered)
}

/// The row loop itself, inlined into each of the two builds above.
#[inline(always)]
fn render_rows_inlined(
    prepared: &Prepared,
    first: usize,
    pixels: &mut [[f32; 3]],
    covered: &mut [bool],
) -> Stats {
    let (width, height) = (prepared.width, prepared.height);
    let shader = Shader::new(&prepared.effects);
    // (object, triangle) per kernel index, the triangle in f32, and where it lands on the image.
    let mut triangles = Vec::new();
    for (o, object) in prepared.objects.iter().enumerate() {
        if let Geometry::Triangles {
            triangles: list, ..
        } = &object.geometry
        {
            for (p, triangle) in list.iter().enumerate() {
                let corners = projected(&prepared.camera, (width, height), &triangle.vertices);
                let f32_vertices = triangle.vertices.map(|v| v.map(|c| c as f32));
                triangles.push(((o, p), f32_vertices, corners));
            }
        }
    }
    let mut stats = Stats::default();
    let mut spans: Vec<Range<usize>> = Vec::with_capacity(triangles.len());
    // Out of the thread-local and back, not inside a closure: the loop must stay in this function to
    // be compiled with its vector width.
    let mut buffers = BUFFERS.take();
    {
        let buffers = &mut buffers;
        for (i, (pixels, covered)) in pixels
            .chunks_mut(width)
            .zip(covered.chunks_mut(width))
            .enumerate()
        {
            buffers.reset(width);
            // Each triangle is tested only on the columns it can cover in this row; rays are made
            // for the columns some triangle needs.
            let row = first + i;
            spans.clear();
            spans.extend(triangles.iter().map(|(_, _, corners)| match corners {
                Some(corners) => column_span(corners, row, width),
                None => 0..width,
            }));
            let needed = spans
                .iter()
                .filter(|s| !s.is_empty())
                .fold(None, |all: Option<Range<usize>>, s| {
                    Some(all.map_or(s.clone(), |a| a.start.min(s.start)..a.end.max(s.end)))
                })
                .unwrap_or(0..0);
            fill_row_rays(&prepared.camera, (width, height), row, needed, buffers);
            for (k, ((_, triangle, _), span)) in triangles.iter().zip(&spans).enumerate() {
                buffers.intersect(*triangle, k as u32, span.clone());
                stats.triangle_tests += span.len() as u64;
            }
            let RowBuffers {
                dir,
                inverse_length,
                t,
                beta,
                gamma,
                index,
                ..
            } = &*buffers;
            stats.rays += width as u64;
            for column in 0..width {
                let k = index[column];
                if k == u32::MAX {
                    continue;
                }
                stats.hits += 1;
                covered[column] = true;
                let ((object, primitive), _, _) = triangles[k as usize];
                let hit = Hit {
                    object,
                    primitive,
                    t: t[column] as f64,
                    at: At::Triangle {
                        beta: beta[column] as f64,
                        gamma: gamma[column] as f64,
                    },
                };
                let ray_dir = [dir[0][column], dir[1][column], dir[2][column]].map(f64::from);
                let object = &prepared.objects[object];
                let inverse_length = f64::from(inverse_length[column]);
                pixels[column] = shader
                    .shade(object, &hit, &ray_dir, inverse_length, &mut stats)
                    .color;
            }
        }
    }
    BUFFERS.set(buffers);
    stats
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};

    /// The nearest hits of one row, every triangle tested on `columns(k)` only.
    fn row_hits(
        camera: &Camera,
        size: (usize, usize),
        row: usize,
        triangles: &[[[f64; 3]; 3]],
        columns: impl Fn(usize) -> Range<usize>,
    ) -> (Vec<u32>, Vec<f32>) {
        let mut buffers = RowBuffers::default();
        buffers.reset(size.0);
        fill_row_rays(camera, size, row, 0..size.0, &mut buffers);
        for (k, triangle) in triangles.iter().enumerate() {
            buffers.intersect(triangle.map(|v| v.map(|c| c as f32)), k as u32, columns(k));
        }
        (buffers.index, buffers.t)
    }

    /// Testing each triangle only on its columns finds exactly the hits that testing every column
    /// finds, for both cameras, triangles in front, across the edge of the image, and behind.
    #[test]
    fn column_spans_lose_no_hit() {
        let mut random = rand_pcg::Pcg64::seed_from_u64(3);
        let cameras = [
            Camera::ImagePlane {
                x: (1.0, -1.0),
                y: (0.5, -0.5),
                z: 1.0,
            },
            Camera::Pinhole {
                position: [0.0, -4.0, 1.0],
                target: [0.0, 0.0, 0.5],
                fov_y: 50.0,
            },
        ];
        let size = (97, 61);
        let mut hits = 0;
        for camera in &cameras {
            for _ in 0..30 {
                let triangles: Vec<[[f64; 3]; 3]> = (0..3)
                    .map(|_| {
                        std::array::from_fn(|_| {
                            std::array::from_fn(|_| random.random_range(-4.0..6.0))
                        })
                    })
                    .collect();
                let corners: Vec<_> = triangles
                    .iter()
                    .map(|t| projected(camera, size, t))
                    .collect();
                for row in 0..size.1 {
                    let all = row_hits(camera, size, row, &triangles, |_| 0..size.0);
                    let spanned = row_hits(camera, size, row, &triangles, |k| match &corners[k] {
                        Some(c) => column_span(c, row, size.0),
                        None => 0..size.0,
                    });
                    assert_eq!(all, spanned, "row {row} of {triangles:?}");
                    hits += all.0.iter().filter(|i| **i != u32::MAX).count();
                }
            }
        }
        assert!(hits > 10_000, "the triangles are hit: {hits}");
    }
}
