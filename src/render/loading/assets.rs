//! Files a render scene names: OBJ meshes (read with tobj) and PNG textures (read with image).
//!
//! The shipped ones are embedded in the binary, so the preset scenes render anywhere (a web page
//! included); other names are looked up on disk beside the scene file.

use std::io::BufReader;
use std::path::PathBuf;

use crate::files::{FileKind, MESH, ReadError, TEXTURE, read_regular};
use crate::math::linalg::V3;
use crate::render::objects::{PreparedTriangle, mesh_triangle};

/// The meshes and textures under `assets/`, by their name relative to it.
const EMBEDDED: [(&str, &[u8]); 2] = [
    (
        "meshes/octasphere.obj",
        include_bytes!("../../../assets/meshes/octasphere.obj"),
    ),
    (
        "textures/checker.png",
        include_bytes!("../../../assets/textures/checker.png"),
    ),
];

/// Why a file a scene names could not be found or read.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum FetchError {
    /// Not among the embedded files (a source with no disk, as on the web).
    #[error("no file '{name}' among the shipped assets ({})", shipped_names().join(", "))]
    NotShipped {
        /// The name asked for.
        name: String,
    },
    /// Not shipped, and in none of the folders looked in.
    #[error(
        "cannot find '{name}' (not shipped, and not at {})",
        .tried.iter().map(|p| p.display().to_string()).collect::<Vec<_>>().join(" or ")
    )]
    NotFound {
        /// The name asked for.
        name: String,
        /// Every path tried.
        tried: Vec<PathBuf>,
    },
    /// Found but refused (a directory, too large, unreadable).
    #[error("{}: {error}", .path.display())]
    Refused {
        /// Where it was found.
        path: PathBuf,
        /// Why.
        error: ReadError,
    },
    /// Another reason, said by the source (a test's or a preview's).
    #[error("{0}")]
    Other(String),
}

/// Why a mesh or a texture gives nothing to render; each names the file.
#[derive(Debug, thiserror::Error)]
pub enum AssetError {
    /// The file was not found or not read.
    #[error(transparent)]
    Fetch(#[from] FetchError),
    /// The load was cancelled (by the user, or a newer load).
    #[error("{0}: {CANCELLED}")]
    Cancelled(String),
    /// The OBJ file is refused or unreadable.
    #[error("{name}: {error}")]
    Mesh {
        /// The file's name.
        name: String,
        /// Why.
        error: MeshError,
    },
    /// The PNG file is refused or unreadable.
    #[error("{name}: {error}")]
    Texture {
        /// The file's name.
        name: String,
        /// Why.
        error: TextureError,
    },
}

impl AssetError {
    /// True when the load was cancelled rather than failed.
    pub fn is_cancelled(&self) -> bool {
        matches!(self, AssetError::Cancelled(_))
    }
}

/// Why an OBJ file is refused or unreadable.
#[derive(Debug, thiserror::Error)]
pub enum MeshError {
    /// More than [`MAX_MESH_TRIANGLES`] triangles, counted up to `line`.
    #[error(
        "line {line}: the mesh has more than {} million triangles, the most a mesh may have",
        MAX_MESH_TRIANGLES / 1_000_000
    )]
    TooManyTriangles {
        /// The line where the count passed the limit.
        line: usize,
    },
    /// A face that uses a vertex not yet given.
    #[error(
        "line {line}: the face uses vertex {index}, but {} before it (an OBJ file's faces must \
         follow their vertices)",
        match .vertices { 0 => "no vertex comes".to_string(), 1 => "only 1 vertex comes".to_string(),
                          n => format!("only {n} vertices come") }
    )]
    FaceBeforeVertices {
        /// The line, from 1.
        line: usize,
        /// The index as written.
        index: i64,
        /// How many vertices came before.
        vertices: u64,
    },
    /// A face with fewer than three corners (`f 1 2`), which has no area to hit.
    #[error("line {line}: a face needs at least 3 corners, this one has {corners}")]
    TooFewCorners {
        /// The line, from 1.
        line: usize,
        /// How many corners it names.
        corners: u64,
    },
    /// An index tobj would wrap around.
    #[error(
        "not a readable OBJ mesh: line {line}: index {index} is out of range ({known} {} before it)",
        ["vertices", "texture coordinates", "normals"][*.slot]
    )]
    IndexOutOfRange {
        /// The line, from 1.
        line: usize,
        /// The index as written.
        index: i64,
        /// How many of its kind came before.
        known: i64,
        /// 0 vertex, 1 texture coordinate, 2 normal.
        slot: usize,
    },
    /// tobj cannot read it.
    #[error("not a readable OBJ mesh: {0}")]
    Unreadable(tobj::LoadError),
    /// A vertex coordinate that is not finite or too large.
    #[error(transparent)]
    Numbers(crate::scene::check::CheckError),
    /// No faces at all.
    #[error("the OBJ file has no faces")]
    NoFaces,
    /// [`MeshLoad::step`] called after it handed the mesh over.
    #[error("the mesh was handed over already")]
    HandedOver,
}

/// Why a PNG texture is refused or unreadable.
#[derive(Debug, thiserror::Error)]
pub enum TextureError {
    /// The image crate cannot read it.
    #[error("not a readable PNG: {0}")]
    Unreadable(#[from] image::ImageError),
    /// More than [`MAX_TEXTURE_PIXELS`].
    #[error(
        "the texture is {width}x{height} pixels, more than the {} million a texture may have \
         (4096x4096)",
        MAX_TEXTURE_PIXELS >> 20
    )]
    TooLarge {
        /// Its width.
        width: u32,
        /// Its height.
        height: u32,
    },
}

/// Where a scene's files come from.
pub trait AssetSource {
    /// The bytes of `name` (relative to `assets/`), a file of `kind` and at most its size, or why not.
    fn read(&self, name: &str, kind: FileKind) -> Result<Vec<u8>, FetchError>;

    /// The size in bytes of `name`, a file of `kind`, or why it cannot be read (as [`Self::read`]
    /// would say), without reading it where that can be avoided.
    fn size(&self, name: &str, kind: FileKind) -> Result<u64, FetchError> {
        self.read(name, kind).map(|bytes| bytes.len() as u64)
    }

    /// The mesh `name` when it was loaded ahead (with progress, see [`Preloaded`]): handed over once.
    fn loaded_mesh(&self, _name: &str) -> Option<Vec<PreparedTriangle>> {
        None
    }
}

/// Only the files embedded in the binary.
pub struct Embedded;

impl AssetSource for Embedded {
    fn read(&self, name: &str, _: FileKind) -> Result<Vec<u8>, FetchError> {
        embedded(name)
            .map(<[u8]>::to_vec)
            .ok_or_else(|| FetchError::NotShipped {
                name: name.to_string(),
            })
    }
}

fn shipped_names() -> Vec<&'static str> {
    EMBEDDED.iter().map(|(n, _)| *n).collect()
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
    fn read(&self, name: &str, kind: FileKind) -> Result<Vec<u8>, FetchError> {
        if let Some(bytes) = embedded(name) {
            return Ok(bytes.to_vec());
        }
        for folder in &self.0 {
            let path = folder.join(name);
            match read_regular(&path, kind) {
                Ok(bytes) => return Ok(bytes),
                Err(ReadError::NotFound) => continue,
                Err(error) => return Err(FetchError::Refused { path, error }),
            }
        }
        Err(self.not_found(name))
    }

    fn size(&self, name: &str, kind: FileKind) -> Result<u64, FetchError> {
        if let Some(bytes) = embedded(name) {
            return Ok(bytes.len() as u64);
        }
        for folder in &self.0 {
            let path = folder.join(name);
            match std::fs::metadata(&path) {
                Err(e) if e.kind() == std::io::ErrorKind::NotFound => continue,
                Ok(metadata) if metadata.is_file() && metadata.len() <= kind.max_bytes => {
                    return Ok(metadata.len());
                }
                // Refused: read_regular says why without reading a byte.
                _ => return self.read(name, kind).map(|bytes| bytes.len() as u64),
            }
        }
        Err(self.not_found(name))
    }
}

impl OnDisk {
    /// The refusal of a file found nowhere.
    fn not_found(&self, name: &str) -> FetchError {
        FetchError::NotFound {
            name: name.to_string(),
            tried: self.0.iter().map(|f| f.join(name)).collect(),
        }
    }
}

/// Reads an OBJ file's triangles (polygons are triangulated), with its normals and UVs when every
/// vertex has them.
pub fn load_mesh(
    assets: &dyn AssetSource,
    name: &str,
) -> Result<Vec<PreparedTriangle>, AssetError> {
    load_mesh_with_progress(assets, name, &mut |_| true)
}

/// [`load_mesh`], telling `progress` how far it has come after each slice of the work (a few
/// milliseconds, except the OBJ parse, which is one slice) and once more at 100%; `progress`
/// returning false cancels the load.
pub fn load_mesh_with_progress(
    assets: &dyn AssetSource,
    name: &str,
    progress: &mut dyn FnMut(MeshProgress) -> bool,
) -> Result<Vec<PreparedTriangle>, AssetError> {
    if let Some(mesh) = assets.loaded_mesh(name) {
        return Ok(mesh);
    }
    let mut load = MeshLoad::start(assets, name)?;
    loop {
        if let Some(triangles) = load.step_reporting(progress)? {
            progress(load.progress());
            return Ok(triangles);
        }
        if !progress(load.progress()) {
            return Err(AssetError::Cancelled(name.to_string()));
        }
    }
}

/// The end of the message of a cancelled load.
pub const CANCELLED: &str = "the load was cancelled";

/// How far a mesh load has come.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeshProgress {
    /// From 0 to 1.
    pub fraction: f64,
    /// The triangles counted so far (all of them once the first pass over the file is done).
    pub triangles: u64,
}

/// The stages of a mesh load, in order.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Stage {
    /// Counting the triangles and checking that faces follow their vertices.
    Faces,
    /// Checking every face index.
    Indices,
    /// tobj reads the file (one slice: it cannot be paused).
    Parse,
    /// Building the prepared triangles.
    Build,
    /// Handed over.
    Done,
}

impl Stage {
    /// The share of the whole load done before this stage, and this stage's share (the shares of
    /// the time each took for a 1 M-triangle OBJ in a release build).
    fn span(self) -> (f64, f64) {
        match self {
            Stage::Faces => (0.0, 0.15),
            Stage::Indices => (0.15, 0.15),
            Stage::Parse => (0.3, 0.6),
            Stage::Build => (0.9, 0.1),
            Stage::Done => (1.0, 0.0),
        }
    }
}

/// An OBJ mesh loaded a slice at a time ([`MeshLoad::step`]), so that a large one shows its
/// progress, can be cancelled, and on the web (no threads) shares the page's frames.
pub struct MeshLoad {
    name: String,
    bytes: Vec<u8>,
    stage: Stage,
    /// Where the next unchecked line starts, and its number (from 1), in the checking stages.
    at: usize,
    line: usize,
    faces: FaceCheck,
    indices: IndexCheck,
    models: Vec<tobj::Model>,
    /// The next model and face (its first index) to build.
    model: usize,
    face: usize,
    triangles: Vec<PreparedTriangle>,
}

/// Bytes checked in one slice.
const CHECK_SLICE_BYTES: usize = 1 << 20;

/// Triangles built in one slice.
const BUILD_SLICE_TRIANGLES: usize = 50_000;

impl MeshLoad {
    /// Reads the file; nothing is parsed yet.
    pub fn start(assets: &dyn AssetSource, name: &str) -> Result<MeshLoad, AssetError> {
        Ok(MeshLoad {
            name: name.to_string(),
            bytes: assets.read(name, MESH)?,
            stage: Stage::Faces,
            at: 0,
            line: 0,
            faces: FaceCheck::default(),
            indices: IndexCheck::default(),
            models: Vec::new(),
            model: 0,
            face: 0,
            triangles: Vec::new(),
        })
    }

    /// How far it has come.
    pub fn progress(&self) -> MeshProgress {
        let (before, share) = self.stage.span();
        let within = match self.stage {
            Stage::Faces | Stage::Indices => self.at as f64 / self.bytes.len().max(1) as f64,
            Stage::Parse | Stage::Done => 0.0,
            Stage::Build => self.triangles.len() as f64 / self.faces.triangles.max(1) as f64,
        };
        MeshProgress {
            fraction: (before + share * within.min(1.0)).min(1.0),
            triangles: self.faces.triangles,
        }
    }

    /// Does one slice of the work: the triangles once the load is finished, `None` before.
    pub fn step(&mut self) -> Result<Option<Vec<PreparedTriangle>>, AssetError> {
        self.step_reporting(&mut |_| true)
    }

    /// [`MeshLoad::step`], telling `report` the progress of the OBJ parse while it runs (the one
    /// slice that cannot be cut short); `report` returning false cancels the parse.
    pub fn step_reporting(
        &mut self,
        report: &mut dyn FnMut(MeshProgress) -> bool,
    ) -> Result<Option<Vec<PreparedTriangle>>, AssetError> {
        let name = &self.name;
        let refused = |error: MeshError| AssetError::Mesh {
            name: name.clone(),
            error,
        };
        match self.stage {
            Stage::Faces | Stage::Indices => {
                let mut end = (self.at + CHECK_SLICE_BYTES).min(self.bytes.len());
                end += self.bytes[end..]
                    .iter()
                    .position(|b| *b == b'\n')
                    .map_or(self.bytes.len() - end, |i| i + 1);
                let chunk = &self.bytes[self.at..end];
                let chunk = chunk.strip_suffix(b"\n").unwrap_or(chunk);
                for line in chunk.split(|b| *b == b'\n').filter(|_| !chunk.is_empty()) {
                    self.line += 1;
                    if self.stage == Stage::Faces {
                        self.faces.line(self.line, line).map_err(refused)?;
                    } else {
                        self.indices.line(self.line, line).map_err(refused)?;
                    }
                }
                self.at = end;
                if end == self.bytes.len() {
                    self.stage = if self.stage == Stage::Faces {
                        Stage::Indices
                    } else {
                        Stage::Parse
                    };
                    (self.at, self.line) = (0, 0);
                }
            }
            Stage::Parse => {
                // tobj reads the bytes in the first 40% of its time, then joins the indices.
                let (before, share) = Stage::Parse.span();
                let share = 0.4 * share;
                let (total, triangles) = (self.bytes.len().max(1) as f64, self.faces.triangles);
                let mut on_read = |read: usize| {
                    report(MeshProgress {
                        fraction: before + share * read as f64 / total,
                        triangles,
                    })
                };
                self.models = parse_obj(&self.bytes, &mut on_read).map_err(|e| match e {
                    ParseError::Cancelled => AssetError::Cancelled(name.clone()),
                    ParseError::Unreadable(e) => refused(MeshError::Unreadable(e)),
                })?;
                self.bytes = Vec::new();
                for model in &self.models {
                    crate::scene::check::check_numbers("vertex coordinates", &model.mesh.positions)
                        .map_err(|e| refused(MeshError::Numbers(e)))?;
                }
                self.triangles.reserve(self.faces.triangles as usize);
                self.stage = Stage::Build;
            }
            Stage::Build => {
                let mut budget = BUILD_SLICE_TRIANGLES;
                while let Some(model) = self.models.get(self.model) {
                    let mesh = &model.mesh;
                    let end = (self.face + 3 * budget).min(mesh.indices.len());
                    build_triangles(mesh, self.face..end, &mut self.triangles);
                    budget -= (end - self.face) / 3;
                    self.face = end;
                    if end == mesh.indices.len() {
                        (self.model, self.face) = (self.model + 1, 0);
                    }
                    if budget == 0 {
                        return Ok(None);
                    }
                }
                if self.triangles.is_empty() {
                    return Err(refused(MeshError::NoFaces));
                }
                self.faces.triangles = self.triangles.len() as u64;
                self.stage = Stage::Done;
                return Ok(Some(std::mem::take(&mut self.triangles)));
            }
            Stage::Done => return Err(refused(MeshError::HandedOver)),
        }
        Ok(None)
    }
}

/// The models of an OBJ file, polygons triangulated, one index per vertex.
/// `on_read` is told how many bytes tobj has read, every [`CHECK_SLICE_BYTES`]; false cancels.
fn parse_obj(
    bytes: &[u8],
    on_read: &mut dyn FnMut(usize) -> bool,
) -> Result<Vec<tobj::Model>, ParseError> {
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ..Default::default()
    };
    let mut reader = BufReader::new(Counted {
        bytes,
        read: 0,
        reported: 0,
        on_read,
        cancelled: false,
    });
    let parsed = tobj::load_obj_buf(&mut reader, &options, |_| {
        Err(tobj::LoadError::OpenFileFailed)
    });
    match parsed {
        Ok((models, _)) => Ok(models),
        Err(_) if reader.get_ref().cancelled => Err(ParseError::Cancelled),
        Err(e) => Err(ParseError::Unreadable(e)),
    }
}

/// Why an OBJ parse stopped.
enum ParseError {
    Cancelled,
    Unreadable(tobj::LoadError),
}

/// Bytes read through, counted for a progress report.
struct Counted<'a, 'b> {
    bytes: &'a [u8],
    read: usize,
    reported: usize,
    on_read: &'b mut dyn FnMut(usize) -> bool,
    cancelled: bool,
}

impl std::io::Read for Counted<'_, '_> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        if self.read - self.reported >= CHECK_SLICE_BYTES {
            self.reported = self.read;
            if !(self.on_read)(self.read) {
                self.cancelled = true;
                return Err(std::io::Error::other(CANCELLED));
            }
        }
        let n = (&self.bytes[self.read..]).read(buf)?;
        self.read += n;
        Ok(n)
    }
}

/// Appends the triangles of the faces whose indices are in `indices` (a range of whole faces).
fn build_triangles(
    mesh: &tobj::Mesh,
    indices: std::ops::Range<usize>,
    triangles: &mut Vec<PreparedTriangle>,
) {
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
    for face in mesh.indices[indices].chunks_exact(3) {
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

/// A source whose meshes were loaded ahead (with progress), handed over when the scene is prepared;
/// everything else comes from `source`.
pub struct Preloaded<S> {
    /// Where the files are.
    pub source: S,
    meshes: std::sync::Mutex<std::collections::HashMap<String, Vec<PreparedTriangle>>>,
}

impl<S: AssetSource> Preloaded<S> {
    /// Nothing loaded yet.
    pub fn new(source: S) -> Preloaded<S> {
        Preloaded {
            source,
            meshes: Default::default(),
        }
    }

    /// Keeps a loaded mesh until the scene asks for it.
    pub fn insert(&mut self, name: &str, mesh: Vec<PreparedTriangle>) {
        if let Ok(meshes) = self.meshes.get_mut() {
            meshes.insert(name.to_string(), mesh);
        }
    }
}

impl<S: AssetSource> AssetSource for Preloaded<S> {
    fn read(&self, name: &str, kind: FileKind) -> Result<Vec<u8>, FetchError> {
        self.source.read(name, kind)
    }

    fn size(&self, name: &str, kind: FileKind) -> Result<u64, FetchError> {
        self.source.size(name, kind)
    }

    fn loaded_mesh(&self, name: &str) -> Option<Vec<PreparedTriangle>> {
        self.meshes.lock().ok()?.remove(name)
    }
}

/// The most triangles a mesh may have (polygons count as the triangles they are cut into): a
/// prepared triangle with normals and texture coordinates takes about 300 bytes, so 2 million take
/// about 600 MB.
pub const MAX_MESH_TRIANGLES: u64 = 2_000_000;

/// Checks an OBJ file's lines before it is parsed: a face may only use the vertices above it (tobj
/// resolves the indices at the end of the file, so a face before its vertices would otherwise draw
/// whatever comes later), and the faces make at most [`MAX_MESH_TRIANGLES`] triangles.
#[derive(Default)]
struct FaceCheck {
    vertices: u64,
    triangles: u64,
}

impl FaceCheck {
    /// Checks line `number` (from 1).
    fn line(&mut self, number: usize, line: &[u8]) -> Result<(), MeshError> {
        let line = String::from_utf8_lossy(line);
        let mut tokens = line.split_whitespace();
        match tokens.next() {
            Some("v") => self.vertices += 1,
            Some("f") => {
                let corners = tokens.clone().count() as u64;
                if corners < 3 {
                    return Err(MeshError::TooFewCorners {
                        line: number,
                        corners,
                    });
                }
                self.triangles += corners.saturating_sub(2);
                if self.triangles > MAX_MESH_TRIANGLES {
                    return Err(MeshError::TooManyTriangles { line: number });
                }
                for token in tokens {
                    let index = token.split('/').next().unwrap_or("");
                    let Ok(index) = index.parse::<i64>() else {
                        continue; // tobj reports what it cannot read.
                    };
                    if index.unsigned_abs() > self.vertices {
                        return Err(MeshError::FaceBeforeVertices {
                            line: number,
                            index,
                            vertices: self.vertices,
                        });
                    }
                }
            }
            _ => {}
        }
        Ok(())
    }
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
    pub fn load(assets: &dyn AssetSource, name: &str) -> Result<Texture, AssetError> {
        let bytes = assets.read(name, TEXTURE)?;
        let refused = |error: TextureError| AssetError::Texture {
            name: name.to_string(),
            error,
        };
        let unreadable = |e: image::ImageError| refused(TextureError::Unreadable(e));
        let reader = || {
            image::ImageReader::with_format(std::io::Cursor::new(&bytes), image::ImageFormat::Png)
        };
        let (width, height) = reader().into_dimensions().map_err(unreadable)?;
        if u64::from(width) * u64::from(height) > MAX_TEXTURE_PIXELS {
            return Err(refused(TextureError::TooLarge { width, height }));
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
#[derive(Default)]
struct IndexCheck {
    /// Vertices, texture coordinates and normals so far.
    counts: [i64; 3],
}

impl IndexCheck {
    /// Checks line `number` (from 1).
    fn line(&mut self, number: usize, line: &[u8]) -> Result<(), MeshError> {
        const LARGEST_INDEX: i64 = 1 << 32;
        let line = String::from_utf8_lossy(line);
        let mut words = line.split_whitespace();
        match words.next() {
            Some("v") => self.counts[0] += 1,
            Some("vt") => self.counts[1] += 1,
            Some("vn") => self.counts[2] += 1,
            Some("f" | "l" | "p") => {
                for vertex in words {
                    for (slot, part) in vertex.split('/').enumerate().take(3) {
                        let Ok(index) = part.parse::<i64>() else {
                            continue; // empty (v//vn) or malformed: tobj reports those itself
                        };
                        let known = self.counts[slot];
                        // A texture coordinate or normal, like a vertex, must come before the face
                        // that uses it (a later one, or none, is read as nothing by tobj).
                        let past_known = slot > 0 && index > known;
                        if index == 0 || index < -known || index > LARGEST_INDEX || past_known {
                            return Err(MeshError::IndexOutOfRange {
                                line: number,
                                index,
                                known,
                                slot,
                            });
                        }
                    }
                }
            }
            _ => {}
        }
        Ok(())
    }
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
        let missing = load_mesh(&Embedded, "meshes/none.obj")
            .unwrap_err()
            .to_string();
        assert!(missing.contains("meshes/none.obj"), "{missing}");
        struct Garbage;
        impl AssetSource for Garbage {
            fn read(&self, _: &str, _: FileKind) -> Result<Vec<u8>, FetchError> {
                Ok(b"not a png".to_vec())
            }
        }
        let broken = Texture::load(&Garbage, "t.png").unwrap_err().to_string();
        assert!(broken.contains("t.png: not a readable PNG"), "{broken}");
    }

    #[test]
    fn faces_with_two_corners_or_indices_past_the_uvs_and_normals_are_refused() {
        struct Obj(&'static str);
        impl AssetSource for Obj {
            fn read(&self, _: &str, _: FileKind) -> Result<Vec<u8>, FetchError> {
                Ok(self.0.as_bytes().to_vec())
            }
        }
        let square = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvn 0 0 1\n";
        let refusal = |faces: &str| {
            let text: &'static str = Box::leak(format!("{square}{faces}").into_boxed_str());
            load_mesh(&Obj(text), "m.obj")
                .map(|t| t.len())
                .map_err(|e| e.to_string())
        };
        assert_eq!(refusal("f 1/1/1 2/2/1 3/3/1\n"), Ok(1));
        let two = refusal("f 1/1/1 2/2/1 3/3/1\nf 1 2\n").unwrap_err();
        assert!(
            two.contains("line 10: a face needs at least 3 corners, this one has 2"),
            "{two}"
        );
        let uv = refusal("f 1/1 2/2 3/9\n").unwrap_err();
        assert!(
            uv.contains("index 9 is out of range (3 texture coordinates"),
            "{uv}"
        );
        let normal = refusal("f 1//1 2//1 3//2\n").unwrap_err();
        assert!(
            normal.contains("index 2 is out of range (1 normals"),
            "{normal}"
        );
    }
}
