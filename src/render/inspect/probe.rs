//! The pixel probe: what happened to one pixel's ray, for loading into the Triangle view.

use crate::intersect::Method;
use crate::math::linalg::V3;
use crate::render::cast::{nearest_hit, to_object_space};
use crate::render::objects::Geometry;
use crate::render::shading::shade::Shader;
use crate::render::{Hit, Ray};
use crate::render::{Prepared, Stats, world_triangle};

/// One pixel's story.
#[derive(Clone, Debug, PartialEq)]
pub struct Probe {
    /// The pixel's row and column.
    pub pixel: (usize, usize),
    /// The ray's origin (world).
    pub origin: V3<f64>,
    /// The ray's direction through the pixel (world).
    pub dir: V3<f64>,
    /// The nearest hit, if any.
    pub hit: Option<Hit>,
    /// Without a hit: the triangle it came nearest to, as (object, triangle).
    pub nearest_miss: Option<(usize, usize)>,
    /// The triangle (hit or nearest missed) in world space, when it is a triangle.
    pub triangle: Option<[V3<f64>; 3]>,
    /// n̂ · (−ê) at the hit, when the scene shades.
    pub facing: Option<f64>,
    /// The pixel's colour, as the render gives it.
    pub color: [f32; 3],
}

/// Casts the ray through (row, column) and reports what it met.
pub fn probe(prepared: &Prepared, row: usize, column: usize) -> Probe {
    let ray = prepared.ray(row, column);
    let Ray { origin, dir } = ray;
    let mut stats = Stats::default();
    let hit = nearest_hit(prepared, ray, &mut stats);
    // Lit scenes and the effects past ray casting: the render's own pixel, lights, shadows, mirrors,
    // glass, occlusion and antialiasing's mean included.
    let traced = crate::render::secondary::applies(prepared).then(|| {
        crate::render::secondary::SecondaryCaster::new(prepared)
            .pixel((row, column), ray, hit, &mut stats)
            .map(|c| c as f32)
    });
    let shading = hit.map(|hit| {
        let inverse_length = 1.0 / crate::math::linalg::dot(&dir, &dir).sqrt();
        Shader::new(&prepared.effects).shade(
            &prepared.objects[hit.object],
            &hit,
            &dir,
            inverse_length,
            &mut stats,
        )
    });
    let nearest_miss = match hit {
        Some(_) => None,
        None => nearest_missed(prepared, ray),
    };
    let target = hit.map(|h| (h.object, h.primitive)).or(nearest_miss);
    Probe {
        pixel: (row, column),
        origin,
        dir,
        hit,
        nearest_miss,
        triangle: target.and_then(|(o, p)| world_triangle(&prepared.objects[o], p)),
        facing: shading.and_then(|s| s.facing),
        color: traced.unwrap_or(shading.map_or([0.0; 3], |s| s.color)),
    }
}

/// The triangle whose plane the ray meets closest to the triangle (in barycentric terms: how far
/// β, γ and 1 − β − γ are below zero), preferring ones in front of the ray.
fn nearest_missed(prepared: &Prepared, ray: Ray) -> Option<(usize, usize)> {
    let mut best: Option<((bool, f64), (usize, usize))> = None;
    for (o, object) in prepared.objects.iter().enumerate() {
        let Geometry::Triangles { triangles, .. } = &object.geometry else {
            continue;
        };
        let local = to_object_space(object, ray, None, &mut Stats::default());
        for (p, triangle) in triangles.iter().enumerate() {
            let case = crate::intersect::Case {
                tri: triangle.vertices,
                origin: local.origin,
                dir: local.dir,
            };
            let Some([t, beta, gamma]) = Method::Cramer.run(&case).values else {
                continue;
            };
            let outside = [beta, gamma, 1.0 - beta - gamma]
                .iter()
                .map(|w| (-w).max(0.0))
                .sum::<f64>();
            let key = (t <= 0.0, outside);
            if best.is_none_or(|(b, _)| key < b) {
                best = Some((key, (o, p)));
            }
        }
    }
    best.map(|(_, target)| target)
}
