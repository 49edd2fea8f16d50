//! Lights at a hit: where each one is seen from, how much light it brings, and the scene's lighting
//! (lights, materials, the effects' parameters) as the renderer holds it.

use crate::math::linalg::{V3, dot, sub};
use crate::scene::render::{EffectSettings, Light, Material, RenderScene};

/// What the effects past ray casting read from a scene.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Lighting {
    /// The lights.
    pub lights: Vec<Light>,
    /// Object i's material (missing: diffuse).
    pub materials: Vec<Material>,
    /// The effects' parameters.
    pub settings: EffectSettings,
}

impl Lighting {
    /// The scene's lights, materials and settings.
    pub fn of(scene: &RenderScene) -> Lighting {
        Lighting {
            lights: scene.lights.clone(),
            materials: (0..scene.objects.len())
                .map(|i| scene.material(i))
                .collect(),
            settings: scene.settings,
        }
    }

    /// Object `index`'s material.
    pub fn material(&self, index: usize) -> Material {
        self.materials.get(index).copied().unwrap_or_default()
    }
}

/// A light seen from a point: the ray towards it and the light it brings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Incoming {
    /// From the point towards the light, not normalised: for a point light, the light is at t = 1.
    pub toward: V3<f64>,
    /// The shadow ray's range ends here (1 for a point light, ∞ for a direction).
    pub t_max: f64,
    /// RGB irradiance on a surface facing the light (1/d² for a point light).
    pub irradiance: V3<f64>,
}

impl Incoming {
    /// The direction to the light from `from`, a start moved off `point` (the shadow ray's origin):
    /// for a point light the light stays at t = 1 (light − from = point + toward − from); a
    /// direction stays what it is.
    pub fn toward_from(&self, point: &V3<f64>, from: &V3<f64>) -> V3<f64> {
        if self.t_max.is_finite() {
            std::array::from_fn(|k| point[k] + self.toward[k] - from[k])
        } else {
            self.toward
        }
    }
}

/// How `light` reaches `point`.
pub fn incoming(light: &Light, point: &V3<f64>) -> Incoming {
    match light {
        Light::Point {
            position,
            color,
            intensity,
        } => {
            let toward = sub(position, point);
            let d2 = dot(&toward, &toward).max(f64::MIN_POSITIVE);
            Incoming {
                toward,
                t_max: 1.0,
                irradiance: color.map(|c| c * intensity / d2),
            }
        }
        Light::Directional {
            direction,
            color,
            intensity,
        } => Incoming {
            toward: direction.map(|c| -c),
            t_max: f64::INFINITY,
            irradiance: color.map(|c| c * intensity),
        },
    }
}

/// Lambert's cosine: n̂ · l̂ for the unit normal and the (any length) direction to the light, 0 when
/// the light is behind the surface.
pub fn lambert(normal: &V3<f64>, toward: &V3<f64>) -> f64 {
    let length = dot(toward, toward).sqrt();
    if length == 0.0 {
        return 0.0;
    }
    (dot(normal, toward) / length).max(0.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_light_falls_off_with_the_square_of_the_distance() {
        let light = Light::Point {
            position: [0.0, 0.0, 2.0],
            color: [1.0, 0.5, 0.0],
            intensity: 8.0,
        };
        let seen = incoming(&light, &[0.0, 0.0, 0.0]);
        assert_eq!(seen.toward, [0.0, 0.0, 2.0]);
        assert_eq!(seen.irradiance, [2.0, 1.0, 0.0]);
        assert_eq!(lambert(&[0.0, 0.0, 1.0], &seen.toward), 1.0);
        assert_eq!(lambert(&[0.0, 0.0, -1.0], &seen.toward), 0.0);
        let sun = Light::Directional {
            direction: [0.0, -1.0, -1.0],
            color: [1.0; 3],
            intensity: 1.0,
        };
        let seen = incoming(&sun, &[5.0, 5.0, 5.0]);
        assert_eq!(seen.t_max, f64::INFINITY);
        assert!((lambert(&[0.0, 0.0, 1.0], &seen.toward) - 0.5f64.sqrt()).abs() < 1e-15);
    }
}
