//! Hostile files through the real binary: scenes with typos, scenes that would hang the renderer,
//! meshes and textures that are not what they claim, outputs that must not be destroyed. Each case
//! ends within a second with a one-line error that names the problem.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

fn raylab(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_raylab"))
        .args(args)
        .output()
        .expect("the binary runs")
}

fn stderr(output: &Output) -> String {
    String::from_utf8_lossy(&output.stderr).into_owned()
}

/// A fresh scratch folder for one test.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("raylab-hostile-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// The shipped closed-mesh scene's text.
fn mesh_scene() -> String {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/assets/scenes/render-mesh.ron");
    std::fs::read_to_string(path).unwrap()
}

/// Renders `scene` (written into `dir`) to `dir/out.png`; the run must fail within a second with one
/// line on standard error, which is returned.
fn refused(dir: &Path, name: &str, scene: &str) -> String {
    let file = dir.join(name);
    std::fs::write(&file, scene).unwrap();
    let png = dir.join("out.png");
    let clock = Instant::now();
    let output = raylab(&[
        "render",
        file.to_str().unwrap(),
        "-o",
        png.to_str().unwrap(),
    ]);
    let elapsed = clock.elapsed();
    let message = stderr(&output);
    assert_eq!(output.status.code(), Some(1), "{name}: {message}");
    assert!(elapsed < Duration::from_secs(1), "{name} took {elapsed:?}");
    assert_eq!(message.trim_end().lines().count(), 1, "{name}: {message}");
    assert!(!png.exists(), "{name}: an image was written");
    message
}

#[test]
fn a_typo_in_a_scene_is_refused_with_file_line_and_column() {
    let dir = scratch("typo");
    let text = mesh_scene().replace(
        "effects:",
        "methd: Some(\"bogus-method\"),\n        effects:",
    );
    let message = refused(&dir, "typo.ron", &text);
    assert!(
        message.contains("typo.ron:11:9: unknown field 'methd' in RenderScene, expected one of"),
        "{message}"
    );
    let text = mesh_scene().replace(
        "color: (0.3",
        "texure: Some(\"no/such/file.png\"), color: (0.3",
    );
    let message = refused(&dir, "texure.ron", &text);
    assert!(
        message.contains("unknown field 'texure' in Object"),
        "{message}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// The render scene of `mesh_scene` with this object instead of the shipped sphere.
fn with_object(object: &str) -> String {
    mesh_scene().replace(
        "(shape: Mesh(obj: \"meshes/octasphere.obj\"), color: (0.3, 0.6, 0.9))",
        object,
    )
}

#[test]
fn numbers_that_would_overflow_or_hang_the_renderer_are_refused() {
    let dir = scratch("overflow");
    let sphere = "shape: Mesh(obj: \"meshes/octasphere.obj\")";
    let image_plane = |camera: &str| {
        mesh_scene().replace(
            "Pinhole(position: (0.0, -4.0, 0.0), target: (0.0, 0.0, 0.0), fov_y: 35.0)",
            camera,
        )
    };
    for (name, scene, expected) in [
        (
            // This one rendered for minutes: every ray tested every triangle in exact arithmetic.
            "translate.ron",
            with_object(&format!(
                "({sphere}, transform: (translate: (1e308, 1e308, 1e308)))"
            )),
            "object 1: coordinates must be at most 1e30 in magnitude (so the renderer's arithmetic \
             cannot overflow), found 1e308",
        ),
        (
            "scale.ron",
            with_object(&format!(
                "({sphere}, transform: (scale: (1e-200, 1.0, 1.0)))"
            )),
            "object 1: the transform's scale component 1e-200 is too small to invert safely",
        ),
        (
            "camera.ron",
            image_plane(
                "Pinhole(position: (0.0, -1e300, 0.0), target: (0.0, 0.0, 0.0), fov_y: 35.0)",
            ),
            "the camera's numbers must be at most 1e30 in magnitude",
        ),
        (
            "target.ron",
            image_plane(
                "Pinhole(position: (0.0, -4.0, 0.0), target: (0.0, -4.0, 1e-310), fov_y: 35.0)",
            ),
            "the camera's position and target are the same point (or closer than 1e-30)",
        ),
        (
            "plane.ron",
            image_plane("ImagePlane(x: (0.0, 0.0), y: (0.0, 0.0), z: 0.0)"),
            "the image plane is at z = 0: rays start on the plane",
        ),
    ] {
        let message = refused(&dir, name, &scene);
        assert!(message.contains(expected), "{name}: {message}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn meshes_with_bad_vertices_or_faces_first_are_refused() {
    let dir = scratch("obj");
    std::fs::create_dir_all(dir.join("meshes")).unwrap();
    for (obj, text, expected) in [
        (
            "nan.obj",
            "v nan 0 3\nv 1 0 3\nv 0 1 3\nf 1 2 3\n",
            "meshes/nan.obj: vertex coordinates must be finite numbers, found NaN",
        ),
        (
            "huge.obj",
            "v 1e300 0 3\nv 1 0 3\nv 0 1 3\nf 1 2 3\n",
            "meshes/huge.obj: vertex coordinates must be at most 1e30 in magnitude",
        ),
        (
            "early.obj",
            "f 1 2 3\nv 0 0 3\nv 1 0 3\nv 0 1 3\n",
            "meshes/early.obj: line 1: the face uses vertex 1, but no vertex comes before it",
        ),
    ] {
        std::fs::write(dir.join("meshes").join(obj), text).unwrap();
        let scene = with_object(&format!("(shape: Mesh(obj: \"meshes/{obj}\"))"));
        let message = refused(&dir, &format!("{obj}.ron"), &scene);
        assert!(message.contains(expected), "{obj}: {message}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}
