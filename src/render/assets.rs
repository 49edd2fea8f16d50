//! Files a render scene names: OBJ meshes (read with tobj) and PNG textures (read with image).
//!
//! The shipped ones are embedded in the binary, so the preset scenes render anywhere (a web page
//! included); other names are looked up on disk beside the scene file.

use std::io::BufReader;
use std::path::PathBuf;

use super::objects::{PreparedTriangle, mesh_triangle};
use crate::files::{FileKind, MESH, ReadError, TEXTURE, read_regular};
use crate::math::linalg::V3;

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
    /// The bytes of `name` (relative to `assets/`), a file of `kind` and at most its size, or why not.
    fn read(&self, name: &str, kind: FileKind) -> Result<Vec<u8>, String>;
}

/// Only the files embedded in the binary.
pub struct Embedded;

impl AssetSource for Embedded {
    fn read(&self, name: &str, _: FileKind) -> Result<Vec<u8>, String> {
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
    fn read(&self, name: &str, kind: FileKind) -> Result<Vec<u8>, String> {
        if let Some(bytes) = embedded(name) {
            return Ok(bytes.to_vec());
        }
        for folder in &self.0 {
            let path = folder.join(name);
            match read_regular(&path, kind) {
                Ok(bytes) => return Ok(bytes),
                Err(ReadError::NotFound) => continue,
                Err(ReadError::Refused(why)) => return Err(format!("{}: {why}", path.display())),
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
    let bytes = assets.read(name, MESH)?;
    check_faces(&bytes).map_err(|e| format!("{name}: {e}"))?;
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
        crate::scene::render::check_numbers("vertex coordinates", &mesh.positions)
            .map_err(|e| format!("{name}: {e}"))?;
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

/// The most triangles a mesh may have (polygons count as the triangles they are cut into): a
/// prepared triangle with normals and texture coordinates takes about 300 bytes, so 2 million take
/// about 600 MB.
pub const MAX_MESH_TRIANGLES: u64 = 2_000_000;

/// Checks an OBJ file before it is parsed: a face may only use the vertices above it (tobj resolves
/// the indices at the end of the file, so a face before its vertices would otherwise draw whatever
/// comes later), and the faces make at most [`MAX_MESH_TRIANGLES`] triangles.
fn check_faces(obj: &[u8]) -> Result<(), String> {
    let mut vertices = 0u64;
    let mut triangles = 0u64;
    for (number, line) in obj.split(|b| *b == b'\n').enumerate() {
        let line = String::from_utf8_lossy(line);
        let mut tokens = line.split_whitespace();
        match tokens.next() {
            Some("v") => vertices += 1,
            Some("f") => {
                let corners = tokens.clone().count() as u64;
                triangles += corners.saturating_sub(2);
                if triangles > MAX_MESH_TRIANGLES {
                    return Err(format!(
                        "line {}: the mesh has more than {} million triangles, the most a mesh may \
                         have",
                        number + 1,
                        MAX_MESH_TRIANGLES / 1_000_000
                    ));
                }
                for token in tokens {
                    let index = token.split('/').next().unwrap_or("");
                    let Ok(index) = index.parse::<i64>() else {
                        continue; // tobj reports what it cannot read.
                    };
                    if index.unsigned_abs() > vertices {
                        let before = match vertices {
                            0 => "no vertex comes".to_string(),
                            1 => "only 1 vertex comes".to_string(),
                            n => format!("only {n} vertices come"),
                        };
                        return Err(format!(
                            "line {}: the face uses vertex {index}, but {before} before it (an OBJ \
                             file's faces must follow their vertices)",
                            number + 1
                        ));
                    }
                }
            }
            _ => {}
        }
    }
    Ok(())
}

/// The most pixels a texture may have (4096 × 4096): its texels then take 48 MiB.
pub const MAX_TEXTURE_PIXELS: u64 = 4096 * 4096;

/// The most memory the PNG decoder may allocate (a 4096 × 4096 image of 16-bit RGBA takes 128 MiB).
const MAX_DECODER_BYTES: u64 = 256 << 20;

/// A decoded texture: 8-bit RGB texels (3 bytes each), row 0 at the top (v = 1), wrapping in both
/// directions.
#[derive(Clone, Debug, PartialEq)]
pub struct Texture {
    /// Width in texels.
    pub width: usize,
    /// Height in texels.
    pub height: usize,
    /// R, G, B of each texel in turn, 0 to 255 (3 bytes a texel).
    pub texels: Vec<u8>,
}

impl Texture {
    /// Decodes a PNG of at most [`MAX_TEXTURE_PIXELS`]; its size is read from the header and
    /// refused before anything is decoded.
    pub fn load(assets: &dyn AssetSource, name: &str) -> Result<Texture, String> {
        let bytes = assets.read(name, TEXTURE)?;
        let unreadable = |e: image::ImageError| format!("{name}: not a readable PNG: {e}");
        let reader = || {
            image::ImageReader::with_format(std::io::Cursor::new(&bytes), image::ImageFormat::Png)
        };
        let (width, height) = reader().into_dimensions().map_err(unreadable)?;
        if u64::from(width) * u64::from(height) > MAX_TEXTURE_PIXELS {
            return Err(format!(
                "{name}: the texture is {width}x{height} pixels, more than the {} million a \
                 texture may have (4096x4096)",
                MAX_TEXTURE_PIXELS >> 20
            ));
        }
        let mut reader = reader();
        let mut limits = image::Limits::default();
        limits.max_alloc = Some(MAX_DECODER_BYTES);
        reader.limits(limits);
        // An 8-bit RGB PNG decodes straight into these bytes; other kinds are converted once.
        let texels = reader.decode().map_err(unreadable)?.into_rgb8().into_raw();
        Ok(Texture {
            width: width as usize,
            height: height as usize,
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
        let at = (row * self.width + column) * 3;
        std::array::from_fn(|k| self.texels[at + k] as f32 / 255.0)
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
        assert_eq!(texture.texels.len(), texture.width * texture.height * 3);
    }

    #[test]
    fn a_missing_or_broken_file_says_what_is_wrong() {
        let missing = load_mesh(&Embedded, "meshes/none.obj").unwrap_err();
        assert!(missing.contains("meshes/none.obj"), "{missing}");
        struct Garbage;
        impl AssetSource for Garbage {
            fn read(&self, _: &str, _: FileKind) -> Result<Vec<u8>, String> {
                Ok(b"not a png".to_vec())
            }
        }
        let broken = Texture::load(&Garbage, "t.png").unwrap_err();
        assert!(broken.contains("t.png: not a readable PNG"), "{broken}");
    }
}
