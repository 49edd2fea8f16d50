//! The batched coverage path: when every object is an untransformed triangle tested by
//! Möller–Trumbore, a row's rays go through the vectorised f32 kernel
//! ([`crate::accuracy::batch::intersect_rays`]) one triangle at a time, and only the hits are shaded.

use std::cell::RefCell;

use super::cast::Hit;
use super::objects::Geometry;
use super::shade::Shader;
use super::{Camera, Prepared, Stats, camera_ray};
use crate::accuracy::Method;
use crate::accuracy::batch::{Nearest, RayBatch, intersect_rays};

/// True when the scene can take the batched path.
pub fn applies(prepared: &Prepared) -> bool {
    prepared.bug.is_none()
        && prepared.objects.iter().all(|object| {
            object.world_to_object.is_none()
                && matches!(&object.geometry, Geometry::Triangles { bvh: None, .. })
                && prepared.method_for(object) == Method::MollerTrumbore
        })
}

/// One row of rays in f32, as structures of arrays, and the nearest hits so far.
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

/// Fills a row's rays in f32.
fn fill_row_rays(camera: &Camera, width: usize, height: usize, row: usize, rays: &mut RowBuffers) {
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

/// 1/|dir| for a row of rays, in one vector loop (shading divides by it for every hit).
fn inverse_lengths(rays: &mut RowBuffers) {
    let n = rays.inverse_length.len();
    let [dx, dy, dz] = &rays.dir;
    let (dx, dy, dz) = (&dx[..n], &dy[..n], &dz[..n]);
    for (i, out) in rays.inverse_length.iter_mut().enumerate() {
        *out = 1.0 / (dx[i] * dx[i] + dy[i] * dy[i] + dz[i] * dz[i]).sqrt();
    }
}

/// Renders rows from `first` into `pixels` and `covered` (whole rows).
pub fn render_rows(
    prepared: &Prepared,
    first: usize,
    pixels: &mut [[f32; 3]],
    covered: &mut [bool],
) -> Stats {
    let (width, height) = (prepared.width, prepared.height);
    let shader = Shader::new(&prepared.effects);
    // (object, triangle) per kernel index, and the triangle in f32.
    let mut triangles = Vec::new();
    for (o, object) in prepared.objects.iter().enumerate() {
        if let Geometry::Triangles {
            triangles: list, ..
        } = &object.geometry
        {
            for (p, triangle) in list.iter().enumerate() {
                triangles.push(((o, p), triangle.vertices.map(|v| v.map(|c| c as f32))));
            }
        }
    }
    let mut stats = Stats::default();
    BUFFERS.with_borrow_mut(|buffers| {
        for (i, (pixels, covered)) in pixels
            .chunks_mut(width)
            .zip(covered.chunks_mut(width))
            .enumerate()
        {
            buffers.reset(width);
            fill_row_rays(&prepared.camera, width, height, first + i, buffers);
            inverse_lengths(buffers);
            let RowBuffers {
                origin,
                dir,
                inverse_length,
                t,
                beta,
                gamma,
                index,
            } = buffers;
            let batch = RayBatch {
                origin: [&origin[0], &origin[1], &origin[2]],
                dir: [&dir[0], &dir[1], &dir[2]],
            };
            let mut nearest = Nearest {
                t,
                beta,
                gamma,
                index,
            };
            for (k, (_, triangle)) in triangles.iter().enumerate() {
                intersect_rays(*triangle, k as u32, &batch, &mut nearest);
            }
            stats.rays += width as u64;
            stats.triangle_tests += (width * triangles.len()) as u64;
            for column in 0..width {
                let k = index[column];
                if k == u32::MAX {
                    continue;
                }
                stats.hits += 1;
                covered[column] = true;
                let ((object, primitive), _) = triangles[k as usize];
                let hit = Hit {
                    object,
                    primitive,
                    t: t[column] as f64,
                    beta: beta[column] as f64,
                    gamma: gamma[column] as f64,
                };
                let ray_dir = [dir[0][column], dir[1][column], dir[2][column]].map(f64::from);
                let object = &prepared.objects[object];
                let inverse_length = f64::from(inverse_length[column]);
                pixels[column] = shader
                    .shade(object, &hit, &ray_dir, inverse_length, &mut stats)
                    .color;
            }
        }
    });
    stats
}
