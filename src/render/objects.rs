//! What a render scene holds (triangles, parallelograms, OBJ meshes, each with an optional transform and
//! texture) and its prepared form: object-space geometry, the world-to-object transform, the normal
//! matrix, a BVH for meshes, decoded textures.

use std::collections::HashMap;
use std::sync::Arc;

use glam::{DAffine3, DMat3};

use super::budget::{MemoryTally, OverMemory, mesh_bytes, texture_bytes};
use super::bvh::Bvh;
use super::kernels::parallelogram4::Parallelogram4Parts;
use super::loading::assets::{AssetError, AssetSource, Texture, load_mesh};
use crate::math::linalg::{V3, cross, sub};
use crate::scene::render::{Object, Shape};

/// A triangle ready to test: vertices in object space, its unit face normal, and its attributes.
#[derive(Clone, Debug, PartialEq)]
pub struct PreparedTriangle {
    /// A, B, C in object space.
    pub vertices: [V3<f64>; 3],
    /// The unit normal of (B − A) × (C − A), object space.
    pub face_normal: V3<f64>,
    /// Per-vertex colours.
    pub colors: Option<[V3<f64>; 3]>,
    /// Per-vertex normals, object space.
    pub normals: Option<[V3<f64>; 3]>,
    /// Per-vertex texture coordinates.
    pub uvs: Option<[[f64; 2]; 3]>,
}

impl PreparedTriangle {
    /// A triangle with its face normal and no attributes.
    pub fn new(vertices: [V3<f64>; 3]) -> PreparedTriangle {
        let [a, b, c] = &vertices;
        PreparedTriangle {
            vertices,
            face_normal: unit(cross(&sub(b, a), &sub(c, a))),
            colors: None,
            normals: None,
            uvs: None,
        }
    }
}

/// A prepared object's geometry.
#[derive(Clone, Debug)]
pub enum Geometry {
    /// Triangles (one, or a mesh) with a BVH when there are enough of them to need one.
    Triangles {
        /// The triangles (shared by every object that names the same mesh file).
        triangles: Arc<[PreparedTriangle]>,
        /// Present for meshes.
        bvh: Option<Arc<Bvh>>,
    },
    /// A parallelogram.
    Parallelogram {
        /// c.
        corner: V3<f64>,
        /// e1.
        e1: V3<f64>,
        /// e2.
        e2: V3<f64>,
        /// The unit normal of e1 × e2.
        face_normal: V3<f64>,
        /// What the four-lane solver derives from e1 × e2, found once
        /// ([`Parallelogram4Parts::of`]); `None` when it leaves every ray to the one-ray solver.
        lanes: Option<Parallelogram4Parts>,
    },
}

/// An object ready to render.
#[derive(Clone, Debug)]
pub struct PreparedObject {
    /// Its geometry in object space.
    pub geometry: Geometry,
    /// World to object (M⁻¹), when the object has a transform.
    pub object_from_world: Option<DAffine3>,
    /// Object to world (M).
    pub world_from_object: DAffine3,
    /// (M⁻¹)ᵀ, which takes normals from object space to world space.
    pub normal_to_world: DMat3,
    /// The flat colour.
    pub color: V3<f64>,
    /// The decoded texture (shared by every object that names the same file).
    pub texture: Option<Arc<Texture>>,
    /// True for an OBJ mesh (a closed surface deserves the watertight method).
    pub is_mesh: bool,
}

/// Meshes with at least this many triangles get a BVH.
const BVH_MIN_TRIANGLES: usize = 8;

/// Why a render scene cannot be prepared.
#[derive(Debug, thiserror::Error)]
pub enum PrepareError {
    /// The scene's numbers, size, camera or settings are refused.
    #[error(transparent)]
    Scene(#[from] crate::scene::check::CheckError),
    /// An object (counted from 1) is refused or its files unreadable.
    #[error("object {index}: {error}")]
    Object {
        /// From 1.
        index: usize,
        /// Why.
        error: ObjectError,
    },
    /// A mesh load was cancelled before the objects were prepared.
    #[error(transparent)]
    Cancelled(AssetError),
    /// The meshes and textures together would hold more memory than the budget.
    #[error(transparent)]
    Memory(#[from] OverMemory),
}

impl PrepareError {
    /// True when a load was cancelled rather than failed.
    pub fn is_cancelled(&self) -> bool {
        matches!(self, PrepareError::Cancelled(_))
    }
}

/// Why one object cannot be prepared.
#[derive(Debug, thiserror::Error)]
pub enum ObjectError {
    /// A scale with a zero (or too small) component.
    #[error(transparent)]
    Scale(#[from] crate::scene::check::CheckError),
    /// A transform whose inverse overflows or underflows.
    #[error("the transform's scale {0:?} is too large or too small to invert in floating point")]
    Uninvertible([f64; 3]),
    /// Its mesh or texture.
    #[error(transparent)]
    Asset(#[from] AssetError),
    /// Its mesh or texture would take the scene's files past the memory budget.
    #[error(transparent)]
    Memory(#[from] OverMemory),
}

/// A mesh's triangles and its BVH.
type SharedMesh = (Arc<[PreparedTriangle]>, Option<Arc<Bvh>>);

/// The meshes and textures prepared so far, by file name: a file that several objects of a scene
/// name is read, parsed (and its BVH built) once, and held once in memory, every object sharing it.
pub struct SharedFiles {
    meshes: HashMap<String, SharedMesh>,
    textures: HashMap<String, Arc<Texture>>,
    /// Their memory, against the scene's budget.
    memory: MemoryTally,
}

impl Default for SharedFiles {
    /// Nothing loaded yet, with the default budget.
    fn default() -> SharedFiles {
        SharedFiles::new(super::budget::MEMORY_BUDGET_BYTES)
    }
}

impl SharedFiles {
    /// Nothing loaded yet; the files may hold at most `budget` bytes together.
    pub fn new(budget: u64) -> SharedFiles {
        SharedFiles {
            meshes: HashMap::new(),
            textures: HashMap::new(),
            memory: MemoryTally::new(budget),
        }
    }

    /// Mesh `name` with its BVH (when it has enough triangles to need one), loaded at its first use.
    fn mesh(&mut self, assets: &dyn AssetSource, name: &str) -> Result<SharedMesh, ObjectError> {
        if let Some(mesh) = self.meshes.get(name) {
            return Ok(mesh.clone());
        }
        let triangles = load_mesh(assets, name)?;
        // Counted before the hierarchy is built, from the most it may take.
        self.memory.add(name, mesh_bytes(triangles.len()))?;
        let bvh = (triangles.len() >= BVH_MIN_TRIANGLES).then(|| Arc::new(Bvh::build(&triangles)));
        let mesh: SharedMesh = (triangles.into(), bvh);
        self.meshes.insert(name.to_string(), mesh.clone());
        Ok(mesh)
    }

    /// Texture `name`, decoded at its first use.
    fn texture(
        &mut self,
        assets: &dyn AssetSource,
        name: &str,
    ) -> Result<Arc<Texture>, ObjectError> {
        if let Some(texture) = self.textures.get(name) {
            return Ok(texture.clone());
        }
        let texture = Arc::new(Texture::load(assets, name)?);
        self.memory
            .add(name, texture_bytes(texture.width, texture.height))?;
        self.textures.insert(name.to_string(), texture.clone());
        Ok(texture)
    }
}

/// Prepares an object: reads its mesh and texture (or takes them from `shared`, when another
/// object read them), inverts its transform.
pub fn prepare(
    object: &Object,
    assets: &dyn AssetSource,
    shared: &mut SharedFiles,
) -> Result<PreparedObject, ObjectError> {
    let matrix = object.transform.matrix();
    crate::scene::check::check_scale(&object.transform.scale)?;
    let inverse = matrix.inverse();
    if !matrix.matrix3.determinant().is_normal() || !inverse.is_finite() {
        return Err(ObjectError::Uninvertible(object.transform.scale));
    }
    let object_from_world = (!object.transform.is_identity()).then_some(inverse);
    let (geometry, is_mesh) = match &object.shape {
        Shape::Triangle {
            vertices,
            colors,
            normals,
            uvs,
        } => {
            let mut triangle = PreparedTriangle::new(*vertices);
            triangle.colors = *colors;
            triangle.normals = normals.map(|n| n.map(unit));
            triangle.uvs = *uvs;
            let geometry = Geometry::Triangles {
                triangles: Arc::new([triangle]),
                bvh: None,
            };
            (geometry, false)
        }
        Shape::Parallelogram { corner, e1, e2 } => {
            let geometry = Geometry::Parallelogram {
                corner: *corner,
                e1: *e1,
                e2: *e2,
                face_normal: unit(cross(e1, e2)),
                lanes: Parallelogram4Parts::of([corner, e1, e2]),
            };
            (geometry, false)
        }
        Shape::Mesh { obj } => {
            let (triangles, bvh) = shared.mesh(assets, obj)?;
            (Geometry::Triangles { triangles, bvh }, true)
        }
    };
    let texture = match &object.texture {
        Some(name) => Some(shared.texture(assets, name)?),
        None => None,
    };
    Ok(PreparedObject {
        geometry,
        object_from_world,
        world_from_object: matrix,
        normal_to_world: matrix.matrix3.inverse().transpose(),
        color: object.color,
        texture,
        is_mesh,
    })
}

/// Builds a triangle from OBJ data.
pub(super) fn mesh_triangle(
    vertices: [V3<f64>; 3],
    normals: Option<[V3<f64>; 3]>,
    uvs: Option<[[f64; 2]; 3]>,
) -> PreparedTriangle {
    let mut triangle = PreparedTriangle::new(vertices);
    triangle.normals = normals.map(|n| n.map(unit));
    triangle.uvs = uvs;
    triangle
}

/// v / |v| (v itself when it is zero).
pub fn unit(v: V3<f64>) -> V3<f64> {
    let length = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    if length == 0.0 {
        v
    } else {
        v.map(|c| c / length)
    }
}
