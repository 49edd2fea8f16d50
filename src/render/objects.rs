//! What a render scene holds (triangles, parallelograms, OBJ meshes, each with an optional transform and
//! texture) and its prepared form: object-space geometry, the world-to-object transform, the normal
//! matrix, a BVH for meshes, decoded textures.

use glam::{DAffine3, DMat3, DVec3, EulerRot};
use serde::{Deserialize, Serialize};

use super::assets::{AssetSource, Texture, load_mesh};
use super::bvh::Bvh;
use crate::math::linalg::{V3, cross, sub};

/// An object's shape, in object space.
// A scene holds a handful of objects: a large triangle variant costs nothing, boxing it would clutter
// the scene files' Rust side.
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Shape {
    /// One triangle with optional per-vertex attributes.
    Triangle {
        /// A, B, C.
        vertices: [[f64; 3]; 3],
        /// Colours of A, B, C (`barycentric-color`).
        #[serde(default)]
        colors: Option<[[f64; 3]; 3]>,
        /// Normals of A, B, C (`smooth-normals`).
        #[serde(default)]
        normals: Option<[[f64; 3]; 3]>,
        /// Texture coordinates of A, B, C (`texture`).
        #[serde(default)]
        uvs: Option<[[f64; 2]; 3]>,
    },
    /// c + α e1 + β e2 with α, β in [0, 1] (seed 001); its texture coordinates are (α, β).
    Parallelogram {
        /// The corner c.
        corner: [f64; 3],
        /// Edge e1.
        e1: [f64; 3],
        /// Edge e2.
        e2: [f64; 3],
    },
    /// Triangles read from an OBJ file (with its normals and UVs when it has them).
    Mesh {
        /// The file, relative to `assets/` (for example `meshes/octasphere.obj`).
        obj: String,
    },
}

/// Object to world: scale, then rotate (degrees about x, then y, then z), then translate.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct Transform {
    /// Translation.
    pub translate: [f64; 3],
    /// Rotation about x, y, z in degrees, applied in that order.
    pub rotate: [f64; 3],
    /// Scale along x, y, z.
    pub scale: [f64; 3],
}

impl Default for Transform {
    fn default() -> Transform {
        Transform {
            translate: [0.0; 3],
            rotate: [0.0; 3],
            scale: [1.0; 3],
        }
    }
}

impl Transform {
    /// The object-to-world matrix M.
    pub fn matrix(&self) -> DAffine3 {
        let [rx, ry, rz] = self.rotate.map(f64::to_radians);
        DAffine3::from_scale_rotation_translation(
            DVec3::from(self.scale),
            glam::DQuat::from_euler(EulerRot::ZYX, rz, ry, rx),
            DVec3::from(self.translate),
        )
    }

    /// True for the identity (no transform to apply).
    pub fn is_identity(&self) -> bool {
        *self == Transform::default()
    }
}

/// One object of a scene.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Object {
    /// Its geometry in object space.
    pub shape: Shape,
    /// Its flat colour (shading effects).
    #[serde(default = "default_color")]
    pub color: [f64; 3],
    /// A PNG relative to `assets/` (for example `textures/checker.png`), sampled by `texture`.
    #[serde(default)]
    pub texture: Option<String>,
    /// Object to world.
    #[serde(default)]
    pub transform: Transform,
}

impl Object {
    /// Every number in the object, appended to `out` (for the finiteness check).
    pub fn numbers(&self, out: &mut Vec<f64>) {
        match &self.shape {
            Shape::Triangle {
                vertices,
                colors,
                normals,
                uvs,
            } => {
                out.extend(vertices.iter().flatten());
                out.extend(colors.iter().flatten().flatten());
                out.extend(normals.iter().flatten().flatten());
                out.extend(uvs.iter().flatten().flatten());
            }
            Shape::Parallelogram { corner, e1, e2 } => {
                out.extend([corner, e1, e2].into_iter().flatten())
            }
            Shape::Mesh { .. } => {}
        }
        out.extend(self.color);
        let t = &self.transform;
        out.extend(t.translate.iter().chain(&t.rotate).chain(&t.scale));
    }
}

fn default_color() -> [f64; 3] {
    [0.8, 0.8, 0.8]
}

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
    pub world_to_object: Option<DAffine3>,
    /// Object to world (M).
    pub object_to_world: DAffine3,
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

/// Prepares an object: reads its mesh and texture, inverts its transform.
pub fn prepare(object: &Object, assets: &dyn AssetSource) -> Result<PreparedObject, String> {
    let matrix = object.transform.matrix();
    if object.transform.scale.contains(&0.0) {
        return Err(format!(
            "the transform's scale {:?} has a zero component: the object would be flat and its \
             transform has no inverse",
            object.transform.scale
        ));
    }
    let inverse = matrix.inverse();
    if !matrix.matrix3.determinant().is_normal() || !inverse.is_finite() {
        return Err(format!(
            "the transform's scale {:?} is too large or too small to invert in floating point",
            object.transform.scale
        ));
    }
    let world_to_object = (!object.transform.is_identity()).then_some(inverse);
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
        world_to_object,
        object_to_world: matrix,
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_transform_scales_then_rotates_then_translates() {
        let transform = Transform {
            translate: [1.0, 2.0, 3.0],
            rotate: [0.0, 0.0, 90.0],
            scale: [2.0, 1.0, 1.0],
        };
        // (1, 0, 0) → scale (2, 0, 0) → rotate 90° about z (0, 2, 0) → translate (1, 4, 3).
        let p = transform.matrix().transform_point3(DVec3::X);
        assert!((p - DVec3::new(1.0, 4.0, 3.0)).length() < 1e-12, "{p}");
    }
}
