//! Seeded, reproducible families of rays and triangles, from easy to hard.
//!
//! A probe is one ray and the triangles it is tested against: one triangle for most families, the two
//! halves of a quad for the seam sweep, and a closed fan for rays aimed at a shared vertex (where a
//! crack is a ray that hits none of them).

use rand::{Rng, SeedableRng};
use rand_pcg::Pcg64;
use serde::{Deserialize, Serialize};

use crate::intersect::Case;
use crate::math::linalg::{V3, add, cross, dot, scale, sub};

/// The families of the study.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Family {
    /// Random, well-conditioned rays and triangles, half aimed inside.
    Random,
    /// Rays through the shared diagonal of a triangulated quad.
    Seam,
    /// Rays aimed exactly at the vertex shared by a closed fan of triangles.
    Fan,
    /// Rays at angles 10^-1 … 10^-8 to the triangle's plane.
    Grazing,
    /// Triangles and rays offset from the origin by 10^0 … 10^8.
    FarAway,
    /// Everything scaled by 10^-20 … 10^20.
    Scales,
    /// Needles: one edge 10^-1 … 10^-7 times the others.
    Needle,
    /// Slivers: C within 10^-2 … 10^-12 of the line AB (near-degenerate).
    Sliver,
}

impl Family {
    /// Every family.
    pub const ALL: [Family; 8] = [
        Family::Random,
        Family::Seam,
        Family::Fan,
        Family::Grazing,
        Family::FarAway,
        Family::Scales,
        Family::Needle,
        Family::Sliver,
    ];

    /// The name in tables and JSON.
    pub fn name(self) -> &'static str {
        match self {
            Family::Random => "random",
            Family::Seam => "seam",
            Family::Fan => "fan",
            Family::Grazing => "grazing",
            Family::FarAway => "far-away",
            Family::Scales => "scales",
            Family::Needle => "needle",
            Family::Sliver => "sliver",
        }
    }

    /// True for the families where a ray should hit one of several triangles (cracks are counted).
    pub fn shares_geometry(self) -> bool {
        matches!(self, Family::Seam | Family::Fan)
    }
}

/// One ray and the triangles it meets.
#[derive(Clone, Debug, PartialEq)]
pub struct Probe {
    /// The triangles, as cases sharing the ray.
    pub cases: Vec<Case<f64>>,
    /// The family's knob for this probe: the grazing angle, the offset, the scale, the aspect.
    pub parameter: f64,
}

/// `count` probes of a family, the same for the same seed.
pub fn generate(family: Family, count: usize, seed: u64) -> Vec<Probe> {
    let mut rng = Pcg64::seed_from_u64(seed ^ (family as u64).wrapping_mul(0x9e37_79b9_7f4a_7c15));
    (0..count).map(|i| probe(family, i, &mut rng)).collect()
}

fn point(rng: &mut Pcg64, size: f64) -> V3<f64> {
    [
        rng.random_range(-size..size),
        rng.random_range(-size..size),
        rng.random_range(-size..size),
    ]
}

fn single(tri: [V3<f64>; 3], origin: V3<f64>, target: V3<f64>, parameter: f64) -> Probe {
    Probe {
        cases: vec![Case {
            tri,
            origin,
            dir: sub(&target, &origin),
        }],
        parameter,
    }
}

/// A ray to `target` from a random point above it (up to 2 aside, 1 to 4 up): origin and direction.
fn ray_from_above(rng: &mut Pcg64, target: &V3<f64>) -> (V3<f64>, V3<f64>) {
    let origin = add(
        target,
        &[
            rng.random_range(-2.0..2.0),
            rng.random_range(-2.0..2.0),
            rng.random_range(1.0..4.0),
        ],
    );
    (origin, sub(target, &origin))
}

/// A point of the triangle's plane at barycentrics (β, γ).
fn at(tri: &[V3<f64>; 3], beta: f64, gamma: f64) -> V3<f64> {
    let [a, b, c] = tri;
    add(
        &add(a, &scale(&beta, &sub(b, a))),
        &scale(&gamma, &sub(c, a)),
    )
}

/// Barycentrics inside the triangle half the time, and anywhere near it otherwise.
fn target_barycentrics(rng: &mut Pcg64, index: usize) -> (f64, f64) {
    if index.is_multiple_of(2) {
        let (u, v): (f64, f64) = (rng.random(), rng.random());
        if u + v > 1.0 {
            (1.0 - u, 1.0 - v)
        } else {
            (u, v)
        }
    } else {
        (rng.random_range(-0.5..1.5), rng.random_range(-0.5..1.5))
    }
}

fn probe(family: Family, index: usize, rng: &mut Pcg64) -> Probe {
    match family {
        Family::Random => {
            let tri = [point(rng, 1.0), point(rng, 1.0), point(rng, 1.0)];
            let (beta, gamma) = target_barycentrics(rng, index);
            let origin = point(rng, 4.0);
            single(tri, origin, at(&tri, beta, gamma), 1.0)
        }
        Family::Seam => {
            // A quad, gently bent along its diagonal v0–v2, split into (v0, v1, v2) and (v0, v2, v3).
            let v0 = point(rng, 1.0);
            let v2 = add(
                &v0,
                &[rng.random_range(1.0..2.0), rng.random_range(1.0..2.0), 0.3],
            );
            let v1 = add(
                &v0,
                &[
                    rng.random_range(1.0..2.0),
                    rng.random_range(-1.0..0.0),
                    rng.random_range(-0.3..0.3),
                ],
            );
            let v3 = add(
                &v0,
                &[
                    rng.random_range(-1.0..0.0),
                    rng.random_range(1.0..2.0),
                    rng.random_range(-0.3..0.3),
                ],
            );
            let u: f64 = rng.random_range(0.01..0.99);
            let target = add(&v0, &scale(&u, &sub(&v2, &v0)));
            let (origin, dir) = ray_from_above(rng, &target);
            Probe {
                cases: vec![
                    Case {
                        tri: [v0, v1, v2],
                        origin,
                        dir,
                    },
                    Case {
                        tri: [v0, v2, v3],
                        origin,
                        dir,
                    },
                ],
                parameter: u,
            }
        }
        Family::Fan => {
            // A closed fan of k triangles around a centre, its ring slightly out of plane.
            let centre = point(rng, 2.0);
            let k = rng.random_range(5..9);
            let phase: f64 = rng.random_range(0.0..1.0);
            let ring: Vec<V3<f64>> = (0..k)
                .map(|i| {
                    let angle = (i as f64 + phase) * std::f64::consts::TAU / k as f64;
                    let radius = rng.random_range(0.5..1.5);
                    add(
                        &centre,
                        &[
                            radius * angle.cos(),
                            radius * angle.sin(),
                            rng.random_range(-0.2..0.2),
                        ],
                    )
                })
                .collect();
            let (origin, dir) = ray_from_above(rng, &centre);
            Probe {
                // The shared vertex is each triangle's C, not A: with A = centre the lecture's
                // Y = A − L would equal D bit for bit, and the test would be trivially exact.
                cases: (0..k)
                    .map(|i| Case {
                        tri: [ring[i], ring[(i + 1) % k], centre],
                        origin,
                        dir,
                    })
                    .collect(),
                parameter: k as f64,
            }
        }
        Family::Grazing => {
            let angle = 10f64.powi(-((index % 8) as i32 + 1));
            let tri = [point(rng, 1.0), point(rng, 1.0), point(rng, 1.0)];
            let (beta, gamma) = target_barycentrics(rng, index / 8);
            let target = at(&tri, beta, gamma);
            // A direction at `angle` to the plane: mostly along the plane, a little along the normal.
            let normal = cross(&sub(&tri[1], &tri[0]), &sub(&tri[2], &tri[0]));
            let n = scale(&(1.0 / dot(&normal, &normal).sqrt()), &normal);
            let raw = point(rng, 1.0);
            let in_plane = sub(&raw, &scale(&dot(&raw, &n), &n));
            let h = scale(&(1.0 / dot(&in_plane, &in_plane).sqrt()), &in_plane);
            let dir = add(&scale(&angle.cos(), &h), &scale(&angle.sin(), &n));
            let origin = sub(&target, &scale(&2.0, &dir));
            single(tri, origin, target, angle)
        }
        Family::FarAway => {
            let offset = 10f64.powi((index % 9) as i32);
            let shift = [offset, offset * 0.7, -offset * 0.4];
            let tri = [point(rng, 1.0), point(rng, 1.0), point(rng, 1.0)].map(|p| add(&p, &shift));
            let (beta, gamma) = target_barycentrics(rng, index / 9);
            let origin = add(&point(rng, 4.0), &shift);
            single(tri, origin, at(&tri, beta, gamma), offset)
        }
        Family::Scales => {
            let factor = 10f64.powi((index % 9) as i32 * 5 - 20);
            let tri =
                [point(rng, 1.0), point(rng, 1.0), point(rng, 1.0)].map(|p| scale(&factor, &p));
            let (beta, gamma) = target_barycentrics(rng, index / 9);
            let origin = scale(&factor, &point(rng, 4.0));
            single(tri, origin, at(&tri, beta, gamma), factor)
        }
        Family::Needle => {
            let aspect = 10f64.powi(-((index % 7) as i32 + 1));
            let a = point(rng, 1.0);
            let b = add(&a, &scale(&aspect, &point(rng, 1.0)));
            let c = add(&a, &point(rng, 2.0));
            let tri = [a, b, c];
            let (beta, gamma) = target_barycentrics(rng, index / 7);
            let origin = point(rng, 4.0);
            single(tri, origin, at(&tri, beta, gamma), aspect)
        }
        Family::Sliver => {
            let closeness = 10f64.powi(-2 * ((index % 6) as i32 + 1));
            let a = point(rng, 1.0);
            let b = point(rng, 1.0);
            let mid = scale(&0.5, &add(&a, &b));
            let c = add(&mid, &scale(&closeness, &point(rng, 1.0)));
            let tri = [a, b, c];
            let (beta, gamma) = target_barycentrics(rng, index / 6);
            let origin = point(rng, 4.0);
            single(tri, origin, at(&tri, beta, gamma), closeness)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn families_are_reproducible_and_finite() {
        for family in Family::ALL {
            let a = generate(family, 50, 7);
            assert_eq!(a, generate(family, 50, 7));
            assert_ne!(a, generate(family, 50, 8));
            assert!(
                a.iter()
                    .flat_map(|p| &p.cases)
                    .all(crate::intersect::finite)
            );
        }
    }
}
