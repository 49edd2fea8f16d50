//! A pixel's ray tree, for the probe: the primary ray through the pixel's centre, how each light
//! reaches its hit (the shadow ray, lit or blocked and by what), the reflected and refracted rays with
//! their bounce depth, and the ambient-occlusion rays summarised: the rays the render traced, in the
//! order it traced them (the same seeded random numbers), recorded as they were cast.

use crate::math::linalg::V3;
use crate::render::Hit;
use crate::render::cast::{self, nearest_hit};
use crate::render::ray_kinds::RayKind;
use crate::render::secondary::{LightTest, Record, SecondaryCaster};
use crate::render::shading::sampling::{pixel_rng, stratified};
use crate::render::{Prepared, Ray, Stats};
use crate::scene::render::Effect;

/// One pixel's rays.
#[derive(Clone, Debug, PartialEq)]
pub struct RayTree {
    /// The pixel's row and column.
    pub pixel: (usize, usize),
    /// The primary ray through the pixel's centre, and every ray it led to.
    pub root: TracedRay,
    /// With `antialiasing`: the k² sample rays whose mean is the pixel's colour, and how many of them
    /// hit something (the tree follows the centre ray, traced as it would be without antialiasing).
    pub samples: Option<Samples>,
}

/// Antialiasing's samples of a pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Samples {
    /// k².
    pub cast: u32,
    /// Those that hit something.
    pub hit: u32,
}

/// A ray that looks for the nearest hit (primary, reflected, refracted), and what it led to.
#[derive(Clone, Debug, PartialEq)]
pub struct TracedRay {
    /// What it is for.
    pub kind: RayKind,
    /// How many bounces led to it (0: the primary ray).
    pub depth: u32,
    /// Origin and direction (world).
    pub ray: Ray,
    /// Its nearest hit.
    pub hit: Option<Hit>,
    /// The colour it brought back.
    pub colour: V3<f64>,
    /// How each light reaches the hit (none without lights).
    pub lights: Vec<LightRay>,
    /// The hit's ambient-occlusion rays, when `ambient-occlusion` is on.
    pub occlusion: Option<Occlusion>,
    /// The reflected and refracted rays from the hit.
    pub children: Vec<TracedRay>,
}

/// How a light reaches a hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightRay {
    /// The light's index in the scene.
    pub light: usize,
    /// The shadow ray and its answer.
    pub test: LightTest,
    /// For a blocked shadow ray: the nearest thing in the way (the render's any-hit query stops at
    /// the first it finds; the probe looks for the nearest, to show it).
    pub blocker: Option<Hit>,
}

/// A hit's ambient-occlusion rays, summarised.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Occlusion {
    /// Rays cast over the hemisphere.
    pub cast: u32,
    /// Those that found something within reach.
    pub blocked: u32,
}

impl TracedRay {
    fn new(kind: RayKind, depth: u32, ray: Ray) -> TracedRay {
        TracedRay {
            kind,
            depth,
            ray,
            hit: None,
            colour: [0.0; 3],
            lights: Vec::new(),
            occlusion: None,
            children: Vec::new(),
        }
    }

    /// This ray and all below it, depth first.
    pub fn all(&self) -> Vec<&TracedRay> {
        let mut out = vec![self];
        for child in &self.children {
            out.extend(child.all());
        }
        out
    }
}

impl LightRay {
    /// The shadow ray, if one was cast.
    pub fn ray(&self) -> Option<Ray> {
        match self.test {
            LightTest::Lit(ray, _) | LightTest::Blocked(ray, _) => Some(ray),
            LightTest::FacesAway | LightTest::Untested => None,
        }
    }

    /// True when something stands between the hit and the light.
    pub fn blocked(&self) -> bool {
        matches!(self.test, LightTest::Blocked(..))
    }
}

/// Builds the tree from what the caster tells: a stack of the rays still open.
struct Builder<'a> {
    prepared: &'a Prepared,
    open: Vec<TracedRay>,
    finished: Option<TracedRay>,
}

impl Record for Builder<'_> {
    fn start(&mut self, kind: RayKind, depth: u32, ray: Ray) {
        self.open.push(TracedRay::new(kind, depth, ray));
    }

    fn met(&mut self, hit: Option<Hit>) {
        if let Some(top) = self.open.last_mut() {
            top.hit = hit;
        }
    }

    fn end(&mut self, colour: V3<f64>) {
        let Some(mut ray) = self.open.pop() else {
            return;
        };
        ray.colour = colour;
        match self.open.last_mut() {
            Some(parent) => parent.children.push(ray),
            None => self.finished = Some(ray),
        }
    }

    fn light(&mut self, light: usize, test: LightTest) {
        let blocker = match test {
            LightTest::Blocked(ray, t_max) => {
                cast::nearest_hit_between(self.prepared, ray, (0.0, t_max), &mut Stats::default())
            }
            _ => None,
        };
        if let Some(top) = self.open.last_mut() {
            top.lights.push(LightRay {
                light,
                test,
                blocker,
            });
        }
    }

    fn occlusion(&mut self, cast: u32, blocked: u32) {
        if let Some(top) = self.open.last_mut() {
            top.occlusion = Some(Occlusion { cast, blocked });
        }
    }
}

/// The rays of pixel (row, column), as the render traces them.
pub fn ray_tree(prepared: &Prepared, row: usize, column: usize) -> RayTree {
    let caster = SecondaryCaster::new(prepared);
    let seed = prepared.lighting.settings.seed;
    let pixel = row * prepared.width + column;
    let centre = prepared.ray(row, column);
    let hit = nearest_hit(prepared, centre, &mut Stats::default());
    let mut builder = Builder {
        prepared,
        open: Vec::new(),
        finished: None,
    };
    builder.start(RayKind::Primary, 0, centre);
    builder.met(hit);
    let mut rng = pixel_rng(seed, pixel);
    let colour = hit.map_or([0.0; 3], |hit| {
        let kind = (RayKind::Primary, 0);
        let mut stats = Stats::default();
        caster.radiance(hit, centre, kind, (&mut rng, &mut builder), &mut stats)
    });
    builder.end(colour);
    let samples = prepared
        .effects
        .contains(&Effect::Antialiasing)
        .then(|| samples(prepared, &caster, (row, column)));
    RayTree {
        pixel: (row, column),
        root: builder
            .finished
            .unwrap_or_else(|| TracedRay::new(RayKind::Primary, 0, centre)),
        samples,
    }
}

/// Antialiasing's samples of the pixel, at the positions the render jitters them to.
fn samples(
    prepared: &Prepared,
    caster: &SecondaryCaster,
    (row, column): (usize, usize),
) -> Samples {
    let settings = &prepared.lighting.settings;
    let mut rng = pixel_rng(settings.seed, row * prepared.width + column);
    let positions = stratified(settings.samples_per_side, &mut rng);
    let hit = positions
        .iter()
        .filter(|(x, y)| {
            let ray = caster.ray_at(row as f64 + y - 0.5, column as f64 + x - 0.5);
            nearest_hit(prepared, ray, &mut Stats::default()).is_some()
        })
        .count();
    Samples {
        cast: positions.len() as u32,
        hit: hit as u32,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::render::{loading::assets::Embedded, render};
    use crate::scene::{Problem, Scene};

    fn prepared(body: &str) -> Prepared {
        let text = format!("(title: \"t\", note: \"n\", problem: Render({body}))");
        let Ok(Scene {
            problem: Problem::Render(scene),
            ..
        }) = Scene::from_ron(&text, "test.ron")
        else {
            panic!("not a render scene: {body}");
        };
        Prepared::new(&scene, &Embedded).expect("the scene prepares")
    }

    /// A floor, a strip above it at z = 1 over x ≤ 0, and a point light at (2, 0, 3).
    const SHADOW: &str = r#"(
        width: 41, height: 21,
        camera: Pinhole(position: (-1.0, -4.0, 6.0), target: (-1.0, 0.0, 0.0), fov_y: 40.0),
        objects: [
            (shape: Parallelogram(corner: (-6.0, -6.0, 0.0), e1: (12.0, 0.0, 0.0), e2: (0.0, 12.0, 0.0))),
            (shape: Triangle(vertices: ((-4.0, -1.5, 1.0), (0.0, -1.5, 1.0), (0.0, 1.5, 1.0)))),
            (shape: Triangle(vertices: ((-4.0, -1.5, 1.0), (0.0, 1.5, 1.0), (-4.0, 1.5, 1.0)))),
        ],
        effects: ["shadows"],
        lights: [Point(position: (2.0, 0.0, 3.0), intensity: 9.0)],
        settings: (ambient: 0.0),
    )"#;

    #[test]
    fn a_pixel_in_shadow_has_a_blocked_shadow_ray_and_the_tree_gives_the_rendered_colour() {
        let prepared = prepared(SHADOW);
        let (image, _) = render(&prepared);
        let (mut blocked, mut lit) = (0, 0);
        for row in 0..prepared.height {
            for column in 0..prepared.width {
                let tree = ray_tree(&prepared, row, column);
                let root = &tree.root;
                assert_eq!(root.kind, RayKind::Primary);
                let shown = image.pixels[row * prepared.width + column];
                assert_eq!(root.colour.map(|c| c as f32), shown, "({row}, {column})");
                if root.hit.is_none_or(|h| h.object != 0) {
                    continue;
                }
                assert_eq!(root.lights.len(), 1);
                let light = root.lights[0];
                assert!(light.ray().is_some(), "a shadow ray is cast");
                if light.blocked() {
                    blocked += 1;
                    assert_eq!(shown, [0.0; 3], "in shadow: black without ambient");
                    let blocker = light.blocker.expect("what is in the way");
                    assert!(blocker.object == 1 || blocker.object == 2, "{blocker:?}");
                } else {
                    lit += 1;
                    assert!(shown[0] > 0.0);
                    assert_eq!(light.blocker, None);
                }
            }
        }
        assert!(blocked > 20 && lit > 20, "{blocked} blocked, {lit} lit");
    }

    #[test]
    fn a_mirror_pixel_has_a_reflection_child_that_hits_the_wall() {
        let prepared = prepared(
            r#"(
            width: 1, height: 1,
            camera: Pinhole(position: (0.0, -2.0, 2.0), target: (0.0, 0.0, 0.0), fov_y: 10.0),
            objects: [
                (shape: Parallelogram(corner: (-1.0, -1.0, 0.0), e1: (2.0, 0.0, 0.0), e2: (0.0, 2.0, 0.0)), material: Mirror(reflectance: 1.0)),
                (shape: Parallelogram(corner: (-1.0, 2.0, 0.0), e1: (2.0, 0.0, 0.0), e2: (0.0, 0.0, 4.0)), color: (1.0, 0.0, 0.0)),
            ],
            effects: ["reflections", "shadows"],
            lights: [Directional(direction: (0.0, 1.0, 0.0), intensity: 1.0)],
            settings: (ambient: 0.0),
        )"#,
        );
        let tree = ray_tree(&prepared, 0, 0);
        assert_eq!(tree.root.hit.map(|h| h.object), Some(0));
        assert_eq!(tree.root.children.len(), 1);
        let mirrored = &tree.root.children[0];
        assert_eq!((mirrored.kind, mirrored.depth), (RayKind::Reflection, 1));
        assert_eq!(mirrored.hit.map(|h| h.object), Some(1));
        // r = d − 2(d·n)n off the floor z = 0: the vertical component flips.
        let d = tree.root.ray.dir;
        let r = mirrored.ray.dir;
        assert!((r[2] + d[2]).abs() < 1e-12 && (r[1] - d[1]).abs() < 1e-12);
        // The wall faces the light travelling +y: its shadow ray to the light is cast and lit.
        assert!(matches!(mirrored.lights[0].test, LightTest::Lit(..)));
        assert_eq!(tree.root.all().len(), 2);
        assert_eq!(tree.samples, None);
    }

    #[test]
    fn a_glass_pixel_has_a_refracted_and_a_reflected_child_that_bend_by_snell() {
        let prepared = prepared(
            r#"(
            width: 1, height: 1,
            camera: Pinhole(position: (1.5, -4.0, 0.3), target: (0.0, 1.0, 0.3), fov_y: 5.0),
            objects: [
                (shape: Parallelogram(corner: (-0.5, 1.0, -1.0), e1: (1.0, 0.0, 0.0), e2: (0.0, 0.0, 2.0)), material: Glass(ior: 1.5)),
                (shape: Parallelogram(corner: (-5.0, 3.0, -5.0), e1: (10.0, 0.0, 0.0), e2: (0.0, 0.0, 10.0))),
            ],
            effects: ["refraction", "reflections"],
            settings: (max_depth: 1),
        )"#,
        );
        // The pane's normal e1 × e2 = (0, −2, 0) faces the camera: the ray goes into the glass.
        let tree = ray_tree(&prepared, 0, 0);
        assert_eq!(tree.root.hit.map(|h| h.object), Some(0), "the glass pane");
        let kinds: Vec<_> = tree
            .root
            .children
            .iter()
            .map(|c| (c.kind, c.depth))
            .collect();
        assert_eq!(
            kinds,
            [(RayKind::Refraction, 1), (RayKind::Reflection, 1)],
            "refracted first, then the Fresnel reflection"
        );
        // Into glass at incidence θ₁: sin θ₂ = sin θ₁ / 1.5.
        let sine = |d: &V3<f64>| {
            let length = crate::math::linalg::dot(d, d).sqrt();
            (d[0] * d[0] + d[2] * d[2]).sqrt() / length
        };
        let into = sine(&tree.root.ray.dir);
        let through = sine(&tree.root.children[0].ray.dir);
        assert!(into > 0.001, "a slanted ray: {into}");
        assert!((through - into / 1.5).abs() < 1e-12, "{into} {through}");
        // The depth limit: no ray below bounce 1.
        assert!(tree.root.children.iter().all(|c| c.children.is_empty()));
    }

    #[test]
    fn occlusion_rays_are_summarised_and_samples_counted() {
        let prepared = prepared(
            r#"(
            width: 8, height: 6,
            camera: Pinhole(position: (0.0, -3.0, 2.0), target: (0.0, 0.0, 0.0), fov_y: 30.0),
            objects: [(shape: Parallelogram(corner: (-50.0, -50.0, 0.0), e1: (100.0, 0.0, 0.0), e2: (0.0, 100.0, 0.0)))],
            effects: ["ambient-occlusion", "antialiasing"],
            settings: (occlusion_rays: 12, samples_per_side: 3),
        )"#,
        );
        let tree = ray_tree(&prepared, 3, 4);
        let occlusion = Occlusion {
            cast: 12,
            blocked: 0,
        };
        assert_eq!(tree.root.occlusion, Some(occlusion), "an open plane");
        assert_eq!(tree.samples, Some(Samples { cast: 9, hit: 9 }));
        assert!(tree.root.lights.is_empty());
    }
}
