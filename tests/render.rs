//! The renderer on seed 003's scenes: the same covered pixels as the seed's own method, and only the
//! work the scene's effects call for.

use raylab::accuracy::Method;
use raylab::render::{Prepared, RenderScene, assets::Embedded, render};
use raylab::scene::{Problem, Scene};

fn scene(file: &str) -> RenderScene {
    let path = format!("{}/assets/scenes/{file}", env!("CARGO_MANIFEST_DIR"));
    match Scene::load(std::path::Path::new(&path)).unwrap().problem {
        Problem::Render(scene) => scene,
        other => panic!("{file} is not a render scene: {other:?}"),
    }
}

fn prepared(file: &str, method: Method) -> Prepared {
    let mut prepared = Prepared::new(&scene(file), &Embedded).unwrap();
    prepared.method = Some(method);
    prepared
}

#[test]
fn seed_003_scenes_cover_the_same_pixels_as_the_seeds_method() {
    for file in ["seed003-facing.ron", "seed003-barycentric.ron"] {
        let (watertight, stats) = render(&prepared(file, Method::Watertight));
        // Seed 003's own method: plane hit, then the three edge tests (with `or` fixed).
        let (plane, _) = render(&prepared(file, Method::Plane));
        let differ = watertight
            .covered
            .iter()
            .zip(&plane.covered)
            .filter(|(a, b)| a != b)
            .count();
        assert!(differ <= 4, "{file}: {differ} pixels differ on the edges");
        assert_eq!(stats.rays as usize, 512 * 256);
        assert!(watertight.covered_pixels() > 30_000, "{file}");
    }
}

#[test]
fn the_facing_scene_shades_and_never_interpolates() {
    let (_, stats) = render(&prepared("seed003-facing.ron", Method::Watertight));
    assert_eq!(stats.color_interpolations, 0);
    assert_eq!(stats.shading, stats.hits);
    let (_, stats) = render(&prepared("seed003-barycentric.ron", Method::Watertight));
    assert_eq!(stats.shading, 0);
    assert_eq!(stats.color_interpolations, stats.hits);
}
