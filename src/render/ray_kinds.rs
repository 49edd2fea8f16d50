//! Rays counted by kind. The counters of [`super::Stats`] outside `secondary` describe the one primary
//! ray through each pixel's centre (what ray casting alone does); everything the effects past ray
//! casting add, from antialiasing's extra samples to shadow rays, is counted here, by kind, with the
//! intersection work those rays did.

use serde::Serialize;

use crate::scene::render::Effect;

/// The shipped scenes that cast every kind of ray: the Cornell box, with every effect, and a scene
/// for each effect alone (the cost table and the peer bench's ray-kind rows render them).
pub const EFFECT_SCENES: [&str; 6] = [
    "render-cornell-box.ron",
    "effect-shadows.ron",
    "effect-reflections.ron",
    "effect-refraction.ron",
    "effect-ambient-occlusion.ron",
    "effect-antialiasing.ron",
];

/// What a ray is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum RayKind {
    /// Through a pixel (its centre; antialiasing's samples are [`RayKind::Sample`]).
    Primary,
    /// Antialiasing's stratified samples: primary rays too, exactly k² a pixel (the pixel's colour
    /// is their mean; the centre ray only decides coverage and is the probe's).
    Sample,
    /// From a hit to a light (`shadows`).
    Shadow,
    /// Off a mirror, or glass's Fresnel reflection (`reflections`).
    Reflection,
    /// Through glass, or reflected wholly inside it (`refraction`).
    Refraction,
    /// Over the hemisphere of a hit (`ambient-occlusion`).
    Occlusion,
}

impl RayKind {
    /// Every kind, in the order they are shown.
    pub const ALL: [RayKind; 6] = [
        RayKind::Primary,
        RayKind::Sample,
        RayKind::Shadow,
        RayKind::Reflection,
        RayKind::Refraction,
        RayKind::Occlusion,
    ];

    /// Its short name, as the Render view lists it.
    pub fn name(self) -> &'static str {
        match self {
            RayKind::Primary => "primary",
            RayKind::Sample => "samples",
            RayKind::Shadow => "shadow",
            RayKind::Reflection => "reflection",
            RayKind::Refraction => "refraction",
            RayKind::Occlusion => "occlusion",
        }
    }

    /// The effect that casts rays of this kind (none for the primary ray).
    pub fn effect(self) -> Option<Effect> {
        match self {
            RayKind::Primary => None,
            RayKind::Sample => Some(Effect::Antialiasing),
            RayKind::Shadow => Some(Effect::Shadows),
            RayKind::Reflection => Some(Effect::Reflections),
            RayKind::Refraction => Some(Effect::Refraction),
            RayKind::Occlusion => Some(Effect::AmbientOcclusion),
        }
    }
}

/// The work of the effects past ray casting.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct Secondary {
    /// Antialiasing's sample rays (k² a pixel).
    pub sample_rays: u64,
    /// Shadow rays.
    pub shadow_rays: u64,
    /// Reflected rays.
    pub reflection_rays: u64,
    /// Refracted rays.
    pub refraction_rays: u64,
    /// Ambient-occlusion rays.
    pub occlusion_rays: u64,
    /// Shadow and occlusion rays that found something in the way (and stopped there).
    pub blocked: u64,
    /// Triangle and parallelogram tests of these rays.
    pub tests: u64,
    /// Box tests of these rays.
    pub box_tests: u64,
    /// These rays taken into an object's space.
    pub transforms: u64,
    /// Hits of sample, reflected and refracted rays (each is shaded).
    pub hits: u64,
    /// Lights evaluated at a hit (diffuse shading by a light, with its shadow ray if `shadows`).
    pub light_evaluations: u64,
}

impl Secondary {
    /// Counts one ray of `kind` (a primary ray is counted in [`super::Stats::rays`]).
    pub fn count(&mut self, kind: RayKind) {
        match kind {
            RayKind::Primary => {}
            RayKind::Sample => self.sample_rays += 1,
            RayKind::Shadow => self.shadow_rays += 1,
            RayKind::Reflection => self.reflection_rays += 1,
            RayKind::Refraction => self.refraction_rays += 1,
            RayKind::Occlusion => self.occlusion_rays += 1,
        }
    }

    /// The rays of `kind` (0 for primary, counted in [`super::Stats::rays`]).
    pub fn rays(&self, kind: RayKind) -> u64 {
        match kind {
            RayKind::Primary => 0,
            RayKind::Sample => self.sample_rays,
            RayKind::Shadow => self.shadow_rays,
            RayKind::Reflection => self.reflection_rays,
            RayKind::Refraction => self.refraction_rays,
            RayKind::Occlusion => self.occlusion_rays,
        }
    }

    /// The sum of two counts.
    pub fn plus(self, o: Secondary) -> Secondary {
        Secondary {
            sample_rays: self.sample_rays + o.sample_rays,
            shadow_rays: self.shadow_rays + o.shadow_rays,
            reflection_rays: self.reflection_rays + o.reflection_rays,
            refraction_rays: self.refraction_rays + o.refraction_rays,
            occlusion_rays: self.occlusion_rays + o.occlusion_rays,
            blocked: self.blocked + o.blocked,
            tests: self.tests + o.tests,
            box_tests: self.box_tests + o.box_tests,
            transforms: self.transforms + o.transforms,
            hits: self.hits + o.hits,
            light_evaluations: self.light_evaluations + o.light_evaluations,
        }
    }

    /// Each counter with its name, for printing.
    pub fn counters(&self) -> [(&'static str, u64); 11] {
        [
            ("antialiasing sample rays", self.sample_rays),
            ("shadow rays", self.shadow_rays),
            ("reflection rays", self.reflection_rays),
            ("refraction rays", self.refraction_rays),
            ("occlusion rays", self.occlusion_rays),
            ("blocked shadow/occlusion rays", self.blocked),
            ("their triangle/parallelogram tests", self.tests),
            ("their box tests", self.box_tests),
            ("their transforms", self.transforms),
            ("their shaded hits", self.hits),
            ("light evaluations", self.light_evaluations),
        ]
    }
}

/// A count a reader takes in at a glance (rays, rays a second): 830 k, 5.5 M, 2.1 G, 26.0 T.
pub fn short_count(n: f64) -> String {
    match n {
        n if n >= 1e12 => format!("{:.1} T", n / 1e12),
        n if n >= 1e9 => format!("{:.1} G", n / 1e9),
        n if n >= 1e6 => format!("{:.1} M", n / 1e6),
        n if n >= 1e3 => format!("{:.0} k", n / 1e3),
        n => format!("{n:.0}"),
    }
}

/// One line for `--stats`: the rays by kind, then the secondary rays' work.
pub fn by_kind_line(stats: &super::Stats) -> String {
    let s = &stats.secondary;
    let work: Vec<String> = s.counters()[5..]
        .iter()
        .map(|(name, value)| format!("{name} {value}"))
        .collect();
    format!(
        "rays by kind: primary {} (+ {} antialiasing samples), shadow {}, reflection {}, \
         refraction {}, occlusion {}; {}",
        stats.rays,
        s.sample_rays,
        s.shadow_rays,
        s.reflection_rays,
        s.refraction_rays,
        s.occlusion_rays,
        work.join(", ")
    )
}
