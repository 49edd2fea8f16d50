//! A ray and where it meets a primitive, named as the lecture names them: a ray o + t d, a triangle's
//! X = (β, γ, t) and a parallelogram's (α, β, t).

use crate::math::linalg::V3;

/// A ray o + t d. The direction is not normalised, so t means the same in world and object space
/// (see the crate's conventions).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    pub origin: V3<f64>,
    pub dir: V3<f64>,
}

impl Ray {
    /// The ray from `origin` along `dir`.
    #[inline(always)]
    pub const fn new(origin: V3<f64>, dir: V3<f64>) -> Ray {
        Ray { origin, dir }
    }

    /// True when every number of the ray is finite (the only rays a box test or the crack-free
    /// test takes).
    #[inline(always)]
    pub fn is_finite(&self) -> bool {
        // Each number's check and'ed without a branch: the chained iterator with `all` stayed a
        // loop of branches, called for every ray of a packet.
        let ([x, y, z], [dx, dy, dz]) = (self.origin, self.dir);
        (x.is_finite() & y.is_finite() & z.is_finite())
            & (dx.is_finite() & dy.is_finite() & dz.is_finite())
    }

    /// The point o + t d.
    #[inline(always)]
    pub fn at(&self, t: f64) -> V3<f64> {
        std::array::from_fn(|k| self.origin[k] + t * self.dir[k])
    }
}

/// The bit set of every ray of a packet of `P` (at most 32): bits 0 to P − 1.
#[inline(always)]
pub const fn all_rays<const P: usize>() -> u32 {
    u32::MAX >> (32 - P)
}

/// Where a ray meets a triangle: the lecture's X = (β, γ, t), the point A + β(B − A) + γ(C − A).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleHit {
    pub beta: f64,
    pub gamma: f64,
    pub t: f64,
}

impl TriangleHit {
    /// The hit from the three numbers in [`crate::intersect::Answer::values`]' order, (t, β, γ).
    #[inline(always)]
    pub fn from_values([t, beta, gamma]: [f64; 3]) -> TriangleHit {
        TriangleHit { beta, gamma, t }
    }
}

/// Where a ray meets a parallelogram: seed 001's (α, β, t), the point c + α e1 + β e2.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParallelogramHit {
    pub alpha: f64,
    pub beta: f64,
    pub t: f64,
}

/// Where on its primitive a hit lies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum At {
    /// A triangle's (β, γ).
    Triangle { beta: f64, gamma: f64 },
    /// A parallelogram's (α, β).
    Parallelogram { alpha: f64, beta: f64 },
}

/// The nearest hit along a ray in a scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Hit {
    /// The object's index in the scene.
    pub object: usize,
    /// The triangle's index in the object (0 for a parallelogram).
    pub primitive: usize,
    /// The ray parameter (world and object space alike).
    pub t: f64,
    /// Where on the primitive.
    pub at: At,
}

impl Hit {
    /// Triangle `primitive` of object `object`, hit at `hit`.
    #[inline(always)]
    pub fn triangle(object: usize, primitive: usize, hit: TriangleHit) -> Hit {
        let TriangleHit { beta, gamma, t } = hit;
        Hit {
            object,
            primitive,
            t,
            at: At::Triangle { beta, gamma },
        }
    }

    /// The parallelogram `object`, hit at `hit`.
    #[inline(always)]
    pub fn parallelogram(object: usize, hit: ParallelogramHit) -> Hit {
        let ParallelogramHit { alpha, beta, t } = hit;
        Hit {
            object,
            primitive: 0,
            t,
            at: At::Parallelogram { alpha, beta },
        }
    }

    /// The primitive's two coordinates: (β, γ) on a triangle, (α, β) on a parallelogram (its
    /// texture coordinates).
    #[inline(always)]
    pub fn coordinates(&self) -> [f64; 2] {
        match self.at {
            At::Triangle { beta, gamma } => [beta, gamma],
            At::Parallelogram { alpha, beta } => [alpha, beta],
        }
    }

    /// A triangle's barycentric weights of A, B and C: (1 − β − γ, β, γ).
    #[inline(always)]
    pub fn weights(&self) -> [f64; 3] {
        let [beta, gamma] = self.coordinates();
        [1.0 - beta - gamma, beta, gamma]
    }
}
