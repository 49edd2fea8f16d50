//! A small 3D canvas on egui's painter: an orbit camera (drag to orbit, scroll to zoom), a projection
//! from world to screen, and drawing helpers that clip at the near plane and skip non-finite points.

use egui::{Color32, Pos2, Rect, Shape, Stroke, Vec2};
use glam::{DMat4, DVec3, DVec4};
use serde::{Deserialize, Serialize};

/// An orbit camera around a target point, z up.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct OrbitCamera {
    /// Angle around the z axis, radians.
    pub yaw: f64,
    /// Angle above the xy plane, radians.
    pub pitch: f64,
    /// Distance from the target.
    pub distance: f64,
    /// The point looked at.
    pub target: [f64; 3],
}

impl Default for OrbitCamera {
    fn default() -> OrbitCamera {
        OrbitCamera {
            yaw: 0.7,
            pitch: 0.45,
            distance: 12.0,
            target: [1.0, 1.0, 1.0],
        }
    }
}

/// The unit direction from the target to the eye of a camera at `yaw` and `pitch`.
fn eye_direction(yaw: f64, pitch: f64) -> DVec3 {
    let (sy, cy) = yaw.sin_cos();
    let (sp, cp) = pitch.sin_cos();
    DVec3::new(cp * cy, cp * sy, sp)
}

/// How well looking from direction `eye` (unit, towards the eye) shows a ray along `dir` and a
/// shape with normal `face`: the smaller of |d̂ × ê| (the ray: 1 side-on, 0 end-on) and |n̂ · ê| (the
/// face: 1 face-on, 0 edge-on); the ray's alone without a face (or with a degenerate one).
fn showing(eye: DVec3, dir: DVec3, face: Option<DVec3>) -> f64 {
    let ray = dir.normalize().cross(eye).length();
    face.filter(|n| n.is_finite() && n.length() > 0.0)
        .map_or(ray, |n| ray.min(n.normalize().dot(eye).abs()))
}

/// Vertical field of view.
const FOV_Y: f64 = 0.8;

impl OrbitCamera {
    /// A camera framing a set of points.
    pub fn framing(points: &[DVec3]) -> OrbitCamera {
        let finite: Vec<DVec3> = points.iter().copied().filter(|p| p.is_finite()).collect();
        if finite.is_empty() {
            return OrbitCamera::default();
        }
        let center = finite.iter().copied().sum::<DVec3>() / finite.len() as f64;
        let radius = finite
            .iter()
            .map(|p| p.distance(center))
            .fold(1.0f64, f64::max);
        OrbitCamera {
            target: center.to_array(),
            distance: (radius * 2.8).clamp(0.5, 1e6),
            ..OrbitCamera::default()
        }
    }

    /// Turns the camera to look at the scene side-on to a ray with direction `dir`, so the ray is
    /// drawn along its length instead of end-on, and, given the `face` (normal) of the shape the ray
    /// is aimed at, so that shape is seen from the front rather than edge-on.
    pub fn across(mut self, dir: DVec3, face: Option<DVec3>) -> OrbitCamera {
        if !(dir.is_finite() && dir.length() > 0.0) {
            return self;
        }
        // How well a direction to the eye shows both (see `showing`).
        let score = |yaw: f64, pitch: f64| showing(eye_direction(yaw, pitch), dir, face);
        if dir.x.hypot(dir.y) > 1e-9 * dir.length() {
            // 55° around from the ray's heading, a little above: the ray is seen along its length
            // and a triangle facing it (as in the lecture) is still seen at an angle, not edge-on.
            self.yaw = dir.y.atan2(dir.x) + 55f64.to_radians();
            self.pitch = 0.35;
        }
        // Good enough (the lecture's scenes): keep the usual view. Else the best of a coarse sweep.
        if score(self.yaw, self.pitch) < 0.35 {
            let sweep = (0..72).flat_map(|y| {
                [0.15, 0.35, 0.55, 0.75, 0.95, 1.15]
                    .map(|pitch| (f64::from(y) * 5f64.to_radians(), pitch))
            });
            let (yaw, pitch) = sweep.fold((self.yaw, self.pitch), |best, candidate| {
                if score(candidate.0, candidate.1) > score(best.0, best.1) + 1e-9 {
                    candidate
                } else {
                    best
                }
            });
            (self.yaw, self.pitch) = (yaw, pitch);
        }
        self
    }

    /// The same view direction, moved and zoomed so the points fill the viewport `rect`: their
    /// projection spans about 80% of its width or height, centred, and stays below the top
    /// `top_reserved` points (where the verdict box sits). Used on load, on resize and on zoom, so the
    /// scene grows with the screen.
    pub fn fitted_to(mut self, points: &[DVec3], rect: Rect, top_reserved: f32) -> OrbitCamera {
        let finite: Vec<DVec3> = points.iter().copied().filter(|p| p.is_finite()).collect();
        if finite.is_empty() || rect.width() < 1.0 || rect.height() < 1.0 {
            return self;
        }
        // The region to fill, in normalised device coordinates (y up).
        let reserved = (2.0 * top_reserved / rect.height()).clamp(0.0, 1.0) as f64;
        let (x_min, x_max, y_min, y_max) = (-0.8, 0.8, -0.82, 0.82 - reserved);
        // Centre and zoom, four times; then centre once more, as the last zoom scaled the points
        // about the screen's centre, not the region's (which the verdict pushes down).
        for pass in 0..5 {
            let projector = self.projector(rect);
            let ndc: Vec<DVec3> = finite
                .iter()
                .map(|p| projector.clip(*p))
                .filter(|c| c.w > NEAR_W)
                .map(|c| c.truncate() / c.w)
                .collect();
            if ndc.len() < finite.len() {
                // Something is behind the camera: back off and try again.
                self.distance = (self.distance * 2.0).min(1e6);
                continue;
            }
            let lo = ndc.iter().fold(DVec3::INFINITY, |m, p| m.min(*p));
            let hi = ndc.iter().fold(DVec3::NEG_INFINITY, |m, p| m.max(*p));
            // Move the target so the points' box centres on the region's centre.
            let half_height = self.distance * (FOV_Y / 2.0).tan();
            let half_width = half_height * (rect.width() / rect.height()) as f64;
            let shift_x = (lo.x + hi.x) / 2.0 - (x_min + x_max) / 2.0;
            let shift_y = (lo.y + hi.y) / 2.0 - (y_min + y_max) / 2.0;
            let moved = DVec3::from(self.target)
                + projector.right * shift_x * half_width
                + projector.up * shift_y * half_height;
            self.target = moved.to_array();
            if pass == 4 {
                break;
            }
            // Then zoom so the larger of the two spans fills its side of the region.
            let scale = ((hi.x - lo.x) / (x_max - x_min)).max((hi.y - lo.y) / (y_max - y_min));
            if scale.is_finite() && scale > 1e-9 {
                self.distance = (self.distance * scale.clamp(0.25, 4.0)).clamp(0.2, 1e6);
            }
        }
        self
    }

    /// How well this camera shows a ray along `dir` and a shape with normal `face` (see
    /// [`showing`]).
    pub fn shows(&self, dir: DVec3, face: Option<DVec3>) -> f64 {
        showing(eye_direction(self.yaw, self.pitch), dir, face)
    }

    /// The eye position.
    pub fn eye(&self) -> DVec3 {
        DVec3::from(self.target) + self.distance * eye_direction(self.yaw, self.pitch)
    }

    /// Orbits by a screen drag.
    pub fn orbit(&mut self, drag: Vec2) {
        self.yaw -= drag.x as f64 * 0.008;
        self.pitch = (self.pitch + drag.y as f64 * 0.008).clamp(-1.5, 1.5);
    }

    /// Zooms by a scroll amount (positive scrolls in).
    pub fn zoom(&mut self, scroll: f32) {
        self.distance = (self.distance * (-scroll as f64 * 0.002).exp()).clamp(0.2, 1e6);
    }

    /// The projection for a viewport.
    pub fn projector(&self, rect: Rect) -> Projector {
        let aspect = (rect.width() / rect.height().max(1.0)) as f64;
        let eye = self.eye();
        let view = glam::dcamera::rh::view::look_at_mat4(eye, DVec3::from(self.target), DVec3::Z);
        let near = (self.distance * 0.01).max(1e-6);
        let projection = glam::dcamera::rh::proj::opengl::perspective(
            FOV_Y,
            aspect.max(0.01),
            near,
            self.distance * 100.0,
        );
        Projector {
            rect,
            clip_from_world: projection * view,
            eye,
            right: view.row(0).truncate(),
            up: view.row(1).truncate(),
        }
    }
}

/// World to screen for one frame.
#[derive(Clone, Debug)]
pub struct Projector {
    /// The viewport.
    pub rect: Rect,
    /// Projection times view.
    pub clip_from_world: DMat4,
    /// The camera position.
    pub eye: DVec3,
    /// The camera's right vector in world space.
    pub right: DVec3,
    /// The camera's up vector in world space.
    pub up: DVec3,
}

/// Points closer than this (in clip w) are behind the camera.
const NEAR_W: f64 = 1e-6;

impl Projector {
    fn clip(&self, p: DVec3) -> DVec4 {
        self.clip_from_world * p.extend(1.0)
    }

    fn screen_from_clip(&self, c: DVec4) -> Pos2 {
        let ndc = c.truncate() / c.w;
        Pos2::new(
            self.rect.center().x + (ndc.x as f32) * self.rect.width() / 2.0,
            self.rect.center().y - (ndc.y as f32) * self.rect.height() / 2.0,
        )
    }

    /// The screen position of a world point, `None` behind the camera or for non-finite input.
    pub fn screen_from_world(&self, p: DVec3) -> Option<Pos2> {
        let c = self.clip(p);
        (p.is_finite() && c.w > NEAR_W).then(|| self.screen_from_clip(c))
    }

    /// The segment clipped to the front of the camera, on screen.
    pub fn segment(&self, a: DVec3, b: DVec3) -> Option<[Pos2; 2]> {
        if !a.is_finite() || !b.is_finite() {
            return None;
        }
        let (mut ca, mut cb) = (self.clip(a), self.clip(b));
        if ca.w <= NEAR_W && cb.w <= NEAR_W {
            return None;
        }
        // Cut the part behind the camera at w = NEAR_W.
        let cut =
            |from: DVec4, to: DVec4| from + (to - from) * ((NEAR_W - from.w) / (to.w - from.w));
        if ca.w <= NEAR_W {
            ca = cut(ca, cb);
        } else if cb.w <= NEAR_W {
            cb = cut(cb, ca);
        }
        let (pa, pb) = (self.screen_from_clip(ca), self.screen_from_clip(cb));
        // Far off-screen coordinates confuse the tessellator: clip to a generous frame.
        let bound = self.rect.expand(self.rect.width().max(self.rect.height()));
        clip_to_rect(pa, pb, bound)
    }

    /// World units per screen point at the depth of `p` (for dragging in the camera's plane).
    pub fn world_per_point(&self, p: DVec3) -> f64 {
        let depth = (p - self.eye).length().max(1e-9);
        2.0 * depth * (FOV_Y / 2.0).tan() / self.rect.height().max(1.0) as f64
    }

    /// The world displacement of a screen drag, in the plane facing the camera at `p`.
    pub fn drag_in_view_plane(&self, p: DVec3, drag: Vec2) -> DVec3 {
        let k = self.world_per_point(p);
        (self.right * drag.x as f64 - self.up * drag.y as f64) * k
    }
}

/// Liang–Barsky: the part of segment a–b inside the rectangle (`None` for non-finite ends).
pub fn clip_to_rect(a: Pos2, b: Pos2, rect: Rect) -> Option<[Pos2; 2]> {
    if !(a.x.is_finite() && a.y.is_finite() && b.x.is_finite() && b.y.is_finite()) {
        return None;
    }
    let d = b - a;
    let (mut enter, mut leave) = (0.0f32, 1.0f32);
    for (p, q) in [
        (-d.x, a.x - rect.min.x),
        (d.x, rect.max.x - a.x),
        (-d.y, a.y - rect.min.y),
        (d.y, rect.max.y - a.y),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                enter = enter.max(r);
            } else {
                leave = leave.min(r);
            }
        }
    }
    (enter <= leave).then(|| [a + d * enter, a + d * leave])
}

/// Draws in world coordinates through a projector.
pub struct Canvas<'a> {
    /// The painter, clipped to the viewport.
    pub painter: &'a egui::Painter,
    /// The projection.
    pub projector: &'a Projector,
}

impl Canvas<'_> {
    /// Where a world point is drawn, `None` behind the camera.
    pub fn screen(&self, p: DVec3) -> Option<Pos2> {
        self.projector.screen_from_world(p)
    }

    /// A label for a world point, placed by the label pass (see [`super::labels`]).
    pub fn place_label(
        &self,
        labels: &mut super::labels::LabelLayer,
        p: DVec3,
        text: impl Into<String>,
        color: Color32,
        priority: super::labels::Priority,
    ) {
        if let Some(at) = self.screen(p) {
            let size = if priority == super::labels::Priority::Key {
                18.0
            } else {
                16.0
            };
            labels.add(
                at,
                text,
                color,
                egui::FontId::proportional(size),
                priority,
                7.0,
            );
        }
    }

    /// A line.
    pub fn line(&self, a: DVec3, b: DVec3, stroke: impl Into<Stroke>) {
        if let Some(points) = self.projector.segment(a, b) {
            self.painter.line_segment(points, stroke);
        }
    }

    /// A dashed line.
    pub fn dashed(&self, a: DVec3, b: DVec3, stroke: impl Into<Stroke>) {
        if let Some(points) = self.projector.segment(a, b) {
            self.painter
                .extend(Shape::dashed_line(&points, stroke.into(), 7.0, 5.0));
        }
    }

    /// An arrow from `from` to `to`, with a head on screen.
    pub fn arrow(&self, from: DVec3, to: DVec3, stroke: impl Into<Stroke>) {
        let stroke = stroke.into();
        let Some([a, b]) = self.projector.segment(from, to) else {
            return;
        };
        self.painter.line_segment([a, b], stroke);
        let along = b - a;
        if along.length() < 2.0 {
            return;
        }
        let dir = along.normalized();
        let head = 11.0f32.min(along.length() * 0.5);
        let side = Vec2::new(-dir.y, dir.x) * head * 0.45;
        self.painter.add(Shape::convex_polygon(
            vec![b, b - dir * head + side, b - dir * head - side],
            stroke.color,
            Stroke::NONE,
        ));
    }

    /// A filled dot; returns its screen position.
    pub fn dot(&self, p: DVec3, radius: f32, color: Color32) -> Option<Pos2> {
        let at = self.projector.screen_from_world(p)?;
        self.painter.circle_filled(at, radius, color);
        Some(at)
    }

    /// A point inside (a filled disc) or outside (a ring with a cross): the shape says it as well as
    /// the colour, for a student who cannot tell the colours apart.
    pub fn inside_mark(&self, p: DVec3, radius: f32, color: Color32, inside: bool) -> Option<Pos2> {
        if inside {
            return self.dot(p, radius, color);
        }
        let at = self.ring(p, radius, Stroke::new(2.5, color))?;
        let d = radius * 0.6;
        let stroke = Stroke::new(2.0, color);
        self.painter
            .line_segment([at + egui::vec2(-d, -d), at + egui::vec2(d, d)], stroke);
        self.painter
            .line_segment([at + egui::vec2(-d, d), at + egui::vec2(d, -d)], stroke);
        Some(at)
    }

    /// A hollow ring (a ghost point).
    pub fn ring(&self, p: DVec3, radius: f32, stroke: impl Into<Stroke>) -> Option<Pos2> {
        let at = self.projector.screen_from_world(p)?;
        self.painter.circle_stroke(at, radius, stroke);
        Some(at)
    }

    /// A filled polygon (the triangle), translucent.
    pub fn polygon(&self, points: &[DVec3], fill: Color32, stroke: Stroke) {
        let screen: Option<Vec<Pos2>> = points
            .iter()
            .map(|p| self.projector.screen_from_world(*p))
            .collect();
        if let Some(screen) = screen {
            self.painter
                .add(Shape::convex_polygon(screen, fill, stroke));
        }
    }
}

impl Canvas<'_> {
    /// Axes from the origin, long enough to reach the given points, whose labels go through the
    /// label pass (minor labels: dropped first when space is short).
    pub fn axes_labelled(&self, points: &[DVec3], labels: &mut super::labels::LabelLayer) {
        let extent = points
            .iter()
            .filter(|p| p.is_finite())
            .map(|p| p.abs().max_element())
            .fold(1.0f64, f64::max)
            * 1.2;
        for (axis, name, color) in [
            (DVec3::X, "x", Color32::from_rgb(0xc8, 0x50, 0x50)),
            (DVec3::Y, "y", Color32::from_rgb(0x50, 0xa8, 0x50)),
            (DVec3::Z, "z", Color32::from_rgb(0x50, 0x70, 0xd0)),
        ] {
            let faded = |a: u8| Color32::from_rgba_unmultiplied(color.r(), color.g(), color.b(), a);
            self.line(DVec3::ZERO, axis * extent, Stroke::new(1.5, faded(200)));
            self.dashed(
                -axis * extent * 0.3,
                DVec3::ZERO,
                Stroke::new(1.0, faded(90)),
            );
            self.place_label(
                labels,
                axis * extent,
                name,
                color,
                super::labels::Priority::Minor,
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn target_projects_to_the_center() {
        let camera = OrbitCamera::default();
        let rect = Rect::from_min_size(Pos2::ZERO, Vec2::new(800.0, 600.0));
        let projector = camera.projector(rect);
        let center = projector
            .screen_from_world(DVec3::from(camera.target))
            .unwrap();
        assert!((center - rect.center()).length() < 1e-3);
        // Behind the camera there is nothing to draw.
        let behind = camera.eye() + (camera.eye() - DVec3::from(camera.target));
        assert!(projector.screen_from_world(behind).is_none());
        assert!(projector.screen_from_world(DVec3::NAN).is_none());
    }

    #[test]
    fn a_drag_moves_points_across_the_screen_by_the_same_amount() {
        let camera = OrbitCamera::default();
        let rect = Rect::from_min_size(Pos2::ZERO, Vec2::new(800.0, 600.0));
        let projector = camera.projector(rect);
        let p = DVec3::from(camera.target);
        let moved = p + projector.drag_in_view_plane(p, Vec2::new(30.0, -20.0));
        let delta =
            projector.screen_from_world(moved).unwrap() - projector.screen_from_world(p).unwrap();
        assert!((delta - Vec2::new(30.0, -20.0)).length() < 0.5, "{delta:?}");
    }
}
