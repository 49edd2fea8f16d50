//! The most rays a render may cast, worked out from its settings before it starts: `raylab render`
//! and the Render view refuse a render past [`WORST_CASE_RAYS`] the same way, with the figures.

use super::Prepared;
use super::ray_kinds::short_count;
use crate::scene::render::Effect;

/// A render that may cast more rays than this (its worst case: every ray of its ray tree hit
/// something that sends more) is refused before it starts: at a billion rays a second it would take
/// over a quarter of an hour.
pub const WORST_CASE_RAYS: f64 = 1e12;

/// A render's worst case, with the settings that make it.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
#[error(
    "this render may cast up to {} rays ({}×{} pixels, {} samples each, max_depth {}, {} occlusion \
     rays), past the budget of {}",
    short_count(self.rays),
    self.width,
    self.height,
    self.samples,
    self.max_depth,
    self.occlusion_rays,
    short_count(WORST_CASE_RAYS)
)]
pub struct WorstCase {
    /// The most rays it may cast.
    pub rays: f64,
    /// The image's width.
    pub width: usize,
    /// The image's height.
    pub height: usize,
    /// Samples a pixel.
    pub samples: u32,
    /// Bounces.
    pub max_depth: u32,
    /// Occlusion rays a hit.
    pub occlusion_rays: u32,
}

/// The most rays `prepared` may cast: per camera sample, a ray tree of max_depth levels (two
/// children a node with refraction, one with reflections alone), each node with a shadow ray a light
/// and the occlusion rays when those effects are on.
pub fn worst_case(prepared: &Prepared) -> WorstCase {
    let on = |effect| prepared.effects.contains(&effect);
    let settings = &prepared.lighting.settings;
    let samples_per_side = if on(Effect::Antialiasing) {
        settings.samples_per_side.max(1)
    } else {
        1
    };
    let samples = f64::from(samples_per_side * samples_per_side);
    let depth = f64::from(settings.max_depth);
    let nodes = if on(Effect::Refraction) {
        2f64.powf(depth + 1.0) - 1.0
    } else if on(Effect::Reflections) {
        depth + 1.0
    } else {
        1.0
    };
    let shadows = if on(Effect::Shadows) {
        prepared.lighting.lights.len() as f64
    } else {
        0.0
    };
    let occlusion = if on(Effect::AmbientOcclusion) {
        f64::from(settings.occlusion_rays)
    } else {
        0.0
    };
    WorstCase {
        rays: (prepared.width * prepared.height) as f64
            * samples
            * nodes
            * (1.0 + shadows + occlusion),
        width: prepared.width,
        height: prepared.height,
        samples: samples_per_side * samples_per_side,
        max_depth: settings.max_depth,
        occlusion_rays: settings.occlusion_rays,
    }
}

/// The worst case of `prepared` when it is past [`WORST_CASE_RAYS`].
pub fn past_budget(prepared: &Prepared) -> Option<WorstCase> {
    Some(worst_case(prepared)).filter(|w| w.rays > WORST_CASE_RAYS)
}
