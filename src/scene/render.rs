//! What a render scene file holds: the image size, the camera, the objects (triangles, parallelograms,
//! OBJ meshes, each with a transform, colour and texture), the intersection method and the effects, with
//! the checks a file format cannot express. [`crate::render`] prepares and renders it.

use glam::{DAffine3, DVec3, EulerRot};
use serde::{Deserialize, Serialize};

use super::check::{CheckError, check_numbers, check_scale};
use crate::intersect::Method;
use crate::math::linalg::{dot, sub};
pub use crate::scene::lighting::{EffectSettings, Light, MAX_LIGHTS, Material};

/// A camera: seed 003's image plane, or a pinhole looking at a target.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub enum Camera {
    /// Seed 003: pixel (row, column) is the point (x, y, z) of a plane, x from `x.0` (left) to `x.1`
    /// (right), y from `y.0` (top) to `y.1` (bottom), both ends included; the ray starts there and goes
    /// along that point's direction from the origin, normalised.
    ImagePlane {
        /// x at the left and right columns.
        x: (f64, f64),
        /// y at the top and bottom rows.
        y: (f64, f64),
        /// The plane's z.
        z: f64,
    },
    /// A pinhole at `position` looking at `target`, z up, with a vertical field of view in degrees.
    Pinhole {
        /// The eye.
        position: [f64; 3],
        /// The point at the image's centre.
        target: [f64; 3],
        /// Vertical field of view, degrees.
        fov_y: f64,
    },
}

/// The effects a scene can call for, in menu order; scene files name them as strings (`"facing-ratio"`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case", try_from = "String", into = "String")]
#[derive(strum::EnumIter, strum::IntoStaticStr)]
#[strum(serialize_all = "kebab-case")]
pub enum Effect {
    /// White where something is hit (a hit mask).
    Coverage,
    /// Darker with distance.
    Depth,
    /// The object's colour times the facing ratio n̂ · (−ê) (seed 003).
    FacingRatio,
    /// Per-vertex colours interpolated with the barycentrics (seed 003, seed 004).
    BarycentricColor,
    /// Facing ratio with the vertex normals interpolated (seed 004).
    SmoothNormals,
    /// A texture sampled at the interpolated texture coordinates (seed 004).
    Texture,
    /// One shadow ray per light per shaded hit: is the light visible?
    Shadows,
    /// Mirror rays from reflective materials, up to `settings.max_depth` bounces.
    Reflections,
    /// Rays through glass by Snell's law (total internal reflection, Schlick's Fresnel mix).
    Refraction,
    /// `settings.occlusion_rays` seeded rays over the hemisphere: how open is the point?
    AmbientOcclusion,
    /// k×k stratified samples per pixel, k = `settings.samples_per_side`.
    Antialiasing,
}

impl Effect {
    /// The effects past ray casting: each casts rays of its own kind.
    pub const PAST_CASTING: [Effect; 5] = [
        Effect::Shadows,
        Effect::Reflections,
        Effect::Refraction,
        Effect::AmbientOcclusion,
        Effect::Antialiasing,
    ];

    /// The name in scene files (`facing-ratio`).
    pub fn name(self) -> &'static str {
        self.into()
    }

    /// What it computes, for a tooltip.
    pub fn explanation(self) -> &'static str {
        match self {
            Effect::Coverage => "White where a ray hits: the hit mask, and nothing else computed.",
            Effect::Depth => "Darker with distance t·|D|: needs only t.",
            Effect::FacingRatio => {
                "Colour × n̂ · (−ê), seed 003's facing ratio: one dot product per hit."
            }
            Effect::BarycentricColor => {
                "(1 − β − γ)·C_A + β·C_B + γ·C_C: the vertex colours interpolated per hit."
            }
            Effect::SmoothNormals => {
                "The facing ratio with the vertex normals interpolated by β and γ, then taken to \
                 world space by the inverse transpose."
            }
            Effect::Texture => "The texture sampled at the interpolated (u, v).",
            Effect::Shadows => {
                "A shadow ray from each shaded hit to each light, stopping at the first thing in \
                 between (an any-hit query): the light counts only if none is."
            }
            Effect::Reflections => {
                "Mirrors reflect: a ray along r = d − 2(d·n)n from the hit, traced again, up to the \
                 depth limit."
            }
            Effect::Refraction => {
                "Glass bends rays by Snell's law, η₁ sin θ₁ = η₂ sin θ₂, reflects them wholly past \
                 the critical angle, and mixes in the reflection by Schlick's Fresnel term."
            }
            Effect::AmbientOcclusion => {
                "N seeded rays over the hemisphere above each hit: the share that escapes scales \
                 the ambient light (an open plane keeps all of it)."
            }
            Effect::Antialiasing => {
                "k×k rays a pixel, one jittered in each cell of a k×k grid, averaged: smooth edges \
                 for k² times the primary rays."
            }
        }
    }
}

impl TryFrom<String> for Effect {
    type Error = crate::names::UnknownName;
    fn try_from(name: String) -> Result<Effect, Self::Error> {
        crate::names::parse("effect", &name)
    }
}

impl From<Effect> for String {
    fn from(effect: Effect) -> String {
        effect.name().into()
    }
}

/// A method named in a scene file (`"watertight"`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(try_from = "String", into = "String")]
pub struct SceneMethod(pub Method);

impl TryFrom<String> for SceneMethod {
    type Error = crate::names::UnknownName;
    fn try_from(name: String) -> Result<SceneMethod, Self::Error> {
        name.parse().map(SceneMethod)
    }
}

impl From<SceneMethod> for String {
    fn from(method: SceneMethod) -> String {
        method.0.name().into()
    }
}

/// A scene to render (the `Render` problem of a scene file). In a file each object names its own
/// `material`; here they are gathered in `materials` (see [`SceneFile`]).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(from = "SceneFile", into = "SceneFile")]
pub struct RenderScene {
    /// Image width in pixels.
    pub width: usize,
    /// Image height in pixels.
    pub height: usize,
    /// The camera.
    pub camera: Camera,
    /// The intersection method; by default watertight for meshes and Möller–Trumbore otherwise.
    #[serde(default)]
    pub method: Option<SceneMethod>,
    /// The objects.
    pub objects: Vec<Object>,
    /// What to compute at a hit.
    pub effects: Vec<Effect>,
    /// The lights (none: the shading effects shade by the facing ratio, as seed 003).
    pub lights: Vec<Light>,
    /// Object i's material is `materials[i]`; missing ones are diffuse.
    pub materials: Vec<Material>,
    /// The effects' parameters.
    pub settings: EffectSettings,
}

impl RenderScene {
    /// Checks what the file format cannot: finite numbers within [`MAX_MAGNITUDE`], a usable size,
    /// camera and field of view, scales that can be inverted.
    pub fn check(&self) -> Result<(), CheckError> {
        if !(1..=MAX_SIDE).contains(&self.width) || !(1..=MAX_SIDE).contains(&self.height) {
            return Err(CheckError::ImageSize {
                width: self.width,
                height: self.height,
            });
        }
        check_numbers("the camera's numbers", &self.camera.numbers())?;
        self.check_camera()?;
        for (i, object) in self.objects.iter().enumerate() {
            let mut numbers = Vec::new();
            object.numbers(&mut numbers);
            check_numbers("coordinates", &numbers)
                .and_then(|()| check_scale(&object.transform.scale))
                .and_then(|()| self.material(i).check())
                .and_then(|()| object.check_colors())
                .map_err(|e| e.in_object(i))?;
        }
        self.check_lighting()
    }

    /// Object `index`'s material.
    pub fn material(&self, index: usize) -> Material {
        self.materials.get(index).copied().unwrap_or_default()
    }

    /// The lights and the effects' parameters.
    fn check_lighting(&self) -> Result<(), CheckError> {
        if self.lights.len() > MAX_LIGHTS {
            return Err(CheckError::TooManyLights(self.lights.len()));
        }
        for (i, light) in self.lights.iter().enumerate() {
            light.check().map_err(|e| e.in_light(i))?;
        }
        self.settings.check()
    }

    /// A camera whose every ray has a direction.
    fn check_camera(&self) -> Result<(), CheckError> {
        match &self.camera {
            Camera::ImagePlane { z, .. } if z.abs() < MIN_MAGNITUDE => {
                Err(CheckError::ImagePlaneAtOrigin(*z))
            }
            Camera::ImagePlane { .. } => Ok(()),
            Camera::Pinhole {
                position,
                target,
                fov_y,
            } => {
                if !(*fov_y > 0.0 && *fov_y < 180.0) {
                    return Err(CheckError::FieldOfView(*fov_y));
                }
                let apart = sub(target, position);
                if dot(&apart, &apart).sqrt() < MIN_MAGNITUDE {
                    return Err(CheckError::CameraHasNoDirection);
                }
                let across = apart[0].hypot(apart[1]);
                if across <= 1e-9 * apart[2].abs() {
                    return Err(CheckError::CameraVertical);
                }
                Ok(())
            }
        }
    }
}

/// The steepest a moved pinhole camera looks up or down, in degrees: straight down the z axis its
/// image would have no "up".
pub const MAX_PITCH_DEGREES: f64 = 89.0;

/// How near and how far a moved pinhole camera may come to its target, in scene units.
pub const DOLLY_RANGE: (f64, f64) = (1e-3, 1e6);

impl Camera {
    /// A pinhole camera's place around its target: (distance, yaw about z, pitch above the xy
    /// plane), angles in radians; `None` for the image plane.
    pub fn orbit_angles(&self) -> Option<(f64, f64, f64)> {
        let Camera::Pinhole {
            position, target, ..
        } = self
        else {
            return None;
        };
        let offset = sub(position, target);
        let distance = dot(&offset, &offset).sqrt();
        if !distance.is_finite() || distance == 0.0 {
            return None;
        }
        let yaw = offset[1].atan2(offset[0]);
        let pitch = (offset[2] / distance).clamp(-1.0, 1.0).asin();
        Some((distance, yaw, pitch))
    }

    /// The pinhole camera moved on the sphere about its target to `yaw` and `pitch` (radians; the
    /// pitch held within ±[`MAX_PITCH_DEGREES`]) at `distance` (held within [`DOLLY_RANGE`]). The
    /// image plane does not move.
    pub fn placed(&self, distance: f64, yaw: f64, pitch: f64) -> Camera {
        let Camera::Pinhole { target, fov_y, .. } = self else {
            return self.clone();
        };
        let limit = MAX_PITCH_DEGREES.to_radians();
        let pitch = pitch.clamp(-limit, limit);
        let distance = distance.clamp(DOLLY_RANGE.0, DOLLY_RANGE.1);
        let along = [
            pitch.cos() * yaw.cos(),
            pitch.cos() * yaw.sin(),
            pitch.sin(),
        ];
        Camera::Pinhole {
            position: std::array::from_fn(|k| target[k] + distance * along[k]),
            target: *target,
            fov_y: *fov_y,
        }
    }

    /// Orbited about its target by `yaw` and `pitch` radians (drag right: the scene turns left).
    pub fn orbited(&self, yaw: f64, pitch: f64) -> Camera {
        match self.orbit_angles() {
            Some((distance, yaw0, pitch0)) => self.placed(distance, yaw0 + yaw, pitch0 + pitch),
            None => self.clone(),
        }
    }

    /// Moved towards its target (`factor` < 1) or away from it (> 1).
    pub fn dollied(&self, factor: f64) -> Camera {
        match self.orbit_angles() {
            Some((distance, yaw, pitch)) if factor.is_finite() && factor > 0.0 => {
                self.placed(distance * factor, yaw, pitch)
            }
            _ => self.clone(),
        }
    }

    /// Moved with its target across the image: `right` and `up` in image heights (a drag of the
    /// whole image's height moves the scene by its height at the target's distance).
    pub fn panned(&self, right: f64, up: f64) -> Camera {
        let (
            Camera::Pinhole {
                position,
                target,
                fov_y,
            },
            Some((distance, yaw, pitch)),
        ) = (self, self.orbit_angles())
        else {
            return self.clone();
        };
        // The image's right and up for a camera at (yaw, pitch), z up.
        let right_axis = [-yaw.sin(), yaw.cos(), 0.0];
        let up_axis = [
            -pitch.sin() * yaw.cos(),
            -pitch.sin() * yaw.sin(),
            pitch.cos(),
        ];
        let height = 2.0 * distance * (fov_y.to_radians() / 2.0).tan();
        let shift: [f64; 3] =
            std::array::from_fn(|k| height * (right * right_axis[k] + up * up_axis[k]));
        let moved = |p: &[f64; 3]| std::array::from_fn(|k| p[k] + shift[k]);
        let camera = Camera::Pinhole {
            position: moved(position),
            target: moved(target),
            fov_y: *fov_y,
        };
        // A pan past the numbers a scene may hold keeps the camera where it was.
        if camera.numbers().iter().all(|c| c.abs() <= MAX_MAGNITUDE) {
            camera
        } else {
            self.clone()
        }
    }

    /// Every number the camera holds.
    pub fn numbers(&self) -> Vec<f64> {
        match self {
            Camera::ImagePlane { x, y, z } => vec![x.0, x.1, y.0, y.1, *z],
            Camera::Pinhole {
                position,
                target,
                fov_y,
            } => [&position[..], &target[..], &[*fov_y]].concat(),
        }
    }
}

/// The largest magnitude of any number in a render scene (and of a mesh's vertices): products of
/// three coordinates, as the intersection tests form them, then stay far inside f64's range, even
/// after a transform's inverse (at most 1 / [`MIN_MAGNITUDE`]) has been applied.
pub const MAX_MAGNITUDE: f64 = 1e30;

/// The smallest magnitude of a transform's scale and of an image plane's z.
pub const MIN_MAGNITUDE: f64 = 1e-30;

/// The largest image side a scene may ask for.
pub const MAX_SIDE: usize = 4096;

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
    /// Its colour and any vertex colours have no negative part, as a light's colour.
    pub fn check_colors(&self) -> Result<(), CheckError> {
        let vertex_colors = match &self.shape {
            Shape::Triangle {
                colors: Some(colors),
                ..
            } => &colors[..],
            _ => &[],
        };
        let mut all = std::iter::once(&self.color).chain(vertex_colors);
        match all.find(|c| c.iter().any(|part| *part < 0.0)) {
            Some(color) => Err(CheckError::NegativeColor(*color)),
            None => Ok(()),
        }
    }

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

/// A render scene as its file holds it: each object with its material.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename = "RenderScene", deny_unknown_fields)]
pub struct SceneFile {
    width: usize,
    height: usize,
    camera: Camera,
    #[serde(default)]
    method: Option<SceneMethod>,
    objects: Vec<ObjectFile>,
    effects: Vec<Effect>,
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    lights: Vec<Light>,
    #[serde(default, skip_serializing_if = "is_default")]
    settings: EffectSettings,
}

/// An object as a file holds it: [`Object`] and its material.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(rename = "Object", deny_unknown_fields)]
struct ObjectFile {
    shape: Shape,
    #[serde(default = "default_color")]
    color: [f64; 3],
    #[serde(default)]
    texture: Option<String>,
    #[serde(default)]
    transform: Transform,
    #[serde(default, skip_serializing_if = "Material::is_diffuse")]
    material: Material,
}

fn is_default(settings: &EffectSettings) -> bool {
    *settings == EffectSettings::default()
}

impl From<SceneFile> for RenderScene {
    fn from(file: SceneFile) -> RenderScene {
        let (objects, materials) = file
            .objects
            .into_iter()
            .map(|o| {
                let object = Object {
                    shape: o.shape,
                    color: o.color,
                    texture: o.texture,
                    transform: o.transform,
                };
                (object, o.material)
            })
            .unzip();
        RenderScene {
            width: file.width,
            height: file.height,
            camera: file.camera,
            method: file.method,
            objects,
            effects: file.effects,
            lights: file.lights,
            materials,
            settings: file.settings,
        }
    }
}

impl From<RenderScene> for SceneFile {
    fn from(scene: RenderScene) -> SceneFile {
        let materials: Vec<Material> = (0..scene.objects.len())
            .map(|i| scene.material(i))
            .collect();
        let objects = scene
            .objects
            .into_iter()
            .zip(materials)
            .map(|(o, material)| ObjectFile {
                shape: o.shape,
                color: o.color,
                texture: o.texture,
                transform: o.transform,
                material,
            })
            .collect();
        SceneFile {
            width: scene.width,
            height: scene.height,
            camera: scene.camera,
            method: scene.method,
            objects,
            effects: scene.effects,
            lights: scene.lights,
            settings: scene.settings,
        }
    }
}

fn default_color() -> [f64; 3] {
    [0.8, 0.8, 0.8]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pinhole() -> Camera {
        Camera::Pinhole {
            position: [0.0, -4.0, 1.0],
            target: [0.0, 0.0, 1.0],
            fov_y: 40.0,
        }
    }

    fn parts(camera: &Camera) -> ([f64; 3], [f64; 3]) {
        match camera {
            Camera::Pinhole {
                position, target, ..
            } => (*position, *target),
            Camera::ImagePlane { .. } => panic!("a pinhole"),
        }
    }

    fn close(a: [f64; 3], b: [f64; 3]) -> bool {
        (0..3).all(|k| (a[k] - b[k]).abs() < 1e-12)
    }

    /// Orbiting keeps the target and the distance; a quarter turn of yaw takes the eye from −y to
    /// +x; the pitch stops short of the pole; the image plane does not move.
    #[test]
    fn a_pinhole_orbits_about_its_target() {
        let camera = pinhole();
        let (distance, yaw, pitch) = camera.orbit_angles().unwrap();
        assert!(
            (distance - 4.0).abs() < 1e-12 && pitch.abs() < 1e-12,
            "{yaw}"
        );
        let turned = camera.orbited(std::f64::consts::FRAC_PI_2, 0.0);
        let (position, target) = parts(&turned);
        assert!(close(position, [4.0, 0.0, 1.0]), "{position:?}");
        assert_eq!(target, [0.0, 0.0, 1.0]);
        let over = camera.orbited(0.0, 10.0);
        let (_, _, pitch) = over.orbit_angles().unwrap();
        assert!(
            (pitch.to_degrees() - MAX_PITCH_DEGREES).abs() < 1e-9,
            "{pitch}"
        );
        let plane = Camera::ImagePlane {
            x: (-1.0, 1.0),
            y: (1.0, -1.0),
            z: 1.0,
        };
        assert_eq!(plane.orbited(1.0, 1.0), plane);
        assert_eq!(plane.dollied(0.5), plane);
        assert_eq!(plane.panned(0.5, 0.5), plane);
    }

    /// A dolly moves the eye along its line to the target, within the allowed range; a pan moves
    /// eye and target together across the image (so the view's direction stays), and refuses to
    /// leave the numbers a scene may hold.
    #[test]
    fn a_pinhole_dollies_and_pans() {
        let camera = pinhole();
        let (position, _) = parts(&camera.dollied(0.5));
        assert!(close(position, [0.0, -2.0, 1.0]), "{position:?}");
        let (near, _, _) = camera.dollied(1e-9).orbit_angles().unwrap();
        assert!((near - DOLLY_RANGE.0).abs() < 1e-15, "{near}");
        assert_eq!(camera.dollied(f64::NAN), camera);
        // Looking along +y, the image's right is +x and its up +z.
        let height = 2.0 * 4.0 * 20f64.to_radians().tan();
        let (position, target) = parts(&camera.panned(0.5, 0.25));
        assert!(
            close(target, [0.5 * height, 0.0, 1.0 + 0.25 * height]),
            "{target:?}"
        );
        assert!(
            close(position, [0.5 * height, -4.0, 1.0 + 0.25 * height]),
            "{position:?}"
        );
        assert_eq!(camera.panned(1e40, 0.0), camera);
    }

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

    #[test]
    fn object_colours_are_checked_as_light_colours_are() {
        let mut scene = crate::scene::first_built_in(|s| match s {
            crate::scene::Problem::Render(r) => Some(r),
            _ => None,
        });
        assert_eq!(scene.check(), Ok(()));
        let last = scene.objects.len();
        scene.objects[last - 1].color = [0.5, -1.0, 0.0];
        let message = scene.check().unwrap_err().to_string();
        assert!(message.contains("negative part"), "{message}");
        assert!(message.contains(&format!("object {last}")), "{message}");
    }
}
