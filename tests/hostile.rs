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
