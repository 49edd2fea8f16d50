//! A bounding volume hierarchy over a mesh's triangles: boxes split at the median centroid of their
//! longest axis, down to a few triangles a leaf.
//!
//! The box test is conservative, so it never culls a triangle the exact test would hit: boxes are
//! padded, the slab distances are widened by a few ulps (as pbrt does), and a direction component that
//! is zero is handled without 0 · ∞.

use super::objects::PreparedTriangle;
use crate::math::linalg::V3;

/// Triangles per leaf, at most.
const LEAF_SIZE: usize = 4;

/// An axis-aligned box.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Bounds {
    min: V3<f64>,
    max: V3<f64>,
}

impl Bounds {
    const EMPTY: Bounds = Bounds {
        min: [f64::INFINITY; 3],
        max: [f64::NEG_INFINITY; 3],
    };

    fn grow(self, p: &V3<f64>) -> Bounds {
        Bounds {
            min: std::array::from_fn(|k| self.min[k].min(p[k])),
            max: std::array::from_fn(|k| self.max[k].max(p[k])),
        }
    }

    fn of(triangle: &PreparedTriangle) -> Bounds {
        triangle.vertices.iter().fold(Bounds::EMPTY, Bounds::grow)
    }

    fn union(self, other: Bounds) -> Bounds {
        self.grow(&other.min).grow(&other.max)
    }

    /// Widened by a relative margin, so rounding in the slab test cannot cull a touching ray.
    fn padded(self) -> Bounds {
        let margin = (0..3)
            .map(|k| self.max[k] - self.min[k])
            .fold(0.0f64, f64::max)
            * 1e-9
            + 1e-300;
        Bounds {
            min: self.min.map(|c| c - margin),
            max: self.max.map(|c| c + margin),
        }
    }

    /// Whether the ray o + t d meets the box for some t in [t_min, t_max]. A slab distance that is
    /// NaN (an overflow to ∞ met ∞, or a NaN in the ray or the box) is a miss: the ray enters or leaves
    /// the slab beyond any finite distance.
    fn hit(&self, origin: &V3<f64>, inverse_dir: &V3<f64>, t_min: f64, t_max: f64) -> bool {
        let (mut near, mut far) = (t_min, t_max);
        for k in 0..3 {
            if inverse_dir[k].is_infinite() {
                // Parallel to this slab: inside it or never (NaN: never).
                if !(origin[k] >= self.min[k] && origin[k] <= self.max[k]) {
                    return false;
                }
                continue;
            }
            let t0 = (self.min[k] - origin[k]) * inverse_dir[k];
            let t1 = (self.max[k] - origin[k]) * inverse_dir[k];
            let (t0, t1) = if t0 <= t1 { (t0, t1) } else { (t1, t0) };
            // Widen the distances by 2γ₃ so a rounded slab cannot cut off a touching ray.
            let widen = 2.0 * 3.0 * f64::EPSILON;
            let (t0, t1) = (t0 - t0.abs() * widen, t1 + t1.abs() * widen);
            if t0.is_nan() || t1.is_nan() {
                return false;
            }
            near = near.max(t0);
            far = far.min(t1);
            if near > far {
                return false;
            }
        }
        true
    }
}

/// A node: a box and either two children or a run of triangles.
#[derive(Clone, Debug)]
struct Node {
    bounds: Bounds,
    /// Leaf: first index into `order`; inner: the second child (the first follows this node).
    start_or_right: u32,
    /// Triangles in a leaf; 0 for an inner node.
    count: u32,
}

/// The hierarchy: nodes in depth-first order and the triangle order they refer to.
#[derive(Clone, Debug)]
pub struct Bvh {
    nodes: Vec<Node>,
    order: Vec<u32>,
}

impl Bvh {
    /// Builds the hierarchy over `triangles`.
    pub fn build(triangles: &[PreparedTriangle]) -> Bvh {
        let bounds: Vec<Bounds> = triangles.iter().map(Bounds::of).collect();
        let centroids: Vec<V3<f64>> = bounds
            .iter()
            .map(|b| std::array::from_fn(|k| (b.min[k] + b.max[k]) / 2.0))
            .collect();
        let mut bvh = Bvh {
            nodes: Vec::with_capacity(2 * triangles.len() / LEAF_SIZE + 1),
            order: (0..triangles.len() as u32).collect(),
        };
        bvh.split(0, triangles.len(), &bounds, &centroids);
        bvh
    }

    /// Adds the node for `order[start..end]` and, below it, its children.
    fn split(&mut self, start: usize, end: usize, bounds: &[Bounds], centroids: &[V3<f64>]) {
        let node_bounds = self.order[start..end]
            .iter()
            .fold(Bounds::EMPTY, |b, &i| b.union(bounds[i as usize]))
            .padded();
        let index = self.nodes.len();
        self.nodes.push(Node {
            bounds: node_bounds,
            start_or_right: start as u32,
            count: (end - start) as u32,
        });
        if end - start <= LEAF_SIZE {
            return;
        }
        let spread = self.order[start..end]
            .iter()
            .fold(Bounds::EMPTY, |b, &i| b.grow(&centroids[i as usize]));
        let axis = (0..3)
            .max_by(|&a, &b| {
                let extent = |k: usize| spread.max[k] - spread.min[k];
                extent(a).total_cmp(&extent(b))
            })
            .unwrap_or(0);
        let middle = (start + end) / 2;
        self.order[start..end].select_nth_unstable_by(middle - start, |&a, &b| {
            centroids[a as usize][axis].total_cmp(&centroids[b as usize][axis])
        });
        self.split(start, middle, bounds, centroids);
        let right = self.nodes.len() as u32;
        self.split(middle, end, bounds, centroids);
        self.nodes[index].start_or_right = right;
        self.nodes[index].count = 0;
    }

    /// Visits the triangles whose boxes the ray o + t d meets for t from `t_min` to the nearest hit
    /// so far. `test(triangle)` returns the triangle's t when it is hit; `box_tests` counts box tests.
    pub fn traverse(
        &self,
        origin: &V3<f64>,
        dir: &V3<f64>,
        t_min: f64,
        mut t_max: f64,
        box_tests: &mut u64,
        mut test: impl FnMut(usize) -> Option<f64>,
    ) {
        let inverse_dir = dir.map(|d| 1.0 / d);
        // Each node is visited at most once, and a median split halves the triangles at every level,
        // so the depth is at most 33 for u32 indices: the stack of 64 cannot overflow.
        let mut stack = [0u32; 64];
        let mut depth = 1;
        while depth > 0 {
            depth -= 1;
            let node = &self.nodes[stack[depth] as usize];
            *box_tests += 1;
            if !node.bounds.hit(origin, &inverse_dir, t_min, t_max) {
                continue;
            }
            if node.count > 0 {
                let start = node.start_or_right as usize;
                for &triangle in &self.order[start..start + node.count as usize] {
                    if let Some(t) = test(triangle as usize) {
                        t_max = t_max.min(t);
                    }
                }
            } else {
                let first = stack[depth] + 1;
                stack[depth] = node.start_or_right;
                stack[depth + 1] = first;
                depth += 2;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::assets::{Embedded, load_mesh};

    #[test]
    fn a_nan_box_is_a_miss() {
        let unit = Bounds {
            min: [0.0; 3],
            max: [1.0; 3],
        };
        let up = [f64::INFINITY, f64::INFINITY, 1.0];
        assert!(unit.hit(&[0.5, 0.5, -1.0], &up, 0.0, f64::INFINITY));
        let nan_box = Bounds {
            min: [f64::NAN; 3],
            max: [1.0; 3],
        };
        assert!(!nan_box.hit(&[0.5, 0.5, -1.0], &up, 0.0, f64::INFINITY));
        assert!(!unit.hit(&[f64::NAN, 0.5, -1.0], &up, 0.0, f64::INFINITY));
    }

    /// A ray from 1e308 whose slab distances overflow to ∞ (then ∞ − ∞ = NaN when widened) visits no
    /// triangle: before, NaN slabs were ignored and every triangle was tested, which with the exact
    /// fallback of the watertight method took minutes per image.
    #[test]
    fn overflowing_slab_distances_test_no_triangle() {
        let mesh = load_mesh(&Embedded, "meshes/octasphere.obj").unwrap();
        let bvh = Bvh::build(&mesh);
        let mut tested = 0;
        let mut box_tests = 0;
        let origin = [-1e308, -1e308, -1e308];
        bvh.traverse(
            &origin,
            &[1e-300, 1.0, 1e-300],
            0.0,
            f64::INFINITY,
            &mut box_tests,
            |_| {
                tested += 1;
                None
            },
        );
        assert_eq!(tested, 0);
        assert!(box_tests <= bvh.nodes.len() as u64);
    }

    /// Whatever the numbers (NaN, ∞, zero and huge components in the mesh and the ray), the traversal
    /// ends after at most one box test per node.
    #[test]
    fn traversal_ends_whatever_the_numbers() {
        let values = [
            0.0,
            -0.0,
            1.0,
            -1.0,
            1e-310,
            1e308,
            -1e308,
            f64::INFINITY,
            f64::NAN,
        ];
        let mut triangles = Vec::new();
        for (i, &a) in values.iter().enumerate() {
            for &b in &values {
                let c = values[(i * 5 + 3) % values.len()];
                triangles.push(PreparedTriangle::new([[a, b, c], [b, c, a], [c, a, b]]));
            }
        }
        let bvh = Bvh::build(&triangles);
        for &o in &values {
            for &d in &values {
                let mut box_tests = 0;
                let mut tests = 0;
                bvh.traverse(
                    &[o, 0.5, -o],
                    &[d, 1.0, -d],
                    0.0,
                    f64::INFINITY,
                    &mut box_tests,
                    |_| {
                        tests += 1;
                        Some(1.0)
                    },
                );
                assert!(box_tests <= bvh.nodes.len() as u64, "{o} {d}: {box_tests}");
                assert!(tests <= triangles.len(), "{o} {d}");
            }
        }
    }

    /// Every triangle a brute-force loop hits first is the one the BVH finds first (ties to the lower
    /// index, as the renderer breaks them).
    #[test]
    fn the_bvh_finds_what_brute_force_finds() {
        use crate::intersect::{Case, Method};
        let mesh = load_mesh(&Embedded, "meshes/octasphere.obj").unwrap();
        let bvh = Bvh::build(&mesh);
        let nearest = |origin: V3<f64>, dir: V3<f64>, through_bvh: bool| {
            let mut best: Option<(f64, usize)> = None;
            let mut test = |i: usize| {
                let case = Case {
                    tri: mesh[i].vertices,
                    origin,
                    dir,
                };
                let answer = Method::Watertight.run(&case);
                let t = answer.values.filter(|_| answer.hit)?[0];
                if best.is_none_or(|(b, bi)| t < b || (t == b && i < bi)) {
                    best = Some((t, i));
                }
                Some(t)
            };
            if through_bvh {
                bvh.traverse(&origin, &dir, 0.0, f64::INFINITY, &mut 0, test);
            } else {
                (0..mesh.len()).for_each(|i| {
                    test(i);
                });
            }
            best
        };
        let mut hits = 0;
        for i in 0..40 {
            for j in 0..40 {
                let origin = [0.0, -3.0, 0.0];
                // Includes rays exactly along the x = 0 and z = 0 seams (i, j = 20).
                let dir = [(i as f64 - 20.0) / 40.0, 1.0, (j as f64 - 20.0) / 40.0];
                let brute = nearest(origin, dir, false);
                assert_eq!(nearest(origin, dir, true), brute, "ray {dir:?}");
                hits += brute.is_some() as usize;
            }
        }
        assert!(hits > 400, "{hits}");
    }
}
