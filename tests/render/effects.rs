//! The effects past ray casting (issue 13): an effect not declared casts no ray of its kind in any
//! shipped scene, and each effect gives the answer known analytically: a shadow's edge at the pixel
//! the light's projection predicts, ambient occlusion of an open plane = 1, k×k antialiasing samples, the pixel their mean.
//! (The reflected direction, Snell's angle and total internal reflection at the critical angle are
//! unit tests of `render::shading::optics`.)

// A test or benchmark fails by panicking: unwrap and expect are how it says so.
#![allow(clippy::unwrap_used, clippy::expect_used)]

use crate::shipped;
use shipped::shipped_render_scenes;

use raylab::math::linalg::V3;
use raylab::render::cast::nearest_hit;
use raylab::render::inspect::cost::each_left_out;
use raylab::render::inspect::probe::probe;
use raylab::render::ray_kinds::RayKind;
use raylab::render::{Prepared, Ray, Stats, loading::assets::Embedded, render};
use raylab::scene::render::{Effect, RenderScene};
use raylab::scene::{Problem, Scene};

/// A render scene from the text of its `Render(...)`.
fn render_scene(body: &str) -> RenderScene {
    let text = format!("(title: \"t\", note: \"n\", problem: Render({body}))");
    match Scene::from_ron(&text, "test.ron").unwrap().problem {
        Problem::Render(scene) => scene,
        _ => unreachable!(),
    }
}

/// The effects past ray casting and the kind of ray each casts.
fn kinds() -> impl Iterator<Item = (Effect, RayKind)> {
    RayKind::ALL
        .into_iter()
        .filter_map(|kind| kind.effect().map(|effect| (effect, kind)))
}

#[test]
fn an_effect_not_declared_casts_no_ray_of_its_kind_in_any_shipped_scene() {
    let scenes = shipped_render_scenes();
    let mut effects_seen = Vec::new();
    for (file, scene) in &scenes {
        let mut base = Prepared::new(scene, &Embedded).unwrap();
        // An eighth of each side: the counting does not depend on the resolution.
        base.width = (base.width / 8).max(2);
        base.height = (base.height / 8).max(2);
        let mut subsets = vec![scene.effects.clone()];
        subsets.extend(each_left_out(&scene.effects).map(|(_, rest)| rest));
        for (i, effects) in subsets.into_iter().enumerate() {
            let mut prepared = base.clone();
            prepared.effects = effects.clone();
            let (_, stats) = render(&prepared);
            for (effect, kind) in kinds() {
                let rays = stats.rays_of(kind);
                if !effects.contains(&effect) {
                    assert_eq!(rays, 0, "{file} with {effects:?}: {kind:?} rays");
                } else if i == 0 {
                    // As shipped, each declared effect casts rays (the scenes are built to show them).
                    assert!(rays > 0, "{file}: {effect:?} declared but no {kind:?} ray");
                    effects_seen.push(effect);
                }
            }
            if scene.lights.is_empty() {
                assert_eq!(stats.secondary.light_evaluations, 0, "{file}");
            }
            let traced = kinds().any(|(e, _)| effects.contains(&e));
            if !traced && (scene.lights.is_empty() || effects == [Effect::Coverage]) {
                // Ray casting alone: nothing past it is done at all.
                assert_eq!(
                    stats.secondary,
                    Default::default(),
                    "{file} with {effects:?}"
                );
            }
        }
    }
    for (effect, _) in kinds() {
        assert!(
            effects_seen.contains(&effect),
            "no shipped scene shows {effect:?}"
        );
    }
}

/// A floor (z = 0, seen from above) and a strip at z = 1 over x ≤ 0, lit by a point light at
/// (2, 0, 3): the strip's edge x = 0 throws the shadow's edge to x = 2 + (0 − 2)·3/(3 − 1) = −1.
const SHADOW_SCENE: &str = r#"(
    width: 81, height: 41,
    camera: Pinhole(position: (-1.0, -4.0, 6.0), target: (-1.0, 0.0, 0.0), fov_y: 40.0),
    objects: [
        (shape: Parallelogram(corner: (-6.0, -6.0, 0.0), e1: (12.0, 0.0, 0.0), e2: (0.0, 12.0, 0.0))),
        (shape: Parallelogram(corner: (-4.0, -1.5, 1.0), e1: (4.0, 0.0, 0.0), e2: (0.0, 3.0, 0.0))),
    ],
    effects: ["shadows"],
    lights: [Point(position: (2.0, 0.0, 3.0), intensity: 9.0)],
    settings: (ambient: 0.0),
)"#;

#[test]
fn a_shadow_edge_falls_on_the_pixel_the_light_projects_it_to() {
    let prepared = Prepared::new(&render_scene(SHADOW_SCENE), &Embedded).unwrap();
    let (image, stats) = render(&prepared);
    let mut checked = 0;
    let mut edges = 0;
    for row in 0..prepared.height {
        let mut before: Option<bool> = None;
        for column in 0..prepared.width {
            let Ray { origin, dir } = prepared.ray(row, column);
            let hit = nearest_hit(&prepared, Ray::new(origin, dir), &mut Stats::default());
            // Only the floor, where the strip's shadow falls (its y range seen from the light).
            let Some(hit) = hit.filter(|h| h.object == 0) else {
                before = None;
                continue;
            };
            let floor: V3<f64> = std::array::from_fn(|k| origin[k] + hit.t * dir[k]);
            // The light's ray to the floor point crosses z = 1 at (x, y) = L + (P − L)·(3 − 1)/3.
            let at = |k: usize| [2.0, 0.0][k] + (floor[k] - [2.0, 0.0][k]) * 2.0 / 3.0;
            let (x, y) = (at(0), at(1));
            if !(-1.5 + 1e-6..1.5 - 1e-6).contains(&y) {
                before = None;
                continue;
            }
            let shadowed = (-4.0..=0.0).contains(&x);
            let dark = image.pixels[row * prepared.width + column] == [0.0; 3];
            assert_eq!(dark, shadowed, "pixel ({row}, {column}): floor {floor:?}");
            if before.is_some_and(|b| b != shadowed) {
                edges += 1;
            }
            before = Some(shadowed);
            checked += 1;
        }
    }
    assert!(
        checked > 500 && edges > 5,
        "{checked} pixels, {edges} edges"
    );
    assert!(stats.secondary.blocked > 0);
}

#[test]
fn the_open_plane_is_wholly_unoccluded() {
    let scene = render_scene(
        r#"(
        width: 24, height: 16,
        camera: Pinhole(position: (0.0, -3.0, 2.0), target: (0.0, 0.0, 0.0), fov_y: 40.0),
        objects: [(shape: Parallelogram(corner: (-50.0, -50.0, 0.0), e1: (100.0, 0.0, 0.0), e2: (0.0, 100.0, 0.0)), color: (0.5, 0.25, 1.0))],
        effects: ["ambient-occlusion"],
        settings: (occlusion_rays: 12),
    )"#,
    );
    let prepared = Prepared::new(&scene, &Embedded).unwrap();
    let (image, stats) = render(&prepared);
    assert!(stats.hits > 100);
    assert_eq!(stats.secondary.occlusion_rays, 12 * stats.hits);
    assert_eq!(stats.secondary.blocked, 0);
    for (pixel, covered) in image.pixels.iter().zip(&image.covered) {
        if *covered {
            // Without lights or a shading effect the surface is white (as coverage), times AO = 1.
            assert_eq!(*pixel, [1.0; 3], "AO of an open plane is 1");
        }
    }
}

#[test]
fn antialiasing_casts_k_squared_samples_a_pixel() {
    for k in [1, 2, 3] {
        let scene = render_scene(&format!(
            r#"(
            width: 10, height: 6,
            camera: ImagePlane(x: (1.0, -1.0), y: (0.6, -0.6), z: 1.0),
            objects: [(shape: Triangle(vertices: ((0.0, 1.0, 2.0), (1.0, -1.0, 2.0), (-1.0, -1.0, 2.0))))],
            effects: ["coverage", "antialiasing"],
            settings: (samples_per_side: {k}),
        )"#
        ));
        let prepared = Prepared::new(&scene, &Embedded).unwrap();
        let (image, stats) = render(&prepared);
        assert_eq!(stats.rays, 60);
        assert_eq!(stats.secondary.sample_rays, 60 * k * k, "k = {k}");
        // The colour is the mean of the k² samples alone: under coverage a sample is white or black,
        // so each pixel is (samples that hit)/k², and together they account for every sample hit.
        let k2 = (k * k) as f32;
        let mut hits = 0;
        for pixel in &image.pixels {
            let white = pixel[0] * k2;
            assert_eq!(
                white,
                white.round(),
                "k = {k}: {pixel:?} is not a mean of {k2} samples"
            );
            assert!(pixel.iter().all(|c| *c == pixel[0]));
            hits += white.round() as u64;
        }
        assert_eq!(hits, stats.secondary.hits, "k = {k}");
        // Some pixels on the triangle's edges are partly covered.
        assert!(k == 1 || image.pixels.iter().any(|p| p[0] > 0.0 && p[0] < 1.0));
        // Coverage is the centre ray's: the same mask as without antialiasing.
        let mut plain = prepared.clone();
        plain.effects = vec![Effect::Coverage];
        assert_eq!(render(&plain).0.covered, image.covered, "k = {k}");
    }
}

/// A ray down onto a mirror floor comes back up by r = d − 2(d·n)n and shows what is above: the
/// render's mirror pixel takes the colour of the object the reflected ray hits.
#[test]
fn a_mirror_shows_what_the_reflected_ray_hits() {
    let scene = render_scene(
        r#"(
        width: 1, height: 1,
        camera: Pinhole(position: (0.0, -2.0, 2.0), target: (0.0, 0.0, 0.0), fov_y: 10.0),
        objects: [
            (shape: Parallelogram(corner: (-1.0, -1.0, 0.0), e1: (2.0, 0.0, 0.0), e2: (0.0, 2.0, 0.0)), material: Mirror(reflectance: 1.0)),
            (shape: Parallelogram(corner: (-1.0, 2.0, 0.0), e1: (2.0, 0.0, 0.0), e2: (0.0, 0.0, 4.0)), color: (1.0, 0.0, 0.0)),
        ],
        effects: ["reflections"],
        lights: [Directional(direction: (0.0, 1.0, 0.0), intensity: 1.0)],
        settings: (ambient: 0.0),
    )"#,
    );
    let prepared = Prepared::new(&scene, &Embedded).unwrap();
    let Ray { origin, dir } = prepared.ray(0, 0);
    // The scene's precondition: the pixel's ray meets the floor at (0, 0, 0); its reflection climbs
    // the wall at y = 2.
    let t = -origin[2] / dir[2];
    let floor: V3<f64> = std::array::from_fn(|k| origin[k] + t * dir[k]);
    assert!(floor.iter().all(|c| c.abs() < 1e-12), "{floor:?}");
    let (image, stats) = render(&prepared);
    assert_eq!(stats.secondary.reflection_rays, 1);
    assert_eq!(stats.secondary.hits, 1);
    // The red wall, lit head-on by the light travelling +y, is what the mirror pixel shows.
    assert!(
        image.pixels[0][0] > 0.5 && image.pixels[0][1] == 0.0,
        "{:?}",
        image.pixels[0]
    );
}

/// The probe reports the pixel's colour as the render gives it, in every shipped scene: lit ones,
/// with shadows, mirrors, glass, occlusion and antialiasing's mean included (the probe used to shade
/// its one ray unlit).
#[test]
fn the_probe_reports_the_rendered_pixels_colour_in_every_shipped_scene() {
    for (file, scene) in shipped_render_scenes() {
        let mut prepared = Prepared::new(&scene, &Embedded).unwrap();
        prepared.width = (prepared.width / 8).max(2);
        prepared.height = (prepared.height / 8).max(2);
        let (image, _) = render(&prepared);
        let (w, h) = (prepared.width, prepared.height);
        for (row, column) in [
            (h / 2, w / 2),
            (h / 3, w / 4),
            (h - 1, w - 1),
            (h / 2, w / 3),
        ] {
            let (probed, shown) = (
                probe(&prepared, row, column).color,
                image.pixels[row * w + column],
            );
            // To the f32 rounding of seed 003's batched path, which interpolates in f32.
            let apart = (0..3)
                .map(|k| (probed[k] - shown[k]).abs())
                .fold(0.0, f32::max);
            assert!(
                apart <= 1e-6,
                "{file} at ({row}, {column}): probed {probed:?}, shown {shown:?}"
            );
        }
    }
}

/// Every shadow ray of the correct Cornell box (at 60x60, every pixel, every bounce) leaves its
/// surface on the face's side it goes to, so none is blocked by the very triangle its ray hit. Moved
/// along the interpolated normal (as the render did), a sphere pixel's shadow ray met its own
/// triangle at t ≈ 1.5e-5: the shadow acne the app teaches as a bug, in the correct image.
#[test]
fn no_shadow_ray_of_the_cornell_box_is_blocked_by_its_own_triangle() {
    use raylab::render::inspect::ray_tree::{TracedRay, ray_tree};
    use raylab::render::secondary::LightTest;
    let (_, mut scene) = shipped_render_scenes()
        .into_iter()
        .find(|(name, _)| name.contains("render-cornell-box"))
        .expect("the Cornell box ships");
    (scene.width, scene.height) = (60, 60);
    let prepared = Prepared::new(&scene, &Embedded).unwrap();
    let (mut blocked, mut lit) = (0, 0);
    for row in 0..prepared.height {
        for column in 0..prepared.width {
            let tree = ray_tree(&prepared, row, column);
            let mut stack: Vec<&TracedRay> = vec![&tree.root];
            while let Some(traced) = stack.pop() {
                stack.extend(&traced.children);
                let Some(hit) = traced.hit else { continue };
                for light in &traced.lights {
                    match (light.test, light.blocker) {
                        (LightTest::Blocked(..), Some(blocker)) => {
                            blocked += 1;
                            assert!(
                                (blocker.object, blocker.primitive) != (hit.object, hit.primitive),
                                "pixel ({row}, {column}), {:?} ray: its shadow ray is blocked by \
                                 its own triangle at t = {}",
                                traced.kind,
                                blocker.t
                            );
                        }
                        (LightTest::Lit(..), _) => lit += 1,
                        _ => {}
                    }
                }
            }
        }
    }
    // The box's spheres and blocks do cast shadows, and most shadow rays reach the light.
    assert!(blocked > 100 && lit > 1000, "{blocked} blocked, {lit} lit");
}
