//! The colour of a hit, computing only what the scene's effects call for (seed 003, seed 004).

use crate::math::linalg::{V3, dot};
use crate::render::Hit;
use crate::render::objects::{Geometry, PreparedObject, unit};
use crate::render::{Effect, Stats};

/// Which effects are on, decided once per render.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Shader {
    depth: bool,
    color: bool,
    texture: bool,
    smooth: bool,
    facing: bool,
    /// Lights shade the scene (see [`crate::render::secondary`]): an object without another colour shows its
    /// own, not white.
    lit: bool,
}

/// A hit's surface before lighting (for the effects past ray casting).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Surface {
    /// The colour from the texture, the vertex colours or the object's.
    pub base: V3<f64>,
    /// The world-space unit normal (interpolated under `smooth-normals`), as the geometry orients it.
    pub normal: V3<f64>,
    /// The flat face's world-space unit normal, as the geometry orients it: `normal` itself unless
    /// that was interpolated. Secondary rays leave the surface along it, so that they start on the
    /// face's side they go to and cannot meet the face itself.
    pub face: V3<f64>,
    /// n̂ · (−ê), when a shading effect asked for it.
    pub facing: Option<f64>,
    /// The `depth` fade factor (1 without it).
    pub fade: f64,
}

/// What shading a hit gave.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shading {
    /// Linear RGB.
    pub color: [f32; 3],
    /// n̂ · (−ê), when a shading effect asked for it.
    pub facing: Option<f64>,
}

impl Shader {
    /// The shader for a list of effects.
    pub fn new(effects: &[Effect]) -> Shader {
        let wants = |e: Effect| effects.contains(&e);
        Shader {
            depth: wants(Effect::Depth),
            color: wants(Effect::BarycentricColor),
            texture: wants(Effect::Texture),
            smooth: wants(Effect::SmoothNormals),
            // Smooth normals are a way of shading, so they shade by the facing ratio too.
            facing: wants(Effect::FacingRatio) || wants(Effect::SmoothNormals),
            lit: false,
        }
    }

    /// The shader for a scene lit by lights: objects keep their colours.
    pub fn lit(effects: &[Effect]) -> Shader {
        Shader {
            lit: true,
            ..Shader::new(effects)
        }
    }

    /// A hit's surface: its colour, normal, facing ratio and fade, counting the same work as
    /// [`Shader::shade`] (the normal is always found: lights and mirrors need it).
    pub fn surface(
        &self,
        object: &PreparedObject,
        hit: &Hit,
        dir: &V3<f64>,
        inverse_length: f64,
        stats: &mut Stats,
    ) -> Surface {
        let base = self.base_color(object, hit, stats);
        if self.facing {
            stats.shading += 1;
        }
        let normal = self.world_normal(object, hit, stats);
        let facing = self
            .facing
            .then(|| facing_ratio(&normal, dir, inverse_length));
        let mut fade = 1.0;
        if self.depth {
            stats.depth_fades += 1;
            fade = 1.0 / depth_divisor(hit, inverse_length);
        }
        let normal = unit(normal);
        let interpolated = self.smooth
            && matches!(&object.geometry,
                Geometry::Triangles { triangles, .. } if triangles[hit.primitive].normals.is_some());
        let face = if interpolated {
            let flat = Shader {
                smooth: false,
                ..*self
            };
            unit(flat.world_normal(object, hit, &mut Stats::default()))
        } else {
            normal
        };
        Surface {
            base,
            normal,
            face,
            facing,
            fade,
        }
    }

    /// The colour of a hit seen along the world direction `dir`, with `inverse_length` = 1/|dir|
    /// (callers that cast many rays compute it in a vector loop); counts the work in `stats`.
    /// Inlined: called once per hit, and a call would pass the direction through memory.
    #[inline(always)]
    pub fn shade(
        &self,
        object: &PreparedObject,
        hit: &Hit,
        dir: &V3<f64>,
        inverse_length: f64,
        stats: &mut Stats,
    ) -> Shading {
        let mut color = self.base_color(object, hit, stats);
        let mut facing = None;
        if self.facing {
            stats.shading += 1;
            let normal = self.world_normal(object, hit, stats);
            // Back faces are black.
            let ratio = facing_ratio(&normal, dir, inverse_length);
            color = color.map(|c| c * ratio.max(0.0));
            facing = Some(ratio);
        }
        if self.depth {
            stats.depth_fades += 1;
            let divisor = depth_divisor(hit, inverse_length);
            color = color.map(|c| c / divisor);
        }
        Shading {
            color: color.map(|c| c as f32),
            facing,
        }
    }

    /// The unshaded colour: a texel, the interpolated vertex colour, the flat colour, or white.
    #[inline(always)]
    fn base_color(&self, object: &PreparedObject, hit: &Hit, stats: &mut Stats) -> V3<f64> {
        let triangle = match &object.geometry {
            Geometry::Triangles { triangles, .. } => Some(&triangles[hit.primitive]),
            Geometry::Parallelogram { .. } => None,
        };
        let weights = hit.weights();
        if self.texture
            && let Some(texture) = &object.texture
        {
            stats.texture_samples += 1;
            // A parallelogram's (α, β) are its texture coordinates; a triangle without UVs uses (β, γ).
            let [u, v] = match triangle.and_then(|t| t.uvs) {
                Some(uvs) => interpolate(&weights, &uvs),
                None => hit.coordinates(),
            };
            return texture.sample(u, v).map(f64::from);
        }
        if self.color
            && let Some(colors) = triangle.and_then(|t| t.colors)
        {
            stats.color_interpolations += 1;
            return interpolate(&weights, &colors);
        }
        if self.facing || self.lit {
            object.color
        } else {
            [1.0; 3]
        }
    }

    /// The world-space unit normal: interpolated from the vertex normals under `smooth-normals`, the
    /// face's otherwise; through the inverse transpose when the object is transformed.
    #[inline(always)]
    fn world_normal(&self, object: &PreparedObject, hit: &Hit, stats: &mut Stats) -> V3<f64> {
        let normal = match &object.geometry {
            Geometry::Triangles { triangles, .. } => {
                let triangle = &triangles[hit.primitive];
                match triangle.normals.filter(|_| self.smooth) {
                    Some(normals) => {
                        stats.normal_interpolations += 1;
                        let weights = hit.weights();
                        interpolate(&weights, &normals)
                    }
                    None => triangle.face_normal,
                }
            }
            Geometry::Parallelogram { face_normal, .. } => *face_normal,
        };
        match object.object_from_world {
            Some(_) => unit(
                object
                    .normal_to_world
                    .mul_vec3(glam::DVec3::from(normal))
                    .to_array(),
            ),
            None if self.smooth => unit(normal),
            None => normal,
        }
    }
}

/// Σ wᵢ vᵢ over the three vertices.
fn interpolate<const N: usize>(weights: &[f64; 3], values: &[[f64; N]; 3]) -> [f64; N] {
    std::array::from_fn(|k| (0..3).map(|i| weights[i] * values[i][k]).sum())
}

/// Seed 003's facing ratio n̂ · (−ê), with ê the unit ray direction (`inverse_length` = 1/|dir|).
#[inline(always)]
fn facing_ratio(normal: &V3<f64>, dir: &V3<f64>, inverse_length: f64) -> f64 {
    -dot(normal, dir) * inverse_length
}

/// The depth cue's divisor 1 + 0.1·distance, the distance along the ray being |t|·|dir|.
#[inline(always)]
fn depth_divisor(hit: &Hit, inverse_length: f64) -> f64 {
    1.0 + 0.1 * (hit.t.abs() / inverse_length)
}
