//! What a render scene holds (triangles, parallelograms, OBJ meshes, each with an optional transform and
//! texture) and its prepared form: object-space geometry, the world-to-object transform, the normal
//! matrix, a BVH for meshes, decoded textures.

use glam::{DAffine3, DMat3};

use super::bvh::Bvh;
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
        /// The triangles.
        triangles: Vec<PreparedTriangle>,
        /// Present for meshes.
        bvh: Option<Bvh>,
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
    /// The decoded texture.
    pub texture: Option<Texture>,
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
}

/// Prepares an object: reads its mesh and texture, inverts its transform.
pub fn prepare(object: &Object, assets: &dyn AssetSource) -> Result<PreparedObject, ObjectError> {
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
                triangles: vec![triangle],
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
            };
            (geometry, false)
        }
        Shape::Mesh { obj } => {
            let triangles = load_mesh(assets, obj)?;
            let bvh = (triangles.len() >= BVH_MIN_TRIANGLES).then(|| Bvh::build(&triangles));
            (Geometry::Triangles { triangles, bvh }, true)
        }
    };
    let texture = match &object.texture {
        Some(name) => Some(Texture::load(assets, name)?),
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
