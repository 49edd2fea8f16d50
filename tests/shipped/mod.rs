//! The shipped scenes, as the render and effects tests iterate them.

use std::path::Path;

use raylab::scene::render::RenderScene;
use raylab::scene::{Problem, Scene};

/// Every shipped scene file whose problem is a render, by file name.
pub fn shipped_render_scenes() -> Vec<(String, RenderScene)> {
    let folder = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes");
    let mut files: Vec<_> = std::fs::read_dir(&folder)
        .unwrap()
        .map(|entry| entry.unwrap().path())
        .filter(|path| path.extension().is_some_and(|e| e == "ron"))
        .collect();
    files.sort();
    files
        .into_iter()
        .filter_map(|path| match Scene::load(&path).unwrap().problem {
            Problem::Render(scene) => {
                let name = path.file_name().unwrap().to_string_lossy().into_owned();
                Some((name, scene))
            }
            _ => None,
        })
        .collect()
}
