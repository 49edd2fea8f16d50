//! What a scene file's format cannot refuse on its own: numbers that are not finite or too large,
//! an unusable image size or camera, a scale that cannot be inverted, a material, light or effect
//! setting outside its range. Each refusal is a variant; its message says what to change.

use super::lighting::{MAX_DEPTH, MAX_LIGHTS, MAX_OCCLUSION_RAYS, MAX_SAMPLES_PER_SIDE};
use super::render::{MAX_MAGNITUDE, MAX_SIDE, MIN_MAGNITUDE};

/// Why a scene is refused.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum CheckError {
    /// NaN or an infinity among `what` (`coordinates`, `the camera's numbers`, …).
    #[error("{what} must be finite numbers, found {value}")]
    NotFinite {
        /// The numbers, for people.
        what: &'static str,
        /// The first bad one.
        value: f64,
    },
    /// A number past ±[`MAX_MAGNITUDE`].
    #[error(
        "{what} must be at most {MAX_MAGNITUDE:e} in magnitude (so the renderer's arithmetic \
         cannot overflow), found {value:e}"
    )]
    TooLarge {
        /// The numbers, for people.
        what: &'static str,
        /// The first bad one.
        value: f64,
    },
    /// An image side outside 1 ..= [`MAX_SIDE`].
    #[error("the image is {width}x{height}: each side must be 1 to {MAX_SIDE} pixels")]
    ImageSize {
        /// Its width.
        width: usize,
        /// Its height.
        height: usize,
    },
    /// An image plane through the origin.
    #[error(
        "the image plane is at z = {0}: rays start on the plane and point away from the origin, so \
         at z = 0 they run along the plane and the one through the origin has no direction; put \
         the plane at |z| ≥ {MIN_MAGNITUDE:e}"
    )]
    ImagePlaneAtOrigin(f64),
    /// A field of view outside (0°, 180°).
    #[error("the field of view is {0}°: it must be between 0° and 180°")]
    FieldOfView(f64),
    /// A pinhole camera whose position and target coincide.
    #[error(
        "the camera's position and target are the same point (or closer than {MIN_MAGNITUDE:e}): \
         the camera has no direction"
    )]
    CameraHasNoDirection,
    /// A pinhole camera looking along z, the image's up.
    #[error(
        "the camera looks straight up or down: z is the image's up, so move the target off the \
         vertical through the position"
    )]
    CameraVertical,
    /// A scale with a zero component.
    #[error(
        "the transform's scale {0:?} has a zero component: the object would be flat and its \
         transform has no inverse"
    )]
    FlatScale([f64; 3]),
    /// A scale component too small to invert.
    #[error(
        "the transform's scale component {0:e} is too small to invert safely: each must be at \
         least {MIN_MAGNITUDE:e} in magnitude"
    )]
    TinyScale(f64),
    /// A mirror reflectance outside [0, 1].
    #[error("the mirror's reflectance is {0}: it must be between 0 and 1")]
    Reflectance(f64),
    /// An index of refraction outside (0, 10].
    #[error(
        "the glass's index of refraction is {0}: it must be above 0 (1 is air, 1.5 glass) and at \
         most 10"
    )]
    IndexOfRefraction(f64),
    /// A light with a negative colour or intensity.
    #[error("its colour {color:?} and intensity {intensity} must be at least 0")]
    NegativeLight {
        /// Its colour.
        color: [f64; 3],
        /// Its intensity.
        intensity: f64,
    },
    /// An object's colour (or a vertex colour) with a negative part.
    #[error("its colour {0:?} has a negative part: a colour's parts are 0 or more (1 is full)")]
    NegativeColor([f64; 3]),
    /// A directional light whose direction is zero.
    #[error("a directional light's direction is (0, 0, 0): it has no direction")]
    NoDirection,
    /// More than [`MAX_LIGHTS`] lights.
    #[error("the scene has {0} lights: at most {MAX_LIGHTS} (each costs a shadow ray per hit)")]
    TooManyLights(usize),
    /// More than [`MAX_DEPTH`] bounces.
    #[error("settings: max_depth is {0}: at most {MAX_DEPTH} bounces (each may double the rays)")]
    Depth(u32),
    /// Occlusion rays outside 1 ..= [`MAX_OCCLUSION_RAYS`].
    #[error("settings: occlusion_rays is {0}: it must be 1 to {MAX_OCCLUSION_RAYS}")]
    OcclusionRays(u32),
    /// k outside 1 ..= [`MAX_SAMPLES_PER_SIDE`].
    #[error(
        "settings: samples_per_side (k, for k×k samples a pixel) is {0}: it must be 1 to \
         {MAX_SAMPLES_PER_SIDE}"
    )]
    SamplesPerSide(u32),
    /// A negative offset or ambient, or an occlusion distance that is not positive.
    #[error(
        "settings: offset ({offset}) and ambient ({ambient}) must be at least 0 and \
         occlusion_distance ({distance}) more than 0"
    )]
    NegativeSettings {
        /// The offset along the normal.
        offset: f64,
        /// The ambient term.
        ambient: f64,
        /// The occlusion distance.
        distance: f64,
    },
    /// Object `index` (from 1) is refused.
    #[error("object {index}: {error}")]
    Object {
        /// From 1.
        index: usize,
        /// Why.
        error: Box<CheckError>,
    },
    /// Light `index` (from 1) is refused.
    #[error("light {index}: {error}")]
    Light {
        /// From 1.
        index: usize,
        /// Why.
        error: Box<CheckError>,
    },
}

impl CheckError {
    /// The same refusal, said of object `index` (from 0).
    pub fn in_object(self, index: usize) -> CheckError {
        CheckError::Object {
            index: index + 1,
            error: Box::new(self),
        }
    }

    /// The same refusal, said of light `index` (from 0).
    pub fn in_light(self, index: usize) -> CheckError {
        CheckError::Light {
            index: index + 1,
            error: Box::new(self),
        }
    }
}

/// Finite, and within ±[`MAX_MAGNITUDE`]; `what` names the numbers in the message.
pub fn check_numbers(what: &'static str, numbers: &[f64]) -> Result<(), CheckError> {
    if let Some(&value) = numbers.iter().find(|v| !v.is_finite()) {
        return Err(CheckError::NotFinite { what, value });
    }
    match numbers.iter().find(|v| v.abs() > MAX_MAGNITUDE) {
        Some(&value) => Err(CheckError::TooLarge { what, value }),
        None => Ok(()),
    }
}

/// A scale whose inverse stays within [`MAX_MAGNITUDE`].
pub fn check_scale(scale: &[f64; 3]) -> Result<(), CheckError> {
    if scale.contains(&0.0) {
        return Err(CheckError::FlatScale(*scale));
    }
    match scale.iter().find(|s| s.abs() < MIN_MAGNITUDE) {
        Some(&small) => Err(CheckError::TinyScale(small)),
        None => Ok(()),
    }
}
