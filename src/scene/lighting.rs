//! What a render scene adds for the effects past ray casting: lights (point and directional), materials
//! (diffuse, mirror, glass) and the effects' parameters (depth limit, occlusion rays, samples per
//! pixel, the self-intersection offset), each with a default so a scene without them loads as before.

use serde::{Deserialize, Serialize};

use super::check::{CheckError, check_numbers};

/// A light: a point radiating in all directions (its intensity falls off as 1/d²) or a direction,
/// as the sun (no falloff).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Light {
    /// A point light at `position`.
    Point {
        /// Where it is.
        position: [f64; 3],
        /// RGB colour.
        #[serde(default = "white")]
        color: [f64; 3],
        /// Radiant intensity: the irradiance at distance 1 facing it.
        #[serde(default = "one")]
        intensity: f64,
    },
    /// Light arriving along `direction` (from the light towards the scene).
    Directional {
        /// The direction light travels (need not be a unit vector).
        direction: [f64; 3],
        /// RGB colour.
        #[serde(default = "white")]
        color: [f64; 3],
        /// Irradiance on a surface facing it.
        #[serde(default = "one")]
        intensity: f64,
    },
}

/// How an object's surface answers light beyond its diffuse colour (the object's `color`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Material {
    /// Diffuse only.
    #[default]
    Diffuse,
    /// A mirror: `reflectance` of the colour is the reflected ray's, the rest the diffuse colour's
    /// (`reflections`).
    Mirror {
        /// In [0, 1].
        reflectance: f64,
    },
    /// Glass: rays refract by Snell's law with index of refraction `ior` (`refraction`); Schlick's
    /// Fresnel term mixes the reflected ray in.
    Glass {
        /// The index of refraction (1.5 for window glass), inside relative to outside.
        ior: f64,
    },
}

/// The parameters of the effects past ray casting.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct EffectSettings {
    /// How many bounces a mirror or glass ray may take (`reflections`, `refraction`); 0: none.
    pub max_depth: u32,
    /// Rays per hit for `ambient-occlusion`.
    pub occlusion_rays: u32,
    /// How far an occluder counts (`None`: at any distance).
    pub occlusion_distance: Option<f64>,
    /// k: `antialiasing` takes k×k stratified samples per pixel.
    pub samples_per_side: u32,
    /// Seeds the occlusion rays and the samples' jitter (the same image every run).
    pub seed: u64,
    /// How far a secondary ray's origin moves off the surface along the face's normal, to the side
    /// the ray goes to, against shadow acne.
    pub offset: f64,
    /// The light every lit surface gets without a light (scaled by `ambient-occlusion`).
    pub ambient: f64,
}

impl Default for EffectSettings {
    fn default() -> EffectSettings {
        EffectSettings {
            max_depth: 4,
            occlusion_rays: 16,
            occlusion_distance: None,
            samples_per_side: 2,
            seed: 1,
            offset: 1e-6,
            ambient: 0.1,
        }
    }
}

/// The deepest bounce a scene may ask for.
pub const MAX_DEPTH: u32 = 16;
/// The most occlusion rays per hit.
pub const MAX_OCCLUSION_RAYS: u32 = 1024;
/// The largest k (k×k samples per pixel).
pub const MAX_SAMPLES_PER_SIDE: u32 = 16;
/// The most lights a scene may hold (each costs a shadow ray per shaded hit).
pub const MAX_LIGHTS: usize = 256;

impl EffectSettings {
    /// Limits that keep a render finite and meaningful.
    pub fn check(&self) -> Result<(), CheckError> {
        if self.max_depth > MAX_DEPTH {
            return Err(CheckError::Depth(self.max_depth));
        }
        if !(1..=MAX_OCCLUSION_RAYS).contains(&self.occlusion_rays) {
            return Err(CheckError::OcclusionRays(self.occlusion_rays));
        }
        if !(1..=MAX_SAMPLES_PER_SIDE).contains(&self.samples_per_side) {
            return Err(CheckError::SamplesPerSide(self.samples_per_side));
        }
        let distance = self.occlusion_distance.unwrap_or(1.0);
        check_numbers("settings", &[self.offset, self.ambient, distance])?;
        if !(self.offset >= 0.0 && self.ambient >= 0.0 && distance > 0.0) {
            return Err(CheckError::NegativeSettings {
                offset: self.offset,
                ambient: self.ambient,
                distance,
            });
        }
        Ok(())
    }
}

impl Light {
    /// Finite numbers, a colour and intensity of at least 0, a direction that is not zero.
    pub fn check(&self) -> Result<(), CheckError> {
        let (place, color, intensity) = match self {
            Light::Point {
                position,
                color,
                intensity,
            } => (position, color, *intensity),
            Light::Directional {
                direction,
                color,
                intensity,
            } => (direction, color, *intensity),
        };
        let numbers = [&place[..], &color[..], &[intensity]].concat();
        check_numbers("its numbers", &numbers)?;
        if intensity < 0.0 || color.iter().any(|c| *c < 0.0) {
            return Err(CheckError::NegativeLight {
                color: *color,
                intensity,
            });
        }
        if matches!(self, Light::Directional { .. }) && place.iter().all(|c| *c == 0.0) {
            return Err(CheckError::NoDirection);
        }
        Ok(())
    }
}

impl Material {
    /// A reflectance in [0, 1], an index of refraction above 0 (and at most 10).
    pub fn check(&self) -> Result<(), CheckError> {
        match *self {
            Material::Diffuse => Ok(()),
            Material::Mirror { reflectance } if !(0.0..=1.0).contains(&reflectance) => {
                Err(CheckError::Reflectance(reflectance))
            }
            Material::Glass { ior } if !(ior > 0.0 && ior <= 10.0) => {
                Err(CheckError::IndexOfRefraction(ior))
            }
            _ => Ok(()),
        }
    }

    /// True for the default (written back to a file only when not).
    pub fn is_diffuse(&self) -> bool {
        *self == Material::Diffuse
    }
}

fn white() -> [f64; 3] {
    [1.0; 3]
}

fn one() -> f64 {
    1.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bad_parameters_are_refused_with_what_is_wrong() {
        let glass = Material::Glass { ior: 0.0 }
            .check()
            .unwrap_err()
            .to_string();
        assert!(glass.contains("index of refraction is 0"), "{glass}");
        assert!(Material::Glass { ior: -1.5 }.check().is_err());
        assert!(Material::Mirror { reflectance: 1.5 }.check().is_err());
        assert!(Material::Glass { ior: 1.5 }.check().is_ok());
        let deep = EffectSettings {
            max_depth: 100,
            ..Default::default()
        };
        assert!(
            deep.check()
                .unwrap_err()
                .to_string()
                .contains("max_depth is 100")
        );
        let k0 = EffectSettings {
            samples_per_side: 0,
            ..Default::default()
        };
        assert!(
            k0.check()
                .unwrap_err()
                .to_string()
                .contains("samples_per_side")
        );
        let dark = Light::Point {
            position: [0.0; 3],
            color: [1.0; 3],
            intensity: -1.0,
        };
        assert!(
            dark.check()
                .unwrap_err()
                .to_string()
                .contains("intensity -1")
        );
        let nowhere = Light::Directional {
            direction: [0.0; 3],
            color: [1.0; 3],
            intensity: 1.0,
        };
        assert!(nowhere.check().is_err());
        assert!(EffectSettings::default().check().is_ok());
    }
}
