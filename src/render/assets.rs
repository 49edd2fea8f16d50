//! Files a render scene names: OBJ meshes (read with tobj) and PNG textures (read with image).
//!
//! The shipped ones are embedded in the binary, so the preset scenes render anywhere (a web page
//! included); other names are looked up on disk beside the scene file.

use std::io::BufReader;
use std::path::PathBuf;

use super::objects::{PreparedTriangle, mesh_triangle};
use crate::geometry::linalg::V3;

/// The meshes and textures under `assets/`, by their name relative to it.
const EMBEDDED: [(&str, &[u8]); 2] = [
    (
        "meshes/octasphere.obj",
        include_bytes!("../../assets/meshes/octasphere.obj"),
    ),
    (
        "textures/checker.png",
        include_bytes!("../../assets/textures/checker.png"),
    ),
];

/// Where a scene's files come from.
pub trait AssetSource {
    /// The bytes of `name` (relative to `assets/`), or why not.
    fn read(&self, name: &str) -> Result<Vec<u8>, String>;
}

/// Only the files embedded in the binary.
pub struct Embedded;

impl AssetSource for Embedded {
    fn read(&self, name: &str) -> Result<Vec<u8>, String> {
        embedded(name).map(<[u8]>::to_vec).ok_or_else(|| {
            let names: Vec<&str> = EMBEDDED.iter().map(|(n, _)| *n).collect();
            format!(
                "no file '{name}' among the shipped assets ({})",
                names.join(", ")
            )
        })
    }
}

fn embedded(name: &str) -> Option<&'static [u8]> {
    let name = name.trim_start_matches("assets/");
    EMBEDDED.iter().find(|(n, _)| *n == name).map(|(_, b)| *b)
}

/// The embedded files first, then files on disk in the given folders, in order (a scene file's
/// folder, and its parent, so a scene in `assets/scenes/` finds `meshes/…`).
pub struct OnDisk(pub Vec<PathBuf>);

impl OnDisk {
    /// Looks beside the scene file and in its parent folder.
    pub fn beside(scene_file: &std::path::Path) -> OnDisk {
        let folder = scene_file.parent().map(PathBuf::from).unwrap_or_default();
        let parent = folder.join("..");
        OnDisk(vec![folder, parent])
    }
}

impl AssetSource for OnDisk {
    fn read(&self, name: &str) -> Result<Vec<u8>, String> {
        if let Some(bytes) = embedded(name) {
            return Ok(bytes.to_vec());
        }
        for folder in &self.0 {
            if let Ok(bytes) = std::fs::read(folder.join(name)) {
                return Ok(bytes);
            }
        }
        let tried: Vec<String> = self
            .0
            .iter()
            .map(|f| f.join(name).display().to_string())
            .collect();
        Err(format!(
            "cannot find '{name}' (not shipped, and not at {})",
            tried.join(" or ")
        ))
    }
}

/// Reads an OBJ file's triangles (polygons are triangulated), with its normals and UVs when every
/// vertex has them.
pub fn load_mesh(assets: &dyn AssetSource, name: &str) -> Result<Vec<PreparedTriangle>, String> {
    let bytes = assets.read(name)?;
    check_face_indices(&bytes).map_err(|e| format!("{name}: not a readable OBJ mesh: {e}"))?;
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ..Default::default()
    };
    let (models, _) = tobj::load_obj_buf(&mut BufReader::new(&bytes[..]), &options, |_| {
        Err(tobj::LoadError::OpenFileFailed)
    })
    .map_err(|e| format!("{name}: not a readable OBJ mesh: {e}"))?;
    let mut triangles = Vec::new();
    for model in &models {
        let mesh = &model.mesh;
        let point = |i: u32| -> V3<f64> {
            let i = i as usize * 3;
            [
                mesh.positions[i],
                mesh.positions[i + 1],
                mesh.positions[i + 2],
            ]
        };
        let has_normals = mesh.normals.len() == mesh.positions.len();
        let has_uvs = mesh.texcoords.len() * 3 == mesh.positions.len() * 2;
        for face in mesh.indices.chunks_exact(3) {
            let face: [u32; 3] = [face[0], face[1], face[2]];
            let vertices = [point(face[0]), point(face[1]), point(face[2])];
            if vertices.iter().flatten().any(|c| !c.is_finite()) {
                return Err(format!("{name}: a vertex is not a finite number"));
            }
            let normals = has_normals.then(|| {
                face.map(|i| {
                    let i = i as usize * 3;
                    [mesh.normals[i], mesh.normals[i + 1], mesh.normals[i + 2]]
                })
            });
            let uvs = has_uvs.then(|| {
                face.map(|i| {
                    let i = i as usize * 2;
                    [mesh.texcoords[i], mesh.texcoords[i + 1]]
                })
            });
            triangles.push(mesh_triangle(vertices, normals, uvs));
        }
    }
    if triangles.is_empty() {
        return Err(format!("{name}: the OBJ file has no faces"));
    }
    Ok(triangles)
}

/// A decoded texture: linear RGB texels, row 0 at the top (v = 1), wrapping in both directions.
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    /// Width in texels.
    pub width: usize,
    /// Height in texels.
    pub height: usize,
    /// RGB in [0, 1].
    pub texels: Vec<[f32; 3]>,
}

impl Texture {
    /// Decodes a PNG.
    pub fn load(assets: &dyn AssetSource, name: &str) -> Result<Texture, String> {
        let bytes = assets.read(name)?;
        let image = image::load_from_memory_with_format(&bytes, image::ImageFormat::Png)
            .map_err(|e| format!("{name}: not a readable PNG: {e}"))?
            .to_rgb8();
        let (width, height) = (image.width() as usize, image.height() as usize);
        let texels = image
            .pixels()
            .map(|p| p.0.map(|c| c as f32 / 255.0))
            .collect();
        Ok(Texture {
            width,
            height,
            texels,
        })
    }

    /// The nearest texel to (u, v); u runs left to right, v bottom to top, repeating outside [0, 1].
    pub fn sample(&self, u: f64, v: f64) -> [f32; 3] {
        let wrap = |x: f64, n: usize| {
            let i = (x.rem_euclid(1.0) * n as f64).floor() as usize;
            i.min(n - 1)
        };
        let column = wrap(u, self.width);
        let row = self.height - 1 - wrap(v, self.height);
        self.texels[row * self.width + column]
    }
}

/// Refuses face indices that tobj would turn into wrapped-around array indices (0, a relative index
/// reaching before the first vertex, or one past any mesh): it panics on them in debug builds and
/// reads the wrong vertex in release builds.
fn check_face_indices(bytes: &[u8]) -> Result<(), String> {
    const LARGEST_INDEX: i64 = 1 << 32;
    let mut counts = [0i64; 3];
    for (number, line) in String::from_utf8_lossy(bytes).lines().enumerate() {
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => counts[0] += 1,
            Some("vt") => counts[1] += 1,
            Some("vn") => counts[2] += 1,
            Some("f" | "l" | "p") => {
                for vertex in words {
                    for (slot, part) in vertex.split('/').enumerate().take(3) {
                        let Ok(index) = part.parse::<i64>() else {
                            continue; // empty (v//vn) or malformed: tobj reports those itself
                        };
                        let known = counts[slot];
                        if index == 0 || index < -known || index > LARGEST_INDEX {
                            return Err(format!(
                                "line {}: index {index} is out of range ({known} {} before it)",
                                number + 1,
                                ["vertices", "texture coordinates", "normals"][slot]
                            ));
                        }
                    }
                }
            }
            _ => {}
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shipped_mesh_and_texture_load() {
        let mesh = load_mesh(&Embedded, "meshes/octasphere.obj").unwrap();
        assert_eq!(mesh.len(), 512);
        assert!(mesh.iter().all(|t| t.normals.is_some() && t.uvs.is_some()));
        let texture = Texture::load(&Embedded, "textures/checker.png").unwrap();
        assert!(texture.width > 0 && texture.height > 0);
    }

    #[test]
    fn a_missing_or_broken_file_says_what_is_wrong() {
        let missing = load_mesh(&Embedded, "meshes/none.obj").unwrap_err();
        assert!(missing.contains("meshes/none.obj"), "{missing}");
        struct Garbage;
        impl AssetSource for Garbage {
            fn read(&self, _: &str) -> Result<Vec<u8>, String> {
                Ok(b"not a png".to_vec())
            }
        }
        let broken = Texture::load(&Garbage, "t.png").unwrap_err();
        assert!(broken.contains("t.png: not a readable PNG"), "{broken}");
    }
}
